// compare_distance2d/3d against exact rational arithmetic (GMP).
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <cstddef>
#include <gmpxx.h>
#include <limits>

#include "exact_oracle.h"
#include "voroclip/core.h"
#include "voroclip/predicates.h"

using namespace voroclip;
using namespace voroclip::test;

namespace {

using P3 = std::array<double, 3>;

int exact_compare(const P3& p, const P3& q, const P3& r, int dim) {
  mpq_class s = 0;
  for (int j = 0; j < dim; ++j) {
    const auto u = static_cast<std::size_t>(j);
    const mpq_class dq = mpq_class(q[u]) - mpq_class(p[u]);
    const mpq_class dr = mpq_class(r[u]) - mpq_class(p[u]);
    s += dq * dq - dr * dr;
  }
  return sgn(s);
}

int ours(const P3& p, const P3& q, const P3& r, int dim) {
  return static_cast<int>(dim == 2 ? compare_distance2d(p.data(), q.data(), r.data())
                                   : compare_distance3d(p.data(), q.data(), r.data()));
}

// p on the bisector of q and r up to rounding: the midpoint plus a multiple of a vector
// orthogonal to q - r, then nudged by a few ulps.
P3 near_bisector(const P3& q, const P3& r, int dim, Rng& rng) {
  P3 p{};
  P3 n{};
  for (int j = 0; j < dim; ++j) {
    const auto u = static_cast<std::size_t>(j);
    p[u] = 0.5 * (q[u] + r[u]);
    n[u] = q[u] - r[u];
  }
  P3 t{};  // a vector orthogonal to n (in the plane of the first two axes)
  t[0] = -n[1];
  t[1] = n[0];
  const double s = uniform(rng, -1, 1);
  for (int j = 0; j < dim; ++j) {
    const auto u = static_cast<std::size_t>(j);
    p[u] = nudge(p[u] + s * t[u], static_cast<int>(rand_int(rng, -3, 3)));
  }
  return p;
}

}  // namespace

TEST_CASE("compare_distance agrees with exact arithmetic", "[predicates][exact]") {
  const std::uint64_t seed = seed_for(0xd157);
  INFO("seed " << seed);
  Rng rng(seed);
  for (const int dim : {2, 3}) {
    std::size_t failures = 0, zeros = 0, filter_failed = 0;
    const std::size_t n = scaled(100000);
    for (std::size_t i = 0; i < n; ++i) {
      P3 q{}, r{}, p{};
      for (int j = 0; j < dim; ++j) {
        const auto u = static_cast<std::size_t>(j);
        q[u] = uniform(rng, -1, 1);
        r[u] = uniform(rng, -1, 1);
        p[u] = uniform(rng, -1, 1);
      }
      switch (i % 4) {
        case 0:
          break;  // random
        case 1:
          p = near_bisector(q, r, dim, rng);
          break;
        case 2: {  // exactly equidistant integer configuration: p = (q + r) / 2 + t
          for (int j = 0; j < dim; ++j) {
            const auto u = static_cast<std::size_t>(j);
            q[u] = static_cast<double>(rand_int(rng, -50, 50)) * 2;
            r[u] = static_cast<double>(rand_int(rng, -50, 50)) * 2;
          }
          p = {0.5 * (q[0] + r[0]) - (q[1] - r[1]), 0.5 * (q[1] + r[1]) + (q[0] - r[0]),
               0.5 * (q[2] + r[2])};
          break;
        }
        default: {  // extreme scales and mixed magnitudes
          const int e = static_cast<int>(rand_int(rng, -500, 500));
          for (auto* pt : {&q, &r, &p}) {
            for (double& x : *pt) x = std::ldexp(x, e);
          }
          if (i % 8 == 3) p[0] = std::ldexp(p[0], -300);
          break;
        }
      }
      const int want = exact_compare(p, q, r, dim);
      zeros += want == 0;
      filter_failed +=
          (dim == 2 ? detail::compare_distance2d_filter(p.data(), q.data(), r.data())
                    : detail::compare_distance3d_filter(p.data(), q.data(), r.data())) == 0;
      if (ours(p, q, r, dim) != want) {
        ++failures;
        FAIL_CHECK("dim " << dim << " p " << hex(p[0]) << " " << hex(p[1]) << " " << hex(p[2])
                          << " q " << hex(q[0]) << " " << hex(q[1]) << " " << hex(q[2]) << " r "
                          << hex(r[0]) << " " << hex(r[1]) << " " << hex(r[2]));
      }
      // Antisymmetry: swapping q and r negates the result.
      if (ours(p, r, q, dim) != -want) ++failures;
    }
    INFO("dimension " << dim << ": " << zeros << " exact zeros, filter undecided "
                      << filter_failed);
    CHECK(failures == 0);
    CHECK(zeros > n / 8);          // the equidistant family is exactly degenerate
    CHECK(filter_failed > n / 8);  // and the exact stages did run
  }
}

TEST_CASE("compare_distance rejects non-finite coordinates", "[predicates]") {
  const double p[3] = {0, 0, 0}, q[3] = {1, 0, 0};
  const double bad[3] = {std::numeric_limits<double>::infinity(), 0, 0};
  const double nan[3] = {0, std::nan(""), 0};
  CHECK_THROWS_AS(compare_distance3d(p, q, bad), Error);
  CHECK_THROWS_AS(compare_distance2d(nan, q, p), Error);
}
