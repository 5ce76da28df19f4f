// voroclip/clip.h — clipped Voronoi diagrams (the module's one public header).
//
// Domain2: a validated polygonal domain with holes (several components allowed).
// ClippedVoronoi2: the Voronoi diagram of sites clipped to a Domain2 (Yan, Wang, Lévy & Liu,
// CAD 2011, sec. 3), with every combinatorial decision exact (see clip2d.cpp).
#pragma once

#include <array>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "voroclip/core.h"
#include "voroclip/delaunay.h"
#include "voroclip/predicates.h"

namespace voroclip {

namespace detail {
class SurfaceLocator;  // clip/src/surface_locate.h
}  // namespace detail

// ---------------------------------------------------------------------------------------
// Domain2: a bounded open set of the plane whose boundary is a set of disjoint simple
// polygonal rings.
//
// Built from PolygonRings (core.h) and validated exactly (orient2d): the constructor
// throws Error, naming the source, the ring(s), the vertex indices (as in the input) and
// the defect, for
//   - a ring with fewer than 3 distinct points, or of zero area (all points collinear);
//   - a ring that crosses or touches itself (including a vertex on a non-adjacent edge and
//     overlapping collinear edges), or two rings that cross or touch;
//   - (JSON) a hole that is not inside its polygon's outer ring, a hole inside another
//     hole, an outer ring inside another polygon's ring in a way that breaks the nesting;
//   - (.poly) a hole marker that does not lie in a hole;
//   - a non-finite coordinate.
// Handled, not rejected: a repeated closing point and repeated consecutive points are
// dropped (nb_dropped_points() counts them).
// Messages name rings by their index in the input (per polygon when a JSON file holds
// several; with the line where it starts for .poly) and vertices by their position in
// their input ring (.poly: the file's vertex numbers). Contacts are counted per pair of
// edges, and the first of the most serious kind is described: crossing, spike (consecutive
// edges folding back), collinear overlap, touch at a point.
// Cost: validation is O(n log n) (a sweep, see domain2.cpp), whatever the shape.
//
// Storage after validation: vertices packed ring after ring; ring r owns the vertices
// [ring_begin(r), ring_end(r)); outer boundaries run counter-clockwise and holes clockwise,
// so the domain is always on the LEFT of an edge (a ring is reversed, when needed, after
// its first vertex, which stays first). Edge v is the segment from vertex v to next(v).
class Domain2 {
 public:
  Domain2() = default;
  explicit Domain2(const PolygonRings& rings);

  const std::string& source() const { return source_; }
  std::uint32_t nb_vertices() const { return static_cast<std::uint32_t>(ring_of_.size()); }
  std::uint32_t nb_edges() const { return nb_vertices(); }
  std::uint32_t nb_rings() const { return static_cast<std::uint32_t>(ring_hole_.size()); }
  std::uint32_t ring_begin(std::uint32_t r) const {
    assert(r < nb_rings());
    return ring_begin_[r];
  }
  std::uint32_t ring_end(std::uint32_t r) const {
    assert(r < nb_rings());
    return ring_begin_[r + 1];
  }
  // True when ring r bounds a hole (it is clockwise); false for an outer boundary.
  bool is_hole(std::uint32_t r) const {
    assert(r < nb_rings());
    return ring_hole_[r] != 0;
  }
  std::uint32_t ring_of(std::uint32_t v) const {
    assert(v < nb_vertices());
    return ring_of_[v];
  }
  const double* vertex(std::uint32_t v) const {
    assert(v < nb_vertices());
    return xy_.data() + 2 * static_cast<std::size_t>(v);
  }
  const std::vector<double>& coords() const { return xy_; }
  std::uint32_t next(std::uint32_t v) const {
    const std::uint32_t r = ring_of(v);
    return v + 1 == ring_begin_[r + 1] ? ring_begin_[r] : v + 1;
  }
  std::uint32_t prev(std::uint32_t v) const {
    const std::uint32_t r = ring_of(v);
    return v == ring_begin_[r] ? ring_begin_[r + 1] - 1 : v - 1;
  }
  // Where vertex v and ring r came from in the PolygonRings: the index of v's point (at
  // xy[2 * source_vertex(v)]) and of r's ring (rings keep their input order).
  std::uint32_t source_vertex(std::uint32_t v) const { return source_vertex_[v]; }
  std::uint32_t source_ring(std::uint32_t r) const { return source_ring_[r]; }
  // The polygon ring r belongs to when the input says (JSON, or rings given with their
  // polygons: from 0), else -1 (.poly: roles from nesting).
  std::int32_t ring_polygon(std::uint32_t r) const { return ring_polygon_[r]; }
  // True when vertex v is a corner: not collinear with prev(v) and next(v) (exact).
  bool is_corner(std::uint32_t v) const;
  // The tag of edge e, for boundary conditions: the .poly segment marker of the input
  // segment it is, marker 0 meaning "no marker" and giving 1 (as in Triangle's output), else
  // its ring's tag: with polygons given (JSON), the ring's position in the input from 1
  // (one polygon: 1 its outer ring, 2, 3, ... its holes; several: polygon after polygon,
  // each outer ring then its holes); by nesting (.poly), 1 for every outer ring, 2, 3, ...
  // for the holes in ring order.
  std::int32_t edge_tag(std::uint32_t e) const { return edge_tag_[e]; }
  // The .poly regional attributes: points (packed x y) and their attribute, as read.
  const std::vector<double>& region_points() const { return region_points_; }
  const std::vector<double>& region_attributes() const { return region_attributes_; }
  // Regional attribute k (in the order given), for messages, as the file names it:
  // "regional attribute 3 (line 31)" (.poly: its own number and line), else
  // "regional attribute k (from 0, in the order given)".
  std::string region_name(std::size_t k) const;

  // Area (outer rings minus holes), summed in floating point: shoelace terms relative to
  // each ring's first vertex, with error-free differences and products, compensated sums
  // (close to the exactly rounded area).
  double area() const { return area_; }
  // Bounding box: lo = (x, y), hi = (x, y).
  const double* bbox_lo() const { return bbox_; }
  const double* bbox_hi() const { return bbox_ + 2; }
  std::uint32_t nb_dropped_points() const { return nb_dropped_; }

