// The SSE2 and AVX2 insphere determinants of Delaunay3 are bit for bit the scalar one of
// the static filter (detail::insphere_approx), on which the filter's error bound is proven.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>

#include "insphere_det.h"

namespace {

std::uint64_t bits(double x) {
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

#if defined(VOROCLIP_INSPHERE_DET_AVX2)
bool cpu_has_avx2() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2");
}
#endif

}  // namespace

TEST_CASE("insphere_det is bit for bit insphere_approx's determinant", "[delaunay][exact]") {
  const std::uint64_t seed = 20260501;
  INFO("seed " << seed);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-60, 60);
#if defined(VOROCLIP_INSPHERE_DET_AVX2)
  const bool avx2 = cpu_has_avx2();
  if (!avx2) WARN("no AVX2 on this CPU: insphere_det_avx2 is not tested");
#endif
  double p[5][3];
  for (int trial = 0; trial < 200000; ++trial) {
    // Mixed magnitudes, near-cospherical sets (small perturbations of one sphere), and
    // points sharing coordinates, so that cancellation and rounding are exercised.
    const int kind = trial % 4;
    const double scale = std::ldexp(1.0, exponent(rng));
    for (auto& point : p) {
      for (double& x : point) {
        x = kind == 0 ? std::ldexp(u(rng), exponent(rng)) : scale * u(rng);
      }
    }
    if (kind == 2) {
      for (auto& point : p) {
        const double r = std::sqrt(point[0] * point[0] + point[1] * point[1] + point[2] * point[2]);
        for (double& x : point) x = x / r * scale;
      }
    }
    if (kind == 3) {
      p[3][0] = p[0][0];
      p[4][1] = p[1][1];
      p[2][2] = p[4][2];
    }
    const double simd = voroclip::detail::insphere_det(p[0], p[1], p[2], p[3], p[4]);
    const double scalar = voroclip::detail::insphere_approx(p[0], p[1], p[2], p[3], p[4]).det;
    if (bits(simd) != bits(scalar)) {
      INFO("trial " << trial << ": " << simd << " vs " << scalar);
      REQUIRE(bits(simd) == bits(scalar));
    }
#if defined(VOROCLIP_INSPHERE_DET_AVX2)
    if (avx2) {
      const double wide = voroclip::detail::insphere_det_avx2(p[0], p[1], p[2], p[3], p[4]);
      if (bits(wide) != bits(scalar)) {
        INFO("trial " << trial << ": AVX2 " << wide << " vs " << scalar);
        REQUIRE(bits(wide) == bits(scalar));
      }
    }
#endif
  }
  // Cube corners: exactly cospherical, det exactly 0 both ways.
  const double corners[5][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  CHECK(voroclip::detail::insphere_det(corners[0], corners[1], corners[2], corners[3],
                                       corners[4]) == 0.0);
#if defined(VOROCLIP_INSPHERE_DET_AVX2)
  if (avx2) {
    CHECK(voroclip::detail::insphere_det_avx2(corners[0], corners[1], corners[2], corners[3],
                                              corners[4]) == 0.0);
  }
#endif
}
