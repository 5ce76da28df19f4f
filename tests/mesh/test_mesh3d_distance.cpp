// Tests of step 5a of mesh3d (Mesh3Options::facet_distance): on a box meshed without
// feature lines, whose corners the uniform spacing cuts off, every corner becomes a vertex
// of the output, exactly at the input's vertex; every vertex placed by the step is an input
// vertex bitwise; the input's distance to the output's boundary (Hausdorff, input -> mesh)
// drops; the vertex count stays within the step's budget; the same bits with 1 and 2
// threads; facet_distance = 0 leaves the mesh as it was.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "mesh_test_shapes.h"
#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/mesh.h"

using voroclip::Domain3;
using voroclip::Mesh3Options;
using voroclip::Mesh3Result;
using voroclip::Mesh3VertexKind;

namespace {

// The output's boundary triangles as a surface.
voroclip::TriangleSurface output_boundary(const Mesh3Result& r) {
  voroclip::TriangleSurface s;
  s.source = "mesh3d output";
  s.xyz = r.xyz;
  s.triangles = r.boundary_triangles;
  return s;
}

// The largest distance from an input vertex to the output's boundary (the Hausdorff
// distance's input -> mesh side at the vertices, where the spacing cuts off the corners).
double vertex_distance(const Domain3& domain, const Mesh3Result& r) {
  const voroclip::SurfaceTree tree(output_boundary(r));
  double worst = 0;
  for (std::uint32_t v = 0; v < domain.nb_vertices(); ++v) {
    worst = std::max(worst, std::sqrt(tree.closest(domain.vertex(v)).distance2));
  }
  return worst;
}

// Whether p is bitwise one of the domain's vertices.
bool is_input_vertex(const Domain3& domain, const double* p) {
  for (std::uint32_t v = 0; v < domain.nb_vertices(); ++v) {
    const double* q = domain.vertex(v);
    if (q[0] == p[0] && q[1] == p[1] && q[2] == p[2]) return true;
  }
  return false;
}

}  // namespace

TEST_CASE("mesh3d facet_distance: the corners a box's spacing cuts off become vertices",
          "[mesh3d][distance]") {
  const Domain3 box(voroclip_test::box_surface({0, 0, 0}, {1, 0.8, 0.6}));
  Mesh3Options o = voroclip_test::small_options(400);
  o.features = false;  // the corners are then surface like any other point
  const Mesh3Result plain = voroclip::mesh3d(box, o);
  REQUIRE(plain.shape_problem.empty());
  CHECK(plain.nb_distance_sites == 0);
  // The uniform spacing h = (volume / n)^(1/3): without the step the corners are cut off
  // by more than the facet distance asked below (else this test could not fail).
  const double h = std::cbrt(0.48 / 400);
  const double facet_distance = 0.15;
  REQUIRE(vertex_distance(box, plain) > facet_distance * h);

  o.facet_distance = facet_distance;
  const Mesh3Result r = voroclip_test::check_same_mesh3d_with_1_and_2_threads(box, o);
  REQUIRE(r.shape_problem.empty());
  CHECK(r.nb_distance_sites >= 8);
  // Within the budget: at most 3 % more sites than asked (besides the topology's).
  CHECK(r.nb_distance_sites_added <= static_cast<std::uint32_t>(0.03 * 400));
  CHECK(r.nb_vertices() <= 400 + r.nb_distance_sites_added + r.nb_topology_sites + 8);
  // Every corner is a vertex of the output, and every fixed vertex an input vertex, bitwise.
  for (std::uint32_t c = 0; c < 8; ++c) {
    const double* corner = box.vertex(c);
    bool found = false;
    for (std::uint32_t v = 0; v < r.nb_vertices(); ++v) {
      const double* p = &r.xyz[3 * std::size_t{v}];
      if (p[0] == corner[0] && p[1] == corner[1] && p[2] == corner[2]) {
        found = true;
        CHECK(r.kinds[v] == Mesh3VertexKind::kCorner);
      }
    }
    CHECK(found);
  }
  for (std::uint32_t v = 0; v < r.nb_vertices(); ++v) {
    if (r.kinds[v] == Mesh3VertexKind::kCorner) CHECK(is_input_vertex(box, &r.xyz[3 * v]));
  }
  // The corners are on the boundary now: no input vertex is off it.
  CHECK(vertex_distance(box, r) == 0);
  // The two-sided Hausdorff distance (sampled, as the CLI reports it) drops too.
  const voroclip::TriangleSurface input = voroclip::boundary_surface(box);
  const double before = voroclip::hausdorff_distance(output_boundary(plain), input).max;
  const double after = voroclip::hausdorff_distance(output_boundary(r), input).max;
  CHECK(after < before);
  // Right-handed tets, exactly.
  std::size_t wrong = 0;
  for (std::size_t t = 0; t < r.tets.size(); t += 4) {
    const double* p[4];
    for (std::size_t k = 0; k < 4; ++k) p[k] = &r.xyz[3 * std::size_t{r.tets[t + k]}];
    wrong += voroclip::orient3d(p[0], p[1], p[2], p[3]) != voroclip::Sign::negative ? 1 : 0;
  }
  CHECK(wrong == 0);
}
