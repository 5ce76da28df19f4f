// Delaunay3: the 3D Delaunay triangulation by Bowyer–Watson insertion (Bowyer 1981,
// Watson 1981) in BRIO order (Amenta, Choi & Rote 2003), with exact predicates and
// symbolic perturbation, on flat arrays.
//
// Storage (about 36 bytes per tetrahedron):
//   tet_vertices_[4t + k]   vertex k of tet t (a point index, or kInfinite)
//   tet_neighbors_[4t + f]  4t' + f': the tet across facet f (the facet opposite vertex f)
//                           and the local index of that facet in t'
//   tet_stamp_[t]           scratch mark for the cavity search (compared with a counter,
//                           so it is never cleared); kFreeStamp marks a recycled slot
// The hull is closed by infinite tets: each holds kInfinite and one hull facet. Deleted
// slots go to free_tets_ and are reused first.
//
// Local numbering. A finite tet (p0, p1, p2, p3) is positive: orient3d(p0, p1, p2, p3) > 0.
// Facet f is opposite vertex f, its vertices listed as kFacetVertex[f]:
//
//            p3                 facet 0: (p1, p2, p3)
//           /|\                 facet 1: (p0, p3, p2)
//          / | \                facet 2: (p3, p0, p1)
//         /  |  \               facet 3: (p2, p1, p0)
//       p0 --+-- p2
//          \ | /                With this order, orient3d(facet, q) < 0 for q on the side
//           \|/                 of the opposite vertex (the tet's inside) and > 0 beyond
//            p1                 the facet. The neighbour lists the shared facet reversed.
//
// Conflict (the Bowyer–Watson cavity of a new point q):
//   finite tet     insphere_sos(p0, p1, p2, p3, q) > 0 (indices = input indices).
//   infinite tet   with hull facet (a, b, c) as listed in it (inside of the hull on the
//                  positive side): orient3d(a, b, c, q) < 0, q strictly outside; or q on
//                  the facet's plane and inside the facet's circumcircle, decided with the
//                  same perturbation: insphere_sos(a, b, c, d, q) > 0 where d is the
//                  fourth vertex of the finite tet behind the facet. (Any sphere through
//                  a, b, c meets the plane in their circumcircle; the sign of the
//                  perturbed terms does not depend on d, whose own term is orient3d(a, b,
//                  c, q) = 0.) The infinite vertex is thus the limit of the lifting, as in
//                  CGAL and Geogram: coplanar points on the hull are triangulated within
//                  the hull facet, and no tet of zero volume is ever created.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "voroclip/predicates.h"

namespace voroclip {

class Delaunay3 {
 public:
  static constexpr std::uint32_t kInfinite = 0xffffffffu;
  static constexpr std::uint32_t kNoTet = 0xffffffffu;

  // kFacetVertex[f][i]: local index of the i-th vertex of facet f (see the diagram above).
  static constexpr int kFacetVertex[4][3] = {{1, 2, 3}, {0, 3, 2}, {3, 0, 1}, {2, 1, 0}};

  Delaunay3() = default;
  // Triangulates n points given as packed x y z. The array is referenced, not copied: it
  // must outlive the triangulation (or the next build()).
  Delaunay3(const double* xyz, std::uint32_t n) { build(xyz, n); }

  // (Re)builds on new points, reusing every buffer (CVT rebuilds each iteration).
  // Throws voroclip::Error for non-finite coordinates or fewer than 4 affinely
  // independent points.
  void build(const double* xyz, std::uint32_t n);

  std::uint32_t nb_points() const { return nb_points_; }
  std::uint32_t nb_unique_points() const { return nb_unique_; }
  // The smallest input index with the same coordinates as point i (i itself if unique).
  std::uint32_t duplicate_of(std::uint32_t i) const { return duplicate_of_[i]; }

  // Slots, including infinite and free ones: iterate t < nb_tet_slots() and skip with
  // is_free(t) / is_infinite(t).
  std::uint32_t nb_tet_slots() const { return static_cast<std::uint32_t>(tet_stamp_.size()); }
  std::uint32_t nb_finite_tets() const { return nb_finite_tets_; }
  bool is_free(std::uint32_t t) const { return tet_stamp_[t] == kFreeStamp; }
  bool is_infinite(std::uint32_t t) const;
  std::uint32_t tet_vertex(std::uint32_t t, int k) const { return tet_vertices_[4 * t + k]; }
  std::uint32_t tet_adjacent(std::uint32_t t, int f) const { return tet_neighbors_[4 * t + f] / 4; }
  int tet_adjacent_facet(std::uint32_t t, int f) const {
    return static_cast<int>(tet_neighbors_[4 * t + f] % 4);
  }
  // A tet incident to vertex v (kNoTet for duplicates and unused points).
  std::uint32_t vertex_tet(std::uint32_t v) const { return vertex_tet_[v]; }

