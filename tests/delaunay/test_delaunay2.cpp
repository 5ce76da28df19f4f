// Tests of Delaunay2 (voroclip/delaunay.h). Every triangulation built here goes through
// check_topology() and check_delaunay() (exact, with the symbolic perturbation); counts are
// checked against the exact formula 2n' - b - 2 (n' distinct points, b on the hull).
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "spatial_sort.h"
#include "support/threads.h"
#include "voroclip/core.h"
#include "voroclip/delaunay.h"
#include "voroclip/predicates.h"
#include "with_threads.h"

using voroclip::Delaunay2;
using voroclip::Sign;

namespace {

using Triangle = std::array<std::uint32_t, 3>;

std::vector<double> random_points(std::uint32_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> xy(2 * static_cast<std::size_t>(n));
  for (double& x : xy) x = u(rng);
  return xy;
}

void require_valid(const Delaunay2& d) {
  const std::string topology = d.check_topology();
  INFO("check_topology: " << topology);
  REQUIRE(topology.empty());
  const std::string delaunay = d.check_delaunay();
  INFO("check_delaunay: " << delaunay);
  REQUIRE(delaunay.empty());
  // The exact count: 2n' - b - 2 finite triangles, b infinite ones.
  const auto b = static_cast<std::uint32_t>(d.hull_vertices().size());
  REQUIRE(d.nb_triangle_slots() - d.nb_triangles() == b);
  REQUIRE(d.nb_triangles() == 2 * d.nb_vertices() - b - 2);
}

std::vector<Triangle> finite_triangles(const Delaunay2& d) {
  std::vector<Triangle> out;
  for (std::uint32_t t = 0; t < d.nb_triangles(); ++t) {
    out.push_back({d.tri_vertex(t, 0), d.tri_vertex(t, 1), d.tri_vertex(t, 2)});
  }
  return out;
}

// Number of distinct points on the boundary of the convex hull, by brute force: a point is
// on it iff it lies on a supporting line through two distinct points.
std::uint32_t brute_force_hull_count(const std::vector<double>& xy,
                                     const std::vector<std::uint32_t>& ids) {
  const auto p = [&xy](std::uint32_t i) { return &xy[2 * static_cast<std::size_t>(i)]; };
  std::set<std::uint32_t> on_hull;
  for (const std::uint32_t u : ids) {
    for (const std::uint32_t w : ids) {
      if (u == w) continue;
      bool supporting = true;
      for (const std::uint32_t x : ids) {
        if (voroclip::orient2d(p(u), p(w), p(x)) == Sign::negative) {
          supporting = false;
          break;
        }
      }
      if (!supporting) continue;
      for (const std::uint32_t x : ids) {
        if (voroclip::orient2d(p(u), p(w), p(x)) == Sign::zero) on_hull.insert(x);
      }
    }
  }
  return static_cast<std::uint32_t>(on_hull.size());
}

}  // namespace

TEST_CASE("Delaunay2 on uniform random points", "[delaunay]") {
  for (const std::uint32_t n : {3u, 4u, 10u, 100u, 1000u, 10000u}) {
    for (const std::uint64_t seed : {1u, 2u, 3u}) {
      CAPTURE(n, seed);
      const std::vector<double> xy = random_points(n, seed);
      const Delaunay2 d(xy.data(), n);
      REQUIRE(d.nb_vertices() == n);
      require_valid(d);
    }
  }
  const std::vector<double> xy = random_points(100000, 42);
  const Delaunay2 d(xy.data(), 100000);
  require_valid(d);
}

TEST_CASE("Delaunay2 on an integer grid", "[delaunay][degenerate]") {
  std::vector<double> xy;
  for (int i = 0; i < 50; ++i) {
    for (int j = 0; j < 50; ++j) {
      xy.push_back(j);
      xy.push_back(i);
    }
  }
  const Delaunay2 d(xy.data(), 2500);
  require_valid(d);
  REQUIRE(d.hull_vertices().size() == 196);
  REQUIRE(d.nb_triangles() == 2 * 2500 - 196 - 2);
  // Every triangle of a unit grid is half a unit square: twice its area is exactly 1.
  for (const Triangle& t : finite_triangles(d)) {
    const double* a = d.point(t[0]);
    const double* b = d.point(t[1]);
    const double* c = d.point(t[2]);
    REQUIRE((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) == 1.0);
  }
}

