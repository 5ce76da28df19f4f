// Circumcenters of tetrahedra (predicates.h, "Circumcenters of tetrahedra"): the exact side
// of a plane on which the circumcenter of four points lies, and a floating-point
// circumcenter with a proven enclosure. Used by the 3D mesh extraction (mesh/src/
// extract3d.cpp) to keep the Delaunay tets whose circumcenter lies in the domain.
//
// The predicate is a filter (circumcenter3d.h: the reduced polynomial, its derivation and
// the error bound), then an exact stage on the coordinate differences to p0
// (bisector_common.h: 128-bit integers, fixed-width integers, expansions, big integers).
#include "circumcenter3d.h"

#include <cmath>
#include <string>

#include "bisector_common.h"
#include "exact.h"
#include "voroclip/core.h"

namespace voroclip {

namespace detail {

namespace {

// Exactness bounds of the exact stage, for differences below 2^B (then |w| < 2^(B+1)):
// |n_x| < 2^(2B+3), |d|^2 < 2^(2B+2), |(d x d)_x| < 2^(2B+1), |Nv_x| < 3 * 2^(4B+3),
// |D| < 3 * 2^(3B+1), |2 D u_x| < 2^(4B+4), |t_x| < 2^(4B+6), |P| < 3 * 2^(6B+9) <
// 2^(6B+11). 128-bit path: B = 19 (2^125). Expansion path: leaves below 2^(h+2) for
// coordinates below 2^(h+1), headroom 11; fixed-width path within kWideMaxBits for leaves
// of up to 81 bits. P (degree 6) and D (degree 3) are homogeneous: a power-of-two scaling
// keeps their signs.
constexpr int kIntegerBits = 19;
constexpr int kDegree = 6;
constexpr int kHeadroomBits = 11;

// Returned when D == 0 (p0..p3 coplanar).
constexpr int kCoplanar = 2;

template <class C>
using Vec3 = typename C::Num[3];

template <class C>
void cross3(C& c, const Vec3<C>& p, const Vec3<C>& q, Vec3<C>& out) {
  out[0] = c.sub(c.mul(p[1], q[2]), c.mul(p[2], q[1]));
  out[1] = c.sub(c.mul(p[2], q[0]), c.mul(p[0], q[2]));
  out[2] = c.sub(c.mul(p[0], q[1]), c.mul(p[1], q[0]));
}

// The reduced form shared by both predicates (circumcenter3d.h), from d[0..2] = d_1, d_2,
// d_3 and d[3] = u = a - p0: t = Nv - 2 D u (x - a = t / (2 D)), and sign(D). Returns false
// when D == 0 (t is then not computed).
template <class C, class M>
bool circumcenter_offset(C& c, const M& d, Vec3<C>& t, int& sign_det) {
  using Num = typename C::Num;
  Num c23[3], c31[3], c12[3];
  cross3<C>(c, d[1], d[2], c23);
  cross3<C>(c, d[2], d[0], c31);
  cross3<C>(c, d[0], d[1], c12);
  const Num det = dot<C, 3>(c, d[0], c23);
  sign_det = C::sign(det);
  if (sign_det == 0) return false;
  const Num l1 = dot<C, 3>(c, d[0], d[0]);
  const Num l2 = dot<C, 3>(c, d[1], d[1]);
  const Num l3 = dot<C, 3>(c, d[2], d[2]);
  const Num det2 = c.add(det, det);
  for (int k = 0; k < 3; ++k) {
    const Num nv = c.add(c.add(c.mul(l1, c23[k]), c.mul(l2, c31[k])), c.mul(l3, c12[k]));
    t[k] = c.sub(nv, c.mul(det2, d[3][k]));
  }
  return true;
}

// d = {d_1, d_2, d_3, u_a, u_b, u_c}, differences to p0. Returns sign orient3d(a, b, c, x).
struct SideFormula {
  template <class C, class M>
  int operator()(C& c, const M& d) const {
    using Num = typename C::Num;
    Num t[3];
    int sign_det = 0;
    if (!circumcenter_offset(c, d, t, sign_det)) return kCoplanar;
    const auto& ua = d[3];
    Num w1[3], w2[3], n[3];
    for (int k = 0; k < 3; ++k) {
      w1[k] = c.sub(d[4][k], ua[k]);
      w2[k] = c.sub(d[5][k], ua[k]);
    }
    cross3<C>(c, w1, w2, n);
    return -C::sign(dot<C, 3>(c, n, t)) * sign_det;
  }
};

// orient2d_circumcenter over d = {d_1, d_2, d_3, u_a, u_b}: sign(Q) * sign(D) (circumcenter3d.h).
// Bounds for differences below 2^B, as above: |w_x| < 2^(B+1), |t_x| < 2^(4B+6), |Q| <
// 2^(5B+8): the 128-bit path takes B = 23 (2^123), the other paths a headroom of 8 bits.
constexpr int kOrient2dIntegerBits = 23;
constexpr int kOrient2dDegree = 5;
constexpr int kOrient2dHeadroomBits = 8;

struct ProjectedSideFormula {
  int i, j;  // the projection's coordinates ((axis + 1) % 3, (axis + 2) % 3)

