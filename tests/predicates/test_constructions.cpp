// circumcenter2d and plane_bisectors_point3d (predicates.h, "Constructions") against exact
// rational solutions (GMP), on random, nearly degenerate and wide-range input: the
// families of the fuzz_sites findings they fix (sites 2.7e-48 apart among others 1e-28
// away; a plane and two bisectors of sites 3e-14 apart).
#include <catch2/catch.hpp>
#include <gmpxx.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include "exact_oracle.h"
#include "voroclip/core.h"
#include "voroclip/predicates.h"

using namespace voroclip;
using namespace voroclip::test;

namespace {

using Q = mpq_class;
using P3 = std::array<double, 3>;

Q q(double x) { return Q(x); }

// The exact circumcentre of a, b, c (2D); false for collinear points.
bool exact_circumcenter2d(const P3& a, const P3& b, const P3& c, Q (&x)[2]) {
  const Q bx = q(b[0]) - q(a[0]), by = q(b[1]) - q(a[1]);
  const Q cx = q(c[0]) - q(a[0]), cy = q(c[1]) - q(a[1]);
  const Q det = bx * cy - by * cx;
  if (det == 0) return false;
  const Q lb = bx * bx + by * by, lc = cx * cx + cy * cy;
  x[0] = q(a[0]) + (cy * lb - by * lc) / (2 * det);
  x[1] = q(a[1]) + (bx * lc - cx * lb) / (2 * det);
  return true;
}

// The exact point of plane (a, b, c) ∩ bisector(p0, p1) ∩ bisector(p0, p2), by Cramer on the
// three plane equations n . x = n . a, (p_k - p0) . x = (|p_k|^2 - |p0|^2) / 2.
bool exact_plane_bisectors(const std::array<P3, 6>& p, Q (&x)[3]) {
  Q m[3][3], r[3];
  const auto v = [&](int i, int k) {
    return q(p[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)]);
  };
  Q w1[3], w2[3];
  for (int k = 0; k < 3; ++k) {
    w1[k] = v(1, k) - v(0, k);
    w2[k] = v(2, k) - v(0, k);
  }
  m[0][0] = w1[1] * w2[2] - w1[2] * w2[1];
  m[0][1] = w1[2] * w2[0] - w1[0] * w2[2];
  m[0][2] = w1[0] * w2[1] - w1[1] * w2[0];
  r[0] = m[0][0] * v(0, 0) + m[0][1] * v(0, 1) + m[0][2] * v(0, 2);
  for (int s = 1; s <= 2; ++s) {
    Q l = 0;
    for (int k = 0; k < 3; ++k) {
      m[s][k] = v(3 + s, k) - v(3, k);
      l += v(3 + s, k) * v(3 + s, k) - v(3, k) * v(3, k);
    }
    r[s] = l / 2;
  }
  const auto det3 = [](const Q(&a)[3][3]) -> Q {
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
           a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
  };
  const Q d = det3(m);
  if (d == 0) return false;
  for (int c = 0; c < 3; ++c) {
    Q mc[3][3];
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 3; ++k) mc[i][k] = k == c ? r[i] : m[i][k];
    }
    x[c] = det3(mc) / d;
  }
  return true;
}

P3 random_point(Rng& rng) {
  return {uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)};
}

double linf(const P3& a, const P3& b) {
  return std::max(std::max(std::fabs(a[0] - b[0]), std::fabs(a[1] - b[1])), std::fabs(a[2] - b[2]));
}

}  // namespace

TEST_CASE("circumcenter2d: within its bound of the exact centre, however flat",
          "[predicates][exact][degenerate]") {
  const std::uint64_t seed = seed_for(0xc2d);
  INFO("seed " << seed);
  Rng rng(seed);
  std::size_t failures = 0, collinear = 0;
  for (std::size_t it = 0; it < scaled(4000); ++it) {
    std::array<P3, 3> p;
    const int kind = static_cast<int>(it % 4);
    for (auto& x : p) x = random_point(rng);
    if (kind == 1) {
      // c at height 2^-m off the line through a and b.
      const double t = uniform(rng, -1, 2),
                   h = std::ldexp(1.0, -static_cast<int>(rand_int(rng, 1, 70)));
      p[2] = {p[0][0] + t * (p[1][0] - p[0][0]) - h * (p[1][1] - p[0][1]),
              p[0][1] + t * (p[1][1] - p[0][1]) + h * (p[1][0] - p[0][0]), 0};
    } else if (kind == 2) {
      // The fuzz finding's shape: b and c 2^-m apart, 2^-e from a, all near the origin.
      const double s = std::ldexp(1.0, -static_cast<int>(rand_int(rng, 20, 100)));
      for (auto& x : p) x = {s * x[0], s * x[1], 0};
      const double d = s * std::ldexp(1.0, -static_cast<int>(rand_int(rng, 10, 60)));
      p[2] = {p[1][0] + d * uniform(rng, -1, 1), p[1][1] + d * uniform(rng, -1, 1), 0};
    } else if (kind == 3) {
      for (auto& x : p) x = {random_wide(rng, -60, 60), random_wide(rng, -60, 60), 0};
    }
    Q x[2];
    double c[2];
    if (!exact_circumcenter2d(p[0], p[1], p[2], x)) {
      ++collinear;
      CHECK_THROWS_AS(circumcenter2d(p[0].data(), p[1].data(), p[2].data(), c), Error);
      continue;
    }
    circumcenter2d(p[0].data(), p[1].data(), p[2].data(), c);
    const double size = linf(p[1], p[0]) + linf(p[2], p[0]);
    for (int t = 0; t < 2; ++t) {
      const double xt = x[t].get_d();
      const double allowed = 2 * kConstructionLimit * size + 0x1p-49 * std::fabs(xt - p[0][t]) +
                             0x1p-52 * std::fabs(xt);
      if (!std::isfinite(c[t]) || abs(x[t] - Q(c[t])) > Q(allowed)) {
        ++failures;
        FAIL_CHECK("kind " << kind << " a " << hex(p[0][0]) << " " << hex(p[0][1]) << " b "
                           << hex(p[1][0]) << " " << hex(p[1][1]) << " c " << hex(p[2][0]) << " "
                           << hex(p[2][1]) << ": coordinate " << t << " is " << hex(c[t])
                           << ", exactly " << hex(xt));
        break;
      }
    }
  }
  INFO(collinear << " collinear");
  CHECK(failures == 0);
  // Collinear and non-finite input throws.
  const double o[2] = {0, 0}, a[2] = {1, 1}, b[2] = {2, 2};
  const double inf[2] = {std::numeric_limits<double>::infinity(), 0};
  double c[2];
  CHECK_THROWS_AS(circumcenter2d(o, a, b, c), Error);
  CHECK_THROWS_AS(circumcenter2d(o, a, inf, c), Error);
}

