// Exact stages of orient2d, orient3d, incircle and insphere (see exact.h).
#include "exact.h"

#include <algorithm>
#include <cmath>
#include <cstring>
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

bool plan_expansion_scaling(const ExponentSpan& span, int degree, int& scale, int headroom_bits) {
  scale = 0;
  if (!span.any_nonzero) return true;
  constexpr int kMinProductExponent = -1074;
  constexpr int kMaxMagnitudeExponent = 990;
  const auto fits = [&](int s) {
    return degree * (span.lowest + s) >= kMinProductExponent &&
           degree * (span.highest + s + 2) + headroom_bits <= kMaxMagnitudeExponent;
  };
  if (fits(0)) return true;
  scale = -(span.highest + 1);
  return fits(scale);
}

WideInt WideIntCalc::from_double(double x, int grid) {
  WideInt r{};
  if (x == 0) return r;
  const DecodedDouble d = decode_double(x);
  const int shift = d.exponent - grid;  // >= 0; shift + 53 <= 128 by the caller's grid
  const unsigned __int128 v = static_cast<unsigned __int128>(d.mantissa) << shift;
  r.limb[0] = static_cast<std::uint64_t>(v);
  r.limb[1] = static_cast<std::uint64_t>(v >> 64);
  r.size = r.limb[1] != 0 ? 2 : 1;
  r.negative = x < 0;
  return r;
}

WideInt WideIntCalc::add_signed(const WideInt& a, const WideInt& b, bool b_negative) {
  WideInt r{};
  if (b.size == 0) return a;
  if (a.size == 0) {
    r = b;
    r.negative = b_negative;
    return r;
  }
  if (a.negative == b_negative) {
    const int n = std::max(a.size, b.size);
    unsigned __int128 carry = 0;
    for (int i = 0; i < n; ++i) {
      carry +=
          static_cast<unsigned __int128>(i < a.size ? a.limb[i] : 0) + (i < b.size ? b.limb[i] : 0);
      r.limb[i] = static_cast<std::uint64_t>(carry);
      carry >>= 64;
    }
    r.size = n;
    if (carry != 0) r.limb[r.size++] = static_cast<std::uint64_t>(carry);  // bounded by caller
    r.negative = a.negative;
    return r;
  }
  // Opposite signs: subtract the smaller magnitude from the larger.
  int cmp = a.size != b.size ? (a.size < b.size ? -1 : 1) : 0;
  for (int i = a.size - 1; cmp == 0 && i >= 0; --i) {
    if (a.limb[i] != b.limb[i]) cmp = a.limb[i] < b.limb[i] ? -1 : 1;
  }
  if (cmp == 0) return r;
  const WideInt& big = cmp > 0 ? a : b;
  const WideInt& small = cmp > 0 ? b : a;
  std::uint64_t borrow = 0;
  for (int i = 0; i < big.size; ++i) {
    const std::uint64_t s = i < small.size ? small.limb[i] : 0;
    const std::uint64_t d = big.limb[i] - s - borrow;
    borrow = (big.limb[i] < s || (big.limb[i] == s && borrow)) ? 1 : 0;
    r.limb[i] = d;
  }
  r.size = big.size;
  while (r.size > 0 && r.limb[r.size - 1] == 0) --r.size;
  r.negative = cmp > 0 ? a.negative : b_negative;
  return r;
}

