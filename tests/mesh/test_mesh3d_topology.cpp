// Tests of the topology refinement's choice of new sites (mesh3d_pipeline.h,
// refinement_points): one per bad cell at its farthest point, farthest first, none closer
// than half its radius to one taken in the same round (the skull's flat boundary tets of
// issue 30 came from pairs of new sites 2.6e-5 apart); and the defects themselves
// (closed_ball_defects) where a shell is far smaller than the spacing.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "mesh3d_pipeline.h"
#include "mesh_test_shapes.h"
#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/mesh.h"

using voroclip::ClosedBallDefects;
using voroclip::mesh3::refinement_points;
using Point = std::array<double, 3>;

namespace {

// Defects of the cells of `cells` (site indices into sites) at `points`, one per cell.
ClosedBallDefects defects_at(const std::vector<std::uint32_t>& cells,
                             const std::vector<Point>& points) {
  ClosedBallDefects d;
  d.cells = cells;
  for (const Point& p : points) d.points.insert(d.points.end(), p.begin(), p.end());
  d.nb_not_disk = static_cast<std::uint32_t>(cells.size());
  return d;
}

// A box [0, 10]^3 and a speck, the box [20, 20.1] x [0, 0.1]^2: two shells, the speck far
// smaller than the spacing of a few sites in the box.
voroclip::TriangleSurface box_and_speck() {
  return voroclip_test::merged(voroclip_test::box_surface({0, 0, 0}, {10, 10, 10}),
                               voroclip_test::box_surface({20, 0, 0}, {20.1, 0.1, 0.1}));
}

// The 8 sites (2.5 or 7.5)^3 in the box, site x + 2y + 4z at 7.5 along the axes set; then
// `more`.
std::vector<double> box_sites(const std::vector<Point>& more) {
  std::vector<double> sites;
  for (int i = 0; i < 8; ++i) {
    for (int k = 0; k < 3; ++k) sites.push_back((i >> k) & 1 ? 7.5 : 2.5);
  }
  for (const Point& p : more) sites.insert(sites.end(), p.begin(), p.end());
  return sites;
}

ClosedBallDefects defects_of(const voroclip::Domain3& domain, const std::vector<double>& sites,
                             const std::vector<std::uint64_t>& knives,
                             const voroclip::Surface3* surface) {
  voroclip::Clip3Options o;
  o.keep_surface = true;
  voroclip::ClippedVoronoi3 cv;
  cv.compute(domain, sites.data(), static_cast<std::uint32_t>(sites.size() / 3), o);
  return voroclip::closed_ball_defects(cv, sites.data(), knives, surface);
}

// Both boxes' edges as knife edges (their normals 90 degrees apart: sharper than 45).
std::vector<std::uint64_t> box_edges() {
  return voroclip::mesh3::sorted_feature_edges(
      voroclip::extract_feature_lines(box_and_speck(), 45));
}

}  // namespace

TEST_CASE("closed_ball_defects: a shell inside one cell counts, knife edges or not",
          "[mesh][exact]") {
  const voroclip::Domain3 domain(box_and_speck());
  const std::vector<std::uint64_t> knives = box_edges();
  REQUIRE(knives.size() == 24);
  const std::vector<double> sites = box_sites({});
  // The speck lies in the cell of site 1, (7.5, 2.5, 2.5), with that cell's corner of the
  // box: two pieces, one of them closed. Before, the knife edges hid it and the mesh lacked
  // the speck ("its boundary has 1 shell where the domain has 2", even at 8,000 vertices).
  for (const auto& k : {std::vector<std::uint64_t>{}, knives}) {
    const ClosedBallDefects d = defects_of(domain, sites, k, nullptr);
    CHECK(d.cells == std::vector<std::uint32_t>{1});
    CHECK(d.nb_not_disk == 1);
    // The refinement point: the region's vertex farthest from the site, a corner of the speck.
    CHECK(d.points == std::vector<double>{20.1, 0, 0});
  }
}

TEST_CASE("closed_ball_defects: the cells of a shell that fewer than four cells meet count",
          "[mesh][exact]") {
  const voroclip::Domain3 domain(box_and_speck());
  const std::vector<std::uint64_t> knives = box_edges();
  // Three sites at corners of the speck: each cell touches its edges, so the knife rule
  // passes them over; a restricted Delaunay surface on three vertices is no closed surface,
  // and with the domain's surface they count.
  const std::vector<Point> three = {{20, 0, 0}, {20.1, 0.1, 0}, {20, 0.1, 0.1}};
  const std::vector<std::uint32_t> theirs = {8, 9, 10};
  const ClosedBallDefects lenient = defects_of(domain, box_sites(three), knives, nullptr);
  for (const std::uint32_t c : theirs) {
    CHECK(std::count(lenient.cells.begin(), lenient.cells.end(), c) == 0);
  }
  const ClosedBallDefects strict = defects_of(domain, box_sites(three), knives, &domain.surface());
  for (const std::uint32_t c : theirs) {
    CHECK(std::count(strict.cells.begin(), strict.cells.end(), c) == 1);
  }
  CHECK(strict.nb_not_disk == lenient.nb_not_disk + 3);
  // A fourth site (the corners of a tetrahedron): the rule no longer applies.
  std::vector<Point> four = three;
  four.push_back({20.1, 0, 0.1});
  CHECK(defects_of(domain, box_sites(four), knives, &domain.surface()).cells ==
        defects_of(domain, box_sites(four), knives, nullptr).cells);
}

