// ClippedVoronoi3::compute(domain, sites, n) with fewer than 4 affinely independent sites
// (clip.h, nb_auxiliary_sites): one site has the whole domain; sites on a line cut it into
// slabs at the midpoints; sites in a plane make prisms over their 2D Voronoi cells, checked
// against ClippedVoronoi2 of the same sites in the box's cross-section.
#include <catch2/catch.hpp>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "support/surfaces.h"
#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/delaunay.h"

using voroclip::ClippedVoronoi2;
using voroclip::ClippedVoronoi3;
using voroclip::Domain3;

namespace {

ClippedVoronoi3 clip(const Domain3& domain, const std::vector<double>& sites) {
  ClippedVoronoi3 cv;
  cv.compute(domain, sites.data(), static_cast<std::uint32_t>(sites.size() / 3));
  REQUIRE(cv.nb_sites() == sites.size() / 3);
  return cv;
}

}  // namespace

TEST_CASE("clip3d: one site has the whole domain", "[clip][degenerate]") {
  const Domain3 box(voroclip_test::box_surface({0, 0, 0}, {1, 2, 3}));
  const ClippedVoronoi3 cv = clip(box, {0.25, 0.5, 2.5});
  CHECK(cv.nb_auxiliary_sites() == 4);
  CHECK(std::fabs(cv.volume(0) - 6) <= 1e-12 * 6);
  CHECK(std::fabs(cv.centroid(0)[0] - 0.5) <= 1e-12);
  CHECK(std::fabs(cv.centroid(0)[1] - 1) <= 1e-12);
  CHECK(std::fabs(cv.centroid(0)[2] - 1.5) <= 1e-12);
  CHECK(cv.is_boundary(0));
  CHECK(std::fabs(cv.surface_area(0) - 22) <= 1e-12 * 22);
  // The same site repeated: the first has the cell.
  const ClippedVoronoi3 twice = clip(box, {0.25, 0.5, 2.5, 0.25, 0.5, 2.5});
  CHECK(std::fabs(twice.volume(0) - 6) <= 1e-12 * 6);
  CHECK(twice.volume(1) == 0);
  // A site outside, alone: it is still the nearest site of every point.
  const ClippedVoronoi3 outside = clip(box, {5, 5, 5});
  CHECK(std::fabs(outside.volume(0) - 6) <= 1e-12 * 6);
  // A closed surface that is not a box: the sphere.
  const Domain3 sphere(
      voroclip::read_surface(std::string(VOROCLIP_SHARED_DATA_DIR) + "/surfaces/sphere.obj"));
  const ClippedVoronoi3 s = clip(sphere, {0.1, 0.2, 0.3});
  CHECK(std::fabs(s.volume(0) - sphere.volume()) <= 1e-12 * sphere.volume());
}

TEST_CASE("clip3d: sites on a line make slabs", "[clip][degenerate]") {
  const Domain3 box(voroclip_test::box_surface({0, 0, 0}, {1, 1, 1}));
  // Along x: the bisectors are x = 0.15 and x = 0.45.
  const ClippedVoronoi3 cv = clip(box, {0.1, 0.5, 0.5, 0.2, 0.5, 0.5, 0.7, 0.5, 0.5});
  CHECK(cv.nb_auxiliary_sites() == 4);
  CHECK(std::fabs(cv.volume(0) - 0.15) <= 1e-12);
  CHECK(std::fabs(cv.volume(1) - 0.30) <= 1e-12);
  CHECK(std::fabs(cv.volume(2) - 0.55) <= 1e-12);
  CHECK(std::fabs(cv.centroid(2)[0] - (0.45 + 1) / 2) <= 1e-12);
  CHECK(std::fabs(cv.total_volume() - 1) <= 1e-12);
  // Two sites on a diagonal through the box's centre: the bisector plane through the
  // centre halves it.
  const ClippedVoronoi3 two = clip(box, {0.2, 0.3, 0.1, 0.8, 0.7, 0.9});
  CHECK(std::fabs(two.volume(0) - 0.5) <= 1e-12);
  CHECK(std::fabs(two.volume(1) - 0.5) <= 1e-12);
  // Nearest-site probes: the centroid of each half is nearer its own site.
  for (std::uint32_t i = 0; i < 2; ++i) {
    const double* c = two.centroid(i);
    const double d0 = std::hypot(c[0] - 0.2, std::hypot(c[1] - 0.3, c[2] - 0.1));
    const double d1 = std::hypot(c[0] - 0.8, std::hypot(c[1] - 0.7, c[2] - 0.9));
    CHECK((i == 0 ? d0 < d1 : d1 < d0));
  }
}

