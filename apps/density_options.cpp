// The user's density and sizing field on the command line (see density_options.h).
#include "density_options.h"

#include <CLI/CLI.hpp>
#include <muParser.h>
#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "cli.h"
#include "voroclip/core.h"

namespace voroclip::cli {

namespace {

// rho = h^-(d+2): n CVT sites of density rho have a local spacing ~ rho^(-1/(d+2)) (Gersho's
// asymptotics, the paper's sec. 5).
double density_of_size(double h, int dimension) {
  return std::pow(h, -static_cast<double>(dimension + 2));
}

std::string point_text(const double* p, int dimension) {
  std::string s = "(" + format_double(p[0]) + ", " + format_double(p[1]);
  if (dimension == 3) s += ", " + format_double(p[2]);
  return s + ")";
}

// A density given by a formula: rho(p), or h(p) with rho = h^-(d+2); a value that is not
// finite and positive throws Error naming the option and the point.
class FormulaDensity {
 public:
  FormulaDensity(const std::string& text, int dimension, bool sizing)
      : expression_(text, dimension, sizing ? "--sizing" : "--density"),
        dimension_(dimension),
        sizing_(sizing) {}

  double operator()(const double* p) const { return checked(p, expression_(p)); }

  // out[k] = rho at the point p + 3k (dimension 3), k < n.
  void evaluate(const double* p, std::size_t n, double* out) const {
    expression_.evaluate(p, n, out);
    if (!sizing_) {
      // A density as is: one pass without branches (vectorised), checked point by point
      // only when a value is bad, for the message.
      bool ok = true;
      for (std::size_t k = 0; k < n; ++k) ok &= out[k] > 0 && out[k] <= kMaxDouble;
      if (ok) return;
    }
    for (std::size_t k = 0; k < n; ++k) out[k] = checked(p + 3 * k, out[k]);
  }

 private:
  static constexpr double kMaxDouble = std::numeric_limits<double>::max();
  // rho from the formula's value v at p; throws when it is not finite and positive.
  double checked(const double* p, double v) const {
    if (!(v > 0) || !std::isfinite(v)) {
      throw Error(std::string(sizing_ ? "--sizing" : "--density") + " \"" + expression_.text() +
                  "\" is " + format_double(v) + " at " + point_text(p, dimension_) + ": the " +
                  (sizing_ ? "size" : "density") + " must be finite and positive");
    }
    if (!sizing_) return v;
    const double rho = density_of_size(v, dimension_);
    if (!(rho > 0) || !std::isfinite(rho)) {
      throw Error("--sizing \"" + expression_.text() + "\" is " + format_double(v) + " at " +
                  point_text(p, dimension_) + ": h^-" + std::to_string(dimension_ + 2) +
                  " is out of the range of doubles");
    }
    return rho;
  }

  Expression expression_;
  int dimension_;
  bool sizing_;
};

// ---- Files.

// Whitespace-separated tokens of a text file with their line numbers; '#' starts a comment.
struct Tokens {
  std::string path;
  std::vector<std::string> words;
  std::vector<std::uint32_t> lines;
  std::size_t next = 0;

