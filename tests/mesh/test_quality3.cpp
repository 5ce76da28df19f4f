// tet_shape / tet_quality: closed forms (regular, right-corner and sliver tets),
// independent formulas on random tets (dihedral angles by projection on the plane
// orthogonal to the edge, circumradius by a linear solve, areas by Heron), similarity
// invariance, exact degeneracy and orientation, the data README's dihedral extremes of the
// shared meshes, and identical results for 1 and N threads.
#include <catch2/catch.hpp>

#include <tbb/global_control.h>

#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "support/threads.h"
#include "voroclip/mesh.h"

using voroclip::TetQuality;
using voroclip::TetShape;

namespace {

const std::string kMeshes = std::string(VOROCLIP_SHARED_DATA_DIR) + "/tetmeshes/";
constexpr double kDeg = 180.0 / M_PI;

using V3 = Eigen::Vector3d;

TetShape shape_of(const std::array<V3, 4>& p) {
  return voroclip::tet_shape(p[0].data(), p[1].data(), p[2].data(), p[3].data());
}

// Oracles, written differently from the library.
double dihedral_by_projection(const std::array<V3, 4>& p, int i, int j) {
  int k = -1, l = -1;
  for (int m = 0; m < 4; ++m) {
    if (m == i || m == j) continue;
    (k < 0 ? k : l) = m;
  }
  const V3 e = (p[j] - p[i]).normalized();
  const V3 u = (p[k] - p[i]) - (p[k] - p[i]).dot(e) * e;
  const V3 v = (p[l] - p[i]) - (p[l] - p[i]).dot(e) * e;
  return std::atan2(u.cross(v).norm(), u.dot(v)) * kDeg;
}

double heron(const V3& a, const V3& b, const V3& c) {
  const double x = (b - a).norm(), y = (c - b).norm(), z = (a - c).norm();
  const double s = (x + y + z) / 2;
  return std::sqrt(std::max(0.0, s * (s - x) * (s - y) * (s - z)));
}

struct Oracle {
  double q1, q2, q3, q4, volume;
};

Oracle oracle(const std::array<V3, 4>& p) {
  Oracle o{180, 0, 0, 0, 0};
  for (const auto& e : TetShape::kTetEdges) {
    const double a = dihedral_by_projection(p, e[0], e[1]);
    o.q1 = std::min(o.q1, a);
    o.q2 = std::max(o.q2, a);
  }
  Eigen::Matrix3d m;
  Eigen::Vector3d rhs;
  for (int i = 0; i < 3; ++i) {
    m.row(i) = 2 * (p[i + 1] - p[0]).transpose();
    rhs[i] = p[i + 1].squaredNorm() - p[0].squaredNorm();
  }
  const V3 centre = m.fullPivLu().solve(rhs);
  const double r_circ = (centre - p[0]).norm();
  o.volume = (p[1] - p[0]).dot((p[2] - p[0]).cross(p[3] - p[0])) / 6;
  const double area = heron(p[1], p[2], p[3]) + heron(p[0], p[2], p[3]) + heron(p[0], p[1], p[3]) +
                      heron(p[0], p[1], p[2]);
  const double r_in = 3 * std::fabs(o.volume) / area;
  o.q3 = 3 * r_in / r_circ;
  double l2 = 0;
  for (const auto& e : TetShape::kTetEdges) l2 += (p[e[1]] - p[e[0]]).squaredNorm();
  o.q4 = 12 * std::cbrt(9 * o.volume * o.volume) / l2;
  return o;
}

std::array<V3, 4> random_tet(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  for (;;) {
    std::array<V3, 4> p;
    for (V3& v : p) v = V3(u(rng), u(rng), u(rng));
    const Oracle o = oracle(p);
    if (o.q3 > 0.05) return p;  // the oracles lose digits on slivers: test those apart
  }
}

}  // namespace

TEST_CASE("tet_shape: the regular tetrahedron", "[mesh][quality]") {
  const std::array<V3, 4> p = {V3(1, 1, 1), V3(1, -1, -1), V3(-1, 1, -1), V3(-1, -1, 1)};
  const TetShape s = shape_of(p);
  const double angle = std::acos(1.0 / 3) * kDeg;  // 70.5288 degrees
  CHECK_FALSE(s.degenerate);
  CHECK_FALSE(s.positive);  // det(p1 - p0, p2 - p0, p3 - p0) = -16
  CHECK(s.volume == Approx(-8.0 / 3).epsilon(1e-15));
  for (const double a : s.dihedral_deg) CHECK(a == Approx(angle).epsilon(1e-14));
  CHECK(s.q1_deg == Approx(70.52877936550931).epsilon(1e-14));
  CHECK(s.q2_deg == Approx(angle).epsilon(1e-14));
  CHECK(s.q3 == Approx(1).epsilon(1e-14));
  CHECK(s.q4 == Approx(1).epsilon(1e-14));
}

