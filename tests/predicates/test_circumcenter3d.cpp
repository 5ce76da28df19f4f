// Tests of the circumcenter predicates (predicates.h, "Circumcenters of tetrahedra"):
// orient3d_circumcenter, circumcenter3d and circumcenter3d_enclosure.
//
// The oracle works from the contract alone, in rationals (GMP): the circumcenter x of
// p0..p3 solves 2 (p_k - p0) . (x - p0) = |p_k - p0|^2 (k = 1, 2, 3) by Cramer's rule, and
// the answer is the sign of the 3 x 3 determinant det[a - x; b - x; c - x] (orient3d's
// definition), not the implementation's reduced polynomial (circumcenter3d.h).
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <gmpxx.h>
#include <limits>
#include <sstream>
#include <string>

#include "circumcenter3d.h"
#include "exact_oracle.h"
#include "voroclip/core.h"
#include "voroclip/predicates.h"

using namespace voroclip;
using namespace voroclip::test;

namespace {

using P3 = std::array<double, 3>;
using Q = mpq_class;
using Q3 = std::array<Q, 3>;

template <class T>
T det3(const std::array<T, 3>& r0, const std::array<T, 3>& r1, const std::array<T, 3>& r2) {
  return r0[0] * (r1[1] * r2[2] - r1[2] * r2[1]) - r0[1] * (r1[0] * r2[2] - r1[2] * r2[0]) +
         r0[2] * (r1[0] * r2[1] - r1[1] * r2[0]);
}

// The exact circumcenter; false when the points are coplanar.
bool exact_circumcenter(const std::array<P3, 4>& p, Q3& x) {
  std::array<Q3, 3> rows;
  Q3 rhs;
  for (std::size_t k = 0; k < 3; ++k) {
    Q s = 0;
    for (std::size_t t = 0; t < 3; ++t) {
      rows[k][t] = 2 * (Q(p[k + 1][t]) - Q(p[0][t]));
      const Q d = Q(p[k + 1][t]) - Q(p[0][t]);
      s += d * d;
    }
    rhs[k] = s;
  }
  const Q det = det3(rows[0], rows[1], rows[2]);
  if (det == 0) return false;
  for (std::size_t t = 0; t < 3; ++t) {
    std::array<Q3, 3> m = rows;
    for (std::size_t k = 0; k < 3; ++k) m[k][t] = rhs[k];
    x[t] = Q(p[0][t]) + det3(m[0], m[1], m[2]) / det;
  }
  return true;
}

struct Case {
  P3 a, b, c;
  std::array<P3, 4> p;
};

std::string str(const P3& p) {
  std::ostringstream s;
  s << '(' << hex(p[0]) << ", " << hex(p[1]) << ", " << hex(p[2]) << ')';
  return s.str();
}

std::string describe(const Case& k) {
  return "a " + str(k.a) + " b " + str(k.b) + " c " + str(k.c) + " p0 " + str(k.p[0]) + " p1 " +
         str(k.p[1]) + " p2 " + str(k.p[2]) + " p3 " + str(k.p[3]);
}

// 2: throws (coplanar p); else -1, 0, +1.
int oracle(const Case& k) {
  Q3 x;
  if (!exact_circumcenter(k.p, x)) return 2;
  Q3 ra, rb, rc;
  for (std::size_t t = 0; t < 3; ++t) {
    ra[t] = Q(k.a[t]) - x[t];
    rb[t] = Q(k.b[t]) - x[t];
    rc[t] = Q(k.c[t]) - x[t];
  }
  return sgn(det3(ra, rb, rc));
}

int run(const Case& k, bool exact_stage) {
  try {
    const Sign s =
        exact_stage
            ? detail::orient3d_circumcenter_exact(k.a.data(), k.b.data(), k.c.data(), k.p[0].data(),
                                                  k.p[1].data(), k.p[2].data(), k.p[3].data())
            : orient3d_circumcenter(k.a.data(), k.b.data(), k.c.data(), k.p[0].data(),
                                    k.p[1].data(), k.p[2].data(), k.p[3].data());
    return static_cast<int>(s);
  } catch (const Error&) {
    return 2;
  }
}

int run_filter(const Case& k) {
  return detail::circumcenter_side_filter(k.a.data(), k.b.data(), k.c.data(), k.p[0].data(),
                                          k.p[1].data(), k.p[2].data(), k.p[3].data());
}

P3 random_point(Rng& rng) {
  return {uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)};
}
P3 grid_point(Rng& rng, long long top) {
  return {static_cast<double>(rand_int(rng, -top, top)),
          static_cast<double>(rand_int(rng, -top, top)),
          static_cast<double>(rand_int(rng, -top, top))};
}
P3 nudged(P3 p, Rng& rng, int ulps) {
  for (double& x : p) x = nudge(x, static_cast<int>(rand_int(rng, -ulps, ulps)));
  return p;
}
P3 scaled_point(const P3& p, int e) {
  return {std::ldexp(p[0], e), std::ldexp(p[1], e), std::ldexp(p[2], e)};
}
P3 axpy(const P3& p, const P3& q, double s) {
  return {p[0] + s * q[0], p[1] + s * q[1], p[2] + s * q[2]};
}