  explicit Tokens(const std::string& file) : path(file) {
    std::istringstream in(read_text_file(file));  // BOM, CR-only line ends, gzip: as core
    std::string line;
    std::uint32_t number = 0;
    while (std::getline(in, line)) {
      ++number;
      const std::size_t hash = line.find('#');
      if (hash != std::string::npos) line.resize(hash);
      std::istringstream ss(line);
      std::string w;
      while (ss >> w) {
        words.push_back(w);
        lines.push_back(number);
      }
    }
  }
  bool done() const { return next >= words.size(); }
  std::string where() const {
    return path + ":" + std::to_string(done() ? (lines.empty() ? 0 : lines.back()) : lines[next]);
  }
  [[noreturn]] void fail(const std::string& what) const { throw Error(where() + ": " + what); }
  const std::string& word(const std::string& what) {
    if (done()) fail("the file ends where " + what + " was expected");
    return words[next++];
  }
  double number(const std::string& what) {
    const std::string& w = word(what);
    try {
      return parse_finite_double(w, what);
    } catch (const UsageError&) {
      --next;
      fail("expected " + what + " (a finite number), got '" + w + "'");
    }
  }
  std::uint64_t count(const std::string& what) {
    const std::string& w = word(what);
    std::uint64_t v = 0;
    bool ok = !w.empty() && w.size() < 19;
    for (const char c : w) ok = ok && std::isdigit(static_cast<unsigned char>(c));
    if (ok) v = std::stoull(w);
    if (!ok) {
      --next;
      fail("expected " + what + " (a whole number), got '" + w + "'");
    }
    return v;
  }
};

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

// Checks a value read from a file: finite and positive (a density may be 0 for a grid),
// naming the file's line and the value's number (from 1, as the file counts).
double checked_value(Tokens& t, const std::string& what, bool sizing) {
  const std::string where = t.where();
  const double v = t.number(what);
  if (!(v > 0)) {
    throw Error(where + ": " + what + " is " + format_double(v) + ": a " +
                (sizing ? "size" : "density") + " must be positive");
  }
  return v;
}

// A regular grid of values (legacy VTK STRUCTURED_POINTS, ASCII).
struct Grid {
  std::uint32_t n[3] = {1, 1, 1};
  double origin[3] = {0, 0, 0}, spacing[3] = {1, 1, 1};
  std::vector<double> values;  // x fastest, then y, then z (VTK's order)
};

Grid read_vtk_grid(const std::string& path, bool sizing, int dimension) {
  Tokens t(path);
  // The header: "# vtk DataFile Version x.y" (a comment to Tokens) and a title line.
  {
    std::istringstream in(read_text_file(path));
    std::string first;
    std::getline(in, first);
    if (first.rfind("# vtk DataFile", 0) != 0) {
      throw Error(path + ":1: not a legacy VTK file (expected '# vtk DataFile Version ...')");
    }
    std::string title;
    std::getline(in, title);
    // Skip the title's words.
    std::istringstream ss(title.substr(0, title.find('#')));
    std::string w;
    while (ss >> w) ++t.next;
  }
  if (upper(t.word("ASCII")) != "ASCII") {
    --t.next;
    t.fail("only ASCII legacy VTK files are read");
  }
  if (upper(t.word("DATASET")) != "DATASET" ||
      upper(t.word("STRUCTURED_POINTS")) != "STRUCTURED_POINTS") {
    --t.next;
    t.fail("expected 'DATASET STRUCTURED_POINTS' (a regular grid)");
  }
  Grid g;
  bool have_dimensions = false;
  std::uint64_t nb_values = 0;
  while (true) {
    const std::string key = upper(t.word("DIMENSIONS, ORIGIN, SPACING or POINT_DATA"));
    if (key == "DIMENSIONS") {
      for (int c = 0; c < 3; ++c) {
        const std::uint64_t k = t.count("a grid dimension");
        if (k < 1 || k > (1u << 20)) t.fail("a grid dimension must be between 1 and 2^20");
        g.n[c] = static_cast<std::uint32_t>(k);
      }
      have_dimensions = true;
    } else if (key == "ORIGIN") {
      for (double& o : g.origin) o = t.number("an origin coordinate");
    } else if (key == "SPACING" || key == "ASPECT_RATIO") {
      for (double& s : g.spacing) {
        s = t.number("a grid spacing");
        if (!(s > 0)) {
          --t.next;
          t.fail("the grid spacing must be positive");
        }
      }
    } else if (key == "POINT_DATA") {
      nb_values = t.count("the number of point values");
      break;
    } else {
      --t.next;
      t.fail("unexpected '" + t.words[t.next] +
             "' (expected DIMENSIONS, ORIGIN, SPACING or POINT_DATA)");
    }
  }
  if (!have_dimensions) t.fail("POINT_DATA before DIMENSIONS");
  const std::uint64_t expected = std::uint64_t{g.n[0]} * g.n[1] * g.n[2];
  if (nb_values != expected) {
    --t.next;
    t.fail("POINT_DATA " + std::to_string(nb_values) + " does not match the grid's " +
           std::to_string(expected) + " points");
  }
  if (dimension == 2 && g.n[2] != 1) t.fail("a 2D density grid must have DIMENSIONS nx ny 1");
  if (dimension == 2 && (g.n[0] < 2 || g.n[1] < 2)) t.fail("the grid needs at least 2 x 2 points");
  if (dimension == 3 && (g.n[0] < 2 || g.n[1] < 2 || g.n[2] < 2)) {
    t.fail("a 3D grid needs at least 2 x 2 x 2 points");
  }
  const std::string kind = upper(t.word("SCALARS"));
  if (kind != "SCALARS") {
    --t.next;
    t.fail("expected 'SCALARS name type' (one value per grid point)");
  }
  const std::string name = t.word("the name of the scalars");
  t.word("the type of the scalars");
  // Optional number of components (must be 1), then an optional LOOKUP_TABLE line.
  if (!t.done() && upper(t.words[t.next]) != "LOOKUP_TABLE" &&
      t.words[t.next].find_first_not_of("0123456789") == std::string::npos) {
    if (t.count("the number of components") != 1) {
      --t.next;
      t.fail("only one component per point is read");
    }
  }
  if (!t.done() && upper(t.words[t.next]) == "LOOKUP_TABLE") {
    t.next += 2;
  }
  // The file's words are in memory already: a grid larger than the values that follow is
  // refused before anything is allocated for it (DIMENSIONS 1024 1024 1024 in a file of a
  // few bytes asked for 8 GB, zero-filled).
  const std::size_t left = t.words.size() - std::min(t.next, t.words.size());
  if (expected > left) {
    t.fail("POINT_DATA " + std::to_string(expected) + ": the file has " + count_of(left, "value") +
           " left");
  }
  g.values.resize(expected);
  for (std::uint64_t k = 0; k < expected; ++k) {
    double v = checked_value(t, "value " + std::to_string(k + 1), sizing);
    if (sizing) {
      v = density_of_size(v, dimension);
      if (!std::isfinite(v)) t.fail("value " + std::to_string(k + 1) + ": h^-(d+2) overflows");
    }
    g.values[k] = v;
  }
  // Another array of point values: which one holds the density (or size) is not for the
  // reader to guess (VTK's own reader would take the first), so it is an error naming them.
  std::vector<std::string> others;
  std::size_t first_other = 0;
  for (std::size_t w = t.next; w + 1 < t.words.size(); ++w) {
    if (upper(t.words[w]) != "SCALARS") continue;
    if (others.empty()) first_other = w;
    others.push_back("'" + t.words[w + 1] + "'");
  }
  if (!others.empty()) {
    std::string list = "'" + name + "'";
    for (std::size_t i = 0; i < others.size(); ++i)
      list += (i + 1 == others.size() ? " and " : ", ") + others[i];
    t.next = first_other;
    t.fail("the grid has " + std::to_string(others.size() + 1) + " SCALARS arrays, " + list +
           ": which one is the " + (sizing ? "size" : "density") +
           " is ambiguous; keep only that one in the file");
  }
  return g;
}

// A Medit .sol: one scalar per vertex (SolAtVertices, type 1), keywords case-insensitive.
std::vector<double> read_sol(const std::string& path, bool sizing, std::uint32_t nb_vertices) {
  Tokens t(path);
  std::vector<double> values;
  bool found = false;
  while (!t.done()) {
    const std::string key = upper(t.word("a keyword"));
    if (key == "MESHVERSIONFORMATTED") {
      t.count("the format version");
    } else if (key == "DIMENSION") {
      const std::uint64_t d = t.count("the dimension");
      if (d != 3) {
        --t.next;
        t.fail("expected Dimension 3, got " + std::to_string(d));
      }
    } else if (key == "SOLATVERTICES") {
      const std::uint64_t n = t.count("the number of vertices");
      if (n != nb_vertices) {
        --t.next;
        t.fail("SolAtVertices has " + std::to_string(n) + " values, the domain's mesh " +
               std::to_string(nb_vertices) + " vertices");
      }
      const std::uint64_t fields = t.count("the number of solution fields");
      const std::uint64_t type = t.count("the solution type");
      if (fields != 1 || type != 1) {
        --t.next;
        t.fail("only one scalar field (\"1 1\") is read");
      }
      values.resize(nb_vertices);
      for (std::uint32_t v = 0; v < nb_vertices; ++v) {
        double x = checked_value(t, "the value of vertex " + std::to_string(v + 1), sizing);
        if (sizing) {
          x = density_of_size(x, 3);
          if (!std::isfinite(x)) t.fail("h^-5 overflows at vertex " + std::to_string(v + 1));
        }
        values[v] = x;
      }
      found = true;
    } else if (key == "END") {
      break;
    } else {
      --t.next;
      t.fail("unexpected '" + t.words[t.next] + "' (expected SolAtVertices)");
    }
  }
  if (!found) throw Error(path + ": no SolAtVertices section");
  return values;
}

// Trilinear interpolation in a grid (values clamped to the grid outside it).
double trilinear(const Grid& g, const double* p) {
  std::uint32_t i[3];
  double u[3];
  for (int c = 0; c < 3; ++c) {
    const double t = std::clamp((p[c] - g.origin[c]) / g.spacing[c], 0.0, g.n[c] - 1.0);
    i[c] = std::min(static_cast<std::uint32_t>(t), g.n[c] - 2);
    u[c] = t - i[c];
  }
  const auto at = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    return g.values[(std::size_t{c} * g.n[1] + b) * g.n[0] + a];
  };
  double v = 0;
  for (int k = 0; k < 8; ++k) {
    const std::uint32_t a = k & 1, b = (k >> 1) & 1, c = (k >> 2) & 1;
    const double w = (a ? u[0] : 1 - u[0]) * (b ? u[1] : 1 - u[1]) * (c ? u[2] : 1 - u[2]);
    v += w * at(i[0] + a, i[1] + b, i[2] + c);
  }
  return v;
}

// Values at the vertices of a tet mesh, interpolated linearly in the tet that holds a
// point. The tet is found through a uniform grid of buckets, each listing the tets whose
// bounding box meets it (about two tets per bucket). Outside every tet (the cones of the
// cell integrals reach a little beyond the volume): the tet of the nearest non-empty ring
// of buckets whose barycentric coordinates are the least negative, with the negative
// coordinates set to 0 (so the value is a convex combination of vertex values: positive).
// Which tet holds a point on a shared face does not matter: the interpolant is continuous.
// The result is a function of the point, the vertices and the tets (in their order).
class TetInterpolant {
 public:
  TetInterpolant(std::vector<double> xyz, std::vector<std::uint32_t> tets,
                 std::vector<double> values)
      : xyz_(std::move(xyz)), tets_(std::move(tets)), values_(std::move(values)) {
    const std::size_t nt = tets_.size() / 4;
    // Each tet's vertices in increasing order: the same bits whatever the orientation the
    // tet was listed with (Domain3 swaps two vertices of a negative tet).
    for (std::size_t t = 0; t < nt; ++t) {
      const auto first = tets_.begin() + static_cast<std::ptrdiff_t>(4 * t);
      std::sort(first, first + 4);
    }
    for (int c = 0; c < 3; ++c) {
      lo_[c] = std::numeric_limits<double>::infinity();
      double hi = -lo_[c];
      for (std::size_t v = 0; v < xyz_.size() / 3; ++v) {
        lo_[c] = std::min(lo_[c], xyz_[3 * v + c]);
        hi = std::max(hi, xyz_[3 * v + c]);
      }
      // (hi - lo overflows for coordinates of both signs near the double range.)
      extent_[c] = std::clamp(hi - lo_[c], 1e-300, std::numeric_limits<double>::max());
    }
    // Buckets of side about cbrt(volume / (nt / 2)), in logarithms: the volume's product
    // overflows or underflows for a mesh 1e200 or 1e-200 across (a NaN side count then
    // crashed the lookup, a volume of 0 made every side 512: 537 MB of buckets for a
    // .vtu of one tet; tests/apps/fuzz_regressions/). At most 512 per side and about two
    // buckets per tet in all, whatever the extents.
    const double log_tets = std::log(std::max(1.0, 0.5 * static_cast<double>(nt)));
    const double log_volume = std::log(extent_[0]) + std::log(extent_[1]) + std::log(extent_[2]);
    for (int c = 0; c < 3; ++c) {
      const double side = std::exp(std::log(extent_[c]) + (log_tets - log_volume) / 3);
      n_[c] = static_cast<std::uint32_t>(std::clamp(std::ceil(side), 1.0, 512.0));
    }
    const std::uint64_t cap = 8 + 2 * std::uint64_t{nt};
    while (std::uint64_t{n_[0]} * n_[1] * n_[2] > cap) {
      std::uint32_t* largest = std::max_element(n_, n_ + 3);
      *largest = (*largest + 1) / 2;
    }
    for (int c = 0; c < 3; ++c) scale_[c] = n_[c] / extent_[c];
    // Two passes: counts, then the tets, bucket by bucket (CSR).
    begin_.assign(std::size_t{n_[0]} * n_[1] * n_[2] + 1, 0);
    for (int pass = 0; pass < 2; ++pass) {
      std::vector<std::uint32_t> fill;
      if (pass == 1) {
        for (std::size_t b = 1; b < begin_.size(); ++b) begin_[b] += begin_[b - 1];
        fill.assign(begin_.begin(), begin_.end() - 1);
        list_.resize(begin_.back());
      }
      if (pass == 0) box_.resize(6 * std::size_t{nt});
      for (std::uint32_t t = 0; t < nt; ++t) {
        std::uint32_t a[3], b[3];
        for (int c = 0; c < 3; ++c) {
          double mn = xyz_[3 * std::size_t{tets_[4 * t]} + c], mx = mn;
          for (int k = 1; k < 4; ++k) {
            const double x = xyz_[3 * std::size_t{tets_[4 * t + k]} + c];
            mn = std::min(mn, x);
            mx = std::max(mx, x);
          }
          box_[6 * std::size_t{t} + c] = mn;
          box_[6 * std::size_t{t} + 3 + c] = mx;
          a[c] = bucket(mn, c);
          b[c] = bucket(mx, c);
        }
        for (std::uint32_t k = a[2]; k <= b[2]; ++k) {
          for (std::uint32_t j = a[1]; j <= b[1]; ++j) {
            for (std::uint32_t i = a[0]; i <= b[0]; ++i) {
              const std::size_t id = (std::size_t{k} * n_[1] + j) * n_[0] + i;
              if (pass == 0) {
                ++begin_[id + 1];
              } else {
                list_[fill[id]++] = t;
              }
            }
          }
        }
      }
    }
  }