TEST_CASE("mesh3d: a body far smaller than the spacing beside a large one keeps its shell",
          "[mesh][regression]") {
  // At 1,000 vertices (spacing about 1) the speck of 0.1 is a body of its own, meshed with
  // its share of the vertices (at least 4) and its corners: both shells at the first try.
  const voroclip::Domain3 domain(box_and_speck());
  const voroclip::Mesh3Result r = voroclip::mesh3d(domain, voroclip_test::small_options(1000));
  CHECK(r.shape_problem.empty());
  CHECK(r.shape_retries == 0);
  std::uint32_t on_speck = 0;
  for (std::size_t v = 0; v < r.xyz.size() / 3; ++v) on_speck += r.xyz[3 * v] >= 20 ? 1 : 0;
  CHECK(on_speck >= 8);
  for (std::size_t t = 0; t < r.tet_tags.size(); ++t) {
    CHECK(r.tet_tags[t] == (r.xyz[3 * std::size_t{r.tets[4 * t]}] >= 20 ? 2 : 1));
  }
  CHECK(voroclip::check_mesh3_shape(domain, r.xyz, r.tets).empty());
}

TEST_CASE("refinement_points: two bad cells with the same farthest point get one site",
          "[mesh][regression]") {
  // Round 8 of skull_low_resolution at 10,000 vertices: cells 3777 and 10388 had their
  // farthest points 2.6e-5 apart, 0.106 from their sites; both became sites.
  const std::vector<double> sites = {3.0, 6.4, 2.64, 3.1, 6.5, 2.78, 8.0, 0.0, 0.0};
  const Point a = {3.03112, 6.44808, 2.71612};
  const Point b = {3.03112, 6.44808, 2.71612 + 2.6e-5};
  const Point far = {8.0, 0.2, 0.0};
  std::uint32_t deferred = 0;
  const std::vector<Point> got =
      refinement_points(defects_at({0, 1, 2}, {a, b, far}), sites, &deferred);
  REQUIRE(got.size() == 2);
  CHECK(deferred == 1);
  // Farthest from its site first: the far one is 0.2 from site 2, cell 1's point 0.107 from
  // site 1, cell 0's 0.095 from site 0 (and 2.6e-5 from cell 1's, below 0.095 / 2).
  CHECK(got[0] == far);
  CHECK(got[1] == b);
  // Without the counter, and in another order: the same points.
  CHECK(refinement_points(defects_at({2, 1, 0}, {far, b, a}), sites, nullptr) == got);
}

TEST_CASE("refinement_points: the spacing rule, at its bound", "[mesh][exact]") {
  // Site 0 at the origin with its point at distance 1; the others at distance 1/2 from their
  // sites, so each must be at least 1/4 from the points taken before it (1/4, 1/2 exact).
  const std::vector<double> sites = {0, 0, 0, 1.25, 0.5, 0, 1.125, 0.5, 0, 3, 0.5, 0};
  const Point p0 = {1, 0, 0};
  const Point at_bound = {1.25, 0, 0};  // exactly 1/4 from p0: taken
  const Point inside = {1.125, 0, 0};   // 1/8 from both: deferred
  const Point alone = {3, 0, 0};        // taken
  std::uint32_t deferred = 0;
  const std::vector<Point> got =
      refinement_points(defects_at({0, 1, 2, 3}, {p0, at_bound, inside, alone}), sites, &deferred);
  CHECK(got == std::vector<Point>{p0, at_bound, alone});
  CHECK(deferred == 1);
  // Every point within reach of the first: one site, never none.
  const std::vector<double> one_site = {0, 0, 0};
  const std::vector<Point> crowded =
      refinement_points(defects_at({0, 0, 0}, {Point{1, 0, 0}, Point{1, 0.1, 0}, Point{1, 0, 0.1}}),
                        one_site, nullptr);
  CHECK(crowded.size() == 1);
  CHECK(refinement_points(ClosedBallDefects{}, one_site, nullptr).empty());
}

