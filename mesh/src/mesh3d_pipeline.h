// The state of one mesh3d() run and the files of its steps (mesh.h lists the steps):
//   mesh3d.cpp               the pipeline: sizing, sampling, the CVTs, extraction, output;
//   features3d.cpp           feature lines, surface patches and the constraints of the sites
//                            (step 4: corners, feature and surface sites);
//   boundary_approx3d.cpp    step 5a: sites fixed where the boundary is too far from the
//                            input (facet_distance);
//   topology_repair3d.cpp    step 5b: sites added until the restricted Voronoi diagram has
//                            the closed-ball property (topology3d.cpp checks it);
//   phong3d.cpp              the smooth surface the surface sites are projected onto;
//   slivers3d.cpp            step 7: sliver perturbation;
//   flips3d.cpp              step 7c: flips against the worst tets;
//   mesh3d_tags.cpp          boundary triangles, patch and region tags;
//   mesh3d_interfaces.cpp    interfaces between the input's regions, followed by the mesh.
// Internal to the mesh module.
#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "voroclip/mesh.h"

namespace voroclip::mesh3 {

using Kind = SiteConstraint3::Kind;

// Thrown by Pipeline::report when the caller's progress callback asks to stop.
struct Cancelled {};

// The local spacing of the sites at a point (model units).
using Spacing = std::function<double(const double*)>;

// Small 3-vector helpers of the sliver and flip passes.
inline void sub3(const double* a, const double* b, double* o) {
  for (int c = 0; c < 3; ++c) o[c] = a[c] - b[c];
}
inline void cross3(const double* a, const double* b, double* o) {
  o[0] = a[1] * b[2] - a[2] * b[1];
  o[1] = a[2] * b[0] - a[0] * b[2];
  o[2] = a[0] * b[1] - a[1] * b[0];
}
inline double dot3(const double* a, const double* b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// acos(c) in radians for the largest cosine c of a tet's dihedral angles, which is at least
// 1/3 (no tet's smallest dihedral angle exceeds the regular tet's, acos(1/3)): the sliver and
// flip passes take it for every candidate position of every vertex, and glibc's acos was a
// fifth of the mean pass (perf, sphere at 30,000 vertices). acos(c) = 2 asin(s) with
// s^2 = z = (1 - c) / 2 (exact for c >= 1/2), asin(s) = s g(z), g(z) = asin(sqrt z) / sqrt z
// interpolated at 17 Chebyshev points of [0, 0.35] (mpmath, 50 digits; the coefficients of
// z^0 .. z^16 below): within 1.2e-16 of g there, so within 6e-16 of acos on [0.3, 1] as
// evaluated here. Below 0.3 (only a flat tet's rounding): std::acos.
inline double acos_of_largest_cosine(double c) {
  if (!(c >= 0.3)) return std::acos(std::max(-1.0, c));
  if (c >= 1) return 0;
  static constexpr double kG[17] = {1.0,
                                    0.16666666666666635,
                                    0.07500000000008622,
                                    0.04464285713354498,
                                    0.030381944972479244,
                                    0.022372140977016595,
                                    0.017353172820128496,
                                    0.013958467994604856,
                                    0.011623074408030768,
                                    0.009179163533166196,
                                    0.011906641365759774,
                                    -0.008388421748245566,
                                    0.05782707832303479,
                                    -0.1146818077116129,
                                    0.19827676389625487,
                                    -0.18848182317705392,
                                    0.09949195002688865};
  // Estrin's scheme (a tree of products: a fifth of Horner's chain of dependent operations).
  const double z = (1 - c) / 2, z2 = z * z, z4 = z2 * z2, z8 = z4 * z4;
  double b[8];
  for (int j = 0; j < 8; ++j) b[j] = kG[2 * j] + kG[2 * j + 1] * z;
  const double c0 = b[0] + b[1] * z2, c1 = b[2] + b[3] * z2, c2 = b[4] + b[5] * z2,
               c3 = b[6] + b[7] * z2;
  const double g = (c0 + c1 * z4) + (c2 + c3 * z4) * z8 + kG[16] * (z8 * z8);
  return 2 * std::sqrt(z) * g;
}

// The smallest dihedral angle of a tet (degrees) from its four face normals n (all outward or
// all inward) and their lengths: the angle whose cosine is the largest -n_f . n_g / |n_f| |n_g|;
// 0 for a flat tet (a normal of length 0).
inline double smallest_dihedral_deg(const double (&n)[4][3], const double (&len)[4]) {
  double worst = -1;  // the largest cosine of a dihedral angle
  for (int f = 0; f < 4; ++f) {
    for (int g = f + 1; g < 4; ++g) {
      const double l = len[f] * len[g];
      if (!(l > 0)) return 0;
      worst = std::max(worst, -dot3(n[f], n[g]) / l);
    }
  }
  return acos_of_largest_cosine(worst) * 180 / 3.14159265358979323846;
}

inline std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
  return a < b ? std::uint64_t{a} << 32 | b : std::uint64_t{b} << 32 | a;
}

// Projection onto the boundary surface (closest point, pseudo-normal) or onto a site's
// feature line (closest point, tangent). Const queries: thread-safe.
struct Projection {
  const SurfaceTree* surface = nullptr;
  const FeatureTree* lines = nullptr;
  const std::vector<std::uint32_t>* line_of = nullptr;  // per site (kCurve)
  const PhongSurface* smooth = nullptr;                 // kSurface sites: lifted onto it when set

