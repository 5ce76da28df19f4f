// Quality of 2D triangle meshes: angles, radius ratios, histograms; text, JSON and SVG.
// Constructed quantities, computed in floating point: an angle is atan2(|u x v|, u . v),
// accurate for small and large angles alike.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <ostream>
#include <sstream>
#include <string>

#include "voroclip/mesh.h"

namespace voroclip {

namespace {

constexpr double kDeg = 57.295779513082320876798;  // 180 / pi

std::string num(double x) {
  if (!std::isfinite(x)) return "null";
  char buffer[32];
  const auto r = std::to_chars(buffer, buffer + sizeof buffer, x);
  return std::string(buffer, r.ptr);
}

std::string fixed(double x, int digits) {
  std::ostringstream s;
  s.imbue(std::locale::classic());
  s.setf(std::ios::fixed);
  s.precision(digits);
  s << x;
  return s.str();
}

std::string xml_escape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

void add_to(std::vector<std::uint32_t>& histogram, double angle, double bin) {
  const double b = std::floor(angle / bin);
  const auto k =
      static_cast<std::size_t>(std::clamp(b, 0.0, static_cast<double>(histogram.size() - 1)));
  ++histogram[k];
}

std::string json_array(const std::vector<std::uint32_t>& v) {
  std::string s = "[";
  for (std::size_t k = 0; k < v.size(); ++k) s += (k ? "," : "") + std::to_string(v[k]);
  return s + "]";
}

}  // namespace

TriangleQuality2 triangle_quality2(const Mesh2& mesh, double bin_degrees) {
  if (!(bin_degrees > 0 && bin_degrees <= 180)) {
    throw Error("triangle_quality2: the bin width must be in (0, 180] degrees");
  }
  TriangleQuality2 q;
  q.nb_triangles = mesh.nb_triangles();
  q.nb_vertices = mesh.nb_vertices();
  q.bin_degrees = bin_degrees;
  const auto nb_bins = static_cast<std::size_t>(std::ceil(180 / bin_degrees));
  q.angle_histogram.assign(nb_bins, 0);
  q.min_angle_histogram.assign(nb_bins, 0);
  q.max_angle_histogram.assign(nb_bins, 0);
  if (q.nb_triangles == 0) return q;
  q.min_angle = 180;
  q.min_radius_ratio = 1;
  double sum_angle = 0, sum_min = 0, sum_max = 0, sum_ratio = 0;
  for (std::uint32_t t = 0; t < q.nb_triangles; ++t) {
    const double* p[3];
    for (int k = 0; k < 3; ++k)
      p[k] = &mesh.xy[2 * std::size_t{mesh.triangles[3 * std::size_t{t} + k]}];
    double angle[3], len[3];
    for (int k = 0; k < 3; ++k) {
      const double* a = p[k];
      const double* b = p[(k + 1) % 3];
      const double* c = p[(k + 2) % 3];
      const double ux = b[0] - a[0], uy = b[1] - a[1], vx = c[0] - a[0], vy = c[1] - a[1];
      angle[k] = std::atan2(std::fabs(ux * vy - uy * vx), ux * vx + uy * vy) * kDeg;
      len[k] = std::hypot(c[0] - b[0], c[1] - b[1]);  // opposite a
    }
    const double mn = std::min({angle[0], angle[1], angle[2]});
    const double mx = std::max({angle[0], angle[1], angle[2]});
    for (const double a : angle) {
      add_to(q.angle_histogram, a, bin_degrees);
      sum_angle += a;
    }
    add_to(q.min_angle_histogram, mn, bin_degrees);
    add_to(q.max_angle_histogram, mx, bin_degrees);
    q.min_angle = std::min(q.min_angle, mn);
    q.max_angle = std::max(q.max_angle, mx);
    sum_min += mn;
    sum_max += mx;
    if (mn < 30) ++q.nb_below_30;
    // 2 r / R = 16 A^2 / (a b c (a + b + c)), with 16 A^2 from Heron's formula in the
    // stable ordering (Kahan).
    double s[3] = {len[0], len[1], len[2]};
    std::sort(s, s + 3);
    const double a = s[2], b = s[1], c = s[0];
    const double heron = (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c));
    const double ratio = std::max(0.0, heron) / (a * b * c * (a + b + c));
    q.min_radius_ratio = std::min(q.min_radius_ratio, ratio);
    sum_ratio += ratio;
  }
  const double n = q.nb_triangles;
  q.mean_angle = sum_angle / (3 * n);
  q.mean_min_angle = sum_min / n;
  q.mean_max_angle = sum_max / n;
  q.mean_radius_ratio = sum_ratio / n;
  return q;
}

