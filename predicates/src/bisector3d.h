// Internals of the 3D Voronoi clipping predicates (predicates.h, "Voronoi clipping
// predicates in 3D"): the floating-point filters, inlined into bisector3d.cpp, and the
// exact stages. Exposed here, not in the public header, so that the tests can check each
// stage on its own.
//
// Reduced forms, in differences to p_i: c_x = p_x - p_i, u = a - p_i, and for y in space
// F_ix(y) = |y - p_i|^2 - |y - p_x|^2 = c_x . (2 (y - p_i) - c_x), so that
// F_ix(a) = c_x . (2u - c_x) and F_ix(y) - F_ix(a) = 2 (y - a) . c_x (eps cancels too).
//
//   bisector_side_edge3d   as in 2D (bisector2d.h) with 3D dot products: w = b - a,
//       E_x = w . c_x (so f_ik(a) - f_ik(b) = -2 E_k), sign f_ij(q) = sign(N) * sign(E_k),
//       N = F_ij(a) E_k - F_ik(a) E_j + eps_i (E_k - E_j) - eps_j E_k + eps_k E_j.
//
//   bisector_side_facet3d  w1 = b - a, w2 = c - a, E_x1 = w1 . c_x, E_x2 = w2 . c_x and
//       m_1 = E_k1 E_l2 - E_k2 E_l1,  m_2 = E_l1 E_j2 - E_l2 E_j1,  m_3 = E_j1 E_k2 - E_j2 E_k1.
//     Subtracting column a from columns b and c of the contract's 3 x 3 matrices leaves
//     2 E_x1 and 2 E_x2 there (row f_ix), and 0 in the row of ones; expanding along column a:
//       D = 4 m_1,   N = 4 (f_ij(a) m_1 + f_ik(a) m_2 + f_il(a) m_3) = 4 (N' + P),
//       N' = F_ij(a) m_1 + F_ik(a) m_2 + F_il(a) m_3,   P = e_ij m_1 + e_ik m_2 + e_il m_3
//     (e_xy = eps_x - eps_y), so sign f_ij(x) = sign(N' + P) * sign(m_1), and P has the
//     coefficients
//       eps_i: m_1 + m_2 + m_3,  eps_j: -m_1 (non-zero: never zero),  eps_k: -m_2,  eps_l: -m_3.
//     By the Binet-Cauchy identity m_x = n . (c_y x c_z) with n = w1 x w2, (x, y, z) a cyclic
//     order of (j, k, l): m_1 = 0 when the triangle is degenerate, c_k and c_l are parallel,
//     or the plane is parallel to the line of the two bisectors (direction c_k x c_l); and
//     the eps_i coefficient is n . ((p_k - p_j) x (p_l - p_j)). N' has degree 6 and m_x
//     degree 4 in coordinate differences. An odd permutation of (a, b, c) changes the sign
//     of n, so of N' and m_1; swapping k and l changes the sign of m_1 and swaps m_2 and m_3
//     with a sign change: the result depends on neither.
//
// Filter bound. The 2D filters carry a magnitude beside every value (bisector2d.h); in 3D
// that would double the arithmetic, so the bounds here are products of per-vector norms.
// Model (as in bisector2d.h): mu = 2^-53; without underflow and overflow, the computed value
// of a tree of sums and products of rounded leaf differences satisfies
// |computed - exact| <= gamma_k mag, gamma_k = k mu / (1 - k mu), where k counts the
// roundings on a monomial's path (leaf difference 1, sum 1 + k(operand), product 1 + k(left)
// + k(right); 2u = u + u is exact) and mag is the sum of |monomial| over the tree's
// monomials at the exact leaves (Higham, "Accuracy and Stability of Numerical Algorithms",
// 2nd ed., section 3.1). With the L-infinity norms of the rounded leaf vectors, W (w), W1,
// W2, C_x (c_x) and U (u), every monomial is bounded by a product of norms:
//   F_x = c_x . (2u - c_x)           k 6    mag <= 3 C_x (2U + C_x)
//   E_x = w . c_x                    k 5    mag <= 3 W C_x
//   edge N = F_j E_k - F_k E_j       k 13   mag <= 9 W C_j C_k (4U + C_j + C_k)
//   m_1 = E_k1 E_l2 - E_k2 E_l1      k 12   mag <= 18 W1 W2 C_k C_l
//   N' = (F_j m_1 + F_k m_2) + F_l m_3   k 21
//                      mag <= 54 W1 W2 C_j C_k C_l (6U + C_j + C_k + C_l)
// The exact leaves exceed the rounded ones by a factor 1 / (1 - mu) at most (deg of them);
// the norm product P of the bound is evaluated with r roundings, counted like k with exact
// leaves (non-negative values: each loses a factor 1 + mu at most; r = 5 for edge N, 1 for
// E_k, 9 for N', 3 for m_1), and K * P with one more (and one to spare). So the filter
// decides sign(value) when |value| > K * P with
//   K >= count * gamma_k * (1 + mu)^(r + 2) / (1 - mu)^deg,
//   edge N 117 mu (stored 1.30e-14), E_k 15 mu (1.67e-15),
//   facet N' 1134 mu (1.26e-13), m_1 216 mu (2.40e-14),
// each rounded up to 3 digits, leaving at least 0.08 % of slack, far above the O(40 mu)
// neglected (scripts/filter_bounds.py computes and checks them).
//
// Range. The filters decide only when W (W1, W2) and every C_x lie in [2^-R, 2^R] and
// U <= 2^R, R = 200 for the degree-4 edge values and 150 for the degree-6 facet values.
// Then (1) nothing overflows: every intermediate is below a small constant times a product
// of at most 6 norms, <= 2^900 (2U + C_x <= 3 * 2^R); (2) underflow is negligible: a product
// whose result underflows has an absolute error <= 2^-1075, which reaches the root
// multiplied by its co-factor (the product of its siblings along the path). Every monomial
// of the root is a monomial of the node times one of its co-factor, so the co-factor is
// bounded by a small count times T / B, T the root's norm product and B the node's, a
// product of d factors >= 2^-R each (2U + C_x >= C_x). For the nodes below the root (d <= 4) the
// error is <= 2^-1075 * 2^(4R) count T <= 2^-400 count T, and at the root (co-factor 1) 2^-1075 <=
// 2^-175 T: far inside the constants' slack. Outside the range (tiny or huge coordinates,
// coincident sites or vertices, NaN or infinities) the exact stage decides: an infinite norm fails
// the range test, and a NaN leaf makes the value NaN (every leaf enters it), which fails |value| >
// K * P.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "voroclip/predicates.h"