TEST_CASE("Delaunay2 on cocircular integer points", "[delaunay][degenerate]") {
  // x^2 + y^2 = 325^2 = 5^4 13^2 has many integer solutions.
  std::vector<double> xy;
  const long r = 325;
  for (long x = -r; x <= r; ++x) {
    for (long y = -r; y <= r; ++y) {
      if (x * x + y * y == r * r) {
        xy.push_back(static_cast<double>(x));
        xy.push_back(static_cast<double>(y));
      }
    }
  }
  const auto m = static_cast<std::uint32_t>(xy.size() / 2);
  REQUIRE(m > 40);
  SECTION("without the centre: a fan of m - 2 triangles") {
    const Delaunay2 d(xy.data(), m);
    require_valid(d);
    REQUIRE(d.hull_vertices().size() == m);
    REQUIRE(d.nb_triangles() == m - 2);
  }
  SECTION("with the centre: m triangles around it") {
    xy.push_back(0);
    xy.push_back(0);
    const Delaunay2 d(xy.data(), m + 1);
    require_valid(d);
    REQUIRE(d.nb_triangles() == m);
    std::vector<std::uint32_t> around;
    d.vertex_neighbors(m, around);
    REQUIRE(around.size() == m);
  }
}

TEST_CASE("Delaunay2 puts collinear hull points on hull edges", "[delaunay][degenerate]") {
  // A triangle with 10 points on each side and a few inside.
  std::vector<double> xy;
  for (int i = 0; i < 10; ++i) {
    xy.insert(xy.end(), {static_cast<double>(i), 0.0});
    xy.insert(xy.end(), {10.0 - i, static_cast<double>(i)});
    xy.insert(xy.end(), {0.0, 10.0 - i});
  }
  xy.insert(xy.end(), {1, 1, 2, 3, 3, 2, 4, 4});
  const auto n = static_cast<std::uint32_t>(xy.size() / 2);
  const Delaunay2 d(xy.data(), n);
  require_valid(d);
  REQUIRE(d.hull_vertices().size() == 30);
  REQUIRE(d.nb_triangles() == 2 * n - 30 - 2);
  // The hull is counter-clockwise and starts at its smallest vertex.
  const std::vector<std::uint32_t> hull = d.hull_vertices();
  REQUIRE(hull.front() == *std::min_element(hull.begin(), hull.end()));
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const double* a = d.point(hull[i]);
    const double* b = d.point(hull[(i + 1) % hull.size()]);
    const double* c = d.point(hull[(i + 2) % hull.size()]);
    REQUIRE(voroclip::orient2d(a, b, c) != Sign::negative);
  }
}

TEST_CASE("Delaunay2 rejects degenerate inputs", "[delaunay][degenerate]") {
  const double xy[] = {0, 0, 1, 1, 2, 2, 3, 3, 4, 4};
  for (const std::uint32_t n : {0u, 1u, 2u}) {
    CAPTURE(n);
    REQUIRE_THROWS_AS(Delaunay2(xy, n), voroclip::Error);
  }
  REQUIRE_THROWS_WITH(Delaunay2(xy, 5), Catch::Contains("collinear"));
  const double same[] = {1, 2, 1, 2, 1, 2, 1, 2};
  REQUIRE_THROWS_WITH(Delaunay2(same, 4), Catch::Contains("coincide"));
  const double two_distinct[] = {1, 2, 3, 4, 1, 2, 3, 4, 1, 2};
  REQUIRE_THROWS_WITH(Delaunay2(two_distinct, 5), Catch::Contains("collinear"));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const double bad1[] = {0, 0, 1, 0, 0, nan, 1, 1};
  REQUIRE_THROWS_WITH(Delaunay2(bad1, 4), Catch::Contains("point 2"));
  const double bad2[] = {0, 0, 1, 0, 0, 1, -inf, 1};
  REQUIRE_THROWS_WITH(Delaunay2(bad2, 4), Catch::Contains("point 3"));
}

