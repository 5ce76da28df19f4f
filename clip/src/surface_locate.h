// Exact point location in the volume bounded by a closed triangle surface (Surface3::locate,
// Surface3::locate_circumcenter; clip/src/surface_locate.cpp has the method).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "voroclip/predicates.h"

namespace voroclip::detail {

// Inside / outside of a closed, embedded triangle surface, exactly.
//
// The surface is given by its vertices (x y z each) and triangles (3 vertex indices
// each); it must be closed (every edge in an even number of triangles) and embedded
// (triangles meet only at shared edges and vertices): Surface3 validates that first. The
// orientation of the triangles is not used: a point is inside when a ray from it crosses
// the surface an odd number of times.
//
// locate(p) answers POSITIVE strictly inside, ZERO on the surface (in a closed triangle),
// NEGATIVE outside, for any finite p; locate_circumcenter does the same for the circumcentre
// of four points (a rational point), with the same exactness. No epsilon: every decision is
// an exact predicate (filtered), and the degenerate hits of the ray (through an edge or a
// vertex, along a triangle parallel to it) are resolved by a symbolic perturbation of the
// query point, so that the parity is always that of a ray in general position.
//
// locate throws Error for a non-finite coordinate, locate_circumcenter for coplanar points
// (no circumcentre) and non-finite coordinates. Zero-area triangles (collinear corners) are
// allowed: they are never crossed, and a point on one is on the surface.
//
// The arrays are copied (only the used vertices); queries are const and thread-safe. Cost
// (bench/bench_surface_locate.cpp, one core): the build is a few linear passes (counting
// and radix sorts), about 0.2 ms per thousand triangles (gargoyle, 100k: about 20 ms); a
// query about 0.1-0.2 microseconds for a point of the bounding box, up to 1 for a point
// within rounding of the surface (exact stages), 0.2-0.45 for a circumcentre.
class SurfaceLocator {
 public:
  SurfaceLocator() = default;
  // Throws Error for an index out of range or a non-finite coordinate of a used vertex.
  SurfaceLocator(const std::vector<double>& xyz, const std::vector<std::uint32_t>& triangles);
  // For tests: the ray along coordinate `axis` (0, 1, 2; -1: chosen by the build, as
  // above) and towards `direction` (+1, -1; 0: chosen per query, as above). Every choice
  // gives the same answers; the tests check that they do.
  SurfaceLocator(const std::vector<double>& xyz, const std::vector<std::uint32_t>& triangles,
                 int axis, int direction);

  Sign locate(const double* p) const;
  Sign locate_circumcenter(const double* p0, const double* p1, const double* p2,
                           const double* p3) const;

 private:
  // The ray's frame: frame coordinate k is world coordinate (axis + 1 + k) % 3 (a cyclic
  // permutation: orientations keep their signs), so the ray runs along frame coordinate 2
  // and the grid is over frame coordinates 0 and 1. A triangle: its corners (indices into
  // verts_, the vertices in frame coordinates), and the exact sign of the area of its
  // projection on frame (x, y) (the sign of its normal's z).
  struct Triangle {
    std::uint32_t v[3];
    int area_sign;
  };
  // An entry of a cell's list (see refs_).
  struct Ref {
    float lower, upper;  // floats at or below / above the triangle's lowest / highest z
    std::uint32_t tri;   // index in tris_
  };
  struct PointQuery;
  struct CircumcenterQuery;

  template <class Query>
  Sign locate_query(Query& q) const;
  template <class Query>
  Sign scan(const Query& q, const Ref* first, const Ref* end, int direction) const;
  template <class Query>
  bool in_closed_triangle(const Query& q, const Triangle& t) const;
  template <class Query>
  std::uint32_t bracket(const Query& q, int k, std::uint32_t first, std::uint32_t last) const;
  std::uint32_t cell_coordinate(int k, double x) const;
  const double* vertex(const Triangle& t, int k) const {
    return verts_.data() + 3 * std::size_t{t.v[k]};
  }
  void to_frame(const double* p, double* f) const {
    f[0] = p[frame_[0]];
    f[1] = p[frame_[1]];
    f[2] = p[frame_[2]];
  }

  int frame_[3] = {0, 1, 2};  // world coordinate of each frame coordinate
  int direction_ = 0;         // forced ray direction (+1, -1), 0: chosen per query
  bool empty_ = true;         // no triangle: everything is outside
  double lo_[3] = {0, 0, 0}, hi_[3] = {0, 0, 0};  // bounding box, frame coordinates
  // The grid over frame coordinates 0 and 1: n_[k] cells along k, cell(x) =
  // clamp(floor((x - lo_[k]) * inv_h_[k]), 0, n_[k] - 1) (monotone in x); bound_[k][i] the
  // smallest double x with cell(x) >= i (i = 1 .. n - 1; bound_[k][0] = -inf, [n] = +inf).
  std::uint32_t n_[2] = {1, 1};
  double inv_h_[2] = {0, 0};
  std::vector<double> bound_[2];
  // Cell c (= cx + n_[0] cy) lists the triangles whose bounding box meets it, entries
  // cell_start_[c] .. cell_start_[c + 1] of refs_, sorted by (lower, tri).
  std::vector<std::uint32_t> cell_start_;
  std::vector<Ref> refs_;
  std::vector<Triangle> tris_;  // in the order of their box centre's cell
  std::vector<double> verts_;   // x y z per vertex, frame coordinates
};

}  // namespace voroclip::detail
