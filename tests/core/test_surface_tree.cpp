// SurfaceTree (closest points, pseudo-normals) against brute force over every triangle
// with an independent point-triangle distance; FeatureLines on closed forms (cube,
// cylinder, one triangle) and on fandisk; FeatureTree against brute force over segments.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "voroclip/core.h"

using voroclip::FeatureLines;
using voroclip::FeatureTree;
using voroclip::SurfaceTree;
using voroclip::TriangleSurface;

namespace {

const std::string kSurfaces = std::string(VOROCLIP_SHARED_DATA_DIR) + "/surfaces/";

using V3 = std::array<double, 3>;
V3 at(const double* p) { return {p[0], p[1], p[2]}; }
V3 operator-(const V3& a, const V3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
V3 operator+(const V3& a, const V3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
V3 operator*(double s, const V3& a) { return {s * a[0], s * a[1], s * a[2]}; }
double dot(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

double segment_distance2(const V3& p, const V3& a, const V3& b) {
  const V3 ab = b - a;
  const double len2 = dot(ab, ab);
  const double t = len2 > 0 ? std::clamp(dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  const V3 d = p - (a + t * ab);
  return dot(d, d);
}

// Independent oracle: the minimiser of |p - a - s (b - a) - t (c - a)|^2 over the plane,
// from the 2 x 2 normal equations, when it lies in the triangle (s, t >= 0, s + t <= 1);
// else the nearest of the three edges.
double triangle_distance2(const V3& p, const V3& a, const V3& b, const V3& c) {
  const V3 ab = b - a, ac = c - a, ap = p - a;
  const double aa = dot(ab, ab), bb = dot(ab, ac), cc = dot(ac, ac);
  const double dd = dot(ab, ap), ee = dot(ac, ap);
  const double det = aa * cc - bb * bb;
  if (det > 0) {
    const double s = (cc * dd - bb * ee) / det, t = (aa * ee - bb * dd) / det;
    if (s >= 0 && t >= 0 && s + t <= 1) {
      const V3 d = ap - s * ab - t * ac;
      return dot(d, d);
    }
  }
  return std::min(
      {segment_distance2(p, a, b), segment_distance2(p, b, c), segment_distance2(p, c, a)});
}

double brute_force2(const TriangleSurface& s, const V3& p, std::uint32_t* which = nullptr) {
  double best = std::numeric_limits<double>::infinity();
  for (std::uint32_t t = 0; t < s.nb_triangles(); ++t) {
    const double d = triangle_distance2(p, at(&s.xyz[3 * std::size_t{s.triangles[3 * t]}]),
                                        at(&s.xyz[3 * std::size_t{s.triangles[3 * t + 1]}]),
                                        at(&s.xyz[3 * std::size_t{s.triangles[3 * t + 2]}]));
    if (d < best) {
      best = d;
      if (which) *which = t;
    }
  }
  return best;
}

double diagonal(const SurfaceTree& tree) {
  const V3 d = at(tree.bbox_hi()) - at(tree.bbox_lo());
  return std::sqrt(dot(d, d));
}

TriangleSurface cube() {
  TriangleSurface s;
  s.source = "cube";
  for (int i = 0; i < 8; ++i) {
    s.xyz.insert(s.xyz.end(), {double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)});
  }
  // Two triangles per face, outward.
  s.triangles = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                 2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
  return s;
}

// A closed cylinder of radius 1 and height 1: `sides` side quads, fans on the caps.
TriangleSurface cylinder(std::uint32_t sides) {
  TriangleSurface s;
  for (std::uint32_t i = 0; i < sides; ++i) {
    const double a = 2 * M_PI * i / sides;
    s.xyz.insert(s.xyz.end(), {std::cos(a), std::sin(a), 0.0});
    s.xyz.insert(s.xyz.end(), {std::cos(a), std::sin(a), 1.0});
  }
  const std::uint32_t bottom = 2 * sides, top = 2 * sides + 1;
  s.xyz.insert(s.xyz.end(), {0, 0, 0, 0, 0, 1});
  for (std::uint32_t i = 0; i < sides; ++i) {
    const std::uint32_t j = (i + 1) % sides;
    s.triangles.insert(s.triangles.end(), {2 * i, 2 * j, 2 * j + 1, 2 * i, 2 * j + 1, 2 * i + 1});
    s.triangles.insert(s.triangles.end(), {bottom, 2 * j, 2 * i, top, 2 * i + 1, 2 * j + 1});
  }
  return s;
}

}  // namespace

TEST_CASE("SurfaceTree: closest points equal brute force on shared surfaces", "[core]") {
  const std::uint64_t seed = 20261124;
  std::cout << "SurfaceTree brute-force test seed " << seed << std::endl;
  std::mt19937_64 rng(seed);
  for (const char* name : {"sphere.obj", "bunny.obj", "fandisk.obj"}) {
    INFO(name);
    const TriangleSurface s = voroclip::read_surface(kSurfaces + name);
    const SurfaceTree tree(s);
    REQUIRE(tree.nb_triangles() == s.nb_triangles());
    const V3 lo = at(tree.bbox_lo()), hi = at(tree.bbox_hi());
    const double diag = diagonal(tree);
    std::uniform_real_distribution<double> u(-0.25, 1.25);
    for (int q = 0; q < 300; ++q) {
      V3 p;
      for (int k = 0; k < 3; ++k) p[static_cast<std::size_t>(k)] = lo[k] + u(rng) * (hi[k] - lo[k]);
      const SurfaceTree::Closest c = tree.closest(p.data());
      const double expected = brute_force2(s, p);
      CHECK(std::fabs(c.distance2 - expected) <= 1e-12 * diag * diag);
      // The point is where it says: on its triangle, at the distance given.
      const V3 d = p - at(c.point);
      CHECK(dot(d, d) == Approx(c.distance2).epsilon(1e-12).margin(1e-24));
      const std::uint32_t* t = &s.triangles[3 * std::size_t{c.triangle}];
      CHECK(triangle_distance2(at(c.point), at(&s.xyz[3 * std::size_t{t[0]}]),
                               at(&s.xyz[3 * std::size_t{t[1]}]),
                               at(&s.xyz[3 * std::size_t{t[2]}])) <= 1e-24 * diag * diag);
      // A hint changes nothing, even a bad one.
      const auto hint = static_cast<std::uint32_t>(rng() % s.nb_triangles());
      const SurfaceTree::Closest h = tree.closest(p.data(), hint);
      CHECK(h.triangle == c.triangle);
      CHECK(h.distance2 == c.distance2);
    }
  }
}

TEST_CASE("SurfaceTree: points on and near the surface, pseudo-normal signs", "[core]") {
  const TriangleSurface s = voroclip::read_surface(kSurfaces + "sphere.obj");
  const SurfaceTree tree(s);
  // Vertices: distance 0, at a vertex.
  for (std::uint32_t v = 0; v < s.nb_vertices(); v += 7) {
    const SurfaceTree::Closest c = tree.closest(&s.xyz[3 * std::size_t{v}]);
    CHECK(c.distance2 == 0);
    CHECK(c.feature == SurfaceTree::Feature::kVertex);
    CHECK(s.triangles[3 * std::size_t{c.triangle} + c.index] == v);
    // On this convex surface the vertex normal points away from the centre.
    CHECK(dot(at(c.normal), at(&s.xyz[3 * std::size_t{v}])) > 0.99);
  }
  // Above a triangle's centroid along its normal: that triangle, inside it, at that height.
  for (std::uint32_t t = 0; t < s.nb_triangles(); t += 11) {
    V3 g = {0, 0, 0};
    for (int k = 0; k < 3; ++k) {
      g = g + (1.0 / 3) *
                  at(&s.xyz[3 * std::size_t{s.triangles[3 * t + static_cast<std::uint32_t>(k)]}]);
    }
    const V3 n = at(tree.triangle_normal(t));
    const V3 p = g + 0.01 * n;
    const SurfaceTree::Closest c = tree.closest(p.data());
    CHECK(c.triangle == t);
    CHECK(c.feature == SurfaceTree::Feature::kFace);
    CHECK(std::sqrt(c.distance2) == Approx(0.01).epsilon(1e-9));
    CHECK(at(c.normal) == n);
  }
  // Inside the inscribed ball: dot(p - closest, normal) < 0; outside the sphere: > 0.
  std::mt19937_64 rng(7);
  std::normal_distribution<double> gauss;
  for (int q = 0; q < 2000; ++q) {
    V3 dir = {gauss(rng), gauss(rng), gauss(rng)};
    dir = (1 / std::sqrt(dot(dir, dir))) * dir;
    for (const double r : {0.3, 0.9, 1.0001, 1.5}) {
      const V3 p = r * dir;
      const SurfaceTree::Closest c = tree.closest(p.data());
      CHECK((dot(p - at(c.point), at(c.normal)) > 0) == (r > 1));
    }
  }
}

TEST_CASE("SurfaceTree: degenerate triangles, empty surfaces, bad input", "[core][degenerate]") {
  TriangleSurface s;
  s.source = "flat";
  s.xyz = {0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 5, 5, 5};
  s.triangles = {0, 1, 2, 0, 0, 3, 4, 4, 4};  // collinear; repeated vertex; a single point
  const SurfaceTree tree(s);
  for (const V3& p : {V3{1.5, 1, 0}, V3{-1, -1, 0}, V3{0, 0.5, 3}, V3{5, 5, 6}, V3{3, 0, 0}}) {
    const SurfaceTree::Closest c = tree.closest(p.data());
    CHECK(c.distance2 == Approx(brute_force2(s, p)).margin(1e-15));
    CHECK(c.feature != SurfaceTree::Feature::kFace);
    CHECK(at(tree.triangle_normal(c.triangle)) == V3{0, 0, 0});
  }
  const SurfaceTree empty{TriangleSurface{}};
  const double p[3] = {0, 0, 0};
  CHECK(empty.closest(p).triangle == SurfaceTree::kNone);
  const double nan[3] = {std::nan(""), 0, 0};
  CHECK(tree.closest(nan).triangle == SurfaceTree::kNone);
  s.triangles = {0, 1, 9};
  CHECK_THROWS_WITH(SurfaceTree(s),
                    "flat: triangle 0 has vertex 9, the surface has 5 vertices (numbered from 0)");
}

TEST_CASE("SurfaceTree: concurrent queries give the sequential answers", "[core]") {
  const TriangleSurface s = voroclip::read_surface(kSurfaces + "bunny.obj");
  const SurfaceTree tree(s);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> points(3 * 4000);
  for (double& x : points) x = u(rng);
  std::vector<SurfaceTree::Closest> seq(4000), par(4000);
  for (std::size_t i = 0; i < 4000; ++i) seq[i] = tree.closest(&points[3 * i]);
  std::vector<std::thread> threads;
  for (std::size_t w = 0; w < 4; ++w) {
    threads.emplace_back([&, w] {
      for (std::size_t i = w; i < 4000; i += 4) par[i] = tree.closest(&points[3 * i]);
    });
  }
  for (std::thread& t : threads) t.join();
  for (std::size_t i = 0; i < 4000; ++i) {
    CHECK(par[i].triangle == seq[i].triangle);
    CHECK(par[i].distance2 == seq[i].distance2);
  }
}

TEST_CASE("extract_feature_lines: cube, cylinder, an open triangle", "[core]") {
  const FeatureLines c = voroclip::extract_feature_lines(cube());
  CHECK(c.nb_feature_edges == 12);  // the face diagonals are flat
  CHECK(c.corners == std::vector<std::uint32_t>{0, 1, 2, 3, 4, 5, 6, 7});
  REQUIRE(c.nb_lines() == 12);
  for (std::uint32_t l = 0; l < 12; ++l) {
    CHECK(c.line_begin[l + 1] - c.line_begin[l] == 2);
    CHECK(c.line_closed[l] == 0);
  }
  // Lines from corner 0 first, towards 1, 2, 4.
  CHECK(std::vector<std::uint32_t>(c.line_vertices.begin(), c.line_vertices.begin() + 6) ==
        std::vector<std::uint32_t>{0, 1, 0, 2, 0, 4});
  // 90 degrees between the normals of neighbouring cube faces: sharp below 90 only.
  CHECK(voroclip::extract_feature_lines(cube(), 89.9).nb_feature_edges == 12);
  CHECK(voroclip::extract_feature_lines(cube(), 90.1).nb_feature_edges == 0);

  // A 64-sided cylinder: 5.6 degrees between side faces, 90 at the rims: two closed loops.
  const FeatureLines cyl = voroclip::extract_feature_lines(cylinder(64));
  CHECK(cyl.corners.empty());
  REQUIRE(cyl.nb_lines() == 2);
  for (std::uint32_t l = 0; l < 2; ++l) {
    CHECK(cyl.line_closed[l] == 1);
    CHECK(cyl.line_begin[l + 1] - cyl.line_begin[l] == 65);
    CHECK(cyl.line_vertices[cyl.line_begin[l]] == cyl.line_vertices[cyl.line_begin[l + 1] - 1]);
  }
  // Loop 0 starts at vertex 0 towards its lower neighbour (2, not 126).
  CHECK(cyl.line_vertices[1] == 2);
  // With 4 sides (a square prism) the side edges are sharp too: 8 corners, 12 lines.
  const FeatureLines box = voroclip::extract_feature_lines(cylinder(4));
  CHECK(box.corners.size() == 8);
  CHECK(box.nb_lines() == 12);

  // One triangle: its border is a closed loop.
  TriangleSurface one;
  one.xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  one.triangles = {0, 1, 2};
  const FeatureLines t = voroclip::extract_feature_lines(one);
  CHECK(t.line_vertices == std::vector<std::uint32_t>{0, 1, 2, 0});
  CHECK(t.line_closed == std::vector<std::uint8_t>{1});
  CHECK_THROWS_AS(voroclip::extract_feature_lines(one, 200), voroclip::Error);
}

TEST_CASE("extract_feature_lines: borders between triangle tags are feature edges", "[core]") {
  // At 180 degrees no edge is sharp by its angle; the tags alone make the lines.
  std::vector<std::int32_t> tag(12, 1);
  CHECK(voroclip::extract_feature_lines(cube(), 180, tag).nb_feature_edges == 0);
  // The bottom face (triangles 0 and 1, z = 0) tagged 5: its four sides, one closed loop.
  tag[0] = tag[1] = 5;
  const FeatureLines bottom = voroclip::extract_feature_lines(cube(), 180, tag);
  CHECK(bottom.nb_feature_edges == 4);
  CHECK(bottom.corners.empty());
  REQUIRE(bottom.nb_lines() == 1);
  CHECK(bottom.line_closed[0] == 1);
  // Its two triangles tagged 5 and 6: the diagonal 0-3 too; 0 and 3 become corners.
  tag[1] = 6;
  const FeatureLines split = voroclip::extract_feature_lines(cube(), 180, tag);
  CHECK(split.nb_feature_edges == 5);
  CHECK(split.corners == std::vector<std::uint32_t>{0, 3});
  CHECK(split.nb_lines() == 3);
  // With the default angle: the cube's 12 edges and the diagonal.
  CHECK(voroclip::extract_feature_lines(cube(), voroclip::kDefaultFeatureAngleDeg, tag)
            .nb_feature_edges == 13);
  tag.pop_back();
  CHECK_THROWS_AS(voroclip::extract_feature_lines(cube(), 180, tag), voroclip::Error);
}

TEST_CASE("extract_feature_lines: fandisk's creases, stable around the default angle", "[core]") {
  const TriangleSurface s = voroclip::read_surface(kSurfaces + "fandisk.obj");
  CHECK(voroclip::extract_feature_lines(s, 1).nb_feature_edges > 1000);  // facets too
  // The corners where three creases meet, from the line ends (a corner is the end of as
  // many lines as feature edges meet there).
  const auto junctions = [](const FeatureLines& f) {
    std::map<std::uint32_t, int> ends;
    for (std::uint32_t l = 0; l < f.nb_lines(); ++l) {
      ++ends[f.line_vertices[f.line_begin[l]]];
      ++ends[f.line_vertices[f.line_begin[l + 1] - 1]];
    }
    std::vector<std::uint32_t> out;
    for (const auto& [v, n] : ends) {
      if (n >= 3) out.push_back(v);
    }
    return out;
  };
  const FeatureLines def = voroclip::extract_feature_lines(s);
  // From 25 to 70 degrees the same 22 junctions of three creases and the same number of
  // lines: only a few edges where two creases fade out come and go (so the 2 corners that
  // end them move along).
  for (const double angle : {25.0, 30.0, 50.0, 60.0, 70.0}) {
    INFO(angle);
    const FeatureLines f = voroclip::extract_feature_lines(s, angle);
    CHECK(junctions(f) == junctions(def));
    CHECK(f.corners.size() == def.corners.size());
    CHECK(f.nb_lines() == def.nb_lines());
  }
  CHECK(junctions(def).size() == 22);
  CHECK(def.corners.size() == 24);
  CHECK(def.nb_feature_edges == 710);
  // Every feature edge is in exactly one line.
  std::uint32_t edges = 0;
  for (std::uint32_t l = 0; l < def.nb_lines(); ++l)
    edges += def.line_begin[l + 1] - def.line_begin[l] - 1;
  CHECK(edges == def.nb_feature_edges);
}

TEST_CASE("FeatureTree: closest points on lines equal brute force; arclength", "[core]") {
  const TriangleSurface s = voroclip::read_surface(kSurfaces + "fandisk.obj");
  const FeatureLines lines = voroclip::extract_feature_lines(s);
  const FeatureTree tree(s, lines);
  REQUIRE(tree.nb_lines() == lines.nb_lines());
  const std::uint64_t seed = 99;
  std::cout << "FeatureTree brute-force test seed " << seed << std::endl;
  std::mt19937_64 rng(seed);
  const SurfaceTree st(s);
  std::uniform_real_distribution<double> u(0, 1);
  for (int q = 0; q < 500; ++q) {
    V3 p;
    for (int k = 0; k < 3; ++k) {
      p[static_cast<std::size_t>(k)] =
          st.bbox_lo()[k] + u(rng) * (st.bbox_hi()[k] - st.bbox_lo()[k]);
    }
    double best = std::numeric_limits<double>::infinity();
    for (std::uint32_t l = 0; l < lines.nb_lines(); ++l) {
      for (std::uint32_t i = lines.line_begin[l]; i + 1 < lines.line_begin[l + 1]; ++i) {
        best = std::min(best,
                        segment_distance2(p, at(&s.xyz[3 * std::size_t{lines.line_vertices[i]}]),
                                          at(&s.xyz[3 * std::size_t{lines.line_vertices[i + 1]}])));
      }
    }
    const FeatureTree::Closest c = tree.closest(p.data());
    CHECK(c.distance2 == Approx(best).epsilon(1e-12));
    // The arclength parametrisation gives the same point back.
    V3 q2, tangent;
    tree.eval(c.line, c.arclength, q2.data(), tangent.data());
    const V3 d = q2 - at(c.point);
    CHECK(dot(d, d) <= 1e-20);
    if (c.t > 0 && c.t < 1) CHECK(dot(tangent, at(c.tangent)) == Approx(1.0));
    // Restricted to its own line, the same answer.
    const FeatureTree::Closest own = tree.closest(p.data(), c.line);
    CHECK(own.distance2 == c.distance2);
    CHECK(own.segment == c.segment);
  }
  // eval clamps open lines and wraps closed ones.
  const TriangleSurface cyl = cylinder(64);
  const FeatureLines cl = voroclip::extract_feature_lines(cyl);
  const FeatureTree ct(cyl, cl);
  const double len = ct.length(0);
  CHECK(len == Approx(128 * std::sin(M_PI / 64)));
  V3 a, b;
  ct.eval(0, 0.3, a.data());
  ct.eval(0, 0.3 + 2 * len, b.data());
  CHECK(std::sqrt(dot(a - b, a - b)) <= 1e-12);
  ct.eval(0, -0.1, b.data());
  ct.eval(0, len - 0.1, a.data());
  CHECK(std::sqrt(dot(a - b, a - b)) <= 1e-12);
  const FeatureTree cubes(cube(), voroclip::extract_feature_lines(cube()));
  cubes.eval(0, 5, a.data());
  CHECK(a == V3{1, 0, 0});  // line 0 is 0 -> 1, length 1: clamped
  cubes.eval(0, -5, a.data());
  CHECK(a == V3{0, 0, 0});
}

TEST_CASE("SurfaceTree: triangles growing geometrically (a deep heuristic tree)",
          "[core][regression]") {
  // Each triangle 2.5 times the previous one, side by side: the last one is larger than
  // all the others together, so the area heuristic splits off a few of the largest at
  // each level (depth 64 here, against 8 for median splits). The build switches to median
  // splits below depth 48, which bounds the traversal's stack (bvh.h). Sizes up to
  // 2.5^160 ~ 1e63: squares stay far from overflow.
  TriangleSurface s;
  s.source = "geometric";
  const std::uint32_t n = 160;
  double x = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    const double size = std::pow(2.5, i);
    s.xyz.insert(s.xyz.end(), {x, 0, 0, x + size, 0, 0, x, size, 0.001 * size});
    s.triangles.insert(s.triangles.end(), {3 * i, 3 * i + 1, 3 * i + 2});
    x += size;
  }
  const SurfaceTree tree(s);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  for (int q = 0; q < 200; ++q) {
    // Near a random triangle, at its scale (the oracle is well conditioned there).
    const auto t = static_cast<std::uint32_t>(rng() % n);
    const double* a = &s.xyz[9 * std::size_t{t}];
    const double size = s.xyz[9 * std::size_t{t} + 3] - a[0];
    const V3 p = {a[0] + size * (2 * u(rng) - 0.5), size * u(rng), size * (u(rng) - 0.5)};
    CHECK(tree.closest(p.data()).distance2 == Approx(brute_force2(s, p)).epsilon(1e-9));
  }
}
