// Reports of a TetQuality: a text table with histograms, a JSON object, an SVG picture of
// four histograms (the kind of figure of Yan et al. 2011, Fig. 14 and 15).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "voroclip/mesh.h"

namespace voroclip {

namespace {

// Fixed-point text with `decimals` digits, locale-independent.
std::string fixed(double v, int decimals) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, decimals);
  return std::string(buf, r.ptr);
}

std::string pad_left(std::string s, std::size_t width) {
  if (s.size() < width) s.insert(0, width - s.size(), ' ');
  return s;
}

// Counts of `bins` regrouped into `rows` rows (bins must be a multiple of rows, else the
// histogram is shown with its own bins).
std::vector<std::uint64_t> regroup(const std::vector<std::uint64_t>& h, std::size_t rows) {
  if (h.empty() || h.size() % rows != 0) return h;
  std::vector<std::uint64_t> out(rows, 0);
  const std::size_t per = h.size() / rows;
  for (std::size_t i = 0; i < h.size(); ++i) out[i / per] += h[i];
  return out;
}

void text_histogram(std::ostream& out, const std::string& name,
                    const std::vector<std::uint64_t>& bins, std::size_t rows, double lo, double hi,
                    int decimals) {
  const std::vector<std::uint64_t> h = regroup(bins, rows);
  std::uint64_t total = 0, peak = 0;
  for (const std::uint64_t c : h) {
    total += c;
    peak = std::max(peak, c);
  }
  out << name << ":\n";
  const double w = (hi - lo) / static_cast<double>(h.size());
  for (std::size_t i = 0; i < h.size(); ++i) {
    const std::size_t bar =
        peak == 0 ? 0
                  : static_cast<std::size_t>(
                        std::llround(40.0 * static_cast<double>(h[i]) / static_cast<double>(peak)));
    out << "  [" << pad_left(fixed(lo + w * static_cast<double>(i), decimals), 6) << ", "
        << pad_left(fixed(lo + w * static_cast<double>(i + 1), decimals), 6)
        << (i + 1 == h.size() ? "] " : ") ") << pad_left(std::to_string(h[i]), 10) << ' '
        << pad_left(
               fixed(total ? 100.0 * static_cast<double>(h[i]) / static_cast<double>(total) : 0.0,
                     2),
               6)
        << "% " << std::string(bar, '#') << '\n';
  }
}

std::string index_list(const std::vector<std::uint32_t>& v, std::size_t limit) {
  std::string s;
  for (std::size_t i = 0; i < v.size() && i < limit; ++i) {
    if (i > 0) s += ", ";
    s += std::to_string(v[i]);
  }
  if (v.size() > limit) s += ", ...";
  return s;
}

nlohmann::json histogram_json(const std::vector<std::uint64_t>& h, double lo, double hi) {
  return {{"lo", lo}, {"hi", hi}, {"counts", h}};
}

}  // namespace

