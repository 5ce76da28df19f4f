// Exact evaluation of the predicates' determinants, after the filter failed.
//
// The determinants are written once, as templates over a "calculator" C that provides
// C::Num with add/sub/mul/sign, and evaluated with one of two calculators:
//
//   ExpansionCalc  Shewchuk expansions (expansion.h) in a per-thread arena. Exact when the
//                  coordinates of the call, after scaling by a power of two, keep every
//                  product clear of overflow and underflow: see plan_expansion_scaling.
//   BigIntCalc     arbitrary-precision integers on the call's common binary grid (every
//                  finite double is an integer multiple of 2^-1074). Exact for every finite
//                  input, slower; used only when the exponent span is too wide.
//
// Both evaluate the translated determinant (rows p_i - p_last, and for the lifted
// predicates |p_i - p_last|^2), which equals the homogeneous one of predicates.h. Before
// either (exact.cpp, exact_sign): points sharing one coordinate exactly give a zero column,
// so orient2d/3d, incircle and insphere are zero; differences that are exact small integers
// go to 128-bit integer arithmetic (small_integer_sign).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "bigint.h"
#include "expansion.h"
#include "voroclip/predicates.h"

namespace voroclip::detail {

// ---------------------------------------------------------------------------------------
// Input analysis.

// x * 2^e, exact whenever the result is a normal double (or zero). A product with a power of
// two built from its bits when 2^e is itself normal; std::ldexp (a library call) otherwise.
inline double times_pow2(double x, int e) {
  if (e >= -1022 && e <= 1023) {
    const std::uint64_t bits = static_cast<std::uint64_t>(e + 1023) << 52;
    double p;
    std::memcpy(&p, &bits, sizeof p);
    return x * p;
  }
  return std::ldexp(x, e);
}

// Throws voroclip::Error when a coordinate is NaN or infinite. `name` is the predicate's.
void require_finite(const char* name, const double* coords, int count);

struct ExponentSpan {
  bool any_nonzero = false;
  int highest = 0;  // max over non-zero coordinates of floor(log2 |x|)
  int lowest = 0;   // min over non-zero coordinates of the exponent of the lowest set bit
};
ExponentSpan exponent_span(const double* coords, int count);

// For a polynomial of degree `degree` in coordinate differences, decides whether expansion
// arithmetic is exact on these coordinates after multiplying them by 2^scale, and picks
// scale. Argument: after scaling, every coordinate is a multiple of q = 2^(lowest+scale)
// and below 2^(highest+scale+1) in magnitude. Every product of `degree` differences, and
// every expansion component built from them, is then a multiple of q^degree; if
// q^degree >= 2^-1074 nothing is ever rounded by underflow (Shewchuk's algorithms stay
// exact under gradual underflow). Magnitudes stay below
// 2^(degree*(highest+scale+2)+headroom_bits): the default 8 covers the at most 120 terms
// of a 5x5 determinant and the lifts; a formula with larger coefficients passes its own
// bound. Keeping that under 2^990 leaves room for Dekker's splitting constant. Prefers
// scale = 0 (no work); otherwise scales the largest coordinate below 1. Returns false
// exactly when highest - lowest + 1 > 1074 / degree (orient2d 537 bits, orient3d 358,
// incircle 268, insphere 214): then the caller uses the big-integer calculator.
bool plan_expansion_scaling(const ExponentSpan& span, int degree, int& scale,
                            int headroom_bits = 8);

// ---------------------------------------------------------------------------------------
// Expansion calculator.

// A bump allocator of doubles that never moves what it handed out; reset() makes all of it
// reusable. One per thread (arena()), so the exact stage allocates nothing after warm-up.
class ExpansionArena {
 public:
  double* allocate(std::size_t n);
  void reset() {
    block_ = 0;
    used_ = 0;
  }

 private:
  std::vector<std::unique_ptr<double[]>> blocks_;
  std::vector<std::size_t> sizes_;
  std::size_t block_ = 0;
  std::size_t used_ = 0;
};

ExpansionArena& thread_arena();

class ExpansionCalc {
 public:
  struct Num {
    double* v;
    int n;
  };

  explicit ExpansionCalc(ExpansionArena& arena) : arena_(arena) { arena_.reset(); }

