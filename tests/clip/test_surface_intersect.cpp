// first_intersecting_pair (clip/src/surface_intersect.cpp): every shared model is free of
// self-intersections; hand-made degenerate pairs (touching at one point, coplanar overlaps,
// folds, near misses at one ulp), each under a scale sweep, a translation far from the
// origin, both triangle orders and both orientations; fans that must not be certified
// (a ring winding twice, a bowtie, rings that do not chain) and a sphere with one vertex
// moved, against the pairs tested alone; the hierarchy against a brute-force scan of all
// pairs on random triangle soups; the smallest of several pairs; 1 vs 2 threads.
// The pair oracle (pairs tested alone) is checked against CGAL in test_surface_vs_cgal.cpp.
#define CATCH_CONFIG_ENABLE_PAIR_STRINGMAKER  // pairs of triangles in messages
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <map>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <tbb/global_control.h>

#include "support/threads.h"
#include "surface_intersect.h"
#include "voroclip/core.h"
#include "voroclip/predicates.h"

using voroclip::detail::first_intersecting_pair;
using voroclip::detail::TrianglePair;

namespace {

constexpr std::uint32_t kNone = TrianglePair::kNone;
using Pair = std::pair<std::uint32_t, std::uint32_t>;

Pair as_pair(const TrianglePair& p) { return {p.a, p.b}; }
const Pair kNoPair{kNone, kNone};

struct Soup {
  std::vector<double> xyz;
  std::vector<std::uint32_t> triangles;
  std::uint32_t nb_triangles() const { return static_cast<std::uint32_t>(triangles.size() / 3); }
};

// Each vertex mapped to the first one with the same coordinates (the precondition).
void weld(Soup& s) {
  std::map<std::array<double, 3>, std::uint32_t> first;
  std::vector<std::uint32_t> to(s.xyz.size() / 3);
  for (std::uint32_t v = 0; v < to.size(); ++v) {
    const std::array<double, 3> p = {s.xyz[3 * v], s.xyz[3 * v + 1], s.xyz[3 * v + 2]};
    to[v] = first.emplace(p, v).first->second;
  }
  for (std::uint32_t& v : s.triangles) v = to[v];
}

// The preconditions of first_intersecting_pair; "" when they hold.
std::string precondition_violation(const Soup& s) {
  std::set<std::array<std::uint32_t, 3>> seen;
  std::map<std::array<double, 3>, std::uint32_t> used;
  for (std::uint32_t t = 0; t < s.nb_triangles(); ++t) {
    std::array<std::uint32_t, 3> v = {s.triangles[3 * t], s.triangles[3 * t + 1],
                                      s.triangles[3 * t + 2]};
    const std::string name = "triangle " + std::to_string(t);
    for (std::uint32_t i : v) {
      if (i >= s.xyz.size() / 3) return name + ": index out of range";
      const std::array<double, 3> p = {s.xyz[3 * i], s.xyz[3 * i + 1], s.xyz[3 * i + 2]};
      if (used.emplace(p, i).first->second != i) return name + ": vertex not welded";
    }
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) return name + ": repeated vertex";
    if (voroclip::collinear3d(&s.xyz[3 * v[0]], &s.xyz[3 * v[1]], &s.xyz[3 * v[2]])) {
      return name + ": zero area";
    }
    std::sort(v.begin(), v.end());
    if (!seen.insert(v).second) return name + ": same vertices as an earlier triangle";
  }
  return "";
}

Soup load(const std::string& name) {
  const voroclip::TriangleSurface s =
      voroclip::read_surface(std::string(VOROCLIP_SHARED_DATA_DIR) + "/surfaces/" + name);
  Soup out{s.xyz, s.triangles};
  weld(out);
  return out;
}

// Triangles a and b of s meet (beyond what they share), by first_intersecting_pair on the
// two alone: no vertex has a complete fan then, so the pair test decides, never a fan
// certificate.
bool pair_alone(const Soup& s, std::uint32_t a, std::uint32_t b) {
  const std::vector<std::uint32_t> two = {s.triangles[3 * a],     s.triangles[3 * a + 1],
                                          s.triangles[3 * a + 2], s.triangles[3 * b],
                                          s.triangles[3 * b + 1], s.triangles[3 * b + 2]};
  return first_intersecting_pair(s.xyz, two).found();
}

