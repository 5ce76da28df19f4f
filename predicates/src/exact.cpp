// Exact stages of orient2d, orient3d, incircle and insphere (see exact.h).
#include "exact.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "voroclip/core.h"

namespace voroclip::detail {

void require_finite(const char* name, const double* coords, int count) {
  for (int i = 0; i < count; ++i) {
    if (!std::isfinite(coords[i])) {
      throw Error(std::string(name) + ": coordinate " + std::to_string(i) + " of its input is " +
                  (std::isnan(coords[i]) ? "NaN" : "infinite") +
                  "; predicates need finite coordinates");
    }
  }
}

ExponentSpan exponent_span(const double* coords, int count) {
  ExponentSpan s;
  for (int i = 0; i < count; ++i) {
    if (coords[i] == 0) continue;
    const int hi = highest_bit_exponent(coords[i]);
    const int lo = lowest_bit_exponent(coords[i]);
    if (!s.any_nonzero) {
      s = {true, hi, lo};
    } else {
      s.highest = std::max(s.highest, hi);
      s.lowest = std::min(s.lowest, lo);
    }
  }
  return s;
}

bool plan_expansion_scaling(const ExponentSpan& span, int degree, int& scale) {
  scale = 0;
  if (!span.any_nonzero) return true;
  constexpr int kMinProductExponent = -1074;
  constexpr int kMaxMagnitudeExponent = 990;
  const auto fits = [&](int s) {
    return degree * (span.lowest + s) >= kMinProductExponent &&
           degree * (span.highest + s + 2) + 8 <= kMaxMagnitudeExponent;
  };
  if (fits(0)) return true;
  scale = -(span.highest + 1);
  return fits(scale);
}

double* ExpansionArena::allocate(std::size_t n) {
  while (true) {
    if (block_ < blocks_.size()) {
      if (used_ + n <= sizes_[block_]) {
        double* p = blocks_[block_].get() + used_;
        used_ += n;
        return p;
      }
      ++block_;
      used_ = 0;
      continue;
    }
    const std::size_t size = std::max<std::size_t>(n, std::size_t{1} << 14);
    blocks_.emplace_back(new double[size]);
    sizes_.push_back(size);
  }
}

ExpansionArena& thread_arena() {
  thread_local ExpansionArena arena;
  return arena;
}

namespace {

// Fast exact path: when every coordinate difference is exact in floating point (its
// two_diff round-off is 0, as for grid and integer data) and, scaled by the power of two
// that brings the largest below 2^B (B = small_integer_bits(Degree)), every difference is
// an integer, they are read as 64-bit integers and the determinant is evaluated in
// 128-bit integer arithmetic. Returns false (nothing decided) otherwise, in particular
// for NaN or infinite coordinates (their round-off is NaN).
template <int R, int D, int Degree, class Formula>
bool small_integer_sign(const double* const (&pts)[R + 1], Formula formula, Sign& result) {
  double d[R][D];
  double largest = 0;
  for (int i = 0; i < R; ++i) {
    for (int j = 0; j < D; ++j) {
      double x, y;
      expansion::two_diff(pts[i][j], pts[R][j], x, y);
      if (y != 0) return false;
      d[i][j] = x;
      largest = std::max(largest, std::fabs(x));
    }
  }
  if (largest == 0) {
    result = Sign::zero;
    return true;
  }
  const int shift = small_integer_bits(Degree) - 1 - highest_bit_exponent(largest);
  Int128Calc::Num n[R][D];
  for (int i = 0; i < R; ++i) {
    for (int j = 0; j < D; ++j) {
      // |scaled| < 2^B <= 2^62: the conversion is defined. The second test catches a
      // non-zero difference that the scaling flushed to zero.
      const double scaled = times_pow2(d[i][j], shift);
      const auto integer = static_cast<long long>(scaled);
      if (static_cast<double>(integer) != scaled || (integer == 0) != (d[i][j] == 0)) {
        return false;
      }
      n[i][j] = integer;
    }
  }
  Int128Calc calc;
  result = static_cast<Sign>(formula(calc, n));
  return true;
}

// Shared driver: checks the input, then evaluates `Formula` over the differences of the
// R + 1 points of dimension D: in 128-bit integers when they allow it, else with
// expansions, else (exponent span too wide for expansions) with big integers.
template <int R, int D, int Degree, class Formula>
Sign exact_sign(const char* name, const double* const (&pts)[R + 1], Formula formula) {
  Sign small;
  if (small_integer_sign<R, D, Degree>(pts, formula, small)) return small;
  double coords[(R + 1) * D];
  for (int i = 0; i <= R; ++i) {
    for (int j = 0; j < D; ++j) coords[i * D + j] = pts[i][j];
  }
  require_finite(name, coords, (R + 1) * D);
  const ExponentSpan span = exponent_span(coords, (R + 1) * D);
  int scale = 0;
  if (plan_expansion_scaling(span, Degree, scale)) {
    ExpansionCalc calc(thread_arena());
    ExpansionCalc::Num d[R][D];
    differences<ExpansionCalc, R, D>(calc, pts, scale, d);
    return static_cast<Sign>(formula(calc, d));
  }
  BigIntCalc calc(span.lowest);
  BigInt d[R][D];
  differences<BigIntCalc, R, D>(calc, pts, 0, d);
  return static_cast<Sign>(formula(calc, d));
}

struct Orient2dFormula {
  template <class C, class M>
  int operator()(C& c, const M& d) const {
    return orient2d_sign(c, d);
  }
};
struct Orient3dFormula {
  template <class C, class M>
  int operator()(C& c, const M& d) const {
    return orient3d_sign(c, d);
  }
};
struct IncircleFormula {
  template <class C, class M>
  int operator()(C& c, const M& d) const {
    return incircle_sign(c, d);
  }
};
struct InsphereFormula {
  template <class C, class M>
  int operator()(C& c, const M& d) const {
    return insphere_sign(c, d);
  }
};

}  // namespace

Sign orient2d_exact(const double* a, const double* b, const double* c) {
  return exact_sign<2, 2, 2>("orient2d", {a, b, c}, Orient2dFormula{});
}

Sign orient3d_exact(const double* a, const double* b, const double* c, const double* d) {
  return exact_sign<3, 3, 3>("orient3d", {a, b, c, d}, Orient3dFormula{});
}

Sign incircle_exact(const double* a, const double* b, const double* c, const double* d) {
  return exact_sign<3, 2, 4>("incircle", {a, b, c, d}, IncircleFormula{});
}

Sign insphere_exact(const double* a, const double* b, const double* c, const double* d,
                    const double* e) {
  return exact_sign<4, 3, 5>("insphere", {a, b, c, d, e}, InsphereFormula{});
}

}  // namespace voroclip::detail