// The circumcenter in floating point (the usual formula, relative to p0).
P3 float_circumcenter(const std::array<P3, 4>& p) {
  double d[3][3];
  for (int k = 0; k < 3; ++k)
    for (int t = 0; t < 3; ++t)
      d[k][t] = p[static_cast<std::size_t>(k + 1)][static_cast<std::size_t>(t)] -
                p[0][static_cast<std::size_t>(t)];
  const auto cross = [](const double* u, const double* v, double* o) {
    o[0] = u[1] * v[2] - u[2] * v[1];
    o[1] = u[2] * v[0] - u[0] * v[2];
    o[2] = u[0] * v[1] - u[1] * v[0];
  };
  double c23[3], c31[3], c12[3];
  cross(d[1], d[2], c23);
  cross(d[2], d[0], c31);
  cross(d[0], d[1], c12);
  double l[3];
  for (int k = 0; k < 3; ++k) l[k] = d[k][0] * d[k][0] + d[k][1] * d[k][1] + d[k][2] * d[k][2];
  const double det = 2 * (d[0][0] * c23[0] + d[0][1] * c23[1] + d[0][2] * c23[2]);
  P3 x;
  for (std::size_t t = 0; t < 3; ++t)
    x[t] = p[0][t] + (l[0] * c23[t] + l[1] * c31[t] + l[2] * c12[t]) / det;
  return x;
}

enum class Family { random, grid, near, mixed, scaled };
constexpr std::array<Family, 5> kFamilies = {Family::random, Family::grid, Family::near,
                                             Family::mixed, Family::scaled};
const char* name(Family f) {
  switch (f) {
    case Family::random:
      return "random";
    case Family::grid:
      return "grid";
    case Family::near:
      return "near";
    case Family::mixed:
      return "mixed";
    case Family::scaled:
      return "scaled";
  }
  return "?";
}

Case make_case(Family fam, Rng& rng) {
  Case k{};
  switch (fam) {
    case Family::random:
      for (P3* q : {&k.a, &k.b, &k.c, &k.p[0], &k.p[1], &k.p[2], &k.p[3]}) *q = random_point(rng);
      break;
    case Family::grid: {
      if (coin(rng)) {
        // Small integers: coplanar sites and circumcenters on the plane occur often.
        for (P3* q : {&k.a, &k.b, &k.c, &k.p[0], &k.p[1], &k.p[2], &k.p[3]})
          *q = grid_point(rng, 2);
      } else {
        // Sites on a lattice sphere around an integer centre x, the plane through x (a
        // is x itself or a lattice point beside it): the sign is exactly zero unless the
        // sites are coplanar.
        const P3 x = grid_point(rng, 3);
        const auto& shell = sphere_points();
        for (auto& q : k.p) {
          const auto& v = shell[rng() % shell.size()];
          q = {x[0] + static_cast<double>(v[0]), x[1] + static_cast<double>(v[1]),
               x[2] + static_cast<double>(v[2])};
        }
        const P3 u = grid_point(rng, 3), w = grid_point(rng, 3);
        const double s = static_cast<double>(rand_int(rng, -2, 2));
        k.a = axpy(x, u, s);
        k.b = axpy(x, u, s + 1);
        k.c = axpy(x, w, 1);
        if (coin(rng)) k.c = axpy(k.c, grid_point(rng, 1), 1);  // off the centre, usually
      }
      break;
    }
    case Family::near: {
      // The plane passes at about 2^-m, m in [0, 60], from the circumcenter: from clearly
      // decided by the filter down to within rounding of it.
      for (auto& q : k.p) q = random_point(rng);
      const P3 x = float_circumcenter(k.p);
      const double h = std::ldexp(1.0, -static_cast<int>(rand_int(rng, 0, 60)));
      k.a = nudged(axpy(x, random_point(rng), h), rng, 2);
      k.b = nudged(axpy(k.a, random_point(rng), 1), rng, 2);
      k.c = nudged(axpy(k.a, random_point(rng), 1), rng, 2);
      if (coin(rng)) k.a = nudged(x, rng, 1);
      break;
    }
    case Family::mixed: {
      static constexpr int kSpreads[4] = {20, 45, 70, 120};
      const int spread = kSpreads[rng() % 4];
      for (P3* q : {&k.a, &k.b, &k.c, &k.p[0], &k.p[1], &k.p[2], &k.p[3]}) {
        if (rng() % 8 == 0) {
          *q = {random_mixed_coordinate(rng), random_mixed_coordinate(rng),
                random_mixed_coordinate(rng)};
        } else {
          *q = {random_wide(rng, -spread, spread), random_wide(rng, -spread, spread),
                random_wide(rng, -spread, spread)};
        }
      }
      break;
    }
    case Family::scaled: {
      Case base = make_case(coin(rng) ? Family::grid : Family::near, rng);
      const auto e = static_cast<int>(rand_int(rng, -900, 900));
      for (P3* q : {&base.a, &base.b, &base.c, &base.p[0], &base.p[1], &base.p[2], &base.p[3]})
        *q = scaled_point(*q, e);
      return base;
    }
  }
  return k;
}

