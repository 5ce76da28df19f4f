// The 3D Voronoi clipping predicates (predicates.h, "Voronoi clipping predicates in 3D";
// DESIGN.md, "Clipping predicates on symbolic vertices"): the side of bisector(i, j) of a
// mesh vertex, of a mesh edge ∩ bisector(i, k), of a mesh facet's plane ∩ bisector(i, k)
// ∩ bisector(i, l), and of a Voronoi vertex. Sites carry the lift perturbation eps_i of
// insphere_sos, so the decisions are those of the power diagram dual to the triangulation
// built with insphere_sos (Delaunay3).
//
// Each predicate is a filter (bisector3d.h: the reduced polynomials, their derivation and
// the error bound), then an exact stage on the coordinate differences to p_i
// (bisector_common.h: 128-bit integers, fixed-width integers, expansions, big integers),
// and finally the symbolic perturbation, whose terms are linear in the eps_x: the non-zero
// coefficient of the smallest index decides.
#include "bisector3d.h"

#include <string>

#include "bisector_common.h"
#include "exact.h"
#include "voroclip/core.h"

namespace voroclip {

namespace detail {

namespace {

// Exactness bounds of the exact stages, for differences d[r] = pts[r] - p_i below 2^B
// (then |w| < 2^(B+1) and |2u - c| < 3 * 2^B per coordinate):
//   edge    |F| < 9 * 2^(2B), |E| < 6 * 2^(2B), |N| < 108 * 2^(4B) < 2^(4B+7)
//   facet   |m| < 72 * 2^(4B), |N'| < 3 * 9 * 72 * 2^(6B) < 2^(6B+11),
// and every other intermediate (products, the perturbation coefficients) is smaller.
// 128-bit path: B = 30 (edge: 2^127) and 19 (facet: 2^125). Expansion path: the leaves
// are below 2^(h+2) for coordinates below 2^(h+1), so headroom 7 (edge: within the default
// 8) and 11 (facet) in plan_expansion_scaling; fixed-width path: leaves below 2^(bits+1),
// within kWideMaxBits for bits <= 120 (edge) and 81 (facet). Every sign tested is that of
// a homogeneous polynomial (edge N, E: degrees 4, 2; facet N', m_x and their sums: 6, 4),
// so the power-of-two scaling keeps it.
constexpr int kEdgeIntegerBits = 30;
constexpr int kEdgeDegree = 4;
constexpr int kEdgeHeadroomBits = 8;
constexpr int kFacetIntegerBits = 19;
constexpr int kFacetDegree = 6;
constexpr int kFacetHeadroomBits = 11;

// Facet: d = {c_j, c_k, c_l, u_a, u_b, u_c} (bisector3d.h). Returns sign f_ij(x), or
// kNoCrossing when m_1 == 0 (D == 0: no single point of the plane on both bisectors).
struct FacetFormula {
  std::uint32_t i, k, l, j;

