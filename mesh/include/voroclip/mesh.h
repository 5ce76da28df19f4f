// voroclip/mesh.h — mesh generation and mesh quality (the module's one public header).
//
// Sections, each written and maintained on its own:
//   3D tet-mesh quality and surface distance: TetShape / tet_quality (per-tet measures
//      Q1..Q4 of Yan et al. 2011, sec. 6, their statistics and histograms as text, JSON
//      and SVG), hausdorff_distance (Metro-style sampled two-sided Hausdorff distance
//      between triangle surfaces). Sources: mesh/src/quality3*.cpp, mesh/src/hausdorff.cpp.
//   3D sizing field: SizingField3 (lfs from poles, a Lipschitz sizing grid, the CVT
//      density for adaptive meshing). Source: mesh/src/sizing3d.cpp.
#pragma once

#include <cstdint>
#include <iosfwd>
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
struct HausdorffOptions {
  double samples_per_triangle = 10;
  std::uint64_t min_samples = 100000;
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
  std::vector<double> lfs_;
  std::vector<double> h_;
  std::uint32_t n_[3] = {0, 0, 0};
  double lo_[3] = {0, 0, 0};
  double spacing_ = 1;
  double h_min_ = 0;
};

}  // namespace voroclip
