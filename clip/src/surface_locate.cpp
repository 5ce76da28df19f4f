// Exact point location in the volume bounded by a closed triangle surface: the parity of
// the crossings of a ray (the Jordan-Brouwer separation theorem; the point-in-polyhedron
// test of O'Rourke, "Computational Geometry in C", 2nd ed., sec. 7.5), made exact and
// degeneracy-free by a symbolic perturbation of the query point (Edelsbrunner & Mücke,
// "Simulation of simplicity", 1990), on a uniform grid of the triangles' projections.
//
// Ray. From the query q along frame coordinate 2 (a world axis; surface_locate.h: the
// frame is a cyclic permutation of the world coordinates, so every orientation keeps its
// sign), towards +z or -z. Write A, B, C for a triangle's corners, n = (B - A) x (C - A)
// and s0 = sign n_z = orient2d of the projections (A, B, C) on the plane (x, y).
//   Perturbation: q is replaced by q' = q + (e, e^2, 0), e > 0 infinitesimal. For a
//     projected edge (A, B),
//       orient2d(A, B, q') = orient2d(A, B, q) - e (B_y - A_y) + e^2 (B_x - A_x),
//     the sign of the first non-zero term; zero only when A and B project to one point.
//     The perturbed ray meets no projected vertex and no projected edge, and misses every
//     triangle parallel to it (s0 = 0: a zero-area projection; the perturbed point is off
//     the line it projects to, as two of its projected edges, summing to zero with the
//     third, run in opposite directions). It crosses triangle T when q' is strictly inside
//     T's projection: the three perturbed edge signs equal s0 != 0.
//   Ahead: the crossing is at q + t e_z with n . (q + t e_z - A) = 0, and orient3d(A, B, C,
//     q) = det[A - q; B - q; C - q] = (A - q) . n (Shewchuk's convention, predicates.h), so
//     t = orient3d(A, B, C, q) / n_z: ahead on the +z ray when sign orient3d = s0, on the
//     -z ray when it is -s0. A triangle entirely beyond q in z (in the ray's direction) is
//     ahead without it.
//   On the surface: q is in closed triangle T with s0 != 0 exactly when its projection is
//     in T's closed projection (no edge sign equals -s0) and orient3d(A, B, C, q) = 0; when
//     T is crossed this must be checked first (q' may be on either side of T's plane). For
//     s0 = 0, q's projection must be on the line T projects to (all three edge signs zero),
//     then orient3d = 0 and the closed test in a projection where T has non-zero area (for
//     a triangle of zero area, collinear corners: q on one of its edges).
//   Answer: ZERO when q is in a closed triangle among those examined (every triangle whose
//     bounding box contains q is: see the grid below); otherwise q is at a positive
//     distance from the surface, q' is on the same side of it for every small e, and the
//     parity of the perturbed ray's crossings, all transversal through triangle interiors,
//     decides: odd POSITIVE, even NEGATIVE.
//
// Grid. Over frame (x, y), about kCellsPerTriangle cells per triangle, square-ish; each
// cell lists the triangles whose bounding box meets it (closed comparisons of exact
// coordinates; cell() is monotone, so a triangle whose box contains q is listed in q's
// cell), sorted by the triangles' lowest z, each entry with float bounds at or below the
// lowest and at or above the highest z (they only filter: a triangle wrongly kept is
// decided exactly, one is skipped, or counted without orient3d, only when its float bounds
// prove it). The -z ray needs the triangles with lowest z <= q_z, a prefix of the list
// (one binary search); the +z ray those with highest z >= q_z: the rest of the list, whose
// triangles lie entirely above q (no orient3d), and the entries of the prefix that reach
// q_z (a test on the entry). A query takes the direction with the shorter part. Most
// entries are then rejected by their triangle's box in (x, y); three orient2d decide the
// others, and orient3d only those that straddle q_z. The ray's axis is the one whose
// projected triangle boxes cover the projected bounding box the fewest times on average
// (the expected number of candidates). Triangles are stored by the cell of their box's
// centre and their vertices in order of first use, so that a cell's data lie together.
//
// Circumcentres. The same decisions for the circumcentre x of p0..p3, a rational point:
// orient2d_circumcenter and orient3d_circumcenter (predicates.h) are the exact predicates;
// the perturbation's terms depend on A and B only. A query starts from the proven box
// around x of circumcenter3d_enclosure: every bounding-box test compares the triangle's
// exact box with it (conservatively), and the projected edge signs are first decided by
// the box filter below, which costs an orient2d. When there is no box (a nearly flat
// tet), x is first compared exactly with the six planes of the surface's bounding box
// (outside: NEGATIVE, as mesh/src/extract3d.cpp does), and the box is the bounding box.
// When the box spans several cells along a grid axis, x's cell is found by binary search
// with exact comparisons of x_k against the cell bounds bound_[k][i], the smallest doubles
// of each cell: if bound[i] <= x_k < bound[i + 1], every double d <= x_k is below
// bound[i + 1] (cell(d) <= i) and every d >= x_k is at least bound[i] (cell(d) >= i), so
// every triangle whose box contains x is listed in cell i.
#include "surface_locate.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <string>