// The smallest pair by testing every pair alone.
Pair brute_force(const Soup& s) {
  for (std::uint32_t a = 0; a < s.nb_triangles(); ++a) {
    for (std::uint32_t b = a + 1; b < s.nb_triangles(); ++b) {
      if (pair_alone(s, a, b)) return {a, b};
    }
  }
  return kNoPair;
}

// ---------------------------------------------------------------------------------------
// Hand-made configurations. Coordinates are small integers, mapped by p -> scale * p +
// offset; with a power-of-two scale and the offsets used this is exact, so every
// incidence (a vertex on a face, two edges through one point, coplanarity) survives it.
// A nudge then moves one coordinate of one vertex by one ulp of its final value.

struct Nudge {
  std::uint32_t vertex;
  int axis;
  double towards;  // +inf or -inf
};

struct Config {
  const char* name;
  std::vector<std::array<double, 3>> points;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<Nudge> nudges;
  Pair expected;
};

constexpr double kUp = HUGE_VAL, kDown = -HUGE_VAL;

// The triangle T0 at z = 1 that most configurations use: vertices 0, 1, 2.
const std::vector<std::array<double, 3>> kT0 = {{0, 0, 1}, {4, 0, 1}, {0, 4, 1}};

std::vector<std::array<double, 3>> with_t0(std::vector<std::array<double, 3>> more) {
  std::vector<std::array<double, 3>> p = kT0;
  p.insert(p.end(), more.begin(), more.end());
  return p;
}

