// The quadratic density rule's arithmetic (clip/src/clip3d_internal.h): add_tet_p2's sums
// in closed form against the table of P2 weights they stand for (kP2Weights, the integrals
// of the P2 basis functions times 1, l_k, l_k l_l).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>

#include "clip3d_internal.h"

namespace {

using voroclip::clip3::kP2Weights;
using voroclip::clip3::Moments;

// add_tet_p2 as the table defines it: sum_n f_n W_n, term by term.
Moments by_table(const double* f, const double* a, const double* b, const double* c) {
  const double det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                     a[2] * (b[0] * c[1] - b[1] * c[0]);
  const double v = det / 6;
  double m = 0, s[3] = {0, 0, 0}, t[6] = {0, 0, 0, 0, 0, 0};
  for (int n = 0; n < 10; ++n) {
    m += f[n] * kP2Weights.w0[n];
    for (int k = 0; k < 3; ++k) s[k] += f[n] * kP2Weights.w1[n][k];
    for (int k = 0; k < 6; ++k) t[k] += f[n] * kP2Weights.w2[n][k];
  }
  const double* e[3] = {a, b, c};
  const auto dot = [](const double* u, const double* w) {
    return u[0] * w[0] + u[1] * w[1] + u[2] * w[2];
  };
  Moments r;
  r.volume = v;
  r.mass = v * m;
  for (int q = 0; q < 3; ++q) r.moment[q] = v * (s[0] * a[q] + s[1] * b[q] + s[2] * c[q]);
  constexpr int kPair[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};
  double en = 0;
  for (int p = 0; p < 6; ++p) {
    en += (p < 3 ? 1 : 2) * t[p] * dot(e[kPair[p][0]], e[kPair[p][1]]);
  }
  r.energy = v * en;
  return r;
}

}  // namespace

TEST_CASE("density 3D: the quadratic rule's closed-form sums equal the P2 weight table",
          "[clip][density][exact]") {
  const std::uint32_t seed = 35;
  INFO("seed " << seed);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> coord(-1, 1), value(0.1, 10);
  for (int trial = 0; trial < 1000; ++trial) {
    double a[3], b[3], c[3], f[10];
    for (int k = 0; k < 3; ++k) {
      a[k] = coord(rng);
      b[k] = coord(rng);
      c[k] = coord(rng);
    }
    for (double& x : f) x = value(rng);
    Moments r;
    voroclip::clip3::add_tet_p2(f, a, b, c, r);
    const Moments t = by_table(f, a, b, c);
    // The sums of positive values are well conditioned; the first moments and the energy
    // can cancel: compared against the size of their terms.
    const double scale = std::fabs(t.volume) * 10 * 4;
    REQUIRE(r.volume == t.volume);
    REQUIRE(std::fabs(r.mass - t.mass) <= 1e-14 * std::fabs(t.mass));
    for (int q = 0; q < 3; ++q) REQUIRE(std::fabs(r.moment[q] - t.moment[q]) <= 1e-13 * scale);
    REQUIRE(std::fabs(r.energy - t.energy) <= 1e-13 * scale * 3);
  }
  // A constant 1: the volume, the centroid (a + b + c) / 4 and the closed form of
  // add_cone for the energy.
  const double a[3] = {1, 0, 0}, b[3] = {0, 2, 0}, c[3] = {0.5, 0.5, 3};
  double ones[10];
  for (double& x : ones) x = 1;
  Moments r, cone;
  voroclip::clip3::add_tet_p2(ones, a, b, c, r);
  voroclip::clip3::add_cone(a, b, c, cone);
  CHECK(r.mass == Approx(cone.volume).epsilon(1e-15));
  for (int q = 0; q < 3; ++q) CHECK(r.moment[q] == Approx(cone.moment[q]).epsilon(1e-15));
  CHECK(r.energy == Approx(cone.energy).epsilon(1e-15));
}