TEST_CASE("Delaunay2 on three and four points", "[delaunay][degenerate]") {
  const double tri[] = {0, 0, 0, 1, 1, 0};  // clockwise as given
  const Delaunay2 d(tri, 3);
  require_valid(d);
  REQUIRE(d.nb_triangles() == 1);
  REQUIRE(finite_triangles(d)[0] == Triangle{0, 2, 1});
  // A duplicate of the fourth point and a collinear one.
  const double four[] = {0, 0, 2, 0, 1, 2, 0, 0, 1, 0};
  const Delaunay2 e(four, 5);
  require_valid(e);
  REQUIRE(e.nb_vertices() == 4);
  REQUIRE(e.duplicate_of(3) == 0);
  REQUIRE(e.nb_triangles() == 2);
}

TEST_CASE("Delaunay2 reports duplicates", "[delaunay][degenerate]") {
  for (const std::uint64_t seed : {1u, 2u, 3u, 4u}) {
    CAPTURE(seed);
    // 300 distinct points, each repeated at 1 to 4 random indices.
    const std::vector<double> base = random_points(300, seed);
    std::mt19937_64 rng(seed);
    std::vector<std::uint32_t> source;
    for (std::uint32_t i = 0; i < 300; ++i) {
      const auto copies = 1 + rng() % 4;
      for (std::uint64_t c = 0; c < copies; ++c) source.push_back(i);
    }
    std::shuffle(source.begin(), source.end(), rng);
    std::vector<double> xy;
    std::vector<std::uint32_t> first(300, Delaunay2::kNone);
    for (std::uint32_t i = 0; i < source.size(); ++i) {
      xy.push_back(base[2 * source[i]]);
      xy.push_back(base[2 * source[i] + 1]);
      first[source[i]] = std::min(first[source[i]], i);
    }
    const auto n = static_cast<std::uint32_t>(source.size());
    const Delaunay2 d(xy.data(), n);
    require_valid(d);
    REQUIRE(d.nb_unique_points() == 300);
    for (std::uint32_t i = 0; i < n; ++i) REQUIRE(d.duplicate_of(i) == first[source[i]]);
    // Same triangulation as the distinct points alone, up to the labels: compare with the
    // distinct points listed in the order of their first occurrence.
    std::vector<double> unique_xy;
    std::vector<std::uint32_t> label;
    for (std::uint32_t i = 0; i < n; ++i) {
      if (d.duplicate_of(i) == i) {
        label.push_back(i);
        unique_xy.insert(unique_xy.end(), {xy[2 * i], xy[2 * i + 1]});
      }
    }
    const Delaunay2 u(unique_xy.data(), 300);
    std::set<Triangle> expected, got;
    for (Triangle t : finite_triangles(u)) {
      for (auto& v : t) v = label[v];
      std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
      expected.insert(t);
    }
    for (const Triangle& t : finite_triangles(d)) got.insert(t);
    REQUIRE(got == expected);
  }
}

TEST_CASE("Delaunay2 is invariant under scaling by powers of two", "[delaunay][exact]") {
  std::vector<double> xy = random_points(500, 9);
  for (int i = 0; i < 20; ++i) {
    for (int j = 0; j < 20; ++j) xy.insert(xy.end(), {i / 19.0, j / 19.0});
  }
  const auto n = static_cast<std::uint32_t>(xy.size() / 2);
  const Delaunay2 reference(xy.data(), n);
  require_valid(reference);
  for (int e = -40; e <= 40; e += 8) {
    CAPTURE(e);
    std::vector<double> scaled = xy;
    for (double& x : scaled) x = std::ldexp(x, e);
    const Delaunay2 d(scaled.data(), n);
    require_valid(d);
    REQUIRE(d.tri_vertices() == reference.tri_vertices());
    REQUIRE(d.tri_neighbors() == reference.tri_neighbors());
  }
}