TEST_CASE("sliver_centers: circumcentres of the tets below the angle, worst first",
          "[mesh][regression]") {
  using voroclip::mesh3::sliver_centers;
  using voroclip::mesh3::SliverCenter;
  // Tet 0: a square of side 2 with one corner lifted by 1 (Q1 24.1 degrees), its circumcentre
  // (1, 1, 1/2) at 3/2 from its vertices. Tet 1: its mirror image in z = 1/2, the same centre
  // and angle. Tet 2: a cap (three nearly collinear vertices, Q1 0.64 degrees) whose
  // circumradius (about 200) exceeds its longest edge: no site for it.
  const std::vector<double> sites = {0,  0, 0, 2,  0, 0, 0,  2,    0, 2,  2, 1,  // tet 0
                                     0,  0, 1, 2,  0, 1, 0,  2,    1, 2,  2, 0,  // tet 1
                                     10, 0, 0, 14, 0, 0, 12, 0.01, 0, 12, 0, 1};
  const std::vector<std::uint32_t> tets = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11};
  double lowest = 0;
  const std::vector<SliverCenter> got = sliver_centers(sites, tets, 30, &lowest);
  CHECK(lowest == Approx(0.6405596).margin(1e-6));
  REQUIRE(got.size() == 1);  // tet 1's centre is tet 0's; the cap is skipped
  CHECK(got[0].q1_deg == Approx(24.09484255).margin(1e-6));
  CHECK(got[0].radius == Approx(1.5));
  CHECK(got[0].center[0] == Approx(1));
  CHECK(got[0].center[1] == Approx(1));
  CHECK(got[0].center[2] == Approx(0.5));
  // Below 20 degrees only the cap is, and it gets no site.
  CHECK(sliver_centers(sites, tets, 20, &lowest).empty());
  CHECK(lowest == Approx(0.6405596).margin(1e-6));
  CHECK(sliver_centers(sites, {}, 20, &lowest).empty());
  CHECK(lowest == 180);
}

TEST_CASE("mesh3d: a plate far thinner than the spacing stops the topology sites at their cap",
          "[mesh][regression]") {
  // A 1 x 1 x 0.001 plate at 300 vertices (spacing about 0.015): the restricted cells reach
  // across it, and each round's sites made more such cells than they split (876, 1409, 2210,
  // ... at 1,000 vertices; 27,048 sites by round 8, then again with twice the vertices,
  // without end). The sites the rounds add stop at max_topology_sites times the vertices.
  const voroclip::Domain3 plate = voroclip_test::six_tet_box(1, 1, 0.001, "plate");
  voroclip::Mesh3Options o = voroclip_test::small_options(300);
  o.max_shape_retries = 0;
  const voroclip::Mesh3Result r = voroclip::mesh3d(plate, o);
  CHECK(r.topology_capped);
  CHECK(r.nb_topology_sites <= 8 * 300);
  CHECK(r.topology_capped_near[2] >= 0);
  CHECK(r.topology_capped_near[2] <= 0.001);
  // A plate it cannot resolve: mesh3d says so (check_mesh3_shape, below), it does not hang.
  CHECK_FALSE(r.shape_problem.empty());
  // The cap must be a number >= 0.
  for (const double bad : {-1.0, std::nan("")}) {
    voroclip::Mesh3Options b = o;
    b.max_topology_sites = bad;
    CHECK_THROWS_WITH(voroclip::mesh3d(plate, b), Catch::Contains("max_topology_sites"));
  }
  // How thick it is where the defects are (shrinking balls: the plate's 0.001), and the
  // count of a uniform spacing that resolves it, volume / (4 t^3).
  CHECK(r.topology_capped_thickness == Approx(0.001).epsilon(1e-3));
  CHECK(r.topology_capped_vertices == Approx(0.001 / (4 * 1e-9)).epsilon(3e-3));
  // With --exact-vertices, an error that says why.
  o.vertex_count = voroclip::Mesh3Options::VertexCount::kExact;
  CHECK_THROWS_WITH(voroclip::mesh3d(plate, o),
                    Catch::Contains("300 vertices do not resolve the surface of plate") &&
                        Catch::Contains("a part far thinner than the spacing (about 0.001 across"));
}

TEST_CASE("mesh3d: no retries with more vertices when they cannot reach a thin part's count",
          "[mesh][regression]") {
  // The 1 x 1 x 0.001 plate at 1,000 vertices: three retries (2,000 to 8,000 vertices) took
  // 2.5 minutes to fail, where a uniform spacing through its 0.001 needs about 250,000. Now
  // the first run's estimate ends it.
  const voroclip::Domain3 plate = voroclip_test::six_tet_box(1, 1, 0.001, "plate");
  voroclip::Mesh3Options o = voroclip_test::small_options(1000);
  const voroclip::Mesh3Result r = voroclip::mesh3d(plate, o);
  CHECK(r.topology_capped);
  CHECK(r.shape_retries_skipped);
  CHECK(r.shape_retries == 0);
  CHECK_FALSE(r.shape_problem.empty());
  CHECK(r.topology_capped_vertices > 4 * 8 * 1000);
  // A 1 x 1 x 0.02 plate at 150 caps its topology sites too, but a uniform spacing needs
  // about 625 vertices there, within 4 times the 600 that two retries reach: it is meshed
  // again as before.
  const voroclip::Domain3 thicker = voroclip_test::six_tet_box(1, 1, 0.02, "plate");
  o = voroclip_test::small_options(150);
  o.max_shape_retries = 0;
  const voroclip::Mesh3Result once = voroclip::mesh3d(thicker, o);
  CHECK(once.topology_capped);
  CHECK(once.topology_capped_vertices == Approx(625).epsilon(3e-3));
  o.max_shape_retries = 2;
  const voroclip::Mesh3Result t = voroclip::mesh3d(thicker, o);
  CHECK_FALSE(t.shape_retries_skipped);
  CHECK(t.shape_retries > 0);
}
