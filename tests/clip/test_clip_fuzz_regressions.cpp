// Findings of fuzz_sites (fuzz/sites/fuzz_sites.cpp: small site sets through Delaunay2/3 and
// ClippedVoronoi2/3) on the engine's constructions: each input, decoded from the fuzzer's
// bytes (kept as seeds in fuzz/seeds/fuzz_sites/, so that every fuzz run checks them again),
// in tests/clip/fuzz_regressions/, with the facts it must satisfy.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "support/surfaces.h"
#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/delaunay.h"

namespace {

const std::string kDir = std::string(VOROCLIP_SOURCE_DIR) + "/tests/clip/fuzz_regressions/";

}  // namespace

TEST_CASE("fuzz regression: clip3d facet point of two bisectors of nearly coincident sites",
          "[clip][regression][degenerate]") {
  // Four sites within 4e-12 of (0.875, 0.875, 0.875), the others far. A vertex of the
  // restricted surface on the face y = 0 is that plane ∩ bisector(2, 7) ∩ bisector(2, 13),
  // sites 7 and 13 2.9e-14 apart: the two bisectors meet at an angle of 2.9e-14, and the
  // floating-point solve of Clip3Context::facet_point put the point 1.3e-3 from the exact
  // one (x 0.87631 instead of 0.875 + 1.5e-14). Site 13's cell came out at -2.265e-4
  // (exactly 3.4e-6), the tet-by-tet clipping, which shares the point, at -2.229e-4.
  const std::vector<double> sites =
      voroclip::read_points(kDir + "clip3d_near_coincident_facet_point.xyz", 3);
  const auto n = static_cast<std::uint32_t>(sites.size() / 3);
  REQUIRE(n == 18);
  // The exact volumes: the cells as intersections of the cube with the half-spaces of the
  // bisectors, vertices and volumes in rational arithmetic (Python fractions), rounded;
  // -1 for a duplicate (no cell: volume 0).
  const double exact[18] = {0.20461125523438817,
                            0.012939619588935162,
                            0.2020425385303511,
                            0.00010172526041258029,
                            -1,
                            -1,
                            0.06763365622863544,
                            0.4007776632042946,
                            -1,
                            -1,
                            -1,
                            -1,
                            0.08070117556036126,
                            3.4015490363881316e-06,
                            0.031188964843585344,
                            0,
                            -1,
                            -1};
  voroclip::Delaunay3 dt;
  dt.build(sites.data(), n);
  REQUIRE(dt.check_topology().empty());
  const voroclip::Domain3 cube(voroclip_test::box_surface({0, 0, 0}, {1, 1, 1}));
  voroclip::ClippedVoronoi3 cv;
  cv.compute(cube, dt);
  REQUIRE(cv.nb_sites() == n);
  double sum = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    INFO("site " << i << ": volume " << cv.volume(i) << ", exactly " << exact[i]);
    const double want = exact[i] < 0 ? 0 : exact[i];
    CHECK(std::fabs(cv.volume(i) - want) <= 1e-12);
    sum += cv.volume(i);
  }
  CHECK(std::fabs(sum - 1) <= 1e-12);
  CHECK(std::fabs(cv.volume(13) - exact[13]) <= 1e-9 * exact[13]);
  // compute(domain, sites, n) (its own, Hilbert-ordered triangulation) agrees.
  voroclip::ClippedVoronoi3 cs;
  cs.compute(cube, sites.data(), n);
  for (std::uint32_t i = 0; i < n; ++i) {
    INFO("site " << i);
    CHECK(std::fabs(cs.volume(i) - cv.volume(i)) <= 1e-12);
  }
}

TEST_CASE("fuzz regression: clip2d Voronoi vertex of sites 2.7e-48 apart",
          "[clip][regression][degenerate]") {
  // Seven sites within 6.3e-13 of the corner (0, 0), sites 3 and 6 2.7e-48 apart, at
  // 2.9e-28 from site 1: the plain circumcentre formula of Delaunay2::circumcenter had a
  // determinant of rounding noise and gave NaN Voronoi vertices, so NaN cell areas.
  const std::vector<double> sites = voroclip::read_points(kDir + "clip2d_nan_voronoi_vertex.xy", 2);
  const auto n = static_cast<std::uint32_t>(sites.size() / 2);
  REQUIRE(n == 7);
  voroclip::Delaunay2 dt;
  dt.build(sites.data(), n);
  REQUIRE(dt.check_topology().empty());
  for (std::uint32_t t = 0; t < dt.nb_triangles(); ++t) {
    double c[2];
    dt.circumcenter(t, c);
    INFO("triangle " << t);
    CHECK(std::isfinite(c[0]));
    CHECK(std::isfinite(c[1]));
  }
  voroclip::PolygonRings p;
  p.source = "square with hole";
  p.xy = {0, 0, 1, 0, 1, 1, 0, 1, 0.375, 0.375, 0.375, 0.625, 0.625, 0.625, 0.625, 0.375};
  p.ring_begin = {0, 4, 8};
  p.ring_polygon = {0, 0};
  p.ring_line = {0, 0};
  const voroclip::Domain2 domain(p);
  voroclip::ClippedVoronoi2 cv;
  voroclip::Clip2Options options;
  options.keep_geometry = true;
  cv.compute(domain, dt, options);
  REQUIRE(cv.nb_sites() == n);
  for (const double x : cv.vertex_coords()) CHECK(std::isfinite(x));
  double sum = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    INFO("site " << i << ": area " << cv.area(i));
    CHECK(cv.area(i) >= 0);
    sum += cv.area(i);
  }
  CHECK(std::fabs(sum - domain.area()) <= 1e-12 * domain.area());
  // Site 1's cell: the strip under bisector(0, 1), y = (c - a x) / b from x = 0 to 1 (sites
  // 0 and 4 at height 6.2e-13, the others below 4.5e-27), less the cells of the others (below
  // 3e-24 in all): the strip's area, exactly (rationals), is 2.427451956853106e-13.
  CHECK(std::fabs(cv.area(1) - 2.427451956853106e-13) <= 1e-9 * 2.427451956853106e-13);
}