  // Exact point location: POSITIVE strictly inside, ZERO on the boundary, NEGATIVE outside;
  // throws Error for a non-finite point. The crossing parity of an axis-parallel ray, over
  // the edges of the point's band (below), in the direction whose band holds fewer edges:
  // a few edges for ordinary domains, up to most of them when every axis-parallel line
  // through the point meets the boundary very often.
  Sign locate(const double* p) const;

 private:
  friend struct Domain2Impl;
  std::string source_;
  std::vector<double> xy_;
  std::vector<std::uint32_t> ring_begin_;  // nb_rings + 1
  std::vector<std::uint8_t> ring_hole_;
  std::vector<std::uint32_t> ring_of_;
  std::vector<std::uint32_t> source_vertex_;
  std::vector<std::uint32_t> source_ring_;
  std::vector<std::int32_t> ring_polygon_;
  std::vector<std::int32_t> edge_tag_;
  std::vector<double> region_points_, region_attributes_;
  std::vector<std::int64_t> region_number_;
  std::vector<std::uint32_t> region_line_;
  double area_ = 0;
  double bbox_[4] = {0, 0, 0, 0};
  std::uint32_t nb_dropped_ = 0;
  // Point-location index, one per axis: bands_[0] cuts the plane into horizontal bands (by
  // y), bands_[1] into vertical ones (by x), of width h from lo; band k lists the edges
  // edge[begin[k] .. begin[k + 1]) whose extent along that axis meets it. The band of a
  // coordinate is a monotone function of it, so an edge whose closed extent holds the
  // coordinate is listed in its band: the index only filters, decisions stay exact.
  struct Bands {
    double lo = 0, h = 1;
    std::vector<std::uint32_t> begin, edge;
    std::uint32_t band(double t) const;
  };
  Bands bands_[2];
};

// ---------------------------------------------------------------------------------------
// Density for the cell integrals.
//   constant   rho = value everywhere (closed forms);
//   callback   rho(x, y) given by the user, integrated with a degree-5 rule (7 points,
//              positive weights) on the triangles of each cell's fan: exact for rho a
//              polynomial of degree <= 3; must be defined on the convex hull of each cell
//              piece, deterministic and safe to call from several threads at once;
//   grid       piecewise linear on a regular grid of nx x ny nodes over [lo, hi] (each
//              grid square split along its diagonal from (i, j) to (i+1, j+1)), evaluated
//              at the fan's vertices and integrated exactly as a linear function on each
//              fan triangle: exact when rho is linear; values outside the grid clamp.
struct Density2 {
  enum class Kind { kConstant, kCallback, kGrid };
  Kind kind = Kind::kConstant;
  double value = 1.0;
  std::function<double(double, double)> callback;
  std::uint32_t nx = 0, ny = 0;
  double lo[2] = {0, 0}, hi[2] = {1, 1};
  std::vector<double> grid;  // nx * ny values, row-major in y: grid[j * nx + i]

  static Density2 constant(double rho);
  static Density2 function(std::function<double(double, double)> rho);
  static Density2 linear_grid(std::uint32_t nx, std::uint32_t ny, const double lo[2],
                              const double hi[2], std::vector<double> values);
  // rho at (x, y) (grid: the piecewise-linear interpolant; constant: value).
  double operator()(double x, double y) const;
  bool is_constant() const { return kind == Kind::kConstant; }
};

// What the progress callback of a clipped diagram (Clip2Options::progress,
// Clip3Options::progress) receives. It is called on the thread that called compute() (never
// from another), at the start of each phase (done = 0) and, within a phase, between chunks
// of cells at most every 50 ms or so, when that thread finishes a chunk. Returning false
// cancels: compute() then throws Error("clip2d: cancelled" / "clip3d: cancelled") soon
// (the chunks under way finish, no other starts) and the diagram is left empty. The
// callback does not change the result of a run it does not cancel (the same bits as
// without it), and costs one test per chunk of cells when empty.
struct ClipProgress {
  // 2D: "cells". 3D: "delaunay" (compute(domain, sites, n) only; total = the sites),
  // "surface" (total = the boundary triangles), "boundary cells", "inner cells",
  // "geometry" (keep_geometry; total = the cells).
  const char* phase = "";
  std::uint64_t done = 0;  // items of this phase finished so far (in chunks)
  std::uint64_t total = 0;
  double seconds = 0;  // wall time since the clipping began (after the "delaunay" phase)
};

struct Clip2Options {
  Density2 density;
  // Progress and cancel (ClipProgress): return false to stop.
  std::function<bool(const ClipProgress&)> progress;
  // Keep each cell's rings (symbolic vertices and coordinates) for export and tests.
  bool keep_geometry = false;
};

// A vertex met while clipping, kept as what defines it (DESIGN.md, "Exactness").
struct ClipVertex2 {
  enum class Kind : std::uint8_t {
    kDomainVertex,  // a = the domain vertex
    kEdgeBisector,  // domain edge a (vertex a to its next) ∩ bisector(b, c), b < c sites
    kVoronoi,       // the Voronoi vertex of sites a < b < c (a Delaunay triangle)
  };
  Kind kind;
  std::uint32_t a, b, c;
  bool operator==(const ClipVertex2& o) const {
    return kind == o.kind && a == o.a && b == o.b && c == o.c;
  }
};

// The Voronoi diagram of the vertices of a Delaunay2 clipped to a Domain2.
//
// Cells are indexed by input point (the Delaunay2's points); a duplicate point, and a site
// whose cell misses the domain, has an empty cell (area 0). A cell's region is a set of
// rings, counter-clockwise around its pieces and clockwise around its holes, so it may
// have several pieces and holes. Per cell: area, mass = ∫rho, centroid = ∫rho x / mass,
// energy = ∫rho |x - x_i|^2 (the CVT energy term, eq. 1), and whether it meets the domain
// boundary. The gradient of the CVT energy is 2 mass (x_i - centroid) (eq. 2).
//
// Threads: TBB loops over cells into per-cell slots, reduced in index order: the result
// is identical for any thread count.
class ClippedVoronoi2 {
 public:
  ClippedVoronoi2();
  ~ClippedVoronoi2();
  ClippedVoronoi2(ClippedVoronoi2&&) noexcept;
  ClippedVoronoi2& operator=(ClippedVoronoi2&&) noexcept;
  // `dt` must be a triangulation of the sites (its point array stays alive while this
  // object is used for geometry queries).
  void compute(const Domain2& domain, const Delaunay2& dt, const Clip2Options& options = {});
  // The diagram of n >= 1 sites (packed x y), on this object's own copy of them and its own
  // triangulation (delaunay()). Sites that do not span the plane (one site, or all on one
  // line) have a well-defined clipped diagram too (the whole domain; strips): it is then
  // computed with 3 (a point) or 2 (a line) auxiliary sites far outside the domain (input
  // indices n, n + 1, ...: in delaunay() only; their cells miss the domain and are
  // dropped), decided exactly. Otherwise the result is compute(domain, Delaunay2(sites, n))
  // bit for bit.
  void compute(const Domain2& domain, const double* sites, std::uint32_t n,
               const Clip2Options& options = {});
  // After compute(domain, sites, n): the triangulation of the sites (and of the auxiliary
  // sites, if any), the number of auxiliary sites (0 when the sites span the plane) and the
  // seconds the copy and the triangulation took.
  const Delaunay2& delaunay() const { return dt_; }
  std::uint32_t nb_auxiliary_sites() const { return nb_auxiliary_; }
  double seconds_delaunay() const { return seconds_delaunay_; }