TEST_CASE("Delaunay2 on the vertices of the sample polygons", "[delaunay]") {
  const std::string dir = std::string(VOROCLIP_SHARED_DATA_DIR) + "/polygons/valid/";
  for (const char* name : {"building", "dude", "earcut", "eberly-6", "hilbert", "issue29",
                           "issue34", "issue35", "issue52"}) {
    CAPTURE(name);
    std::ifstream in(dir + name + ".json");
    REQUIRE(in.good());
    const nlohmann::json rings = nlohmann::json::parse(in);
    std::vector<double> xy;
    for (const auto& ring : rings) {
      for (const auto& p : ring) {
        xy.push_back(p.at(0).get<double>());
        xy.push_back(p.at(1).get<double>());
      }
    }
    const Delaunay2 d(xy.data(), static_cast<std::uint32_t>(xy.size() / 2));
    require_valid(d);
  }
}

TEST_CASE("Delaunay2 equals the brute-force triangulation on small sets", "[delaunay][exact]") {
  // Small coordinate ranges make many collinear and cocircular quadruples and duplicates.
  for (std::uint64_t seed = 1; seed <= 60; ++seed) {
    std::mt19937_64 rng(seed);
    const auto n = static_cast<std::uint32_t>(4 + rng() % 37);
    const int range = seed % 3 == 0 ? 1000000 : static_cast<int>(3 + seed % 5);
    std::vector<double> xy;
    for (std::uint32_t i = 0; i < 2 * n; ++i)
      xy.push_back(static_cast<double>(rng() % static_cast<std::uint64_t>(range)));
    CAPTURE(seed, n, range);
    const auto p = [&xy](std::uint32_t i) { return &xy[2 * static_cast<std::size_t>(i)]; };
    // Not enough affinely independent points: skip (the error is tested elsewhere).
    bool independent = false;
    for (std::uint32_t k = 2; k < n && !independent; ++k) {
      for (std::uint32_t j = 1; j < k && !independent; ++j) {
        for (std::uint32_t i = 0; i < j && !independent; ++i) {
          independent = voroclip::orient2d(p(i), p(j), p(k)) != Sign::zero;
        }
      }
    }
    if (!independent) {
      REQUIRE_THROWS_AS(Delaunay2(xy.data(), n), voroclip::Error);
      continue;
    }
    const Delaunay2 d(xy.data(), n);
    require_valid(d);
    std::vector<std::uint32_t> ids;
    for (std::uint32_t i = 0; i < n; ++i) {
      std::uint32_t first = i;
      for (std::uint32_t j = 0; j < i; ++j) {
        if (p(j)[0] == p(i)[0] && p(j)[1] == p(i)[1]) {
          first = j;
          break;
        }
      }
      REQUIRE(d.duplicate_of(i) == first);
      if (first == i) ids.push_back(i);
    }
    // Every ccw triple with a perturbed-empty circumcircle, rotated to its smallest vertex.
    std::set<Triangle> expected;
    for (const std::uint32_t a : ids) {
      for (const std::uint32_t b : ids) {
        for (const std::uint32_t c : ids) {
          if (!(a < b && a < c && b != c)) continue;
          if (voroclip::orient2d(p(a), p(b), p(c)) != Sign::positive) continue;
          bool empty = true;
          for (const std::uint32_t q : ids) {
            if (q == a || q == b || q == c) continue;
            if (voroclip::incircle_sos(p(a), p(b), p(c), p(q), a, b, c, q) == Sign::positive) {
              empty = false;
              break;
            }
          }
          if (empty) expected.insert({a, b, c});
        }
      }
    }
    std::set<Triangle> got;
    for (const Triangle& t : finite_triangles(d)) {
      // Empty circle without the perturbation too (the triangulation refines Delaunay).
      for (const std::uint32_t q : ids) {
        if (q == t[0] || q == t[1] || q == t[2]) continue;
        REQUIRE(voroclip::incircle(p(t[0]), p(t[1]), p(t[2]), p(q)) != Sign::positive);
      }
      got.insert(t);
    }
    REQUIRE(got == expected);
    const std::uint32_t b = brute_force_hull_count(xy, ids);
    REQUIRE(d.hull_vertices().size() == b);
    REQUIRE(d.nb_triangles() == 2 * static_cast<std::uint32_t>(ids.size()) - b - 2);
  }
}