WideInt WideIntCalc::mul(const WideInt& a, const WideInt& b) {
  WideInt r{};
  if (a.size == 0 || b.size == 0) return r;
  r.size = std::min(a.size + b.size, kWideLimbs);
  for (int i = 0; i < a.size; ++i) {
    std::uint64_t carry = 0;
    for (int j = 0; j < b.size && i + j < kWideLimbs; ++j) {
      const unsigned __int128 t =
          static_cast<unsigned __int128>(a.limb[i]) * b.limb[j] + r.limb[i + j] + carry;
      r.limb[i + j] = static_cast<std::uint64_t>(t);
      carry = static_cast<std::uint64_t>(t >> 64);
    }
    if (i + b.size < kWideLimbs) r.limb[i + b.size] = carry;
  }
  while (r.size > 0 && r.limb[r.size - 1] == 0) --r.size;
  r.negative = a.negative != b.negative;
  return r;
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

// Second integer tier (see WideIntCalc): the exact differences d, the largest of exponent
// `highest`, read on their common binary grid when they span at most kWideLeafBits bits.
template <int R, int D, int Degree, class Formula>
bool wide_integer_sign(const double (&d)[R][D], int highest, Formula formula, Sign& result) {
  int grid = highest;
  for (int i = 0; i < R; ++i) {
    for (int j = 0; j < D; ++j) {
      if (d[i][j] != 0) grid = std::min(grid, lowest_bit_exponent(d[i][j]));
    }
  }
  const int bits = highest - grid + 1;
  if (!wide_integer_fits(Degree, bits)) return false;
  WideIntCalc::Num n[R][D];
  for (int i = 0; i < R; ++i) {
    for (int j = 0; j < D; ++j) n[i][j] = WideIntCalc::from_double(d[i][j], grid);
  }
  WideIntCalc calc;
  result = static_cast<Sign>(formula(calc, n));
  return true;
}

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
  const int highest = highest_bit_exponent(largest);
  const int shift = small_integer_bits(Degree) - 1 - highest;
  Int128Calc::Num n[R][D];
  for (int i = 0; i < R; ++i) {
    for (int j = 0; j < D; ++j) {
      // |scaled| < 2^B <= 2^62: the conversion is defined. The second test catches a
      // non-zero difference that the scaling flushed to zero.
      const double scaled = times_pow2(d[i][j], shift);
      const auto integer = static_cast<long long>(scaled);
      if (static_cast<double>(integer) != scaled || (integer == 0) != (d[i][j] == 0)) {
        return wide_integer_sign<R, D, Degree>(d, highest, formula, result);
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
  // Points that all share one coordinate exactly (on an axis-aligned line or plane, as on a
  // box's face, where the filters always fail) give the matrix of differences a zero
  // column: a determinant whose columns include the differences themselves (orient, incircle,
  // insphere: Formula::kZeroColumnDecides) is zero, decided without the exact arithmetic.
  if constexpr (Formula::kZeroColumnDecides) {
    for (int j = 0; j < D; ++j) {
      bool shared = true;
      for (int i = 0; i < R && shared; ++i) shared = pts[i][j] == pts[R][j];
      if (!shared) continue;
      bool finite = true;
      for (int i = 0; i <= R; ++i) {
        for (int k = 0; k < D; ++k) finite = finite && std::isfinite(pts[i][k]);
      }
      if (finite) return Sign::zero;
      break;  // require_finite below names the coordinate
    }
  }
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
  static constexpr bool kZeroColumnDecides = true;
  template <class C, class M>
  int operator()(C& c, const M& d) const {
    return orient2d_sign(c, d);
  }
};
struct Orient3dFormula {
  static constexpr bool kZeroColumnDecides = true;
  template <class C, class M>
  int operator()(C& c, const M& d) const {
    return orient3d_sign(c, d);
  }
};
struct IncircleFormula {
  static constexpr bool kZeroColumnDecides = true;
  template <class C, class M>
  int operator()(C& c, const M& d) const {
    return incircle_sign(c, d);
  }
};
struct CompareDistanceFormula {
  static constexpr bool kZeroColumnDecides = false;
  template <class C, class M>
  int operator()(C& c, const M& d) const {
    return compare_distance_sign(c, d);
  }
};
struct InsphereFormula {
  static constexpr bool kZeroColumnDecides = true;
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

// Differences to p (the last point): |q - p|^2 - |r - p|^2.
Sign compare_distance2d_exact(const double* p, const double* q, const double* r) {
  return exact_sign<2, 2, 2>("compare_distance2d", {q, r, p}, CompareDistanceFormula{});
}

Sign compare_distance3d_exact(const double* p, const double* q, const double* r) {
  return exact_sign<2, 3, 2>("compare_distance3d", {q, r, p}, CompareDistanceFormula{});
}

}  // namespace voroclip::detail