#include "voroclip/core.h"
#include "voroclip/predicates.h"

namespace voroclip::detail {

namespace {

// Half a cell per triangle (a triangle then meets about 6 cells): on the shared surfaces
// the query times are flat between 0.25 and 1 cells per triangle, the build time grows
// with the cells (bench/bench_surface_locate.cpp).
constexpr double kCellsPerTriangle = 0.5;
constexpr std::uint32_t kMaxCellsPerAxis = 4096;
constexpr double kMaxCells = 0x1p22;
constexpr double kInf = std::numeric_limits<double>::infinity();

int to_int(Sign s) { return static_cast<int>(s); }

// The perturbed sign of orient2d(a, b, q') for an edge with orient2d(a, b, q) = 0 (see
// the header comment): sign(a_y - b_y), else sign(b_x - a_x); 0 when a, b project to one
// point.
int perturbed_edge_sign(const double* a, const double* b) {
  if (a[1] != b[1]) return a[1] > b[1] ? 1 : -1;
  if (a[0] != b[0]) return b[0] > a[0] ? 1 : -1;
  return 0;
}

// Box filter of orient2d((a_0, a_1), (b_0, b_1), x) for an exact point x known only to lie
// in the box |x_k - c_k| <= h_k (k = 0, 1): +1 / -1 when the sign is certain, else 0.
//   V(x) = (b_0 - a_0)(x_1 - a_1) - (b_1 - a_1)(x_0 - a_0) is affine in x, so |V(x) - V(c)|
//   <= G = |b_0 - a_0| h_1 + |b_1 - a_1| h_0 (exact differences). orient2d_approx(a, b, c)
//   computes V(c) with |det - V(c)| <= E + 2^-1074, E = kOrient2dBound * scale (predicates.h:
//   the orient2d filter's bound; its two products add at most 2^-1075 each if they
//   underflow). The computed g (rounded differences, |b_k - a_k| <= |fl(b_k - a_k)| /
//   (1 - u), u = 2^-53; two products and a sum rounded, the products possibly underflowing)
//   satisfies G <= g / (1 - u)^3 + 2^-1073 <= g (1 + 4u) + 2^-1073. The threshold
//   (E~ + g)(1 + 2^-40) + 2^-990, evaluated with four roundings (each losing at most a
//   factor 1 - u), exceeds E + g (1 + 4u) + 2^-1072: a |det| above it has V(x)'s sign. An
//   infinite or NaN det, scale or g never decides.
int box_orient2d(const double* a, const double* b, const double* c, const double* h) {
  const Approx r = orient2d_approx(a, b, c);
  const double g = std::fabs(b[0] - a[0]) * h[1] + std::fabs(b[1] - a[1]) * h[0];
  const double bound = (kOrient2dBound * r.scale + g) * (1 + 0x1p-40) + 0x1p-990;
  const double m = std::fabs(r.det);
  if (m > bound && m <= DBL_MAX) return decided_sign(r.det);
  return 0;
}

// Floats below / above x, for the lists' z bounds (conservative: they only filter; exact
// decisions compare the doubles). Out of float's range they saturate at +-FLT_MAX or the
// infinity on the safe side.
float float_below(double x) {
  const auto f = static_cast<float>(x);
  return static_cast<double>(f) > x ? std::nextafter(f, -std::numeric_limits<float>::infinity())
                                    : f;
}
float float_above(double x) {
  const auto f = static_cast<float>(x);
  return static_cast<double>(f) < x ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

// Order-preserving map of non-NaN floats to unsigned integers (-0 just below +0).
std::uint32_t ordered_float(float x) {
  std::uint32_t b;
  std::memcpy(&b, &x, sizeof b);
  return (b & 0x80000000u) != 0 ? ~b : b | 0x80000000u;
}

// The projection of frame point p along frame axis k: coordinates (k + 1, k + 2) mod 3.
void project(int k, const double* p, double* out) {
  static constexpr int kFirst[3] = {1, 2, 0}, kSecond[3] = {2, 0, 1};
  out[0] = p[kFirst[k]];
  out[1] = p[kSecond[k]];
}

// Order-preserving map of doubles to unsigned integers (-0 just below +0), for the
// bisection over doubles, and its inverse.
constexpr std::uint64_t kTopBit = std::uint64_t{1} << 63;
std::uint64_t ordered(double x) {
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return (b & kTopBit) != 0 ? ~b : b | kTopBit;
}
double from_ordered(std::uint64_t k) {
  const std::uint64_t b = (k & kTopBit) != 0 ? k & ~kTopBit : ~k;
  double x;
  std::memcpy(&x, &b, sizeof x);
  return x;
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Queries: a point or a circumcentre in frame coordinates, with a closed box [lo, hi]
// known to contain it and the exact predicates the location needs.

struct SurfaceLocator::PointQuery {
  double p[3];
  double lo[3], hi[3];

  // orient2d of the projections on frame (x, y): (a, b, q).
  int side(const double* a, const double* b) const { return to_int(orient2d(a, b, p)); }
  // The same in the projection along frame axis k.
  int side(int k, const double* a, const double* b) const {
    double a2[2], b2[2], p2[2];
    project(k, a, a2);
    project(k, b, b2);
    project(k, p, p2);
    return to_int(orient2d(a2, b2, p2));
  }
  int orient(const double* a, const double* b, const double* c) const {
    return to_int(orient3d(a, b, c, p));
  }
  // sign(q_k - t).
  int compare(int k, double t) const { return int{p[k] > t} - int{p[k] < t}; }
};

struct SurfaceLocator::CircumcenterQuery {
  double p[4][3];  // the sites, frame coordinates
  bool boxed = false;
  double centre[3], halfwidth[3];  // circumcenter3d_enclosure's, when boxed
  // A box known to contain x (unbounded until one is known).
  double lo[3] = {-kInf, -kInf, -kInf}, hi[3] = {kInf, kInf, kInf};

  int side(const double* a, const double* b) const {
    if (boxed) {
      const int s = box_orient2d(a, b, centre, halfwidth);
      if (s != 0) return s;
    }
    return to_int(orient2d_circumcenter(2, a, b, p[0], p[1], p[2], p[3]));
  }
  int side(int k, const double* a, const double* b) const {
    if (boxed) {
      double a2[2], b2[2], c2[2], h2[2];
      project(k, a, a2);
      project(k, b, b2);
      project(k, centre, c2);
      project(k, halfwidth, h2);
      const int s = box_orient2d(a2, b2, c2, h2);
      if (s != 0) return s;
    }
    return to_int(orient2d_circumcenter(k, a, b, p[0], p[1], p[2], p[3]));
  }
  int orient(const double* a, const double* b, const double* c) const {
    return to_int(orient3d_circumcenter(a, b, c, p[0], p[1], p[2], p[3]));
  }
  // sign(x_k - t): the plane x_k = t through a = t e_k, b = a + e_{k+1}, c = a + e_{k+2}
  // has n = e_k, so orient3d(a, b, c, x) = -(x - a) . n = -(x_k - t).
  int compare(int k, double t) const {
    if (lo[k] > t) return 1;
    if (hi[k] < t) return -1;
    double a[3] = {0, 0, 0};
    a[k] = t;
    double b[3] = {a[0], a[1], a[2]}, c[3] = {a[0], a[1], a[2]};
    b[(k + 1) % 3] = 1;
    c[(k + 2) % 3] = 1;
    return -to_int(orient3d_circumcenter(a, b, c, p[0], p[1], p[2], p[3]));
  }
};

// ---------------------------------------------------------------------------------------
// Build.

SurfaceLocator::SurfaceLocator(const std::vector<double>& xyz,
                               const std::vector<std::uint32_t>& triangles)
    : SurfaceLocator(xyz, triangles, -1, 0) {}

SurfaceLocator::SurfaceLocator(const std::vector<double>& xyz,
                               const std::vector<std::uint32_t>& triangles, int axis,
                               int direction) {
  if (axis < -1 || axis > 2 || direction < -1 || direction > 1) {
    throw Error("SurfaceLocator: axis " + std::to_string(axis) + " / direction " +
                std::to_string(direction) + " out of range");
  }
  if (triangles.size() % 3 != 0 || xyz.size() % 3 != 0) {
    throw Error("SurfaceLocator: the arrays do not hold whole vertices and triangles");
  }
  const std::size_t nv = xyz.size() / 3, nt = triangles.size() / 3;
  if (nt > std::size_t{0xffffffffu} / 4) throw Error("SurfaceLocator: too many triangles");
  direction_ = direction;
  for (std::size_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = triangles[3 * t + static_cast<std::size_t>(k)];
      if (v >= nv) {
        throw Error("SurfaceLocator: triangle " + std::to_string(t) + " has vertex index " +
                    std::to_string(v) + ", out of range (" + std::to_string(nv) +
                    " vertices, numbered from 0)");
      }
    }
  }
  if (nt == 0) return;
  empty_ = false;

  // World bounding box and, per axis, the mean number of projected triangle boxes over a
  // point of the projected bounding box (the expected number of candidates of a ray).
  double wlo[3], whi[3];
  for (int c = 0; c < 3; ++c) wlo[c] = whi[c] = xyz[3 * std::size_t{triangles[0]} + c];
  double cover[3] = {0, 0, 0};
  for (std::size_t t = 0; t < nt; ++t) {
    double tlo[3], thi[3];
    for (int c = 0; c < 3; ++c) {
      const double x0 = xyz[3 * std::size_t{triangles[3 * t]} + c];
      const double x1 = xyz[3 * std::size_t{triangles[3 * t + 1]} + c];
      const double x2 = xyz[3 * std::size_t{triangles[3 * t + 2]} + c];
      if (!(std::isfinite(x0) && std::isfinite(x1) && std::isfinite(x2))) {
        const std::uint32_t v =
            triangles[3 * t + (std::isfinite(x0) ? std::isfinite(x1) ? 2 : 1 : 0)];
        throw Error("SurfaceLocator: vertex " + std::to_string(v) +
                    " (from 0) has a non-finite coordinate");
      }
      tlo[c] = std::min(std::min(x0, x1), x2);
      thi[c] = std::max(std::max(x0, x1), x2);
      wlo[c] = std::min(wlo[c], tlo[c]);
      whi[c] = std::max(whi[c], thi[c]);
    }
    for (int a = 0; a < 3; ++a) {
      const int i = (a + 1) % 3, j = (a + 2) % 3;
      cover[a] += (thi[i] - tlo[i]) * (thi[j] - tlo[j]);
    }
  }
  if (axis < 0) {
    double best = std::numeric_limits<double>::infinity();
    axis = 2;
    for (int a = 2; a >= 0; --a) {
      const int i = (a + 1) % 3, j = (a + 2) % 3;
      const double area = (whi[i] - wlo[i]) * (whi[j] - wlo[j]);
      const double mean = area > 0 ? cover[a] / area : std::numeric_limits<double>::infinity();
      if (mean < best) {  // NaN and infinite means never win; ties keep the later axis
        best = mean;
        axis = a;
      }
    }
  }
  for (int k = 0; k < 3; ++k) frame_[k] = (axis + 1 + k) % 3;
  for (int k = 0; k < 3; ++k) {
    lo_[k] = wlo[frame_[k]];
    hi_[k] = whi[frame_[k]];
  }

  // The grid.
  const double extent[2] = {hi_[0] - lo_[0], hi_[1] - lo_[1]};
  const bool usable[2] = {extent[0] > 0 && extent[0] <= DBL_MAX,
                          extent[1] > 0 && extent[1] <= DBL_MAX};
  const double cells =
      std::min(kMaxCells, std::max(1.0, kCellsPerTriangle * static_cast<double>(nt)));
  double want[2] = {1, 1};
  if (usable[0] && usable[1]) {
    const double h = std::sqrt(extent[0] / cells * extent[1]);
    want[0] = extent[0] / h;
    want[1] = extent[1] / h;
  } else if (usable[0] || usable[1]) {
    want[usable[0] ? 0 : 1] = cells;
  }
  for (int k = 0; k < 2; ++k) {
    const double n = std::isfinite(want[k]) ? std::round(want[k]) : 1;
    n_[k] = usable[k] ? static_cast<std::uint32_t>(
                            std::min(static_cast<double>(kMaxCellsPerAxis), std::max(1.0, n)))
                      : 1;
    inv_h_[k] = usable[k] ? static_cast<double>(n_[k]) / extent[k] : 0;
    // bound_[k][i]: the smallest double in [lo, hi] with cell >= i, by bisection over the
    // doubles' order (cell(lo) = 0 and cell(hi) = n - 1: (hi - lo) * inv_h rounds to
    // within a few ulps of n >= 1).
    bound_[k].assign(n_[k] + 1, 0);
    bound_[k][0] = -std::numeric_limits<double>::infinity();
    bound_[k][n_[k]] = std::numeric_limits<double>::infinity();
    for (std::uint32_t i = 1; i < n_[k]; ++i) {
      std::uint64_t below = ordered(lo_[k]), above = ordered(hi_[k]);  // cell < i, >= i
      while (above - below > 1) {
        const std::uint64_t mid = below + (above - below) / 2;
        if (cell_coordinate(k, from_ordered(mid)) >= i) {
          above = mid;
        } else {
          below = mid;
        }
      }
      bound_[k][i] = from_ordered(above);
    }
  }
  const std::size_t nb_cells = std::size_t{n_[0]} * n_[1];

  // Triangles ordered by the cell of their box's centre (counting sort), so that a cell's
  // triangles lie close together in memory; vertices in the frame, numbered in the order of
  // their first use by the triangles so ordered (unused vertices are dropped).
  std::vector<std::uint32_t> order(nt);
  {
    std::vector<std::uint32_t> home(nt);
    std::vector<std::uint32_t> place(nb_cells + 1, 0);
    for (std::size_t t = 0; t < nt; ++t) {
      double mid[2];
      for (int k = 0; k < 2; ++k) {
        const auto c = static_cast<std::size_t>(frame_[k]);
        const double x0 = xyz[3 * std::size_t{triangles[3 * t]} + c];
        const double x1 = xyz[3 * std::size_t{triangles[3 * t + 1]} + c];
        const double x2 = xyz[3 * std::size_t{triangles[3 * t + 2]} + c];
        const double l = std::min(std::min(x0, x1), x2), h = std::max(std::max(x0, x1), x2);
        mid[k] = l + 0.5 * (h - l);
      }
      home[t] = cell_coordinate(0, mid[0]) + n_[0] * cell_coordinate(1, mid[1]);
      ++place[home[t] + 1];
    }
    std::partial_sum(place.begin(), place.end(), place.begin());
    for (std::uint32_t t = 0; t < nt; ++t) order[place[home[t]]++] = t;
  }
  constexpr std::uint32_t kUnused = 0xffffffffu;
  std::vector<std::uint32_t> renumber(nv, kUnused);
  tris_.resize(nt);
  verts_.clear();
  for (std::size_t s = 0; s < nt; ++s) {
    Triangle& f = tris_[s];
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t v = triangles[3 * std::size_t{order[s]} + k];
      if (renumber[v] == kUnused) {
        renumber[v] = static_cast<std::uint32_t>(verts_.size() / 3);
        double fp[3];
        to_frame(&xyz[3 * std::size_t{v}], fp);
        verts_.insert(verts_.end(), fp, fp + 3);
      }
      f.v[k] = renumber[v];
    }
    f.area_sign = to_int(orient2d(vertex(f, 0), vertex(f, 1), vertex(f, 2)));
  }

  // Cell lists: each triangle in every cell its box meets. Counted, then filled in the
  // order of (lower, tri) (a stable radix sort of the triangles by lower), so that every
  // cell's list comes out sorted. (Filling in the triangles' order and sorting each cell
  // was twice as slow; the writes in z order touch one open cache line per cell.)
  struct Box {
    std::uint32_t x0, x1, y0, y1;
    float zlo, zhi;
  };
  std::vector<Box> boxes(nt);
  std::uint64_t nb_refs = 0;
  for (std::uint32_t t = 0; t < nt; ++t) {
    const double* p[3] = {vertex(tris_[t], 0), vertex(tris_[t], 1), vertex(tris_[t], 2)};
    double l[3], h[3];
    for (int k = 0; k < 3; ++k) {
      l[k] = std::min(std::min(p[0][k], p[1][k]), p[2][k]);
      h[k] = std::max(std::max(p[0][k], p[1][k]), p[2][k]);
    }
    const Box b{cell_coordinate(0, l[0]), cell_coordinate(0, h[0]), cell_coordinate(1, l[1]),
                cell_coordinate(1, h[1]), float_below(l[2]),        float_above(h[2])};
    boxes[t] = b;
    nb_refs += std::uint64_t{b.x1 - b.x0 + 1} * (b.y1 - b.y0 + 1);
  }
  if (nb_refs > 0xffffffffu) {
    throw Error("SurfaceLocator: too many (triangle, cell) pairs: the triangles are too large");
  }
  cell_start_.assign(nb_cells + 1, 0);
  for (const Box& b : boxes) {
    for (std::uint32_t y = b.y0; y <= b.y1; ++y) {
      for (std::uint32_t x = b.x0; x <= b.x1; ++x) ++cell_start_[x + n_[0] * std::size_t{y} + 1];
    }
  }
  std::partial_sum(cell_start_.begin(), cell_start_.end(), cell_start_.begin());
  refs_.resize(cell_start_.back());
  {
    std::vector<std::uint32_t> by_lower(nt), scratch(nt), key(nt);
    for (std::uint32_t t = 0; t < nt; ++t) {
      by_lower[t] = t;
      key[t] = ordered_float(boxes[t].zlo);
    }
    for (int shift = 0; shift < 32; shift += 16) {  // LSD radix sort, 16-bit digits: stable
      std::vector<std::uint32_t> bucket(0x10001, 0);
      for (const std::uint32_t t : by_lower) ++bucket[((key[t] >> shift) & 0xffff) + 1];
      std::partial_sum(bucket.begin(), bucket.end(), bucket.begin());
      for (const std::uint32_t t : by_lower) scratch[bucket[(key[t] >> shift) & 0xffff]++] = t;
      by_lower.swap(scratch);
    }
    std::vector<std::uint32_t> place(cell_start_.begin(), cell_start_.end() - 1);
    for (const std::uint32_t t : by_lower) {
      const Box& b = boxes[t];
      for (std::uint32_t y = b.y0; y <= b.y1; ++y) {
        for (std::uint32_t x = b.x0; x <= b.x1; ++x) {
          refs_[place[x + n_[0] * std::size_t{y}]++] = {b.zlo, b.zhi, t};
        }
      }
    }
  }
}

std::uint32_t SurfaceLocator::cell_coordinate(int k, double x) const {
  const double d = (x - lo_[k]) * inv_h_[k];
  if (!(d > 0)) return 0;
  const double last = static_cast<double>(n_[k] - 1);
  return d >= last ? n_[k] - 1 : static_cast<std::uint32_t>(d);
}

// ---------------------------------------------------------------------------------------
// Queries.

Sign SurfaceLocator::locate(const double* p) const {
  PointQuery q;
  to_frame(p, q.p);
  if (!(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]))) {
    throw Error("SurfaceLocator::locate: a coordinate is not finite");
  }
  if (empty_) return Sign::negative;
  for (int k = 0; k < 3; ++k) {
    if (q.p[k] < lo_[k] || q.p[k] > hi_[k]) return Sign::negative;
    q.lo[k] = q.hi[k] = q.p[k];
  }
  return locate_query(q);
}