TEST_CASE("Delaunay2 queries", "[delaunay]") {
  const std::uint32_t n = 2000;
  const std::vector<double> xy = random_points(n, 17);
  const Delaunay2 d(xy.data(), n);
  require_valid(d);
  const auto p = [&xy](std::uint32_t i) { return &xy[2 * static_cast<std::size_t>(i)]; };

  SECTION("neighbours and incident triangles agree with the triangle list") {
    std::vector<std::set<std::uint32_t>> adjacent(n);
    std::vector<std::uint32_t> degree(n, 0);
    for (const Triangle& t : finite_triangles(d)) {
      for (int k = 0; k < 3; ++k) {
        adjacent[t[k]].insert(t[(k + 1) % 3]);
        adjacent[t[(k + 1) % 3]].insert(t[k]);
        ++degree[t[k]];
      }
    }
    std::vector<std::uint32_t> out;
    for (std::uint32_t v = 0; v < n; ++v) {
      d.vertex_neighbors(v, out);
      REQUIRE(std::set<std::uint32_t>(out.begin(), out.end()) == adjacent[v]);
      REQUIRE(out.size() == adjacent[v].size());
      d.triangles_around_vertex(v, out);
      REQUIRE(out.size() == degree[v]);
      REQUIRE(std::find(out.begin(), out.end(), d.vertex_triangle(v)) != out.end());
      for (std::size_t i = 0; i + 1 < out.size(); ++i) {
        // Counter-clockwise: consecutive triangles share the edge from v to the next one.
        const int k = d.local_index(out[i], v);
        REQUIRE(d.tri_adjacent(out[i], (k + 1) % 3) == out[i + 1]);
      }
      REQUIRE(d.is_hull_vertex(v) == (out.size() + 1 == adjacent[v].size()));
    }
  }
  SECTION("circumcenters are equidistant from the three vertices") {
    for (std::uint32_t t = 0; t < d.nb_triangles(); ++t) {
      double c[2];
      d.circumcenter(t, c);
      const auto r = [&](int k) {
        return std::hypot(d.point(d.tri_vertex(t, k))[0] - c[0],
                          d.point(d.tri_vertex(t, k))[1] - c[1]);
      };
      REQUIRE(std::fabs(r(0) - r(1)) <= 1e-6 * (1 + r(0)));
      REQUIRE(std::fabs(r(0) - r(2)) <= 1e-6 * (1 + r(0)));
    }
  }
  SECTION("locate and nearest_vertex against brute force") {
    std::mt19937_64 rng(99);
    std::uniform_real_distribution<double> u(-0.5, 1.5);
    std::uint32_t hint = Delaunay2::kNone;
    for (int i = 0; i < 2000; ++i) {
      const double q[2] = {u(rng), u(rng)};
      const std::uint32_t t = d.locate(q[0], q[1], hint);
      hint = t;
      if (d.is_infinite(t)) {
        int k = 0;
        while (d.tri_vertex(t, k) != Delaunay2::kInfinite) ++k;
        REQUIRE(voroclip::orient2d(d.point(d.tri_vertex(t, (k + 1) % 3)),
                                   d.point(d.tri_vertex(t, (k + 2) % 3)), q) == Sign::positive);
      } else {
        for (int k = 0; k < 3; ++k) {
          REQUIRE(voroclip::orient2d(d.point(d.tri_vertex(t, (k + 1) % 3)),
                                     d.point(d.tri_vertex(t, (k + 2) % 3)), q) != Sign::negative);
        }
      }
      // Exact brute force: the nearest point, the smallest index among equidistant ones.
      std::uint32_t best = 0;
      for (std::uint32_t j = 1; j < n; ++j) {
        if (voroclip::compare_distance2d(q, p(j), p(best)) == Sign::negative) best = j;
      }
      REQUIRE(d.nearest_vertex(q[0], q[1], hint) == best);
    }
  }
}

