// voroclip/mesh.h — mesh generation and mesh quality (the module's one public header).
//
// Sections, each written and maintained on its own:
//   3D tet-mesh quality and surface distance: TetShape / tet_quality (per-tet measures
//      Q1..Q4 of Yan et al. 2011, sec. 6, their statistics and histograms as text, JSON
//      and SVG), hausdorff_distance (Metro-style sampled two-sided Hausdorff distance
//      between triangle surfaces). Sources: mesh/src/quality3*.cpp, mesh/src/hausdorff.cpp.
//   3D sizing field: SizingField3 (lfs from poles, a Lipschitz sizing grid, the CVT
//      density for adaptive meshing). Source: mesh/src/sizing3d.cpp.
//   2D CVT triangle meshing of polygons with holes (Yan et al. 2011, sec. 5.1) and its
//      quality report. Sources: mesh/src/mesh2d.cpp, sizing2d.cpp, extract2d.cpp,
//      quality2d.cpp.
//   3D CVT tet meshing: TetExtractor3 (exact extraction of the Delaunay tets whose
//      circumcenter lies in the domain, boundary filling, manifold repair),
//      perturb_slivers3 (sliver perturbation), mesh3d (the pipeline of sec. 5.2).
//      Sources: mesh/src/extract3d.cpp, mesh/src/slivers3d.cpp, mesh/src/mesh3d.cpp.
#pragma once

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/cvt.h"

namespace voroclip {

// =======================================================================================
// 3D tet-mesh quality and surface distance (quality3.cpp, quality3_report.cpp,
// hausdorff.cpp).
// =======================================================================================

// The shape of one tetrahedron (Yan et al. 2011, sec. 6, after Dardenne et al. [32]):
//   Q1 = the smallest of its six dihedral angles (degrees; 70.53 for the regular tet),
//   Q2 = the largest (degrees; 70.53 for the regular tet, up to 180 for slivers),
//   Q3 = 3 r_in / r_circ, the radius ratio (1 for the regular tet, 0 when flat),
//   Q4 = 12 (9 V^2)^(1/3) / sum of the six squared edge lengths (1 regular, 0 flat).
// Dihedral angle k is at edge kTetEdges[k], between the two faces that contain it.
// Computed in floating point from the edge vectors, scaled by a power of two so that no
// product overflows or underflows: invariant under translation and exactly under scaling
// by powers of two, up to rounding under rotations; dihedral angles via atan2 (accurate
// near 0 and 180 degrees). Q3 = 3 det^2 / (A |N|), Q4 = 12 (det^2 / 4)^(1/3) / sum l^2,
// with det = 6 V, A the total face area and N the circumcentre numerator
// |a|^2 (b x c) + |b|^2 (c x a) + |c|^2 (a x b) for edges a, b, c from vertex 0.
// A tet of zero volume, decided exactly (orient3d == 0, repeated vertices included), is
// `degenerate` and gets Q1 = 0, Q2 = 180, Q3 = Q4 = 0 and no dihedral angles (zeros).
// `positive`: det(p1 - p0, p2 - p0, p3 - p0) > 0 (TetGen's orientation, right-handed).
struct TetShape {
  static constexpr int kTetEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  double dihedral_deg[6] = {0, 0, 0, 0, 0, 0};
  double q1_deg = 0, q2_deg = 180, q3 = 0, q4 = 0;
  double volume = 0;  // signed: det(p1 - p0, p2 - p0, p3 - p0) / 6, rounded
  bool degenerate = true;
  bool positive = false;
};

TetShape tet_shape(const double* p0, const double* p1, const double* p2, const double* p3);

// The .vtu quality field of a tet mesh, for write_tet_mesh(path, mesh, format, fields):
// "q1_min_dihedral_deg", per tet its smallest dihedral angle (tet_shape's q1_deg), then NaN
// per triangle (mesh3d's .vtu, from the CLI and from Python).
std::vector<VtuCellField> tet_quality_fields(const TetMeshInput& mesh);

struct TetQualityOptions {
  std::uint32_t dihedral_bins = 180;  // histograms of dihedral angles over [0, 180] degrees
  std::uint32_t quality_bins = 100;   // histograms of Q3 and Q4 over [0, 1]
  bool keep_per_tet = false;          // fill TetQuality::per_tet
};

// min / mean / max of a measure, with the (lowest) tets where min and max are reached.
struct QualityStat {
  double min = 0, mean = 0, max = 0;
  std::uint32_t argmin = 0, argmax = 0;
};

// The quality of a tet mesh: orientation census, Q1..Q4 statistics and histograms.
//
// Orientation: every tet's sign is decided exactly; the majority orientation is the
// mesh's, and the tets of the other one are `inverted` (on a tie, those oriented unlike the
// first non-degenerate tet). Degenerate tets (zero volume, exact) are listed apart and
// count in q1..q4 with their values above (0, 180, 0, 0), so that they show in the minima
// and pull the means down; they add nothing to the dihedral histograms. Inverted tets are
// measured by their shape (the same as the reflected tet's).
// Histogram bin i of b bins over [lo, hi] holds the values in [lo + i w, lo + (i + 1) w),
// w = (hi - lo) / b, the last bin including hi.
// Parallel over fixed blocks of tets, reduced in block order: the result is the same,
// bit for bit, for any number of threads.
struct TetQuality {
  std::uint32_t nb_tets = 0, nb_vertices = 0, nb_used_vertices = 0;
  std::uint32_t nb_positive = 0, nb_negative = 0;  // by the sign of det, degenerate excluded
  std::vector<std::uint32_t> inverted;             // tet indices, increasing
  std::vector<std::uint32_t> degenerate;           // tet indices, increasing
  QualityStat q1_deg, q2_deg, q3, q4;
  QualityStat dihedral_deg;  // over the 6 angles of every non-degenerate tet (argmin: tet)
  std::vector<std::uint64_t> dihedral_histogram;      // all dihedral angles
  std::vector<std::uint64_t> min_dihedral_histogram;  // Q1, dihedral_bins over [0, 180]
  std::vector<std::uint64_t> q3_histogram, q4_histogram;
  // With keep_per_tet: the TetShape of every tet.
  std::vector<TetShape> per_tet;
};

// The quality of the tets (4 vertex indices each into xyz, packed x y z). Throws Error
// for a vertex index out of range or a non-finite coordinate of a used vertex; an empty
// mesh gives zeros.
TetQuality tet_quality(const double* xyz, std::uint32_t nb_vertices, const std::uint32_t* tets,
                       std::uint32_t nb_tets, const TetQualityOptions& options = {});
TetQuality tet_quality(const TetMeshInput& mesh, const TetQualityOptions& options = {});

// Metro-style sampled distance between triangle surfaces (Cignoni, Rocchini, Scopigno,
// "Metro: measuring error on simplified surfaces", 1998). Each surface is sampled at
//   - every vertex used by a triangle,
//   - points along every edge, m - 1 evenly spaced inside it, m = max(1, round(len / h)),
//   - the centroids of the n^2 similar sub-triangles of every triangle (each edge cut in
//     n, n = max(1, round(sqrt(area) / h))),
// with h = sqrt(area_total / target), target = max(min_samples, samples_per_triangle x
// the surface's triangle count); the exact (double-precision) distance from each sample to
// the other surface comes from a SurfaceTree. The sampled maximum is a lower bound of the
// true one-sided Hausdorff distance, within about the sampling step for smooth maxima.
// mean = the area-weighted mean over the sub-triangle samples (each weighs area / n^2):
// the mean distance over the surface (over the vertices when the area is zero).
// With `scale` set, each sample's distance is divided by scale(sample) before the maximum
// and the mean are taken (a distance relative to a local size, e.g. mesh3d's check of its
// boundary against the local edge length); scale must be positive and safe to call from
// several threads at once. scale_batch, when set, is used instead: out[k] = the scale at
// xyz[3k..3k+2] for the n samples of a block (up to 4096) at once (a Python or interpreted
// function pays its per-call cost once per block); the same values give the same result.
struct HausdorffOptions {
  double samples_per_triangle = 10;
  std::uint64_t min_samples = 100000;
  std::function<double(const double*)> scale;
  std::function<void(const double* xyz, std::size_t n, double* out)> scale_batch;
};

struct OneSidedDistance {
  double max = 0, mean = 0;
  double where[3] = {0, 0, 0};  // the sample where max is reached (first in sample order)
  std::uint64_t nb_samples = 0;
};

struct HausdorffDistance {
  OneSidedDistance forward;   // samples of `surface`, distances to `reference`
  OneSidedDistance backward;  // samples of `reference`, distances to `surface`
  double max = 0;             // the two-sided Hausdorff distance: max of the two maxima
  double mean = 0;            // the larger of the two means
  double diagonal = 0;        // of the bounding box of the reference's triangles
  double max_relative() const { return diagonal > 0 ? max / diagonal : 0; }
  double mean_relative() const { return diagonal > 0 ? mean / diagonal : 0; }
};

// One-sided: samples of `from`, distances to the surface of `to`. Parallel over triangles
// into per-item slots reduced in order: identical results for any thread count.
OneSidedDistance sampled_distance(const TriangleSurface& from, const SurfaceTree& to,
                                  const HausdorffOptions& options = {});

// Two-sided. Throws Error when either surface has no triangle.
HausdorffDistance hausdorff_distance(const TriangleSurface& surface,
                                     const TriangleSurface& reference,
                                     const HausdorffOptions& options = {});
// The same with the surfaces' trees already built (SurfaceTree(surface), SurfaceTree(reference)).
HausdorffDistance hausdorff_distance(const TriangleSurface& surface,
                                     const SurfaceTree& surface_tree,
                                     const TriangleSurface& reference,
                                     const SurfaceTree& reference_tree,
                                     const HausdorffOptions& options = {});

// Reports. `title` names the mesh (a file name). `distance` (optional) adds the Hausdorff
// figures, `reference` naming the reference surface.
//   text: a table of min / mean / max of Q1..Q4 and of all dihedral angles, the
//         orientation census (inverted and degenerate tets listed, the first 10), the
//         histograms of Q1 and of all dihedral angles in 10-degree rows and of Q3 and Q4 in
//         0.1 rows, then the distance;
//   JSON: one object with the keys tets, vertices, used_vertices, inverted_tets,
//         degenerate_tets (counts), inverted, degenerate (the first 1000 indices),
//         {min,mean,max}_min_dihedral_deg, {min,mean,max}_max_dihedral_deg,
//         {min,mean,max}_dihedral_deg, {min,mean,max}_q3, {min,mean,max}_q4,
//         histograms {dihedral_deg, min_dihedral_deg, q3, q4: {lo, hi, counts}} and with a
//         distance hausdorff, hausdorff_rel, hausdorff_mean, hausdorff_mean_rel,
//         bbox_diagonal, hausdorff_forward, hausdorff_backward, samples;
//   SVG:  four histogram panels (Q1, all dihedral angles, Q3, Q4) with min / mean / max.
void write_quality_text(std::ostream& out, const TetQuality& quality, const std::string& title,
                        const HausdorffDistance* distance = nullptr,
                        const std::string& reference = "");
void write_quality_json(std::ostream& out, const TetQuality& quality,
                        const HausdorffDistance* distance = nullptr);
void write_quality_svg(std::ostream& out, const TetQuality& quality, const std::string& title);

// =======================================================================================
// 3D sizing field (paper sec. 5.2, "Initialization", after Alliez, Cohen-Steiner, Yvinec
// & Desbrun, "Variational tetrahedral meshing", SIGGRAPH 2005, sec. 5).
//
// The local feature size (lfs) of each boundary vertex is its distance to the medial
// axis, approximated by the poles of the Voronoi diagram of the boundary vertices
// (Amenta & Bern 1999): the inner pole of vertex v is the farthest Voronoi vertex of v's
// cell on the inner side of the surface (the side opposite its outward normal), the outer
// pole the farthest on the outer side (none for a vertex of the convex hull, whose cell is
// unbounded outwards); lfs(v) is the distance from v to the nearer of its poles (the
// pole distance; on a dense sampling it approaches the distance to the medial axis).
// The sizing field is the largest g-Lipschitz function below lfs on the boundary,
//     h(x) = max(h_min, min over boundary vertices v of (lfs(v) + g |x - v|)),
// sampled at the nodes of a regular grid over the domain's bounding box (the minimising
// vertex of each node found by propagation over grid neighbours, as in vector distance
// transforms, and the value computed exactly for it) and interpolated trilinearly.
// h_min = max lfs / max_ratio keeps sharp edges (where lfs tends to 0) from asking for
// arbitrarily small elements. Only relative sizes matter for CVT meshing: the density is
// rho = h^-(d+2) = h^-5 (the CVT energy's scaling, Du, Faber & Gunzburger 1999), and the
// number of vertices sets the absolute scale.
struct Sizing3Options {
  double gradation = 0.5;         // g: h grows by at most g per unit length
  double max_ratio = 20;          // h_min = max lfs / max_ratio
  std::uint32_t resolution = 64;  // grid nodes along the longest side of the bounding box
};

class SizingField3 {
 public:
  // Throws Error for a domain without boundary triangles, or invalid options.
  SizingField3(const Domain3& domain, const Sizing3Options& options = {});
  // The same with the boundary vertices v with skip[v] != 0 left out of the minimum (their
  // lfs is still estimated and in vertex_lfs): e.g. the vertices of sharp edges, whose pole
  // distance goes to 0 with the input's sampling. All skipped: the bounding box's diagonal
  // everywhere.
  SizingField3(const Domain3& domain, const Sizing3Options& options,
               const std::vector<std::uint8_t>& skip);
  // The field of a domain made of parts (the regions of a tet mesh, each a Domain3 of some of
  // its tets on all of its vertices, numbered alike): the minimum over every part's boundary
  // vertices, each with its lfs in that part, so that each part's own thickness and features
  // size it, and an interface between two parts as the boundary does. skips[i], when given,
  // leaves out vertices of part i. vertex_lfs() holds a vertex's smallest estimate.
  // Throws Error for a part on other vertices.
  SizingField3(const Domain3& domain, const std::vector<const Domain3*>& parts,
               const Sizing3Options& options,
               const std::vector<std::vector<std::uint8_t>>& skips = {});