Sign SurfaceLocator::locate_circumcenter(const double* p0, const double* p1, const double* p2,
                                         const double* p3) const {
  CircumcenterQuery q;
  to_frame(p0, q.p[0]);
  to_frame(p1, q.p[1]);
  to_frame(p2, q.p[2]);
  to_frame(p3, q.p[3]);
  q.boxed = circumcenter3d_enclosure(q.p[0], q.p[1], q.p[2], q.p[3], q.centre, q.halfwidth);
  if (q.boxed) {
    // The half-width covers the rounding of centre +- halfwidth (circumcenter3d.h).
    for (int k = 0; k < 3; ++k) {
      q.lo[k] = q.centre[k] - q.halfwidth[k];
      q.hi[k] = q.centre[k] + q.halfwidth[k];
    }
  }
  if (empty_) {
    // Still an exact answer about the input: coplanar sites throw.
    if (!q.boxed) q.compare(0, 0);
    return Sign::negative;
  }
  if (q.boxed) {
    for (int k = 0; k < 3; ++k) {
      if (q.hi[k] < lo_[k] || q.lo[k] > hi_[k]) return Sign::negative;
    }
  } else {
    // No box: the exact side of the six planes of the bounding box (throws for coplanar
    // sites), then the bounding box is the box.
    for (int k = 0; k < 3; ++k) {
      if (q.compare(k, lo_[k]) < 0 || q.compare(k, hi_[k]) > 0) return Sign::negative;
      q.lo[k] = lo_[k];
      q.hi[k] = hi_[k];
    }
  }
  return locate_query(q);
}

