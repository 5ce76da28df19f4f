// Internals of the 2D Voronoi clipping predicates (predicates.h, "Voronoi clipping
// predicates in 2D"): the floating-point filters, inlined into bisector2d.cpp, and the
// exact stages. Exposed here, not in the public header, so that the tests can check each
// stage on its own.
//
// Both edge predicates reduce to polynomials of degree 4 in coordinate differences, with
// c_x = p_x - p_i, u = a - p_i, w = b - a, E_x = w . c_x (so D_ix = F_ix(a) - F_ix(b) =
// -2 E_x) and F_ix(a) = c_x . (2u - c_x) = |a - p_i|^2 - |a - p_x|^2:
//
//   bisector_side_edge2d    f_ij(q) = N / E_k with
//                           N = F_ij(a) E_k - F_ik(a) E_j
//                               + eps_i (E_k - E_j) - eps_j E_k + eps_k E_j
//                           (f_ij(q) = (f_ij(a) D_ik - f_ik(a) D_ij) / D_ik, q = a + t w on
//                           the perturbed bisector f_ik = 0: the contract's formula with
//                           N0 = -2 (F_ij(a) E_k - F_ik(a) E_j) and sign(D_ik) = -sign(E_k)).
//   compare_on_bisector2d   with s = 2a - p_i - p_k = u + (a - p_k), X = cross(w, s), and
//                           the crossing q = m + t d on the perturbed bisector (m the midpoint
//                           of p_i p_k, shifted by -e c_k / (2 |c_k|^2), e = eps_i - eps_k):
//                           d . (q - p_i) = (|c_k|^2 X + e cross(w, c_k)) / (2 E), so
//                           d . (q2 - q1) = |c_k|^2 (A + e B) / (2 E1 E2) with
//                           A = X2 E1 - X1 E2,  B = -cross(w1, w2).
//                           (The contract's degree-6 A and degree-4 B are 2 |c_k|^2 times
//                           these: the factor |c_k|^2 > 0 drops out.)
//
// Filter bound (dynamic, from the magnitudes of the call). Model: mu = 2^-53 is the unit
// roundoff; a sum of doubles is exact or has relative error <= mu (a sum below 2^-1021 is
// exact); a product has relative error <= mu or, when its result is subnormal, absolute
// error <= 2^-1075. Count for each computed monomial the roundings it went through, k: a
// rounded leaf difference 1, a sum 1 + k(operand), a product 1 + k(left) + k(right). Then,
// without underflow, |computed - exact| <= gamma_k mag, gamma_k = k mu / (1 - k mu), where
// mag is the same expression tree evaluated on the absolute values of the leaves with every
// subtraction made an addition (so monomials never cancel in it; Higham, "Accuracy and
// Stability of Numerical Algorithms", 2nd ed., section 3.1, applied monomial by monomial). The
// filters evaluate mag in floating point beside the value, with |u_x| + |v_x| standing for |s_x| (v
// = a - p_k, s = u + v): F and X have k = 5, E k = 4, the degree-4 values N and A k = 11; their mag
// takes 7 roundings from the rounded leaves, which are within a factor 1 +- mu of the exact ones.
// So the constant must be at least
//   gamma_11 (1 + mu)^(7 + 2) / (1 - mu)^4 = 11 mu (1 + O(24 mu))   (N, A: 1.23e-15)
//   gamma_4 (1 + mu)^(2 + 2) / (1 - mu)^2  =  4 mu (1 + O(10 mu))   (E:    4.45e-16)
// where the extra (1 + mu)^2 covers the rounding of bound * mag (and one to spare); the
// rounding up to 3 digits leaves 0.2 % (E) and 0.7 % (N, A) of slack, far above O(24 mu).
// (scripts/filter_bounds.py prints them.) Underflow: an absolute error of at most 2^-1075
// at a product node reaches the root multiplied by the magnitudes of its co-factors: at
// most 2 + 2 S in all, where S is the sum of the four degree-2 magnitudes (F or X, and E);
// with the second-order terms and the mag's own underflow, below 2^-1073 (1 + S). The
// filter decides only when mag >= 2^-1000 (1 + S) (E: mag >= 2^-1000), where that is below
// 2^-73 mag, well inside the constants' slack. (Adding 2^-1070 (1 + S) to the bound would
// be as rigorous, but arithmetic on subnormals costs about 100 cycles on x86: 4x the
// filter.) Overflow needs no range test: every computed |value| is at most its computed
// mag (rounding is monotone), so when the mags are finite nothing overflowed; an infinite
// or NaN mag (overflow, or NaN/infinite input) makes |value| > bound * mag false. So the
// filter works at every magnitude where the degree-4 values stay above 2^-1000.
#pragma once

#include <cmath>
#include <cstdint>

#include "voroclip/predicates.h"

