// The 2D Voronoi clipping predicates (predicates.h, "Voronoi clipping predicates in 2D";
// DESIGN.md, "Clipping predicates on symbolic vertices"): the side of bisector(i, j) of a
// polygon vertex, of a polygon edge ∩ bisector(i, k) and of a Voronoi vertex, and the
// order of two crossings along one bisector. Sites carry the lift perturbation eps_i of
// the *_sos predicates, so the decisions are those of the power diagram dual to the
// triangulation built with incircle_sos.
//
// Each predicate is a filter (bisector2d.h: the polynomials, their derivation and the
// error bound), then an exact stage on the coordinate differences to p_i: 128-bit integers
// when those are small integers on a common binary grid, Shewchuk expansions after a
// power-of-two scaling, big integers when the exponents span too wide a range (exact.cpp's
// tiers but its fixed-width one, on exact.h's calculators; the driver and the edge formula
// are shared with 3D in bisector_common.h), and finally the symbolic
// perturbation, whose terms here are linear in the eps_x: the first non-zero coefficient in
// increasing index order decides.
#include "bisector2d.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <string>

#include "bisector_common.h"
#include "exact.h"
#include "voroclip/core.h"

namespace voroclip {

namespace detail {

namespace {

// The exact stages' polynomials, of degree <= 4 in the differences d[r] = pts[r] - p_i.
//
// 128-bit path: with |d| < 2^B, |2u - c| < 3 * 2^B and |w| = |u_b - u_a| < 2^(B+1), so
// |F| < 3 * 2^(2B+1), |X| < 3 * 2^(2B+2), |E| < 2^(2B+2), and the degree-4 values
// N = F E - F E and A = X E - X E are below 3 * 2^(4B+5) < 2^(4B+7): B = 30 keeps every
// intermediate below 2^127. Expansion path: with leaves below 2^(h+2) the same bound
// reads 2^(4(h+2)+7), within plan_expansion_scaling's 2^(4(h+2)+8) for degree 4, and every
// product has degree <= 4 in the leaves (the perturbation coefficients are of degree 2,
// homogeneous too, so the power-of-two scaling keeps every sign).
constexpr int kIntegerBits = 30;
constexpr int kDegree = 4;
constexpr int kHeadroomBits = 8;

template <class C>
typename C::Num cross(C& c, const typename C::Num (&p)[2], const typename C::Num (&q)[2]) {
  return c.sub(c.mul(p[0], q[1]), c.mul(p[1], q[0]));
}

// Compare: d = {c_k, u_a1, u_b1, u_a2, u_b2}. Returns sign d . (q2 - q1) (0 when the
// crossings coincide for every eps), or kNoCrossing when E1 == 0 or E2 == 0.
struct CompareFormula {
  std::uint32_t i, k;