std::vector<Config> configurations() {
  const std::array<std::uint32_t, 3> t0 = {0, 1, 2}, t1 = {3, 4, 5};
  const Pair hit{0, 1};
  std::vector<Config> c;
  // No common vertex: one common point.
  c.push_back({"vertex on the face's interior",
               with_t0({{1, 1, 1}, {1, 1, 3}, {3, 1, 3}}),
               {t0, t1},
               {},
               hit});
  c.push_back({"vertex one ulp above the face",
               with_t0({{1, 1, 1}, {1, 1, 3}, {3, 1, 3}}),
               {t0, t1},
               {{3, 2, kUp}},
               kNoPair});
  c.push_back(
      {"vertex through the face", with_t0({{1, 1, 0}, {1, 1, 3}, {3, 1, 3}}), {t0, t1}, {}, hit});
  c.push_back(
      {"vertex on an edge", with_t0({{2, 0, 1}, {2, -1, 3}, {3, -1, 3}}), {t0, t1}, {}, hit});
  c.push_back({"vertex one ulp off an edge",
               with_t0({{2, 0, 1}, {2, -1, 3}, {3, -1, 3}}),
               {t0, t1},
               {{3, 1, kDown}},
               kNoPair});
  // The edge (3,3,0)-(1,1,2) meets T0's edge (4,0,1)-(0,4,1) at (2,2,1) only: the second
  // triangle lies in the plane x = y and reaches z = 1 along (2,2,1)-(3,3,1).
  c.push_back({"edge across an edge at one point",
               with_t0({{3, 3, 0}, {1, 1, 2}, {5, 5, 0}}),
               {t0, t1},
               {},
               hit});
  c.push_back({"edge one ulp past an edge",
               with_t0({{3, 3, 0}, {1, 1, 2}, {5, 5, 0}}),
               {t0, t1},
               {{0, 2, kDown}, {1, 2, kDown}, {2, 2, kDown}},
               kNoPair});
  c.push_back(
      {"edge across the interior", with_t0({{1, 1, 0}, {1, 1, 2}, {5, 5, 2}}), {t0, t1}, {}, hit});
  c.push_back(
      {"parallel planes", with_t0({{0, 0, 2}, {4, 0, 2}, {0, 4, 2}}), {t0, t1}, {}, kNoPair});
  // No common vertex, one plane.
  c.push_back({"coplanar overlap", with_t0({{1, 1, 1}, {5, 1, 1}, {1, 5, 1}}), {t0, t1}, {}, hit});
  c.push_back({"coplanar, one inside the other",
               with_t0({{1, 1, 1}, {2, 1, 1}, {1, 2, 1}}),
               {t0, t1},
               {},
               hit});
  c.push_back({"coplanar, a vertex on an edge",
               with_t0({{2, 2, 1}, {5, 2, 1}, {2, 5, 1}}),
               {t0, t1},
               {},
               hit});
  c.push_back({"coplanar, a vertex one ulp off an edge",
               with_t0({{2, 2, 1}, {5, 2, 1}, {2, 5, 1}}),
               {t0, t1},
               {{3, 1, kUp}},
               kNoPair});
  c.push_back({"coplanar, collinear edges overlapping",
               with_t0({{2, 0, 1}, {6, 0, 1}, {4, -2, 1}}),
               {t0, t1},
               {},
               hit});
  c.push_back({"coplanar, collinear edges one ulp apart",
               with_t0({{4, 0, 1}, {8, 0, 1}, {6, -2, 1}}),
               {t0, t1},
               {{3, 0, kUp}},
               kNoPair});
  c.push_back(
      {"coplanar, disjoint", with_t0({{3, 3, 1}, {6, 3, 1}, {3, 6, 1}}), {t0, t1}, {}, kNoPair});
  // One common vertex, v = 0 at (0,0,1).
  const std::array<std::uint32_t, 3> s1 = {0, 3, 4};
  c.push_back({"common vertex, coplanar wedges overlapping",
               with_t0({{4, 1, 1}, {1, 4, 1}}),
               {t0, s1},
               {},
               hit});
  c.push_back({"common vertex, coplanar opposite wedges",
               with_t0({{-4, 0, 1}, {0, -4, 1}}),
               {t0, s1},
               {},
               kNoPair});
  c.push_back({"common vertex, coplanar, edges collinear back to back",
               with_t0({{-4, 0, 1}, {-1, -3, 1}}),
               {t0, s1},
               {},
               kNoPair});
  c.push_back({"common vertex, coplanar, a vertex on the other's edge",
               with_t0({{2, 0, 1}, {1, -3, 1}}),
               {t0, s1},
               {},
               hit});
  c.push_back({"common vertex, coplanar, an edge along part of the other's edge",
               with_t0({{0, 2, 1}, {-2, 1, 1}}),
               {t0, s1},
               {},
               hit});
  c.push_back({"common vertex, coplanar, an edge along the other's edge and beyond",
               with_t0({{0, 6, 1}, {-2, 1, 1}}),
               {t0, s1},
               {},
               hit});
  c.push_back({"common vertex, far edge through the interior",
               with_t0({{1, 1, 0}, {1, 1, 2}}),
               {t0, s1},
               {},
               hit});
  c.push_back({"common vertex, far edge touching an edge",
               with_t0({{2, 2, 0}, {2, 2, 2}}),
               {t0, s1},
               {},
               hit});
  c.push_back({"common vertex, far edge beyond, through the interior",
               with_t0({{3, 3, 0}, {3, 3, 2}}),
               {t0, s1},
               {},
               hit});
  c.push_back({"common vertex, crossing the plane outside the angle",
               with_t0({{-1, -1, 0}, {-1, -1, 2}}),
               {t0, s1},
               {},
               kNoPair});
  c.push_back({"common vertex, crossing the plane along an edge",
               with_t0({{0, 1, 0}, {0, 1, 2}}),
               {t0, s1},
               {},
               hit});
  c.push_back({"common vertex, crossing the plane one ulp outside an edge",
               with_t0({{0, 1, 0}, {0, 1, 2}}),
               {t0, s1},
               {{3, 0, kDown}, {4, 0, kDown}},
               kNoPair});
  c.push_back(
      {"common vertex, above the plane", with_t0({{1, 1, 2}, {2, 1, 2}}), {t0, s1}, {}, kNoPair});
  c.push_back({"common vertex, an edge into the plane at the other's far edge",
               with_t0({{2, 2, 1}, {3, 3, 3}}),
               {t0, s1},
               {},
               hit});
  // A common edge, (0,0,1)-(4,0,1).
  const std::array<std::uint32_t, 3> e1 = {0, 1, 3};
  c.push_back(
      {"common edge, folded (coplanar, same side)", with_t0({{2, 1, 1}}), {t0, e1}, {}, hit});
  c.push_back(
      {"common edge, folded, the third vertex outside", with_t0({{5, 5, 1}}), {t0, e1}, {}, hit});
  c.push_back({"common edge, flat (coplanar, opposite sides)",
               with_t0({{2, -1, 1}}),
               {t0, e1},
               {},
               kNoPair});
  c.push_back({"common edge, dihedral", with_t0({{2, -1, 3}}), {t0, e1}, {}, kNoPair});
  c.push_back({"common edge, sharp dihedral", with_t0({{2, 1, 3}}), {t0, e1}, {}, kNoPair});
  c.push_back(
      {"common edge, one ulp from folded", with_t0({{2, 1, 1}}), {t0, e1}, {{3, 2, kUp}}, kNoPair});
  return c;
}