TEST_CASE("Delaunay2 rebuilds reuse the object", "[delaunay]") {
  Delaunay2 d;
  for (const std::uint64_t seed : {5u, 6u, 5u}) {
    const std::vector<double> xy = random_points(3000, seed);
    d.build(xy.data(), 3000);
    require_valid(d);
    const Delaunay2 fresh(xy.data(), 3000);
    REQUIRE(d.tri_vertices() == fresh.tri_vertices());
    REQUIRE(d.tri_neighbors() == fresh.tri_neighbors());
  }
  Delaunay2::Options options;
  options.check = true;
  const std::vector<double> xy = random_points(1000, 8);
  REQUIRE_NOTHROW(Delaunay2(xy.data(), 1000, options));
  // Without kept buffers: the same result, rebuilt twice.
  options.keep_buffers = false;
  Delaunay2 lean(options);
  const Delaunay2 reference(xy.data(), 1000);
  for (int i = 0; i < 2; ++i) {
    lean.build(xy.data(), 1000);
    REQUIRE(lean.tri_vertices() == reference.tri_vertices());
    REQUIRE(lean.tri_neighbors() == reference.tri_neighbors());
  }
}

// Arrays above detail::kHugePageAdviceBytes are reallocated (their contents dropped) and
// advised for huge pages when a rebuild grows past their capacity.
TEST_CASE("Delaunay2 rebuilds growing past the huge-page threshold", "[delaunay]") {
  Delaunay2 d;
  for (const std::uint32_t n : {3000u, 200000u, 5000u, 250000u}) {
    const std::uint64_t seed = 40 + n;
    INFO("n " << n << ", seed " << seed);
    const std::vector<double> xy = random_points(n, seed);
    d.build(xy.data(), n);
    Delaunay2::Options lean;
    lean.keep_buffers = false;
    const Delaunay2 fresh(xy.data(), n, lean);
    REQUIRE(d.nb_triangles() == fresh.nb_triangles());
    REQUIRE(d.tri_vertices() == fresh.tri_vertices());
    REQUIRE(d.tri_neighbors() == fresh.tri_neighbors());
    require_valid(d);
  }
}

// Every array of the result, with duplicate_of() and vertex_triangle().
std::vector<std::uint32_t> all_arrays(const Delaunay2& d) {
  std::vector<std::uint32_t> out = d.tri_vertices();
  out.insert(out.end(), d.tri_neighbors().begin(), d.tri_neighbors().end());
  for (std::uint32_t v = 0; v < d.nb_points(); ++v) {
    out.push_back(d.duplicate_of(v));
    out.push_back(d.vertex_triangle(v));
  }
  return out;
}

