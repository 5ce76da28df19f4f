// first_intersecting_pair against CGAL (tests only; the only surface-intersection test that
// includes CGAL). The oracle is CGAL's exact triangle-triangle intersection (Epeck): for
// triangles without a common vertex, do_intersect; for triangles with common vertices, the
// intersection is constructed and must be more than what they share (more than the point v
// for one common vertex, more than the segment uv for a common edge) to count. Random pairs
// and random soups in small integer grids, where coplanar, collinear and touching
// configurations are the rule.
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/intersections.h>
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "surface_intersect.h"

using voroclip::detail::first_intersecting_pair;

namespace {

using K = CGAL::Exact_predicates_exact_constructions_kernel;
using Point = K::Point_3;
using Segment = K::Segment_3;
using Triangle = K::Triangle_3;

struct Soup {
  std::vector<double> xyz;
  std::vector<std::uint32_t> triangles;
  std::uint32_t nb_triangles() const { return static_cast<std::uint32_t>(triangles.size() / 3); }
  Point point(std::uint32_t v) const { return {xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]}; }
  Triangle triangle(std::uint32_t t) const {
    return {point(triangles[3 * t]), point(triangles[3 * t + 1]), point(triangles[3 * t + 2])};
  }
};

// Adds p to the soup unless a vertex has its coordinates (welded); returns its index.
std::uint32_t add_point(Soup& s, std::map<std::array<double, 3>, std::uint32_t>& index,
                        const std::array<double, 3>& p) {
  const auto next = static_cast<std::uint32_t>(index.size());
  const std::uint32_t v = index.emplace(p, next).first->second;
  if (v == next) s.xyz.insert(s.xyz.end(), p.begin(), p.end());
  return v;
}

// CGAL's answer: triangles a and b of s meet beyond what they share.
bool cgal_meet(const Soup& s, std::uint32_t a, std::uint32_t b, int* nb_shared = nullptr) {
  std::vector<std::uint32_t> common;
  for (std::uint32_t i = 0; i < 3; ++i) {
    for (std::uint32_t j = 0; j < 3; ++j) {
      if (s.triangles[3 * a + i] == s.triangles[3 * b + j]) {
        common.push_back(s.triangles[3 * a + i]);
      }
    }
  }
  if (nb_shared != nullptr) *nb_shared = static_cast<int>(common.size());
  const Triangle ta = s.triangle(a), tb = s.triangle(b);
  if (common.empty()) return CGAL::do_intersect(ta, tb);
  const auto inter = CGAL::intersection(ta, tb);
  const bool nonempty = static_cast<bool>(inter);
  REQUIRE(nonempty);  // they share a vertex at least
  if (common.size() == 1) {
    const Point* p = boost::get<Point>(&*inter);
    return p == nullptr || *p != s.point(common[0]);
  }
  REQUIRE(common.size() == 2);
  const Segment* e = boost::get<Segment>(&*inter);
  if (e == nullptr) return true;
  const Segment uv(s.point(common[0]), s.point(common[1]));
  return !(*e == uv || *e == uv.opposite());
}

// The first pair by CGAL, scanning all pairs.
std::pair<std::uint32_t, std::uint32_t> cgal_first(const Soup& s) {
  for (std::uint32_t a = 0; a < s.nb_triangles(); ++a) {
    for (std::uint32_t b = a + 1; b < s.nb_triangles(); ++b) {
      if (cgal_meet(s, a, b)) return {a, b};
    }
  }
  return {voroclip::detail::TrianglePair::kNone, voroclip::detail::TrianglePair::kNone};
}

}  // namespace