  template <class C, class M>
  int operator()(C& c, const M& d) const {
    using Num = typename C::Num;
    const auto& ua = d[3];
    Num w1[3], w2[3];
    for (int t = 0; t < 3; ++t) {
      w1[t] = c.sub(d[4][t], ua[t]);
      w2[t] = c.sub(d[5][t], ua[t]);
    }
    // e[x][s] = w_s . c_x for x = j, k, l.
    Num e[3][2];
    for (int x = 0; x < 3; ++x) {
      e[x][0] = dot<C, 3>(c, w1, d[x]);
      e[x][1] = dot<C, 3>(c, w2, d[x]);
    }
    const auto minor = [&](int x, int y) {
      return c.sub(c.mul(e[x][0], e[y][1]), c.mul(e[x][1], e[y][0]));
    };
    const Num m1 = minor(1, 2);
    const int sign_m1 = C::sign(m1);
    if (sign_m1 == 0) return kNoCrossing;
    const Num m2 = minor(2, 0), m3 = minor(0, 1);
    const Num fij = bisector_value<C, 3>(c, d[0], ua);
    const Num fik = bisector_value<C, 3>(c, d[1], ua);
    const Num fil = bisector_value<C, 3>(c, d[2], ua);
    int s = C::sign(c.add(c.add(c.mul(fij, m1), c.mul(fik, m2)), c.mul(fil, m3)));
    if (s == 0) {
      // Coefficients eps_i: m_1 + m_2 + m_3, eps_j: -m_1 (non-zero), eps_k: -m_2, eps_l: -m_3.
      const std::uint32_t index[4] = {i, j, k, l};
      const int coef[4] = {C::sign(c.add(c.add(m1, m2), m3)), -sign_m1, -C::sign(m2), -C::sign(m3)};
      s = perturbation_sign(index, coef);
    }
    return s * sign_m1;
  }
};

// m_1 alone, over d = {c_k, c_l, u_a, u_b, u_c}: (w1 . c_k)(w2 . c_l) - (w2 . c_k)(w1 . c_l)
// with w1 = u_b - u_a, w2 = u_c - u_a. For leaves below 2^B, |w| < 2^(B+1), each dot product
// is below 2^(2B+3) and m_1 below 2^(4B+7): the edge formula's bounds (degree 4, headroom 8,
// 128-bit path for B = 30) hold.
struct PlaneFormula {
  template <class C, class M>
  int operator()(C& c, const M& d) const {
    using Num = typename C::Num;
    Num w1[3], w2[3];
    for (int t = 0; t < 3; ++t) {
      w1[t] = c.sub(d[3][t], d[2][t]);
      w2[t] = c.sub(d[4][t], d[2][t]);
    }
    const Num ek1 = dot<C, 3>(c, w1, d[0]), ek2 = dot<C, 3>(c, w2, d[0]);
    const Num el1 = dot<C, 3>(c, w1, d[1]), el2 = dot<C, 3>(c, w2, d[1]);
    return C::sign(c.sub(c.mul(ek1, el2), c.mul(ek2, el1)));
  }
};

}  // namespace

Sign voronoi_edge_direction3d_exact(const double* pi, const double* pk, const double* pl,
                                    const double* a, const double* b, const double* c) {
  return static_cast<Sign>(exact_eval<5, 3, kEdgeIntegerBits, kEdgeDegree, kEdgeHeadroomBits, true>(
      "voronoi_edge_direction3d", {pk, pl, a, b, c, pi}, PlaneFormula{}));
}

Sign bisector_side_edge3d_exact(const double* pi, const double* pk, const double* pj,
                                const double* a, const double* b, std::uint32_t i, std::uint32_t k,
                                std::uint32_t j) {
  const int s = exact_eval<4, 3, kEdgeIntegerBits, kEdgeDegree, kEdgeHeadroomBits, true>(
      "bisector_side_edge3d", {pk, pj, a, b, pi}, EdgeFormula<3>{i, k, j});
  if (s == kNoCrossing) {
    throw Error("bisector_side_edge3d: segment [a, b] does not cross bisector(" +
                std::to_string(i) + ", " + std::to_string(k) +
                ") (it is parallel to it, a == b or p_i == p_k); the predicate needs a and b "
                "strictly on opposite sides");
  }
  return static_cast<Sign>(s);
}

Sign bisector_side_facet3d_exact(const double* pi, const double* pk, const double* pl,
                                 const double* pj, const double* a, const double* b,
                                 const double* c, std::uint32_t i, std::uint32_t k, std::uint32_t l,
                                 std::uint32_t j) {
  const int s = exact_eval<6, 3, kFacetIntegerBits, kFacetDegree, kFacetHeadroomBits, true>(
      "bisector_side_facet3d", {pj, pk, pl, a, b, c, pi}, FacetFormula{i, k, l, j});
  if (s == kNoCrossing) {
    throw Error("bisector_side_facet3d: the plane of (a, b, c) does not meet bisector(" +
                std::to_string(i) + ", " + std::to_string(k) + ") ∩ bisector(" + std::to_string(i) +
                ", " + std::to_string(l) +
                ") in one point (degenerate triangle, sites i, k, l collinear, or the plane "
                "parallel to their Voronoi edge)");
  }
  return static_cast<Sign>(s);
}

}  // namespace detail

Sign bisector_side_vertex3d(const double* pi, const double* pj, const double* a, std::uint32_t i,
                            std::uint32_t j) {
  detail::require_distinct("bisector_side_vertex3d", {i, j});
  // F_ij(a) = |a - p_i|^2 - |a - p_j|^2; eps_i - eps_j breaks a tie.
  const int s = detail::compare_distance3d_filter(a, pi, pj);
  if (s != 0) return static_cast<Sign>(s);
  detail::require_finite_points<3>("bisector_side_vertex3d", {pi, pj, a});
  const Sign f = detail::compare_distance3d_exact(a, pi, pj);
  if (f != Sign::zero) return f;
  return i < j ? Sign::positive : Sign::negative;
}

Sign bisector_side_edge3d(const double* pi, const double* pk, const double* pj, const double* a,
                          const double* b, std::uint32_t i, std::uint32_t k, std::uint32_t j) {
  detail::require_distinct("bisector_side_edge3d", {i, k, j});
  const int s = detail::bisector_edge3d_filter(pi, pk, pj, a, b);
  if (s != 0) return static_cast<Sign>(s);
  return detail::bisector_side_edge3d_exact(pi, pk, pj, a, b, i, k, j);
}

Sign bisector_side_facet3d(const double* pi, const double* pk, const double* pl, const double* pj,
                           const double* a, const double* b, const double* c, std::uint32_t i,
                           std::uint32_t k, std::uint32_t l, std::uint32_t j) {
  detail::require_distinct("bisector_side_facet3d", {i, k, l, j});
  const int s = detail::bisector_facet3d_filter(pi, pk, pl, pj, a, b, c);
  if (s != 0) return static_cast<Sign>(s);
  return detail::bisector_side_facet3d_exact(pi, pk, pl, pj, a, b, c, i, k, l, j);
}

Sign bisector_side_voronoi3d(const double* pi, const double* pk, const double* pl, const double* pm,
                             const double* pj, std::uint32_t i, std::uint32_t k, std::uint32_t l,
                             std::uint32_t m, std::uint32_t j) {
  detail::require_distinct("bisector_side_voronoi3d", {i, k, l, m, j});
  detail::require_finite_points<3>("bisector_side_voronoi3d", {pi, pk, pl, pm, pj});
  // With x the power centre of i, k, l, m (pi_i(x) = ... = pi_m(x) = R), subtracting 2 x
  // times the coordinate columns and R - |x|^2 times the constant column from the lifted
  // column of the in-sphere matrix (rows (p, |p|^2 + eps, 1)) leaves (0, 0, 0, 0,
  // pi_j(x) - R) there; expanding along it (cofactor sign (-1)^(5+4)),
  //   insphere(i, k, l, m, j) = (R - pi_j(x)) * orient3d(i, k, l, m) = f_ij(x) * orient3d
  // for the perturbed lifts. That is linear in the eps, with eps_j coefficient
  // -orient3d != 0, so the lift perturbation of insphere_sos always decides before its
  // coordinate perturbations: the sign of f_ij(x) is insphere_sos * orient3d.
  const Sign o = orient3d(pi, pk, pl, pm);
  if (o == Sign::zero) {
    throw Error("bisector_side_voronoi3d: sites " + std::to_string(i) + ", " + std::to_string(k) +
                ", " + std::to_string(l) + ", " + std::to_string(m) +
                " are coplanar: they have no Voronoi vertex");
  }
  return insphere_sos(pi, pk, pl, pm, pj, i, k, l, m, j) * o;
}

Sign voronoi_edge_direction3d(const double* pi, const double* pk, const double* pl, const double* a,
                              const double* b, const double* c) {
  const int s = detail::voronoi_edge_direction3d_filter(pi, pk, pl, a, b, c);
  if (s != 0) return static_cast<Sign>(s);
  return detail::voronoi_edge_direction3d_exact(pi, pk, pl, a, b, c);
}

}  // namespace voroclip