  std::uint32_t nb_sites() const { return static_cast<std::uint32_t>(cells_.size()); }
  double area(std::uint32_t i) const { return cells_[i].area; }
  double mass(std::uint32_t i) const { return cells_[i].mass; }
  // The mass centroid; the site itself for an empty cell.
  const double* centroid(std::uint32_t i) const { return cells_[i].centroid; }
  double energy(std::uint32_t i) const { return cells_[i].energy; }
  bool is_boundary(std::uint32_t i) const { return cells_[i].boundary != 0; }
  std::uint32_t nb_boundary_sites() const { return nb_boundary_; }

  // Sums over cells, in index order.
  double total_area() const { return total_area_; }
  double total_mass() const { return total_mass_; }
  double total_energy() const { return total_energy_; }

  // ---- Geometry (only with keep_geometry). Cell i has the rings
  // [cell_ring_begin(i), cell_ring_begin(i + 1)); ring r has the vertices
  // [ring_vertex_begin(r), ring_vertex_begin(r + 1)) of vertices() / vertex_coords().
  bool has_geometry() const { return !cell_ring_begin_.empty(); }
  std::uint32_t cell_ring_begin(std::uint32_t i) const { return cell_ring_begin_[i]; }
  std::uint32_t ring_vertex_begin(std::uint32_t r) const { return ring_vertex_begin_[r]; }
  const std::vector<ClipVertex2>& vertices() const { return vertices_; }
  const std::vector<double>& vertex_coords() const { return vertex_xy_; }

 private:
  friend struct Clip2Impl;
  // One record per cell: what a cell loop writes is one cache line.
  struct Cell {
    double area, mass, energy, centroid[2];
    std::uint32_t boundary;
  };
  std::vector<Cell> cells_;
  std::uint32_t nb_boundary_ = 0;
  double total_area_ = 0, total_mass_ = 0, total_energy_ = 0;
  std::vector<std::uint32_t> cell_ring_begin_, ring_vertex_begin_;
  std::vector<ClipVertex2> vertices_;
  std::vector<double> vertex_xy_;
  // compute(domain, sites, n): the sites (then the auxiliary ones) and their triangulation.
  std::vector<double> sites_;
  Delaunay2 dt_;
  std::uint32_t nb_auxiliary_ = 0;
  double seconds_delaunay_ = 0;
  // Per-site and per-triangle working arrays, kept between calls so that a CVT's
  // repeated computes allocate nothing.
  struct Workspace;
  std::unique_ptr<Workspace> ws_;
};

// ---------------------------------------------------------------------------------------
// Surface3: the boundary of a bounded volume as a closed, oriented, embedded triangle
// surface of one or more shells, validated exactly (clip/src/surface3.cpp). It is all that
// the 3D clipping, CVT and meshing need of a domain: inside / outside is an exact query on
// it (locate), so no tetrahedral mesh is needed.
//
// Built from a TriangleSurface (core.h: OBJ, OFF, STL, PLY files) or, by Domain3, from the
// boundary of a tet mesh. Vertices keep their input indices: a vertex with the coordinates
// of an earlier one is welded to it (triangles use the earliest index with those
// coordinates); unused and welded vertices stay in the array, unused by any triangle.
// Triangles keep their input order.
//
// A valid surface (each defect is reported as below):
//   - indices in range; finite coordinates (of the used vertices);
//   - no triangle with a repeated vertex (after welding) or of zero area (collinear
//     corners, exact); no two triangles with the same three vertices (duplicates);
//   - every edge in exactly two triangles, which run through it in opposite directions: a
//     closed, consistently oriented 2-manifold; the triangles around each vertex form one
//     fan (no pinched vertex);
//   - no two triangles meet other than at the edge or the vertex they share (exact
//     triangle-triangle tests; touching counts as meeting);
//   - each shell (connected component) oriented as its nesting says: a shell inside an
//     even number of other shells bounds the volume from outside and faces outward, one
//     inside an odd number (a cavity, or the inner wall of a hollow part) faces inward; so
//     every triangle's right-hand normal, (b - a) x (c - a) for (a, b, c), points out of
//     the volume. An inside-out shell is rejected by default (it usually means a wrong
//     export); with Surface3Options::reorient it is reversed instead (Shell::reoriented).
// The constructor throws Error "source: what", naming triangles as the file numbers its
// faces (TriangleSurface::triangle_face: "face 12 (line 40)"; from 0 without numbering),
// vertices as the file numbers them (vertex_base) and the defect, e.g. "bunny.obj: faces
// 230 (line 3535) and 2473 (line 5778) intersect". The first defect found in a fixed
// order (the checks above, each by its smallest element) is reported, for any thread
// count.
//
// Local numbering, as Domain3's boundary: edge e of triangle t is opposite its corner e,
// from corner e + 1 to corner e + 2 (mod 3), and adjacent(t, e) is the triangle across it
// (which runs through it the other way).
struct Surface3Options {
  // Reverse the shells whose orientation contradicts their nesting instead of rejecting
  // the surface.
  bool reorient = false;
};

class Surface3 {
 public:
  static constexpr std::uint32_t kNone = 0xffffffffu;