  // The exact difference a - b of two doubles, as an expansion of 0, 1 or 2 components.
  Num diff(double a, double b) {
    double* h = arena_.allocate(2);
    double x, y;
    expansion::two_diff(a, b, x, y);
    int n = 0;
    if (y != 0) h[n++] = y;
    if (x != 0) h[n++] = x;
    return {h, n};
  }
  Num add(Num a, Num b) {
    double* h = arena_.allocate(static_cast<std::size_t>(a.n + b.n));
    return shorten({h, expansion::expansion_sum(a.v, a.n, b.v, b.n, h)});
  }
  Num sub(Num a, Num b) {
    double* h = arena_.allocate(static_cast<std::size_t>(a.n + b.n));
    return shorten({h, expansion::expansion_diff(a.v, a.n, b.v, b.n, h)});
  }
  Num mul(Num a, Num b) {
    if (a.n < b.n) std::swap(a, b);  // scale the longer one by each component of the shorter
    if (b.n == 1) {
      double* h = arena_.allocate(2 * static_cast<std::size_t>(a.n));
      return shorten({h, expansion::scale_expansion(a.v, a.n, b.v[0], h)});
    }
    const std::size_t size = 2 * static_cast<std::size_t>(a.n) * static_cast<std::size_t>(b.n);
    double* h = arena_.allocate(size);
    double* scratch = arena_.allocate(size + 2 * static_cast<std::size_t>(a.n));
    return shorten({h, expansion::expansion_product(a.v, a.n, b.v, b.n, h, scratch)});
  }
  static int sign(Num a) { return expansion::sign(a.v, a.n); }

 private:
  // Compression costs one linear pass and keeps later products small: on inputs with few
  // significant bits (grids, integer data) every intermediate collapses to 1-2 components.
  static Num shorten(Num a) {
    if (a.n > 2) a.n = expansion::compress(a.v, a.n);
    return a;
  }

  ExpansionArena& arena_;
};

// ---------------------------------------------------------------------------------------
// 128-bit integer calculator, for coordinate differences that are small integers on a
// common binary grid (see small_integer_bits): no rounding, no allocation, no compression.

class Int128Calc {
 public:
  using Num = __int128;
  static Num add(Num a, Num b) { return a + b; }
  static Num sub(Num a, Num b) { return a - b; }
  static Num mul(Num a, Num b) { return a * b; }
  static int sign(Num a) { return int{a > 0} - int{a < 0}; }
};

// The largest bit length B of the integer differences (|d| < 2^B) for which the
// determinant and every intermediate of the formulas below fit in a signed 128-bit integer:
//   orient2d            |det| < 2^(2B+1)                    B <= 61
//   compare_distance3d  |det| < 2 * 3 * 2^(2B) < 2^(2B+3)  B <= 61 (degree 2 shares it)
//   orient3d            |det| < 6 * 2^(3B)  < 2^(3B+3)      B <= 41
//   incircle            |det| < 12 * 2^(4B) < 2^(4B+4)      B <= 30
//   insphere            |det| < 72 * 2^(5B) < 2^(5B+7)      B <= 23
// (2x2 minors < 2^(2B+1), 3x3 minors < 6 * 2^(3B), lifts < 3 * 2^(2B).)
constexpr int small_integer_bits(int degree) {
  return degree == 2 ? 61 : degree == 3 ? 41 : degree == 4 ? 30 : 23;
}

// ---------------------------------------------------------------------------------------
// Fixed-width integer calculator: sign and magnitude in kLimbs 64-bit limbs, on the stack.
// For differences that are exact doubles spanning up to kWideLeafBits bits on their
// common binary grid (near-degenerate floating-point input, where every filter fails):
// no allocation, about ten times faster than the expansions on such data. The caller
// guarantees that no intermediate exceeds kWideMaxBits (see wide_integer_fits).

inline constexpr int kWideLimbs = 8;
inline constexpr int kWideLeafBits = 120;  // a leaf is at most two limbs
inline constexpr int kWideMaxBits = 64 * kWideLimbs - 8;

struct WideInt {
  std::uint64_t limb[kWideLimbs];
  int size;       // limbs in use; 0 for zero
  bool negative;  // never set for zero
};

class WideIntCalc {
 public:
  using Num = WideInt;
  static Num add(const Num& a, const Num& b) { return add_signed(a, b, b.negative); }
  static Num sub(const Num& a, const Num& b) { return add_signed(a, b, !b.negative && b.size); }
  static Num mul(const Num& a, const Num& b);
  static int sign(const Num& a) { return a.size == 0 ? 0 : (a.negative ? -1 : 1); }
  // The integer x * 2^-grid; x is an integer multiple of 2^grid below 2^(grid+120).
  static Num from_double(double x, int grid);

 private:
  static Num add_signed(const Num& a, const Num& b, bool b_negative);
};

// Whether a polynomial of `degree` in leaves of at most `leaf_bits` bits, with at most 120
// terms (a 5x5 determinant), stays below 2^kWideMaxBits.
constexpr bool wide_integer_fits(int degree, int leaf_bits) {
  return leaf_bits <= kWideLeafBits && degree * (leaf_bits + 1) + 8 <= kWideMaxBits;
}

// ---------------------------------------------------------------------------------------
// Big-integer calculator: coordinates are read as integers on the grid 2^grid.

class BigIntCalc {
 public:
  using Num = BigInt;
  explicit BigIntCalc(int grid) : grid_(grid) {}
  Num diff(double a, double b) const {
    return BigInt::from_scaled_double(a, grid_) - BigInt::from_scaled_double(b, grid_);
  }
  static Num add(const Num& a, const Num& b) { return a + b; }
  static Num sub(const Num& a, const Num& b) { return a - b; }
  static Num mul(const Num& a, const Num& b) { return a * b; }
  static int sign(const Num& a) { return a.sign(); }