  void operator()(std::uint32_t site, Kind kind, const double* p, double* q, double* d) const;
};

// Feature lines (features3d.cpp).

// The sorted edge keys of the borders between the input's tagged boundary patches (a tet
// mesh file's boundary triangle refs: `tags`, one per triangle of `surface`); empty without
// tags.
std::vector<std::uint64_t> tag_border_edges(const TriangleSurface& surface,
                                            const std::vector<std::int32_t>& tags);
// Per triangle edge (3 t + e, the edge opposite corner e) the triangle across it, or
// SurfaceTree::kNone where the edge is not shared by exactly two triangles (a border, or where
// an interface meets the boundary); on a closed 2-manifold, Surface3::adjacent.
std::vector<std::uint32_t> triangle_neighbours(const TriangleSurface& surface);

// The surface's sharpest dihedral angle, degrees: the smallest angle, measured inside the
// volume, between two triangles that share an edge (180 - the angle between their normals
// where the edge is convex, 180 + it where reflex, 180 where flat; convexity by orient3d,
// exact). 180 for a surface without triangles.
double sharpest_dihedral_deg(const Surface3& surface);

// Feature lines cut at the vertices where they turn by more than angle_deg (the angle
// between consecutive segments), which become corners: where a crease folds back on
// itself two feature edges meet, yet the point is a corner of the shape.
FeatureLines split_at_turns(const TriangleSurface& s, const FeatureLines& lines, double angle_deg);

// The feature lines at least as long as `ratio` times the local spacing of the sites at
// their middle vertex, and the corners that end them: shorter creases (noise of a coarse
// surface, details below the resolution) are treated as smooth surface.
// A line with an edge of `keep` (sorted edge keys: the borders of tagged patches) is kept
// whatever its length.
FeatureLines drop_short_lines(const TriangleSurface& s, const FeatureLines& lines, double ratio,
                              const Spacing& spacing, const std::vector<std::uint64_t>& keep);

// The edge keys of the edges of `lines`, sorted.
std::vector<std::uint64_t> sorted_feature_edges(const FeatureLines& lines);

// The patch of each boundary triangle: the triangles grouped by a flood fill across the
// edges that are not feature edges, numbered in the order of their first triangle.
std::vector<std::uint32_t> triangle_patches(const TriangleSurface& surface,
                                            const FeatureLines& lines);

// The surface patches of the sites (SurfacePatches), `patch` the patch of each boundary
// triangle: a surface site is on the patch of the triangle it projects onto, a feature site
// on the patches beside the segment it projects onto, a corner on the patches around its
// vertex.
SurfacePatches site_patches(const TriangleSurface& input, const FeatureLines& lines,
                            const SurfaceTree& surface, const FeatureTree& line_tree,
                            const std::vector<double>& sites, const std::vector<Kind>& kinds,
                            const std::vector<std::uint32_t>& line_of,
                            const std::vector<std::uint32_t>& corner_vertex,
                            const std::vector<std::uint32_t>& patch);

// Removes the flat tets lying on the boundary: tets whose four vertices are constrained
// sites (`kinds` not kFree), with at least two faces on the boundary and a smallest dihedral
// angle below max_q1_deg, worst first, at most one of the tets around each vertex per pass.
// No move of the sites fixes them (their vertices stay on the surface); without them the
// boundary runs across their inner faces. A pass whose result `keep` refuses is undone and
// ends the peeling; at most `passes` passes. Returns the number of tets removed
// (slivers3d.cpp).
std::uint32_t peel_flat_boundary_tets(
    const std::vector<double>& sites, const std::vector<Kind>& kinds,
    std::vector<std::uint32_t>& tets, double max_q1_deg, std::uint32_t passes,
    const std::function<bool(const std::vector<std::uint32_t>&)>& keep);

// Flips, smoothing and insertion against the tets whose min(Q1, 50 Q4) (Q1 in degrees; Q4 =
// 0.4 weighs as 20 degrees) is below below_deg, worst first (flips3d.cpp): 2-3 flips of interior
// faces and removal of interior edges with up to 8 tets around them (3-2, 4-4, ...); else a move of
// one of the tet's free vertices (kinds kFree; with on_surface, of its surface vertices on the
// surface too); else a new free vertex in the cavity of the tet and its face neighbours
// (appended to `sites`; not when a vertex would be left inside the cavity). Each is
// applied when the smallest such measure of the tets it makes beats that of the tets it
// replaces by more than gain_deg and their smallest Q4 is not below the replaced tets' (or
// 0.5: a constraint of the search for the operation); at
// most max_operations. The boundary triangles are unchanged (their vertices only slide on
// the surface, with on_surface) but for the boundary flips (with same_patch); every new tet is
// right-handed exactly (orient3d < 0, as `tets` is given).
struct Flip3Options {
  double below_deg = 30, gain_deg = 0.01;
  // Before and after, a pass against the tets whose Q4 is below below_q4 (0: none), each
  // operation raising the smallest Q4 by more than gain_q4 and keeping the smallest Q1 of the
  // tets it replaces (or below_deg).
  double below_q4 = 0, gain_q4 = 0.001;
  std::uint32_t max_operations = 0;
  bool flip = true, smooth = true, insert = true;  // which operations
  // When set, surface vertices (kSurface) move too, each candidate position p replaced by
  // q, on_surface(v, p, q) (false: the candidate is dropped).
  std::function<bool(std::uint32_t, const double*, double*)> on_surface;
  // When set, boundary 2-2 flips too: the boundary edge (a, b) of the triangles (a, b, c) and
  // (b, a, d) replaced by (c, d), the tets around (a, b) (an open fan of 2 to 8) by a
  // triangulation of the fan, the boundary triangles by (a, c, d) and (b, d, c); only when
  // same_patch(a, b, c, d) (the four triangles in one surface patch, the caller's), (c, d)
  // is no edge of the mesh, a or b is a surface vertex (kSurface: no feature edge goes),
  // and the four triangles' normals are within kBoundaryFlipDeg of each other (flips3d.cpp).
  std::function<bool(std::uint32_t, std::uint32_t, std::uint32_t, std::uint32_t)> same_patch;
};
struct Flip3Stats {
  // flips counts the boundary flips too.
  std::uint32_t flips = 0, moves = 0, insertions = 0, boundary_flips = 0;
};
Flip3Stats flip_slivers3(std::vector<double>& sites, const std::vector<Kind>& kinds,
                         std::vector<std::uint32_t>& tets, const Flip3Options& options);

// The pass for the mean Q1 (flips3d.cpp; step 7d of mesh3d): `rounds` rounds, each of flips
// (2-3 of interior faces, removal of interior edges with up to 4 tets around them), each taken
// when it raises the mesh's mean Q1, then of moves of the free vertices (and, with on_surface as
// in Flip3Options, of the surface vertices on the surface), each to the best position a compass
// search finds for the sum of the Q1 of its tets (a surface vertex only where its boundary
// triangles are within 30 degrees of each other, and no farther from the surface or from its
// old position than before). Every operation keeps the smallest Q1 of the
// tets it replaces or 30 degrees, their smallest Q4 or 0.4, and makes right-handed tets only
// (orient3d, exact); the boundary triangles are unchanged (their surface vertices at most
// slide). The moves go by classes of vertices that share no tet (greedy in vertex order), the
// searches of a class in parallel (TBB), their moves applied in vertex order; the flips'
// candidates found in parallel by blocks of tets, taken one tet after the other: the same
// result for any thread count. A round that changes nothing ends the pass.
struct Mean3Stats {
  std::uint32_t flips = 0, moves = 0, rounds = 0;
  double mean_before = 0, mean_after = 0;  // mean Q1 of the tets, degrees
};
Mean3Stats raise_mean3(
    std::vector<double>& sites, const std::vector<Kind>& kinds, std::vector<std::uint32_t>& tets,
    std::uint32_t rounds,
    const std::function<bool(std::uint32_t, const double*, double*)>& on_surface);

// Where to insert a site against each kept tet whose smallest dihedral angle is below
// below_deg (slivers3d.cpp): its circumcentre, worst tet first (ties by index), skipping a
// tet whose circumradius exceeds its longest edge (a flat tet's circumcentre is far from it)
// and a centre closer than half its radius to one already taken. A kept tet's circumcentre
// lies in the volume and its circumsphere is empty, so the new site is at least the radius
// from every site: next to two feature corners a fraction of the spacing apart (homer at
// 10,000 vertices: 0.0028 against 0.013) the tets with that short edge and a far opposite
// edge get a vertex near it.
struct SliverCenter {
  double q1_deg = 0, radius = 0;
  std::array<double, 3> center{};
};
// *lowest: the smallest dihedral angle of all the tets (180 when there is none).
std::vector<SliverCenter> sliver_centers(const std::vector<double>& sites,
                                         const std::vector<std::uint32_t>& tets, double below_deg,
                                         double* lowest);

// The perturbation's local scorer (slivers3d.cpp) inserts each candidate position into the
// triangulation of the other sites of the neighbourhood; check_local_scores compares that,
// for every vertex with kept tets (the mesh extracted from `sites`), against building the
// local triangulation whole: the score, whether there is an incident kept tet and the worst
// one's vertices, bit for bit. Positions: the vertex's own, each neighbour's, the midpoints
// to them, and the vertex's plus each offset given (3 values each).
struct LocalScoreCheck {
  std::uint64_t positions = 0, mismatches = 0;
  std::uint32_t vertices_with_base = 0;  // the others' triangulation could be built
};
LocalScoreCheck check_local_scores(const TetExtractor3& extractor, const std::vector<double>& sites,
                                   const std::vector<SiteConstraint3::Kind>& kinds,
                                   const std::vector<double>& positions_per_vertex);

// The points where one round of the topology refinement adds sites (topology_repair3d.cpp):
// each bad cell's farthest point (defects.points), farthest from its cell's site first
// (ties by coordinates), skipping a point closer than half that distance to a point already
// taken: two bad cells often have their farthest points at two restricted Voronoi vertices
// a hair apart (where a Voronoi edge crosses the surface next to a mesh edge), and both
// taken they become two boundary vertices 1e-5 to 1e-2 of the spacing apart, with flat
// tets between them (skull_low_resolution at 10,000 vertices: Q1 0.005 degrees). The
// first repairs both cells or the next round finds what is left; at least one point is
// taken when there is a defect, so the refinement advances (Cheng, Dey & Ramos insert one
// point at a time; this keeps their insertion radius within a factor of two per round).
// The skipped points are counted into *nb_deferred when it is not null.
std::vector<std::array<double, 3>> refinement_points(const ClosedBallDefects& defects,
                                                     const std::vector<double>& sites,
                                                     std::uint32_t* nb_deferred);

// Step 2 (mesh3d.cpp): about n sites on a body-centred cubic lattice strictly inside the
// domain (its spacing fitted to the count, the offset from the seed); empty when no spacing
// gives within 10 % of n (a part thinner than the lattice's layers): sample at random then.
std::vector<double> lattice_sites(const Domain3& domain, const TetExtractor3& locator,
                                  std::uint32_t n, std::uint64_t seed);

// VertexCount::kRaise's retries (mesh3d.cpp): while `wrong(result)`, at most
// options.max_shape_retries times, `run` again with twice the vertices (a progress report
// with retry_vertices first); the result keeps the count asked for, the retries and why
// (`what` + the first result's shape problem), and the time of all the runs.
Mesh3Result raise_vertices(const Mesh3Options& options, Mesh3Result result,
                           const std::function<Mesh3Result(const Mesh3Options&)>& run,
                           const std::function<bool(const Mesh3Result&)>& wrong,
                           const std::string& what);

// x to 4 significant digits, for messages (mesh3d.cpp).
std::string brief(double x);

// Step 8's quality figures of a finished mesh (result.xyz, kinds, tets): the quality report,
// the input's sharpest dihedral angle and the bound, the tets below it, Q1 by boundary
// vertices.
void measure_mesh3_quality(const Domain3& domain, Mesh3Result& result);

// What the sites' count is spread over the bodies by: per body the integral over its
// volume of h^-3, h the target size's shape (the volume for a uniform size; from the
// user's density, the local feature size with options.adaptive, or the lfs cap with one
// uniform spacing for all the bodies).
std::vector<double> body_site_integrals(const std::vector<Domain3>& bodies,
                                        const Mesh3Options& options);

// Several bodies (mesh3d_bodies.cpp). The bodies of the domain, each an outer shell with the
// cavities directly inside it (for a tet mesh: its face-connected tets), as domains of
// their own, in the order of their outer shells; empty for a domain of one body.
std::vector<Domain3> domain_bodies(const Domain3& domain);
// mesh3d of a domain of several bodies: each body meshed on its own (mesh3d, with its share
// of options.nb_vertices by body_site_integrals, at least 4), the meshes put together in body
// order, tags and figures for the whole.
Mesh3Result mesh3d_bodies(const Domain3& domain, const std::vector<Domain3>& bodies,
                          const Mesh3Options& options);

// Interfaces between the regions of a tet mesh domain (mesh3d_interfaces.cpp has the method).
constexpr std::uint32_t kNoRegion = 0xffffffffu;
struct RegionInterfaces {
  // The regions, by increasing tag: each the volume of the input's tets of that tag (a
  // Domain3 of them, on the domain's vertices).
  std::vector<Domain3> regions;
  std::vector<std::int32_t> tags;
  // The domain's boundary triangles (first, in the domain's order) and the interfaces' (the
  // facets between tets of two regions, oriented outward from the lower region): the surface
  // the sites are sampled on; not a 2-manifold where an interface meets the boundary or
  // another interface.
  TriangleSurface surface;
  std::uint32_t nb_boundary_triangles = 0;
  // Per interface triangle: its two regions (lower, higher) and its interface (one per pair of
  // regions that meet, numbered in the order of their first triangle); nb_interfaces of them.
  std::vector<std::array<std::uint32_t, 2>> sides;
  std::vector<std::uint32_t> interface_of;
  std::uint32_t nb_interfaces = 0;
  // Per triangle of `surface`, the regions it bounds (bit k: region k; one for a boundary
  // triangle, two for an interface's); empty with more than 64 regions.
  std::vector<std::uint64_t> triangle_regions;
  // Per triangle of `surface`: the domain's boundary_refs, then the file's tags of the
  // interface triangles (Domain3::inner_triangle_ref; 0 where it lists none); empty when the
  // file tags no triangle of either.
  std::vector<std::int32_t> refs;
  // The region holding p (strictly; else the first whose boundary holds it; kNoRegion
  // outside the domain). Exact.
  std::uint32_t region_of(const double* p) const;
};
// Whether the domain has several regions (tet tags) the mesh can follow: each region's tets a
// valid volume on its own (Domain3: a closed 2-manifold boundary, no tets meeting along an
// edge or at a vertex only); then `out` is filled. Not when the domain has no tet tags or
// one; `why_not` says why when it has several it cannot follow.
bool region_interfaces(const Domain3& domain, RegionInterfaces& out, std::string& why_not);
// The tags the file gives triangles between tets of two regions (Domain3::inner_triangle_ref:
// its own interface tags), sorted, each once.
std::vector<std::int32_t> file_interface_tags(const Domain3& domain);
// The file's tagged triangles between two tets of the same region (Mesh3Result::
// embedded_tags_dropped: an embedded surface, which the mesh does not follow), per tag.
std::vector<Mesh3Result::EmbeddedTag> file_embedded_tags(const Domain3& domain);
// The region of each tet of a mesh whose tets are Delaunay: the input region holding its
// circumcentre (exact; a tet with its circumcentre outside the domain, kept at the boundary,
// by its centroid or a face neighbour), then the extraction's crease rule with the sites'
// patches `sp` where a face between two regions crosses a feature line.
struct TetRegions {
  std::vector<std::uint32_t> region;  // per tet, an index into RegionInterfaces::regions
  std::uint32_t nb = 0;               // regions
};
TetRegions interface_regions(const RegionInterfaces& interfaces, const std::vector<double>& sites,
                             const std::vector<std::uint32_t>& tets, const SurfacePatches& sp);
// Runs `pass` on the tets of each region in turn (with `kinds` but the vertices of two
// regions' tets kFixed, and kFree for sites an earlier pass added), the tets put together
// region after region (regions.region follows): a pass that keeps its tets' union and
// boundary (flips, moves of vertices off that boundary, insertions) never makes a tet across
// an interface.
void per_region(
    std::vector<double>& sites, const std::vector<Kind>& kinds, std::vector<std::uint32_t>& tets,
    TetRegions& regions,
    const std::function<void(std::vector<std::uint32_t>&, const std::vector<Kind>&)>& pass);
// The mesh's interfaces (Mesh3Result::interface_triangles, interface_tags, their names) from
// its tets and `regions`: a face between tets of two regions takes the file's tag of the input
// interface triangle between the same regions nearest its centroid (`sampled_tree`: the tree
// of `interfaces.surface`), or when that has none its interface's rank after
// result.boundary_tags' largest.
void tag_interfaces(const RegionInterfaces& interfaces, const SurfaceTree& sampled_tree,
                    const TetRegions& regions, Mesh3Result& result);
// The distance between the mesh's interfaces (result.interface_triangles) and the input's,
// either way, sampled, in local edge lengths (`edge_length`: its scale, and scale_batch
// when set) into result.interface_distance_to_edge_length; what is wrong when it exceeds
// `bound` (> 0), or when the mesh has no interface, else empty.
std::string interface_distance(const RegionInterfaces& interfaces,
                               const HausdorffOptions& edge_length, double bound,
                               Mesh3Result& result);
// What is wrong with the mesh's regions, empty when nothing: each region's tets must have the
// shape of the input's region (check_mesh3_shape).
std::string interface_shape(const RegionInterfaces& interfaces, const std::vector<double>& xyz,
                            const std::vector<std::uint32_t>& tets, const TetRegions& regions);

// One mesh3d() run: the caller's domain and options, the result being filled, the phase
// clock and the sites with their constraints. Each step is a member, defined in the file
// named above.
struct Pipeline {
  using Clock = std::chrono::steady_clock;