  // h at p (trilinear on the grid; points outside the grid clamp to it).
  double size(const double* p) const;
  // rho = h^-5 at every vertex of the domain (for Clip3Options::vertex_density and
  // random_points3).
  std::vector<double> vertex_density(const Domain3& domain) const;

  // Per domain vertex: its lfs estimate if it is a boundary vertex, else 0.
  const std::vector<double>& vertex_lfs() const { return lfs_; }
  double min_size() const { return h_min_; }
  // The grid: n[0] x n[1] x n[2] nodes from lo with spacing `spacing`, values x-fastest.
  const std::uint32_t* grid_size() const { return n_; }
  const double* grid_origin() const { return lo_; }
  double grid_spacing() const { return spacing_; }
  const std::vector<double>& grid_values() const { return h_; }

 private:
  void spread(const Domain3& domain, const std::vector<double>& xyz,
              const std::vector<double>& seed_lfs, const Sizing3Options& options);

  std::vector<double> lfs_;
  std::vector<double> h_;
  std::uint32_t n_[3] = {0, 0, 0};
  double lo_[3] = {0, 0, 0};
  double spacing_ = 1;
  double h_min_ = 0;
};

// =======================================================================================
// 2D: CVT triangle meshing of a Domain2 (mesh/src/mesh2d.cpp, sizing2d.cpp, extract2d.cpp)
// =======================================================================================
//
// Pipeline (paper sec. 5.1, steps 3-6; 1, 2 and 7 are this library's):
//   1. Sizing. A target edge length h(x) = min(H, min_j (s_j + g |x - x_j|)): a uniform
//      size H, capped near small boundary features (samples x_j of the boundary with the
//      size s_j they need, below) and growing away from them with slope g (`gradation`).
//      H is chosen so that the expected vertex count of an equilateral mesh of size h,
//      (2 / sqrt(3)) * integral of h^-2, is `nb_vertices` (or H = `edge_length`). The CVT
//      density is rho = (H / h)^4 (a CVT cell's diameter goes as rho^(-1/4) in 2D).
//   2. Sampling: independent sites with probability density proportional to h^-2,
//      strictly inside the domain (exact locate), from `seed`.
//   3. Unconstrained CVT (L-BFGS with a diagonal preconditioner, cvt.h).
//   4. Boundary: fixed vertices (below) become fixed sites; the sites of boundary cells
//      within 0.75 h of the boundary are snapped to their closest boundary point; each
//      boundary path keeps round(integral of ds / h) - 1 sliding sites (the snapped sites
//      closest to their neighbours are dropped, missing ones are added in the widest
//      gaps). Snapping empties the middle of parts only a few cells wide, so empty circles
//      are then filled: a free site at each Delaunay circumcenter inside the domain whose
//      radius exceeds 0.8 h (0.577 h in an equilateral mesh) and that lies 0.4 h or more
//      from the boundary, largest first.
//   5. Constrained CVT: fixed sites stay, sliding sites move along their path (tangential
//      gradient, eq. 3), the others are free.
//   6. Extraction (extract_conforming_mesh2, the default): the constrained Delaunay
//      triangulation of the sites with the boundary chains (each ring's boundary sites
//      in ring order) as segments, restricted to their inside: the union of the
//      triangles is the domain (every corner is a fixed site), each tip of a cut sharp
//      corner is added back as one triangle. With `conforming` false, the paper's rule
//      (extract_mesh2): the Delaunay triangles whose circumcenter lies inside the domain,
//      decided exactly, each then checked exactly to lie in the closed domain; this
//      leaves notches at the boundary (Mesh2Stats::covered_fraction < 1).
//   7. Repair: while some triangle has an angle below `repair_angle_deg` (at most
//      `repair_rounds` times), the non-fixed vertex at the largest angle of each such
//      triangle is removed (an end of a needle's short edge, a cap's apex) and a short
//      constrained CVT follows, then step 6 again. The result is the best mesh of the
//      rounds (largest smallest angle, then largest mean smallest angle): repair never
//      makes it worse.
//   8. Refinement (conforming only): Delaunay refinement (Ruppert) of the triangles
//      still below `repair_angle_deg`, in up to `refine_rounds` rounds: circumcenters,
//      or midpoints of the boundary edges they encroach (never a chord of a cut corner);
//      triangles at a domain corner sharper than that angle are left as they are.
//   9. Smoothing (conforming only): in up to `smooth_passes` passes, each free vertex with
//      a closed star moves towards the centroid of its neighbours (all the way, 1/2 or 1/4),
//      and each sliding vertex (`smooth_boundary`) along its domain edge towards the
//      centroid's projection, when its star's smallest angle grows (or stays, or both are
//      40 degrees or more, and the star's sum of smallest angles grows) and the star stays
//      valid; the mesh is extracted again after each pass. Raises the mean smallest angle
//      (issue52, 1000 vertices: 52.97 to 53.50 degrees without the sliding and the 40
//      degree rule; hilbert, 3000: 49.88 to 51.19 with them) and never lowers the
//      smallest below min(itself, 40 degrees).
//  10. Flips and search (conforming only): in up to `flip_rounds` rounds, edges between two
//      triangles are flipped where the sum of the two smallest angles grows (the
//      constrained Delaunay triangulation maximises their minimum, not their sum), the
//      minimum kept at or above min(itself, 40 degrees), then one smoothing pass as in
//      step 9 that also searches from the best trial point (compass search, 8 directions
//      or along the edge, halving steps), without extracting again: the connectivity is
//      kept, the mesh is no longer constrained Delaunay. Raises the mean smallest angle
//      where the grading or the boundary's spacing squeeze the triangles (earcut, 1000
//      vertices asked: 51.24 to 51.78 degrees; issue35: 50.83 to 51.44) and never lowers
//      the smallest below min(itself, 40 degrees).
//   Tags (tag_mesh2): boundary edges carry the .poly segment marker of their side, else
//   their ring's tag (Domain2::edge_tag: JSON, the ring's position in the file from 1;
//   .poly, 1 for outer rings, 2, 3, ... for holes); a vertex where the tag changes is
//   fixed. Triangles carry the .poly regional attribute of their part of the mesh, else
//   their polygon's number from 1 (JSON; one polygon: 1), else 1.
// The vertex count is approximate: the sampling gives `nb_vertices`, the boundary and
// gap steps change it. Where the feature sizes alone ask for more than nb_vertices
// (Mesh2Stats::feature_vertices, the equilateral count of the feature size field:
// eberly-6.json about 6,660, issue35.json about 4,470) the mesh has more than asked
// (eberly-6 at 1,000: 6,395; issue35 at 1,000: 3,696); elsewhere they change it (parts of the
// domain a few cells wide take more vertices than their area suggests: +28% on shared/data
// hilbert.json), the repair removes a few.
//
// What the circumcenter rule leaves out: obtuse triangles against the boundary (their
// circumcenter is beyond it) are not kept, which leaves notches — under 1% of the area on
// ordinary domains, a few percent where the domain is only a few cells wide
// (Mesh2Stats::covered_fraction); `keep_gaps` keeps them. Where the two sides of a thin
// spike of a hole are sampled more coarsely than the spike is wide, Delaunay triangles
// jump across it; they fail the containment check and are dropped (dropped_outside),
// leaving a small uncovered spot near the spike's tip.
//
// Boundary vertices. Domain vertices are classified by the turn of the boundary there
// (domain on the left): REFLEX vertices (a right turn, interior angle > 180 degrees) are
// always fixed mesh vertices — a mesh edge cutting one would leave the domain, so the mesh
// could not be valid otherwise; CONVEX vertices turning by at least `corner_angle_deg` are
// fixed CORNERS; with `fix_input_vertices` every vertex is fixed (paper Fig. 13); other
// convex vertices and collinear ones are passed by sliding sites (a mesh edge may cut a
// convex bend: the mesh stays inside). The fixed vertices split each ring into boundary
// paths (a ring without one is one closed path).
//
// Sharp corners. A corner whose interior angle is below `sharp_angle_deg` cannot be a mesh
// vertex without a triangle angle below that angle, and the wedge near it is narrower
// than the local size. Such a corner is cut off the domain before meshing: the tip is
// replaced by a chord between the points at arclength r = h / (2 sin(angle / 2)) from it
// on either side (where the wedge is h wide), or the nearest fixed vertex before that,
// or half-way to another sharp corner; a fixed vertex up to half the chord's length beyond
// r is taken as the cut when the tip's smallest angle stays the corner's and the boundary
// keeps 60 degrees or more there (a cut point just short of a fixed vertex left a short
// edge and triangles of 15-19 degrees beside the chord). The cut domain is validated exactly as a
// Domain2 (if a chord crosses another ring the cuts are halved, up to three times, else the corners
// stay as fixed corners), re-analysed (a cut may make a sharp corner at a fixed vertex; up to three
// rounds), and meshed: the chord's ends are fixed vertices, the tip (an area about r h / 2 each) is
// left uncovered, and the mesh lies in the cut domain, hence in the domain.
//
// Feature sizes s_j, on samples of every boundary path P (spacing half the local s_j):
//   s_j = min(length of P, distance from x_j to the nearest fixed vertex that does not end
//             P or to the nearest edge of a path that shares no end with P)
// (Ruppert's local feature size with the paths as features: a narrow part of the domain
// gets about one triangle across its width, and a short path between two fixed vertices
// gets triangles of its length).
//
// Coordinates. Fixed vertices at domain vertices have the domain's coordinates. Sliding
// sites and cut points are rounded, after the optimisation, to a double point in the
// closed domain: exactly on their edge when it holds already (for instance on horizontal
// and vertical edges), otherwise a few ulps from it on the domain side (a general segment
// holds no double point but its ends).
//
// Threads: the clipped diagrams, the sizing grid and the extraction checks run in TBB
// loops writing per-item slots: the result is identical for any thread count.

// A triangle mesh in the plane: counter-clockwise triangles (orient2d > 0, exact).
struct Mesh2 {
  enum class VertexKind : std::uint8_t {
    kInterior,  // a free site
    kBoundary,  // a sliding site, on `vertex_edge`
    kFixed,     // a fixed site: a domain vertex (`vertex_domain`) or a cut point of a
                // sharp corner (on `vertex_edge`)
  };
  static constexpr std::uint32_t kNone = 0xffffffffu;

