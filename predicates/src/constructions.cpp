// Constructions of the clipped diagrams' vertices (predicates.h, "Constructions"): the 2D
// Voronoi vertex (circumcentre of a triangle) and the 3D point where a boundary facet's
// plane meets two bisectors. Each is a floating-point formula with a proven error bound,
// used when the bound is below kConstructionLimit of the input's size, else the exact
// numerator and denominator (expansions after a power-of-two scaling, big integers when
// the exponents span too much), each rounded, then divided.
//
// Error model (as circumcenter3d.h): mu = 2^-53; k counts the roundings on a monomial's
// path (leaf difference 1, sum 1 + max k(operand), product 1 + k(left) + k(right));
// |computed - exact| <= gamma_k mag, mag the sum of |monomial| at the leaves, bounded by
// products of the L-infinity norms of the rounded leaf vectors; gamma_k = k mu / (1 - k mu).
// The constants below are 1.4 to 2.3 times the bounds so derived, which covers the rounding of
// the norm products themselves and of the leaves' norms.
//
// circumcenter2d. Differences to a: b' = b - a, c' = c - a (norms B, C).
//   |b'|^2                               k 4    mag <= 2 B^2
//   D = b'x c'y - b'y c'x                k 4    mag <= 2 B C
//   Nx = c'y |b'|^2 - b'y |c'|^2         k 7    mag <= 2 B C (B + C)      (Ny alike)
// center = a + N / (2 D). eD = 2^-49 B C (>= 2 gamma_4 = 8 mu), eN = 2^-48 B C (B + C)
// (>= 2 gamma_7 = 14 mu).
//
// plane_bisectors_point3d. Leaves d1 = p1 - p0, d2 = p2 - p0, u = a - p0, w1 = b - a,
// w2 = c - a (norms D1, D2, U, W1, W2); n = w1 x w2, e = d1 x d2. The point is p0 + y with
//   n . y = n . u,   d1 . y = |d1|^2 / 2,   d2 . y = |d2|^2 / 2,
// so (Cramer) y = N / (2 det), det = n . e, N = 2 (n . u) e + |d1|^2 (d2 x n) + |d2|^2 (n x d1):
//   n_x, e_x                             k 4    mag <= 2 W1 W2, 2 D1 D2
//   n . u                                k 8    mag <= 6 W1 W2 U
//   2 (n . u) e_x                        k 13   mag <= 24 W1 W2 U D1 D2
//   |d1|^2 (d2 x n)_x                    k 13   mag <= 12 W1 W2 D1^2 D2   (|d2|^2 (n x d1)_x alike)
//   N_x                                  k 15   mag <= 12 W1 W2 D1 D2 (2 U + D1 + D2)
//   det = n . e                          k 11   mag <= 12 W1 W2 D1 D2
// eN = 2^-45 W1 W2 D1 D2 (2 U + D1 + D2) (>= 12 gamma_15 = 180 mu), eD = 2^-45 W1 W2 D1 D2
// (>= 12 gamma_11 = 132 mu).
//
// Both: with delta = |D~| - eD > 0, |N_x / (2 D) - N~_x / (2 D~)| <= (eN + |N~_x| eD / |D~|)
// / (2 delta) (circumcenter3d.h). The floating-point result is taken when that is below
// kConstructionLimit times the sum of the leaves' norms (B + C; D1 + D2 + U), the leaves'
// norms lie in [2^-150, 2^150] (then no product overflows and underflow stays far inside
// the constants' slack: degree <= 5) and the quotient is finite.
#include <algorithm>
#include <cmath>

#include "circumcenter3d.h"
#include "exact.h"
#include "voroclip/core.h"
#include "voroclip/predicates.h"