TEST_CASE("tet_shape: the right-corner tetrahedron", "[mesh][quality]") {
  const std::array<V3, 4> p = {V3(0, 0, 0), V3(1, 0, 0), V3(0, 1, 0), V3(0, 0, 1)};
  const TetShape s = shape_of(p);
  CHECK(s.positive);
  CHECK(s.volume == Approx(1.0 / 6).epsilon(1e-15));
  // 90 degrees along the axes, acos(1/sqrt(3)) along the slanted face's edges.
  for (int k = 0; k < 3; ++k) CHECK(s.dihedral_deg[k] == Approx(90).epsilon(1e-14));
  for (int k = 3; k < 6; ++k) {
    CHECK(s.dihedral_deg[k] == Approx(std::acos(1 / std::sqrt(3.0)) * kDeg).epsilon(1e-14));
  }
  CHECK(s.q1_deg == Approx(54.735610317245346).epsilon(1e-14));
  CHECK(s.q2_deg == Approx(90).epsilon(1e-14));
  CHECK(s.q3 == Approx(std::sqrt(3.0) - 1).epsilon(1e-14));  // r_in = 1/(3+sqrt 3), R = sqrt 3/2
  CHECK(s.q4 == Approx(12 * std::cbrt(0.25) / 9).epsilon(1e-14));  // V = 1/6, sum l^2 = 9
}

TEST_CASE("tet_shape: slivers, needles and caps", "[mesh][quality]") {
  // The classic sliver: a square's corners lifted alternately by h. Its dihedral angles
  // at the two long edges are 180 - 2 atan(h); the other four are small.
  for (const double h : {0.5, 0.1, 1e-3, 1e-6}) {
    INFO("h = " << h);
    const std::array<V3, 4> p = {V3(1, 0, 0), V3(-1, 0, 0), V3(0, 1, h), V3(0, -1, h)};
    const TetShape s = shape_of(p);
    CHECK(s.q2_deg == Approx(180 - 2 * std::atan(h) * kDeg).epsilon(1e-13));
    CHECK(s.dihedral_deg[0] == Approx(180 - 2 * std::atan(h) * kDeg).epsilon(1e-13));  // p0p1
    CHECK(s.dihedral_deg[5] == Approx(180 - 2 * std::atan(h) * kDeg).epsilon(1e-13));  // p2p3
    // The four other edges, against the projection oracle.
    for (int k = 1; k < 5; ++k) {
      CHECK(s.dihedral_deg[k] ==
            Approx(dihedral_by_projection(p, TetShape::kTetEdges[k][0], TetShape::kTetEdges[k][1]))
                .epsilon(1e-9));
    }
    CHECK(s.q4 == Approx(12 * std::cbrt(4 * h * h) / (16 + 4 * h * h)).epsilon(1e-13));
    CHECK(s.volume == Approx(-2 * h / 3).epsilon(1e-13));  // det = -4h (p1 - p0 = (-2, 0, 0))
    // Q3: the four faces have the area sqrt(1 + h^2), so r_in = 3 V / A -> 0 like h, and
    // R -> 1: Q3 -> 0 although every edge is long.
    const double area = 4 * heron(p[0], p[1], p[2]);
    const double r_in = 3 * (2 * h / 3) / area;
    const double r_circ = std::sqrt(1 + h * h / 4);  // the centre is (0, 0, h / 2)
    CHECK(s.q3 == Approx(3 * r_in / r_circ).epsilon(1e-9));
  }
  // A needle (one long edge) and a cap (a vertex over the opposite face's centroid).
  const std::array<V3, 4> needle = {V3(0, 0, 0), V3(100, 0, 0), V3(0, 1, 0), V3(0, 0, 1)};
  const std::array<V3, 4> cap = {V3(1, 0, 0), V3(-0.5, std::sqrt(0.75), 0),
                                 V3(-0.5, -std::sqrt(0.75), 0), V3(0, 0, 1e-3)};
  for (const auto& p : {needle, cap}) {
    const TetShape s = shape_of(p);
    const Oracle o = oracle(p);
    CHECK(s.q1_deg == Approx(o.q1).epsilon(1e-9));
    CHECK(s.q2_deg == Approx(o.q2).epsilon(1e-9));
    CHECK(s.q3 == Approx(o.q3).epsilon(1e-9));
    CHECK(s.q4 == Approx(o.q4).epsilon(1e-12));
  }
  // The cap's base edges: the side faces rise at atan(h / r_in(base)) = atan(0.002).
  CHECK(shape_of(cap).q1_deg == Approx(std::atan(1e-3 / 0.5) * kDeg).epsilon(1e-9));
}