  template <class C, class M>
  int operator()(C& c, const M& d) const {
    using Num = typename C::Num;
    const auto& ck = d[0];
    Num w[2][2], x[2], e[2];
    for (int s = 0; s < 2; ++s) {
      const auto& ua = d[1 + 2 * s];
      const auto& ub = d[2 + 2 * s];
      w[s][0] = c.sub(ub[0], ua[0]);
      w[s][1] = c.sub(ub[1], ua[1]);
      e[s] = dot(c, w[s], ck);
      if (C::sign(e[s]) == 0) return kNoCrossing;
      const Num sa[2] = {c.add(ua[0], c.sub(ua[0], ck[0])), c.add(ua[1], c.sub(ua[1], ck[1]))};
      x[s] = cross(c, w[s], sa);
    }
    int a = C::sign(c.sub(c.mul(x[1], e[0]), c.mul(x[0], e[1])));
    if (a == 0) {
      // A + e B with B = -cross(w1, w2), e = eps_i - eps_k: sign(e) = +1 when i < k.
      a = -C::sign(cross(c, w[0], w[1])) * (i < k ? 1 : -1);
    }
    return a * C::sign(e[0]) * C::sign(e[1]);
  }
};

}  // namespace

Sign bisector_side_edge2d_exact(const double* pi, const double* pk, const double* pj,
                                const double* a, const double* b, std::uint32_t i, std::uint32_t k,
                                std::uint32_t j) {
  const int s = exact_eval<4, 2, kIntegerBits, kDegree, kHeadroomBits, false>(
      "bisector_side_edge2d", {pk, pj, a, b, pi}, EdgeFormula<2>{i, k, j});
  if (s == kNoCrossing) {
    throw Error("bisector_side_edge2d: segment [a, b] does not cross bisector(" +
                std::to_string(i) + ", " + std::to_string(k) +
                ") (it is parallel to it, a == b or p_i == p_k); the predicate needs a and b "
                "strictly on opposite sides");
  }
  return static_cast<Sign>(s);
}

Sign compare_on_bisector2d_exact(const double* pi, const double* pk, const double* a1,
                                 const double* b1, const double* a2, const double* b2,
                                 std::uint32_t i, std::uint32_t k) {
  const int s = exact_eval<5, 2, kIntegerBits, kDegree, kHeadroomBits, false>(
      "compare_on_bisector2d", {pk, a1, b1, a2, b2, pi}, CompareFormula{i, k});
  if (s == kNoCrossing) {
    throw Error("compare_on_bisector2d: a segment does not cross bisector(" + std::to_string(i) +
                ", " + std::to_string(k) +
                ") (it is parallel to it, degenerate, or p_i == p_k); each segment needs its "
                "endpoints strictly on opposite sides");
  }
  return static_cast<Sign>(s);
}

}  // namespace detail

Sign bisector_side_vertex2d(const double* pi, const double* pj, const double* a, std::uint32_t i,
                            std::uint32_t j) {
  detail::require_distinct("bisector_side_vertex2d", {i, j});
  // F_ij(a) = |a - p_i|^2 - |a - p_j|^2; eps_i - eps_j breaks a tie.
  const int s = detail::compare_distance2d_filter(a, pi, pj);
  if (s != 0) return static_cast<Sign>(s);
  detail::require_finite_points<2>("bisector_side_vertex2d", {pi, pj, a});
  const Sign f = detail::compare_distance2d_exact(a, pi, pj);
  if (f != Sign::zero) return f;
  return i < j ? Sign::positive : Sign::negative;
}

Sign bisector_side_edge2d(const double* pi, const double* pk, const double* pj, const double* a,
                          const double* b, std::uint32_t i, std::uint32_t k, std::uint32_t j) {
  detail::require_distinct("bisector_side_edge2d", {i, k, j});
  const int s = detail::bisector_edge_filter(pi, pk, pj, a, b);
  if (s != 0) return static_cast<Sign>(s);
  return detail::bisector_side_edge2d_exact(pi, pk, pj, a, b, i, k, j);
}

Sign bisector_side_voronoi2d(const double* pi, const double* pk, const double* pl, const double* pj,
                             std::uint32_t i, std::uint32_t k, std::uint32_t l, std::uint32_t j) {
  detail::require_distinct("bisector_side_voronoi2d", {i, k, l, j});
  detail::require_finite_points<2>("bisector_side_voronoi2d", {pi, pk, pl, pj});
  // With x the power centre of i, k, l (pi_i(x) = pi_k(x) = pi_l(x) = R), subtracting
  // 2 x times the coordinate columns and R - |x|^2 times the constant column from the lifted
  // column of the in-circle matrix leaves (0, 0, 0, pi_j(x) - R) there, so
  //   incircle(i, k, l, j) = (R - pi_j(x)) * orient2d(i, k, l) = f_ij(x) * orient2d(i, k, l)
  // for the perturbed lifts: the sign of f_ij(x) is incircle_sos * orient2d.
  const Sign o = orient2d(pi, pk, pl);
  if (o == Sign::zero) {
    throw Error("bisector_side_voronoi2d: sites " + std::to_string(i) + ", " + std::to_string(k) +
                ", " + std::to_string(l) + " are collinear: they have no Voronoi vertex");
  }
  return incircle_sos(pi, pk, pl, pj, i, k, l, j) * o;
}

Sign compare_on_bisector2d(const double* pi, const double* pk, const double* a1, const double* b1,
                           const double* a2, const double* b2, std::uint32_t i, std::uint32_t k) {
  detail::require_distinct("compare_on_bisector2d", {i, k});
  const int s = detail::bisector_compare_filter(pi, pk, a1, b1, a2, b2);
  if (s != 0) return static_cast<Sign>(s);
  return detail::compare_on_bisector2d_exact(pi, pk, a1, b1, a2, b2, i, k);
}

}  // namespace voroclip
