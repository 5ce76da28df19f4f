// The `voroclip demo` command: the exact predicate kernel on two bundled examples.
//
// 1. The "classroom example" of Kettner, Mehlhorn, Pion, Schirra and Yap, "Classroom
//    examples of robustness problems in geometric computations", CGTA 40(1), 2008, sec. 3:
//    orient2d(p, q, r) for q = (12, 12), r = (24, 24) and the 256 x 256 points
//    p = (0.5 + i*u, 0.5 + j*u), u = 2^-53 (consecutive doubles above 0.5). All of them are
//    within a few ulps of the line y = x; the exact determinant is 12 (p.y - p.x), so the
//    exact sign is known in closed form and the demo checks every exact answer against it.
// 2. Symbolic perturbation on the corners of the unit cube: all eight are cospherical, so
//    insphere is exactly zero for every 5-tuple and insphere_sos must decide.
// 3. CVT meshing (Yan, Wang, Lévy & Liu, CAD 2011) of a built-in domain with three holes:
//    the clipped Voronoi diagram of a centroidal Voronoi tessellation, and a CVT triangle
//    mesh, checked exactly (check_mesh2) and measured (angles).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "voroclip/clip.h"
#include "voroclip/cvt.h"
#include "voroclip/mesh.h"
#include "voroclip/predicates.h"

namespace voroclip::cli {

struct SignCounts {
  std::size_t positive = 0;
  std::size_t zero = 0;
  std::size_t negative = 0;
  void add(Sign s);
};

struct ClassroomResult {
  static constexpr std::size_t kGrid = 256;
  // Signs of point (i, j) at [j * kGrid + i].
  std::vector<Sign> naive;
  std::vector<Sign> exact;
  SignCounts naive_counts;
  SignCounts exact_counts;
  std::size_t naive_wrong = 0;
  // The wrong naive signs split by kind: zero for a point off the line, non-zero for a point
  // on it, and the opposite sign.
  std::size_t naive_false_zero = 0;
  std::size_t naive_false_nonzero = 0;
  std::size_t naive_flipped = 0;
};

struct CubeTest {
  std::uint32_t corner;  // the fifth point; corner k is (k & 1, (k >> 1) & 1, (k >> 2) & 1)
  Sign exact;
  Sign sos;
};

struct CubeResult {
  std::array<std::uint32_t, 4> tetrahedron;  // corners in positive orient3d order
  std::vector<CubeTest> tests;
  SignCounts sos_counts;
};

/// Evaluates both predicates on the whole grid in parallel (one slot per point, so the
/// result does not depend on the number of threads) and checks every exact sign against
/// the closed form; throws voroclip::Error if one disagrees.
ClassroomResult run_classroom_example();

/// Throws voroclip::Error if an exact insphere on the cube is not zero.
CubeResult run_cube_example();

/// A two-panel SVG picture (naive | exact) of the classroom example's signs.
void write_classroom_svg(const ClassroomResult& result, std::ostream& out);

struct MeshDemoResult {
  Domain2 domain;
  std::uint32_t cvt_sites = 0;
  Cvt2Result cvt;
  std::uint32_t boundary_cells = 0;
  double cells_area = 0;  // sum of the clipped cells' areas (the domain's area)
  Mesh2 mesh;
  Mesh2Stats mesh_stats;
  TriangleQuality2 quality;
  std::string clip_svg, mesh_svg;  // the two pictures (complete SVG documents)
};

/// The domain: a rounded outline with a circular, a square and a triangular hole.
PolygonRings demo_domain_rings();

/// A CVT of 200 sites (L-BFGS) and its clipped diagram; a CVT mesh of about 500 vertices.
/// Throws voroclip::Error if the mesh fails check_mesh2. Deterministic for any thread count.
MeshDemoResult run_mesh_demo();

/// The demo's picture: the clipped Voronoi diagram and the mesh side by side, the classroom
/// example's two panels below.
void write_demo_svg(const ClassroomResult& classroom, const MeshDemoResult& mesh,
                    std::ostream& out);

}  // namespace voroclip::cli