namespace voroclip {

namespace {

constexpr double kLower = 0x1p-150, kUpper = 0x1p+150;
constexpr double kDet2Bound = 0x1p-49, kNum2Bound = 0x1p-48;
constexpr double kDet3Bound = 0x1p-45, kNum3Bound = 0x1p-45;

// The bound's test: every |N~_k / (2 D~) - N_k / (2 D)| <= limit * size.
bool within_limit(double e_num, double e_det, double det, double num_max, double size) {
  const double abs_det = std::fabs(det), delta = abs_det - e_det;
  return delta > 0 && (e_num * abs_det + num_max * e_det) * (1 + 0x1p-40) <=
                          2 * delta * abs_det * (kConstructionLimit * size);
}

// An expansion's value: its components summed from the smallest (within an ulp or so).
double value(const detail::ExpansionCalc::Num& e) {
  double v = 0;
  for (int k = 0; k < e.n; ++k) v += e.v[k];
  return v;
}

// ---- circumcenter2d, exact stage: over d = {b - a, c - a}, N (2 values) and D.
template <class C>
bool circumcenter2d_terms(C& c, const typename C::Num (&d)[2][2], typename C::Num (&num)[2],
                          typename C::Num& det) {
  det = c.sub(c.mul(d[0][0], d[1][1]), c.mul(d[0][1], d[1][0]));
  if (C::sign(det) == 0) return false;
  const auto lb = c.add(c.mul(d[0][0], d[0][0]), c.mul(d[0][1], d[0][1]));
  const auto lc = c.add(c.mul(d[1][0], d[1][0]), c.mul(d[1][1], d[1][1]));
  num[0] = c.sub(c.mul(d[1][1], lb), c.mul(d[0][1], lc));
  num[1] = c.sub(c.mul(d[0][0], lc), c.mul(d[1][0], lb));
  return true;
}

// ---- plane_bisectors_point3d, exact stage: over d = {d1, d2, u, b - p0, c - p0}, N and det.
template <class C>
bool plane_bisectors_terms(C& c, const typename C::Num (&d)[5][3], typename C::Num (&num)[3],
                           typename C::Num& det) {
  using Num = typename C::Num;
  const auto cross = [&](const Num(&p)[3], const Num(&q)[3], Num(&out)[3]) {
    out[0] = c.sub(c.mul(p[1], q[2]), c.mul(p[2], q[1]));
    out[1] = c.sub(c.mul(p[2], q[0]), c.mul(p[0], q[2]));
    out[2] = c.sub(c.mul(p[0], q[1]), c.mul(p[1], q[0]));
  };
  const auto dot = [&](const Num(&p)[3], const Num(&q)[3]) {
    return c.add(c.add(c.mul(p[0], q[0]), c.mul(p[1], q[1])), c.mul(p[2], q[2]));
  };
  Num w1[3], w2[3], n[3], e[3], f[3], g[3];
  for (int k = 0; k < 3; ++k) {
    w1[k] = c.sub(d[3][k], d[2][k]);
    w2[k] = c.sub(d[4][k], d[2][k]);
  }
  cross(w1, w2, n);
  cross(d[0], d[1], e);
  det = dot(n, e);
  if (C::sign(det) == 0) return false;
  cross(d[1], n, f);
  cross(n, d[0], g);
  const Num nu = dot(n, d[2]);
  const Num nu2 = c.add(nu, nu);
  const Num l1 = dot(d[0], d[0]), l2 = dot(d[1], d[1]);
  for (int k = 0; k < 3; ++k) {
    num[k] = c.add(c.add(c.mul(nu2, e[k]), c.mul(l1, f[k])), c.mul(l2, g[k]));
  }
  return true;
}

// origin + N / (2 det) from the exact terms, for the R points pts (the last is the origin)
// of dimension D, degree `degree` of N. False when det == 0. With `absolute`, the numerator
// is N + 2 det origin, exactly, so that the result is within a few ulps of the exact point
// itself rather than of its offset from the origin (the origin may be a site 1e20 away
// from a point near 0: origin + N / (2 det) then keeps nothing of the offset's bits).
template <int R, int D, class Terms>
bool exact_construction(const double* const (&pts)[R + 1], int degree, const Terms& terms,
                        double* out, bool absolute = false) {
  const double* origin = pts[R];
  const detail::ExponentSpan span = [&] {
    double coords[(R + 1) * D];
    for (int r = 0; r <= R; ++r) {
      for (int j = 0; j < D; ++j) coords[D * r + j] = pts[r][j];
    }
    return detail::exponent_span(coords, (R + 1) * D);
  }();
  int scale = 0;
  if (detail::plan_expansion_scaling(span, degree, scale, 12)) {
    using Calc = detail::ExpansionCalc;
    Calc c(detail::thread_arena());
    Calc::Num d[R][D], num[D], det;
    detail::differences<Calc, R, D>(c, pts, scale, d);
    if (!terms(c, d, num, det)) return false;
    // N scales by 2^(degree scale), det by 2^((degree - 1) scale): the quotient by 2^scale.
    const double det2 = 2 * value(det);
    for (int k = 0; k < D; ++k) {
      if (absolute) {
        // The origin scaled as the differences: origin det as N.
        const auto o = c.diff(scale == 0 ? origin[k] : detail::times_pow2(origin[k], scale), 0.0);
        const auto od = c.mul(o, det);
        const double q = value(c.add(num[k], c.add(od, od))) / det2;
        out[k] = scale == 0 ? q : detail::times_pow2(q, -scale);
        continue;
      }
      const double q = value(num[k]) / det2;
      out[k] = origin[k] + (scale == 0 ? q : detail::times_pow2(q, -scale));
    }
    return true;
  }
  using Calc = detail::BigIntCalc;
  Calc c(span.lowest);
  Calc::Num d[R][D], num[D], det;
  detail::differences<Calc, R, D>(c, pts, 0, d);
  if (!terms(c, d, num, det)) return false;
  int e_det = 0;
  const double m_det = det.approx(e_det);
  for (int k = 0; k < D; ++k) {
    int e_num = 0;
    // N / (2 det) in units of 2^lowest (N in units of 2^(degree lowest), det of
    // 2^((degree - 1) lowest); the origin in units of 2^lowest).
    if (absolute) {
      const Calc::Num od = c.mul(c.diff(origin[k], 0.0), det);
      const double m_num = c.add(num[k], c.add(od, od)).approx(e_num);
      out[k] = std::ldexp(m_num / (2 * m_det), e_num - e_det + span.lowest);
      continue;
    }
    const double m_num = num[k].approx(e_num);
    out[k] = origin[k] + std::ldexp(m_num / (2 * m_det), e_num - e_det + span.lowest);
  }
  return true;
}

// |x - p|^2 - |x - q|^2 (D coordinates) exactly, then rounded (within an ulp or so).
template <int D>
double bisector_value_exact_impl(const double* x, const double* p, const double* q) {
  const double* const pts[3] = {p, q, x};
  const auto terms = [](auto& c, const auto& d) {
    auto f = c.sub(c.mul(d[0][0], d[0][0]), c.mul(d[1][0], d[1][0]));
    for (int k = 1; k < D; ++k) {
      f = c.add(f, c.sub(c.mul(d[0][k], d[0][k]), c.mul(d[1][k], d[1][k])));
    }
    return f;
  };
  double coords[3 * D];
  for (int r = 0; r < 3; ++r) {
    for (int j = 0; j < D; ++j) coords[D * r + j] = pts[r][j];
  }
  detail::require_finite("bisector_value_exact", coords, 3 * D);
  const detail::ExponentSpan span = detail::exponent_span(coords, 3 * D);
  int scale = 0;
  if (detail::plan_expansion_scaling(span, 2, scale, 12)) {
    using Calc = detail::ExpansionCalc;
    Calc c(detail::thread_arena());
    Calc::Num d[2][D];
    detail::differences<Calc, 2, D>(c, pts, scale, d);
    const double f = value(terms(c, d));
    return scale == 0 ? f : detail::times_pow2(f, -2 * scale);
  }
  using Calc = detail::BigIntCalc;
  Calc c(span.lowest);
  Calc::Num d[2][D];
  detail::differences<Calc, 2, D>(c, pts, 0, d);
  int e = 0;
  const double m = terms(c, d).approx(e);
  return std::ldexp(m, e + 2 * span.lowest);
}

}  // namespace

void circumcenter2d(const double* a, const double* b, const double* c, double* center) {
  const double bx = b[0] - a[0], by = b[1] - a[1], cx = c[0] - a[0], cy = c[1] - a[1];
  const double nb = std::max(std::fabs(bx), std::fabs(by));
  const double nc = std::max(std::fabs(cx), std::fabs(cy));
  if (std::min(nb, nc) >= kLower && std::max(nb, nc) <= kUpper) {
    const double lb = bx * bx + by * by, lc = cx * cx + cy * cy;
    const double det = bx * cy - by * cx;
    const double nx = cy * lb - by * lc, ny = bx * lc - cx * lb;
    const double pd = nb * nc, ps = nb + nc;
    if (within_limit(kNum2Bound * (pd * ps), kDet2Bound * pd, det,
                     std::max(std::fabs(nx), std::fabs(ny)), ps)) {
      const double det2 = det + det;
      const double qx = nx / det2, qy = ny / det2;
      if (std::isfinite(qx) && std::isfinite(qy)) {
        center[0] = a[0] + qx;
        center[1] = a[1] + qy;
        return;
      }
    }
  }
  const double coords[6] = {a[0], a[1], b[0], b[1], c[0], c[1]};
  detail::require_finite("circumcenter2d", coords, 6);
  const double* const pts[3] = {b, c, a};
  const auto terms = [](auto& calc, const auto& d, auto& num, auto& det) {
    return circumcenter2d_terms(calc, d, num, det);
  };
  if (!exact_construction<2, 2>(pts, 3, terms, center)) {
    throw Error(
        "circumcenter2d: the three points are collinear: their circumcenter is not defined");
  }
}

namespace {

// The exact stage of plane_bisectors_point3d (absolute: of its _absolute variant, the point
// itself rather than its offset from p0 rounded); false when the point is not defined or not
// finite.
bool plane_bisectors_exact(const double* a, const double* b, const double* c, const double* p0,
                           const double* p1, const double* p2, bool absolute, double* x) {
  for (const double* p : {a, b, c, p0, p1, p2}) {
    if (!(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]))) return false;
  }
  const double* const pts[6] = {p1, p2, a, b, c, p0};
  const auto terms = [](auto& calc, const auto& d, auto& num, auto& det) {
    return plane_bisectors_terms(calc, d, num, det);
  };
  double out[3];
  if (!exact_construction<5, 3>(pts, 5, terms, out, absolute)) return false;
  if (!(std::isfinite(out[0]) && std::isfinite(out[1]) && std::isfinite(out[2]))) return false;
  for (int k = 0; k < 3; ++k) x[k] = out[k];
  return true;
}

}  // namespace