  // One connected component of the surface.
  struct Shell {
    std::uint32_t first_triangle = 0;  // its lowest triangle index
    std::uint32_t nb_triangles = 0, nb_vertices = 0, nb_edges = 0;
    std::uint32_t genus = 0;  // (2 - (V - E + F)) / 2
    // The innermost shell that encloses this one (kNone: none), and how many do.
    std::uint32_t parent = kNone;
    std::uint32_t depth = 0;
    double area = 0;
    // The volume it encloses, signed by its role: positive for an outer boundary, negative
    // for a cavity (odd depth). Sum of the signed tet volumes over its triangles from a
    // fixed point, compensated.
    double volume = 0;
    bool reoriented = false;  // reversed by Surface3Options::reorient
    bool cavity() const { return depth % 2 == 1; }
  };

  Surface3() = default;
  explicit Surface3(const TriangleSurface& surface, const Surface3Options& options = {});

  const std::string& source() const { return source_; }
  std::uint32_t nb_vertices() const { return static_cast<std::uint32_t>(xyz_.size() / 3); }
  const double* vertex(std::uint32_t v) const {
    assert(v < nb_vertices());
    return xyz_.data() + 3 * static_cast<std::size_t>(v);
  }
  const std::vector<double>& coords() const { return xyz_; }

  std::uint32_t nb_triangles() const { return static_cast<std::uint32_t>(triangles_.size() / 3); }
  // Corner k of triangle t; the corners, counter-clockwise seen from outside the volume.
  std::uint32_t triangle_vertex(std::uint32_t t, int k) const {
    assert(t < nb_triangles() && k >= 0 && k < 3);
    return triangles_[3 * static_cast<std::size_t>(t) + static_cast<std::size_t>(k)];
  }
  const std::uint32_t* triangle(std::uint32_t t) const {
    assert(t < nb_triangles());
    return triangles_.data() + 3 * static_cast<std::size_t>(t);
  }
  const std::vector<std::uint32_t>& triangles() const { return triangles_; }
  std::uint32_t adjacent(std::uint32_t t, int e) const {
    assert(t < nb_triangles() && e >= 0 && e < 3);
    return adjacent_[3 * static_cast<std::size_t>(t) + static_cast<std::size_t>(e)];
  }
  // Every triangle once, depth first over the surface (from the lowest-numbered triangle
  // of each shell, across edges in the order 0, 1, 2 pushed on a stack): consecutive
  // triangles are mostly adjacent.
  const std::vector<std::uint32_t>& order() const { return order_; }

  const std::vector<Shell>& shells() const { return shells_; }
  std::uint32_t shell_of(std::uint32_t t) const { return shell_of_[t]; }
  // Total area, and the enclosed volume (the shells' signed volumes summed: outer minus
  // cavities). Bounding box of the used vertices.
  double area() const { return area_; }
  double volume() const { return volume_; }
  const double* bbox_lo() const { return bbox_; }
  const double* bbox_hi() const { return bbox_ + 3; }
  // Vertices welded to an earlier one with the same coordinates.
  std::uint32_t nb_welded_vertices() const { return nb_welded_; }

  // Exact point location: POSITIVE strictly inside the volume, ZERO on the surface,
  // NEGATIVE outside. The parity of the crossings of an axis-parallel ray with the
  // triangles, the point perturbed symbolically off the ray's degenerate hits (edges,
  // vertices, triangles parallel to the ray), on a grid of the triangles' projections
  // (surface_locate.cpp). Throws Error for a non-finite coordinate. Thread-safe.
  Sign locate(const double* p) const;
  // The same for the circumcentre of p0..p3 (the point equidistant from the four), exact.
  // Throws Error for coplanar points.
  Sign locate_circumcenter(const double* p0, const double* p1, const double* p2,
                           const double* p3) const;

  // For messages: triangle t as the input names it ("face 12 (line 40)"; from a tet mesh,
  // "the boundary facet (vertices 2 5 7) of tetrahedron 3 (line 40)"), and vertex v.
  std::string triangle_name(std::uint32_t t) const;
  std::string vertex_name(std::uint32_t v) const;
  std::string tet_name(std::uint32_t t) const;  // kTetFacet