  std::vector<double> xy;                    // packed x y
  std::vector<std::uint32_t> triangles;      // 3 vertex indices per triangle
  std::vector<VertexKind> vertex_kind;       // per vertex
  std::vector<std::uint32_t> vertex_domain;  // the domain vertex it sits at, or kNone
  std::vector<std::uint32_t> vertex_edge;    // boundary vertices not at a domain vertex: the
                                             // domain edge (vertex v to next(v)), or kNone
  std::vector<std::uint32_t> vertex_site;    // index of its site in the optimised site array
                                             // (kNone for the corner of a cut tip)
  // Tags (tag_mesh2): boundary edges, 2 vertices each with the domain on their left, and
  // each one's tag (Domain2::edge_tag: the .poly segment marker, else the ring's tag); per
  // triangle, its region: the .poly regional attribute of its part of the domain (a part:
  // triangles connected across edges), else its polygon's number from 1 (JSON), else 1.
  std::vector<std::uint32_t> boundary_edges;
  std::vector<std::int32_t> boundary_tags;
  std::vector<std::int32_t> triangle_regions;

  std::uint32_t nb_vertices() const { return static_cast<std::uint32_t>(xy.size() / 2); }
  std::uint32_t nb_triangles() const { return static_cast<std::uint32_t>(triangles.size() / 3); }
};

enum class Mesh2Phase : std::uint8_t {
  kSampling,       // sizing field and initial sites (iteration 0)
  kUnconstrained,  // CVT of free sites
  kConstrained,    // CVT with sliding and fixed boundary sites
  kExtraction,     // triangles (iteration: the repair round)
  kRepair,         // short constrained CVT after a repair's removals
  kRefinement,     // conforming: step 8 (iteration: the round, from 0)
  kSmoothing,      // conforming: step 9 (iteration: the pass, from 0)
  kFlips,          // conforming: step 10 (iteration: the round of flips and search, from 0)
};
const char* phase_name(Mesh2Phase phase);

struct Mesh2Progress {
  Mesh2Phase phase = Mesh2Phase::kSampling;
  std::uint32_t iteration = 0;  // within the phase
  double energy = 0;
  double gradient_norm = 0;
  double seconds = 0;  // since the start of mesh_domain2
  // Non-zero once, before a run with this many vertices asked, made because the last run's
  // mean smallest angle missed Mesh2Options::mean_angle_target_deg (the other fields: the
  // last run's mean in `energy`).
  std::uint32_t retry_vertices = 0;
  // Non-zero once per run given an edge length (nb_vertices == 0), after the sizing and
  // before the sampling: the vertex count the sizes imply, which the sampling aims for
  // (Mesh2Stats::implied_vertices; the other fields are zero).
  std::uint32_t implied_vertices = 0;
};

struct Mesh2Options {
  // Target number of mesh vertices. 0: use edge_length. A run whose count misses it by
  // more than `vertex_tolerance` (relative) is redone, at most twice (the sampling scaled
  // by the miss, then the secant through the two runs), and the closest kept
  // (Mesh2Stats::vertex_count_runs); a domain whose small features need more vertices gets
  // more, in one run (Mesh2Stats::vertex_count_note says by how much).
  std::uint32_t nb_vertices = 0;
  double vertex_tolerance = 0.1;
  // Target edge length H far from small features, used when nb_vertices == 0.
  double edge_length = 0;
  // Slope g of the sizing field away from small features (h grows by g per unit length).
  double gradation = 0.3;
  // Convex domain vertices where the boundary turns by at least this many degrees are
  // fixed corners.
  double corner_angle_deg = 0;
  // Convex corners with an interior angle below this many degrees are cut (see above).
  double sharp_angle_deg = 30;
  // Every domain vertex becomes a fixed mesh vertex (paper Fig. 13).
  bool fix_input_vertices = false;
  // Also keep the Delaunay triangles that lie in the domain but whose circumcenter does
  // not (obtuse triangles against the boundary, which the paper's rule leaves out as
  // notches): the mesh then covers the domain wherever the boundary is recovered, at the
  // price of some angles above 90 degrees.
  bool keep_gaps = false;
  // Conforming extraction (extract_conforming_mesh2, the default): the union of the
  // triangles is the domain, every corner a vertex (with corner_angle_deg = 0), the tips
  // of cut sharp corners one triangle each. false: the paper's circumcenter rule
  // (extract_mesh2, with keep_gaps).
  bool conforming = true;
  // Optional density rho for the CVT instead of the sizing field's uniform part: the size
  // is then h = min(c rho^(-1/4), feature sizes) with c set by nb_vertices / edge_length.
  // Must be positive on the domain. Constant (the default): uniform.
  Density2 density;
  std::uint64_t seed = 1;
  CvtMethod method = CvtMethod::kLbfgs;
  // Each CVT phase stops when |g| <= tolerance * |g_0| or after its iteration budget.
  std::uint32_t unconstrained_iterations = 100;
  std::uint32_t constrained_iterations = 200;
  double unconstrained_tolerance = 1e-3;
  double constrained_tolerance = 1e-4;
  // Repair (step 7): rounds, the angle below which a triangle is repaired, and the CVT
  // iterations after each round's removals. 0 rounds: the paper's pipeline alone.
  std::uint32_t repair_rounds = 4;
  double repair_angle_deg = 30;
  std::uint32_t repair_iterations = 40;
  // Refinement (step 8, conforming extraction only): rounds of Delaunay refinement of the
  // triangles still below repair_angle_deg. 0: none.
  std::uint32_t refine_rounds = 30;
  // Smoothing (step 9, conforming extraction only): passes moving free vertices where
  // their star's angles improve (never lowering the smallest angle). 0: none.
  std::uint32_t smooth_passes = 10;
  // The smoothing also slides the boundary vertices that are not at a domain vertex along
  // their domain edge (same rule, the target projected on the edge).
  bool smooth_boundary = true;
  // Flips (step 10, conforming extraction only): rounds of edge flips raising the sum of
  // the smallest angles of the two triangles of an edge, each followed by a smoothing
  // pass. 0: none (the mesh stays constrained Delaunay).
  std::uint32_t flip_rounds = 10;
  // Issue 31's quality target for the mean smallest angle (degrees; 0: none). When a mesh
  // of a vertex count (nb_vertices > 0, with raise_for_mean_angle) misses it, the domain
  // is meshed again with more vertices, at most max_mean_angle_runs times, and the first
  // mesh that reaches it (else the one with the highest mean) is kept: its count may then
  // be far above nb_vertices, which Mesh2Stats::mean_angle_raise says, with why. The next
  // count follows from the runs so far: corridors a few triangles wide (hilbert.json) get
  // the count that puts rows of vertices inside them (mean_angle_note's estimate, at most 8
  // times the count); other domains the count of the model mean = 60 - c N^-p through the
  // last runs (p = 3/4 with one run, measured on earcut, eberly-6 and issue35: 0.67-0.89;
  // fitted through two, within [1/2, 3/2]), aiming half a degree above the target, at least
  // 1.2 and at most 4 times the last count. With edge_length
  // (the size given, not the count) nothing is raised: mean_angle_note says what is missed.
  // A target outside [0, 60) degrees throws Error.
  double mean_angle_target_deg = 53;
  bool raise_for_mean_angle = true;
  std::uint32_t max_mean_angle_runs = 3;
  // Called at the start of each phase (iteration 0), after every CVT iteration, and once
  // with Mesh2Progress::implied_vertices (edge length only); return false to stop: the mesh
  // is then extracted from the sites reached (valid, lower quality; an empty mesh when
  // stopped before the sampling) and Mesh2Stats::cancelled is set.
  std::function<bool(const Mesh2Progress&)> progress;
};

struct Mesh2Stats {
  std::uint32_t nb_sites = 0;            // after the boundary step
  std::uint32_t nb_fixed = 0;            // fixed sites: domain vertices and cut points
  std::uint32_t nb_sliding = 0;          // sliding sites
  std::uint32_t nb_sharp_corners = 0;    // corners cut (sharp_angle_deg)
  std::uint32_t nb_tip_triangles = 0;    // their tips, one triangle each (conforming)
  std::uint32_t refine_added = 0;        // vertices added by the refinement (step 8)
  std::uint32_t smoothed = 0;            // vertex moves of the smoothing (steps 9 and 10)
  std::uint32_t flips = 0;               // edge flips of step 10
  std::uint32_t requested_vertices = 0;  // options.nb_vertices
  std::uint32_t vertex_count_runs = 0;   // runs redone to land near it (0 to 2)
  // Given an edge length (nb_vertices == 0): the vertex count its sizes imply (2 / sqrt(3)
  // times the integral of h^-2 over the domain), the sites sampled; the boundary step and
  // the refinement change the count made from it. 0 with nb_vertices.
  std::uint32_t implied_vertices = 0;
  // Expected vertex count of the small features' sizes alone (h = the feature size field,
  // no uniform part): above nb_vertices, the features force more vertices than asked.
  std::uint32_t feature_vertices = 0;
  // Empty when the count is within vertex_tolerance of nb_vertices (or none was asked);
  // else one line: the count made, by how much it misses, and why (the small features'
  // count above the request, or the steps that changed the count).
  std::string vertex_count_note;
  // Empty when the mean smallest angle reaches mean_angle_target_deg; else one line: the
  // mean, the triangles at the boundary and inside with their means, and why (corridors a
  // few triangles wide, with an estimate of the vertex count that reaches 53; an interior
  // graded to small features; the boundary's share).
  std::string mean_angle_note;
  // Non-empty when the mesh was made again with more vertices to reach
  // mean_angle_target_deg (Mesh2Options::raise_for_mean_angle): the first mesh's count and
  // mean, why it missed, the runs and the count kept. mean_angle_runs counts those runs.
  std::string mean_angle_raise;
  std::uint32_t mean_angle_runs = 0;
  std::uint32_t nb_gap_sites = 0;  // free sites added in gaps after the boundary step
  std::uint32_t nb_paths = 0;
  double edge_length = 0;  // H
  double min_size = 0;     // smallest h of the feature samples
  std::uint32_t unconstrained_iterations = 0, constrained_iterations = 0;
  double energy = 0;                   // final CVT energy
  double relative_gradient = 0;        // |g| / |g0| at the end of the constrained phase
  std::uint32_t repair_rounds = 0;     // repair rounds run
  std::uint32_t repair_removed = 0;    // vertices removed by them
  std::uint32_t nb_gaps = 0;           // triangles left out by the circumcenter rule alone
  double covered_fraction = 0;         // mesh area / domain area
  std::uint32_t dropped_outside = 0;   // kept by the circumcenter rule, but not contained
  std::uint32_t removed_vertices = 0;  // sites used by no triangle
  double seconds_sampling = 0, seconds_unconstrained = 0, seconds_constrained = 0,
         seconds_extraction = 0, seconds = 0;
  bool cancelled = false;
  // The mesh's own check: empty when it passed check_mesh2 and (conforming extraction,
  // corner_angle_deg == 0) check_mesh2_conforming, else the first defect found.
  std::string check;
};

// Meshes the domain. Throws Error for impossible options (no size given, a non-positive
// size, gradation, or angle out of range). Deterministic for given options.
Mesh2 mesh_domain2(const Domain2& domain, const Mesh2Options& options, Mesh2Stats* stats = nullptr);

// Step 6 alone: the mesh of given sites. `kinds` (optional, one per site) and
// `site_domain` / `site_edge` (optional) are copied to the mesh's vertex data.
struct Extract2Stats {
  std::uint32_t nb_delaunay = 0;  // finite Delaunay triangles
  std::uint32_t nb_circumcenter_outside = 0;
  std::uint32_t dropped_outside = 0;  // circumcenter inside but triangle not contained
  std::uint32_t removed_vertices = 0;
  // Conforming extraction: boundary chain segments, the flips that made them edges of the
  // triangulation, and the flips that made it constrained Delaunay again.
  std::uint32_t nb_boundary_segments = 0, nb_recovery_flips = 0, nb_delaunay_flips = 0;
  // Gaps: triangles in the closed domain whose circumcenter is outside (obtuse triangles
  // against the boundary, which the rule leaves out), as site indices, 3 per triangle.
  std::vector<std::uint32_t> gap_triangles;
};
Mesh2 extract_mesh2(const Domain2& domain, const std::vector<double>& sites,
                    const std::vector<Mesh2::VertexKind>& kinds = {},
                    const std::vector<std::uint32_t>& site_domain = {},
                    const std::vector<std::uint32_t>& site_edge = {},
                    Extract2Stats* stats = nullptr, bool keep_gaps = false);

// Step 6, conforming: the constrained Delaunay triangulation of the sites with the
// boundary chains as segments, restricted to their inside (see extract2d_conforming.cpp).
// A boundary site is one with site_domain (it sits at that domain vertex) or site_edge (on
// that edge, in the closed domain, at most a few ulps off the edge); the boundary sites of
// each ring, in ring order, make its chain. The union of the triangles is the polygon of
// the chains: the domain exactly when every corner of it is a site, else the domain less
// the convex bends the chains cut (a reflex vertex must be a site: a chain cutting one
// would leave the domain). All three per-site arrays are required. Throws Error when a
// ring has fewer than 3 boundary sites or chains cross.
Mesh2 extract_conforming_mesh2(const Domain2& domain, const std::vector<double>& sites,
                               const std::vector<Mesh2::VertexKind>& kinds,
                               const std::vector<std::uint32_t>& site_domain,
                               const std::vector<std::uint32_t>& site_edge,
                               Extract2Stats* stats = nullptr);

// Exact location of the circumcenter of the Delaunay triangle (i, k, l) of `dt` (the
// Voronoi vertex of the three sites, with the symbolic perturbation of the Voronoi
// clipping predicates, so never on the boundary): POSITIVE inside the domain, NEGATIVE
// outside. Crossing parity of the ray along bisector(i, k) beyond the vertex, each
// crossing decided by bisector_side_edge2d; O(domain edges).
Sign circumcenter_location2(const Domain2& domain, const Delaunay2& dt, std::uint32_t triangle);

// Exact checks of a mesh against its domain: every triangle counter-clockwise with
// non-zero area (orient2d), inside the closed domain (no domain edge meets its interior,
// and its interior is inside), edges shared by at most two triangles with opposite
// orientations, every vertex used. Empty when valid, else the first defect.
std::string check_mesh2(const Domain2& domain, const Mesh2& mesh);

// Fills the mesh's tags (Mesh2::boundary_edges, boundary_tags, triangle_regions; see
// mesh_domain2's "Tags") from its vertices' domain data (vertex_domain / vertex_edge;
// mesh_domain2 calls it). Throws Error
// for a regional attribute that is not an integer or a region point in no triangle.
void tag_mesh2(const Domain2& domain, Mesh2& mesh);

// File formats of a 2D triangle mesh (write_mesh2). Each holds the triangles with their
// regions (triangle_regions) and the boundary edges with their tags (boundary_tags).
enum class Mesh2FileFormat {
  // VTK XML .vtu (write_vtu), ASCII: triangles (type 5) then boundary edges (type 3,
  // lines); cell data "cell_id", "min_angle" (degrees, 0 on edges), "region" (a triangle's
  // region, 0 on edges) and "patch" (an edge's boundary tag, 0 on triangles), as the tet
  // meshes' (TetMeshFormat::kVtk); point data "kind" (0 interior, 1 sliding, 2 fixed); z = 0.
  kVtu,
  // Medit .mesh, Dimension 2, numbered from 1: Vertices (ref = kind as above), Edges (ref =
  // boundary tag), Triangles (ref = region).
  kMedit,
  // Gmsh .msh 2.2 ASCII: edges (type 1) in physical groups "boundary <tag>", triangles
  // (type 2) in groups "region <tag>", elementary = physical.
  kGmsh22,
  // Gmsh .msh 4.1 ASCII: as 2.2, one curve entity per boundary tag and one surface entity
  // per region, each in its physical group; all nodes in surface 1.
  kGmsh41,
  kVtuBinary,      // as kVtu, base64-encoded appended data (VtuEncoding::kBase64)
  kVtuCompressed,  // as kVtu, zlib-compressed appended data (VtuEncoding::kZlibBase64)
};

// Writes a tagged mesh (tags filled, e.g. by mesh_domain2 / tag_mesh2) in `format`: the
// files the CLI's mesh2d writes. Throws Error for arrays of mismatched sizes, an index out
// of range, or (Gmsh) a tag below 1 (Gmsh physical tags are positive).
void write_mesh2(std::ostream& out, const Mesh2& mesh, Mesh2FileFormat format);

// Exact checks that a valid mesh (check_mesh2) conforms to its domain: every boundary edge
// of the mesh (an edge of one triangle) lies along the domain's boundary — both ends
// within 16 ulps (per coordinate; the closed box meets the edge, decided by orient2d) of
// edges of one straight part of it (edges joined at vertices that are not corners); with
// `corners`, every corner of the domain (Domain2::is_corner) is a mesh vertex with its
// exact coordinates; and the triangles' areas sum to the domain's area to 1e-12 relative,
// plus 2 x 16 ulps (of the largest coordinate) times the boundary's length: the rounding of
// its vertices. Empty when all hold, else the first failure.
std::string check_mesh2_conforming(const Domain2& domain, const Mesh2& mesh, bool corners = true);

// ---------------------------------------------------------------------------------------
// Quality of a triangle mesh (angles in degrees, computed in floating point).
struct TriangleQuality2 {
  std::uint32_t nb_triangles = 0, nb_vertices = 0;
  double min_angle = 0, max_angle = 0;
  double mean_angle = 0;      // of all angles: 60 whenever there is a triangle
  double mean_min_angle = 0;  // mean over triangles of the smallest angle
  double mean_max_angle = 0;  // mean over triangles of the largest angle
  // Radius ratio 2 r_in / r_circ: 1 for an equilateral triangle, 0 for a flat one.
  double min_radius_ratio = 0, mean_radius_ratio = 0;
  std::uint32_t nb_below_30 = 0;  // triangles with an angle below 30 degrees
  double bin_degrees = 0;
  // Histograms over [0, 180) in bins of bin_degrees: all angles, and the smallest and
  // largest angle of each triangle.
  std::vector<std::uint32_t> angle_histogram, min_angle_histogram, max_angle_histogram;
};

TriangleQuality2 triangle_quality2(const Mesh2& mesh, double bin_degrees = 2.0);
// The smallest angle of each triangle, in degrees.
std::vector<double> triangle_min_angles(const Mesh2& mesh);
// Human-readable summary (several lines), and one JSON object with the keys
// nb_triangles, nb_vertices, min_angle_deg, mean_angle_deg, max_angle_deg,
// mean_min_angle_deg, mean_max_angle_deg, min_radius_ratio, mean_radius_ratio,
// triangles_below_30_deg, bin_deg, angle_histogram, min_angle_histogram,
// max_angle_histogram.
std::string quality_text(const TriangleQuality2& q);
std::string quality_json(const TriangleQuality2& q);
// An SVG bar chart of the angle histograms (all angles, and per-triangle min and max),
// with the summary figures; `title` is escaped.
void write_quality_svg(std::ostream& out, const TriangleQuality2& q, const std::string& title);

// =======================================================================================
// 3D CVT tet meshing: extraction of the mesh from the Delaunay triangulation of the sites
// (paper sec. 5.2, "Final mesh extraction"; mesh/src/extract3d.cpp).
//
// A Delaunay tet is kept when its circumcenter lies in the CLOSED domain: inside the volume
// or on its boundary surface (the tie rule: a circumcenter exactly on the boundary counts
// as inside). The decision is exact: Surface3::locate_circumcenter, the parity of the
// crossings of a ray from the circumcenter with the domain's surface, by exact predicates
// on the circumcenter's rational coordinates (no tet mesh is needed). No epsilon anywhere.
//
// The kept tets can have a non-manifold boundary (tets meeting along an edge or at a
// vertex only; it happens near concave parts of the boundary). With repair_manifold, each
// such edge or vertex is fixed by a local rule (extract3d.cpp): around it, either every
// kept component of its star but the one of largest volume is removed, or every non-kept
// component but the largest (the one holding infinite tets, if any) is added, whichever
// changes less volume; a tet changed once is not changed again. What that leaves after
// max_repair_passes, or after a pass that could change no tet, is fixed by removals only
// (every kept component but the largest; at a vertex whose kept tets form one component
// around holes, all of them), which always ends with a closed 2-manifold boundary.

// Where the points of a triangulation lie on the domain's boundary: per point p, the
// surface patches [begin[p], begin[p + 1]) of `patches` that hold it (none: not on the
// surface). A patch is a region of the boundary surface bounded by feature lines (a smooth
// surface is one patch); a point on a feature line is on the patches on both sides, a
// feature corner on all the patches around it.
struct SurfacePatches {
  std::vector<std::uint32_t> begin;  // nb points + 1
  std::vector<std::uint32_t> patches;
};

struct Extract3Options {
  // When given, the extraction fills the boundary (extract3d.cpp): a boundary facet of the
  // kept tets is a dent when one of its vertices is not on the surface, and crosses a
  // crease when its vertices share no patch. The finite tet across a dent is added; at a
  // crease, the tet across is added when its centroid is strictly inside the domain (the
  // chamfer of a convex feature edge), and the kept tet is removed when its own centroid
  // is strictly outside (a bridge over a concave edge). A tet changes at most once. In
  // passes, until nothing changes (at most max_fill_passes). Sites on a curved or polyhedral
  // surface make the circumcenters of the boundary layer's tets lie close to the surface, on either
  // side: without this, a well-shaped tet whose circumcenter is just outside leaves an interior
  // site on the boundary (a dent one layer deep), or cuts a sharp edge.
  const SurfacePatches* surface = nullptr;
  std::uint32_t max_fill_passes = 8;
  bool repair_manifold = true;
  // Passes of the first rule (each re-examines the boundary); it stops earlier when clean.
  std::uint32_t max_repair_passes = 16;
};

struct Extract3Stats {
  std::uint32_t nb_delaunay_tets = 0;          // finite tets of the triangulation
  std::uint32_t nb_inside = 0;                 // with the circumcenter in the closed domain
  std::uint32_t nb_on_boundary = 0;            // of those, exactly on the boundary (tie rule)
  std::uint32_t nb_filled = 0;                 // tets added across dents
  std::uint32_t nb_creases = 0;                // tets added across creases
  std::uint32_t nb_carved = 0;                 // tets removed at creases
  std::uint32_t nb_nonmanifold_edges = 0;      // found by the repair (over all passes)
  std::uint32_t nb_nonmanifold_vertices = 0;   // found by the repair (over all passes)
  std::uint32_t nb_added = 0, nb_removed = 0;  // tets changed by the repair
  std::uint32_t nb_repair_passes = 0;
  std::uint32_t nb_kept = 0;  // tets returned
  double seconds = 0;
};

// The exact location of circumcenters in a domain, and the extraction. Queries are const
// and thread-safe. The domain must outlive it.
class TetExtractor3 {
 public:
  explicit TetExtractor3(const Domain3& domain);