std::string quality_text(const TriangleQuality2& q) {
  std::ostringstream s;
  s.imbue(std::locale::classic());
  s << q.nb_triangles << " triangles, " << q.nb_vertices << " vertices\n";
  if (q.nb_triangles == 0) return s.str();
  s << "angles (degrees): min " << fixed(q.min_angle, 2) << ", mean " << fixed(q.mean_angle, 2)
    << ", max " << fixed(q.max_angle, 2) << "\n"
    << "per triangle: mean of the smallest angle " << fixed(q.mean_min_angle, 2)
    << ", mean of the largest " << fixed(q.mean_max_angle, 2) << "; " << q.nb_below_30
    << " triangle" << (q.nb_below_30 == 1 ? "" : "s") << " with an angle below 30\n"
    << "radius ratio 2r/R: min " << fixed(q.min_radius_ratio, 4) << ", mean "
    << fixed(q.mean_radius_ratio, 4) << "\n";
  // A compact histogram of the smallest angles, in 10-degree groups.
  s << "smallest angle per triangle:";
  const double bin = q.bin_degrees;
  for (int g = 0; g < 6; ++g) {
    std::uint64_t count = 0;
    for (std::size_t k = 0; k < q.min_angle_histogram.size(); ++k) {
      const double centre = (static_cast<double>(k) + 0.5) * bin;
      if (centre >= 10 * g && (centre < 10 * (g + 1) || g == 5)) count += q.min_angle_histogram[k];
    }
    s << (g ? ", " : " ") << 10 * g << (g == 5 ? "+" : "-" + std::to_string(10 * g + 10)) << ": "
      << count;
  }
  s << "\n";
  return s.str();
}

std::string quality_json(const TriangleQuality2& q) {
  std::string s = "{";
  s += "\"nb_triangles\":" + std::to_string(q.nb_triangles);
  s += ",\"nb_vertices\":" + std::to_string(q.nb_vertices);
  s += ",\"min_angle_deg\":" + num(q.min_angle);
  s += ",\"mean_angle_deg\":" + num(q.mean_angle);
  s += ",\"max_angle_deg\":" + num(q.max_angle);
  s += ",\"mean_min_angle_deg\":" + num(q.mean_min_angle);
  s += ",\"mean_max_angle_deg\":" + num(q.mean_max_angle);
  s += ",\"min_radius_ratio\":" + num(q.min_radius_ratio);
  s += ",\"mean_radius_ratio\":" + num(q.mean_radius_ratio);
  s += ",\"triangles_below_30_deg\":" + std::to_string(q.nb_below_30);
  s += ",\"bin_deg\":" + num(q.bin_degrees);
  s += ",\"angle_histogram\":" + json_array(q.angle_histogram);
  s += ",\"min_angle_histogram\":" + json_array(q.min_angle_histogram);
  s += ",\"max_angle_histogram\":" + json_array(q.max_angle_histogram);
  return s + "}";
}