 private:
  friend class Domain3;
  // How messages name triangles: by index from 0, by the file's face numbers and lines, or
  // (a tet mesh's boundary) by their tet and its line.
  enum class Naming : std::uint8_t { kIndex, kFace, kTetFacet };
  // The checks and structures after the per-triangle checks (surface3.cpp): edges and
  // adjacency, fans, self-intersections, shells and their order, areas and volumes,
  // nesting and orientation, the locator.
  void build(const Surface3Options& options);
  // "source:line: face 12", the start of a message about triangle t.
  std::string at(std::uint32_t t) const;
  // kTetFacet: "the boundary facet (vertices 2 5 7) of tetrahedron 3", without the line.
  std::string tet_facet_name(std::uint32_t t) const;
  // Vertex v as the file numbers it ("7"): its label, or its index from vertex_base_.
  std::string vertex_number(std::uint32_t v) const;
  std::string source_;
  std::vector<double> xyz_;
  std::vector<std::uint32_t> triangles_;
  std::vector<std::uint32_t> adjacent_;
  std::vector<std::uint32_t> order_;
  std::vector<std::uint32_t> shell_of_;
  std::vector<Shell> shells_;
  Naming naming_ = Naming::kIndex;
  std::vector<std::uint32_t> triangle_face_;  // kFace: the face number; kTetFacet: the tet
  std::vector<std::uint32_t> triangle_line_;  // (0: not known)
  std::uint32_t vertex_base_ = 0;
  // kTetFacet: how the tet mesh's file names tets and vertices (TetMeshInput).
  std::string tet_noun_ = "tet";
  std::vector<std::uint64_t> tet_label_;
  std::vector<std::uint64_t> vertex_label_;
  double area_ = 0, volume_ = 0;
  double bbox_[6] = {0, 0, 0, 0, 0, 0};
  std::uint32_t nb_welded_ = 0;
  // The point-location structure (immutable once built; shared by copies).
  std::shared_ptr<const detail::SurfaceLocator> locator_;
};

// ---------------------------------------------------------------------------------------
// Domain3: a bounded volume for the 3D clipped diagrams, CVT and meshing: its boundary
// surface (Surface3), and optionally a tetrahedral mesh of it.
//
// From a surface: the volume it bounds; nothing else is needed (clip3d, CVT, mesh3d).
// From a tet mesh (clip/src/domain3.cpp): the tets, validated exactly, and their boundary
// as the surface (validated as a Surface3, the checks the tets have made skipped: the
// triangle-triangle and nesting tests remain). Only what needs tets reads them: the
// tet-by-tet clipping (Clip3Options::tet_clipping, the reference path), a density linear
// per tet (Clip3Options::vertex_density), and the region data of the mesh.
//
// Tet mesh validation: every tet is made positively oriented (orient3d of its vertices in
// order > 0, exact), swapping its local vertices 2 and 3 when it is negative. The
// constructor throws Error, naming the source, the element (tet index as in the
// TetMeshInput, i.e. the file's order from 0, and its line in the file), the vertices
// involved (indices into the TetMeshInput's vertices, from 0) and the defect, for
//   - a tet of zero volume (four coplanar vertices, exact) or with a repeated vertex;
//   - duplicate vertices (two vertices with equal coordinates, both used by tets);
//   - a facet shared by more than two tets, or two tets that overlap (a facet whose two
//     tets lie on the same side of it);
//   - a boundary (facets of exactly one tet) that is not a closed 2-manifold: a boundary
//     edge not shared by exactly two boundary triangles (tets meeting along an edge only),
//     or a vertex whose boundary triangles form more than one fan (tets meeting at a
//     vertex only); boundary triangles that intersect (Surface3);
//   - a non-finite coordinate (of a used vertex), a vertex index out of range.
// Vertices used by no tet are allowed and ignored (kept, so indices stay those of the
// input). Tets keep the input's order (source_tet(t) == t) and the result is the same for
// any thread count.
//
// Local numbering (the convention of Delaunay3::kFacetVertex): facet f of tet t is
// opposite vertex f and has the vertices kTetFacetVertex[f], listed so that
// orient3d(facet, q) < 0 for q on the tet's side and > 0 beyond it: "outward" in the sense
// of orient3d. With Shewchuk's sign convention (predicates.h) such a triangle is CLOCKWISE
// seen from outside. Input tets oriented the other way (TetGen's det(p1 - p0, p2 - p0,
// p3 - p0) > 0, i.e. orient3d < 0) are all swapped. Surface triangle b is the facet
// boundary_facet(b) of tet boundary_tet(b), reversed (counter-clockwise seen from outside,
// as Surface3 lists triangles); surface triangles are ordered by (tet, facet).
class Domain3 {
 public:
  static constexpr std::uint32_t kNone = 0xffffffffu;
  static constexpr int kTetFacetVertex[4][3] = {{1, 2, 3}, {0, 3, 2}, {3, 0, 1}, {2, 1, 0}};

  Domain3() = default;
  // The volume bounded by a closed surface.
  explicit Domain3(const TriangleSurface& surface, const Surface3Options& options = {});
  explicit Domain3(Surface3 surface);
  // The volume of a tet mesh.
  explicit Domain3(const TetMeshInput& mesh);

  const Surface3& surface() const { return surface_; }
  const std::string& source() const { return surface_.source(); }
  // Vertices: the surface's (for a tet mesh: every vertex of the mesh, same indices).
  std::uint32_t nb_vertices() const { return surface_.nb_vertices(); }
  const double* vertex(std::uint32_t v) const { return surface_.vertex(v); }
  const std::vector<double>& coords() const { return surface_.coords(); }
  // The enclosed volume (Surface3::volume) and the bounding box.
  double volume() const { return surface_.volume(); }
  const double* bbox_lo() const { return surface_.bbox_lo(); }
  const double* bbox_hi() const { return surface_.bbox_hi(); }
  // Exact point location (Surface3::locate).
  Sign locate(const double* p) const { return surface_.locate(p); }

  // ---- The tet mesh (empty for a domain given by its surface).
  bool has_tets() const { return !tets_.empty(); }
  std::uint32_t nb_tets() const { return static_cast<std::uint32_t>(tets_.size() / 4); }
  std::uint32_t tet_vertex(std::uint32_t t, int k) const {
    assert(t < nb_tets() && k >= 0 && k < 4);
    return tets_[4 * static_cast<std::size_t>(t) + static_cast<std::size_t>(k)];
  }
  // The tet across facet f of t, or kNone on the boundary.
  std::uint32_t tet_adjacent(std::uint32_t t, int f) const {
    assert(t < nb_tets() && f >= 0 && f < 4);
    return tet_adjacent_[4 * static_cast<std::size_t>(t) + static_cast<std::size_t>(f)];
  }
  // The surface triangle that is facet f of t (kNone for an interior facet); O(1): t's
  // surface triangles are consecutive.
  std::uint32_t tet_boundary(std::uint32_t t, int f) const;
  // The tet and facet of surface triangle b.
  std::uint32_t boundary_tet(std::uint32_t b) const { return boundary_tet_[b]; }
  int boundary_facet(std::uint32_t b) const { return boundary_facet_[b]; }
  // Where tet t came from in the input (its index there), for messages.
  std::uint32_t source_tet(std::uint32_t t) const { return source_tet_[t]; }
  // The sum of the tet volumes |det| / 6 (each in floating point), in tet order, compensated.
  double tet_volume() const { return tet_volume_; }