template <class Query>
std::uint32_t SurfaceLocator::bracket(const Query& q, int k, std::uint32_t first,
                                      std::uint32_t last) const {
  // The largest i in [first, last] with bound_[k][i] <= x_k (bound_[k][first] <= x_k holds).
  while (first < last) {
    const std::uint32_t mid = first + (last - first + 1) / 2;
    if (q.compare(k, bound_[k][mid]) >= 0) {
      first = mid;
    } else {
      last = mid - 1;
    }
  }
  return first;
}

template <class Query>
Sign SurfaceLocator::locate_query(Query& q) const {
  std::uint32_t cell[2];
  for (int k = 0; k < 2; ++k) {
    const std::uint32_t first = cell_coordinate(k, q.lo[k]), last = cell_coordinate(k, q.hi[k]);
    cell[k] = first == last ? first : bracket(q, k, first, last);
    // The cell's closed extent is part of the box: x_k is in [bound[i], bound[i + 1]].
    q.lo[k] = std::max(q.lo[k], bound_[k][cell[k]]);
    q.hi[k] = std::min(q.hi[k], bound_[k][cell[k] + 1]);
  }
  // Candidates: for -z the triangles of the cell with lowest z <= hi_z (a prefix of its
  // list), for +z those with highest z >= lo_z (the rest, and the prefix's entries that
  // reach lo_z: a cheap test on the list); the direction with the shorter part.
  const std::size_t c = cell[0] + std::size_t{n_[0]} * cell[1];
  const Ref* first = refs_.data() + cell_start_[c];
  const Ref* end = refs_.data() + cell_start_[c + 1];
  const Ref* split =
      std::upper_bound(first, end, q.hi[2], [](double z, const Ref& r) { return z < r.lower; });
  const int direction = direction_ != 0 ? direction_ : split - first < end - split ? -1 : 1;
  return direction > 0 ? scan(q, first, end, 1) : scan(q, first, split, -1);
}