  template <class C, class M>
  int operator()(C& c, const M& d) const {
    using Num = typename C::Num;
    Num t[3];
    int sign_det = 0;
    if (!circumcenter_offset(c, d, t, sign_det)) return kCoplanar;
    const auto& ua = d[3];
    const Num wi = c.sub(d[4][i], ua[i]), wj = c.sub(d[4][j], ua[j]);
    return C::sign(c.sub(c.mul(wi, t[j]), c.mul(wj, t[i]))) * sign_det;
  }
};

}  // namespace

Sign orient2d_circumcenter_exact(int axis, const double* a, const double* b, const double* p0,
                                 const double* p1, const double* p2, const double* p3) {
  const ProjectedSideFormula formula{axis == 2 ? 0 : axis + 1, axis == 0 ? 2 : axis - 1};
  const int s =
      exact_eval<5, 3, kOrient2dIntegerBits, kOrient2dDegree, kOrient2dHeadroomBits, true>(
          "orient2d_circumcenter", {p1, p2, p3, a, b, p0}, formula);
  if (s == kCoplanar) {
    throw Error(
        "orient2d_circumcenter: the four points are coplanar: their circumcenter is not "
        "defined");
  }
  return static_cast<Sign>(s);
}

Sign orient3d_circumcenter_exact(const double* a, const double* b, const double* c,
                                 const double* p0, const double* p1, const double* p2,
                                 const double* p3) {
  const int s = exact_eval<6, 3, kIntegerBits, kDegree, kHeadroomBits, true>(
      "orient3d_circumcenter", {p1, p2, p3, a, b, c, p0}, SideFormula{});
  if (s == kCoplanar) {
    throw Error(
        "orient3d_circumcenter: the four points are coplanar: their circumcenter is not "
        "defined");
  }
  return static_cast<Sign>(s);
}

}  // namespace detail

Sign orient3d_circumcenter(const double* a, const double* b, const double* c, const double* p0,
                           const double* p1, const double* p2, const double* p3) {
  const int s = detail::circumcenter_side_filter(a, b, c, p0, p1, p2, p3);
  if (s != 0) return static_cast<Sign>(s);
  return detail::orient3d_circumcenter_exact(a, b, c, p0, p1, p2, p3);
}

Sign orient2d_circumcenter(int axis, const double* a, const double* b, const double* p0,
                           const double* p1, const double* p2, const double* p3) {
  if (axis < 0 || axis > 2) {
    throw Error("orient2d_circumcenter: axis " + std::to_string(axis) + " is not 0, 1 or 2");
  }
  const int s = detail::circumcenter_orient2d_filter(axis, a, b, p0, p1, p2, p3);
  if (s != 0) return static_cast<Sign>(s);
  return detail::orient2d_circumcenter_exact(axis, a, b, p0, p1, p2, p3);
}

namespace {
// (circumcenter3d's floating-point path, detail::circumcenter3d_fast in predicates.h, takes
// the result when its proven error is below 2^-36 of the tet's size. Tighter limits send
// many more Delaunay tets here, as their worst-case bound grows as D1 D2 D3 / |D|, the
// inverse of the tet's shape: 2^-42 sent 1.7 % of a CVT's tets, 2^-36 a few in ten
// thousand.)

[[noreturn]] void throw_coplanar() {
  throw Error("circumcenter3d: the four points are coplanar: their circumcenter is not defined");
}

// circumcenter3d when the floating-point formula's bound is too large (or the input out of
// its range): Nv and D exactly, each rounded, then divided. Expansions on the differences
// scaled by 2^scale (Nv scales by 2^(4 scale), D by 2^(3 scale), Nv / (2 D) by 2^scale);
// when the coordinates' exponents span too much for them, big integers on the common grid
// 2^lowest (Nv in units of 2^(4 lowest), D of 2^(3 lowest)), whose quotient is formed from
// mantissas and exponents so that no intermediate overflows.
void exact_circumcenter(const double* p0, const double* p1, const double* p2, const double* p3,
                        double* center) {
  const double* const pts[4] = {p1, p2, p3, p0};
  double coords[12];
  for (int r = 0; r < 4; ++r) {
    for (int j = 0; j < 3; ++j) coords[3 * r + j] = pts[r][j];
  }
  detail::require_finite("circumcenter3d", coords, 12);
  const detail::ExponentSpan span = detail::exponent_span(coords, 12);
  int scale = 0;
  if (detail::plan_expansion_scaling(span, 4, scale, 11)) {
    using Calc = detail::ExpansionCalc;
    Calc c(detail::thread_arena());
    Calc::Num d[3][3], nv[3], det;
    detail::differences<Calc, 3, 3>(c, pts, scale, d);
    if (!detail::exact_nv_det(c, d, nv, det)) throw_coplanar();
    // An expansion's value: its components summed from the smallest (non-overlapping,
    // increasing magnitude): within an ulp or so.
    const auto value = [](const Calc::Num& e) {
      double v = 0;
      for (int k = 0; k < e.n; ++k) v += e.v[k];
      return v;
    };
    const double det2 = 2 * value(det);
    for (int k = 0; k < 3; ++k) {
      const double q = value(nv[k]) / det2;
      center[k] = p0[k] + (scale == 0 ? q : detail::times_pow2(q, -scale));
    }
    return;
  }
  using Calc = detail::BigIntCalc;
  Calc c(span.lowest);
  Calc::Num d[3][3], nv[3], det;
  detail::differences<Calc, 3, 3>(c, pts, 0, d);
  if (!detail::exact_nv_det(c, d, nv, det)) throw_coplanar();
  int e_det = 0;
  const double m_det = det.approx(e_det);
  for (int k = 0; k < 3; ++k) {
    int e_nv = 0;
    const double m_nv = nv[k].approx(e_nv);
    // Nv / (2 D) in units of 2^lowest.
    const double q = std::ldexp(m_nv / (2 * m_det), e_nv - e_det + span.lowest);
    center[k] = p0[k] + q;
  }
}

}  // namespace

namespace detail {
void circumcenter3d_exact(const double* p0, const double* p1, const double* p2, const double* p3,
                          double* center) {
  exact_circumcenter(p0, p1, p2, p3, center);
}
}  // namespace detail

bool circumcenter3d_enclosure(const double* p0, const double* p1, const double* p2,
                              const double* p3, double* center, double* halfwidth) {
  const detail::CircumcenterApprox x = detail::circumcenter_approx(p0, p1, p2, p3);
  const bool finite = std::isfinite(p0[0]) && std::isfinite(p0[1]) && std::isfinite(p0[2]);
  if (!finite || !(x.lower >= detail::kCircumcenterLower) ||
      !(x.upper <= detail::kCircumcenterUpper)) {
    return false;
  }
  const double e_det = detail::kCircumcenterDetBound * x.pd;
  const double abs_det = std::fabs(x.det);
  const double delta = abs_det - e_det;
  if (!(delta > 0)) return false;
  const double e_num = detail::kCircumcenterNumBound * (x.pd * x.ps);
  constexpr double kMu = 0x1p-53;
  const double det2 = x.det + x.det;
  for (int k = 0; k < 3; ++k) {
    const double q = x.nv[k] / det2;
    center[k] = p0[k] + q;
    const double e = (e_num + std::fabs(x.nv[k]) * e_det / abs_det) / (delta + delta) +
                     kMu * std::fabs(q) / (1 - kMu) + kMu * std::fabs(center[k]);
    halfwidth[k] = 2 * e + 0x1p-1000;
    if (!std::isfinite(center[k]) || !std::isfinite(halfwidth[k])) return false;
  }
  return true;
}

}  // namespace voroclip
