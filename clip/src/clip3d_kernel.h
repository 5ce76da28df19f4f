// The convex-cell kernel of the 3D clipped Voronoi diagram (clip3d_kernel.cpp): a tet of
// the domain's mesh (or one of its facets) clipped exactly by the bisectors of a cell, and
// the tet-by-tet integration of a cell built on it (Yan et al. 2011, sec. 4.2). Usable on
// its own, as Geogram's ConvexCell: ConvexCell holds its scratch (one per thread) and the
// context it reads.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "clip3d_internal.h"

namespace voroclip {

namespace clip3 {

// A vertex of a clip: the three planes that define it (any order).
struct PVertex {
  Plane p[3];
};

// A convex polyhedron (several faces) or polygon (one face). Face k lies on plane
// face_plane[k] and has the vertices face_verts[face_begin[k] .. face_begin[k + 1]).
// Faces are oriented consistently (adjacent faces run through a shared edge in opposite
// directions): the tet's facets as in Domain3::kTetFacetVertex.
struct Poly {
  std::vector<PVertex> verts;
  std::vector<Plane> face_plane;
  std::vector<std::uint32_t> face_begin{0};
  std::vector<std::uint32_t> face_verts;

  void clear() {
    verts.clear();
    face_plane.clear();
    face_begin.assign(1, 0);
    face_verts.clear();
  }
  std::uint32_t nb_faces() const { return static_cast<std::uint32_t>(face_plane.size()); }
  bool empty() const { return face_plane.empty(); }
};

// The plane shared by vertices u and w (adjacent along an edge) other than `face`.
Plane other_common_plane(const PVertex& u, const PVertex& w, Plane face);

// True when |v - p_c|^2 < |v - p_j|^2 certainly: v is strictly on c's side of
// bisector(c, j), whatever the perturbation (which only breaks exact ties). Floating-point
// filter: with a = v - p_c, b = v - p_j rounded (relative error u = 2^-53 each), the sums of
// squares A, B carry a relative error below gamma_5 (three products, two sums of
// non-negative terms) and A - B one more rounding, so |(A - B) - F| <= gamma_6 (A + B) /
// (1 - gamma_5) < 6.01 u (A + B) for the exact F = |v - p_c|^2 - |v - p_j|^2; the bound is
// taken as 8 u (A + B) (its own rounding included). Underflow: each product that underflows
// errs by at most 2^-1074, covered by the 1e-300 term. Overflow and NaN make the
// comparison fail (infinite bound, NaN value): the caller then asks the exact predicate.
inline bool certainly_nearer(const double* v, const double* pc, const double* pj) {
  const double a0 = v[0] - pc[0], a1 = v[1] - pc[1], a2 = v[2] - pc[2];
  const double b0 = v[0] - pj[0], b1 = v[1] - pj[1], b2 = v[2] - pj[2];
  const double A = (a0 * a0 + a1 * a1) + a2 * a2;
  const double B = (b0 * b0 + b1 * b1) + b2 * b2;
  return A - B < -(8.9e-16 * (A + B) + 1e-300);
}

// Clips tets of the domain by the bisectors of a cell, and integrates a cell tet by tet.
// A polyhedron's vertices are kept as the three planes that define them (PVertex), among
// the four facets of the current tet and the bisectors of the cell's site; every side
// test is an exact predicate on the input points (clip3d_kernel.cpp).
class ConvexCell {
 public:
  explicit ConvexCell(const Clip3Context& ctx) : ctx_(ctx) {}

  // Tet t (its facet `only_facet` alone when >= 0: a triangle) clipped by the bisectors of
  // site i with each of `nbrs` (keeping i's side): the piece, possibly empty, valid until
  // the next call.
  const Poly& clip_tet(std::uint32_t t, int only_facet, std::uint32_t i,
                       const std::vector<std::uint32_t>& nbrs);
  // Cell c tet by tet from the tets seeds[0, nb_seeds): its integrals, (cell, tet) pairs and,
  // with keep_geometry, its faces (one piece per tet) added to res. With seeds_out, the
  // (neighbour, tet) pairs where a piece has a face on their bisector are appended.
  void clip_cell(std::uint32_t c, const std::uint32_t* seeds, std::size_t nb_seeds, CellOut& res,
                 std::vector<std::pair<std::uint32_t, std::uint32_t>>* seeds_out);

  // Exact side of a vertex of a clip in tet t of cell i with respect to bisector(i, j):
  // POSITIVE when on j's side (clipped away).
  Sign side(const PVertex& v, std::uint32_t t, std::uint32_t i, std::uint32_t j) const;
  // Coordinates of a vertex, from its sorted global ids (bit-identical in every cell).
  void coords(const PVertex& v, std::uint32_t t, std::uint32_t i, double* x) const;
  // Tet t (its four facets) as a polyhedron, or its facet only_facet alone.
  static void init_tet(Poly& p, int only_facet);
  // Clips `in` by bisector(i, j) into `res` (keeps site i's side). False when nothing was
  // cut (res untouched: use `in`).
  bool clip(const Poly& in, Poly& res, std::uint32_t t, std::uint32_t i, std::uint32_t j);

 private:
  static void add_tet(const double* o, const double* a, const double* b, const double* d,
                      Moments& res);
  void add_tet_linear(std::uint32_t t, const double* o, const double* a, const double* b,
                      const double* d, Moments& res) const;
  double density_at(std::uint32_t t, const double* x) const;

  // clip()'s buffers: per vertex of `in`, its side and new index; the edges cut (their
  // keys, the new vertices), and the new face's edges, chained.
  struct ClipBuffers {
    std::vector<std::int8_t> sides;
    std::vector<std::uint32_t> remap;
    std::vector<std::uint64_t> edge_keys;
    std::vector<std::uint32_t> edge_new;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> cut_edges;
    std::vector<std::uint32_t> chain_next;
  };

  Clip3Context ctx_;
  Poly a_, b_;  // the piece, and the next one (swapped)
  ClipBuffers buf_;
  std::vector<std::uint32_t> nbrs_;  // clip_cell: the cell's neighbours
  std::vector<double> xyz_;          // clip_cell: a piece's vertices
  // clip_cell: per domain tet, the last cell (+ 1) that queued it; the FIFO of tets.
  std::vector<std::uint32_t> stamp_, queue_;
};

}  // namespace clip3

}  // namespace voroclip