  // ---- Tags from a tet mesh file (TetMeshInput): per tet its region tag (empty: none
  // given); per surface triangle the tag of the file's triangle with the same three
  // vertices, 0 when the file lists none (empty when the file tags no surface triangle); the tag
  // names (Gmsh).
  const std::vector<std::int32_t>& tet_refs() const { return tet_ref_; }
  const std::vector<std::int32_t>& boundary_refs() const { return boundary_ref_; }
  const std::vector<TetMeshInput::TagName>& tag_names() const { return tag_names_; }
  // The tag the file gives the triangle with vertices a, b, c (any order) when it is not a
  // surface triangle (a face between two tets: an interface between regions), 0 when the
  // file tags no such triangle. O(log of the file's tagged triangles).
  std::int32_t inner_triangle_ref(std::uint32_t a, std::uint32_t b, std::uint32_t c) const;
  // The file's tetrahedra and triangles of second order or higher, read by their corners
  // (TetMeshInput::nb_higher_order_tets, nb_higher_order_triangles): the domain is the
  // straight tets on those corners, whatever the curved ones' other nodes say. 0 otherwise.
  std::uint64_t nb_higher_order_tets() const { return higher_order_[0]; }
  std::uint64_t nb_higher_order_triangles() const { return higher_order_[1]; }

 private:
  Surface3 surface_;
  std::vector<std::uint32_t> tets_;
  std::vector<std::uint32_t> tet_adjacent_;
  std::vector<std::uint32_t> boundary_tet_;
  std::vector<std::int8_t> boundary_facet_;
  std::vector<std::uint32_t> source_tet_;
  // Tet t's surface triangles are [tet_boundary_begin_[t], tet_boundary_begin_[t + 1]).
  std::vector<std::uint32_t> tet_boundary_begin_;
  double tet_volume_ = 0;
  std::vector<std::int32_t> tet_ref_, boundary_ref_;
  // The file's tagged triangles that are no surface triangle: sorted vertices, tag; sorted.
  std::vector<std::pair<std::array<std::uint32_t, 3>, std::int32_t>> inner_ref_;
  std::vector<TetMeshInput::TagName> tag_names_;
  std::uint64_t higher_order_[2] = {0, 0};  // tets, triangles
};

// Reads a 3D domain by extension (case-insensitive): a surface (.obj, .off, .stl, .ply:
// read_surface) or a tet mesh (.mesh, .node, .ele, .msh, .vtk, .vtu: read_tet_mesh), and
// validates it. Throws Error as the reader and the constructor do.
Domain3 read_domain3(const std::string& path, const Surface3Options& options = {});

// ---------------------------------------------------------------------------------------
// ClippedVoronoi3: the Voronoi diagram of the vertices of a Delaunay3 clipped to the
// volume of a Domain3 (Yan et al. 2011, sec. 4; clip/src/clip3d.cpp).
//
// Cells are indexed by input point; duplicates and cells that miss the volume are empty.
// Per cell: volume, mass = ∫rho, centroid, energy = ∫rho |x - x_i|^2, the area of its
// restricted surface cell (cell ∩ boundary surface) and whether that is non-empty (a
// boundary cell). Only the domain's surface is needed: the restricted surface is computed
// triangle by triangle; inner cells come from the Delaunay triangulation (cones over their
// Voronoi facets); boundary cells, by the divergence theorem, from their restricted
// surface polygons and the pieces of their Voronoi edges inside the volume (an edge that
// crosses the surface several times contributes its inside parts as signed segments from
// each crossing; clip3d.cpp). The tet-by-tet clipping of sec. 4.2 runs only for a tet mesh
// domain under tet_clipping (the reference) or a density linear per tet. Voronoi vertices
// are circumcenter3d's (predicates.h): within a few ulps even for Delaunay slivers whose
// floating-point determinant is zero (sites snapped to a flat face, to the last bits).
//
// Threads: TBB loops into per-cell (per-triangle) slots, reduced in index order: identical
// results for any thread count.

// Density for the 3D cell integrals (the 3D counterpart of Density2).
//   constant       rho = value everywhere (closed forms);
//   callback       rho(x, y, z) given by the user, integrated on the tetrahedra of each
//                  cell's cone decomposition (from the site over the faces of cell ∩
//                  volume, each face fanned) by `rule`:
//                    kDegree5    Walkington's 14 points per tet, positive weights: exact for
//                                rho a polynomial of degree <= 3 (the default);
//                    kQuadratic  rho replaced on each tet by its quadratic interpolant at
//                                the tet's vertices and edge midpoints, integrated exactly:
//                                exact for rho of degree <= 2. The cones share most of
//                                those points, so rho is called about 260 times per cell
//                                instead of about 1100; but the energy's error is O(h^3) in
//                                the cells' size h (O(h^6) for kDegree5), and so is the
//                                mismatch between the gradient 2 m (x - c) and the
//                                energy's derivative, and the interpolant can be negative
//                                where rho varies by a large factor within a cell.
//                  It must be finite and positive on every Voronoi cell that meets the
//                  volume (the cones reach the whole cell, not only its part in the
//                  volume), deterministic, and safe to call from several threads at once.
//                  With `batch` set (Density3::batch_function), the cell integrals call it
//                  with the points of a chunk of cells at once instead of `callback`
//                  point by point (the same values: it must give, for each point, the bits
//                  callback gives; an interpreted formula pays its per-call overhead once
//                  per batch);
//   vertex_linear  linear on each tet of the domain's tet mesh with these values at the
//                  mesh's vertices (one per vertex, >= 0): needs a tet mesh, and clips every
//                  cell tet by tet (sec. 4.2), integrated exactly per piece.
struct Density3 {
  enum class Kind { kConstant, kCallback, kVertexLinear };
  enum class Rule { kDegree5, kQuadratic };
  Kind kind = Kind::kConstant;
  Rule rule = Rule::kDegree5;  // kCallback's quadrature
  double value = 1.0;
  std::function<double(double, double, double)> callback;
  // rho at n points: out[k] = rho(xyz[3k], xyz[3k + 1], xyz[3k + 2]). Optional.
  std::function<void(const double* xyz, std::size_t n, double* out)> batch;
  std::vector<double> vertex_values;