TEST_CASE("plane_bisectors_point3d: within its bound of the exact point, however close the sites",
          "[predicates][exact][degenerate]") {
  const std::uint64_t seed = seed_for(0xfb3);
  INFO("seed " << seed);
  Rng rng(seed);
  std::size_t failures = 0, none = 0;
  for (std::size_t it = 0; it < scaled(4000); ++it) {
    // a, b, c (the plane), p0, p1, p2 (the sites).
    std::array<P3, 6> p;
    for (auto& x : p) x = random_point(rng);
    const int kind = static_cast<int>(it % 4);
    if (kind == 1 || kind == 2) {
      // Two (kind 1) or three (kind 2) sites within 2^-m of each other: p2 near p1 is the
      // finding's shape (bisectors of p0 meeting at a tiny angle).
      const double d = std::ldexp(1.0, -static_cast<int>(rand_int(rng, 10, 50)));
      p[5] = {p[4][0] + d * uniform(rng, -1, 1), p[4][1] + d * uniform(rng, -1, 1),
              p[4][2] + d * uniform(rng, -1, 1)};
      if (kind == 2) {
        p[3] = {p[4][0] + d * uniform(rng, -1, 1), p[4][1] + d * uniform(rng, -1, 1),
                p[4][2] + d * uniform(rng, -1, 1)};
      }
    } else if (kind == 3) {
      const int e = static_cast<int>(rand_int(rng, -60, 60));
      for (auto& x : p) x = {std::ldexp(x[0], e), std::ldexp(x[1], e), std::ldexp(x[2], e)};
    }
    Q x[3];
    double c[3] = {7, 7, 7};
    const bool ok = plane_bisectors_point3d(p[0].data(), p[1].data(), p[2].data(), p[3].data(),
                                            p[4].data(), p[5].data(), c);
    if (!exact_plane_bisectors(p, x)) {
      ++none;
      CHECK_FALSE(ok);
      continue;
    }
    REQUIRE(ok);
    const double size = linf(p[4], p[3]) + linf(p[5], p[3]) + linf(p[0], p[3]);
    for (int t = 0; t < 3; ++t) {
      const double xt = x[t].get_d();
      const double allowed = 2 * kConstructionLimit * size + 0x1p-49 * std::fabs(xt - p[3][t]) +
                             0x1p-52 * std::fabs(xt);
      if (!std::isfinite(c[t]) || abs(x[t] - Q(c[t])) > Q(allowed)) {
        ++failures;
        FAIL_CHECK("kind " << kind << " it " << it << ": coordinate " << t << " is " << hex(c[t])
                           << ", exactly " << hex(xt));
        break;
      }
    }
  }
  INFO(none << " without a unique point");
  CHECK(failures == 0);
  // The finding's point: the plane y = 0, sites 2, 7, 13 of tests/clip/fuzz_regressions/
  // clip3d_near_coincident_facet_point.xyz; bisector(7, 13) is x = 0.875 + 1.4e-14.
  const double a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, cc[3] = {1, 0, 1};
  const double s2[3] = {1.0625, 1.0625, 0.31248479732312262};
  const double s7[3] = {0.87499999999999989, 0.87499999999999989, 0.87499999999999989};
  const double s13[3] = {0.87500000000002942, 0.87499999999999989, 0.87499999999999989};
  double y[3];
  REQUIRE(plane_bisectors_point3d(a, b, cc, s2, s7, s13, y));
  CHECK(std::fabs(y[1]) <= 0x1p-52);
  CHECK(std::fabs(y[0] - 0.5 * (s7[0] + s13[0])) <= 0x1p-52);
}