TEST_CASE("first_intersecting_pair: random triangle pairs against CGAL",
          "[clip][exact][degenerate][cgal]") {
  const std::uint64_t seed = 77031;
  std::mt19937_64 rng(seed);
  // counts[nb_shared][meet]
  std::array<std::array<int, 2>, 3> counts = {};
  for (int grid = 1; grid <= 4; ++grid) {
    std::uniform_int_distribution<int> coord(0, grid), share(0, 5), pick(0, 2), nudge(0, 2);
    for (int trial = 0; trial < 30000; ++trial) {
      INFO("seed " << seed << ", grid " << grid << ", trial " << trial);
      std::array<std::array<double, 3>, 6> p;
      for (auto& q : p) {
        for (double& x : q) x = coord(rng);
      }
      // In one trial out of four, coordinates moved by one ulp (with probability 1/3 each):
      // near-degenerate rather than degenerate, where the filters cannot decide.
      if (trial % 4 == 3) {
        for (auto& q : p) {
          for (double& x : q) {
            const int r = nudge(rng);
            if (r != 0) x = std::nextafter(x, r == 1 ? -HUGE_VAL : HUGE_VAL);
          }
        }
      }
      // Often make the second triangle reuse one or two corners of the first.
      const int nb_reused = std::min(share(rng), 3) % 3;
      for (int k = 0; k < nb_reused; ++k) {
        p[static_cast<std::size_t>(3 + k)] = p[static_cast<std::size_t>(pick(rng))];
      }
      Soup s;
      std::map<std::array<double, 3>, std::uint32_t> index;
      for (const auto& q : p) s.triangles.push_back(add_point(s, index, q));
      std::array<std::uint32_t, 3> a = {s.triangles[0], s.triangles[1], s.triangles[2]};
      std::array<std::uint32_t, 3> b = {s.triangles[3], s.triangles[4], s.triangles[5]};
      if (CGAL::collinear(s.point(a[0]), s.point(a[1]), s.point(a[2])) ||
          CGAL::collinear(s.point(b[0]), s.point(b[1]), s.point(b[2]))) {
        continue;  // zero area (or a repeated vertex): outside the preconditions
      }
      std::sort(a.begin(), a.end());
      std::sort(b.begin(), b.end());
      if (a == b) continue;
      int nb_shared = 0;
      const bool expected = cgal_meet(s, 0, 1, &nb_shared);
      const bool found = first_intersecting_pair(s.xyz, s.triangles).found();
      CHECK(found == expected);
      ++counts[static_cast<std::size_t>(nb_shared)][expected ? 1 : 0];
    }
  }
  // Every kind of pair, meeting and not, was met many times.
  for (const auto& kind : counts) {
    CHECK(kind[0] > 500);
    CHECK(kind[1] > 500);
  }
}

TEST_CASE("first_intersecting_pair: random triangle soups against a CGAL scan of all pairs",
          "[clip][exact][cgal]") {
  const std::uint64_t seed = 51423;
  std::mt19937_64 rng(seed);
  int nb_found = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const int grid = 3 + trial % 10;
    const auto n = static_cast<std::uint32_t>(2 + trial % 40);
    INFO("seed " << seed << ", trial " << trial << ", grid " << grid << ", " << n << " triangles");
    std::uniform_int_distribution<int> coord(0, grid), delta(-2, 2);
    Soup s;
    std::map<std::array<double, 3>, std::uint32_t> index;
    std::set<std::array<std::uint32_t, 3>> seen;
    while (s.nb_triangles() < n) {
      std::array<std::array<double, 3>, 3> p;
      for (double& x : p[0]) x = coord(rng);
      for (std::size_t k = 1; k < 3; ++k) {
        for (std::size_t j = 0; j < 3; ++j) {
          p[k][j] = std::clamp(p[0][j] + delta(rng), 0.0, static_cast<double>(grid));
        }
      }
      if (CGAL::collinear(Point(p[0][0], p[0][1], p[0][2]), Point(p[1][0], p[1][1], p[1][2]),
                          Point(p[2][0], p[2][1], p[2][2]))) {
        continue;
      }
      std::array<std::uint32_t, 3> t;
      for (std::size_t k = 0; k < 3; ++k) t[k] = add_point(s, index, p[k]);
      std::array<std::uint32_t, 3> sorted = t;
      std::sort(sorted.begin(), sorted.end());
      if (!seen.insert(sorted).second) continue;
      s.triangles.insert(s.triangles.end(), t.begin(), t.end());
    }
    const auto expected = cgal_first(s);
    const voroclip::detail::TrianglePair got = first_intersecting_pair(s.xyz, s.triangles);
    CHECK(std::make_pair(got.a, got.b) == expected);
    if (got.found()) ++nb_found;
  }
  CHECK(nb_found > 50);
  CHECK(nb_found < 190);
}