TEST_CASE("tet_shape: independent formulas on random tets", "[mesh][quality]") {
  const std::uint64_t seed = 11;
  std::cout << "tet_shape random test seed " << seed << std::endl;
  std::mt19937_64 rng(seed);
  for (int n = 0; n < 2000; ++n) {
    const std::array<V3, 4> p = random_tet(rng);
    const TetShape s = shape_of(p);
    const Oracle o = oracle(p);
    for (int k = 0; k < 6; ++k) {
      CHECK(s.dihedral_deg[k] ==
            Approx(dihedral_by_projection(p, TetShape::kTetEdges[k][0], TetShape::kTetEdges[k][1]))
                .epsilon(1e-10));
    }
    CHECK(s.q1_deg == Approx(o.q1).epsilon(1e-10));
    CHECK(s.q2_deg == Approx(o.q2).epsilon(1e-10));
    CHECK(s.q3 == Approx(o.q3).epsilon(1e-10));
    CHECK(s.q4 == Approx(o.q4).epsilon(1e-12));
    CHECK(s.volume == Approx(o.volume).epsilon(1e-12));
    CHECK(s.positive == (o.volume > 0));
    // Angles of a tet: each face's three dihedral angles at its edges exceed 180 degrees
    // in sum (a spherical triangle's angle sum), and Q's are in (0, 1].
    CHECK(s.q3 <= 1 + 1e-12);
    CHECK(s.q4 <= 1 + 1e-12);
  }
}

TEST_CASE("tet_shape: invariant under similarity transforms", "[mesh][quality]") {
  const std::uint64_t seed = 12;
  std::cout << "tet_shape similarity test seed " << seed << std::endl;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int n = 0; n < 300; ++n) {
    const std::array<V3, 4> p = random_tet(rng);
    const TetShape s = shape_of(p);
    // Powers of two: bit for bit.
    for (const double scale : {0x1p-600, 0x1p-40, 0x1p40, 0x1p600}) {
      std::array<V3, 4> q;
      for (int k = 0; k < 4; ++k) q[k] = scale * p[k];
      const TetShape t = shape_of(q);
      for (int k = 0; k < 6; ++k) CHECK(t.dihedral_deg[k] == s.dihedral_deg[k]);
      CHECK(t.q3 == s.q3);
      CHECK(t.q4 == s.q4);
    }
    // Rotation, any scale, translation, reflection: equal to rounding.
    const Eigen::Matrix3d rot =
        Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized().toRotationMatrix();
    for (const double scale : {1e-9, 3.7, 1e9}) {
      // A shift of a few tet sizes: a far shift would round the coordinates themselves.
      const V3 shift = scale * V3(10 * u(rng), u(rng), 3 * u(rng));
      std::array<V3, 4> q, r;
      for (int k = 0; k < 4; ++k) {
        q[k] = scale * (rot * p[k]) + shift;
        r[k] = V3(-q[k].x(), q[k].y(), q[k].z());
      }
      for (const auto& tet : {q, r}) {
        const TetShape t = shape_of(tet);
        for (int k = 0; k < 6; ++k)
          CHECK(t.dihedral_deg[k] == Approx(s.dihedral_deg[k]).epsilon(1e-9));
        CHECK(t.q3 == Approx(s.q3).epsilon(1e-9));
        CHECK(t.q4 == Approx(s.q4).epsilon(1e-9));
      }
      CHECK(shape_of(r).positive != shape_of(q).positive);  // a reflection inverts
    }
  }
}