  double operator()(const double* p) const {
    std::uint32_t b[3];
    for (int c = 0; c < 3; ++c) b[c] = bucket(p[c], c);
    // The point's own bucket lists the tet that holds it, if any: the first of its tets,
    // in list order, whose box holds the point and whose barycentric coordinates are all
    // >= 0 (most of a bucket's tets only meet it with their box: the box test skips them).
    {
      const std::size_t id = (std::size_t{b[2]} * n_[1] + b[1]) * n_[0] + b[0];
      for (std::uint32_t q = begin_[id]; q < begin_[id + 1]; ++q) {
        const double* box = &box_[6 * std::size_t{list_[q]}];
        if (p[0] < box[0] || p[1] < box[1] || p[2] < box[2] || p[0] > box[3] || p[1] > box[4] ||
            p[2] > box[5]) {
          continue;
        }
        double w[4];
        if (may_hold(list_[q], p) && barycentric(list_[q], p, w) &&
            std::min({w[0], w[1], w[2], w[3]}) >= 0) {
          return interpolate(list_[q], w);
        }
      }
    }
    // Outside every tet (or inside one only within rounding, its box missing the point):
    // the nearest ring of buckets with tets, the least negative coordinates.
    const std::uint32_t reach = std::max({n_[0], n_[1], n_[2]});
    for (std::uint32_t r = 0; r <= reach; ++r) {
      double best_min = -std::numeric_limits<double>::infinity();
      double best_value = 0;
      bool any = false;
      const auto range = [&](int c, std::uint32_t& first, std::uint32_t& last) {
        first = b[c] >= r ? b[c] - r : 0;
        last = std::min(b[c] + r, n_[c] - 1);
      };
      std::uint32_t f[3], l[3];
      for (int c = 0; c < 3; ++c) range(c, f[c], l[c]);
      for (std::uint32_t k = f[2]; k <= l[2]; ++k) {
        for (std::uint32_t j = f[1]; j <= l[1]; ++j) {
          for (std::uint32_t i = f[0]; i <= l[0]; ++i) {
            // Only the ring at distance r (the inside was searched before).
            const std::uint32_t d = std::max({dist(i, b[0]), dist(j, b[1]), dist(k, b[2])});
            if (d != r) continue;
            const std::size_t id = (std::size_t{k} * n_[1] + j) * n_[0] + i;
            for (std::uint32_t q = begin_[id]; q < begin_[id + 1]; ++q) {
              double w[4];
              if (!barycentric(list_[q], p, w)) continue;
              const double m = std::min({w[0], w[1], w[2], w[3]});
              if (m >= 0) return interpolate(list_[q], w);
              if (m > best_min) {
                best_min = m;
                for (double& x : w) x = std::max(x, 0.0);
                const double s = (w[0] + w[1]) + (w[2] + w[3]);
                for (double& x : w) x /= s;
                best_value = interpolate(list_[q], w);
              }
              any = true;
            }
          }
        }
      }
      if (any) return best_value;
    }
    return values_[0];  // (not reached: every tet is in some bucket)
  }