Soup instantiate(const Config& c, double scale, double offset) {
  Soup s;
  for (const auto& p : c.points) {
    for (int j = 0; j < 3; ++j) s.xyz.push_back(scale * p[static_cast<std::size_t>(j)] + offset);
  }
  for (const Nudge& n : c.nudges) {
    double& x = s.xyz[3 * n.vertex + static_cast<std::uint32_t>(n.axis)];
    x = std::nextafter(x, n.towards);
  }
  for (const auto& t : c.triangles) s.triangles.insert(s.triangles.end(), t.begin(), t.end());
  return s;
}

// For two triangles: the same pair for either order and either orientation of each.
void check_two(Soup s, const Pair& expected) {
  REQUIRE(s.nb_triangles() == 2);
  for (int swap = 0; swap < 2; ++swap) {
    for (int flip = 0; flip < 4; ++flip) {
      Soup v = s;
      if (swap != 0) std::rotate(v.triangles.begin(), v.triangles.begin() + 3, v.triangles.end());
      if ((flip & 1) != 0) std::swap(v.triangles[1], v.triangles[2]);
      if ((flip & 2) != 0) std::swap(v.triangles[4], v.triangles[5]);
      INFO("swapped " << swap << ", flipped " << flip);
      CHECK(as_pair(first_intersecting_pair(v.xyz, v.triangles)) == expected);
    }
  }
}

// Adds a small triangle crossing triangle t near its centroid, standing across its plane;
// it meets t only (its size is a hundredth of t's smallest height).
void add_piercing_triangle(Soup& s, std::uint32_t t) {
  const double* p[3] = {&s.xyz[3 * s.triangles[3 * t]], &s.xyz[3 * s.triangles[3 * t + 1]],
                        &s.xyz[3 * s.triangles[3 * t + 2]]};
  double c[3], u[3], w[3];
  for (int j = 0; j < 3; ++j) {
    c[j] = (p[0][j] + p[1][j] + p[2][j]) / 3;
    u[j] = p[1][j] - p[0][j];
    w[j] = p[2][j] - p[0][j];
  }
  const double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                       u[0] * w[1] - u[1] * w[0]};
  const double nn = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  double longest = 0;
  for (int k = 0; k < 3; ++k) {
    const double* a = p[k];
    const double* b = p[(k + 1) % 3];
    longest =
        std::max(longest, std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                                    (a[2] - b[2]) * (a[2] - b[2])));
  }
  const double h = 0.01 * nn / longest;  // a hundredth of the smallest height
  const double ul = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
  const auto base = static_cast<std::uint32_t>(s.xyz.size() / 3);
  const double q[3][3] = {{c[0] + h * n[0] / nn, c[1] + h * n[1] / nn, c[2] + h * n[2] / nn},
                          {c[0] - h * n[0] / nn, c[1] - h * n[1] / nn, c[2] - h * n[2] / nn},
                          {c[0] + h * (n[0] / nn + u[0] / ul), c[1] + h * (n[1] / nn + u[1] / ul),
                           c[2] + h * (n[2] / nn + u[2] / ul)}};
  for (const auto& x : q) s.xyz.insert(s.xyz.end(), x, x + 3);
  s.triangles.insert(s.triangles.end(), {base, base + 1, base + 2});
}

