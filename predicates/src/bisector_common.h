// Shared internals of the 2D and 3D Voronoi clipping predicates (bisector2d.cpp,
// bisector3d.cpp): argument checks, the sign of a linear symbolic perturbation, and the
// exact-stage driver that evaluates a formula over the coordinate differences of a call to
// its last point (p_i) with exact.h's calculators: 128-bit integers when the differences
// are small integers on a common binary grid, optionally fixed-width integers when the
// coordinates span few enough bits, Shewchuk expansions after a power-of-two scaling, big
// integers when the exponents span too wide a range.
//
// A formula is a function object `int operator()(C& calc, const Num (&d)[R][D])`, generic
// over the calculator C; it must be a polynomial of degree <= Degree in the differences,
// homogeneous in each of its sign tests (so that a power-of-two scaling keeps every sign),
// and the caller states the bit bounds that keep it exact (see exact_eval).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <string>

#include "exact.h"
#include "voroclip/core.h"

namespace voroclip::detail {

// Throws voroclip::Error when two of the site indices of a call are equal.
inline void require_distinct(const char* name, std::initializer_list<std::uint32_t> indices) {
  for (auto x = indices.begin(); x != indices.end(); ++x) {
    for (auto y = x + 1; y != indices.end(); ++y) {
      if (*x == *y) {
        throw Error(std::string(name) + ": site indices must be distinct (index " +
                    std::to_string(*x) + " appears twice)");
      }
    }
  }
}

// require_finite over separately stored points of dimension D (at most 5 of them).
template <int D>
void require_finite_points(const char* name, std::initializer_list<const double*> points) {
  double coords[5 * D];
  int n = 0;
  for (const double* p : points) {
    for (int j = 0; j < D; ++j) coords[n++] = p[j];
  }
  require_finite(name, coords, n);
}

// The sign of a linear form sum_x coef_x eps_x with eps_x >> eps_y when x < y: the sign of
// the non-zero coefficient of the smallest index (N distinct indices); 0 if all are zero.
template <int N>
int perturbation_sign(const std::uint32_t (&index)[N], const int (&coef)[N]) {
  int first = -1;
  for (int x = 0; x < N; ++x) {
    if (coef[x] != 0 && (first < 0 || index[x] < index[first])) first = x;
  }
  return first < 0 ? 0 : coef[first];
}

// 128-bit path (see exact.cpp's small_integer_sign): when every difference to the last
// point is exact in floating point and, scaled by the power of two that brings the largest
// below 2^IntegerBits, an integer. The caller guarantees that the formula keeps every
// intermediate below 2^127 for differences below 2^IntegerBits. Returns false when that
// does not hold (in particular for NaN or infinite coordinates, whose round-off is NaN).
template <int R, int D, int IntegerBits, class Formula>
bool small_integer_eval(const double* const (&pts)[R + 1], const Formula& formula, int& result) {
  static_assert(IntegerBits <= 62, "differences are read as 64-bit integers");
  double d[R][D];
  double largest = 0;
  for (int r = 0; r < R; ++r) {
    for (int j = 0; j < D; ++j) {
      double x, y;
      expansion::two_diff(pts[r][j], pts[R][j], x, y);
      if (y != 0) return false;
      d[r][j] = x;
      largest = std::max(largest, std::fabs(x));
    }
  }
  const int shift = largest == 0 ? 0 : IntegerBits - 1 - highest_bit_exponent(largest);
  Int128Calc::Num n[R][D];
  for (int r = 0; r < R; ++r) {
    for (int j = 0; j < D; ++j) {
      // |scaled| < 2^IntegerBits: the conversion is defined. The second test catches a
      // non-zero difference that the scaling flushed to zero.
      const double scaled = times_pow2(d[r][j], shift);
      const auto integer = static_cast<long long>(scaled);
      if (static_cast<double>(integer) != scaled || (integer == 0) != (d[r][j] == 0)) {
        return false;
      }
      n[r][j] = integer;
    }
  }
  Int128Calc calc;
  result = formula(calc, n);
  return true;
}

// Fixed-width integer path (exact.h's WideIntCalc): the coordinates of the call read as
// integers on their common binary grid 2^span.lowest, when they span at most `bits` =
// highest - lowest + 1 <= kWideLeafBits bits, and their differences (below 2^(bits+1))
// computed exactly. The caller's bound 2^(Degree B + HeadroomBits) on every intermediate,
// for leaves below 2^B, must stay within kWideMaxBits. This is the common case of
// near-degenerate floating-point input (every filter failed, the differences are not exact
// doubles, so the 128-bit path does not apply): no allocation, several times faster than
// the expansions. Returns false when the span is too wide.
template <int R, int D, int Degree, int HeadroomBits, class Formula>
bool wide_integer_eval(const double* const (&pts)[R + 1], const ExponentSpan& span,
                       const Formula& formula, int& result) {
  const int bits = span.highest - span.lowest + 1;
  if (!span.any_nonzero || bits > kWideLeafBits ||
      Degree * (bits + 1) + HeadroomBits > kWideMaxBits) {
    return false;
  }
  WideIntCalc::Num d[R][D];
  for (int r = 0; r < R; ++r) {
    for (int j = 0; j < D; ++j) {
      d[r][j] = WideIntCalc::sub(WideIntCalc::from_double(pts[r][j], span.lowest),
                                 WideIntCalc::from_double(pts[R][j], span.lowest));
    }
  }
  WideIntCalc calc;
  result = formula(calc, d);
  return true;
}

// Evaluates `formula` exactly over the differences of the R + 1 points (dimension D) to
// the last one; throws voroclip::Error (naming `name`) for NaN or infinite coordinates.
// IntegerBits: see small_integer_eval. Degree and HeadroomBits: the formula's degree and a
// bound 2^(Degree B + HeadroomBits) on every intermediate when the leaves (differences) are
// below 2^B; plan_expansion_scaling's bound follows with B = h + 2 for coordinates below
// 2^(h+1). WideTier: whether to try wide_integer_eval before the expansions.
template <int R, int D, int IntegerBits, int Degree, int HeadroomBits, bool WideTier, class Formula>
int exact_eval(const char* name, const double* const (&pts)[R + 1], const Formula& formula) {
  int result = 0;
  if (small_integer_eval<R, D, IntegerBits>(pts, formula, result)) return result;
  double coords[D * (R + 1)];
  for (int r = 0; r <= R; ++r) {
    for (int j = 0; j < D; ++j) coords[D * r + j] = pts[r][j];
  }
  require_finite(name, coords, D * (R + 1));
  const ExponentSpan span = exponent_span(coords, D * (R + 1));
  if constexpr (WideTier) {
    if (wide_integer_eval<R, D, Degree, HeadroomBits>(pts, span, formula, result)) return result;
  }
  int scale = 0;
  if (plan_expansion_scaling(span, Degree, scale, HeadroomBits)) {
    ExpansionCalc calc(thread_arena());
    ExpansionCalc::Num d[R][D];
    differences<ExpansionCalc, R, D>(calc, pts, scale, d);
    return formula(calc, d);
  }
  BigIntCalc calc(span.lowest);
  BigInt d[R][D];
  differences<BigIntCalc, R, D>(calc, pts, 0, d);
  return formula(calc, d);
}

// ---------------------------------------------------------------------------------------
// Formulas shared by 2D and 3D.

// Returned by the formulas when a precondition on the geometry fails (a segment that does
// not cross the bisector, E == 0; a plane whose two bisector lines do not cross, D == 0).
inline constexpr int kNoCrossing = 2;

template <class C, int D>
typename C::Num dot(C& c, const typename C::Num (&p)[D], const typename C::Num (&q)[D]) {
  auto s = c.add(c.mul(p[0], q[0]), c.mul(p[1], q[1]));
  if constexpr (D == 3) s = c.add(s, c.mul(p[2], q[2]));
  return s;
}

// F_ix(a) = |a - p_i|^2 - |a - p_x|^2 = c_x . (2 u - c_x), with c_x = p_x - p_i and
// u = a - p_i (exact calculators: evaluated as c_x . (u + (u - c_x))).
template <class C, int D>
typename C::Num bisector_value(C& c, const typename C::Num (&cx)[D],
                               const typename C::Num (&u)[D]) {
  typename C::Num s[D];
  for (int t = 0; t < D; ++t) s[t] = c.add(u[t], c.sub(u[t], cx[t]));
  return dot<C, D>(c, cx, s);
}

// bisector_side_edge2d/3d over d = {c_k, c_j, u_a, u_b} (differences to p_i). With
// w = u_b - u_a and E_x = w . c_x, the crossing q = a + t w of the perturbed bisector(i, k)
// gives f_ij(q) = N / E_k,
//     N = F_ij(a) E_k - F_ik(a) E_j + eps_i (E_k - E_j) - eps_j E_k + eps_k E_j
// (bisector2d.h). Returns sign f_ij(q), or kNoCrossing when E_k == 0.
template <int D>
struct EdgeFormula {
  std::uint32_t i, k, j;

  template <class C, class M>
  int operator()(C& c, const M& d) const {
    using Num = typename C::Num;
    const auto& ck = d[0];
    const auto& cj = d[1];
    const auto& ua = d[2];
    Num w[D];
    for (int t = 0; t < D; ++t) w[t] = c.sub(d[3][t], ua[t]);
    const Num ek = dot<C, D>(c, w, ck);
    const int sign_ek = C::sign(ek);
    if (sign_ek == 0) return kNoCrossing;
    const Num ej = dot<C, D>(c, w, cj);
    const Num fik = bisector_value<C, D>(c, ck, ua);
    const Num fij = bisector_value<C, D>(c, cj, ua);
    int n = C::sign(c.sub(c.mul(fij, ek), c.mul(fik, ej)));
    if (n == 0) {
      // The eps_j coefficient -E_k is non-zero: never zero.
      const std::uint32_t index[3] = {i, j, k};
      const int coef[3] = {C::sign(c.sub(ek, ej)), -sign_ek, C::sign(ej)};
      n = perturbation_sign(index, coef);
    }
    return n * sign_ek;
  }
};

}  // namespace voroclip::detail
