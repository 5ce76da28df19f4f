// The restricted surface of the 3D clipped Voronoi diagram (clip3d_surface.cpp; Yan et
// al. 2011, sec. 4.1): SurfaceRvd, the pass over the boundary triangles, and
// RestrictedSurface, what it leaves for the cells (clip3d_cells.h) and clip3d.cpp.
#pragma once

#include <tbb/enumerable_thread_specific.h>

#include <cstdint>
#include <vector>

#include "clip3d_internal.h"

namespace voroclip {

namespace clip3 {

// The crossings of one Voronoi edge with the surface: the Delaunay triangle
// (s[0] < s[1] < s[2]), how many, the point when there is one, and sigma, the sign of
// n . N with n = (p_s1 - p_s0) x (p_s2 - p_s0) and N the outward normal of the boundary
// triangle crossed (voronoi_edge_direction3d): the edge, oriented along n, leaves the
// volume there when sigma > 0.
struct EdgeCrossings {
  std::uint32_t s[3], count;
  double x[3];
  std::int8_t sigma;
  // count >= 2: the crossings are multi_crossings[first, first + count), in triangle order.
  std::uint32_t first;
};

// One crossing of a Voronoi edge crossed several times: the point and sigma (as above).
struct CrossingPoint {
  double x[3];
  std::int8_t sigma;
};

// The restricted surface: the boundary cells, their share of the integrals from the
// surface, and the crossings of the Voronoi edges with the surface.
struct RestrictedSurface {
  std::vector<EdgeCrossings> crossings;        // sorted by s
  std::vector<CrossingPoint> multi_crossings;  // of the edges crossed several times
  std::vector<std::uint32_t> crossing_begin;   // per site a: crossings with s[0] == a
  std::vector<std::uint8_t> is_boundary;       // per site
  // Per site: 1 when a Voronoi edge of its cell crosses the surface several times.
  std::vector<std::uint8_t> multi_crossed;
  std::vector<std::uint32_t> boundary_cells;  // sorted
  std::vector<std::uint32_t> boundary_slot;   // per site: index in boundary_cells
  // Per boundary cell: its restricted polygons' triangles, in triangle order (CSR).
  std::vector<std::uint32_t> cell_tri_begin, cell_tris;
  std::vector<Moments> surface_moments;  // per boundary cell: the polygons' cones
  std::vector<double> surface_area;      // per site
  // keep_surface: per vertex of the polygons (SurfaceRvd::compute's, before
  // to_input_indices), the site across the polygon edge from it (kNone: an edge on the
  // triangle's boundary).
  std::vector<std::uint32_t> surface_across;

  // The crossings of the Voronoi edge of sites a, b, c (any order; nullptr: none).
  const EdgeCrossings* find_crossings(std::uint32_t a, std::uint32_t b, std::uint32_t c) const;
};

struct TriVertex;
struct TriPoly;

// The restricted surface pass, in parallel over chunks of boundary triangles; per thread a
// Scratch of its own (clip3d_surface.cpp) and the thread's Stars, whose neighbour lists and
// stars the cells read again later.
class SurfaceRvd {
 public:
  explicit SurfaceRvd(const Clip3Context& ctx) : ctx_(ctx) {}
  // The restricted surface. With `polygons` (keep_surface), also its polygons, per cell in
  // triangle order (ClippedVoronoi3::surface_polygons, cells by index).
  RestrictedSurface compute(tbb::enumerable_thread_specific<Stars>& stars,
                            ClippedVoronoi3::Polygons* polygons) const;

 private:
  struct Scratch;
  struct Chunk;
  // A boundary triangle: its index, corners (domain vertices, in the triangle's order).
  struct Tri {
    std::uint32_t b, mv[3];
    const double* x[3];
  };
  // The cell of point p (perturbed), by descent from cell c.
  std::uint32_t descend(const double* p, std::uint32_t c, Stars& stars) const;
  Sign tri_side(const Tri& tri, const TriVertex& v, std::uint32_t c, std::uint32_t j) const;
  void tri_coords(const Tri& tri, const TriVertex& v, std::uint32_t c, double* x) const;
  ClipVertex3 tri_symbolic(const Tri& tri, const TriVertex& v, std::uint32_t c) const;
  // Triangle b as the `stamp`-th chunk sees it (Scratch::corner_cell): its polygons, one per
  // cell it meets, appended to chunk.
  void clip_triangle(std::uint32_t b, std::uint32_t stamp, Stars& stars, Scratch& s,
                     Chunk& chunk) const;
  // A callback density: flushes the thread's DensityBatch and copies each polygon's
  // weighted moments (Chunk::weighted) into the chunk's sums.
  void finish_weighted(Chunk& chunk) const;
  void emit_polygon(const Tri& tri, std::uint32_t c, const TriPoly& p, Scratch& s,
                    Chunk& chunk) const;

  Clip3Context ctx_;
};

}  // namespace clip3

}  // namespace voroclip