TEST_CASE("Delaunay2 strips: the same arrays for any strips and threads", "[delaunay][threads]") {
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  struct Input {
    const char* name;
    std::vector<double> xy;
  };
  std::vector<Input> inputs;
  inputs.push_back({"uniform", random_points(20000, 78)});
  {
    // A 100 x 100 integer grid, every point twice, in random order (duplicates whose
    // smaller index may come second; cocircular quadruples everywhere).
    std::vector<std::array<double, 2>> grid;
    for (int copy = 0; copy < 2; ++copy) {
      for (int i = 0; i < 100; ++i) {
        for (int j = 0; j < 100; ++j) grid.push_back({double(i), double(j)});
      }
    }
    std::shuffle(grid.begin(), grid.end(), rng);
    Input in{"grid twice", {}};
    for (const auto& p : grid) in.xy.insert(in.xy.end(), {p[0], p[1]});
    inputs.push_back(in);
  }
  {
    Input in{"skewed", {}};
    for (int i = 0; i < 20000; ++i) {
      const double a = u(rng), b = u(rng);
      in.xy.insert(in.xy.end(), {a * a * a, 2 * b * b});
    }
    inputs.push_back(in);
  }
  {
    // Twins whose larger index comes in an earlier round: the smaller one, inserted in a
    // strip of the last round, finds its vertex there (and the triangulation is rebuilt
    // with the smaller index).
    Input in{"twins across rounds", random_points(20000, 80)};
    std::vector<std::uint32_t> rounds;
    const std::vector<std::uint32_t> order =
        voroclip::detail::brio_order(in.xy.data(), 20000, 2, &rounds);
    REQUIRE(rounds.size() >= 3);
    const std::size_t last = rounds.size() - 2;  // the last round is [rounds[last], 20000)
    int twins = 0;
    for (std::uint32_t i = rounds[last]; i < 20000 && twins < 20; i += 97) {
      const std::uint32_t small = order[i];
      const std::uint32_t large = order[rounds[last - 1] + static_cast<std::uint32_t>(twins)];
      if (small >= large) continue;
      in.xy[2 * small] = in.xy[2 * large];
      in.xy[2 * small + 1] = in.xy[2 * large + 1];
      ++twins;
    }
    REQUIRE(twins == 20);
    inputs.push_back(in);
  }
  {
    // Every triangle crosses the disk: the strips defer most points, and zoning stops.
    Input in{"circle", {}};
    for (int i = 0; i < 20000; ++i) {
      const double a = 6.283185307179586 * u(rng);
      in.xy.insert(in.xy.end(), {std::cos(a), std::sin(a)});
    }
    inputs.push_back(in);
  }
  for (const Input& in : inputs) {
    INFO(in.name);
    Delaunay2::Options sequential;
    sequential.zones = 1;
    const Delaunay2 reference(in.xy.data(), static_cast<std::uint32_t>(in.xy.size() / 2),
                              sequential);
    require_valid(reference);
    REQUIRE(reference.stats().zoned_passes == 0);
    const std::vector<std::uint32_t> expected = all_arrays(reference);
    std::uint32_t deferred = 0;
    for (const std::uint32_t zones : {2u, 3u, 7u}) {
      for (const std::size_t threads : {std::size_t{1}, voroclip_test::test_threads()}) {
        INFO("zones " << zones << ", threads " << threads);
        Delaunay2::Options options;
        options.zones = zones;
        options.zoned_round = 1024;
        options.check = true;
        const Delaunay2 d = voroclip::test::build_with_threads<Delaunay2>(in.xy, threads, options);
        REQUIRE(all_arrays(d) == expected);
        const Delaunay2::Stats& stats = d.stats();
        REQUIRE(stats.zoned_passes > 0);
        if (std::string(in.name) == "circle") {
          REQUIRE(stats.zoned_passes == 1);
          REQUIRE(2 * stats.deferred_points > stats.zoned_points);
        } else {
          REQUIRE(stats.zoned_passes >= 4);
          REQUIRE(2 * stats.deferred_points < stats.zoned_points);
        }
        deferred += stats.deferred_points;
      }
    }
    REQUIRE(deferred > 0);
  }
  // The default: strips by the number of threads, from rounds of 32768 points on.
  const std::vector<double> xy = random_points(100000, 79);
  const std::vector<std::uint32_t> expected = all_arrays(Delaunay2(xy.data(), 100000));
  for (const std::size_t threads : {1u, 2u, 4u}) {
    INFO("threads " << threads);
    const Delaunay2 d = voroclip::test::build_with_threads<Delaunay2>(xy, threads, {});
    REQUIRE(all_arrays(d) == expected);
    REQUIRE(d.stats().zoned_passes == (threads == 1 ? 0u : 1u));
  }
}