 private:
  std::uint32_t bucket(double x, int c) const {
    const double t = std::floor((x - lo_[c]) * scale_[c]);
    return static_cast<std::uint32_t>(std::clamp(t, 0.0, n_[c] - 1.0));
  }
  static std::uint32_t dist(std::uint32_t a, std::uint32_t b) { return a > b ? a - b : b - a; }
  const double* vertex(std::uint32_t t, int k) const {
    return &xyz_[3 * std::size_t{tets_[4 * std::size_t{t} + static_cast<std::size_t>(k)]}];
  }
  static double det3(const double* a, const double* b, const double* c) {
    return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
           a[2] * (b[0] * c[1] - b[1] * c[0]);
  }
  // The edges of tet t from its vertex 0 (e), p from there (q), and det(e).
  double frame(std::uint32_t t, const double* p, double (&e)[3][3], double (&q)[3]) const {
    const double* a = vertex(t, 0);
    for (int k = 0; k < 3; ++k) {
      for (int c = 0; c < 3; ++c) e[k][c] = vertex(t, k + 1)[c] - a[c];
    }
    for (int c = 0; c < 3; ++c) q[c] = p[c] - a[c];
    return det3(e[0], e[1], e[2]);
  }
  // False when barycentric() would give the point a negative coordinate w1, w2 or w3
  // (w_k = n_k / d: its sign is that of n_k d), without its divisions: most tets whose box
  // holds the point do not.
  bool may_hold(std::uint32_t t, const double* p) const {
    double e[3][3], q[3];
    const double d = frame(t, p, e, q);
    const auto opposite = [d](double n) { return d > 0 ? n < 0 : n > 0; };
    return !opposite(det3(q, e[1], e[2])) && !opposite(det3(e[0], q, e[2])) &&
           !opposite(det3(e[0], e[1], q));
  }
  // Barycentric coordinates of p in tet t (false: a flat tet).
  bool barycentric(std::uint32_t t, const double* p, double* w) const {
    double e[3][3], q[3];
    const double d = frame(t, p, e, q);
    if (d == 0 || !std::isfinite(d)) return false;
    w[1] = det3(q, e[1], e[2]) / d;
    w[2] = det3(e[0], q, e[2]) / d;
    w[3] = det3(e[0], e[1], q) / d;
    w[0] = 1 - (w[1] + w[2] + w[3]);
    return true;
  }
  double interpolate(std::uint32_t t, const double* w) const {
    double v = 0;
    for (int k = 0; k < 4; ++k)
      v += w[k] * values_[tets_[4 * std::size_t{t} + static_cast<std::size_t>(k)]];
    return v;
  }