  static Density3 constant(double rho);
  static Density3 function(std::function<double(double, double, double)> rho);
  // A callback density given at many points at once; callback evaluates one point.
  static Density3 batch_function(
      std::function<void(const double* xyz, std::size_t n, double* out)> rho);
  static Density3 vertex_linear(std::vector<double> values);
  // rho at (x, y, z) for a constant or callback density, as Density2's; vertex_linear
  // needs the tet that holds the point and throws Error here.
  double operator()(double x, double y, double z) const;
  bool is_constant() const { return kind == Kind::kConstant; }
};

// A vertex of a restricted surface polygon, kept as what defines it (DESIGN.md,
// "Exactness"): mesh vertex indices (Domain3) and sites, each list sorted, unused entries
// kNone. The decisions about it are exact predicates on those (predicates.h).
struct ClipVertex3 {
  static constexpr std::uint32_t kNone = 0xffffffffu;
  enum class Kind : std::uint8_t {
    kMeshVertex,      // mesh[0]
    kEdgeBisector,    // mesh edge (mesh[0], mesh[1]) ∩ bisector(site[0], site[1])
    kFacetBisectors,  // boundary triangle (mesh[0..2]) ∩ bisector(site[0], site[1]) ∩
                      // bisector(site[0], site[2]): the Voronoi edge of the three sites
  };
  Kind kind;
  std::uint32_t mesh[3];
  std::uint32_t site[3];
  bool operator==(const ClipVertex3& o) const {
    return kind == o.kind && mesh[0] == o.mesh[0] && mesh[1] == o.mesh[1] && mesh[2] == o.mesh[2] &&
           site[0] == o.site[0] && site[1] == o.site[1] && site[2] == o.site[2];
  }
};

struct Clip3Options {
  Density3 density;
  // Progress and cancel (ClipProgress): return false to stop.
  std::function<bool(const ClipProgress&)> progress;
  // Keep the restricted surface polygons (surface_polygons(): per cell, symbolic vertices
  // and coordinates). They are computed anyway: this only stores them.
  bool keep_surface = false;
  // Keep the restricted surface and the faces of every cell (cell_faces()), for export and
  // tests. The cell integrals do not change.
  bool keep_geometry = false;
  // Integrate every boundary cell by the tet-by-tet clipping (sec. 4.2), the reference the
  // default path is tested against: several times slower. Needs a domain with a tet mesh.
  bool tet_clipping = false;
  // For compute(domain, sites, n): the options of the Delaunay triangulation it builds.
  Delaunay3Options delaunay;
};

class ClippedVoronoi3 {
 public:
  // Throws voroclip::Error on bad input; the result is then empty (nb_sites() == 0).
  // A Delaunay3 needs 4 affinely independent sites (its constructor throws, saying so, for
  // one site or sites on a line or in a plane): the clipped diagram of such sites comes
  // from compute(domain, sites, n) below, which handles them exactly.
  void compute(const Domain3& domain, const Delaunay3& dt, const Clip3Options& options = {});
  // The same for n sites (x y z each), faster: the Delaunay triangulation is built here, of
  // a copy of the sites along a Hilbert curve (hilbert_sort of the input order,
  // which keeps duplicates in input order), presorted (Delaunay3Options::presorted: its
  // BRIO rounds need no sort of their own), so that the sites of neighbouring cells are
  // neighbours in memory; with the sites in input order each cell reads its neighbours
  // from all over the array (sphere-fine, 10^6 uniform sites: clipping 1.27-1.29 s ->
  // 1.07-1.10 s on two threads). Cells, polygons and symbolic vertices are reported with
  // input indices, polygons grouped by cell in input order as above. The symbolic
  // perturbation ranks sites in that spatial order, so where it decides (a degenerate
  // input) the result is that of compute(domain, dt) on the sorted sites triangulated
  // presorted, which differs from the input order's only in measure zero; the sums then
  // differ from those in the last bits. Duplicates: the first in input order gets the cell.
  void compute(const Domain3& domain, const double* sites, std::uint32_t n,
               const Clip3Options& options = {});
  // After compute(domain, sites, n): its triangulation, of the sites in spatial order (its
  // vertex k is input site site_order()[k]), and the seconds spent on the sort, the copy
  // and the triangulation.
  const Delaunay3& delaunay() const { return dt_; }
  // Sites with fewer than 4 affinely independent points among them (one site, sites on a
  // line or in a plane) have a well-defined clipped diagram too (the whole domain, slabs,
  // prisms): compute(domain, sites, n) then adds 2 or 4 auxiliary sites far outside the
  // domain (input indices n, n + 1, ...: in delaunay() and site_order() only; their cells
  // miss the domain and are dropped), and this is their number (0 otherwise).
  std::uint32_t nb_auxiliary_sites() const { return nb_auxiliary_; }
  const std::vector<std::uint32_t>& site_order() const { return site_order_; }
  double seconds_delaunay() const { return seconds_delaunay_; }

  std::uint32_t nb_sites() const { return static_cast<std::uint32_t>(cells_.size()); }
  double volume(std::uint32_t i) const { return cells_[i].volume; }
  double mass(std::uint32_t i) const { return cells_[i].mass; }
  const double* centroid(std::uint32_t i) const { return cells_[i].centroid; }
  double energy(std::uint32_t i) const { return cells_[i].energy; }
  double surface_area(std::uint32_t i) const { return cells_[i].surface_area; }
  bool is_boundary(std::uint32_t i) const { return cells_[i].boundary != 0; }
  std::uint32_t nb_boundary_sites() const { return nb_boundary_; }
  double total_volume() const { return total_volume_; }
  double total_mass() const { return total_mass_; }
  double total_energy() const { return total_energy_; }
  double total_surface_area() const { return total_surface_area_; }

  // Wall-clock seconds of the last compute(), per phase: the restricted surface (cells of
  // the boundary vertices, clipped triangles, crossings of Voronoi edges with the
  // surface); the boundary cells (their Voronoi vertices placed inside or outside, their
  // integrals, the tet-by-tet clipping where needed); the inner cells (circumcentres,
  // inside/outside of the other cells, their integrals, the per-cell results).
  double seconds_surface() const { return seconds_[0]; }
  double seconds_boundary_cells() const { return seconds_[1]; }
  double seconds_inner_cells() const { return seconds_[2]; }
  // (Cell, tet) pairs clipped tet by tet (tet_clipping, a density linear per tet);
  // boundary cells with a Voronoi edge that crosses the surface more than once.
  std::uint64_t nb_clipped_pairs() const { return nb_pairs_; }
  std::uint32_t nb_multi_crossing_cells() const { return nb_multi_crossing_; }