// Three random points and a fourth at height h times |(p1 - p0) x (p2 - p0)| above their
// centroid: flatter and flatter tets as h goes to 0.
std::array<P3, 4> flat_tet(Rng& rng, double h) {
  std::array<P3, 4> p;
  for (auto& q : p) q = random_point(rng);
  const P3 u = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
  const P3 v = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
  const P3 nrm = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  p[3] = axpy({(p[0][0] + p[1][0] + p[2][0]) / 3, (p[0][1] + p[1][1] + p[2][1]) / 3,
               (p[0][2] + p[1][2] + p[2][2]) / 3},
              nrm, h);
  return p;
}

}  // namespace

TEST_CASE("orient3d_circumcenter: hand-derived cases", "[predicates][exact]") {
  // The unit cube's corners 0, e_x, e_y, e_z: circumcenter (1/2, 1/2, 1/2).
  const double p0[3] = {0, 0, 0}, p1[3] = {1, 0, 0}, p2[3] = {0, 1, 0}, p3[3] = {0, 0, 1};
  // The plane z = 1/2 through (0, 0, 1/2), (1, 0, 1/2), (0, 1, 1/2): counter-clockwise
  // seen from above, so a point below (z < 1/2) is positive: the centre is on it.
  const double a[3] = {0, 0, 0.5}, b[3] = {1, 0, 0.5}, c[3] = {0, 1, 0.5};
  CHECK(orient3d_circumcenter(a, b, c, p0, p1, p2, p3) == Sign::zero);
  const double a2[3] = {0, 0, 0.25}, b2[3] = {1, 0, 0.25}, c2[3] = {0, 1, 0.25};
  // Plane z = 1/4 (counter-clockwise from above): the centre at z = 1/2 is above: negative.
  CHECK(orient3d_circumcenter(a2, b2, c2, p0, p1, p2, p3) == Sign::negative);
  CHECK(orient3d_circumcenter(a2, c2, b2, p0, p1, p2, p3) == Sign::positive);
  // Any order of the four sites: the same circumcenter.
  CHECK(orient3d_circumcenter(a2, b2, c2, p3, p1, p0, p2) == Sign::negative);
  // Agreement with orient3d on the explicit centre.
  const double x[3] = {0.5, 0.5, 0.5};
  CHECK(orient3d(a2, b2, c2, x) == Sign::negative);
  // The enclosure holds the exact centre, tightly.
  double centre[3], hw[3];
  REQUIRE(circumcenter3d_enclosure(p0, p1, p2, p3, centre, hw));
  for (int k = 0; k < 3; ++k) {
    CHECK(std::fabs(centre[k] - 0.5) <= hw[k]);
    CHECK(hw[k] < 1e-12);
  }
}

TEST_CASE("orient3d_circumcenter agrees with the rational oracle on every family",
          "[predicates][exact][degenerate]") {
  const std::uint64_t seed = seed_for(0xc1c3d);
  INFO("seed " << seed);
  Rng rng(seed);
  for (const Family fam : kFamilies) {
    INFO("family " << name(fam));
    const std::size_t n = scaled(fam == Family::mixed ? 2000 : 8000);
    std::size_t failures = 0, zeros = 0, throws = 0, undecided = 0;
    for (std::size_t it = 0; it < n; ++it) {
      const Case k = make_case(fam, rng);
      const int want = oracle(k);
      const int got = run(k, false), exact = run(k, true), filt = run_filter(k);
      zeros += want == 0;
      throws += want == 2;
      undecided += filt == 0;
      // The filter decides only when the answer is certain.
      const bool ok = got == want && exact == want && (filt == 0 || filt == want);
      if (!ok) {
        ++failures;
        if (failures <= 10) {
          FAIL_CHECK(describe(k) << ": want " << want << " got " << got << " exact stage " << exact
                                 << " filter " << filt);
        }
      }
    }
    INFO(zeros << " on the plane, " << throws << " coplanar, " << undecided
               << " undecided by the filter, of " << n);
    CHECK(failures == 0);
    if (fam == Family::random) CHECK(undecided * 1000 <= n);
    if (fam == Family::grid) {
      // The family reaches exact ties and coplanar sites.
      CHECK(zeros > n / 10);
      CHECK(throws > n / 100);
    }
    if (fam == Family::near) {
      // Both stages at work.
      CHECK(undecided > n / 8);
      CHECK(undecided < n - n / 8);
    }
  }
}