// A random soup of small triangles in the integer grid [0, g]^3 (many coplanar, collinear
// and touching configurations), welded, without zero-area or repeated triangles.
Soup random_soup(std::mt19937_64& rng, std::uint32_t n, int g, int size) {
  std::uniform_int_distribution<int> coord(0, g), delta(-size, size);
  Soup s;
  std::map<std::array<double, 3>, std::uint32_t> index;
  std::set<std::array<std::uint32_t, 3>> seen;
  while (s.nb_triangles() < n) {
    std::array<std::array<double, 3>, 3> p;
    for (int j = 0; j < 3; ++j) p[0][static_cast<std::size_t>(j)] = coord(rng);
    for (int k = 1; k < 3; ++k) {
      for (std::size_t j = 0; j < 3; ++j) {
        p[static_cast<std::size_t>(k)][j] =
            std::clamp(p[0][j] + delta(rng), 0.0, static_cast<double>(g));
      }
    }
    if (voroclip::collinear3d(p[0].data(), p[1].data(), p[2].data())) continue;
    std::array<std::uint32_t, 3> t;
    for (std::size_t k = 0; k < 3; ++k) {
      const auto next = static_cast<std::uint32_t>(index.size());
      t[k] = index.emplace(p[k], next).first->second;
      if (t[k] == next) s.xyz.insert(s.xyz.end(), p[k].begin(), p[k].end());
    }
    std::array<std::uint32_t, 3> sorted = t;
    std::sort(sorted.begin(), sorted.end());
    if (!seen.insert(sorted).second) continue;
    s.triangles.insert(s.triangles.end(), t.begin(), t.end());
  }
  return s;
}

}  // namespace

TEST_CASE("first_intersecting_pair: the shared models do not intersect themselves",
          "[clip][exact]") {
  for (const char* name : {"bunny.obj", "elk.off", "fandisk.obj", "gargoyle.off", "homer.obj",
                           "rocker-arm.obj", "skull_low_resolution.obj", "sphere.obj"}) {
    INFO(name);
    const Soup s = load(name);
    REQUIRE(precondition_violation(s).empty());
    CHECK(as_pair(first_intersecting_pair(s.xyz, s.triangles)) == kNoPair);
  }
}

TEST_CASE("first_intersecting_pair: hand-made pairs, each in both orders and orientations",
          "[clip][exact][degenerate]") {
  for (const Config& c : configurations()) {
    INFO(c.name);
    const Soup s = instantiate(c, 1.0, 0.0);
    REQUIRE(precondition_violation(s).empty());
    check_two(s, c.expected);
  }
}

TEST_CASE("first_intersecting_pair: hand-made pairs under a scale sweep and far from the origin",
          "[clip][exact][degenerate]") {
  // Powers of two from 2^-30 (about 1e-9) to 2^30 (about 1e9), and 1e3, 1e6, 1e9: exact on
  // these small integers, so the geometry is the same; the offsets keep every coordinate
  // exact too (at 2^-30 they need 50 bits). Nudges are one ulp of the final coordinates.
  std::vector<double> scales;
  for (int e = -30; e <= 30; e += 5) scales.push_back(std::ldexp(1.0, e));
  scales.insert(scales.end(), {1e3, 1e6, 1e9});
  for (const double scale : scales) {
    for (const double offset : {0.0, 1e6, -1e6}) {
      for (const Config& c : configurations()) {
        INFO(c.name << ", scale " << scale << ", offset " << offset);
        const Soup s = instantiate(c, scale, offset);
        REQUIRE(precondition_violation(s).empty());
        check_two(s, c.expected);
      }
    }
  }
}

TEST_CASE("first_intersecting_pair: the smallest of several pairs", "[clip][exact]") {
  // T1 and T2 are far apart at z = 0; T3 pierces T2, T4 pierces T1, T5 pierces T1 and T2's
  // plane outside T2. Pairs (1, 4), (1, 5), (2, 3): the first is (1, 4).
  Soup s;
  s.xyz = {100, 100, 100, 101, 100, 100, 100, 101, 100,  // T0, alone
           0,   0,   0,   4,   0,   0,   0,   4,   0,    // T1
           10,  0,   0,   14,  0,   0,   10,  4,   0,    // T2
           11,  1,   -1,  11,  1,   1,   12,  1,   1,    // T3 through T2
           1,   1,   -1,  1,   1,   1,   2,   1,   1,    // T4 through T1
           1,   2,   -1,  1,   2,   1,   2,   2,   1};   // T5 through T1
  for (std::uint32_t v = 0; v < 18; ++v) s.triangles.push_back(v);
  REQUIRE(precondition_violation(s).empty());
  CHECK(as_pair(first_intersecting_pair(s.xyz, s.triangles)) == Pair{1, 4});
  CHECK(brute_force(s) == Pair{1, 4});
  // Without T4 the next is (1, 5) (now (1, 4)).
  s.triangles.erase(s.triangles.begin() + 12, s.triangles.begin() + 15);
  CHECK(as_pair(first_intersecting_pair(s.xyz, s.triangles)) == Pair{1, 4});
  // Without T1 too, (2, 3) (now (1, 2)).
  s.triangles.erase(s.triangles.begin() + 3, s.triangles.begin() + 6);
  CHECK(as_pair(first_intersecting_pair(s.xyz, s.triangles)) == Pair{1, 2});
}