bool plane_bisectors_point3d(const double* a, const double* b, const double* c, const double* p0,
                             const double* p1, const double* p2, double* x) {
  double d1[3], d2[3], u[3], w1[3], w2[3];
  for (int k = 0; k < 3; ++k) {
    d1[k] = p1[k] - p0[k];
    d2[k] = p2[k] - p0[k];
    u[k] = a[k] - p0[k];
    w1[k] = b[k] - a[k];
    w2[k] = c[k] - a[k];
  }
  const auto norm = [](const double* v) {
    return std::max(std::max(std::fabs(v[0]), std::fabs(v[1])), std::fabs(v[2]));
  };
  const double n1 = norm(d1), n2 = norm(d2), nu = norm(u), nw1 = norm(w1), nw2 = norm(w2);
  if (std::min(std::min(n1, n2), std::min(nw1, nw2)) >= kLower &&
      std::max(std::max(std::max(n1, n2), std::max(nw1, nw2)), nu) <= kUpper) {
    const double n[3] = {w1[1] * w2[2] - w1[2] * w2[1], w1[2] * w2[0] - w1[0] * w2[2],
                         w1[0] * w2[1] - w1[1] * w2[0]};
    const double e[3] = {d1[1] * d2[2] - d1[2] * d2[1], d1[2] * d2[0] - d1[0] * d2[2],
                         d1[0] * d2[1] - d1[1] * d2[0]};
    const double f[3] = {d2[1] * n[2] - d2[2] * n[1], d2[2] * n[0] - d2[0] * n[2],
                         d2[0] * n[1] - d2[1] * n[0]};
    const double g[3] = {n[1] * d1[2] - n[2] * d1[1], n[2] * d1[0] - n[0] * d1[2],
                         n[0] * d1[1] - n[1] * d1[0]};
    const double det = (n[0] * e[0] + n[1] * e[1]) + n[2] * e[2];
    const double dot_nu = (n[0] * u[0] + n[1] * u[1]) + n[2] * u[2];
    const double nu2 = dot_nu + dot_nu;
    const double l1 = (d1[0] * d1[0] + d1[1] * d1[1]) + d1[2] * d1[2];
    const double l2 = (d2[0] * d2[0] + d2[1] * d2[1]) + d2[2] * d2[2];
    double num[3];
    for (int k = 0; k < 3; ++k) num[k] = (nu2 * e[k] + l1 * f[k]) + l2 * g[k];
    const double pd = (nw1 * nw2) * (n1 * n2), ps = (n1 + n2) + nu;
    if (within_limit(kNum3Bound * (pd * (ps + nu)), kDet3Bound * pd, det,
                     std::max(std::max(std::fabs(num[0]), std::fabs(num[1])), std::fabs(num[2])),
                     ps)) {
      const double det2 = det + det;
      const double q[3] = {num[0] / det2, num[1] / det2, num[2] / det2};
      if (std::isfinite(q[0]) && std::isfinite(q[1]) && std::isfinite(q[2])) {
        for (int k = 0; k < 3; ++k) x[k] = p0[k] + q[k];
        return true;
      }
    }
  }
  return plane_bisectors_exact(a, b, c, p0, p1, p2, false, x);
}