TEST_CASE("orient3d_circumcenter: scale invariance and symmetries", "[predicates][exact]") {
  const std::uint64_t seed = seed_for(0xc1c3e);
  INFO("seed " << seed);
  Rng rng(seed);
  std::size_t failures = 0;
  for (std::size_t it = 0; it < scaled(500); ++it) {
    const Case k0 = make_case(it % 2 == 0 ? Family::near : Family::grid, rng);
    const int s0 = run(k0, false);
    // An odd permutation of (a, b, c) flips the sign; any permutation of the sites keeps it.
    Case flipped = k0;
    std::swap(flipped.a, flipped.b);
    Case permuted = k0;
    std::swap(permuted.p[0], permuted.p[3]);
    std::swap(permuted.p[1], permuted.p[2]);
    const int sf = run(flipped, false), sp = run(permuted, false);
    if ((s0 == 2 ? sf != 2 : sf != -s0) || sp != s0) {
      ++failures;
      FAIL_CHECK(describe(k0) << ": " << s0 << " flipped " << sf << " permuted " << sp);
    }
    for (int e = -500; e <= 500; e += 50 + static_cast<int>(rng() % 7)) {
      Case k = k0;
      for (P3* q : {&k.a, &k.b, &k.c, &k.p[0], &k.p[1], &k.p[2], &k.p[3]}) *q = scaled_point(*q, e);
      if (run(k, false) != s0) {
        ++failures;
        FAIL_CHECK("scale 2^" << e << ": " << describe(k0));
      }
    }
  }
  CHECK(failures == 0);
}

TEST_CASE("circumcenter3d_enclosure holds the exact circumcenter", "[predicates][exact]") {
  const std::uint64_t seed = seed_for(0xc1c3f);
  INFO("seed " << seed);
  Rng rng(seed);
  std::size_t failures = 0, refused = 0, tight = 0, n_random = 0;
  const std::size_t n = scaled(6000);
  for (std::size_t it = 0; it < n; ++it) {
    std::array<P3, 4> p;
    const int kind = static_cast<int>(it % 4);
    if (kind == 0) {
      for (auto& q : p) q = random_point(rng);
    } else if (kind == 1) {
      // Flatter and flatter: p3 at height 2^-m above the plane of p0, p1, p2.
      p = flat_tet(rng, std::ldexp(1.0, -static_cast<int>(rand_int(rng, 1, 60))));
    } else if (kind == 2) {
      // Mixed magnitudes, offset far from the origin.
      const P3 o = {random_wide(rng, -30, 30), random_wide(rng, -30, 30),
                    random_wide(rng, -30, 30)};
      const int e = static_cast<int>(rand_int(rng, -40, 10));
      for (auto& q : p) q = axpy(o, random_point(rng), std::ldexp(1.0, e));
    } else {
      const int e = static_cast<int>(rand_int(rng, -140, 140));
      for (auto& q : p) q = scaled_point(random_point(rng), e);
    }
    double centre[3], hw[3];
    Q3 x;
    const bool exists = exact_circumcenter(p, x);
    if (!circumcenter3d_enclosure(p[0].data(), p[1].data(), p[2].data(), p[3].data(), centre, hw)) {
      ++refused;
      continue;
    }
    if (!exists) {
      ++failures;
      FAIL_CHECK("an enclosure for coplanar points");
      continue;
    }
    bool inside = true;
    double radius = 0;
    for (std::size_t t = 0; t < 3; ++t) {
      inside = inside && abs(x[t] - Q(centre[t])) <= Q(hw[t]);
      radius = std::max(radius, std::fabs(centre[t] - p[0][t]));
    }
    if (!inside) {
      ++failures;
      FAIL_CHECK("p0 " << str(p[0]) << " p1 " << str(p[1]) << " p2 " << str(p[2]) << " p3 "
                       << str(p[3]) << ": the exact centre is outside the enclosure");
    }
    if (kind == 0) {
      ++n_random;
      tight += std::max({hw[0], hw[1], hw[2]}) < 1e-9 * radius;
    }
  }
  INFO(refused << " refused of " << n);
  CHECK(failures == 0);
  // Refused only for very flat tets; tight for ordinary ones.
  CHECK(refused < n / 8);
  CHECK(tight * 100 >= n_random * 99);
}

