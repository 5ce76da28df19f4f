// cvt/src/rejection_sampling.h — points of a domain drawn with a density by rejection, shared
// by random_points2 and random_points3 (internal to the cvt module).
#pragma once

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

namespace voroclip::detail {

// Uniform doubles in [0, 1) from the 53 high bits of a 64-bit generator: the same numbers on
// every platform (std::uniform_real_distribution's are not specified).
struct Uniform01 {
  std::mt19937_64 rng;
  explicit Uniform01(std::uint64_t seed) : rng(seed) {}
  double operator()() { return static_cast<double>(rng() >> 11) * 0x1p-53; }
};

// n points in D dimensions, packed. draw(p) writes a uniform point of the domain;
// value(p) is the density there (checked by the caller's value). Uniform when !variable;
// otherwise each draw is kept with probability value / bound, bound twice the largest
// value at min(max(n, 1024), 65536) uniform points (drawn first, from the same stream).
template <int D, class Draw, class Value>
std::vector<double> rejection_sample(std::uint32_t n, bool variable, Uniform01& uniform,
                                     const Draw& draw, const Value& value) {
  double bound = 0;
  if (variable) {
    const std::uint32_t m = std::max<std::uint32_t>(1024, std::min<std::uint32_t>(n, 65536));
    for (std::uint32_t i = 0; i < m; ++i) {
      double p[D];
      draw(p);
      bound = std::max(bound, value(p));
    }
    bound *= 2;
  }
  std::vector<double> out;
  out.reserve(D * std::size_t{n});
  for (std::uint32_t i = 0; i < n; ++i) {
    double p[D];
    for (;;) {
      draw(p);
      if (bound == 0 || uniform() * bound <= value(p)) break;
    }
    out.insert(out.end(), p, p + D);
  }
  return out;
}

}  // namespace voroclip::detail