template <class Query>
Sign SurfaceLocator::scan(const Query& q, const Ref* first, const Ref* end, int direction) const {
  unsigned crossings = 0;
  for (const Ref* r = first; r < end; ++r) {
    if (direction > 0 && r->upper < q.lo[2]) continue;  // behind
    const Triangle& t = tris_[r->tri];
    const double* a = vertex(t, 0);
    const double* b = vertex(t, 1);
    const double* d = vertex(t, 2);
    if (std::max(std::max(a[0], b[0]), d[0]) < q.lo[0] ||
        std::min(std::min(a[0], b[0]), d[0]) > q.hi[0] ||
        std::max(std::max(a[1], b[1]), d[1]) < q.lo[1] ||
        std::min(std::min(a[1], b[1]), d[1]) > q.hi[1]) {
      continue;
    }
    const int s0 = t.area_sign;
    // Entirely beyond the query in the ray's direction (so the query is not on it).
    const bool beyond = direction > 0 ? r->lower > q.hi[2] : r->upper < q.lo[2];
    if (s0 == 0) {
      // Parallel to the ray: never crossed; the query may be on it.
      if (beyond || q.side(a, b) != 0 || q.side(b, d) != 0 || q.side(d, a) != 0) continue;
      if (in_closed_triangle(q, t)) return Sign::zero;
      continue;
    }
    int o[3] = {q.side(a, b), 0, 0};
    if (o[0] == -s0) continue;
    o[1] = q.side(b, d);
    if (o[1] == -s0) continue;
    o[2] = q.side(d, a);
    if (o[2] == -s0) continue;
    // The projection of the query is in the closed projection of the triangle.
    bool crossed = true;
    if (o[0] == 0) crossed = perturbed_edge_sign(a, b) == s0;
    if (o[1] == 0) crossed = crossed && perturbed_edge_sign(b, d) == s0;
    if (o[2] == 0) crossed = crossed && perturbed_edge_sign(d, a) == s0;
    if (beyond) {
      crossings += crossed;
      continue;
    }
    // Straddling the query's z: on the triangle when on its plane; else crossed ahead when
    // orient3d has the sign direction * s0.
    const int o3 = q.orient(a, b, d);
    if (o3 == 0) return Sign::zero;
    crossings += crossed && o3 == direction * s0;
  }
  return crossings % 2 == 1 ? Sign::positive : Sign::negative;
}