TEST_CASE("first_intersecting_pair: fewer than two triangles", "[clip][exact][degenerate]") {
  const std::vector<double> xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  CHECK(!first_intersecting_pair(xyz, {}).found());
  CHECK(!first_intersecting_pair(xyz, {0, 1, 2}).found());
}

TEST_CASE("first_intersecting_pair: fans that must not be certified", "[clip][exact][degenerate]") {
  // A planar ring around v = 0 that winds twice: six triangles of 120 degrees each, all
  // oriented alike, their ring edges one cycle. Triangles 0 and 2 (common vertex v) overlap
  // along the ray at 0 degrees; 0 and 3 overlap in a wedge.
  Soup twice;
  twice.xyz = {0, 0, 0};
  for (int j = 0; j < 6; ++j) {
    const double r = 4 + j, angle = 2.0943951023931953 * j;  // 120 degrees
    twice.xyz.insert(twice.xyz.end(), {r * std::cos(angle), r * std::sin(angle), 0.0});
  }
  // The ray at 0 degrees exactly: points 1 and 4 on the x axis.
  twice.xyz[3 * 1 + 1] = 0;
  twice.xyz[3 * 4 + 1] = 0;
  for (std::uint32_t j = 0; j < 6; ++j) {
    twice.triangles.insert(twice.triangles.end(), {0, j + 1, (j + 1) % 6 + 1});
  }
  REQUIRE(precondition_violation(twice).empty());
  CHECK(brute_force(twice) == Pair{0, 2});
  CHECK(as_pair(first_intersecting_pair(twice.xyz, twice.triangles)) == Pair{0, 2});
  // The second turn's point on the ray moved below it: the ray at 0 degrees now meets the
  // first turn at a ring point and the second inside a triangle (counted half-open, the
  // ring still winds twice).
  Soup below = twice;
  below.xyz[3 * 4 + 1] = -0.5;
  REQUIRE(precondition_violation(below).empty());
  const Pair below_pair = brute_force(below);
  CHECK(below_pair != kNoPair);
  CHECK(as_pair(first_intersecting_pair(below.xyz, below.triangles)) == below_pair);
  // Three triangles on v whose ring edges do not chain (no common ring vertex): all
  // oriented alike, the ray at 0 degrees in one of them only, yet the first two overlap.
  Soup loose;
  loose.xyz = {0, 0, 0};
  for (const double degrees : {-10.0, 100.0, 50.0, 150.0, 200.0, 300.0}) {
    const double angle = degrees * 3.14159265358979323846 / 180;
    loose.xyz.insert(loose.xyz.end(), {4 * std::cos(angle), 4 * std::sin(angle), 0.0});
  }
  loose.triangles = {0, 1, 2, 0, 3, 4, 0, 5, 6};
  REQUIRE(precondition_violation(loose).empty());
  CHECK(brute_force(loose) == Pair{0, 1});
  CHECK(as_pair(first_intersecting_pair(loose.xyz, loose.triangles)) == Pair{0, 1});
  // A proper star of three triangles around v plus a triangle hanging off it, first in
  // the index order: its ring edge leads into the cycle but is not on it. It folds onto
  // triangle 1 across their common edge.
  Soup hanging;
  hanging.xyz = {0, 0, 0};
  for (const auto& [radius, degrees] :
       std::vector<std::pair<double, double>>{{2, 20}, {4, -60}, {4, 60}, {4, 180}}) {
    const double angle = degrees * 3.14159265358979323846 / 180;
    hanging.xyz.insert(hanging.xyz.end(),
                       {radius * std::cos(angle), radius * std::sin(angle), 0.0});
  }
  hanging.triangles = {0, 1, 3, 0, 2, 3, 0, 3, 4, 0, 4, 2};
  REQUIRE(precondition_violation(hanging).empty());
  CHECK(brute_force(hanging) == Pair{0, 1});
  CHECK(as_pair(first_intersecting_pair(hanging.xyz, hanging.triangles)) == Pair{0, 1});
  // The same ring lifted into a cone that winds twice (no two triangles coplanar).
  Soup cone = twice;
  for (std::uint32_t j = 1; j <= 6; ++j) cone.xyz[3 * j + 2] = 1 + 0.5 * j;
  REQUIRE(precondition_violation(cone).empty());
  const Pair cone_pair = brute_force(cone);
  CHECK(cone_pair != kNoPair);
  CHECK(as_pair(first_intersecting_pair(cone.xyz, cone.triangles)) == cone_pair);

  // A bowtie: two tetrahedra's boundaries sharing the vertex v = 0 (two ring cycles).
  const auto bowtie = [](double tip_x) {
    Soup b;
    b.xyz = {0,     0,  0,  1,     -1, -1, 1,     1, -1, 1, 0, 1,  // first: apex v, base at x = 1
             tip_x, -1, -1, tip_x, 1,  -1, tip_x, 0, 1};
    b.triangles = {0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2,   // tetrahedron (v, 1, 2, 3)
                   0, 5, 4, 0, 6, 5, 0, 4, 6, 4, 5, 6};  // tetrahedron (v, 4, 5, 6)
    return b;
  };
  const Soup apart = bowtie(-1), inside = bowtie(2);
  REQUIRE(precondition_violation(apart).empty());
  REQUIRE(precondition_violation(inside).empty());
  CHECK(brute_force(apart) == kNoPair);
  CHECK(as_pair(first_intersecting_pair(apart.xyz, apart.triangles)) == kNoPair);
  const Pair inside_pair = brute_force(inside);
  CHECK(inside_pair != kNoPair);
  CHECK(as_pair(first_intersecting_pair(inside.xyz, inside.triangles)) == inside_pair);
}