 private:
  int grid_;
};

// ---------------------------------------------------------------------------------------
// The determinants, over differences d[i][j] = p_i[j] - p_last[j] (Shewchuk's formulas).

template <class C>
typename C::Num det2(C& c, const typename C::Num& a0, const typename C::Num& a1,
                     const typename C::Num& b0, const typename C::Num& b1) {
  return c.sub(c.mul(a0, b1), c.mul(a1, b0));
}

template <class C>
int orient2d_sign(C& c, const typename C::Num (&d)[2][2]) {
  return C::sign(det2(c, d[0][0], d[0][1], d[1][0], d[1][1]));
}

template <class C>
int orient3d_sign(C& c, const typename C::Num (&d)[3][3]) {
  // adz * (bdx cdy - cdx bdy) + bdz * (cdx ady - adx cdy) + cdz * (adx bdy - bdx ady)
  const auto bc = det2(c, d[1][0], d[1][1], d[2][0], d[2][1]);
  const auto ca = det2(c, d[2][0], d[2][1], d[0][0], d[0][1]);
  const auto ab = det2(c, d[0][0], d[0][1], d[1][0], d[1][1]);
  return C::sign(c.add(c.add(c.mul(d[0][2], bc), c.mul(d[1][2], ca)), c.mul(d[2][2], ab)));
}

template <class C, int N>
typename C::Num lift(C& c, const typename C::Num (&row)[N]) {
  static_assert(N == 2 || N == 3, "lifts of 2D or 3D differences");
  auto s = c.add(c.mul(row[0], row[0]), c.mul(row[1], row[1]));
  if constexpr (N == 3) s = c.add(s, c.mul(row[2], row[2]));
  return s;
}

template <class C>
int incircle_sign(C& c, const typename C::Num (&d)[3][2]) {
  const auto bc = det2(c, d[1][0], d[1][1], d[2][0], d[2][1]);
  const auto ca = det2(c, d[2][0], d[2][1], d[0][0], d[0][1]);
  const auto ab = det2(c, d[0][0], d[0][1], d[1][0], d[1][1]);
  return C::sign(
      c.add(c.add(c.mul(lift(c, d[0]), bc), c.mul(lift(c, d[1]), ca)), c.mul(lift(c, d[2]), ab)));
}

template <class C>
int insphere_sign(C& c, const typename C::Num (&d)[4][3]) {
  enum { x, y, z };
  const auto& a = d[0];
  const auto& b = d[1];
  const auto& cc = d[2];
  const auto& e = d[3];  // Shewchuk's "d" (the fifth point is the origin after translation)
  const auto ab = det2(c, a[x], a[y], b[x], b[y]);
  const auto bc = det2(c, b[x], b[y], cc[x], cc[y]);
  const auto cd = det2(c, cc[x], cc[y], e[x], e[y]);
  const auto da = det2(c, e[x], e[y], a[x], a[y]);
  const auto ac = det2(c, a[x], a[y], cc[x], cc[y]);
  const auto bd = det2(c, b[x], b[y], e[x], e[y]);
  const auto abc = c.add(c.sub(c.mul(a[z], bc), c.mul(b[z], ac)), c.mul(cc[z], ab));
  const auto bcd = c.add(c.sub(c.mul(b[z], cd), c.mul(cc[z], bd)), c.mul(e[z], bc));
  const auto cda = c.add(c.add(c.mul(cc[z], da), c.mul(e[z], ac)), c.mul(a[z], cd));
  const auto dab = c.add(c.add(c.mul(e[z], ab), c.mul(a[z], bd)), c.mul(b[z], da));
  const auto det = c.add(c.sub(c.mul(lift(c, e), abc), c.mul(lift(c, cc), dab)),
                         c.sub(c.mul(lift(c, b), cda), c.mul(lift(c, a), bcd)));
  return C::sign(det);
}

template <class C, int D>
int compare_distance_sign(C& c, const typename C::Num (&d)[2][D]) {
  return C::sign(c.sub(lift(c, d[0]), lift(c, d[1])));
}

// Fills d[i][j] = pts[i][j] - pts[R][j] (R = the last point) with the calculator's exact
// difference, on coordinates multiplied by 2^scale (exact: see plan_expansion_scaling).
// (times_pow2, not a product with one factor 2^scale: when every coordinate is subnormal,
// scale exceeds 1023 and 2^scale itself is not a double.)
template <class C, int R, int D>
void differences(C& c, const double* const (&pts)[R + 1], int scale, typename C::Num (&d)[R][D]) {
  for (int i = 0; i < R; ++i) {
    for (int j = 0; j < D; ++j) {
      d[i][j] = scale == 0 ? c.diff(pts[i][j], pts[R][j])
                           : c.diff(times_pow2(pts[i][j], scale), times_pow2(pts[R][j], scale));
    }
  }
}

}  // namespace voroclip::detail