namespace voroclip::detail {

inline constexpr double kBisectorDegree4Bound = 1.23e-15;  // 11 mu, rounded up
inline constexpr double kBisectorDegree2Bound = 4.45e-16;  // 4 mu, rounded up
inline constexpr double kBisectorMagLower = 0x1p-1000;

// sign f_ij(q) for q = [a, b] ∩ bisector(i, k) when the unperturbed N and E_k are certainly
// non-zero: +1 / -1; 0 when the exact stage must decide.
inline int bisector_edge_filter(const double* pi, const double* pk, const double* pj,
                                const double* a, const double* b) {
  const double ckx = pk[0] - pi[0], cky = pk[1] - pi[1];
  const double cjx = pj[0] - pi[0], cjy = pj[1] - pi[1];
  const double ux = a[0] - pi[0], uy = a[1] - pi[1];
  const double vkx = a[0] - pk[0], vky = a[1] - pk[1];
  const double vjx = a[0] - pj[0], vjy = a[1] - pj[1];
  const double wx = b[0] - a[0], wy = b[1] - a[1];
  const double fik = ckx * (ux + vkx) + cky * (uy + vky);
  const double fij = cjx * (ux + vjx) + cjy * (uy + vjy);
  const double ek = wx * ckx + wy * cky;
  const double ej = wx * cjx + wy * cjy;
  const double n = fij * ek - fik * ej;

  const double aux = std::fabs(ux), auy = std::fabs(uy);
  const double awx = std::fabs(wx), awy = std::fabs(wy);
  const double ackx = std::fabs(ckx), acky = std::fabs(cky);
  const double acjx = std::fabs(cjx), acjy = std::fabs(cjy);
  const double mfik = ackx * (aux + std::fabs(vkx)) + acky * (auy + std::fabs(vky));
  const double mfij = acjx * (aux + std::fabs(vjx)) + acjy * (auy + std::fabs(vjy));
  const double mek = awx * ackx + awy * acky;
  const double mej = awx * acjx + awy * acjy;
  const double mn = mfij * mek + mfik * mej;
  const double s = (mfik + mfij) + (mek + mej);

  const bool n_certain =
      std::fabs(n) > kBisectorDegree4Bound * mn && mn >= kBisectorMagLower * (1 + s);
  const bool e_certain = std::fabs(ek) > kBisectorDegree2Bound * mek && mek >= kBisectorMagLower;
  if (n_certain && e_certain) return decided_sign(n) * decided_sign(ek);
  return 0;
}

// sign d . (q2 - q1) for the crossings of [a1, b1] and [a2, b2] with bisector(i, k) when
// the unperturbed A, E1 and E2 are certainly non-zero: +1 / -1; 0 otherwise.
inline int bisector_compare_filter(const double* pi, const double* pk, const double* a1,
                                   const double* b1, const double* a2, const double* b2) {
  const double cx = pk[0] - pi[0], cy = pk[1] - pi[1];
  const double acx = std::fabs(cx), acy = std::fabs(cy);
  struct Crossing {
    double x, e, mx, me;
  };
  const auto crossing = [&](const double* a, const double* b) {
    const double ux = a[0] - pi[0], uy = a[1] - pi[1];
    const double vx = a[0] - pk[0], vy = a[1] - pk[1];
    const double wx = b[0] - a[0], wy = b[1] - a[1];
    const double awx = std::fabs(wx), awy = std::fabs(wy);
    return Crossing{wx * (uy + vy) - wy * (ux + vx), wx * cx + wy * cy,
                    awx * (std::fabs(uy) + std::fabs(vy)) + awy * (std::fabs(ux) + std::fabs(vx)),
                    awx * acx + awy * acy};
  };
  const Crossing q1 = crossing(a1, b1), q2 = crossing(a2, b2);
  const double det = q2.x * q1.e - q1.x * q2.e;
  const double mdet = q2.mx * q1.me + q1.mx * q2.me;
  const double s = (q1.mx + q2.mx) + (q1.me + q2.me);

  const bool det_certain =
      std::fabs(det) > kBisectorDegree4Bound * mdet && mdet >= kBisectorMagLower * (1 + s);
  const bool e1_certain =
      std::fabs(q1.e) > kBisectorDegree2Bound * q1.me && q1.me >= kBisectorMagLower;
  const bool e2_certain =
      std::fabs(q2.e) > kBisectorDegree2Bound * q2.me && q2.me >= kBisectorMagLower;
  if (det_certain && e1_certain && e2_certain) {
    return decided_sign(det) * decided_sign(q1.e) * decided_sign(q2.e);
  }
  return 0;
}

// The exact stages, for every finite input (non-finite coordinates throw voroclip::Error);
// they also throw when the preconditions are violated (see predicates.h).
Sign bisector_side_edge2d_exact(const double* pi, const double* pk, const double* pj,
                                const double* a, const double* b, std::uint32_t i, std::uint32_t k,
                                std::uint32_t j);
Sign compare_on_bisector2d_exact(const double* pi, const double* pk, const double* a1,
                                 const double* b1, const double* a2, const double* b2,
                                 std::uint32_t i, std::uint32_t k);

}  // namespace voroclip::detail
