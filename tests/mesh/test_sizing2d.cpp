// Tests of the 2D mesher's sizing field (mesh/src/sizing2d.h): the binned cone envelope
// equals the brute-force minimum, and its two-level tabulation stays within the bound of
// a g-Lipschitz function's bilinear interpolation.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "sizing2d.h"

using voroclip::mesh2d::ConeEnvelope;
using voroclip::mesh2d::FeatureSample;
using voroclip::mesh2d::SizingField2;

TEST_CASE("sizing2d: envelope equals brute force, tabulation within its bound", "[mesh]") {
  const std::uint64_t seed = 2024;
  INFO("seed " << seed);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1), s(0.002, 0.05);
  std::vector<FeatureSample> samples;
  // Samples along two lines and a few scattered, sizes from 0.002.
  for (int k = 0; k < 400; ++k) samples.push_back({u(rng), 0.3, s(rng)});
  for (int k = 0; k < 400; ++k) samples.push_back({0.7, u(rng), s(rng)});
  for (int k = 0; k < 50; ++k) samples.push_back({u(rng), u(rng), s(rng)});
  const double g = 0.3, cap = 0.08;
  const double lo[2] = {0, 0}, hi[2] = {1, 1};
  const ConeEnvelope env(samples, g, lo, hi);
  const auto brute = [&](double x, double y, double c) {
    double best = c;
    for (const FeatureSample& f : samples)
      best = std::min(best, f.s + g * std::hypot(x - f.x, y - f.y));
    return best;
  };
  SizingField2 field;
  field.build(env, cap, lo, hi);
  REQUIRE(field.nb_nodes() > 0);
  const double bound = g * std::sqrt(2.0) * field.max_spacing() * (1 + 1e-12);
  for (int k = 0; k < 20000; ++k) {
    const double x = u(rng) * 1.2 - 0.1, y = u(rng) * 1.2 - 0.1;
    REQUIRE(env.value(x, y, cap) == brute(x, y, cap));
    REQUIRE(env.value(x, y, 1e300) == brute(x, y, 1e300));
    // Outside the box the table clamps to its border.
    const double cx = std::clamp(x, 0.0, 1.0), cy = std::clamp(y, 0.0, 1.0);
    REQUIRE(std::fabs(field.feature(x, y) - brute(cx, cy, cap)) <= bound);
  }
  // Far from every sample the field is the cap exactly.
  const ConeEnvelope one({{0, 0, 0.01}}, g, lo, hi);
  SizingField2 f1;
  f1.build(one, cap, lo, hi);
  CHECK(f1.feature(0.9, 0.9) == cap);
  CHECK(f1.feature(0, 0) == Approx(0.01).margin(g * std::sqrt(2.0) * f1.max_spacing()));
}