  std::vector<double> xyz_;
  std::vector<std::uint32_t> tets_;
  std::vector<double> values_;
  double lo_[3], extent_[3], scale_[3];
  std::uint32_t n_[3];
  std::vector<std::uint32_t> begin_, list_;
  std::vector<double> box_;  // per tet: min x, y, z, max x, y, z
};

// A .vtu's PointData as density values (rho, or rho = h^-5 of a sizing), checked: finite and
// positive, an error naming the file, the DataArray's line and the point (VTK numbering).
TetMeshInput read_vtu_values(const std::string& path, bool sizing) {
  TetMeshInput m = read_tet_mesh(path);
  if (m.point_data.empty()) {
    throw Error(path + ": no PointData array of one component (one value per point)");
  }
  const std::string where = path + ":" + std::to_string(m.point_data_line) + ": PointData " +
                            m.point_data_name + ": point ";
  for (std::size_t v = 0; v < m.point_data.size(); ++v) {
    double x = m.point_data[v];
    if (!(x > 0) || !std::isfinite(x)) {
      throw Error(where + std::to_string(v) + " (from 0): " + format_double(x) + ": a " +
                  (sizing ? "size" : "density") + " must be finite and positive");
    }
    if (sizing) {
      x = density_of_size(x, 3);
      if (!std::isfinite(x)) {
        throw Error(where + std::to_string(v) + " (from 0): h^-5 overflows");
      }
    }
    m.point_data[v] = x;
  }
  return m;
}

}  // namespace

std::string DensityArgs::describe() const {
  if (!density.empty()) return "--density \"" + density + "\"";
  if (!sizing.empty()) return "--sizing \"" + sizing + "\"";
  if (!density_file.empty()) return "--density-file " + density_file;
  if (!sizing_file.empty()) return "--sizing-file " + sizing_file;
  return "";
}

void add_density_options(CLI::App* command, DensityArgs& args, int dimension, bool sizing) {
  const std::string vars = dimension == 2 ? "x and y" : "x, y and z";
  const std::string files = dimension == 2
                                ? ".vtk STRUCTURED_POINTS grid (nx ny 1), linear per half square"
                                : "Medit .sol (one value per vertex of the domain's tet mesh, "
                                  "linear per tet), a .vtu with PointData (linear in its tets) "
                                  "or a .vtk STRUCTURED_POINTS grid (trilinear)";
  CLI::Option* d =
      command
          ->add_option("--density", args.density,
                       "Density rho of the CVT: a formula in " + vars +
                           " (muparser: + - * / ^, sqrt, exp, log, sin, min, max, a<b?c:d, "
                           "_pi ...), e.g. \"1 + 10*x\"; it must be finite and positive")
          ->type_name("EXPR");
  CLI::Option* df =
      command->add_option("--density-file", args.density_file, "Density values from a " + files)
          ->type_name("FILE");
  d->excludes(df);
  if (sizing) {
    const std::string power = std::to_string(dimension + 2);
    CLI::Option* s = command
                         ->add_option("--sizing", args.sizing,
                                      "Target edge length h as a formula in " + vars +
                                          " (as --density); the density is rho = h^-" + power +
                                          "; alone, h is the edge length in model units and "
                                          "the vertex count follows; with --vertices, h "
                                          "gives the shape and --vertices the count")
                         ->type_name("EXPR");
    CLI::Option* sf =
        command
            ->add_option("--sizing-file", args.sizing_file,
                         "Target edge length h (rho = h^-" + power + ") from a " + files)
            ->type_name("FILE");
    s->excludes(d)->excludes(df)->excludes(sf);
    sf->excludes(d)->excludes(df);
  }
}

// ---- Expression: one muparser Parser per thread, and its bytecode run a block at a time.

// muparser's bytecode (ParserBase::GetByteCode: reverse Polish, the variables as pointers
// to the parser's x, y, z) run over columns of points, one instruction for a whole block
// of points, where Parser::Eval() interprets every instruction anew at each point (and its
// bulk mode Eval(double*, int) re-parses the formula on every call and runs an OpenMP loop
// in Debian's build). Each instruction does the parser's arithmetic in the parser's order,
// so a point's value is the parser's, bit for bit, with one exception: v^2 is v*v, the
// correctly rounded square (what the parser itself computes for x^2 of a variable, and
// GCC for pow(v, 2.0)), where the parser calls pow for an expression v: glibc's pow(v, 2)
// is one ulp off for about 1 v in 1100 (43878 of 5e7 random doubles). Instructions it does not run
// (the ternary a ? b : c, assignments, string and bulk functions, functions of more than 3 fixed
// arguments) leave it uncompiled, and the parser evaluates point by point.
class ColumnProgram {
 public:
  static constexpr std::size_t kBlock = 64;