TEST_CASE("circumcenter3d is within a few ulps of the exact circumcenter, slivers included",
          "[predicates][exact]") {
  const std::uint64_t seed = seed_for(0xc3c3d);
  INFO("seed " << seed);
  Rng rng(seed);
  std::size_t failures = 0, coplanar = 0, slivers = 0;
  const std::size_t n = scaled(8000);
  for (std::size_t it = 0; it < n; ++it) {
    std::array<P3, 4> p;
    const int kind = static_cast<int>(it % 5);
    if (kind == 0) {
      for (auto& q : p) q = random_point(rng);
    } else if (kind == 1) {
      // p3 at height 2^-m above the plane of p0, p1, p2 (m up to 60).
      p = flat_tet(rng, std::ldexp(1.0, -static_cast<int>(rand_int(rng, 1, 60))));
    } else if (kind == 2) {
      // Slivers of the Delaunay kind: four points nearly on one sphere and nearly on one
      // great circle (heights 2^-m, alternating signs), whose floating-point determinant
      // is rounding error: the centre is still the sphere's, to a few ulps.
      const P3 o = random_point(rng);
      const double r = std::ldexp(1.0, static_cast<int>(rand_int(rng, -20, 4)));
      const double h = std::ldexp(1.0, -static_cast<int>(rand_int(rng, 20, 60)));
      for (std::size_t k = 0; k < 4; ++k) {
        const double t = 1.5707963267948966 * (static_cast<double>(k) + uniform(rng, -0.2, 0.2));
        const double z = (k % 2 == 0 ? h : -h) * uniform(rng, 0.5, 1);
        p[k] = {o[0] + r * std::cos(t), o[1] + r * std::sin(t), o[2] + r * z};
      }
      ++slivers;
    } else if (kind == 3) {
      const P3 o = {random_wide(rng, -30, 30), random_wide(rng, -30, 30),
                    random_wide(rng, -30, 30)};
      const int e = static_cast<int>(rand_int(rng, -40, 10));
      for (auto& q : p) q = axpy(o, random_point(rng), std::ldexp(1.0, e));
    } else {
      const int e = static_cast<int>(rand_int(rng, -140, 140));
      for (auto& q : p) q = scaled_point(random_point(rng), e);
    }
    Q3 x;
    if (!exact_circumcenter(p, x)) {
      ++coplanar;
      double c[3];
      CHECK_THROWS_AS(circumcenter3d(p[0].data(), p[1].data(), p[2].data(), p[3].data(), c), Error);
      continue;
    }
    double c[3];
    circumcenter3d(p[0].data(), p[1].data(), p[2].data(), p[3].data(), c);
    // The contract: within 2^-36 of the tet's size (the floating-point path, when its
    // proven bound allows), or a few ulps of the offset from p0 and of the result.
    double size = 0;
    for (std::size_t k = 1; k < 4; ++k) {
      size += std::sqrt((p[k][0] - p[0][0]) * (p[k][0] - p[0][0]) +
                        (p[k][1] - p[0][1]) * (p[k][1] - p[0][1]) +
                        (p[k][2] - p[0][2]) * (p[k][2] - p[0][2]));
    }
    for (std::size_t t = 0; t < 3; ++t) {
      const double xt = x[t].get_d();
      const double allowed =
          0x1p-35 * size + 0x1p-49 * std::fabs(xt - p[0][t]) + 0x1p-52 * std::fabs(xt);
      if (!std::isfinite(c[t]) || abs(x[t] - Q(c[t])) > Q(allowed)) {
        ++failures;
        FAIL_CHECK("kind " << kind << " p0 " << str(p[0]) << " p1 " << str(p[1]) << " p2 "
                           << str(p[2]) << " p3 " << str(p[3]) << ": coordinate " << t << " is "
                           << hex(c[t]) << ", exactly " << hex(xt));
        break;
      }
    }
  }
  INFO(coplanar << " coplanar, " << slivers << " slivers of " << n);
  CHECK(failures == 0);
  CHECK(slivers > 0);
}

TEST_CASE("circumcenter3d: a sliver whose floating-point determinant is zero",
          "[predicates][exact][degenerate]") {
  // Four points of the unit sphere nearly on its equator (heights +-2^-40): the rounded
  // determinant of the difference vectors is 0 or noise, the exact one is not; the centre
  // is the origin.
  const double h = 0x1p-40;
  const double z2 = std::sqrt(1 - h * h);
  const double p0[3] = {z2, 0, h}, p1[3] = {0, z2, -h}, p2[3] = {-z2, 0, h}, p3[3] = {0, -z2, -h};
  std::array<P3, 4> p = {P3{p0[0], p0[1], p0[2]}, P3{p1[0], p1[1], p1[2]}, P3{p2[0], p2[1], p2[2]},
                         P3{p3[0], p3[1], p3[2]}};
  Q3 x;
  REQUIRE(exact_circumcenter(p, x));
  double c[3];
  circumcenter3d(p0, p1, p2, p3, c);
  for (std::size_t t = 0; t < 3; ++t) {
    INFO("coordinate " << t << ": " << hex(c[t]) << ", exactly " << hex(x[t].get_d()));
    CHECK(abs(x[t] - Q(c[t])) <= Q(0x1p-50));
  }
  const double inf = std::numeric_limits<double>::infinity();
  const double far[3] = {inf, 0, 0};
  CHECK_THROWS_AS(circumcenter3d(p0, p1, p2, far, c), Error);
  CHECK_THROWS_AS(circumcenter3d(p0, p1, p2, p0, c), Error);
}