TEST_CASE("clip3d: coplanar sites make prisms over their 2D cells", "[clip][degenerate]") {
  // The box [0, 1]^2 x [0, 2]; sites in the plane z = 0.7: cell i is its 2D cell in the
  // unit square times the height 2.
  const Domain3 box(voroclip_test::box_surface({0, 0, 0}, {1, 1, 2}));
  const std::uint64_t seed = 11;
  INFO("seed " << seed);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.05, 0.95);
  const std::uint32_t n = 60;
  std::vector<double> xy, xyz;
  for (std::uint32_t i = 0; i < n; ++i) {
    const double x = u(rng), y = u(rng);
    xy.insert(xy.end(), {x, y});
    xyz.insert(xyz.end(), {x, y, 0.7});
  }
  // A duplicate in the plane, too.
  xy.insert(xy.end(), {xy[0], xy[1]});
  xyz.insert(xyz.end(), {xyz[0], xyz[1], xyz[2]});
  const ClippedVoronoi3 cv = clip(box, xyz);
  CHECK(cv.nb_auxiliary_sites() == 2);
  voroclip::PolygonRings square;
  square.source = "square";
  square.xy = {0, 0, 1, 0, 1, 1, 0, 1};
  square.ring_begin = {0, 4};
  square.ring_polygon = {0};
  square.ring_line = {0};
  const voroclip::Domain2 domain2(square);
  const voroclip::Delaunay2 dt(xy.data(), n + 1);
  ClippedVoronoi2 cv2;
  cv2.compute(domain2, dt);
  for (std::uint32_t i = 0; i <= n; ++i) {
    CHECK(std::fabs(cv.volume(i) - 2 * cv2.area(i)) <= 1e-12);
    CHECK(std::fabs(cv.centroid(i)[0] - cv2.centroid(i)[0]) <= 1e-9);
    CHECK(std::fabs(cv.centroid(i)[2] - (cv.volume(i) > 0 ? 1.0 : 0.7)) <= 1e-9);
  }
  CHECK(cv.volume(n) == 0);
  CHECK(std::fabs(cv.total_volume() - 2) <= 1e-12 * 2);
  // Geometry: the neighbour pairs are the 2D ones, with areas = lengths x 2.
  ClippedVoronoi3 g;
  voroclip::Clip3Options o;
  o.keep_geometry = true;
  g.compute(box, xyz.data(), n + 1, o);
  ClippedVoronoi2 g2;
  voroclip::Clip2Options o2;
  o2.keep_geometry = true;
  g2.compute(domain2, dt, o2);
  const voroclip::NeighborTable t3 = voroclip::cell_neighbors(g);
  const voroclip::NeighborTable t2 = voroclip::cell_neighbors(g2);
  CHECK(t3.pairs == t2.pairs);
  if (t3.pairs == t2.pairs) {
    for (std::uint32_t r = 0; r < t3.nb_pairs(); ++r) {
      CHECK(std::fabs(t3.measure[r] - 2 * t2.measure[r]) <= 1e-9);
    }
  }
}

TEST_CASE("clip3d: coplanar sites give the same bits with 1 and 2 threads",
          "[clip][degenerate][threads]") {
  const Domain3 sphere(
      voroclip::read_surface(std::string(VOROCLIP_SHARED_DATA_DIR) + "/surfaces/sphere.obj"));
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-0.6, 0.6);
  std::vector<double> sites;
  for (int i = 0; i < 500; ++i) sites.insert(sites.end(), {u(rng), u(rng), 0.25});
  std::vector<double> volumes[2];
  for (int threads = 1; threads <= 2; ++threads) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                    static_cast<std::size_t>(threads));
    const ClippedVoronoi3 cv = clip(sphere, sites);
    for (std::uint32_t i = 0; i < cv.nb_sites(); ++i) volumes[threads - 1].push_back(cv.volume(i));
    CHECK(std::fabs(cv.total_volume() - sphere.volume()) <= 1e-12 * sphere.volume());
  }
  CHECK(volumes[0] == volumes[1]);
}