  // The finite tets incident to vertex v, and its Delaunay neighbours (the sites of the
  // adjacent Voronoi cells), appended to `out` (cleared first), sorted.
  void vertex_tets(std::uint32_t v, std::vector<std::uint32_t>& out) const;
  void vertex_neighbors(std::uint32_t v, std::vector<std::uint32_t>& out) const;
  // Hull vertices (finite vertices of infinite tets), sorted.
  std::vector<std::uint32_t> hull_vertices() const;
  // Circumcenter of finite tet t, in floating point (not exact; for output and clipping).
  void circumcenter(std::uint32_t t, double* out) const;

  // Bytes held by the triangulation's arrays (capacities), for memory reports.
  std::size_t memory_bytes() const;

  // Exact checks, used by the tests on every result. Return an empty string when valid,
  // else a description of the first defect found.
  std::string check_topology() const;
  std::string check_delaunay() const;

 private:
  static constexpr std::uint32_t kFreeStamp = 0xffffffffu;

  const double* point(std::uint32_t v) const { return pts_ + 3 * static_cast<std::size_t>(v); }
  // The index symbolic perturbation uses for vertex v: always the input index.
  std::uint32_t sos_id(std::uint32_t v) const { return sos_ids_ ? sos_ids_[v] : v; }
  std::uint32_t new_tet();
  void free_tet(std::uint32_t t);
  void set_neighbors(std::uint32_t t, int f, std::uint32_t t2, int f2) {
    tet_neighbors_[4 * t + f] = 4 * t2 + static_cast<std::uint32_t>(f2);
    tet_neighbors_[4 * t2 + f2] = 4 * t + static_cast<std::uint32_t>(f);
  }
  int infinite_slot(std::uint32_t t) const;
  bool in_conflict(std::uint32_t t, std::uint32_t q) const;
  std::uint32_t locate(std::uint32_t q, std::uint32_t hint, std::uint32_t& duplicate) const;
  void insert(std::uint32_t q, std::uint32_t& hint);
  std::uint32_t initial_tetrahedron(const std::vector<std::uint32_t>& order);

  const double* xyz_ = nullptr;
  // During construction vertices are numbered in insertion order and their coordinates
  // copied in that order (sorted_xyz_), so that the points of neighbouring tets are
  // neighbours in memory; input_id_ maps them back. build() ends by renumbering the tets
  // to input indices; from then on pts_ = xyz_ and sos_ids_ = nullptr.
  const double* pts_ = nullptr;
  const std::uint32_t* sos_ids_ = nullptr;
  std::vector<double> sorted_xyz_;
  std::vector<std::uint32_t> input_id_;
  std::uint32_t nb_points_ = 0;
  std::uint32_t nb_unique_ = 0;
  std::uint32_t nb_finite_tets_ = 0;
  StaticFilter filter_;

  std::vector<std::uint32_t> tet_vertices_;
  std::vector<std::uint32_t> tet_neighbors_;
  std::vector<std::uint32_t> tet_stamp_;
  std::vector<std::uint32_t> free_tets_;
  std::vector<std::uint32_t> vertex_tet_;
  std::vector<std::uint32_t> duplicate_of_;
  std::vector<std::uint32_t> duplicate_internal_;  // during construction, internal ids
  std::uint32_t stamp_ = 0;

  // Per-insertion scratch, reused.
  std::vector<std::uint32_t> cavity_;
  std::vector<std::uint32_t> stack_;
  struct BoundaryFacet {
    std::uint32_t tet;        // the tet outside the cavity
    int facet;                // its facet on the cavity boundary
    int dead_facet;           // the facet's index in the cavity tet behind it
    std::uint32_t vertex[4];  // that cavity tet's vertices, q in place of the opposite one
  };
  std::vector<BoundaryFacet> boundary_;
  std::vector<std::uint64_t> edge_keys_;
  std::vector<std::uint32_t> edge_values_;
};

}  // namespace voroclip