TEST_CASE("circumcenter3d: subnormal heights (exponents too far apart for expansions)",
          "[predicates][exact][degenerate]") {
  // Sites on the plane z = 0 moved off it by a few subnormal steps, as a CVT's sites
  // snapped to a face at z = 0 and moved by ulps: the expansions cannot hold the products
  // (the exponents span more than 1000), big integers do. The exact centre is compared
  // where it is a double; where its offset from p0 exceeds the double range, the result
  // must be infinite with the exact sign, never NaN.
  const std::uint64_t seed = seed_for(0x5ab);
  INFO("seed " << seed);
  Rng rng(seed);
  const double tiny = std::numeric_limits<double>::denorm_min();
  std::size_t finite = 0, overflow = 0;
  for (std::size_t it = 0; it < scaled(400); ++it) {
    std::array<P3, 4> p;
    for (auto& q : p) {
      const bool grid = it % 2 == 0;
      q = {grid ? 0.25 + 0.5 * static_cast<double>(rand_int(rng, 0, 3)) : uniform(rng, 0, 2),
           grid ? 0.25 + 0.5 * static_cast<double>(rand_int(rng, 0, 3)) : uniform(rng, 0, 2),
           tiny * static_cast<double>(rand_int(rng, -3, 3))};
    }
    Q3 x;
    if (!exact_circumcenter(p, x)) {
      double c[3];
      CHECK_THROWS_AS(circumcenter3d(p[0].data(), p[1].data(), p[2].data(), p[3].data(), c), Error);
      continue;
    }
    double c[3];
    circumcenter3d(p[0].data(), p[1].data(), p[2].data(), p[3].data(), c);
    for (std::size_t t = 0; t < 3; ++t) {
      INFO("p0 " << str(p[0]) << " p1 " << str(p[1]) << " p2 " << str(p[2]) << " p3 " << str(p[3])
                 << " coordinate " << t << ": " << hex(c[t]));
      REQUIRE_FALSE(std::isnan(c[t]));
      if (abs(x[t]) > Q(std::numeric_limits<double>::max())) {
        ++overflow;
        CHECK(std::isinf(c[t]));
        CHECK((c[t] > 0) == (x[t] > 0));
      } else {
        ++finite;
        const double xt = x[t].get_d();
        CHECK(abs(x[t] - Q(c[t])) <=
              Q(0x1p-49 * std::fabs(xt - p[0][t]) + 0x1p-52 * std::fabs(xt)) + Q(tiny));
      }
    }
  }
  INFO(finite << " finite coordinates, " << overflow << " beyond the double range");
  CHECK(finite > 0);
}

TEST_CASE("orient3d_circumcenter and the enclosure: coplanar sites and non-finite input",
          "[predicates][exact][degenerate]") {
  const double o[3] = {0, 0, 0}, x[3] = {1, 0, 0}, y[3] = {0, 1, 0}, xy[3] = {1, 1, 0};
  const double z[3] = {0, 0, 1};
  CHECK_THROWS_AS(orient3d_circumcenter(o, x, z, o, x, y, xy), Error);
  double centre[3], hw[3];
  CHECK_FALSE(circumcenter3d_enclosure(o, x, y, xy, centre, hw));
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double bad[3] = {nan, 0, 0}, huge[3] = {inf, 0, 0};
  CHECK_THROWS_AS(orient3d_circumcenter(bad, x, z, o, x, y, z), Error);
  CHECK_THROWS_AS(orient3d_circumcenter(o, x, z, o, x, huge, z), Error);
  CHECK_FALSE(circumcenter3d_enclosure(o, x, huge, z, centre, hw));
  CHECK_FALSE(circumcenter3d_enclosure(bad, x, y, z, centre, hw));
}

// ---------------------------------------------------------------------------------------
// orient2d_circumcenter: the same families; the oracle is the axis component of
// (b - a) x (x - a) at the exact circumcenter x (the contract's definition).

namespace {

std::size_t other(int axis, int k) { return static_cast<std::size_t>((axis + k) % 3); }

// 2: throws (coplanar p); else -1, 0, +1.
int oracle2d(const Case& k, int axis) {
  Q3 x;
  if (!exact_circumcenter(k.p, x)) return 2;
  const std::size_t i = other(axis, 1), j = other(axis, 2);
  const Q wi = Q(k.b[i]) - Q(k.a[i]), wj = Q(k.b[j]) - Q(k.a[j]);
  return sgn(wi * (x[j] - Q(k.a[j])) - wj * (x[i] - Q(k.a[i])));
}

int run2d(const Case& k, int axis, bool exact_stage) {
  try {
    const Sign s = exact_stage ? detail::orient2d_circumcenter_exact(axis, k.a.data(), k.b.data(),
                                                                     k.p[0].data(), k.p[1].data(),
                                                                     k.p[2].data(), k.p[3].data())
                               : orient2d_circumcenter(axis, k.a.data(), k.b.data(), k.p[0].data(),
                                                       k.p[1].data(), k.p[2].data(), k.p[3].data());
    return static_cast<int>(s);
  } catch (const Error&) {
    return 2;
  }
}

int run2d_filter(const Case& k, int axis) {
  return detail::circumcenter_orient2d_filter(axis, k.a.data(), k.b.data(), k.p[0].data(),
                                              k.p[1].data(), k.p[2].data(), k.p[3].data());
}

// Coordinates rotated: (x, y, z) -> (y, z, x). Axis k of the input is axis k - 1 (mod 3)
// of the result, with the same two projected coordinates in the same order.
P3 rotated(const P3& p) { return {p[1], p[2], p[0]}; }

}  // namespace