void circumcenter2d_absolute(const double* a, const double* b, const double* c, double* center) {
  const double coords[6] = {a[0], a[1], b[0], b[1], c[0], c[1]};
  detail::require_finite("circumcenter2d_absolute", coords, 6);
  const double* const pts[3] = {b, c, a};
  const auto terms = [](auto& calc, const auto& d, auto& num, auto& det) {
    return circumcenter2d_terms(calc, d, num, det);
  };
  if (!exact_construction<2, 2>(pts, 3, terms, center, true)) {
    throw Error(
        "circumcenter2d: the three points are collinear: their circumcenter is not defined");
  }
}

void circumcenter3d_absolute(const double* p0, const double* p1, const double* p2, const double* p3,
                             double* center) {
  double coords[12];
  for (int k = 0; k < 3; ++k) {
    coords[k] = p0[k];
    coords[3 + k] = p1[k];
    coords[6 + k] = p2[k];
    coords[9 + k] = p3[k];
  }
  detail::require_finite("circumcenter3d_absolute", coords, 12);
  const double* const pts[4] = {p1, p2, p3, p0};
  const auto terms = [](auto& calc, const auto& d, auto& num, auto& det) {
    return detail::exact_nv_det(calc, d, num, det);  // over d = {p1 - p0, p2 - p0, p3 - p0}
  };
  if (!exact_construction<3, 3>(pts, 4, terms, center, true)) {
    throw Error("circumcenter3d: the four points are coplanar: their circumcenter is not defined");
  }
}

bool plane_bisectors_point3d_absolute(const double* a, const double* b, const double* c,
                                      const double* p0, const double* p1, const double* p2,
                                      double* x) {
  return plane_bisectors_exact(a, b, c, p0, p1, p2, true, x);
}

double bisector_value2d_exact(const double* x, const double* p, const double* q) {
  return bisector_value_exact_impl<2>(x, p, q);
}

double bisector_value3d_exact(const double* x, const double* p, const double* q) {
  return bisector_value_exact_impl<3>(x, p, q);
}

}  // namespace voroclip