TEST_CASE("tet_shape: bit for bit at the ends of the exponent range", "[mesh][quality]") {
  // Small-integer tets scaled by powers of two down to subnormal coordinates (the edges'
  // largest component below 2^-1022: scaled by ldexp) and up to 2^1020 (scaled by one
  // multiplication with a power of two near the smallest normal): every coordinate and edge
  // is exact, so the angles and measures are those of the unscaled tet, bit for bit.
  std::mt19937_64 rng(31);
  std::uniform_int_distribution<int> coord(-7, 7);
  for (int n = 0; n < 200; ++n) {
    std::array<V3, 4> p;
    for (auto& v : p) v = V3(coord(rng), coord(rng), coord(rng));
    const TetShape s = shape_of(p);
    if (s.degenerate) continue;
    for (const double scale : {0x1p-1070, 0x1p-1060, 0x1p-1024, 0x1p-1019, 0x1p1000, 0x1p1019}) {
      std::array<V3, 4> q;
      for (int k = 0; k < 4; ++k) q[k] = scale * p[k];
      const TetShape t = shape_of(q);
      REQUIRE_FALSE(t.degenerate);
      CHECK(t.positive == s.positive);
      for (int k = 0; k < 6; ++k) CHECK(t.dihedral_deg[k] == s.dihedral_deg[k]);
      CHECK(t.q1_deg == s.q1_deg);
      CHECK(t.q3 == s.q3);
      CHECK(t.q4 == s.q4);
    }
  }
}

TEST_CASE("tet_shape: zero volume is decided exactly", "[mesh][quality][exact][degenerate]") {
  // Coplanar in exact arithmetic although no coordinate is small; and a repeated vertex.
  const std::array<V3, 4> flat = {V3(0.1, 0.2, 0.3), V3(1.1, 0.7, 0.3), V3(0.3, 1.9, 0.3),
                                  V3(0.7, 0.9, 0.3)};
  const std::array<V3, 4> twice = {V3(0, 0, 0), V3(1, 0, 0), V3(0, 1, 0), V3(1, 0, 0)};
  for (const auto& p : {flat, twice}) {
    const TetShape s = shape_of(p);
    CHECK(s.degenerate);
    CHECK(s.q1_deg == 0);
    CHECK(s.q2_deg == 180);
    CHECK(s.q3 == 0);
    CHECK(s.q4 == 0);
    CHECK(s.volume == 0);
  }
  // 2^-60 off the plane: not degenerate, a valid (terrible) tet; nothing is NaN.
  std::array<V3, 4> almost = flat;
  almost[3].z() = 0.3 + 0x1p-54;
  const TetShape s = shape_of(almost);
  CHECK_FALSE(s.degenerate);
  CHECK(s.q1_deg >= 0);
  CHECK(s.q1_deg < 1e-6);
  CHECK(s.q2_deg > 180 - 1e-6);
  CHECK(s.q3 >= 0);
  CHECK(s.q3 < 1e-6);
  CHECK(std::isfinite(s.q4));
}

TEST_CASE("tet_quality: inverted and degenerate tets are reported, not fatal",
          "[mesh][quality][degenerate]") {
  voroclip::TetMeshInput mesh;
  mesh.source = "hand";
  // A cube's corners, 5 tets (all det > 0), then one inverted and two degenerate.
  mesh.xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 0, 1, 1, 0, 1, 0, 1, 1, 1, 1, 1};
  mesh.tets = {0, 1, 2, 4, 1, 3, 2, 7, 1, 2, 4, 7, 1, 5, 7, 4, 2, 4, 7, 6, 0, 2, 1, 4,  // inverted
               0, 1, 3, 2,   // flat: z = 0
               0, 1, 0, 5};  // repeated vertex
  voroclip::TetQualityOptions options;
  options.keep_per_tet = true;
  const TetQuality q = voroclip::tet_quality(mesh, options);
  CHECK(q.nb_tets == 8);
  CHECK(q.nb_vertices == 8);
  CHECK(q.nb_used_vertices == 8);
  CHECK(q.nb_positive == 5);
  CHECK(q.nb_negative == 1);
  CHECK(q.inverted == std::vector<std::uint32_t>{5});
  CHECK(q.degenerate == std::vector<std::uint32_t>{6, 7});
  CHECK(q.q1_deg.min == 0);
  CHECK(q.q1_deg.argmin == 6);
  CHECK(q.q2_deg.max == 180);
  CHECK(q.q3.min == 0);
  CHECK(q.q4.min == 0);
  // The inverted tet has the shape of tet 0 (its mirror).
  CHECK(q.per_tet[5].q3 == Approx(q.per_tet[0].q3).epsilon(1e-15));
  // Statistics and histograms agree with the per-tet values.
  double sum = 0;
  for (const TetShape& s : q.per_tet) sum += s.q4;
  CHECK(q.q4.mean == Approx(sum / 8).epsilon(1e-15));
  std::uint64_t total = 0;
  for (const std::uint64_t c : q.q4_histogram) total += c;
  CHECK(total == 8);
  total = 0;
  for (const std::uint64_t c : q.dihedral_histogram) total += c;
  CHECK(total == 6 * 6);
  CHECK(q.min_dihedral_histogram[0] == 2);  // the degenerate tets, Q1 = 0
  // The right-corner tet 0: 54.7 and 90 degrees fall in those 1-degree bins.
  CHECK(q.min_dihedral_histogram[54] >= 1);
  // The reports name them.
  std::ostringstream text, json, svg;
  voroclip::write_quality_text(text, q, "hand");
  CHECK(text.str().find("WARNING: 1 inverted tet (oriented unlike the other 5): 5") !=
        std::string::npos);
  CHECK(text.str().find("WARNING: 2 degenerate tets (zero volume, exact): 6, 7") !=
        std::string::npos);
  voroclip::write_quality_json(json, q);
  CHECK(json.str().find("\"inverted_tets\":1") != std::string::npos);
  CHECK(json.str().find("\"degenerate\":[6,7]") != std::string::npos);
  voroclip::write_quality_svg(svg, q, "hand <&>");
  CHECK(svg.str().rfind("<svg", 0) == 0);
  CHECK(svg.str().find("hand &lt;&amp;&gt;: 8 tets, 1 inverted, 2 degenerate") !=
        std::string::npos);
  // Bad indices and coordinates are errors.
  mesh.tets.back() = 8;
  CHECK_THROWS_WITH(voroclip::tet_quality(mesh),
                    "hand: tet 7 has vertex 8, the mesh has 8 vertices (numbered from 0)");
}

