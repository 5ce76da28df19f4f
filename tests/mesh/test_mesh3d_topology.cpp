// Tests of the topology refinement's choice of new sites (mesh3d_pipeline.h,
// refinement_points): one per bad cell at its farthest point, farthest first, none closer
// than half its radius to one taken in the same round (the skull's flat boundary tets of
// issue 30 came from pairs of new sites 2.6e-5 apart).
#include <catch2/catch.hpp>

#include <array>
#include <cstdint>
#include <vector>

#include "mesh3d_pipeline.h"
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

}  // namespace

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