  // ---- Geometry. Polygons as flat coordinate lists: polygon p has the points
  // [polygon_begin[p], polygon_begin[p + 1]) of xyz (x y z each).
  struct Polygons {
    std::vector<std::uint32_t> site;   // per polygon: its cell
    std::vector<std::uint32_t> piece;  // cell_faces: per polygon, its convex piece
    // cell_faces: per polygon, the site across it (the face lies on their bisector), or
    // kSurface (on the domain's boundary) or kInterior (on a tet facet inside the volume:
    // between two pieces of the same cell, so not part of the cell's boundary).
    std::vector<std::uint32_t> across;
    std::vector<std::uint32_t> polygon_begin;  // nb polygons + 1
    std::vector<double> xyz;
    // surface_polygons only: per polygon its boundary triangle (Domain3), per point its
    // symbolic vertex; the polygons of site i are [site_begin[i], site_begin[i + 1]).
    std::vector<std::uint32_t> triangle;
    std::vector<ClipVertex3> vertices;
    std::vector<std::uint32_t> site_begin;
  };
  // The restricted surface (keep_surface or keep_geometry): per boundary cell, one polygon
  // per boundary triangle it meets, in triangle order, with the triangle's orientation
  // (Domain3: clockwise seen from outside); cells in index order.
  const Polygons& surface_polygons() const { return surface_; }
  // Faces of every cell with a non-empty part in the volume (keep_geometry), in pieces
  // numbered from 0, each piece's faces consecutive, all facing inwards (clockwise seen from
  // outside the cell, as Domain3::kTetFacetVertex for positive tets). A boundary cell is one
  // piece: its restricted surface polygons (across kSurface, one per triangle it meets),
  // then per neighbour j the loops that bound cell ∩ volume on bisector(i, j) (across j;
  // where the volume passes through the facet, the face has holes: its outer loops and
  // its hole loops, which turn the other way), boundary cells first; under tet_clipping
  // (a tet mesh) a boundary cell is instead its convex pieces in the tets it meets (their
  // faces on tet facets inside the volume marked kInterior). Then every inner cell as one
  // piece, its Voronoi facets (one per Delaunay neighbour: the circumcentres of the tets
  // around the Delaunay edge). Cells in Hilbert order of their sites. The faces other than
  // kInterior ones bound the cell. Degenerate (cospherical) sites give facets of zero area
  // and repeated points, as they are.
  const Polygons& cell_faces() const { return faces_; }
  static constexpr std::uint32_t kSurface = 0xffffffffu;
  static constexpr std::uint32_t kInterior = 0xfffffffeu;
  // The boundary of every cell (keep_geometry), as cell_faces() without its kInterior
  // faces and with the pieces of each face on a bisector joined: one polygon per
  // connected part of the face (their common edges dropped; their points stay, so a
  // joined polygon may have points inside its straight edges). The pieces join on points
  // of equal coordinates (a point met in several tets is computed from the same symbolic
  // vertex, to the same bits); a face whose pieces do not make simple loops around its
  // parts (a part with a hole; coinciding points of distinct vertices in degenerate input)
  // is left in pieces. Faces on the surface stay one per boundary triangle and tet. Per
  // cell in cell_faces() order, a face where its first piece was; site and across as in
  // cell_faces() (piece left empty).
  Polygons cell_boundaries() const;

 private:
  friend struct Clip3Impl;
  struct Cell {
    // Left uninitialized: compute() writes every field of every cell, in parallel loops
    // (which also first-touch the pages), not in a serial fill beforehand.
    Cell() {}  // NOLINT(modernize-use-equals-default): `= default` would zero in resize()
    double volume, mass, energy, centroid[3], surface_area;
    std::uint32_t boundary;
  };
  std::vector<Cell> cells_;
  std::uint32_t nb_boundary_ = 0, nb_multi_crossing_ = 0;
  double total_volume_ = 0, total_mass_ = 0, total_energy_ = 0, total_surface_area_ = 0;
  double seconds_[3] = {0, 0, 0};
  std::uint64_t nb_pairs_ = 0;
  Polygons surface_, faces_;
  // compute(domain, sites, n): the sorted copy, its order and its triangulation, and the
  // cells in that order (then scattered to their input slots in cells_).
  std::vector<Cell> ranked_cells_;
  // Not zeroed by resize(): the parallel copy writes (and first touches) it.
  std::vector<double, detail::UninitializedAllocator<double>> sorted_sites_;
  std::vector<std::uint32_t> site_order_;
  Delaunay3 dt_;
  double seconds_delaunay_ = 0;
  void compute_impl(const Domain3& domain, const Delaunay3& dt, const Clip3Options& options,
                    const std::uint32_t* input_index);
  // ranked_cells_, the polygons' sites and the grouping of surface_ to input indices.
  void to_input_indices();
  void sum_totals();
  void drop_auxiliary_sites(std::uint32_t n, std::uint32_t k);
  std::uint32_t nb_auxiliary_ = 0;
};

// ---------------------------------------------------------------------------------------
// Tables of cells (core.h, "Tables of the cells"; clip/src/cell_table.cpp): what clip2d and
// clip3d write with -o cells.csv and --neighbors.

// The pairs of cells that share a boundary piece of the clipped diagram (an edge in 2D, a
// face in 3D, on their bisector), each pair once (site_a < site_b, sorted), with the
// length (2D) or area (3D) of what they share, summed over its pieces and measured on
// site_a's side. Read from the cells' geometry: the diagram must have been computed with
// keep_geometry (throws Error otherwise). In 2D an edge of cell i lies on bisector(i, j)
// when both its end vertices are defined by i and j (ClipVertex2); in 3D a face is on
// bisector(i, j) when its `across` is j (cell_boundaries()), its area the norm of the sum
// of its loops' vector areas (hole loops turn the other way and subtract). Every pair is
// an edge of the Delaunay triangulation of the sites.
NeighborTable cell_neighbors(const ClippedVoronoi2& cv);
NeighborTable cell_neighbors(const ClippedVoronoi3& cv);

// The per-cell table of a diagram of the sites `sites` (x y [z] per site, input order, as
// given to compute), with the neighbour counts of `neighbors` when given.
CellTable cell_table(const ClippedVoronoi2& cv, const double* sites,
                     const NeighborTable* neighbors = nullptr);
CellTable cell_table(const ClippedVoronoi3& cv, const double* sites,
                     const NeighborTable* neighbors = nullptr);

}  // namespace voroclip