TEST_CASE("tet_quality: the shared meshes' dihedral extremes of the data README",
          "[mesh][quality]") {
  struct Row {
    const char* name;
    double min_deg, max_deg;
    std::uint64_t below5;  // dihedral angles under 5 degrees
  };
  const Row rows[] = {
      {"sphere", 6.23, 163.94, 0},
      {"bunny", 6.27, 165.39, 0},
      {"homer", 0.38, 178.33, 190},
      {"rocker-arm", 2.57, 170.99, 11},
      {"elk", 2.24, 175.26, 45},
      {"fandisk", 3.89, 173.44, 4},
      {"skull_low_resolution", 5.74, 164.96, 0},
  };
  for (const Row& r : rows) {
    INFO(r.name);
    const voroclip::TetMeshInput mesh = voroclip::read_tet_mesh(kMeshes + r.name + ".mesh");
    const TetQuality q = voroclip::tet_quality(mesh);
    CHECK(q.nb_tets == mesh.nb_tets());
    CHECK(q.inverted.empty());
    CHECK(q.degenerate.empty());
    CHECK(q.nb_positive == q.nb_tets);  // TetGen's orientation
    CHECK(std::round(q.q1_deg.min * 100) / 100 == Approx(r.min_deg).margin(1e-9));
    CHECK(std::round(q.q2_deg.max * 100) / 100 == Approx(r.max_deg).margin(1e-9));
    CHECK(q.dihedral_deg.min == q.q1_deg.min);
    CHECK(q.dihedral_deg.max == q.q2_deg.max);
    std::uint64_t below5 = 0;
    for (int b = 0; b < 5; ++b) below5 += q.dihedral_histogram[static_cast<std::size_t>(b)];
    CHECK(below5 == r.below5);
    CHECK(q.q3.max <= 1 + 1e-12);
    CHECK(q.q4.max <= 1 + 1e-12);
  }
}

TEST_CASE("tet_quality: the same bits for 1 and 2 threads", "[mesh][quality][threads]") {
  const voroclip::TetMeshInput mesh = voroclip::read_tet_mesh(kMeshes + "rocker-arm.mesh");
  TetQuality one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = voroclip::tet_quality(mesh);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism,
                          voroclip_test::test_threads());
    two = voroclip::tet_quality(mesh);
  }
  for (const auto& [a, b] : {std::pair{one.q1_deg, two.q1_deg}, std::pair{one.q2_deg, two.q2_deg},
                             std::pair{one.q3, two.q3}, std::pair{one.q4, two.q4},
                             std::pair{one.dihedral_deg, two.dihedral_deg}}) {
    CHECK(a.min == b.min);
    CHECK(a.mean == b.mean);
    CHECK(a.max == b.max);
    CHECK(a.argmin == b.argmin);
    CHECK(a.argmax == b.argmax);
  }
  CHECK(one.dihedral_histogram == two.dihedral_histogram);
  CHECK(one.q4_histogram == two.q4_histogram);
}