TEST_CASE(
    "first_intersecting_pair: a closed surface with one vertex moved, against pairs tested alone",
    "[clip][exact]") {
  // Moving vertex v of the clean sphere changes only the pairs with a triangle on v; those
  // are tested alone (no fan certificate involved), the others stay apart.
  const Soup sphere = load("sphere.obj");
  REQUIRE(as_pair(first_intersecting_pair(sphere.xyz, sphere.triangles)) == kNoPair);
  const std::uint64_t seed = 1357;
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::uint32_t> pick(0, sphere.nb_triangles() * 3 - 1);
  std::uniform_real_distribution<double> offset(-1, 1);
  int nb_found = 0, nb_clear = 0;
  for (int trial = 0; trial < 400; ++trial) {
    Soup s = sphere;
    const std::uint32_t v = s.triangles[pick(rng)];
    const double reach = trial % 4 == 0 ? 0.02 : trial % 4 == 1 ? 0.1 : trial % 4 == 2 ? 0.3 : 1.5;
    for (int j = 0; j < 3; ++j) s.xyz[3 * v + static_cast<std::uint32_t>(j)] += reach * offset(rng);
    INFO("seed " << seed << ", trial " << trial << ", vertex " << v);
    if (!precondition_violation(s).empty()) continue;
    // Boxes of the corners (exact): triangles whose boxes are apart do not meet.
    std::vector<std::array<double, 6>> box(s.nb_triangles());
    for (std::uint32_t t = 0; t < s.nb_triangles(); ++t) {
      for (std::uint32_t j = 0; j < 3; ++j) {
        const double x0 = s.xyz[3 * s.triangles[3 * t] + j];
        const double x1 = s.xyz[3 * s.triangles[3 * t + 1] + j];
        const double x2 = s.xyz[3 * s.triangles[3 * t + 2] + j];
        box[t][j] = std::min({x0, x1, x2});
        box[t][j + 3] = std::max({x0, x1, x2});
      }
    }
    const auto boxes_meet = [&box](std::uint32_t t, std::uint32_t u) {
      for (std::size_t j = 0; j < 3; ++j) {
        if (box[t][j] > box[u][j + 3] || box[u][j] > box[t][j + 3]) return false;
      }
      return true;
    };
    Pair expected = kNoPair;
    for (std::uint32_t t = 0; t < s.nb_triangles(); ++t) {
      const std::uint32_t* tv = &s.triangles[3 * t];
      if (tv[0] != v && tv[1] != v && tv[2] != v) continue;
      for (std::uint32_t u = 0; u < s.nb_triangles(); ++u) {
        const Pair p{std::min(t, u), std::max(t, u)};
        if (u != t && p < expected && boxes_meet(t, u) && pair_alone(s, p.first, p.second)) {
          expected = p;
        }
      }
    }
    CHECK(as_pair(first_intersecting_pair(s.xyz, s.triangles)) == expected);
    (expected == kNoPair ? nb_clear : nb_found) += 1;
  }
  CHECK(nb_found > 30);
  CHECK(nb_clear > 30);
}