void write_quality_svg(std::ostream& out, const TriangleQuality2& q, const std::string& title) {
  constexpr double kWidth = 760, kHeight = 420;
  constexpr double kLeft = 60, kRight = 20, kTop = 78, kBottom = 50;
  const double pw = kWidth - kLeft - kRight, ph = kHeight - kTop - kBottom;
  const std::size_t nb = q.angle_histogram.size();
  // Percent of the angles (all: 3 per triangle) or of the triangles (min, max) per bin.
  const auto percent = [&](const std::vector<std::uint32_t>& h, std::size_t k, double total) {
    return total > 0 ? 100.0 * h[k] / total : 0.0;
  };
  const double n = q.nb_triangles;
  double top = 1;
  for (std::size_t k = 0; k < nb; ++k) {
    top = std::max({top, percent(q.angle_histogram, k, 3 * n), percent(q.min_angle_histogram, k, n),
                    percent(q.max_angle_histogram, k, n)});
  }
  top = std::ceil(top / 5) * 5;
  const auto x_of = [&](double deg) { return kLeft + pw * deg / 180; };
  const auto y_of = [&](double pct) { return kTop + ph * (1 - pct / top); };
  out << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kWidth << "\" height=\"" << kHeight
      << "\" viewBox=\"0 0 " << kWidth << ' ' << kHeight
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
      << "<text x=\"" << kLeft << "\" y=\"22\" font-size=\"15\">" << xml_escape(title)
      << "</text>\n"
      << "<text x=\"" << kLeft << "\" y=\"42\">" << q.nb_triangles << " triangles, "
      << q.nb_vertices << " vertices; angles min " << fixed(q.min_angle, 2) << "\u00b0, max "
      << fixed(q.max_angle, 2) << "\u00b0; mean smallest angle " << fixed(q.mean_min_angle, 2)
      << "\u00b0; radius ratio min " << fixed(q.min_radius_ratio, 3) << ", mean "
      << fixed(q.mean_radius_ratio, 3) << "</text>\n";
  // Legend.
  const char* colours[3] = {"#bbbbbb", "#2c7bb6", "#d7191c"};
  const char* names[3] = {"all angles (% of angles)", "smallest angle (% of triangles)",
                          "largest angle (% of triangles)"};
  for (int s = 0; s < 3; ++s) {
    const double lx = kLeft + 230.0 * s;
    out << "<rect x=\"" << lx << "\" y=\"52\" width=\"12\" height=\"12\" fill=\"" << colours[s]
        << "\"/><text x=\"" << lx + 17 << "\" y=\"62\">" << names[s] << "</text>\n";
  }
  // Axes, grid, ticks.
  out << "<g stroke=\"#dddddd\">\n";
  for (double pct = 0; pct <= top + 1e-9; pct += top / 5) {
    out << "<line x1=\"" << kLeft << "\" x2=\"" << kLeft + pw << "\" y1=\"" << y_of(pct)
        << "\" y2=\"" << y_of(pct) << "\"/>\n";
  }
  out << "</g>\n<g text-anchor=\"end\">\n";
  for (double pct = 0; pct <= top + 1e-9; pct += top / 5) {
    out << "<text x=\"" << kLeft - 6 << "\" y=\"" << y_of(pct) + 4 << "\">" << fixed(pct, 0)
        << "%</text>\n";
  }
  out << "</g>\n<g text-anchor=\"middle\">\n";
  for (int deg = 0; deg <= 180; deg += 30) {
    out << "<text x=\"" << x_of(deg) << "\" y=\"" << kTop + ph + 18 << "\">" << deg
        << "\u00b0</text>\n";
  }
  out << "<text x=\"" << kLeft + pw / 2 << "\" y=\"" << kHeight - 10
      << "\">angle (degrees), bins of " << num(q.bin_degrees) << "\u00b0</text>\n</g>\n";
  // Bars: the three histograms side by side within each bin.
  const double bw = pw / 180 * q.bin_degrees / 3;
  for (int s = 0; s < 3; ++s) {
    const std::vector<std::uint32_t>& h = s == 0   ? q.angle_histogram
                                          : s == 1 ? q.min_angle_histogram
                                                   : q.max_angle_histogram;
    const double total = s == 0 ? 3 * n : n;
    out << "<g fill=\"" << colours[s] << "\">\n";
    for (std::size_t k = 0; k < nb; ++k) {
      if (h[k] == 0) continue;
      const double pct = percent(h, k, total);
      const double x = x_of(static_cast<double>(k) * q.bin_degrees) + s * bw;
      out << "<rect x=\"" << x << "\" y=\"" << y_of(pct) << "\" width=\"" << bw << "\" height=\""
          << y_of(0) - y_of(pct) << "\"/>\n";
    }
    out << "</g>\n";
  }
  // The 30-degree mark (the usual quality target) and the frame.
  out << "<line x1=\"" << x_of(30) << "\" x2=\"" << x_of(30) << "\" y1=\"" << kTop << "\" y2=\""
      << kTop + ph << "\" stroke=\"#555\" stroke-dasharray=\"4 3\"/>\n"
      << "<rect x=\"" << kLeft << "\" y=\"" << kTop << "\" width=\"" << pw << "\" height=\"" << ph
      << "\" fill=\"none\" stroke=\"black\"/>\n</svg>\n";
}

std::vector<double> triangle_min_angles(const Mesh2& mesh) {
  std::vector<double> out(mesh.nb_triangles());
  for (std::uint32_t t = 0; t < mesh.nb_triangles(); ++t) {
    double mn = 180;
    for (int k = 0; k < 3; ++k) {
      const double* a = &mesh.xy[2 * std::size_t{mesh.triangles[3 * std::size_t{t} + k]}];
      const double* b = &mesh.xy[2 * std::size_t{mesh.triangles[3 * std::size_t{t} + (k + 1) % 3]}];
      const double* c = &mesh.xy[2 * std::size_t{mesh.triangles[3 * std::size_t{t} + (k + 2) % 3]}];
      const double ux = b[0] - a[0], uy = b[1] - a[1], vx = c[0] - a[0], vy = c[1] - a[1];
      mn = std::min(mn, std::atan2(std::fabs(ux * vy - uy * vx), ux * vx + uy * vy) * 180 / M_PI);
    }
    out[t] = mn;
  }
  return out;
}

}  // namespace voroclip