  // False (and the program stays unusable) when the bytecode has an instruction it does
  // not run. `vars` are the parser's variables x, y, z.
  bool compile(const mu::ParserByteCode& code, const double* vars) {
    code_.clear();
    const mu::SToken* t = code.GetBase();
    int depth = 0, max_depth = 0;
    for (; t->Cmd != mu::cmEND; ++t) {
      Ins ins;
      int pushed = 0, popped = 0;
      switch (t->Cmd) {
        case mu::cmVAR:
        case mu::cmVARPOW2:
        case mu::cmVARPOW3:
        case mu::cmVARPOW4:
        case mu::cmVARMUL: {
          const std::ptrdiff_t v = t->Val.ptr - vars;
          if (v < 0 || v > 2) return false;
          ins.op = t->Cmd == mu::cmVAR       ? Op::kVar
                   : t->Cmd == mu::cmVARPOW2 ? Op::kVarPow2
                   : t->Cmd == mu::cmVARPOW3 ? Op::kVarPow3
                   : t->Cmd == mu::cmVARPOW4 ? Op::kVarPow4
                                             : Op::kVarMul;
          ins.var = static_cast<int>(v);
          ins.a = t->Val.data;
          ins.b = t->Val.data2;
          pushed = 1;
          break;
        }
        case mu::cmVAL:
          ins.op = Op::kVal;
          ins.a = t->Val.data2;
          pushed = 1;
          break;
        case mu::cmLE:
          ins.op = Op::kLe;
          popped = 1;
          break;
        case mu::cmGE:
          ins.op = Op::kGe;
          popped = 1;
          break;
        case mu::cmNEQ:
          ins.op = Op::kNeq;
          popped = 1;
          break;
        case mu::cmEQ:
          ins.op = Op::kEq;
          popped = 1;
          break;
        case mu::cmLT:
          ins.op = Op::kLt;
          popped = 1;
          break;
        case mu::cmGT:
          ins.op = Op::kGt;
          popped = 1;
          break;
        case mu::cmADD:
          ins.op = Op::kAdd;
          popped = 1;
          break;
        case mu::cmSUB:
          ins.op = Op::kSub;
          popped = 1;
          break;
        case mu::cmMUL:
          ins.op = Op::kMul;
          popped = 1;
          break;
        case mu::cmDIV:
          ins.op = Op::kDiv;
          popped = 1;
          break;
        case mu::cmLAND:
          ins.op = Op::kAnd;
          popped = 1;
          break;
        case mu::cmLOR:
          ins.op = Op::kOr;
          popped = 1;
          break;
        case mu::cmPOW:
          popped = 1;
          if (!code_.empty() && code_.back().op == Op::kVal && code_.back().a == 2.0) {
            // v^2: the value 2 pushed just before is dropped, v squared in place.
            code_.pop_back();
            --depth;
            popped = 0;
            ins.op = Op::kSquare;
          } else {
            ins.op = Op::kPow;
          }
          break;
        case mu::cmFUNC:
          ins.fun = t->Fun.cb;
          ins.argc = t->Fun.argc;
          if (ins.argc < -64) {
            return false;
          } else if (ins.argc < 0) {
            ins.op = Op::kMulti;  // -argc arguments
            pushed = 1;
            popped = -ins.argc;
          } else if (ins.argc <= 3) {
            ins.op = Op::kFun;
            pushed = 1;
            popped = ins.argc;
          } else {
            return false;
          }
          break;
        default:
          return false;  // cmIF/ELSE/ENDIF, cmASSIGN, string and bulk functions
      }
      depth += pushed - popped;
      if (depth < 1) return false;
      max_depth = std::max(max_depth, depth);
      // The result of the instruction is in column depth (1-based, as the parser's stack).
      ins.dst = depth;
      code_.push_back(ins);
    }
    if (depth != 1 || code_.empty()) return false;
    columns_ = static_cast<std::size_t>(max_depth) + 1;
    stack_.assign(columns_ * kBlock, 0.0);
    return true;
  }

  // out[k] = the formula at point k (dimension coordinates per point; z = 0 in 2D).
  void run(const double* p, std::size_t n, int dimension, double* out) {
    for (std::size_t first = 0; first < n; first += kBlock) {
      const std::size_t m = std::min(kBlock, n - first);
      double var[3][kBlock];
      for (std::size_t i = 0; i < m; ++i) {
        const double* q = p + (first + i) * static_cast<std::size_t>(dimension);
        var[0][i] = q[0];
        var[1][i] = q[1];
        var[2][i] = 0;
        if (dimension == 3) var[2][i] = q[2];
      }
      for (const Ins& ins : code_) execute(ins, var, m);
      const double* r = column(1);
      for (std::size_t i = 0; i < m; ++i) out[first + i] = r[i];
    }
  }

 private:
  enum class Op {
    kVar,
    kVarPow2,
    kVarPow3,
    kVarPow4,
    kVarMul,
    kVal,
    kLe,
    kGe,
    kNeq,
    kEq,
    kLt,
    kGt,
    kAdd,
    kSub,
    kMul,
    kDiv,
    kAnd,
    kOr,
    kPow,
    kSquare,
    kFun,
    kMulti
  };
  struct Ins {
    Op op = Op::kVal;
    int dst = 0;  // the column the result goes to
    int var = 0;
    double a = 0, b = 0;
    mu::generic_callable_type fun{};
    int argc = 0;
  };

  double* column(int k) { return stack_.data() + static_cast<std::size_t>(k) * kBlock; }

  template <class F>
  void binary(const Ins& ins, std::size_t m, F f) {
    double* d = column(ins.dst);
    const double* e = column(ins.dst + 1);
    for (std::size_t i = 0; i < m; ++i) d[i] = f(d[i], e[i]);
  }

