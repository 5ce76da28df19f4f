// Tests of the 2D mesher's sizing field (mesh/src/sizing2d.h): the binned cone envelope
// equals the brute-force minimum, and its two-level tabulation stays within the bound of
// a g-Lipschitz function's bilinear interpolation.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
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

TEST_CASE("sizing2d: cell squares tile the cell and bound the field from below", "[mesh][exact]") {
  // One sample of size 1e-9 at a node of the tabulation: its cell has 97 x 97 nodes and a
  // node square whose corners range from 1e-9 to about g * its side.
  const double g = 0.3, cap = 0.0625;
  const double lo[2] = {0, 0}, hi[2] = {1, 1};
  const ConeEnvelope env({{0.5, 0.5, 1e-9}}, g, lo, hi);
  SizingField2 field;
  field.build(env, cap, lo, hi);
  const std::uint64_t seed = 7;
  INFO("seed " << seed);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::uint32_t refined = 0;
  for (std::uint32_t c = 0; c < field.nb_cells(); ++c) {
    double clo[2], chi[2];
    field.cell_box(c, clo, chi);
    std::vector<SizingField2::BoundedSquare> squares;
    field.cell_squares(c, 2, 40, &squares);
    REQUIRE(!squares.empty());
    // Every square is a dyadic part of a node square: the sides squared add up to the
    // cell's area in units of the smallest side (exact sums of powers of two).
    double smallest = squares[0].side;
    for (const auto& q : squares) smallest = std::min(smallest, q.side);
    double area = 0;
    for (const auto& q : squares) area += (q.side / smallest) * (q.side / smallest);
    CHECK(area * smallest * smallest == Approx((chi[0] - clo[0]) * (chi[1] - clo[1])));
    double cell_min = std::numeric_limits<double>::infinity();
    for (const auto& q : squares) {
      cell_min = std::min(cell_min, q.min);
      REQUIRE(q.x >= clo[0]);
      REQUIRE(q.y >= clo[1]);
      REQUIRE(q.x + q.side <= chi[0] * (1 + 1e-15));
      REQUIRE(q.y + q.side <= chi[1] * (1 + 1e-15));
      // Brute force: the field on the square is within [min, 2 min] (the split ratio),
      // up to the rounding of the bilinear evaluation.
      for (int k = 0; k < 4; ++k) {
        const double x = q.x + u(rng) * q.side, y = q.y + u(rng) * q.side;
        const double f = field.feature(x, y);
        REQUIRE(f >= q.min * (1 - 1e-14));
        REQUIRE(f <= 2 * q.min * (1 + 1e-14));
      }
    }
    CHECK(cell_min == field.cell_min(c));
    refined += squares.size() > 1;
  }
  // The cells around the sample have node squares, split down to sizes near 1e-9.
  CHECK(refined >= 1);
  double tiny = 1;
  for (std::uint32_t c = 0; c < field.nb_cells(); ++c) {
    std::vector<SizingField2::BoundedSquare> squares;
    field.cell_squares(c, 2, 40, &squares);
    for (const auto& q : squares) tiny = std::min(tiny, q.side);
  }
  CHECK(tiny < 1e-8);
}