namespace voroclip::detail {

inline constexpr double kBisector3dEdgeBound = 1.30e-14;   // 117 mu, rounded up
inline constexpr double kBisector3dCrossBound = 1.67e-15;  // 15 mu
inline constexpr double kBisector3dFacetBound = 1.26e-13;  // 1134 mu
inline constexpr double kBisector3dPlaneBound = 2.40e-14;  // 216 mu
inline constexpr double kBisector3dEdgeLower = 0x1p-200, kBisector3dEdgeUpper = 0x1p+200;
inline constexpr double kBisector3dFacetLower = 0x1p-150, kBisector3dFacetUpper = 0x1p+150;

// A 3D vector of rounded differences p - q and its L-infinity norm.
struct Diff3 {
  double x, y, z, norm;
};

inline Diff3 diff3(const double* p, const double* q) {
  const double x = p[0] - q[0], y = p[1] - q[1], z = p[2] - q[2];
  return {x, y, z, std::max(std::max(std::fabs(x), std::fabs(y)), std::fabs(z))};
}

inline double dot3(const Diff3& p, const Diff3& q) { return (p.x * q.x + p.y * q.y) + p.z * q.z; }

// F_ix(a) = c . (2u - c) for c = c_x; u2 = 2u (exact).
inline double bisector_value3(const Diff3& c, double u2x, double u2y, double u2z) {
  return (c.x * (u2x - c.x) + c.y * (u2y - c.y)) + c.z * (u2z - c.z);
}

// sign f_ij(q) for q = [a, b] ∩ bisector(i, k) when the unperturbed N and E_k are certainly
// non-zero: +1 / -1; 0 when the exact stage must decide.
inline int bisector_edge3d_filter(const double* pi, const double* pk, const double* pj,
                                  const double* a, const double* b) {
  const Diff3 ck = diff3(pk, pi), cj = diff3(pj, pi), w = diff3(b, a), u = diff3(a, pi);
  const double u2x = u.x + u.x, u2y = u.y + u.y, u2z = u.z + u.z;
  const double ek = dot3(w, ck), ej = dot3(w, cj);
  const double n =
      bisector_value3(cj, u2x, u2y, u2z) * ek - bisector_value3(ck, u2x, u2y, u2z) * ej;

  const double lower = std::min(std::min(w.norm, ck.norm), cj.norm);
  const double upper = std::max(std::max(w.norm, ck.norm), std::max(cj.norm, u.norm));
  const double pe = w.norm * ck.norm;
  const double pn = (pe * cj.norm) * ((4 * u.norm + cj.norm) + ck.norm);
  if (lower >= kBisector3dEdgeLower && upper <= kBisector3dEdgeUpper &&
      std::fabs(n) > kBisector3dEdgeBound * pn && std::fabs(ek) > kBisector3dCrossBound * pe) {
    return decided_sign(n) * decided_sign(ek);
  }
  return 0;
}

// sign f_ij(x) for x = plane(a, b, c) ∩ bisector(i, k) ∩ bisector(i, l) when the
// unperturbed N' and m_1 are certainly non-zero: +1 / -1; 0 when the exact stage must
// decide.
inline int bisector_facet3d_filter(const double* pi, const double* pk, const double* pl,
                                   const double* pj, const double* a, const double* b,
                                   const double* c) {
  const Diff3 cj = diff3(pj, pi), ck = diff3(pk, pi), cl = diff3(pl, pi);
  const Diff3 w1 = diff3(b, a), w2 = diff3(c, a), u = diff3(a, pi);
  const double ej1 = dot3(w1, cj), ej2 = dot3(w2, cj);
  const double ek1 = dot3(w1, ck), ek2 = dot3(w2, ck);
  const double el1 = dot3(w1, cl), el2 = dot3(w2, cl);
  const double m1 = ek1 * el2 - ek2 * el1;
  const double m2 = el1 * ej2 - el2 * ej1;
  const double m3 = ej1 * ek2 - ej2 * ek1;
  const double u2x = u.x + u.x, u2y = u.y + u.y, u2z = u.z + u.z;
  const double n =
      (bisector_value3(cj, u2x, u2y, u2z) * m1 + bisector_value3(ck, u2x, u2y, u2z) * m2) +
      bisector_value3(cl, u2x, u2y, u2z) * m3;

  const double lower =
      std::min(std::min(std::min(w1.norm, w2.norm), std::min(cj.norm, ck.norm)), cl.norm);
  const double upper = std::max(std::max(std::max(w1.norm, w2.norm), std::max(cj.norm, ck.norm)),
                                std::max(cl.norm, u.norm));
  const double pd = ((w1.norm * w2.norm) * ck.norm) * cl.norm;
  const double pn = (pd * cj.norm) * (((6 * u.norm + cj.norm) + ck.norm) + cl.norm);
  if (lower >= kBisector3dFacetLower && upper <= kBisector3dFacetUpper &&
      std::fabs(n) > kBisector3dFacetBound * pn && std::fabs(m1) > kBisector3dPlaneBound * pd) {
    return decided_sign(n) * decided_sign(m1);
  }
  return 0;
}

// sign(n . ((b - a) x (c - a))), n = (p_k - p_i) x (p_l - p_i): m_1 above (Binet-Cauchy), with
// its bound, when certainly non-zero: +1 / -1; 0 when the exact stage must decide.
inline int voronoi_edge_direction3d_filter(const double* pi, const double* pk, const double* pl,
                                           const double* a, const double* b, const double* c) {
  const Diff3 ck = diff3(pk, pi), cl = diff3(pl, pi), w1 = diff3(b, a), w2 = diff3(c, a);
  const double m1 = dot3(w1, ck) * dot3(w2, cl) - dot3(w2, ck) * dot3(w1, cl);
  const double lower = std::min(std::min(w1.norm, w2.norm), std::min(ck.norm, cl.norm));
  const double upper = std::max(std::max(w1.norm, w2.norm), std::max(ck.norm, cl.norm));
  const double pd = ((w1.norm * w2.norm) * ck.norm) * cl.norm;
  if (lower >= kBisector3dFacetLower && upper <= kBisector3dFacetUpper &&
      std::fabs(m1) > kBisector3dPlaneBound * pd) {
    return decided_sign(m1);
  }
  return 0;
}

// The exact stages, for every finite input (non-finite coordinates throw voroclip::Error);
// they also throw when the preconditions are violated (see predicates.h).
Sign bisector_side_edge3d_exact(const double* pi, const double* pk, const double* pj,
                                const double* a, const double* b, std::uint32_t i, std::uint32_t k,
                                std::uint32_t j);
Sign bisector_side_facet3d_exact(const double* pi, const double* pk, const double* pl,
                                 const double* pj, const double* a, const double* b,
                                 const double* c, std::uint32_t i, std::uint32_t k, std::uint32_t l,
                                 std::uint32_t j);

Sign voronoi_edge_direction3d_exact(const double* pi, const double* pk, const double* pl,
                                    const double* a, const double* b, const double* c);

}  // namespace voroclip::detail