TEST_CASE(
    "first_intersecting_pair: random triangle soups: the hierarchy finds the brute-force pair",
    "[clip][exact]") {
  // Soups of n triangles in small grids: most pairs touch or overlap for small n and large
  // triangles; sparse soups of small triangles give no pair or a late one.
  const std::uint64_t seed = 20240611;
  std::mt19937_64 rng(seed);
  int nb_found = 0, nb_clear = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const std::uint32_t n = 2 + static_cast<std::uint32_t>(trial % 60);
    const int g = 4 + 4 * (trial % 7), size = 1 + trial % 3;
    INFO("seed " << seed << ", trial " << trial << ", " << n << " triangles, grid " << g);
    const Soup s = random_soup(rng, n, g, size);
    REQUIRE(precondition_violation(s).empty());
    const Pair expected = brute_force(s);
    CHECK(as_pair(first_intersecting_pair(s.xyz, s.triangles)) == expected);
    (expected == kNoPair ? nb_clear : nb_found) += 1;
  }
  // Both outcomes are exercised.
  CHECK(nb_found > 30);
  CHECK(nb_clear > 30);
}

TEST_CASE("first_intersecting_pair: an intersection late in the index order, 1 and 2 threads",
          "[clip][exact][threads]") {
  Soup s = load("gargoyle.off");
  const std::uint32_t n = s.nb_triangles();
  REQUIRE(n == 100000);
  // A triangle through 90000 (added first, index n) and one through 70000 (index n + 1):
  // the first pair is (70000, n + 1), though (90000, n) has the smaller second triangle.
  add_piercing_triangle(s, 90000);
  add_piercing_triangle(s, 70000);
  REQUIRE(precondition_violation(s).empty());
  Pair one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = as_pair(first_intersecting_pair(s.xyz, s.triangles));
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism,
                          voroclip_test::test_threads());
    two = as_pair(first_intersecting_pair(s.xyz, s.triangles));
  }
  CHECK(one == Pair{70000, n + 1});
  CHECK(two == one);
  // Only the second one left: (90000, n).
  s.triangles.resize(3 * std::size_t{n + 1});
  CHECK(as_pair(first_intersecting_pair(s.xyz, s.triangles)) == Pair{90000, n});
}

TEST_CASE("first_intersecting_pair: a soup with many intersecting pairs, 1 and 2 threads",
          "[clip][exact][threads]") {
  // Thousands of pairs meet: the threads race to lower the shared minimum.
  const std::uint64_t seed = 8675309;
  std::mt19937_64 rng(seed);
  INFO("seed " << seed);
  const Soup s = random_soup(rng, 4000, 24, 3);
  REQUIRE(precondition_violation(s).empty());
  const Pair expected = brute_force(s);
  REQUIRE(expected != kNoPair);
  for (int threads = 1; threads <= 2; ++threads) {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism,
                          static_cast<std::size_t>(threads));
    for (int run = 0; run < 5; ++run) {
      INFO(threads << " threads, run " << run);
      CHECK(as_pair(first_intersecting_pair(s.xyz, s.triangles)) == expected);
    }
  }
}

TEST_CASE("first_intersecting_pair: timing on gargoyle, 2 threads", "[clip][.slow]") {
  // Prints the median of 11 runs; asserts the answer only (never the time).
  const Soup s = load("gargoyle.off");
  tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
  std::vector<double> seconds;
  for (int run = 0; run < 11; ++run) {
    const auto t0 = std::chrono::steady_clock::now();
    const TrianglePair p = first_intersecting_pair(s.xyz, s.triangles);
    seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    CHECK(!p.found());
  }
  std::sort(seconds.begin(), seconds.end());
  std::cout << "first_intersecting_pair, gargoyle (100,000 triangles), 2 threads: median "
            << seconds[5] << " s, min " << seconds[0] << " s, max " << seconds[10] << " s\n";
}