  Pipeline(const Domain3& d, const Mesh3Options& o, Mesh3Result& r)
      : domain(d), options(o), result(r), t_start(Clock::now()), t_phase(t_start) {}

  // Steps 1 to 8 into `result`; a cancelled run leaves result.cancelled set and no mesh.
  void run();

  // The caller's progress callback with the phase and time filled in; false when it asks to
  // stop. report() throws Cancelled instead.
  bool notify(Mesh3Progress p) const;
  void report(const Mesh3Progress& p) const;
  // Closes the current phase's time and reports the next one.
  void next_phase(Mesh3Phase next);
  // The CVT's progress as mesh progress (iteration, energy, |g|).
  std::function<bool(const CvtProgress&)> cvt_progress() const;

  // Step 4 (features3d.cpp): corners take the site nearest to them (a new site when that one
  // is taken), feature lines the sites whose cells they cross, surface sites are the
  // boundary sites left (`boundary`, per site); every constrained site is moved onto its
  // corner, line or the surface.
  void constrain_sites(const FeatureLines& lines, const FeatureTree& line_tree,
                       const Spacing& local_spacing, const std::vector<std::uint8_t>& boundary,
                       const Projection& project);
  // Step 4's sites on the lines' gaps: where one site's cell holds two lines (the two rims of
  // a plate thinner than the spacing, a thin fin), it takes the line with more samples and
  // the other has no site there. A gap of 1.5 local spacings or more between a line's sites
  // (an open line's ends count as sites) gets sites at even arclengths, k in a gap of length
  // g with k + 1 = g / spacing rounded, each only where no constrained site is within half a
  // spacing; their positions go to `added`, their lines to `added_line`.
  void fill_line_gaps(const FeatureTree& line_tree, const Spacing& local_spacing,
                      std::vector<double>& added, std::vector<std::uint32_t>& added_line);
  // Sites on the lines' gaps (fill_line_gaps) after the CVT has moved the line sites, appended
  // as line sites; their number.
  std::uint32_t refill_line_gaps(const FeatureTree& line_tree, const Spacing& local_spacing);
  // Appends line sites (kCurve) at `xyz` (3 each) on the feature lines `line`.
  void append_line_sites(const std::vector<double>& xyz, const std::vector<std::uint32_t>& line);
  // Free sites whose cells reach the boundary (`boundary`, from the CVT's last diagram) go
  // onto the surface: they would become boundary vertices inside the volume. Their number.
  std::uint32_t snap_boundary_free_sites(const std::vector<std::uint8_t>& boundary,
                                         const Projection& project);
  // Step 5a (boundary_approx3d.cpp): sites fixed at the input vertices farther than
  // options.facet_distance times the local spacing from the boundary of the mesh the sites
  // give (extracted with the patches site_patches_now() returns), each round followed by a
  // short constrained CVT.
  void approximate_boundary(const TetExtractor3& extractor, Cvt3Options& cvt,
                            const Spacing& local_spacing, const std::vector<std::uint8_t>& boundary,
                            const Projection& project,
                            const std::function<SurfacePatches()>& site_patches_now);
  // With interfaces: the free sites whose cells cross an interface are marked in `boundary`
  // (resized to the sites' count), as the CVT marks those whose cells reach the boundary, so
  // that they go onto it. The first time (after the unconstrained CVT) only those of the
  // higher region of the two: one layer of sites onto each interface, as the boundary gets;
  // after that (both_sides) the cells of either side that still reach across
  // (mesh3d_interfaces.cpp).
  void mark_interface_sites(std::vector<std::uint8_t>& boundary, bool both_sides) const;
  // Step 5b (topology_repair3d.cpp).
  void repair_topology(const TriangleSurface& surface, const Clip3Options& clip, Cvt3Options& cvt,
                       std::vector<std::uint8_t>& boundary, const Projection& project);
  // What steps 6 and 7 read of the steps before: the extractor, the surface the sites are on
  // (the boundary, and the interfaces when followed) with its tree, feature lines and
  // patches, the feature lines where interfaces meet, the local spacing and the projection.
  struct Surroundings {
    const TetExtractor3& extractor;
    const TriangleSurface& surface;
    const SurfaceTree& surface_tree;
    const FeatureLines& lines;
    const FeatureTree& line_tree;
    const std::vector<std::uint32_t>& triangle_patch;
    const std::vector<std::uint8_t>& junction_line;
    const Spacing& local_spacing;
    const Projection& project;
  };
  // Steps 6 and 7 (mesh3d_slivers.cpp): the extraction and the sliver perturbation, the
  // insertions at the slivers left, the junction lines' sites, the peeling, the flips and
  // moves; the tets, the sites' surface patches and, with interfaces, the tets' regions.
  void make_tets(const Surroundings& around, std::vector<std::uint32_t>& tets,
                 SurfacePatches& patches, TetRegions& regions);

  const Domain3& domain;
  const Mesh3Options& options;
  Mesh3Result& result;
  // Set when the domain's regions have interfaces the mesh follows (region_interfaces).
  std::unique_ptr<RegionInterfaces> interfaces;
  Clock::time_point t_start, t_phase;
  Mesh3Phase phase = Mesh3Phase::kSizing;

  // The sites (3 coordinates each) and, per site, its constraint, its feature line (kCurve)
  // and its corner vertex of the domain (kFixed at a corner); n sites.
  std::vector<double> sites;
  std::vector<Kind> kinds;
  std::vector<std::uint32_t> line_of, corner_vertex;
  std::uint32_t n = 0;
};

// Seconds since t.
inline double since(Pipeline::Clock::time_point t) {
  return std::chrono::duration<double>(Pipeline::Clock::now() - t).count();
}

}  // namespace voroclip::mesh3