TEST_CASE("orient2d_circumcenter: hand-derived cases", "[predicates][exact]") {
  // The circumcenter of 0, e_x, e_y, e_z is (1/2, 1/2, 1/2).
  const double p0[3] = {0, 0, 0}, p1[3] = {1, 0, 0}, p2[3] = {0, 1, 0}, p3[3] = {0, 0, 1};
  // Axis 2, the plane (x, y): a -> (0, 0), b -> (1, 0); the centre (1/2, 1/2) is on the left.
  const double a2[3] = {0, 0, 5}, b2[3] = {1, 0, -3};
  CHECK(orient2d_circumcenter(2, a2, b2, p0, p1, p2, p3) == Sign::positive);
  CHECK(orient2d_circumcenter(2, b2, a2, p0, p1, p2, p3) == Sign::negative);
  CHECK(orient2d_circumcenter(2, a2, b2, p3, p2, p0, p1) == Sign::positive);
  // Axis 0, the plane (y, z); axis 1, the plane (z, x) (cyclic order).
  const double a0[3] = {5, 0, 0}, b0[3] = {2, 1, 0};
  CHECK(orient2d_circumcenter(0, a0, b0, p0, p1, p2, p3) == Sign::positive);
  const double a1[3] = {0, 3, 0}, b1[3] = {0, -1, 1};
  CHECK(orient2d_circumcenter(1, a1, b1, p0, p1, p2, p3) == Sign::positive);
  const double b1x[3] = {1, -1, 0};  // (z, x) from (0, 0) to (0, 1): the centre on the right
  CHECK(orient2d_circumcenter(1, a1, b1x, p0, p1, p2, p3) == Sign::negative);
  // The projection of the centre on the projected line (not the 3D line): zero.
  const double a3[3] = {0, 0.5, 7}, b3[3] = {1, 0.5, 9};
  CHECK(orient2d_circumcenter(2, a3, b3, p0, p1, p2, p3) == Sign::zero);
  CHECK(orient2d_circumcenter(0, a3, b3, p0, p1, p2, p3) == Sign::zero);      // (y, z): y = 1/2
  CHECK(orient2d_circumcenter(1, a3, b3, p0, p1, p2, p3) == Sign::positive);  // (z, x)
  // a and b with the same projection: zero whatever the centre.
  const double a4[3] = {3, 7, 1}, b4[3] = {3, 7, -4};
  CHECK(orient2d_circumcenter(2, a4, b4, p0, p1, p2, p3) == Sign::zero);
  // Agreement with orient2d on the explicit projected centre.
  const double c2d[2] = {0.5, 0.5}, a2d[2] = {0, 0}, b2d[2] = {1, 0};
  CHECK(orient2d(a2d, b2d, c2d) == Sign::positive);
}

TEST_CASE("orient2d_circumcenter agrees with the rational oracle on every family",
          "[predicates][exact][degenerate]") {
  const std::uint64_t seed = seed_for(0xc1c2d);
  INFO("seed " << seed);
  Rng rng(seed);
  for (const Family fam : kFamilies) {
    INFO("family " << name(fam));
    const std::size_t n = scaled(fam == Family::mixed ? 2000 : 8000);
    std::size_t failures = 0, zeros = 0, throws = 0, undecided = 0;
    for (std::size_t it = 0; it < n; ++it) {
      const Case k = make_case(fam, rng);
      const int axis = static_cast<int>(rng() % 3);
      const int want = oracle2d(k, axis);
      const int got = run2d(k, axis, false), exact = run2d(k, axis, true);
      const int filt = run2d_filter(k, axis);
      zeros += want == 0;
      throws += want == 2;
      undecided += filt == 0;
      const bool ok = got == want && exact == want && (filt == 0 || filt == want);
      if (!ok) {
        ++failures;
        if (failures <= 10) {
          FAIL_CHECK("axis " << axis << " " << describe(k) << ": want " << want << " got " << got
                             << " exact stage " << exact << " filter " << filt);
        }
      }
    }
    INFO(zeros << " on the line, " << throws << " coplanar, " << undecided
               << " undecided by the filter, of " << n);
    CHECK(failures == 0);
    if (fam == Family::random) CHECK(undecided * 1000 <= n);
    if (fam == Family::grid) {
      // The lattice family puts a and b on a line through the centre: exact zeros.
      CHECK(zeros > n / 10);
      CHECK(throws > n / 100);
    }
    if (fam == Family::near) {
      CHECK(undecided > n / 8);
      CHECK(undecided < n - n / 8);
    }
  }
}

TEST_CASE("orient2d_circumcenter: scale invariance and symmetries", "[predicates][exact]") {
  const std::uint64_t seed = seed_for(0xc1c2e);
  INFO("seed " << seed);
  Rng rng(seed);
  std::size_t failures = 0;
  for (std::size_t it = 0; it < scaled(500); ++it) {
    const Case k0 = make_case(it % 2 == 0 ? Family::near : Family::grid, rng);
    const int axis = static_cast<int>(it % 3);
    const int s0 = run2d(k0, axis, false);
    // Swapping a and b flips the sign; any permutation of the sites keeps it; rotating the
    // coordinates moves the axis.
    Case flipped = k0;
    std::swap(flipped.a, flipped.b);
    Case permuted = k0;
    std::swap(permuted.p[0], permuted.p[2]);
    std::swap(permuted.p[1], permuted.p[3]);
    Case rot = k0;
    for (P3* q : {&rot.a, &rot.b, &rot.p[0], &rot.p[1], &rot.p[2], &rot.p[3]}) *q = rotated(*q);
    const int sf = run2d(flipped, axis, false), sp = run2d(permuted, axis, false);
    const int sr = run2d(rot, (axis + 2) % 3, false);
    if ((s0 == 2 ? sf != 2 : sf != -s0) || sp != s0 || sr != s0) {
      ++failures;
      FAIL_CHECK("axis " << axis << " " << describe(k0) << ": " << s0 << " flipped " << sf
                         << " permuted " << sp << " rotated " << sr);
    }
    for (int e = -500; e <= 500; e += 50 + static_cast<int>(rng() % 7)) {
      Case k = k0;
      for (P3* q : {&k.a, &k.b, &k.c, &k.p[0], &k.p[1], &k.p[2], &k.p[3]}) *q = scaled_point(*q, e);
      if (run2d(k, axis, false) != s0) {
        ++failures;
        FAIL_CHECK("scale 2^" << e << ": axis " << axis << " " << describe(k0));
      }
    }
  }
  CHECK(failures == 0);
}

