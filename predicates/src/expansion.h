// Floating-point expansion arithmetic (Shewchuk, "Adaptive Precision Floating-Point
// Arithmetic and Fast Robust Geometric Predicates", DCG 18, 1997, sections 2.3–2.8).
//
// An expansion is an array e[0..n) of doubles whose exact sum is the value represented,
// stored in increasing order of magnitude, non-overlapping and without zero components
// (every routine here eliminates zeros). The value 0 is the empty expansion (n == 0).
// Because the components do not overlap, the sign of the value is the sign of the
// largest (last) component.
//
// Exactness holds when no operation overflows and no product underflows below the
// smallest subnormal's granularity. predicates/src/exact.cpp guarantees that by scaling
// the inputs of a predicate by a power of two (see exact.h: ExpansionRange); routines
// here do not check.
//
// All routines require IEEE-754 binary64 with round-to-nearest-even and no extended
// precision (x86-64 SSE2; compiled with -ffp-contract=off so that a*b+c is never fused
// behind our back).
#pragma once

#include <cmath>

namespace voroclip::expansion {

// x + y == a + b exactly, x == fl(a + b). (Knuth's TwoSum, Shewchuk Thm 7.)
inline void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double bv = x - a;
  const double av = x - bv;
  y = (a - av) + (b - bv);
}

// Same as two_sum, valid when |a| >= |b| or a == 0 (Dekker, Shewchuk Thm 6).
inline void fast_two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  y = b - (x - a);
}

// x + y == a - b exactly, x == fl(a - b).
inline void two_diff(double a, double b, double& x, double& y) {
  x = a - b;
  const double bv = a - x;
  const double av = x + bv;
  y = (a - av) + (bv - b);
}

// x + y == a * b exactly, x == fl(a * b). With hardware FMA the error term is one fused
// multiply-add; otherwise Dekker's splitting (Shewchuk Thm 18).
inline void two_product(double a, double b, double& x, double& y) {
  x = a * b;
#if defined(__FMA__) || defined(__FMA4__) || defined(__aarch64__)
  y = std::fma(a, b, -x);
#else
  constexpr double kSplitter = 134217729.0;  // 2^27 + 1
  double c = kSplitter * a;
  const double ahi = c - (c - a);
  const double alo = a - ahi;
  c = kSplitter * b;
  const double bhi = c - (c - b);
  const double blo = b - bhi;
  y = alo * blo - (((x - ahi * bhi) - alo * bhi) - ahi * blo);
#endif
}

// h = e + f. h needs room for ne + nf components; returns the length of h.
// (Shewchuk's fast_expansion_sum_zeroelim, with Two-Sum in every step, so it does not rely on
// the strong non-overlap property for its first step.)  h must not alias e or f.
int expansion_sum(const double* e, int ne, const double* f, int nf, double* h);

// h = e - f. Same contract as expansion_sum.
int expansion_diff(const double* e, int ne, const double* f, int nf, double* h);

// h = b * e. h needs room for 2 * ne components; returns the length of h. h must not alias e.
// (Shewchuk's scale_expansion_zeroelim.)
int scale_expansion(const double* e, int ne, double b, double* h);

// h = e * f, the full product: the sum over the components of f of scale_expansion(e, f_j).
// h needs room for 2 * ne * nf components and scratch for 2 * ne * nf + 2 * ne; neither may
// alias e or f. Returns the length of h.
int expansion_product(const double* e, int ne, const double* f, int nf, double* h, double* scratch);

// Rewrites e in place into an equivalent, usually much shorter expansion (Shewchuk's
// Compress, Thm 23: non-adjacent components; the largest approximates the value to within
// one ulp). Returns the new length, never larger than ne.
int compress(double* e, int ne);

// -1, 0 or +1: the exact sign of the value of e.
inline int sign(const double* e, int ne) {
  return ne == 0 ? 0 : (e[ne - 1] > 0 ? 1 : (e[ne - 1] < 0 ? -1 : 0));
}

}  // namespace voroclip::expansion