void write_quality_text(std::ostream& out, const TetQuality& q, const std::string& title,
                        const HausdorffDistance* distance, const std::string& reference) {
  out << "Tet mesh quality of " << title << ": " << count_of(q.nb_tets, "tet") << ", "
      << count_of(q.nb_vertices, "vertex", "vertices") << " (" << q.nb_used_vertices
      << " used); tets below are numbered from 0 in the file's order\n";
  if (q.inverted.empty() && q.degenerate.empty()) {
    out << "Orientation: every tet has the same orientation (det(p1-p0, p2-p0, p3-p0) "
        << (q.nb_positive >= q.nb_negative ? "> 0" : "< 0") << "), none has zero volume\n";
  } else {
    if (!q.inverted.empty()) {
      out << "WARNING: " << q.inverted.size() << " inverted tet"
          << (q.inverted.size() == 1 ? "" : "s") << " (oriented unlike the other "
          << (q.nb_positive + q.nb_negative - q.inverted.size())
          << "): " << index_list(q.inverted, 10) << '\n';
    }
    if (!q.degenerate.empty()) {
      out << "WARNING: " << q.degenerate.size() << " degenerate tet"
          << (q.degenerate.size() == 1 ? "" : "s")
          << " (zero volume, exact): " << index_list(q.degenerate, 10) << '\n';
    }
  }
  const auto row = [&](const char* name, const QualityStat& s, int decimals) {
    out << "  " << name << pad_left(fixed(s.min, decimals), 10)
        << pad_left(fixed(s.mean, decimals), 10) << pad_left(fixed(s.max, decimals), 10)
        << "   (min at tet " << s.argmin << ", max at tet " << s.argmax << ")\n";
  };
  out << "                                      min      mean       max\n";
  row("Q1 min dihedral angle (deg)  ", q.q1_deg, 3);
  row("Q2 max dihedral angle (deg)  ", q.q2_deg, 3);
  row("Q3 3 r_in / r_circ           ", q.q3, 4);
  row("Q4 12 (9V^2)^(1/3) / sum l^2 ", q.q4, 4);
  row("all dihedral angles (deg)    ", q.dihedral_deg, 3);
  text_histogram(out, "Q1, min dihedral angle per tet (deg)", q.min_dihedral_histogram, 18, 0, 180,
                 0);
  text_histogram(out, "All dihedral angles (deg)", q.dihedral_histogram, 18, 0, 180, 0);
  text_histogram(out, "Q3", q.q3_histogram, 10, 0, 1, 1);
  text_histogram(out, "Q4", q.q4_histogram, 10, 0, 1, 1);
  if (distance != nullptr) {
    out << "Hausdorff distance to " << reference << ": " << fixed(distance->max, 6) << " = "
        << fixed(100 * distance->max_relative(), 4) << " % of the bounding-box diagonal "
        << fixed(distance->diagonal, 6) << "; mean " << fixed(distance->mean, 6) << " = "
        << fixed(100 * distance->mean_relative(), 4) << " %\n"
        << "  mesh boundary -> reference: max " << fixed(distance->forward.max, 6) << ", mean "
        << fixed(distance->forward.mean, 6) << " (" << distance->forward.nb_samples << " samples)\n"
        << "  reference -> mesh boundary: max " << fixed(distance->backward.max, 6) << ", mean "
        << fixed(distance->backward.mean, 6) << " (" << distance->backward.nb_samples
        << " samples)\n";
  }
}

void write_quality_json(std::ostream& out, const TetQuality& q, const HausdorffDistance* distance) {
  const auto first = [](const std::vector<std::uint32_t>& v) {
    return std::vector<std::uint32_t>(
        v.begin(), v.begin() + static_cast<std::ptrdiff_t>(std::min<std::size_t>(v.size(), 1000)));
  };
  nlohmann::json j = {
      {"tets", q.nb_tets},
      {"vertices", q.nb_vertices},
      {"used_vertices", q.nb_used_vertices},
      {"inverted_tets", q.inverted.size()},
      {"degenerate_tets", q.degenerate.size()},
      {"inverted", first(q.inverted)},
      {"degenerate", first(q.degenerate)},
      {"min_min_dihedral_deg", q.q1_deg.min},
      {"min_dihedral_deg", q.q1_deg.min},
      {"mean_min_dihedral_deg", q.q1_deg.mean},
      {"max_min_dihedral_deg", q.q1_deg.max},
      {"min_max_dihedral_deg", q.q2_deg.min},
      {"mean_max_dihedral_deg", q.q2_deg.mean},
      {"max_max_dihedral_deg", q.q2_deg.max},
      {"max_dihedral_deg", q.q2_deg.max},
      {"mean_dihedral_deg", q.dihedral_deg.mean},
      {"min_q3", q.q3.min},
      {"mean_q3", q.q3.mean},
      {"max_q3", q.q3.max},
      {"min_q4", q.q4.min},
      {"mean_q4", q.q4.mean},
      {"max_q4", q.q4.max},
      {"histograms",
       {{"dihedral_deg", histogram_json(q.dihedral_histogram, 0, 180)},
        {"min_dihedral_deg", histogram_json(q.min_dihedral_histogram, 0, 180)},
        {"q3", histogram_json(q.q3_histogram, 0, 1)},
        {"q4", histogram_json(q.q4_histogram, 0, 1)}}},
  };
  if (distance != nullptr) {
    j["hausdorff"] = distance->max;
    j["hausdorff_rel"] = distance->max_relative();
    j["hausdorff_mean"] = distance->mean;
    j["hausdorff_mean_rel"] = distance->mean_relative();
    j["bbox_diagonal"] = distance->diagonal;
    const auto side = [](const OneSidedDistance& d) {
      return nlohmann::json{{"max", d.max},
                            {"mean", d.mean},
                            {"where", {d.where[0], d.where[1], d.where[2]}},
                            {"samples", d.nb_samples}};
    };
    j["hausdorff_forward"] = side(distance->forward);
    j["hausdorff_backward"] = side(distance->backward);
  }
  out << j.dump() << '\n';
}