TEST_CASE("orient2d_circumcenter: the centre exactly on the projected line, at every scale",
          "[predicates][exact][degenerate]") {
  // Sites symmetric about c (c + (±r, 0, 0), c + (0, r, 0), c + (0, 0, r)): the circumcenter
  // is c exactly. a and b on a line through c's projection, offset along the axis: zero;
  // moved by one ulp across it: the side of the move.
  const std::uint64_t seed = seed_for(0xc1c2f);
  INFO("seed " << seed);
  Rng rng(seed);
  std::size_t failures = 0;
  for (int e = -1000; e <= 1000; e += 40) {
    for (int axis = 0; axis < 3; ++axis) {
      const P3 c = {std::ldexp(static_cast<double>(rand_int(rng, -64, 64)), e),
                    std::ldexp(static_cast<double>(rand_int(rng, -64, 64)), e),
                    std::ldexp(static_cast<double>(rand_int(rng, -64, 64)), e)};
      const double r = std::ldexp(static_cast<double>(rand_int(rng, 1, 64)), e);
      Case k{};
      k.p[0] = {c[0] + r, c[1], c[2]};
      k.p[1] = {c[0] - r, c[1], c[2]};
      k.p[2] = {c[0], c[1] + r, c[2]};
      k.p[3] = {c[0], c[1], c[2] + r};
      const std::size_t i = other(axis, 1), j = other(axis, 2), ax = other(axis, 0);
      // a = c + s d, b = c + (s + 1) d along a lattice direction d in the projection.
      const double di = std::ldexp(static_cast<double>(rand_int(rng, -8, 8)), e);
      const double dj = std::ldexp(static_cast<double>(rand_int(rng, 1, 8)), e);
      // s != -1: b's projection is not the centre's (a's move below would keep the line on it).
      long long si = rand_int(rng, -3, 2);
      if (si >= -1) ++si;
      const double s = static_cast<double>(si);
      k.a = c;
      k.a[i] += s * di;
      k.a[j] += s * dj;
      k.a[ax] += std::ldexp(static_cast<double>(rand_int(rng, -64, 64)), e);
      k.b = c;
      k.b[i] += (s + 1) * di;
      k.b[j] += (s + 1) * dj;
      k.b[ax] -= std::ldexp(static_cast<double>(rand_int(rng, -64, 64)), e);
      const int want0 = oracle2d(k, axis);
      if (want0 != 0 || run2d(k, axis, false) != 0) {
        ++failures;
        FAIL_CHECK("2^" << e << " axis " << axis << ": " << describe(k) << " oracle " << want0);
      }
      // One ulp of a's i coordinate up: the line (never parallel to the i axis, dj != 0)
      // leaves the centre, which falls on the side the oracle gives (non-zero, and the
      // predicate agrees).
      Case moved = k;
      moved.a[i] = nudge(moved.a[i], 1);
      const int want1 = oracle2d(moved, axis);
      if (want1 == 0 || run2d(moved, axis, false) != want1) {
        ++failures;
        FAIL_CHECK("2^" << e << " axis " << axis << " nudged: " << describe(moved));
      }
    }
  }
  CHECK(failures == 0);
}

TEST_CASE("orient2d_circumcenter: coplanar sites, bad axis and non-finite input",
          "[predicates][exact][degenerate]") {
  const double o[3] = {0, 0, 0}, x[3] = {1, 0, 0}, y[3] = {0, 1, 0}, xy[3] = {1, 1, 0};
  const double z[3] = {0, 0, 1};
  for (int axis = 0; axis < 3; ++axis) {
    CHECK_THROWS_AS(orient2d_circumcenter(axis, o, z, o, x, y, xy), Error);
  }
  CHECK_THROWS_AS(orient2d_circumcenter(3, o, z, o, x, y, z), Error);
  CHECK_THROWS_AS(orient2d_circumcenter(-1, o, z, o, x, y, z), Error);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const double bad[3] = {0, nan, 0}, huge[3] = {0, 0, -inf};
  CHECK_THROWS_AS(orient2d_circumcenter(2, bad, z, o, x, y, z), Error);
  CHECK_THROWS_AS(orient2d_circumcenter(0, o, z, o, x, huge, z), Error);
}