  void execute(const Ins& ins, const double (&var)[3][kBlock], std::size_t m) {
    double* d = column(ins.dst);
    switch (ins.op) {
      case Op::kVar:
        for (std::size_t i = 0; i < m; ++i) d[i] = var[ins.var][i];
        return;
      case Op::kVarPow2:
        for (std::size_t i = 0; i < m; ++i) d[i] = var[ins.var][i] * var[ins.var][i];
        return;
      case Op::kVarPow3:
        for (std::size_t i = 0; i < m; ++i) {
          const double v = var[ins.var][i];
          d[i] = v * v * v;
        }
        return;
      case Op::kVarPow4:
        for (std::size_t i = 0; i < m; ++i) {
          const double v = var[ins.var][i];
          d[i] = v * v * v * v;
        }
        return;
      case Op::kVarMul:
        for (std::size_t i = 0; i < m; ++i) d[i] = var[ins.var][i] * ins.a + ins.b;
        return;
      case Op::kVal:
        for (std::size_t i = 0; i < m; ++i) d[i] = ins.a;
        return;
      case Op::kLe:
        return binary(ins, m, [](double u, double v) { return double(u <= v); });
      case Op::kGe:
        return binary(ins, m, [](double u, double v) { return double(u >= v); });
      case Op::kNeq:
        return binary(ins, m, [](double u, double v) { return double(u != v); });
      case Op::kEq:
        return binary(ins, m, [](double u, double v) { return double(u == v); });
      case Op::kLt:
        return binary(ins, m, [](double u, double v) { return double(u < v); });
      case Op::kGt:
        return binary(ins, m, [](double u, double v) { return double(u > v); });
      case Op::kAdd:
        return binary(ins, m, [](double u, double v) { return u + v; });
      case Op::kSub:
        return binary(ins, m, [](double u, double v) { return u - v; });
      case Op::kMul:
        return binary(ins, m, [](double u, double v) { return u * v; });
      case Op::kDiv:
        return binary(ins, m, [](double u, double v) { return u / v; });
      case Op::kAnd:
        return binary(ins, m, [](double u, double v) { return double(u != 0 && v != 0); });
      case Op::kOr:
        return binary(ins, m, [](double u, double v) { return double(u != 0 || v != 0); });
      case Op::kPow:
        return binary(ins, m, [](double u, double v) { return std::pow(u, v); });
      case Op::kSquare:
        for (std::size_t i = 0; i < m; ++i) d[i] = d[i] * d[i];
        return;
      case Op::kFun: {
        const mu::generic_callable_type& f = ins.fun;
        // The arguments are in columns dst .. dst + argc - 1; the result goes to dst.
        switch (ins.argc) {
          case 0:
            for (std::size_t i = 0; i < m; ++i) d[i] = f.call_fun<0>();
            return;
          case 1:
            for (std::size_t i = 0; i < m; ++i) d[i] = f.call_fun<1>(d[i]);
            return;
          case 2: {
            const double* e = column(ins.dst + 1);
            for (std::size_t i = 0; i < m; ++i) d[i] = f.call_fun<2>(d[i], e[i]);
            return;
          }
          default: {
            const double* e = column(ins.dst + 1);
            const double* g = column(ins.dst + 2);
            for (std::size_t i = 0; i < m; ++i) d[i] = f.call_fun<3>(d[i], e[i], g[i]);
            return;
          }
        }
      }
      case Op::kMulti: {
        const int argc = -ins.argc;
        double args[64];
        for (std::size_t i = 0; i < m; ++i) {
          for (int k = 0; k < argc; ++k) args[k] = column(ins.dst + k)[i];
          d[i] = ins.fun.call_multfun(args, argc);
        }
        return;
      }
    }
  }

  std::vector<Ins> code_;
  std::size_t columns_ = 0;
  std::vector<double> stack_;  // columns_ columns of kBlock values
};

struct Expression::Impl {
  struct Slot {
    mu::Parser parser;
    double v[3] = {0, 0, 0};
    ColumnProgram program;
    bool compiled = false;  // program runs the formula (else parser.Eval() per point)
    void load(const double* p, int dim) {
      v[0] = p[0];
      v[1] = p[1];
      v[2] = 0;
      if (dim == 3) v[2] = p[2];
    }
  };
  std::string text;
  int dimension;
  // Distinct for every Expression ever made in the process (never reused, unlike an
  // address): the key of the per-thread cache below.
  std::uint64_t id = next_id.fetch_add(1, std::memory_order_relaxed);
  mutable tbb::enumerable_thread_specific<std::unique_ptr<Slot>> slots;
  static std::atomic<std::uint64_t> next_id;

  std::unique_ptr<Slot> make() const {
    auto slot = std::make_unique<Slot>();
    slot->parser.DefineVar("x", &slot->v[0]);
    slot->parser.DefineVar("y", &slot->v[1]);
    if (dimension == 3) slot->parser.DefineVar("z", &slot->v[2]);
    slot->parser.SetExpr(text);
    slot->parser.Eval();  // parses: the bytecode exists from here on
    slot->compiled = slot->program.compile(slot->parser.GetByteCode(), slot->v);
    return slot;
  }

  // The calling thread's slot.
  Slot& local(int dim) const;
};

Expression::Expression(const std::string& text, int dimension, const std::string& option)
    : text_(text), dimension_(dimension), impl_(std::make_unique<Impl>()) {
  impl_->text = text;
  impl_->dimension = dimension;
  if (text.find_first_not_of(" \t") == std::string::npos) {
    throw UsageError(option + ": the formula is empty");
  }
  try {
    // muparser parses at the first evaluation: evaluate once to report syntax errors now.
    std::unique_ptr<Impl::Slot> slot = impl_->make();
    slot->parser.Eval();
    if (slot->parser.GetNumResults() != 1) {
      throw UsageError(option + " \"" + text + "\": expected one formula, not a list");
    }
  } catch (const mu::Parser::exception_type& e) {
    std::string message = e.GetMsg();
    while (!message.empty() && (message.back() == '.' || message.back() == ' ')) message.pop_back();
    // muparser's messages say "at position N" (from 0) where it knows one.
    if (message.find("position") == std::string::npos && e.GetPos() >= 0) {
      message += " at position " + std::to_string(e.GetPos());
    }
    throw UsageError(option + " \"" + text + "\": " + message + " (variables: x, y" +
                     (dimension == 3 ? ", z" : "") + ")");
  }
}

std::atomic<std::uint64_t> Expression::Impl::next_id{1};

Expression::~Expression() = default;

