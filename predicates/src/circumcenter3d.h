// Internals of the circumcenter predicates (predicates.h, "Circumcenters of tetrahedra"):
// the floating-point filter, inlined into circumcenter3d.cpp, and the exact stage. Exposed
// here, not in the public header, so that the tests can check each stage on its own.
//
// Reduced form, in differences to p_0: d_k = p_k - p_0 (k = 1, 2, 3), u = a - p_0,
// w1 = b - a, w2 = c - a, n = w1 x w2 (the normal of the facet, degree 2),
//   D  = d_1 . (d_2 x d_3)                                           (degree 3)
//   Nv = |d_1|^2 (d_2 x d_3) + |d_2|^2 (d_3 x d_1) + |d_3|^2 (d_1 x d_2) (degree 4)
// The circumcenter is x = p_0 + Nv / (2 D) (the solution of 2 d_k . (x - p_0) = |d_k|^2),
// and orient3d(a, b, c, x) = det[a - x; b - x; c - x] = -(x - a) . n, so
//   sign orient3d(a, b, c, x) = -sign(P) * sign(D),   P = n . (Nv - 2 D u)  (degree 6).
//
// Filter bound (the norm-product model of bisector3d.h): mu = 2^-53, k counts the
// roundings on a monomial's path (leaf difference 1, sum 1 + k(operand), product 1 + k(left)
// + k(right); 2 D is exact), |computed - exact| <= gamma_k mag, mag the sum of |monomial|
// at the exact leaves. With the L-infinity norms W1, W2, D1, D2, D3, U of the rounded leaf
// vectors w1, w2, d_1, d_2, d_3, u:
//   n_x                              k 4    mag <= 2 W1 W2
//   |d_k|^2                          k 5    mag <= 3 Dk^2
//   (d_2 x d_3)_x                    k 4    mag <= 2 D2 D3
//   Nv_x = (l1 c23 + l2 c31) + l3 c12    k 12   mag <= 6 D1 D2 D3 (D1 + D2 + D3)
//   D = (d1x c23x + d1y c23y) + d1z c23z k 8    mag <= 6 D1 D2 D3
//   t_x = Nv_x - (2 D) u_x           k 13   mag <= 6 D1 D2 D3 (D1 + D2 + D3 + 2 U)
//   P = (n_x t_x + n_y t_y) + n_z t_z    k 20   mag <= 36 W1 W2 D1 D2 D3 (D1 + D2 + D3 + 2 U)
// The filter decides sign(value) when |value| > K * P~, P~ the norm product evaluated with
// r roundings (P: r = 8, D: r = 2), K >= count * gamma_k * (1 + mu)^(r + 2) / (1 - mu)^deg:
//   P 720 mu (stored 8.00e-14), D 48 mu (5.33e-15), each rounded up to 3 digits
// (scripts/filter_bounds.py computes them and checks the slack).
//
// Range. As for the facet predicate of bisector3d.h (degree 6, the same shape of norm
// product): the filter decides only when W1, W2, D1, D2, D3 lie in [2^-150, 2^150] and
// U <= 2^150; then nothing overflows and underflow stays far inside the constants' slack.
// Outside the range, and for NaN or infinite coordinates, the exact stage decides (or
// throws).
//
// Enclosure of the circumcenter (circumcenter3d_enclosure). With the same bounds
// eN = KN * D1 D2 D3 (D1 + D2 + D3) on |Nv~_x - Nv_x| (KN >= 6 gamma_12 (1 + mu)^7 /
// (1 - mu)^4: 72 mu, stored 8.00e-15) and eD = KD * D1 D2 D3 on |D~ - D|, and
// delta = |D~| - eD > 0 (else no enclosure: the tet is too flat for the bound):
//   |Nv_x / (2 D) - Nv~_x / (2 D~)| <= (eN + |Nv~_x| eD / |D~|) / (2 delta)
// (from Nv/D - Nv~/D~ = (Nv - Nv~)/D + Nv~ (D~ - D) / (D D~) and |D| >= delta), the
// division adds mu |q~| / (1 - mu) and the sum p_0 + q~ adds mu |x~|. The half-width is
// twice the sum of these terms (which covers the roundings of its own evaluation and of
// x~ +- halfwidth), plus 2^-1000 for underflow.
//
// orient2d_circumcenter(axis, a, b, p0..p3). With (i, j) = (axis + 1, axis + 2) mod 3 and
// w = b - a, its value is the axis component of w x (x - a) = w x t / (2 D), t = Nv - 2 D u
// as above, so
//   sign = sign(Q) * sign(D),   Q = w_i t_j - w_j t_i                (degree 5).
// Filter bound, the same model: only w_i, w_j and u_i, u_j enter, so W and U may be the
// norms of those two components (W = max(|w~_i|, |w~_j|), U likewise):
//   t_x                              k 13   mag <= 6 D1 D2 D3 (D1 + D2 + D3 + 2 U)
//   w_i t_j                          k 15   mag <= 6 W D1 D2 D3 (D1 + D2 + D3 + 2 U)
//   Q = w_i t_j - w_j t_i            k 16   mag <= 12 W D1 D2 D3 (D1 + D2 + D3 + 2 U)
// the norm product evaluated as (W (D1 D2 D3)) ((D1 + D2 + D3) + 2 U), r = 7 roundings:
//   Q 12 gamma_16 (1 + mu)^9 / (1 - mu)^5 = 192.0 mu (stored 2.14e-14, 0.39 % of slack;
//   the norm-product formula of scripts/filter_bounds.py with count 12, k 16, r 7, deg 5).
// Range: as for P (degree 5 < 6, the same norms in [2^-150, 2^150]): a product that
// underflows at degree d <= 4 reaches Q multiplied by at most a small count times T / B
// <= 2^(4 * 150) T (T the root's norm product, B >= 2^(-150 d) the node's), so its error is
// below 2^-475 T, and at the top products (co-factor 1) 2^-1075 <= 2^-325 T: far inside
// the slack (about 2^-60 T).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "bisector3d.h"
#include "voroclip/predicates.h"