  // Where the circumcenter of p0..p3 (not coplanar) lies: POSITIVE strictly inside the
  // domain, ZERO on the boundary surface, NEGATIVE outside. Exact. Throws Error for
  // coplanar points.
  Sign circumcenter_side(const double* p0, const double* p1, const double* p2,
                         const double* p3) const;
  // Where point p lies, with the same convention (exact). Throws Error for a non-finite
  // coordinate.
  Sign point_side(const double* p) const;

  // The kept tets of dt (4 input point indices each), each listed so that
  // det(p1 - p0, p2 - p0, p3 - p0) > 0 (orient3d(p0, p1, p2, p3) < 0: the right-handed
  // orientation of TetGen, Medit and the shared data), in the order of dt's tet slots.
  // Parallel over the tets, one slot each: the same result for any thread count.
  std::vector<std::uint32_t> extract(const Delaunay3& dt, const Extract3Options& options = {},
                                     Extract3Stats* stats = nullptr) const;

 private:
  const Domain3* domain_;
};

// =======================================================================================
// 3D CVT tet meshing: sliver removal by vertex perturbation (Tournois, Srinivasan & Alliez,
// IMR 2009; mesh/src/slivers3d.cpp has the algorithm).

struct Perturb3Options {
  // Kept tets whose smallest dihedral angle is below this are slivers.
  double target_dihedral_deg = 30;
  std::uint32_t max_rounds = 20;
  // Stop when a round removed no sliver and raised the smallest angle by less than this.
  double min_progress_deg = 1;
  // Seed of the pseudo-random directions.
  std::uint64_t seed = 1;
  // The options of every extraction (the surface patches must outlive the call).
  Extract3Options extraction;
  // Called before each round with the round, the number of slivers and the smallest
  // dihedral angle; return false to stop.
  std::function<bool(std::uint32_t, std::uint32_t, double)> progress;
  // When set, called with the final sites and the mesh extracted from them. When it returns
  // false, the earlier rounds' sites (kept) and meshes are checked in order, and the first
  // round refused is undone (the sites go back, the mesh is extracted again;
  // Perturb3Stats::undone); the rounds go on from there with only free (interior) sites
  // moving, each checked, and a second refusal ends them. It must depend on its arguments
  // only. mesh3d uses it to keep the domain's shape.
  std::function<bool(const std::vector<double>& sites, const std::vector<std::uint32_t>& tets)>
      keep_round;
};

struct Perturb3Stats {
  std::uint32_t rounds = 0, moves = 0;
  std::uint32_t initial_slivers = 0, final_slivers = 0;
  double initial_min_dihedral_deg = 0, final_min_dihedral_deg = 0;
  double seconds = 0;
  bool cancelled = false;
  bool undone = false;  // a round was undone (Perturb3Options::keep_round)
};

// Moves the vertices of slivers of the mesh extracted from the sites' Delaunay
// triangulation (sites updated in place). kinds: per site (or empty: all free); fixed
// sites never move, surface and curve sites move within their constraint through
// `project` (as in Cvt3Options; here it may be called from several threads at once, so
// it must be thread-safe). `mesh` and `extraction`, when given, receive the tets that
// extract() (default options) gives for the final sites, and its statistics.
// Deterministic: the same result for any thread count.
Perturb3Stats perturb_slivers3(const TetExtractor3& extractor, std::vector<double>& sites,
                               const std::vector<SiteConstraint3::Kind>& kinds,
                               const SiteProjector3& project, const Perturb3Options& options = {},
                               std::vector<std::uint32_t>* mesh = nullptr,
                               Extract3Stats* extraction = nullptr);

// =======================================================================================
// 3D CVT tet meshing: the pipeline (Yan et al. 2011, sec. 5.2; mesh/src/mesh3d.cpp).
//
//   1. sizing: uniform, or adaptive from the local feature size (SizingField3: density
//      h^-5 on the domain's vertices);
//   2. initial sampling: about nb_vertices sites on a body-centred cubic lattice strictly
//      inside the domain (uniform sizing: the lattice is the best known CVT in space, so
//      only the boundary layer has far to go), or drawn with the density (random_points3),
//      also when no lattice spacing gives within 10 % of nb_vertices (a part thinner than
//      the lattice's layers);
//   3. unconstrained CVT (L-BFGS);
//   4. classification and snapping: the sites whose Voronoi cell meets the boundary
//      surface move to their closest point on it (lifted onto its smooth interpolant with
//      smooth_surface: PhongSurface); with features, the boundary edges whose
//      triangles' normals differ by more than feature_angle_deg form feature lines
//      (extract_feature_lines; cut where they turn sharply, the short ones dropped): the
//      sites nearest to points along them move onto them, each feature corner gets a
//      fixed site (the nearest site, or a new one), and a line's gaps of 1.5 spacings or more
//      get new sites where no constrained site is within half a spacing (a site whose cell
//      holds two lines, the two rims of a plate about a spacing thick, takes only one);
//   5. constrained CVT (L-BFGS): surface sites move on the surface, feature sites along
//      their line (eq. 3), corners are fixed;
//   5a. distance to the input (facet_distance > 0 only): sites fixed at the input vertices
//      farther from the boundary of the mesh the sites give than facet_distance times the
//      spacing (approximate_boundary, boundary_approx3d.cpp);
//   5b. topology: sites are added where the restricted Voronoi diagram of the sites on the
//      surface lacks the closed-ball property (closed_ball_defects, below: a restricted
//      cell that is not a disk, two cells sharing more than one arc, a Voronoi edge crossing
//      the surface twice), each at its bad cell's restricted point farthest from the site,
//      round after round until there is none (at most max_topology_rounds); then a short
//      constrained CVT spreads them and the check runs again (at most topology_cycles
//      times); the last state without defects is kept: the restricted Delaunay
//      triangulation that bounds the mesh is then homeomorphic to the surface. When
//      max_topology_stall rounds bring neither a state with fewer defects nor fewer defects
//      than the round before (next to a crease sharper than 90 degrees the insertions can
//      feed themselves), the state with the fewest is kept and the output's check (step 8)
//      decides. The sites
//      added raise the vertex count (or, with VertexCount::kExact, make mesh3d throw,
//      naming where and the count that would do);
//   6. extraction of the Delaunay tets whose circumcenter lies in the domain (TetExtractor3,
//      exact, manifold repair);
//   7. sliver perturbation (perturb_slivers3), surface and feature sites within their
//      constraint; the mesh is extracted again. When its shape is wrong, the first round
//      that broke it is undone (perturbation.undone) and the rounds go on moving interior
//      sites only;
//   7a. sliver insertion: a site at the circumcentre of each tet still below
//      sliver_insertion_deg (inside when it is at least half its circumradius deep, else on
//      the surface), then 6 and 7 again, kept only when the smallest angle rises and the
//      shape stays right (else tried once with every site on the surface);
//   7b. flat tets on the boundary (four boundary vertices, two boundary faces) are peeled;
//   regions: a tet mesh whose regions are volumes of their own
//      (Mesh3Result::nb_interfaces_followed) has its interfaces sampled with the boundary
//      from step 4 on (sites whose cells cross one go onto it; after 5b the gaps of the lines
//      get sites again; the sites of the lines where an interface meets the boundary or
//      another stay put in step 7; after 7a, a tet with vertices in two regions only gets a
//      site on such a line, or its surface vertex near one goes onto it, and 6 and 7 run
//      again), and here each tet takes the region its circumcentre lies in (exact; the
//      crease rule of the extraction at feature lines); 7c and 7d then work within each
//      region, the vertices two regions share fixed;
//   7c. flips (2-3, edge removal: 3-2, 4-4, ...), else moves of interior vertices, else
//      interior vertices inserted, against the tets below flip_dihedral_deg, worst first,
//      each raising the smallest angle of the tets it replaces (the mesh need not stay
//      Delaunay; the boundary is unchanged);
//   7d. for the mean smallest angle (mean_rounds): flips raising the mesh's mean Q1 and moves
//      of interior vertices (and of surface vertices on flat parts, within their patch)
//      raising the sum of Q1 over their tets, keeping the smallest angle (or 30 degrees) and
//      Q4 (or 0.4) of what they replace; the boundary triangles are unchanged;
//   8. output: the vertices used by the tets (sites used by none are dropped), their kinds,
//      the tets (right-handed), the quality (tet_quality) and the timing of each phase; the
//      output's boundary is checked against the domain's surface (check_mesh3_shape: a
//      closed 2-manifold, one shell per input shell with its genus; and the sampled
//      distance between the two boundaries at most the local target edge length, so that
//      no part thinner than the edges is cut off or bridged), and the verdict is in
//      Mesh3Result::shape_problem (empty when right). With VertexCount::kRaise a mesh of
//      the wrong shape makes the pipeline run again with twice the vertices (at most
//      max_shape_retries times).
// Deterministic for a given seed: the same mesh for any thread count.

enum class Mesh3Phase : std::uint8_t {
  kSizing,
  kSampling,
  kUnconstrained,
  kSnapping,
  kConstrained,
  kTopology,
  kExtraction,
  kSlivers,
  kQuality,
};
inline constexpr int kNbMesh3Phases = 9;

// "sizing", "sampling", "unconstrained", "snapping", "constrained", "topology",
// "extraction", "slivers", "quality".
const char* mesh3_phase_name(Mesh3Phase phase);

// What the progress callback receives: at the start of each phase (iteration 0), after
// every CVT iteration (energy, gradient norm; also those of the short CVTs of the topology
// phase), at each topology round (topology_round, defects and added_sites set) and before
// every perturbation round (iteration = round, slivers and min_dihedral_deg set).
struct Mesh3Progress {
  Mesh3Phase phase = Mesh3Phase::kSizing;
  std::uint32_t iteration = 0;
  double energy = 0;
  double gradient_norm = 0;
  std::uint32_t slivers = 0;
  double min_dihedral_deg = 0;
  // kTopology, once per round (topology_round set, iteration = round): the cells that break
  // the closed-ball property (closed_ball_defects), sites added so far.
  bool topology_round = false;
  std::uint32_t defects = 0, added_sites = 0;
  // Non-zero once, at the start of a new run with this many vertices: the last run's mesh
  // did not have the domain's shape (Mesh3Options::max_shape_retries).
  std::uint32_t retry_vertices = 0;
  // A domain of several bodies (outer shells) meshes them one by one: body (from 1) of
  // nb_bodies is being meshed (0 and 0 for a domain of one body); body_vertices is non-zero
  // once, at the start of each body: its share of the vertices.
  std::uint32_t body = 0, nb_bodies = 0, body_vertices = 0;
  // Non-zero once, before anything else, when Mesh3Options::edge_length gives the vertex
  // count: that count (a caller may refuse it, returning false, before the run allocates).
  std::uint32_t implied_vertices = 0;
  double seconds = 0;  // since the start of the pipeline (of the body's)
};

// A smooth surface over a triangle surface: Phong tessellation (Boubekeur and Alexa,
// "Phong tessellation", SIGGRAPH Asia 2008), patch by patch. Each corner of a triangle
// has the unit normal of its vertex within the triangle's patch (the angle-weighted mean of
// the normals of the patch's triangles around the vertex; patches are regions bounded by
// feature lines, so the surface is not smoothed across a crease). The point x of triangle
// t with barycentric coordinates u_k over its corners p_k is lifted to
//   x* = x + sum_k shape_k u_k ((p_k - x) . n_k) n_k   (shape_k = shape, 0 if p_k is pinned),
// the blend of the projections of x onto the corners' tangent planes (shape = 0: the flat
// triangle). shape = 1/2 reproduces a quadric to second order: for a curve y = k t^2 / 2
// sampled at two points with their exact normals, the lift of the chord's point at
// fraction s is the curve's point up to terms of higher order in the slope k L (the chord's gap k
// L^2 s (1 - s) / 2 closed exactly to leading order), and on a sphere the facets' midpoints and
// centroids land on it to leading order; Boubekeur and Alexa's 3/4 overshoots there by half the
// facets' sag (mesh3d's default, see Mesh3Options::smooth_shape). The lifted surface is continuous
// across the edges inside a patch, passes through every vertex of the input (x = p_k gives x* = p_k
// exactly: its own term is zero, the others have weight zero), and is flat where a patch is
// planar (every corner normal is the face's normal). On a sphere sampled by a triangle mesh
// it removes most of the gap between the facets and the sphere (the facets' sag).
// Planar regions keep their plane. A vertex is flat when its star is closed, in one patch
// and exactly coplanar (orient3d, exact); a planar region is a set of triangles reached from
// the stars of flat vertices across edges inside the patch to exactly coplanar neighbours.
// Every corner of a region's triangle, and every corner at a vertex where the patch meets
// exactly one region, has the region's normal: a planar face that blends tangentially into
// a curved one (CAD models) stays exactly in its plane, and the curved side leaves it
// tangentially, instead of both bulging by the averaged normals at the junction (a site
// lifted off an exactly planar face sees the whole face across the outside). Faces planar
// only up to the rounding of their coordinates are smoothed like curved ones.
class PhongSurface {
 public:
  // triangle_patch: one patch id per triangle of `surface` (empty: one patch); pinned: one
  // flag per vertex of `surface` (empty: none), a pinned vertex's term has shape 0, so
  // that the lift is the identity on an edge between pinned vertices (feature lines stay
  // where they are, and the patches on both sides meet there); shape in [0, 1]. Throws Error
  // for a triangle_patch or pinned of the wrong size or a shape outside [0, 1].
  PhongSurface(const TriangleSurface& surface, const std::vector<std::uint32_t>& triangle_patch,
               const std::vector<std::uint8_t>& pinned = {}, double shape = 0.5);