Expression::Impl::Slot& Expression::Impl::local(int) const {
  // The thread's slot of the expression it evaluated last, found without the hash lookup
  // of enumerable_thread_specific::local() (measured: about a tenth of an evaluation).
  // The id, never reused, tells whether the cached slot is this expression's.
  thread_local std::uint64_t cached_id = 0;
  thread_local Slot* cached_slot = nullptr;
  Slot* slot = cached_slot;
  if (cached_id != id) {
    std::unique_ptr<Slot>& owned = slots.local();
    if (!owned) owned = make();
    slot = owned.get();
    cached_id = id;
    cached_slot = slot;
  }
  return *slot;
}

double Expression::operator()(const double* p) const {
  Impl::Slot& slot = impl_->local(dimension_);
  if (slot.compiled) {
    double v = 0;
    slot.program.run(p, 1, dimension_, &v);
    return v;
  }
  slot.load(p, dimension_);
  return slot.parser.Eval();
}

void Expression::evaluate(const double* p, std::size_t n, double* out) const {
  Impl::Slot& slot = impl_->local(dimension_);
  if (slot.compiled) {
    slot.program.run(p, n, dimension_, out);
    return;
  }
  const std::size_t d = static_cast<std::size_t>(dimension_);
  for (std::size_t k = 0; k < n; ++k) {
    slot.load(p + d * k, dimension_);
    out[k] = slot.parser.Eval();
  }
}

bool Expression::compiled() const { return impl_->local(dimension_).compiled; }

double Expression::parser_value(const double* p) const {
  Impl::Slot& slot = impl_->local(dimension_);
  slot.load(p, dimension_);
  return slot.parser.Eval();
}

// ---- Densities.

Density2 make_density2(const DensityArgs& args, const Domain2& domain) {
  (void)domain;
  if (!args.density.empty() || !args.sizing.empty()) {
    const bool sizing = args.density.empty();
    auto f = std::make_shared<const FormulaDensity>(sizing ? args.sizing : args.density, 2, sizing);
    return Density2::function([f](double x, double y) {
      const double p[3] = {x, y, 0.0};  // (the third coordinate is never read in 2D)
      return (*f)(p);
    });
  }
  if (!args.density_file.empty() || !args.sizing_file.empty()) {
    const bool sizing = args.density_file.empty();
    const std::string& path = sizing ? args.sizing_file : args.density_file;
    if (input_extension(path) != ".vtk") {
      throw UsageError(std::string(sizing ? "--sizing-file" : "--density-file") +
                       ": in 2D the file must be a legacy .vtk STRUCTURED_POINTS grid, got '" +
                       path + "'");
    }
    Grid g = read_vtk_grid(path, sizing, 2);
    const double lo[2] = {g.origin[0], g.origin[1]};
    const double hi[2] = {g.origin[0] + (g.n[0] - 1) * g.spacing[0],
                          g.origin[1] + (g.n[1] - 1) * g.spacing[1]};
    return Density2::linear_grid(g.n[0], g.n[1], lo, hi, std::move(g.values));
  }
  return Density2{};
}

Density3 pointwise_density3(const Density3& rho, const Domain3& domain) {
  if (rho.kind != Density3::Kind::kVertexLinear) return rho;
  if (!domain.has_tets() || rho.vertex_values.size() != domain.nb_vertices()) {
    throw Error("pointwise_density3: a density linear per tet needs one value per vertex of " +
                domain.source() + "'s tet mesh");
  }
  std::vector<double> xyz(domain.vertex(0),
                          domain.vertex(0) + 3 * std::size_t{domain.nb_vertices()});
  std::vector<std::uint32_t> tets(4 * std::size_t{domain.nb_tets()});
  for (std::uint32_t t = 0; t < domain.nb_tets(); ++t) {
    for (int k = 0; k < 4; ++k)
      tets[4 * std::size_t{t} + static_cast<std::size_t>(k)] = domain.tet_vertex(t, k);
  }
  auto f =
      std::make_shared<const TetInterpolant>(std::move(xyz), std::move(tets), rho.vertex_values);
  return Density3::function([f](double x, double y, double z) {
    const double p[3] = {x, y, z};
    return (*f)(p);
  });
}

Density3 make_density3(const DensityArgs& args, const Domain3& domain, bool pointwise) {
  if (!args.density.empty() || !args.sizing.empty()) {
    const bool sizing = args.density.empty();
    auto f = std::make_shared<const FormulaDensity>(sizing ? args.sizing : args.density, 3, sizing);
    // In batches: the cell integrals evaluate a chunk of cells' quadrature points at once.
    return Density3::batch_function(
        [f](const double* xyz, std::size_t n, double* out) { f->evaluate(xyz, n, out); });
  }
  if (!args.density_file.empty() || !args.sizing_file.empty()) {
    const bool sizing = args.density_file.empty();
    const std::string option = sizing ? "--sizing-file" : "--density-file";
    const std::string& path = sizing ? args.sizing_file : args.density_file;
    const std::string ext = input_extension(path);
    if (ext == ".sol") {
      if (!domain.has_tets()) {
        throw UsageError(option + ": a .sol gives values at the vertices of a tet mesh, and " +
                         domain.source() + " is a surface; use a .vtu or .vtk file");
      }
      Density3 rho = Density3::vertex_linear(read_sol(path, sizing, domain.nb_vertices()));
      return pointwise ? pointwise_density3(rho, domain) : rho;
    }
    if (ext == ".vtu") {
      TetMeshInput m = read_vtu_values(path, sizing);
      auto f = std::make_shared<const TetInterpolant>(std::move(m.xyz), std::move(m.tets),
                                                      std::move(m.point_data));
      return Density3::function([f](double x, double y, double z) {
        const double p[3] = {x, y, z};
        return (*f)(p);
      });
    }
    if (ext == ".vtk") {
      auto g = std::make_shared<const Grid>(read_vtk_grid(path, sizing, 3));
      return Density3::function([g](double x, double y, double z) {
        const double p[3] = {x, y, z};
        return trilinear(*g, p);
      });
    }
    throw UsageError(option +
                     ": expected a Medit .sol, a .vtu with PointData or a legacy .vtk "
                     "STRUCTURED_POINTS grid, got '" +
                     path + "'");
  }
  return Density3{};
}

}  // namespace voroclip::cli
