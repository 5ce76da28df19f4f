// Coordinates for the validator targets (fuzz_surface3.cpp, fuzz_domain2.cpp), drawn from
// the fuzzer's bytes in one of three modes: small integers (grids: the collinear,
// coplanar, touching and repeated cases an exact validator must decide), small integers
// scaled by a power of two from 2^-1074 to 2^1000 (the same shapes at extreme exponents,
// subnormals included), or any double (NaN and infinities included: refused by name).
#pragma once

#include <fuzzer/FuzzedDataProvider.h>

#include <cmath>
#include <cstdint>
#include <limits>

namespace voroclip::fuzz {

class CoordSource {
 public:
  explicit CoordSource(FuzzedDataProvider& fdp)
      : fdp_(fdp),
        mode_(fdp.ConsumeIntegralInRange<int>(0, 2)),
        exponent_(fdp.ConsumeIntegralInRange<int>(-1074, 1000)) {}

  double next() {
    switch (mode_) {
      case 0:
        return fdp_.ConsumeIntegralInRange<int>(-4, 4);
      case 1:
        return std::ldexp(fdp_.ConsumeIntegralInRange<int>(-8, 8), exponent_);
      default:
        return fdp_.ConsumeFloatingPoint<double>();
    }
  }

 private:
  FuzzedDataProvider& fdp_;
  int mode_;
  int exponent_;
};

}  // namespace voroclip::fuzz