namespace voroclip::detail {

inline constexpr double kCircumcenterSideBound = 8.00e-14;      // 720 mu, rounded up
inline constexpr double kCircumcenterOrient2dBound = 2.14e-14;  // 192 mu
// kCircumcenterDetBound (48 mu), kCircumcenterNumBound (72 mu) and the range
// kCircumcenterLower / kCircumcenterUpper are in predicates.h (circumcenter3d's inline
// floating-point path uses them).

// The floating-point values of the reduced form (differences to p0) and their norms.
struct CircumcenterApprox {
  double nv[3];  // Nv
  double det;    // D
  double pd;     // D1 D2 D3 (rounded)
  double ps;     // D1 + D2 + D3 (rounded)
  double lower, upper;
};

// Nv and D (above) in the exact arithmetic C over the differences d[k] = p_(k+1)
// - p0; false when D == 0.
template <class C>
bool exact_nv_det(C& c, const typename C::Num (&d)[3][3], typename C::Num (&nv)[3],
                  typename C::Num& det) {
  using Num = typename C::Num;
  const auto cross = [&](const Num(&a)[3], const Num(&b)[3], Num(&out)[3]) {
    out[0] = c.sub(c.mul(a[1], b[2]), c.mul(a[2], b[1]));
    out[1] = c.sub(c.mul(a[2], b[0]), c.mul(a[0], b[2]));
    out[2] = c.sub(c.mul(a[0], b[1]), c.mul(a[1], b[0]));
  };
  const auto dot = [&](const Num(&a)[3], const Num(&b)[3]) {
    return c.add(c.add(c.mul(a[0], b[0]), c.mul(a[1], b[1])), c.mul(a[2], b[2]));
  };
  Num c23[3], c31[3], c12[3];
  cross(d[1], d[2], c23);
  cross(d[2], d[0], c31);
  cross(d[0], d[1], c12);
  det = dot(d[0], c23);
  if (C::sign(det) == 0) return false;
  const Num l1 = dot(d[0], d[0]), l2 = dot(d[1], d[1]), l3 = dot(d[2], d[2]);
  for (int k = 0; k < 3; ++k) {
    nv[k] = c.add(c.add(c.mul(l1, c23[k]), c.mul(l2, c31[k])), c.mul(l3, c12[k]));
  }
  return true;
}

inline CircumcenterApprox circumcenter_approx(const double* p0, const double* p1, const double* p2,
                                              const double* p3) {
  const Diff3 d1 = diff3(p1, p0), d2 = diff3(p2, p0), d3 = diff3(p3, p0);
  const double c23[3] = {d2.y * d3.z - d2.z * d3.y, d2.z * d3.x - d2.x * d3.z,
                         d2.x * d3.y - d2.y * d3.x};
  const double c31[3] = {d3.y * d1.z - d3.z * d1.y, d3.z * d1.x - d3.x * d1.z,
                         d3.x * d1.y - d3.y * d1.x};
  const double c12[3] = {d1.y * d2.z - d1.z * d2.y, d1.z * d2.x - d1.x * d2.z,
                         d1.x * d2.y - d1.y * d2.x};
  const double l1 = dot3(d1, d1), l2 = dot3(d2, d2), l3 = dot3(d3, d3);
  CircumcenterApprox r;
  for (int t = 0; t < 3; ++t) r.nv[t] = (l1 * c23[t] + l2 * c31[t]) + l3 * c12[t];
  r.det = (d1.x * c23[0] + d1.y * c23[1]) + d1.z * c23[2];
  r.pd = (d1.norm * d2.norm) * d3.norm;
  r.ps = (d1.norm + d2.norm) + d3.norm;
  r.lower = std::min(std::min(d1.norm, d2.norm), d3.norm);
  r.upper = std::max(std::max(d1.norm, d2.norm), d3.norm);
  return r;
}

// sign orient3d(a, b, c, circumcenter(p0, p1, p2, p3)) when P and D are certainly non-zero:
// +1 / -1; 0 when the exact stage must decide.
inline int circumcenter_side_filter(const double* a, const double* b, const double* c,
                                    const double* p0, const double* p1, const double* p2,
                                    const double* p3) {
  const CircumcenterApprox x = circumcenter_approx(p0, p1, p2, p3);
  const Diff3 w1 = diff3(b, a), w2 = diff3(c, a), u = diff3(a, p0);
  const double n[3] = {w1.y * w2.z - w1.z * w2.y, w1.z * w2.x - w1.x * w2.z,
                       w1.x * w2.y - w1.y * w2.x};
  const double d2 = x.det + x.det;
  const double t[3] = {x.nv[0] - d2 * u.x, x.nv[1] - d2 * u.y, x.nv[2] - d2 * u.z};
  const double p = (n[0] * t[0] + n[1] * t[1]) + n[2] * t[2];

  const double lower = std::min(std::min(w1.norm, w2.norm), x.lower);
  const double upper = std::max(std::max(std::max(w1.norm, w2.norm), x.upper), u.norm);
  const double pp = (((w1.norm * w2.norm) * x.pd)) * (x.ps + 2 * u.norm);
  if (lower >= kCircumcenterLower && upper <= kCircumcenterUpper &&
      std::fabs(p) > kCircumcenterSideBound * pp &&
      std::fabs(x.det) > kCircumcenterDetBound * x.pd) {
    return -decided_sign(p) * decided_sign(x.det);
  }
  return 0;
}

// orient2d_circumcenter's value (the axis component of (b - a) x (x - a), x the
// circumcenter) when Q and D are certainly non-zero: +1 / -1; 0 when the exact stage must
// decide. axis is 0, 1 or 2 (not checked here).
inline int circumcenter_orient2d_filter(int axis, const double* a, const double* b,
                                        const double* p0, const double* p1, const double* p2,
                                        const double* p3) {
  const CircumcenterApprox x = circumcenter_approx(p0, p1, p2, p3);
  const int i = axis == 2 ? 0 : axis + 1, j = axis == 0 ? 2 : axis - 1;
  const double wi = b[i] - a[i], wj = b[j] - a[j];
  const double ui = a[i] - p0[i], uj = a[j] - p0[j];
  const double d2 = x.det + x.det;
  const double ti = x.nv[i] - d2 * ui, tj = x.nv[j] - d2 * uj;
  const double q = wi * tj - wj * ti;

  const double wn = std::max(std::fabs(wi), std::fabs(wj));
  const double un = std::max(std::fabs(ui), std::fabs(uj));
  const double lower = std::min(wn, x.lower);
  const double upper = std::max(std::max(wn, x.upper), un);
  const double pq = (wn * x.pd) * (x.ps + 2 * un);
  if (lower >= kCircumcenterLower && upper <= kCircumcenterUpper &&
      std::fabs(q) > kCircumcenterOrient2dBound * pq &&
      std::fabs(x.det) > kCircumcenterDetBound * x.pd) {
    return decided_sign(q) * decided_sign(x.det);
  }
  return 0;
}

// The exact stages, for every finite input; throw voroclip::Error for coplanar p0..p3 and
// non-finite coordinates.
Sign orient3d_circumcenter_exact(const double* a, const double* b, const double* c,
                                 const double* p0, const double* p1, const double* p2,
                                 const double* p3);

Sign orient2d_circumcenter_exact(int axis, const double* a, const double* b, const double* p0,
                                 const double* p1, const double* p2, const double* p3);

}  // namespace voroclip::detail