template <class Query>
bool SurfaceLocator::in_closed_triangle(const Query& q, const Triangle& t) const {
  const double* a = vertex(t, 0);
  const double* b = vertex(t, 1);
  const double* d = vertex(t, 2);
  if (q.orient(a, b, d) != 0) return false;
  for (int k = 0; k < 2; ++k) {
    // A projection where the triangle has non-zero area.
    double a2[2], b2[2], d2[2];
    project(k, a, a2);
    project(k, b, b2);
    project(k, d, d2);
    const int s = to_int(orient2d(a2, b2, d2));
    if (s != 0) return q.side(k, a, b) != -s && q.side(k, b, d) != -s && q.side(k, d, a) != -s;
  }
  // Zero area (collinear corners): on one of its edges. On segment [u, v] when on its
  // line (the three components of (v - u) x (q - u) are zero) and in its bounding box.
  const auto on_segment = [&](const double* u, const double* v) {
    for (int k = 0; k < 3; ++k) {
      if (q.compare(k, std::min(u[k], v[k])) < 0 || q.compare(k, std::max(u[k], v[k])) > 0) {
        return false;
      }
    }
    return q.side(0, u, v) == 0 && q.side(1, u, v) == 0 && q.side(2, u, v) == 0;
  };
  return on_segment(a, b) || on_segment(b, d) || on_segment(d, a);
}

}  // namespace voroclip::detail