TEST_CASE("Delaunay2 on a million points", "[delaunay][.slow]") {
  const std::vector<double> xy = random_points(1000000, 2026);
  const Delaunay2 d(xy.data(), 1000000);
  require_valid(d);
  std::vector<double> grid;
  for (int i = 0; i < 1000; ++i) {
    for (int j = 0; j < 1000; ++j)
      grid.insert(grid.end(), {static_cast<double>(i), static_cast<double>(j)});
  }
  const Delaunay2 g(grid.data(), 1000000);
  require_valid(g);
  REQUIRE(g.nb_triangles() == 2 * 1000000 - 3996 - 2);
}

TEST_CASE("Delaunay2 on heavily degenerate integer sets", "[delaunay][degenerate]") {
  // Few distinct values: duplicates, collinear runs on the hull and cocircular quadruples
  // everywhere.
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    std::mt19937_64 rng(seed);
    const std::uint64_t range = 4 + seed * 3;
    std::vector<double> xy;
    for (int i = 0; i < 6000; ++i) xy.push_back(static_cast<double>(rng() % range));
    CAPTURE(seed, range);
    const Delaunay2 d(xy.data(), 3000);
    require_valid(d);
    std::set<std::pair<double, double>> distinct;
    for (std::size_t i = 0; i < 3000; ++i) distinct.insert({xy[2 * i], xy[2 * i + 1]});
    REQUIRE(d.nb_unique_points() == distinct.size());
  }
}

TEST_CASE("Delaunay2 on near-degenerate floating-point sets", "[delaunay][degenerate]") {
  SECTION("points on a circle, rounded") {
    std::vector<double> xy;
    for (int i = 0; i < 20000; ++i) {
      const double a = 2 * M_PI * i / 20000.0;
      xy.push_back(std::cos(a));
      xy.push_back(std::sin(a));
    }
    const Delaunay2 d(xy.data(), 20000);
    require_valid(d);
  }
  SECTION("a segment of points and one apex") {
    std::vector<double> xy;
    for (int i = 0; i < 1000; ++i) xy.insert(xy.end(), {0.1 * i, 0.3 * i});
    xy.insert(xy.end(), {5.0, -7.0});
    const Delaunay2 d(xy.data(), 1001);
    require_valid(d);
    // The apex sees every collinear point: a fan of 999 triangles when the points are
    // exactly collinear after rounding; otherwise still valid with the exact count.
    REQUIRE(d.nb_triangles() ==
            2 * d.nb_vertices() - static_cast<std::uint32_t>(d.hull_vertices().size()) - 2);
  }
  SECTION("exactly collinear points and one apex") {
    std::vector<double> xy;
    for (int i = 0; i < 1000; ++i) xy.insert(xy.end(), {static_cast<double>(i), 2.0 * i});
    xy.insert(xy.end(), {3.0, -7.0});
    const Delaunay2 d(xy.data(), 1001);
    require_valid(d);
    REQUIRE(d.hull_vertices().size() == 1001);
    REQUIRE(d.nb_triangles() == 999);
  }
}

TEST_CASE("Delaunay2 nearest_vertex breaks ties by the smallest index", "[delaunay][degenerate]") {
  std::vector<double> xy;
  for (int x = 0; x < 8; ++x)
    for (int y = 0; y < 8; ++y) xy.insert(xy.end(), {double(x), double(y)});
  const Delaunay2 d(xy.data(), 64);
  // Cell centres are equidistant from 4 grid points, edge midpoints from 2.
  for (double x = 0; x < 7.5; x += 0.5)
    for (double y = 0; y < 7.5; y += 0.5) {
      const double q[2] = {x, y};
      std::uint32_t best = 0;
      for (std::uint32_t j = 1; j < 64; ++j) {
        if (voroclip::compare_distance2d(q, &xy[2 * j], &xy[2 * best]) == Sign::negative) best = j;
      }
      CHECK(d.nearest_vertex(x, y) == best);
    }
}