void write_quality_svg(std::ostream& out, const TetQuality& q, const std::string& title) {
  // Two rows of two panels; each panel: its name above, bars, axis labels, then a line of
  // min / mean / max below.
  constexpr int kWidth = 960, kHeight = 680, kPanelW = 420, kPanelH = 230;
  struct Panel {
    const char* name;
    const std::vector<std::uint64_t>* bins;
    double lo, hi;
    const QualityStat* stat;
    int decimals;
    const char* colour;
  };
  const Panel panels[4] = {
      {"Q1: min dihedral angle per tet (deg)", &q.min_dihedral_histogram, 0, 180, &q.q1_deg, 2,
       "#3b7dd8"},
      {"All dihedral angles (deg)", &q.dihedral_histogram, 0, 180, &q.dihedral_deg, 2, "#6a5acd"},
      {"Q3 = 3 r_in / r_circ", &q.q3_histogram, 0, 1, &q.q3, 3, "#2e8b57"},
      {"Q4 = 12 (9V^2)^(1/3) / sum l^2", &q.q4_histogram, 0, 1, &q.q4, 3, "#d2691e"},
  };
  const auto escape = [](const std::string& s) {
    std::string r;
    for (const char c : s) {
      if (c == '<') {
        r += "&lt;";
      } else if (c == '>') {
        r += "&gt;";
      } else if (c == '&') {
        r += "&amp;";
      } else if (c == '"') {
        r += "&quot;";
      } else {
        r += c;
      }
    }
    return r;
  };
  out << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kWidth << "\" height=\"" << kHeight
      << "\" viewBox=\"0 0 " << kWidth << ' ' << kHeight
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
      << "<text x=\"20\" y=\"24\" font-size=\"15\">" << escape(title) << ": " << q.nb_tets
      << " tets";
  if (!q.inverted.empty()) out << ", " << q.inverted.size() << " inverted";
  if (!q.degenerate.empty()) out << ", " << q.degenerate.size() << " degenerate";
  out << "</text>\n";
  for (int k = 0; k < 4; ++k) {
    const Panel& p = panels[k];
    const int x0 = 40 + (k % 2) * (kPanelW + 60), y0 = 60 + (k / 2) * (kPanelH + 80);
    std::uint64_t peak = 0;
    for (const std::uint64_t c : *p.bins) peak = std::max(peak, c);
    out << "<g>\n<text x=\"" << x0 << "\" y=\"" << y0 - 8 << "\" font-size=\"13\">"
        << escape(p.name) << "</text>\n";
    const double bw = static_cast<double>(kPanelW) / static_cast<double>(p.bins->size());
    for (std::size_t i = 0; i < p.bins->size(); ++i) {
      if ((*p.bins)[i] == 0) continue;
      const double h = peak == 0
                           ? 0
                           : static_cast<double>(kPanelH) * static_cast<double>((*p.bins)[i]) /
                                 static_cast<double>(peak);
      out << "<rect x=\"" << fixed(x0 + bw * static_cast<double>(i), 2) << "\" y=\""
          << fixed(y0 + kPanelH - h, 2) << "\" width=\"" << fixed(std::max(bw - 0.3, 0.3), 2)
          << "\" height=\"" << fixed(h, 2) << "\" fill=\"" << p.colour << "\"/>\n";
    }
    out << "<line x1=\"" << x0 << "\" y1=\"" << y0 + kPanelH << "\" x2=\"" << x0 + kPanelW
        << "\" y2=\"" << y0 + kPanelH << "\" stroke=\"black\"/>\n";
    for (int t = 0; t <= 4; ++t) {
      const double v = p.lo + (p.hi - p.lo) * t / 4;
      out << "<text x=\"" << x0 + kPanelW * t / 4 << "\" y=\"" << y0 + kPanelH + 16
          << "\" text-anchor=\"middle\">" << fixed(v, p.hi > 1 ? 0 : 2) << "</text>\n";
    }
    out << "<text x=\"" << x0 << "\" y=\"" << y0 + kPanelH + 36 << "\">min "
        << fixed(p.stat->min, p.decimals) << "  mean " << fixed(p.stat->mean, p.decimals)
        << "  max " << fixed(p.stat->max, p.decimals) << "</text>\n</g>\n";
  }
  out << "</svg>\n";
}

}  // namespace voroclip