  // The lifted point of the point x of triangle t (x in t's plane, inside t or on its
  // boundary) to q, and to `normal` the unit interpolated normal there (the normalised
  // sum_k u_k n_k; t's own normal where that sum vanishes, zero for a degenerate t).
  void lift(std::uint32_t t, const double* x, double* q, double* normal) const;
  // The lifted point of the closest point of the flat surface (`tree`, built from the same
  // surface) to p. Thread-safe.
  void project(const SurfaceTree& tree, const double* p, double* q, double* normal) const;
  // The unit normal of corner k (0..2) of triangle t.
  const double* corner_normal(std::uint32_t t, int k) const {
    return &corner_normal_[9 * std::size_t{t} + 3 * static_cast<std::size_t>(k)];
  }
  double shape() const { return shape_; }

 private:
  std::vector<double> corners_;        // 9 per triangle: its corners' coordinates
  std::vector<double> corner_normal_;  // 9 per triangle
  std::vector<double> face_normal_;    // 3 per triangle, unit (zero if degenerate)
  std::vector<double> corner_shape_;   // 3 per triangle: shape, or 0 at a pinned vertex
  double shape_ = 0.5;
};

enum class Mesh3Sampling : std::uint8_t {
  kLattice,  // body-centred cubic lattice (uniform sizing only; adaptive sizing draws, and
             // so does a domain thinner than the lattice's layers)
  kRandom,   // random_points3 with the density
};

// Vertices per volume h^3 of a mesh3d mesh whose median edge length is h: N L^3 / V
// measured on the shared models (L the median edge length, interior and boundary edges):
// sphere.obj uniform 1.77 at 3000 vertices, 1.62 at 10^4; fandisk.obj uniform 1.97 at
// 5000; graded (h = 0.1 + 0.12 (x + 1) on the sphere, 0.15 + 0.1 |z| on fandisk, about
// 1000 and 3500 vertices) 2.0 and 1.9. With 1.9 the median of |e| / h is within 5 % of 1
// on all of them (tests/apps/test_cli_density.cpp checks the sphere's graded case).
inline constexpr double kMesh3VerticesPerEdgeVolume = 1.9;

struct Mesh3Options {
  // Number of sites (about the number of vertices of the result: plus one site per
  // feature corner without a site nearby, minus the sites no tet uses).
  std::uint32_t nb_vertices = 10000;
  // Density from the local feature size (SizingField3 with `sizing`) instead of uniform.
  // With interfaces followed (a tet mesh's regions), here and for lfs_cap the field is the
  // regions' (SizingField3 of parts): each region's boundary, its interfaces included, sizes
  // it, so that an inclusion or a layer thinner than the spacing is sized by its own shape.
  bool adaptive = false;
  // A cap on the uniform size (no adaptive, constant density): the sites' spacing is at most
  // lfs_cap times the local feature size field (SizingField3 with `sizing`, seeded by the
  // boundary vertices off the sharp feature lines, whose pole distance only measures the
  // input's sampling), so that thin parts, ears and close sheets get sites. The uniform
  // spacing H elsewhere is solved for so that about nb_vertices sites remain; when the cap
  // alone needs more, the field's shape is used, scaled to nb_vertices. 0 (the default): no
  // cap. Measured at 10^4 vertices (1 against 0): elk's smallest dihedral angle 7.7 -> 21.0
  // degrees, bunny's 16.9 -> 21.3, Hausdorff distances 20-40 % smaller; but rocker-arm's
  // 22.9 -> 8.1 (a graded spot around a small feature) and gargoyle's 27.3 -> 2.7 (the cap
  // alone needs more than 10^4 vertices there), and the CVT runs with a callback density
  // (2-5x slower) wherever the cap binds. Hence opt-in.
  double lfs_cap = 0;
  Sizing3Options sizing;
  // Or the user's density rho (a function; excludes adaptive): elements of size h about
  // rho^(-1/5) (rho = h^-5), scaled so that about nb_vertices sites fill the volume; the
  // sites are then drawn with density rho^(3/5), a CVT's (random_points3), not on the lattice.
  Density3 density;
  // > 0: the target edge length is absolute, h(x) = edge_length * rho(x)^(-1/5) in model
  // units (edge_length itself for a constant density), and nb_vertices is replaced by the
  // count that gives it: kMesh3VerticesPerEdgeVolume * integral of h^-3 over the volume
  // (not with adaptive). 0: h's shape only, scaled to nb_vertices.
  double edge_length = 0;
  // Sharp features: an edge is sharp when its triangles' normals differ by more than this
  // (extract_feature_lines). features = false: the surface alone.
  bool features = true;
  double feature_angle_deg = kDefaultFeatureAngleDeg;
  // Feature lines shorter than this times the local spacing of the sites are dropped (and
  // the corners that end only them): creases of a coarse smooth surface, or details below
  // the resolution, are meshed as smooth surface. Lines are also cut into two where they
  // turn by more than feature_angle_deg, the point becoming a corner.
  double min_feature_length = 1.5;
  // Initial sampling, and its seed (the lattice's offset, or the random draws).
  Mesh3Sampling sampling = Mesh3Sampling::kLattice;
  std::uint64_t seed = 1;
  // L-BFGS iterations of the two CVT phases, and their stopping tolerance on |g| / |g_0|.
  std::uint32_t unconstrained_iterations = 16;
  std::uint32_t constrained_iterations = 30;
  double gradient_tolerance = 1e-4;
  // Where the surface sites lie (Mesh3VertexKind::kSurface). smooth_surface = true: on the
  // Phong tessellation (PhongSurface, shape smooth_shape) of the domain's boundary, its patches
  // bounded by, and pinned along, every boundary edge sharper than feature_angle_deg (kept as a
  // feature line or not, and also when features = false), so that no crease is rounded. A site is
  // placed at the lift of its closest point on the boundary triangles, in the snapping, in the
  // constrained CVT (its direction there the interpolated normal) and in the sliver perturbation.
  // false: on the boundary triangles themselves (their closest point). Either way feature sites
  // stay on the feature lines (polylines of boundary edges) and corners on the domain's vertices.
  // "On the surface" then means on the smooth surface that the input's facets approximate:
  // where the boundary is curved, the vertices lie off the input's triangles (outside the
  // input domain where it is convex, by about 2 smooth_shape times the facets' sag), which
  // brings the output's boundary nearer that surface and the input's vertices (Hausdorff
  // distance); on planar patches both placements are the same point. smooth_shape 1/2
  // reproduces a quadric; the default 3/4 puts a convex part half a facet sag outside it,
  // which offsets the inward sag of the output's own, larger triangles: on sphere-fine with
  // 25k vertices (bench/RESULTS.md) the two-sided Hausdorff distance is 0.043-0.044 % of
  // the diagonal with 3/4, 0.046-0.050 % with 1/2, 0.053 % flat (seeds 1-3); 1 gives 0.041 %
  // but a worse smallest dihedral angle. Exactly planar faces stay planar (PhongSurface).
  // Off by default: on a coarsely tessellated curved boundary the lift moves the surface
  // sites noticeably outside the domain whose tets the extraction keeps, which leaves more
  // and worse slivers (bunny, 6.6k triangles, 30k vertices: smallest dihedral angle 0.17
  // degrees against 29 flat) and, at 100k vertices, a sliver phase 4x longer. Use it on
  // finely tessellated curved boundaries (sphere-fine: 20k triangles).
  bool smooth_surface = false;
  double smooth_shape = 0.75;
  // Distance to the input (step 5a): after the constrained CVT, the mesh the sites give is
  // extracted and each input boundary vertex farther from its boundary than facet_distance
  // times the local spacing (tips, ridges, thin parts that the spacing cuts off: the
  // two-sided Hausdorff distance's worst places) gets a site fixed on it, farthest first and
  // one per spacing per round: the nearest surface site moves there when within a spacing,
  // else a site is added. A short constrained CVT (facet_distance_iterations) follows each
  // round; at most facet_distance_rounds rounds, and facet_distance_budget times the sites
  // moved or added in all. 0: none. Opt-in: measured at 10^4 vertices, seed 1 (--stats json,
  // Hausdorff in % of the diagonal, min Q1 in degrees, 0 -> 0.15): bunny 1.38 -> 0.75 and min
  // Q1 16.9 -> 26.9, elk 1.10 -> 0.65 but 7.7 -> 1.3, fandisk 0.69 -> 0.68 and 16.7 -> 11.8,
  // gargoyle 1.31 -> 1.25 and 27.3 -> 22.8, homer 1.08 -> 0.61 but 20.7 -> 7.5, rocker-arm
  // 0.86 -> 0.58 and 22.9 -> 19.2, skull_low_resolution 1.49 -> 0.91 (0.0 -> 0.4), sphere
  // 0.155 unchanged (no site); mean Q1 within 0.3 degrees; up to 2.5x the time (CVT rounds):
  // a fixed site on a spiky input vertex makes slivers that the perturbation cannot move.
  double facet_distance = 0;
  std::uint32_t facet_distance_rounds = 4;
  std::uint32_t facet_distance_iterations = 4;
  double facet_distance_budget = 0.03;
  // Topology (step 5b): at most max_topology_rounds rounds of site insertion in all; after
  // the rounds that remove every defect, topology_iterations constrained CVT iterations
  // (0: none), at most topology_cycles times (1: the sites the rounds add after that CVT
  // stay where they are put; 3 cycles, before session 27, cost homer 5.0 of 13.4 s at
  // 10,000 vertices for the same quality: bench/RESULTS.md). When the sites of nb_vertices
  // cannot resolve the surface, kRaise adds the sites needed (Mesh3Result::nb_topology_sites
  // counts them), kExact throws Error naming where the surface is not resolved and about how
  // many vertices would do. Refinement stops after max_topology_stall rounds that neither
  // beat its fewest defective cells nor had fewer than the round before (next to a crease
  // sharper than 90 degrees it can feed itself); the state with the fewest defects is meshed
  // and check_mesh3_shape judges it.
  enum class VertexCount : std::uint8_t { kRaise, kExact };
  VertexCount vertex_count = VertexCount::kRaise;
  std::uint32_t max_topology_rounds = 60;
  std::uint32_t topology_iterations = 10;
  std::uint32_t topology_cycles = 1;
  std::uint32_t max_topology_stall = 8;
  // At most max_topology_sites times nb_vertices sites added by step 5b in one run: a part
  // far thinner than the spacing (a 1 x 1 x 0.001 plate at 1,000 vertices) needs millions,
  // and its defects grew round after round (876 to 27,799 cells, 27,048 sites added by round
  // 8; then again with twice the vertices, without end). At the cap the rounds stop
  // (Mesh3Result::topology_capped): kRaise meshes the state with the fewest defects, whose
  // shape check_mesh3_shape judges; kExact throws. The shared models add at most 2.1 times
  // the vertices (skull_low_resolution.obj at 500: 1,040 sites); a 3 x 3 x 0.1 plate at 150
  // vertices (test_mesh3d_tags) adds about 1,000.
  double max_topology_sites = 8;
  // kRaise: when the output's boundary does not have the domain's shape (check_mesh3_shape;
  // features thinner than the sites' spacing), the whole pipeline runs again with twice the
  // vertices, at most max_shape_retries times; the first run with the right shape is
  // returned (Mesh3Result::requested_vertices, shape_retries, raised_because).
  std::uint32_t max_shape_retries = 3;
  // The output's boundary and the domain's may be at most this many local target edge lengths
  // apart (Mesh3Result::distance_to_edge_length), else the shape is wrong (a part thinner than
  // the edges cut off, or a gap bridged): the bound is 1. 0: not checked.
  double max_boundary_distance = 1;
  // Sliver perturbation (perturb = false: none). Its `extraction` settings are the ones
  // every extraction of mesh3d uses (with or without perturbation); mesh3d only sets their
  // `surface` to the patches of its sites.
  bool perturb = true;
  Perturb3Options perturbation;
  // After the perturbation: tets whose four vertices lie on the boundary, with two or more
  // boundary faces and a smallest dihedral angle below this (degrees), are removed, worst
  // first, while the boundary keeps the domain's shape (check_mesh3_shape); 0: none.
  double peel_dihedral_deg = 20;
  // After the perturbation, while tets below sliver_insertion_deg are left: a site at their
  // circumcentres (inside when the centre is at least half the circumradius deep, else on the
  // surface), extraction and perturbation again; a pass that does not raise the smallest
  // dihedral angle or breaks the shape is undone, tried once more with every site on the
  // surface if it had sites inside, else it stops them. At most sliver_insertion_passes
  // passes (0: none).
  double sliver_insertion_deg = 20;
  std::uint32_t sliver_insertion_passes = 2;
  // Last (step 7c), against the tets whose min(Q1, 50 Q4) (smallest dihedral angle in
  // degrees; Q4 = 0.4 weighs as 20 degrees) is below flip_dihedral_deg, worst first: topological
  // flips (2-3 flips of interior faces, removal of interior edges with up to 8 tets around them:
  // 3-2, 4-4, ...), else a move of an interior vertex of the tet (or, with flip_moves_surface, of a
  // surface vertex within its surface patch), else a new interior vertex in the cavity of the tet
  // and its face neighbours; each kept only when it raises that measure's smallest over the tets it
  // replaces by more than flip_gain_deg and keeps their smallest Q4 (or 0.5). The mesh need not
  // stay Delaunay; its boundary keeps its triangles (surface vertices only slide on the surface).
  // At most max_flips_per_tet times the number of tets operations; 0 degrees: none.
  double flip_dihedral_deg = 30;
  double flip_gain_deg = 0.01;
  bool flip_moves_surface = true;  // surface vertices move too (within their patch)
  // Before and after, the same operations against the tets whose Q4 is below flip_q4 (0:
  // none), each raising the smallest Q4 of the tets it replaces and keeping their smallest
  // dihedral angle (or flip_dihedral_deg).
  double flip_q4 = 0.4;
  std::uint32_t max_flips_per_tet = 1;
  // Then (step 7d) mean_rounds rounds for the mean smallest dihedral angle over all tets: flips
  // of interior faces and edges (up to 4 tets around them) that raise the mesh's mean Q1, then
  // moves of the interior vertices (and, with flip_moves_surface, of the surface vertices within
  // their patch) that raise the sum of Q1 over the vertex's tets; each keeping the smallest Q1
  // of the tets it replaces (or 30 degrees) and their smallest Q4 (or 0.4). 0: none.
  std::uint32_t mean_rounds = 3;
  // Called as described at Mesh3Progress; return false to stop: the result then has
  // cancelled == true and no tets.
  std::function<bool(const Mesh3Progress&)> progress;
};

enum class Mesh3VertexKind : std::uint8_t {
  kInterior,  // free in the volume
  kSurface,   // on the boundary surface (or on an interface between regions it follows)
  kFeature,   // on a feature line
  kCorner,    // at a feature corner (fixed)
};

struct Mesh3Result {
  std::vector<double> xyz;             // vertices, x y z each
  std::vector<Mesh3VertexKind> kinds;  // per vertex
  // 4 vertex indices per tet, det(p1 - p0, p2 - p0, p3 - p0) > 0 (exactly).
  std::vector<std::uint32_t> tets;
  // The boundary: the faces of exactly one tet, outward (counter-clockwise seen from
  // outside), grouped by patch tag (increasing; in the order of (tet, facet) within a
  // patch), 3 vertex indices each; the patch tag of each
  // (the input's triangle tags when a tet mesh file gives them, whose borders the mesh
  // keeps as feature lines; otherwise the patches of the surface between the feature
  // lines, numbered from 1 in the order of their first input triangle, body after body
  // when the domain has several); the region tag of
  // each tet (the input's tet tags, by the input tet that holds the tet's centroid; otherwise
  // one region per volume component, numbered from 1 by its outer shell's order among the
  // surface's outer shells); the input's tag names (Gmsh files), then for each tag used
  // without one "patch <tag>" (dimension 2) or "region <tag>" (dimension 3), by increasing tag.
  std::vector<std::uint32_t> boundary_triangles;
  std::vector<std::int32_t> boundary_tags, tet_tags;
  // The interfaces the mesh follows (nb_interfaces_followed below): the faces between two
  // tets of different region tags, each once, oriented outward from its tet of the lower
  // region tag, 3 vertex indices each, grouped by tag; the tag of the file's interface
  // triangle nearest each (a tet mesh file that lists them with tags), else one tag per
  // interface, after the largest boundary tag and file triangle tag, in the order of the
  // input's interfaces (several bodies: body by body, after all their boundary tags); named
  // "interface <a>-<b>" (the region tags on its two sides) in tag_names when the file names
  // no such tag. Empty otherwise. The writers put them
  // with the boundary triangles (the .mesh Triangles, Gmsh physical surfaces, the .vtu
  // triangles' "patch").
  std::vector<std::uint32_t> interface_triangles;
  std::vector<std::int32_t> interface_tags;
  std::vector<TetMeshInput::TagName> tag_names;
  // The file's tagged triangles that the mesh does not follow: faces between two tets of the
  // same region (or of a file without tet tags), neither boundary nor an interface between
  // regions -- an embedded surface such as a sensor's. The mesh has no triangle of theirs,
  // and its tets cross them. Per such tag (increasing): the file's name of it (empty: none)
  // and the count of those triangles. Empty when the file has none.
  struct EmbeddedTag {
    std::int32_t tag = 0;
    std::string name;
    std::uint32_t nb_triangles = 0;
    bool operator==(const EmbeddedTag& o) const {
      return tag == o.tag && name == o.name && nb_triangles == o.nb_triangles;
    }
  };
  std::vector<EmbeddedTag> embedded_tags_dropped;
  std::uint32_t nb_sites = 0;          // sites optimised (corners added included)
  std::uint32_t nb_dropped_sites = 0;  // used by no tet, not in xyz
  std::uint32_t nb_boundary_sites = 0, nb_feature_sites = 0, nb_corner_sites = 0;
  std::uint32_t nb_feature_lines = 0, nb_feature_corners = 0;
  // Step 5a (Mesh3Options::facet_distance): sites fixed at input vertices (in
  // nb_corner_sites too), and of them those added rather than moved.
  std::uint32_t nb_distance_sites = 0, nb_distance_sites_added = 0;
  // The lfs cap (Mesh3Options::lfs_cap): the fraction of the volume where it binds (0: the
  // size is uniform) and the uniform spacing elsewhere (0 when not uniform anywhere).
  double lfs_capped_fraction = 0;
  double lfs_cap_spacing = 0;
  CvtResult unconstrained, constrained;
  Extract3Stats extraction;
  Perturb3Stats perturbation;
  std::uint32_t nb_peeled = 0;  // flat boundary tets removed (Mesh3Options::peel_dihedral_deg)
  TetQuality quality;
  // Q1 (the smallest dihedral angle, degrees) of the tets by how many of their vertices are
  // constrained (surface, feature or corner vertices: on the boundary, or on an interface
  // between regions the mesh follows): [0] all four, [1] three, [2] two or fewer. Slivers
  // of a CVT mesh sit there, where the sites cannot move freely.
  struct Q1Class {
    std::uint32_t nb_tets = 0;
    double min_deg = 0, mean_deg = 0;  // 0 without tets
  };
  Q1Class q1_by_boundary_vertices[3];
  // The dihedral-angle verdict. The input's sharpest dihedral angle alpha (degrees: the
  // smallest angle, inside the volume, between two boundary triangles of the domain that
  // share an edge), the bound min(20, alpha / 2) the mesh is held to (a tet in the wedge of
  // a feature edge of angle alpha has a dihedral angle below alpha there), and the tets
  // whose smallest dihedral angle is below the bound (0: the mesh meets it).
  double input_sharpest_dihedral_deg = 180;
  double dihedral_bound_deg = 20;
  std::uint32_t nb_tets_below_bound = 0;
  // Regions (tet_tags): the input's distinct tet tags (0 without them).
  // When each region is a volume of its own (its tets a valid tet mesh), the mesh follows
  // the interfaces between them as it follows the boundary: sites on them, each tet in one
  // region (mesh3d_interfaces.cpp); nb_interfaces_followed counts them (one per pair of
  // regions that meet), each region takes the tag most of its tets lie in, and
  // nb_tets_across_regions counts the tets whose centroid lies in an input tet of another
  // tag. Otherwise (interfaces_not_followed says why: a region whose tets meet along an edge
  // only, ...) the sites follow the boundary only, a tet takes the region of the input tet
  // holding its centroid, and nb_tets_across_regions counts the tets that reach across an
  // interface (a vertex inside the domain but in no input tet of the tet's own region). 0
  // when the input has one region or none.
  std::uint32_t nb_input_regions = 0, nb_tets_across_regions = 0;
  std::uint32_t nb_interfaces_followed = 0;
  std::string interfaces_not_followed;
  // Topology (step 5b): the sites added, the rounds run, and the defects left after them
  // (zero when the surface is resolved); nb_topology_deferred counts the bad cells whose
  // new site, too close to one added in the same round, was left for a later round.
  std::uint32_t nb_topology_sites = 0, topology_rounds = 0, topology_defects_left = 0;
  // Step 5b stopped at Mesh3Options::max_topology_sites with defects left, the first of them
  // near this point.
  bool topology_capped = false;
  std::array<double, 3> topology_capped_near{};
  // When capped: the domain's thickness where the defects were (the median diameter of the
  // largest inscribed balls touching the surface at the first round's defect points, by
  // shrinking balls), and about how many vertices a uniform spacing resolving it needs
  // (volume / (4 thickness^3): a 1 x 1 x 0.01 plate is resolved from 2,400 vertices on);
  // 0 when not capped. kRaise does not mesh again when even max_shape_retries doublings
  // stay 4 times short of that count (shape_retries_skipped).
  double topology_capped_thickness = 0;
  double topology_capped_vertices = 0;
  bool shape_retries_skipped = false;
  std::uint32_t nb_topology_deferred = 0;
  // Sites inserted at slivers' circumcentres (Mesh3Options::sliver_insertion_passes), and of
  // them those inside the volume (a circumcentre deep enough, step 7a).
  std::uint32_t nb_sliver_sites = 0, nb_sliver_sites_inside = 0;
  // Step 7c (Mesh3Options::flip_dihedral_deg): flips, moves of interior vertices (and of
  // surface vertices within their patch, flip_moves_surface), interior vertices inserted (in
  // nb_sites too).
  std::uint32_t nb_flips = 0, nb_flip_moves = 0, nb_flip_sites = 0;
  // Of nb_flips, the boundary 2-2 flips (a boundary edge replaced by the other diagonal of
  // its two nearly coplanar boundary triangles, in one patch); flips_rerun_for_shape when
  // they or the surface moves changed the boundary's shape and 7c was redone without the
  // boundary flips (and, when that was not enough, without the surface moves).
  std::uint32_t nb_boundary_flips = 0;
  bool flips_rerun_for_shape = false;
  // Step 7d (Mesh3Options::mean_rounds): the flips and vertex moves made, the rounds run, the
  // mean Q1 of the tets before and after it (degrees), its time (seconds, in the slivers phase).
  std::uint32_t nb_mean_flips = 0, nb_mean_moves = 0, mean_rounds = 0;
  double mean_q1_before_deg = 0, mean_q1_after_deg = 0, mean_seconds = 0;
  // The output's boundary (boundary_triangles) against the domain's boundary triangles:
  // hausdorff_distance with the default options, and the largest sampled distance between
  // them (either way) divided by the local target edge length at the sample,
  // cbrt(kMesh3VerticesPerEdgeVolume) times the sites' local spacing (the median edge
  // length's, mesh.h). Above Mesh3Options::max_boundary_distance the boundary cuts off (or
  // bridges) a part of the domain thinner than the edges, and shape_problem says where;
  // distance_seconds its time.
  HausdorffDistance distance;
  double distance_to_edge_length = 0;
  // The same between the interfaces the mesh follows and the input's (0 without them), held
  // to the same bound.
  double interface_distance_to_edge_length = 0;
  double distance_seconds = 0;
  // Empty when the output's boundary has the domain's shape (check_mesh3_shape, and the
  // distance above within max_boundary_distance), else what differs; a caller should not
  // use a mesh with a problem as a model of the domain.
  std::string shape_problem;
  // The vertices asked for (Mesh3Options::nb_vertices), the runs redone with twice as many
  // because the mesh did not have the domain's shape, and the first run's shape problem.
  // With several bodies (nb_bodies > 1, each meshed on its own): shape_retries is the most
  // any body needed (or the whole's retries, when two bodies' meshes met), raised_because
  // and shape_problem name the body; the other figures are the whole mesh's, counts summed,
  // mean_q1_before_deg weighted by each body's tets.
  std::uint32_t requested_vertices = 0, shape_retries = 0;
  std::string raised_because;
  std::uint32_t nb_bodies = 1;
  // Wall-clock seconds per phase (Mesh3Phase order) and in all.
  double seconds[kNbMesh3Phases] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  double total_seconds = 0;
  bool cancelled = false;

