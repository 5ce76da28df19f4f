// Cross-check of Delaunay2 against CGAL's Delaunay_triangulation_2 (tests only: CGAL is
// never linked by anything the project ships). On generic input the Delaunay triangulation
// is unique, so the two must agree triangle for triangle; on degenerate input they may
// choose different diagonals but have the same number of triangles.
#include <catch2/catch.hpp>
#include <tbb/global_control.h>

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "tet_set.h"
#include "voroclip/delaunay.h"

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<std::uint32_t, Kernel>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase>;
using CgalDelaunay = CGAL::Delaunay_triangulation_2<Kernel, Tds>;
using Triangle = std::array<std::uint32_t, 3>;

// count coordinates uniform in [-1, 1).
std::vector<double> uniform_coordinates(std::size_t count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> c(count);
  for (double& x : c) x = u(rng);
  return c;
}

std::set<Triangle> cgal_triangles(const std::vector<double>& xy) {
  std::vector<std::pair<Kernel::Point_2, std::uint32_t>> points;
  for (std::uint32_t i = 0; 2 * i < xy.size(); ++i) {
    points.emplace_back(Kernel::Point_2(xy[2 * i], xy[2 * i + 1]), i);
  }
  CgalDelaunay dt(points.begin(), points.end());
  std::set<Triangle> out;
  for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f) {
    Triangle t = {f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()};
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    out.insert(t);
  }
  return out;
}

std::set<Triangle> our_triangles(const voroclip::Delaunay2& d) {
  std::set<Triangle> out;
  for (std::uint32_t t = 0; t < d.nb_triangles(); ++t) {
    out.insert({d.tri_vertex(t, 0), d.tri_vertex(t, 1), d.tri_vertex(t, 2)});
  }
  return out;
}

}  // namespace

TEST_CASE("Delaunay2 equals CGAL on random points", "[delaunay][cgal]") {
  for (const std::uint64_t seed : {1u, 2u, 3u, 4u}) {
    CAPTURE(seed);
    const std::vector<double> xy = uniform_coordinates(2 * 10000, seed);
    const voroclip::Delaunay2 d(xy.data(), 10000);
    REQUIRE(d.check_topology().empty());
    REQUIRE(d.check_delaunay().empty());
    REQUIRE(our_triangles(d) == cgal_triangles(xy));
  }
}

TEST_CASE("Delaunay2 built in strips equals CGAL", "[delaunay][cgal][parallel]") {
  // Small rounds in strips, the strips' tasks on two threads: most points go through them
  // and some are deferred at strip boundaries; the result must still be CGAL's.
  voroclip::Delaunay2::Options options;
  options.zones = 3;
  options.zoned_round = 1024;
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
  for (const std::uint64_t seed : {606u, 707u}) {
    CAPTURE(seed);
    const std::vector<double> xy = uniform_coordinates(2 * 20000, seed);
    const voroclip::Delaunay2 d(xy.data(), 20000, options);
    REQUIRE(d.stats().zoned_points > 15000);
    REQUIRE(d.stats().deferred_points > 0);
    REQUIRE(d.check_topology().empty());
    REQUIRE(d.check_delaunay().empty());
    REQUIRE(our_triangles(d) == cgal_triangles(xy));
  }
}

TEST_CASE("Delaunay2 and CGAL count the same triangles on degenerate sets",
          "[delaunay][cgal][degenerate]") {
  std::vector<double> xy;
  for (int i = 0; i < 30; ++i) {
    for (int j = 0; j < 30; ++j)
      xy.insert(xy.end(), {static_cast<double>(i), static_cast<double>(j)});
  }
  for (int i = 0; i < 200; ++i)
    xy.insert(xy.end(), {static_cast<double>(i % 30), static_cast<double>((7 * i) % 30)});
  const voroclip::Delaunay2 d(xy.data(), static_cast<std::uint32_t>(xy.size() / 2));
  REQUIRE(d.check_topology().empty());
  REQUIRE(d.check_delaunay().empty());
  REQUIRE(d.nb_vertices() == 900);
  REQUIRE(d.nb_triangles() == cgal_triangles(xy).size());
}

namespace {

using VertexBase3 = CGAL::Triangulation_vertex_base_with_info_3<std::uint32_t, Kernel>;
using Tds3 = CGAL::Triangulation_data_structure_3<VertexBase3,
                                                  CGAL::Delaunay_triangulation_cell_base_3<Kernel>>;
using CgalDelaunay3 = CGAL::Delaunay_triangulation_3<Kernel, Tds3>;
using voroclip::test::Tet;

std::vector<Tet> cgal_tets(const std::vector<double>& xyz) {
  std::vector<std::pair<Kernel::Point_3, std::uint32_t>> input;
  for (std::uint32_t i = 0; i < xyz.size() / 3; ++i) {
    input.emplace_back(Kernel::Point_3(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]), i);
  }
  const CgalDelaunay3 dt(input.begin(), input.end());
  std::vector<Tet> out;
  for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c) {
    Tet v = {c->vertex(0)->info(), c->vertex(1)->info(), c->vertex(2)->info(),
             c->vertex(3)->info()};
    std::sort(v.begin(), v.end());
    out.push_back(v);
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

TEST_CASE("Delaunay3 equals CGAL on random points", "[delaunay][cgal]") {
  for (const std::uint64_t seed : {101u, 202u, 303u}) {
    INFO("seed " << seed);
    const std::vector<double> xyz = uniform_coordinates(3 * 10000, seed);
    const voroclip::Delaunay3 dt(xyz.data(), 10000);
    REQUIRE(dt.check_topology().empty());
    REQUIRE(dt.check_delaunay().empty());
    CHECK(voroclip::test::finite_tets(dt) == cgal_tets(xyz));
  }
}

TEST_CASE("Delaunay3 built in parallel zones equals CGAL", "[delaunay][cgal][parallel]") {
  // Small zones: most points go through the parallel passes and many are deferred at zone
  // boundaries; the result must still be CGAL's Delaunay triangulation.
  voroclip::Delaunay3::Options options;
  options.points_per_zone = 256;
  for (const std::uint64_t seed : {404u, 505u}) {
    INFO("seed " << seed);
    const std::vector<double> xyz = uniform_coordinates(3 * 10000, seed);
    const voroclip::Delaunay3 dt(xyz.data(), 10000, options);
    REQUIRE(dt.stats().zoned_points > 5000);
    REQUIRE(dt.check_topology().empty());
    REQUIRE(dt.check_delaunay().empty());
    CHECK(voroclip::test::finite_tets(dt) == cgal_tets(xyz));
  }
}