  std::uint32_t nb_vertices() const { return static_cast<std::uint32_t>(xyz.size() / 3); }
  std::uint32_t nb_tets() const { return static_cast<std::uint32_t>(tets.size() / 4); }
};

// Meshes the volume of `domain` (mesh.h, "the pipeline"). A domain of several bodies (outer
// shells, each with the cavities directly inside it) has each body meshed on its own, with
// its share of nb_vertices (by the integral of h^-3 over it: its volume for a uniform size;
// at least 4), and the meshes put together in the order of their outer shells: one CVT over
// all would let a cell, and the tets, reach across a gap narrower than the spacing between
// two bodies. Where the bodies' meshes meet (closer than their triangles' sag), kRaise meshes
// the whole again with twice the vertices (max_shape_retries). Throws Error for invalid options
// (fewer than 4 vertices, a feature angle outside [0, 180], a smooth_shape outside
// [0, 1]) or a domain without boundary.
Mesh3Result mesh3d(const Domain3& domain, const Mesh3Options& options = {});

// The boundary surface of a Domain3 as a TriangleSurface (its vertices, all of them, and
// its boundary triangles oriented outward by the right-hand rule).
TriangleSurface boundary_surface(const Domain3& domain);

// =======================================================================================
// 3D CVT tet meshing: the topology of the boundary (mesh/src/topology3d.cpp).

// The cells of a restricted Voronoi diagram on the domain's surface (a ClippedVoronoi3
// computed with keep_surface, of the sites `sites`) that break the closed-ball property
// (Edelsbrunner & Shah 1997): a restricted cell that is not a closed disk, a pair of cells
// whose shared boundary is not a single arc, a Voronoi edge that crosses the surface more
// than once. Decided on the polygons' symbolic vertices (no floating-point decision). For
// each such cell, the vertex of its restricted region farthest from its site (where the
// standard refinement inserts a site).
struct ClosedBallDefects {
  std::uint32_t nb_not_disk = 0, nb_facets = 0, nb_edges = 0;
  std::vector<std::uint32_t> cells;  // increasing
  std::vector<double> points;        // x y z per cell
};
//
// `knife_edges` (sorted keys min(a, b) << 32 | max(a, b) of surface vertex pairs, maybe
// empty): edges of the surface where its triangles' normals differ by more than 90
// degrees. The surface has no positive reach there, so no sampling gives the cells that
// touch such an edge the property (a site near it owns a strip across it, which the next
// site splits): those cells are not counted; the output's shape check judges them. But
// they count when their region has a closed piece (a whole shell of the surface inside
// one cell) and, with `surface` (the domain's, whose triangles the polygons name), when
// they are the cells of a shell that fewer than four cells meet: a part much smaller than
// the spacing (a small body beside a large one) has no triangle of the restricted
// Delaunay surface otherwise, whatever its edges.
ClosedBallDefects closed_ball_defects(const ClippedVoronoi3& cv, const double* sites,
                                      const std::vector<std::uint64_t>& knife_edges = {},
                                      const Surface3* surface = nullptr);

// Whether a tet mesh (xyz, 4 indices per tet) has the shape of the domain: its tets valid
// as a Domain3 (positive volume, no overlap, a closed 2-manifold boundary: no tets meeting
// along an edge or at a vertex only), one boundary shell per shell of the domain's surface,
// with the same genus and nesting (depth), matched in order of (depth, genus, volume).
// Empty when it has, else one line saying what differs.
std::string check_mesh3_shape(const Domain3& domain, const std::vector<double>& xyz,
                              const std::vector<std::uint32_t>& tets);

}  // namespace voroclip
