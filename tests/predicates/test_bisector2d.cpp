// Tests of the 2D Voronoi clipping predicates (predicates.h, "Voronoi clipping predicates in
// 2D"): bisector_side_vertex2d, bisector_side_edge2d, bisector_side_voronoi2d and
// compare_on_bisector2d.
//
// The oracle is written from the contract alone, in rationals (GMP), and does the symbolic
// perturbation on its own: every quantity is a polynomial in the eps_x of the call's sites
// with exact rational coefficients (EpsPoly), built from pi_x(y) = |y - p_x|^2 + eps_x by
// the formulas of the contract, without using their closed forms:
//   vertex    f_ij(a)
//   edge      (f_ik(a) f_ij(b) - f_ij(a) f_ik(b)) * sign(f_ik(a) - f_ik(b))
//   voronoi   f_ij(x) at the power centre x of i, k, l (solved by Cramer's rule, x affine
//             in the eps)
//   compare   num2 D1 - num1 D2 times sign(D1 D2), num = f(a) g(b) - f(b) g(a),
//             D = f(a) - f(b), g(y) = d . y, d = rot90(p_k - p_i)
// The sign of a polynomial is that of its dominant monomial when the eps are positive
// infinitesimals with eps_x >> eps_y for index x < y (every power of eps_y is negligible
// against eps_x): the monomial whose exponent of the smallest eps is the smallest, then the
// next smallest, and so on. The oracle also reports the degree of that monomial: the
// contract's predicates are all decided by terms of degree <= 1.
//
// The implementation (predicates/src/bisector2d.cpp) uses different, lower-degree
// polynomials; the geometric tests construct the crossing points and Voronoi vertices
// explicitly in rationals as a third formulation.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <gmpxx.h>
#include <iterator>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "bisector2d.h"
#include "eps_poly.h"
#include "exact_oracle.h"
#include "voroclip/core.h"
#include "voroclip/delaunay.h"
#include "voroclip/predicates.h"

using namespace voroclip;
using namespace voroclip::test;

namespace {

using P2 = std::array<double, 2>;

Q sq_dist(const P2& x, const P2& p) {
  const Q dx = Q(x[0]) - Q(p[0]), dy = Q(x[1]) - Q(p[1]);
  return dx * dx + dy * dy;
}

// f_xy(y) = pi_x(y) - pi_y(y) for sites in slots sx, sy.
EpsPoly f(const P2& y, const P2& px, int sx, const P2& py, int sy) {
  return EpsPoly(sq_dist(y, px) - sq_dist(y, py)) + EpsPoly::eps(sx) - EpsPoly::eps(sy);
}

struct Expected {
  bool throws = false;  // a precondition is violated
  int sign = 0;         // the perturbed sign
  int unperturbed = 0;  // the sign with eps = 0 (what a filter may decide)
  int degree = 0;       // degree of the deciding monomial
};

// ---------------------------------------------------------------------------------------
// The four oracles.

Expected oracle_vertex(const P2& pi, const P2& pj, const P2& a, std::uint32_t i, std::uint32_t j) {
  Expected r;
  if (i == j) return {true, 0, 0, 0};
  const EpsPoly v = f(a, pi, 0, pj, 1);
  r.sign = v.sign({i, j, 0, 0}, 2, r.degree);
  r.unperturbed = sgn(v.constant());
  return r;
}

struct EdgeCase {
  P2 pi, pk, pj, a, b;
  std::uint32_t i, k, j;
};

std::string describe(const EdgeCase& c) {
  std::ostringstream os;
  const auto pt = [&](const char* n, const P2& p) {
    os << n << "{" << hex(p[0]) << ", " << hex(p[1]) << "} ";
  };
  pt("pi", c.pi);
  pt("pk", c.pk);
  pt("pj", c.pj);
  pt("a", c.a);
  pt("b", c.b);
  os << "i " << c.i << " k " << c.k << " j " << c.j;
  return os.str();
}

Expected oracle_edge(const EdgeCase& c) {
  Expected r;
  if (c.i == c.j || c.i == c.k || c.j == c.k) return {true, 0, 0, 0};
  // slots: i 0, k 1, j 2
  const EpsPoly fik_a = f(c.a, c.pi, 0, c.pk, 1), fik_b = f(c.b, c.pi, 0, c.pk, 1);
  const EpsPoly fij_a = f(c.a, c.pi, 0, c.pj, 2), fij_b = f(c.b, c.pi, 0, c.pj, 2);
  const EpsPoly d = fik_a - fik_b;
  REQUIRE(d.is_constant());
  const int sd = sgn(d.constant());
  if (sd == 0) return {true, 0, 0, 0};
  const EpsPoly n = fik_a * fij_b - fij_a * fik_b;
  r.sign = n.sign({c.i, c.k, c.j, 0}, 3, r.degree) * sd;
  r.unperturbed = sgn(n.constant()) * sd;
  return r;
}

struct VoronoiCase {
  P2 pi, pk, pl, pj;
  std::uint32_t i, k, l, j;
};

std::string describe(const VoronoiCase& c) {
  std::ostringstream os;
  for (const P2* p : {&c.pi, &c.pk, &c.pl, &c.pj})
    os << "{" << hex((*p)[0]) << ", " << hex((*p)[1]) << "} ";
  os << "i " << c.i << " k " << c.k << " l " << c.l << " j " << c.j;
  return os.str();
}

Expected oracle_voronoi(const VoronoiCase& c) {
  Expected r;
  const std::uint32_t ids[] = {c.i, c.k, c.l, c.j};
  for (int x = 0; x < 4; ++x)
    for (int y = x + 1; y < 4; ++y)
      if (ids[x] == ids[y]) return {true, 0, 0, 0};
  // slots: i 0, k 1, l 2, j 3. The power centre x: f_ik(x) = f_il(x) = 0, i.e.
  // 2 (p_m - p_i) . x = |p_m|^2 - |p_i|^2 + eps_m - eps_i for m = k, l.
  const auto lift = [](const P2& p) -> Q { return Q(p[0]) * Q(p[0]) + Q(p[1]) * Q(p[1]); };
  const Q a11 = 2 * (Q(c.pk[0]) - Q(c.pi[0])), a12 = 2 * (Q(c.pk[1]) - Q(c.pi[1]));
  const Q a21 = 2 * (Q(c.pl[0]) - Q(c.pi[0])), a22 = 2 * (Q(c.pl[1]) - Q(c.pi[1]));
  const EpsPoly r1 = EpsPoly(lift(c.pk) - lift(c.pi)) + EpsPoly::eps(1) - EpsPoly::eps(0);
  const EpsPoly r2 = EpsPoly(lift(c.pl) - lift(c.pi)) + EpsPoly::eps(2) - EpsPoly::eps(0);
  const Q det = a11 * a22 - a12 * a21;
  if (sgn(det) == 0) return {true, 0, 0, 0};
  const Q inv = 1 / det;
  const EpsPoly x = (r1 * EpsPoly(a22) - r2 * EpsPoly(a12)) * EpsPoly(inv);
  const EpsPoly y = (r2 * EpsPoly(a11) - r1 * EpsPoly(a21)) * EpsPoly(inv);
  // f_ij(x) = 2 x . (p_j - p_i) + |p_i|^2 - |p_j|^2 + eps_i - eps_j
  const EpsPoly v = x * EpsPoly(2 * (Q(c.pj[0]) - Q(c.pi[0]))) +
                    y * EpsPoly(2 * (Q(c.pj[1]) - Q(c.pi[1]))) + EpsPoly(lift(c.pi) - lift(c.pj)) +
                    EpsPoly::eps(0) - EpsPoly::eps(3);
  r.sign = v.sign({c.i, c.k, c.l, c.j}, 4, r.degree);
  r.unperturbed = sgn(v.constant());
  return r;
}

struct CompareCase {
  P2 pi, pk, a1, b1, a2, b2;
  std::uint32_t i, k;
};

std::string describe(const CompareCase& c) {
  std::ostringstream os;
  for (const P2* p : {&c.pi, &c.pk, &c.a1, &c.b1, &c.a2, &c.b2})
    os << "{" << hex((*p)[0]) << ", " << hex((*p)[1]) << "} ";
  os << "i " << c.i << " k " << c.k;
  return os.str();
}

Expected oracle_compare(const CompareCase& c) {
  Expected r;
  if (c.i == c.k) return {true, 0, 0, 0};
  // slots: i 0, k 1. d = rot90(p_k - p_i), g(y) = d . y, f = f_ik.
  const Q dx = Q(c.pi[1]) - Q(c.pk[1]), dy = Q(c.pk[0]) - Q(c.pi[0]);
  const auto g = [&](const P2& y) { return EpsPoly(dx * Q(y[0]) + dy * Q(y[1])); };
  const auto num = [&](const P2& a, const P2& b) {
    return f(a, c.pi, 0, c.pk, 1) * g(b) - f(b, c.pi, 0, c.pk, 1) * g(a);
  };
  const EpsPoly d1 = f(c.a1, c.pi, 0, c.pk, 1) - f(c.b1, c.pi, 0, c.pk, 1);
  const EpsPoly d2 = f(c.a2, c.pi, 0, c.pk, 1) - f(c.b2, c.pi, 0, c.pk, 1);
  REQUIRE(d1.is_constant());
  REQUIRE(d2.is_constant());
  const int s12 = sgn(d1.constant()) * sgn(d2.constant());
  if (s12 == 0) return {true, 0, 0, 0};
  // d.q2 - d.q1 = num2 / D2 - num1 / D1 = (num2 D1 - num1 D2) / (D1 D2)
  const EpsPoly v = num(c.a2, c.b2) * d1 - num(c.a1, c.b1) * d2;
  r.sign = v.sign({c.i, c.k, 0, 0}, 2, r.degree) * s12;
  r.unperturbed = sgn(v.constant()) * s12;
  return r;
}

// ---------------------------------------------------------------------------------------
// Calls, with a thrown voroclip::Error reported as `threw`.

struct Got {
  bool threw = false;
  int sign = 0;
};

template <class F>
Got call(F fn) {
  Got g;
  try {
    g.sign = to_int(fn());
  } catch (const Error&) {
    g.threw = true;
  }
  return g;
}

Got run(const EdgeCase& c) {
  return call([&] {
    return bisector_side_edge2d(c.pi.data(), c.pk.data(), c.pj.data(), c.a.data(), c.b.data(), c.i,
                                c.k, c.j);
  });
}
Got run_exact(const EdgeCase& c) {
  return call([&] {
    return detail::bisector_side_edge2d_exact(c.pi.data(), c.pk.data(), c.pj.data(), c.a.data(),
                                              c.b.data(), c.i, c.k, c.j);
  });
}
int run_filter(const EdgeCase& c) {
  return detail::bisector_edge_filter(c.pi.data(), c.pk.data(), c.pj.data(), c.a.data(),
                                      c.b.data());
}
Got run(const CompareCase& c) {
  return call([&] {
    return compare_on_bisector2d(c.pi.data(), c.pk.data(), c.a1.data(), c.b1.data(), c.a2.data(),
                                 c.b2.data(), c.i, c.k);
  });
}
Got run_exact(const CompareCase& c) {
  return call([&] {
    return detail::compare_on_bisector2d_exact(c.pi.data(), c.pk.data(), c.a1.data(), c.b1.data(),
                                               c.a2.data(), c.b2.data(), c.i, c.k);
  });
}
int run_filter(const CompareCase& c) {
  return detail::bisector_compare_filter(c.pi.data(), c.pk.data(), c.a1.data(), c.b1.data(),
                                         c.a2.data(), c.b2.data());
}
Got run(const VoronoiCase& c) {
  return call([&] {
    return bisector_side_voronoi2d(c.pi.data(), c.pk.data(), c.pl.data(), c.pj.data(), c.i, c.k,
                                   c.l, c.j);
  });
}

// Statistics of one family: how often the exact zero was perturbed, and the filter failed.
struct Tally {
  std::size_t n = 0, failures = 0, perturbed = 0, throws = 0, undecided = 0, zeros = 0;
};

// Checks the full predicate, the exact stage alone and the filter against the oracle.
template <class Case, class Oracle>
void check_case(const Case& c, Oracle oracle, Tally& t) {
  const Expected want = oracle(c);
  ++t.n;
  t.throws += want.throws;
  t.perturbed += !want.throws && want.unperturbed == 0;
  t.zeros += !want.throws && want.sign == 0;
  const Got got = run(c), exact = run_exact(c);
  const int filt = run_filter(c);
  t.undecided += filt == 0;
  bool ok = got.threw == want.throws && exact.threw == want.throws;
  if (!want.throws) {
    ok = ok && got.sign == want.sign && exact.sign == want.sign;
    ok = ok && want.degree <= 1;
  }
  // The filter decides only the unperturbed sign, and only when that is certain.
  ok = ok && (filt == 0 || (!want.throws && filt == want.unperturbed));
  if (!ok) {
    ++t.failures;
    if (t.failures <= 10) {
      FAIL_CHECK(describe(c) << ": expected " << (want.throws ? "throw" : std::to_string(want.sign))
                             << " (unperturbed " << want.unperturbed << ", degree " << want.degree
                             << "), got " << (got.threw ? "throw" : std::to_string(got.sign))
                             << ", exact stage "
                             << (exact.threw ? "throw" : std::to_string(exact.sign)) << ", filter "
                             << filt);
    }
  }
}

// ---------------------------------------------------------------------------------------
// Inputs.

// Distinct indices in [0, top]: small, so that every order of the indices occurs.
template <std::size_t N>
std::array<std::uint32_t, N> distinct_indices(Rng& rng, std::uint32_t top = 9) {
  std::array<std::uint32_t, N> idx{};
  for (std::size_t x = 0; x < N; ++x) {
    for (;;) {
      const auto v = static_cast<std::uint32_t>(rand_int(rng, 0, top));
      if (std::find(idx.begin(), idx.begin() + static_cast<std::ptrdiff_t>(x), v) ==
          idx.begin() + static_cast<std::ptrdiff_t>(x)) {
        idx[x] = v;
        break;
      }
    }
  }
  return idx;
}

P2 random_point(Rng& rng) { return {uniform(rng, -1, 1), uniform(rng, -1, 1)}; }
P2 grid_point(Rng& rng, long long top) {
  return {static_cast<double>(rand_int(rng, -top, top)),
          static_cast<double>(rand_int(rng, -top, top))};
}
P2 mixed_point(Rng& rng) { return {random_mixed_coordinate(rng), random_mixed_coordinate(rng)}; }
P2 nudged(P2 p, Rng& rng, int ulps) {
  for (double& x : p) x = nudge(x, static_cast<int>(rand_int(rng, -ulps, ulps)));
  return p;
}
P2 scaled_point(const P2& p, int e) { return {std::ldexp(p[0], e), std::ldexp(p[1], e)}; }

// Half of the time p, else p moved by a random vector of length about 2^-m, m in [8, 60]:
// from clearly decided by the filter down to within rounding of the degenerate position,
// so that the filter's bound is exercised where it matters.
P2 off_by(const P2& p, Rng& rng) {
  if (coin(rng)) return p;
  const double h = std::ldexp(1.0, -static_cast<int>(rand_int(rng, 8, 60)));
  return {p[0] + h * uniform(rng, -1, 1), p[1] + h * uniform(rng, -1, 1)};
}

// The circumcentre of three points, in floating point (near-degenerate constructions).
P2 circumcenter(const P2& a, const P2& b, const P2& c) {
  const double bx = b[0] - a[0], by = b[1] - a[1], cx = c[0] - a[0], cy = c[1] - a[1];
  const double d = 2 * (bx * cy - by * cx);
  const double b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
  return {a[0] + (cy * b2 - by * c2) / d, a[1] + (bx * c2 - cx * b2) / d};
}

enum class Family { random, grid, near, mixed, scaled };
constexpr std::array<Family, 5> kFamilies = {Family::random, Family::grid, Family::near,
                                             Family::mixed, Family::scaled};
const char* name(Family f) {
  switch (f) {
    case Family::random:
      return "random";
    case Family::grid:
      return "grid";
    case Family::near:
      return "near-degenerate";
    case Family::mixed:
      return "mixed magnitudes";
    case Family::scaled:
      return "scaled";
  }
  return "?";
}

EdgeCase make_edge(Family fam, Rng& rng) {
  EdgeCase c{};
  const auto idx = distinct_indices<3>(rng);
  c.i = idx[0];
  c.k = idx[1];
  c.j = idx[2];
  switch (fam) {
    case Family::random:
      c.pi = random_point(rng), c.pk = random_point(rng), c.pj = random_point(rng);
      c.a = random_point(rng), c.b = random_point(rng);
      break;
    case Family::grid: {
      // Small integers: F == 0, N0 == 0 and D == 0 all occur often.
      const long long top = coin(rng) ? 2 : 4;
      for (P2* p : {&c.pi, &c.pk, &c.pj, &c.a, &c.b}) *p = grid_point(rng, top);
      if (rng() % 4 == 0) c.pj = c.pk;  // duplicate sites: f_ij = f_ik + eps terms
      break;
    }
    case Family::near: {
      // The segment passes within ulps of the Voronoi vertex of i, k, j: f_ij(q) ~ 0.
      c.pi = random_point(rng), c.pk = random_point(rng), c.pj = random_point(rng);
      const P2 v = off_by(circumcenter(c.pi, c.pk, c.pj), rng);
      const P2 dir = random_point(rng);
      const double s = uniform(rng, 0.1, 1), t = uniform(rng, 0.1, 1);
      c.a = nudged({v[0] + s * dir[0], v[1] + s * dir[1]}, rng, 2);
      c.b = nudged({v[0] - t * dir[0], v[1] - t * dir[1]}, rng, 2);
      if (coin(rng)) c.a = nudged(v, rng, 1);  // an endpoint at the Voronoi vertex
      break;
    }
    case Family::mixed:
      for (P2* p : {&c.pi, &c.pk, &c.pj, &c.a, &c.b}) *p = mixed_point(rng);
      break;
    case Family::scaled: {
      // A grid or random configuration times 2^e, |e| <= 1000 (exact, no overflow).
      EdgeCase base = make_edge(coin(rng) ? Family::grid : Family::random, rng);
      const auto e = static_cast<int>(rand_int(rng, -1000, 1000));
      for (P2* p : {&base.pi, &base.pk, &base.pj, &base.a, &base.b}) *p = scaled_point(*p, e);
      return base;
    }
  }
  return c;
}

CompareCase make_compare(Family fam, Rng& rng) {
  CompareCase c{};
  const auto idx = distinct_indices<2>(rng);
  c.i = idx[0];
  c.k = idx[1];
  switch (fam) {
    case Family::random:
      for (P2* p : {&c.pi, &c.pk, &c.a1, &c.b1, &c.a2, &c.b2}) *p = random_point(rng);
      break;
    case Family::grid: {
      // Small integers: A == 0 and B == 0 (parallel segments, shared crossings) occur often.
      const long long top = coin(rng) ? 2 : 3;
      for (P2* p : {&c.pi, &c.pk, &c.a1, &c.b1, &c.a2, &c.b2}) *p = grid_point(rng, top);
      if (rng() % 4 == 0) c.a2 = c.a1;  // segments sharing an endpoint
      break;
    }
    case Family::near: {
      // Both segments pass within ulps of one point v of the bisector.
      c.pi = random_point(rng), c.pk = random_point(rng);
      const double t = uniform(rng, -1, 1);
      const P2 v = off_by({0.5 * (c.pi[0] + c.pk[0]) + t * (c.pi[1] - c.pk[1]),
                           0.5 * (c.pi[1] + c.pk[1]) + t * (c.pk[0] - c.pi[0])},
                          rng);
      for (auto [a, b] : {std::pair{&c.a1, &c.b1}, std::pair{&c.a2, &c.b2}}) {
        const P2 dir = random_point(rng);
        const double s = uniform(rng, 0.1, 1), r = uniform(rng, 0.1, 1);
        *a = nudged({v[0] + s * dir[0], v[1] + s * dir[1]}, rng, 2);
        *b = nudged({v[0] - r * dir[0], v[1] - r * dir[1]}, rng, 2);
      }
      if (coin(rng)) c.a2 = c.a1 = nudged(v, rng, 1);  // a shared endpoint near the bisector
      break;
    }
    case Family::mixed:
      for (P2* p : {&c.pi, &c.pk, &c.a1, &c.b1, &c.a2, &c.b2}) *p = mixed_point(rng);
      break;
    case Family::scaled: {
      CompareCase base = make_compare(coin(rng) ? Family::grid : Family::random, rng);
      const auto e = static_cast<int>(rand_int(rng, -1000, 1000));
      for (P2* p : {&base.pi, &base.pk, &base.a1, &base.b1, &base.a2, &base.b2})
        *p = scaled_point(*p, e);
      return base;
    }
  }
  return c;
}

VoronoiCase make_voronoi(Family fam, Rng& rng) {
  VoronoiCase c{};
  const auto idx = distinct_indices<4>(rng);
  c.i = idx[0], c.k = idx[1], c.l = idx[2], c.j = idx[3];
  switch (fam) {
    case Family::random:
      for (P2* p : {&c.pi, &c.pk, &c.pl, &c.pj}) *p = random_point(rng);
      break;
    case Family::grid:
      for (P2* p : {&c.pi, &c.pk, &c.pl, &c.pj}) *p = grid_point(rng, 2);
      break;
    case Family::near: {
      for (P2* p : {&c.pi, &c.pk, &c.pl}) *p = random_point(rng);
      // p_j on the circle through the three, up to rounding.
      const P2 o = circumcenter(c.pi, c.pk, c.pl);
      const double r = std::hypot(c.pi[0] - o[0], c.pi[1] - o[1]);
      const double t = uniform(rng, 0, 6.283185307179586);
      c.pj = nudged({o[0] + r * std::cos(t), o[1] + r * std::sin(t)}, rng, 2);
      break;
    }
    case Family::mixed:
      for (P2* p : {&c.pi, &c.pk, &c.pl, &c.pj}) *p = mixed_point(rng);
      break;
    case Family::scaled: {
      VoronoiCase base = make_voronoi(coin(rng) ? Family::grid : Family::random, rng);
      const auto e = static_cast<int>(rand_int(rng, -1000, 1000));
      for (P2* p : {&base.pi, &base.pk, &base.pl, &base.pj}) *p = scaled_point(*p, e);
      return base;
    }
  }
  return c;
}

// Segments that cross the bisector of two sites: endpoints redrawn until F_ik(a) and
// F_ik(b) have strictly opposite signs.
void make_crossing(const P2& pi, const P2& pk, P2& a, P2& b, Rng& rng) {
  for (;;) {
    a = random_point(rng), b = random_point(rng);
    const int sa = sgn(sq_dist(a, pi) - sq_dist(a, pk)), sb = sgn(sq_dist(b, pi) - sq_dist(b, pk));
    if (sa * sb < 0) return;
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------

TEST_CASE("oracle: hand-derived cases", "[predicates][exact]") {
  // Sites (0,0) and (2,0): bisector x = 1. Polygon vertex (1,5) on it: the tie goes to the
  // larger index, whose eps is smaller.
  const P2 p0 = {0, 0}, p2 = {2, 0}, on = {1, 5}, left = {0.5, 0};
  CHECK(oracle_vertex(p0, p2, on, 3, 7).sign == 1);  // i < j: x is on j's side
  CHECK(oracle_vertex(p0, p2, on, 7, 3).sign == -1);
  CHECK(oracle_vertex(p0, p2, left, 7, 3).sign == -1);
  CHECK(to_int(bisector_side_vertex2d(p0.data(), p2.data(), on.data(), 3, 7)) == 1);
  CHECK(to_int(bisector_side_vertex2d(p0.data(), p2.data(), on.data(), 7, 3)) == -1);
  CHECK(to_int(bisector_side_vertex2d(p0.data(), p2.data(), left.data(), 7, 3)) == -1);

  // Segment y = 0 from (-1,0) to (3,0) crosses bisector(i=(0,0), k=(2,0)) at q = (1,0).
  // Site j = (1,-1): |q - p_i| = 1 = |q - p_j|: a tie, decided by the perturbation; with
  // j = (1, 3): q is closer to i, f_ij(q) < 0.
  EdgeCase e{{0, 0}, {2, 0}, {1, 3}, {-1, 0}, {3, 0}, 0, 1, 2};
  CHECK(oracle_edge(e).sign == -1);
  CHECK(run(e).sign == -1);
  e.pj = {1, -1};
  const Expected tie = oracle_edge(e);
  CHECK(tie.unperturbed == 0);
  // N = eps_i (E_k - E_j) - eps_j E_k + eps_k E_j with w = (4, 0), c_k = (2, 0), c_j =
  // (1, -1): E_k = 8, E_j = 4. i = 0 smallest: coefficient 4 > 0; sign(E_k) > 0: +1.
  CHECK(tie.sign == 1);
  CHECK(run(e).sign == 1);
  e.i = 5;  // now k = 1 comes first: coefficient of eps_k is E_j = 4 > 0: still +1
  CHECK(oracle_edge(e).sign == 1);
  CHECK(run(e).sign == 1);
  e.k = 9;  // order j = 2 < i = 5 < k = 9: coefficient of eps_j is -E_k < 0
  CHECK(oracle_edge(e).sign == -1);
  CHECK(run(e).sign == -1);

  // compare: sites (0,0), (2,0): d = (0, 2), travel direction +y. Horizontal segments
  // crossing the bisector x = 1 at (1, 1) and (1, 4): q2 after q1.
  CompareCase cc{{0, 0}, {2, 0}, {0, 1}, {2, 1}, {0, 4}, {3, 4}, 0, 1};
  CHECK(oracle_compare(cc).sign == 1);
  CHECK(run(cc).sign == 1);
  std::swap(cc.a1, cc.a2);
  std::swap(cc.b1, cc.b2);
  CHECK(oracle_compare(cc).sign == -1);
  CHECK(run(cc).sign == -1);
  // Two segments through the same point (1, 1) of the bisector, with different slopes:
  // the perturbation moves the bisector by -e c/(2|c|^2) (e = eps_i - eps_k > 0 for i < k:
  // towards p_i), so the crossings separate.
  CompareCase same{{0, 0}, {2, 0}, {0, 0}, {2, 2}, {0, 2}, {2, 0}, 0, 1};
  const Expected s = oracle_compare(same);
  CHECK(s.unperturbed == 0);
  CHECK(s.sign != 0);
  CHECK(run(same).sign == s.sign);
  // Collinear overlapping segments: the same crossing for every eps.
  CompareCase twice{{0, 0}, {2, 0}, {0, 1}, {2, 1}, {-1, 1}, {3, 1}, 0, 1};
  CHECK(oracle_compare(twice).sign == 0);
  CHECK(run(twice).sign == 0);
}

TEST_CASE("Voronoi vertex sign convention: a site outside the circle is farther",
          "[predicates][exact]") {
  // Triangle (0,0), (4,0), (0,4) counter-clockwise: Voronoi vertex (2, 2), radius^2 8.
  const P2 a = {0, 0}, b = {4, 0}, c = {0, 4}, far = {10, 10}, near = {2, 3};
  CHECK(to_int(orient2d(a.data(), b.data(), c.data())) == 1);
  // far: |x - far|^2 = 128 > 8: f_ij(x) < 0, the vertex stays on i's side.
  CHECK(to_int(bisector_side_voronoi2d(a.data(), b.data(), c.data(), far.data(), 0, 1, 2, 3)) ==
        -1);
  CHECK(to_int(bisector_side_voronoi2d(b.data(), a.data(), c.data(), far.data(), 1, 0, 2, 3)) ==
        -1);
  // near: |x - near|^2 = 1 < 8: the vertex is closer to j.
  CHECK(to_int(bisector_side_voronoi2d(a.data(), b.data(), c.data(), near.data(), 0, 1, 2, 3)) ==
        1);
  CHECK(oracle_voronoi({a, b, c, far, 0, 1, 2, 3}).sign == -1);
  CHECK(oracle_voronoi({a, b, c, near, 0, 1, 2, 3}).sign == 1);
  // Cocircular j = (4, 4): the tie is broken like incircle_sos: j's lift perturbation
  // (index 3, the smallest eps here) against the others'.
  const P2 co = {4, 4};
  const Expected t = oracle_voronoi({a, b, c, co, 0, 1, 2, 3});
  CHECK(t.unperturbed == 0);
  CHECK(to_int(bisector_side_voronoi2d(a.data(), b.data(), c.data(), co.data(), 0, 1, 2, 3)) ==
        t.sign);
}

TEST_CASE("bisector predicates agree with the rational oracle on every family",
          "[predicates][exact][degenerate]") {
  const std::uint64_t seed = seed_for(0xb15ec);
  INFO("seed " << seed);
  Rng rng(seed);
  for (const Family fam : kFamilies) {
    INFO("family " << name(fam));
    const std::size_t n = scaled(fam == Family::random ? 20000 : 8000);
    Tally edge, cmp;
    for (std::size_t it = 0; it < n; ++it) {
      check_case(make_edge(fam, rng), oracle_edge, edge);
      check_case(make_compare(fam, rng), oracle_compare, cmp);
    }
    INFO("edge: " << edge.perturbed << " perturbed, " << edge.throws << " throw, " << edge.undecided
                  << " filter undecided of " << edge.n);
    INFO("compare: " << cmp.perturbed << " perturbed, " << cmp.zeros << " zero, " << cmp.throws
                     << " throw, " << cmp.undecided << " filter undecided of " << cmp.n);
    CHECK(edge.failures == 0);
    CHECK(cmp.failures == 0);
    if (fam == Family::random) {
      // The filter decides random input (almost) always.
      CHECK(edge.undecided * 1000 <= edge.n);
      CHECK(cmp.undecided * 1000 <= cmp.n);
    }
    if (fam == Family::grid) {
      // The families reach what they are meant to: exact ties decided by eps, violated
      // preconditions.
      CHECK(edge.perturbed > n / 20);
      CHECK(cmp.perturbed > n / 50);
      CHECK(edge.throws > n / 50);
      CHECK(cmp.throws > n / 50);
      CHECK(cmp.zeros > 0);  // coinciding crossings: A == 0 and B == 0
      CHECK(edge.zeros == 0);
    }
    if (fam == Family::near) {
      // Both stages at work: the filter near its bound, the exact stage below it.
      CHECK(edge.undecided > n / 4);
      CHECK(cmp.undecided > n / 4);
      CHECK(edge.undecided < n - n / 8);
      CHECK(cmp.undecided < n - n / 8);
    }
  }
}

TEST_CASE("bisector_side_vertex2d and bisector_side_voronoi2d agree with the oracle",
          "[predicates][exact][degenerate]") {
  const std::uint64_t seed = seed_for(0xb15ec2);
  INFO("seed " << seed);
  Rng rng(seed);
  for (const Family fam : kFamilies) {
    INFO("family " << name(fam));
    const std::size_t n = scaled(4000);
    std::size_t failures = 0, ties = 0;
    for (std::size_t it = 0; it < n; ++it) {
      // Vertex: a on the bisector of p_i, p_j half of the time (exactly for the grid).
      const auto idx = distinct_indices<2>(rng);
      P2 pi, pj, a;
      if (fam == Family::grid) {
        pi = grid_point(rng, 3), pj = grid_point(rng, 3), a = grid_point(rng, 3);
      } else if (fam == Family::mixed) {
        pi = mixed_point(rng), pj = mixed_point(rng), a = mixed_point(rng);
      } else {
        pi = random_point(rng), pj = random_point(rng);
        const double t = uniform(rng, -2, 2);
        a = nudged({0.5 * (pi[0] + pj[0]) + t * (pi[1] - pj[1]),
                    0.5 * (pi[1] + pj[1]) + t * (pj[0] - pi[0])},
                   rng, 1);
        if (fam == Family::scaled) {
          const auto e = static_cast<int>(rand_int(rng, -1000, 1000));
          pi = scaled_point(pi, e), pj = scaled_point(pj, e), a = scaled_point(a, e);
        }
      }
      const Expected want = oracle_vertex(pi, pj, a, idx[0], idx[1]);
      ties += want.unperturbed == 0;
      const Got got = call(
          [&] { return bisector_side_vertex2d(pi.data(), pj.data(), a.data(), idx[0], idx[1]); });
      // Antisymmetry: f_ji = -f_ij.
      const Got swapped = call(
          [&] { return bisector_side_vertex2d(pj.data(), pi.data(), a.data(), idx[1], idx[0]); });
      if (got.threw || got.sign != want.sign || swapped.threw || swapped.sign != -want.sign) {
        ++failures;
        FAIL_CHECK("vertex pi {" << hex(pi[0]) << ", " << hex(pi[1]) << "} pj {" << hex(pj[0])
                                 << ", " << hex(pj[1]) << "} a {" << hex(a[0]) << ", " << hex(a[1])
                                 << "} i " << idx[0] << " j " << idx[1] << ": want " << want.sign
                                 << " got " << got.sign << " swapped " << swapped.sign);
      }

      const VoronoiCase v = make_voronoi(fam, rng);
      const Expected vw = oracle_voronoi(v);
      const Got vg = run(v);
      if (vg.threw != vw.throws || (!vw.throws && (vg.sign != vw.sign || vw.degree > 1))) {
        ++failures;
        FAIL_CHECK("voronoi " << describe(v) << ": want "
                              << (vw.throws ? "throw" : std::to_string(vw.sign)) << " got "
                              << (vg.threw ? "throw" : std::to_string(vg.sign)));
      }
    }
    INFO(ties << " vertex ties");
    CHECK(failures == 0);
    if (fam == Family::grid) CHECK(ties > n / 50);
  }
}

TEST_CASE("scale sweep: inputs times 2^e, e in [-500, 500], give identical signs",
          "[predicates][exact][degenerate]") {
  const std::uint64_t seed = seed_for(0xb15ec3);
  INFO("seed " << seed);
  Rng rng(seed);
  std::size_t failures = 0, compared = 0;
  for (std::size_t it = 0; it < scaled(300); ++it) {
    const Family fam = it % 3 == 0 ? Family::near : (it % 3 == 1 ? Family::grid : Family::random);
    const EdgeCase e0 = make_edge(fam, rng);
    const CompareCase c0 = make_compare(fam, rng);
    const VoronoiCase v0 = make_voronoi(fam, rng);
    const Got ge = run(e0), gc = run(c0), gv = run(v0);
    const Got gx = call([&] {
      return bisector_side_vertex2d(e0.pi.data(), e0.pj.data(), e0.a.data(), e0.i, e0.j);
    });
    for (int ex = -500; ex <= 500; ex += 25 + static_cast<int>(rng() % 5)) {
      EdgeCase e = e0;
      for (P2* p : {&e.pi, &e.pk, &e.pj, &e.a, &e.b}) *p = scaled_point(*p, ex);
      CompareCase c = c0;
      for (P2* p : {&c.pi, &c.pk, &c.a1, &c.b1, &c.a2, &c.b2}) *p = scaled_point(*p, ex);
      VoronoiCase v = v0;
      for (P2* p : {&v.pi, &v.pk, &v.pl, &v.pj}) *p = scaled_point(*p, ex);
      const Got se = run(e), sc = run(c), sv = run(v);
      const Got sx = call(
          [&] { return bisector_side_vertex2d(e.pi.data(), e.pj.data(), e.a.data(), e.i, e.j); });
      ++compared;
      const auto same = [](const Got& x, const Got& y) {
        return x.threw == y.threw && x.sign == y.sign;
      };
      if (!same(se, ge) || !same(sc, gc) || !same(sv, gv) || !same(sx, gx)) {
        ++failures;
        FAIL_CHECK("scale 2^" << ex << ": edge " << describe(e0) << " / compare " << describe(c0)
                              << " / voronoi " << describe(v0));
      }
    }
  }
  INFO(compared << " scaled inputs");
  CHECK(failures == 0);
}

TEST_CASE("geometric meaning: explicit crossings and Voronoi vertices in rationals",
          "[predicates][exact]") {
  const std::uint64_t seed = seed_for(0xb15ec4);
  INFO("seed " << seed);
  Rng rng(seed);
  std::size_t failures = 0;
  // q = a + t (b - a) on the bisector of p_i, p_k.
  const auto crossing = [](const P2& pi, const P2& pk, const P2& a, const P2& b) {
    const Q fa = sq_dist(a, pi) - sq_dist(a, pk), fb = sq_dist(b, pi) - sq_dist(b, pk);
    const Q t = fa / (fa - fb);
    return std::array<Q, 2>{Q(a[0]) + t * (Q(b[0]) - Q(a[0])), Q(a[1]) + t * (Q(b[1]) - Q(a[1]))};
  };
  const auto dist2 = [](const std::array<Q, 2>& x, const P2& p) -> Q {
    const Q dx = x[0] - Q(p[0]), dy = x[1] - Q(p[1]);
    return dx * dx + dy * dy;
  };
  for (std::size_t it = 0; it < scaled(3000); ++it) {
    const auto idx = distinct_indices<4>(rng, 1000);
    const P2 pi = random_point(rng), pk = random_point(rng), pj = random_point(rng);
    const P2 pl = random_point(rng);
    P2 a, b, a2, b2;
    make_crossing(pi, pk, a, b, rng);
    make_crossing(pi, pk, a2, b2, rng);

    const auto q = crossing(pi, pk, a, b);
    const int want_edge = sgn(dist2(q, pi) - dist2(q, pj));
    const int got_edge = to_int(bisector_side_edge2d(pi.data(), pk.data(), pj.data(), a.data(),
                                                     b.data(), idx[0], idx[1], idx[2]));

    const auto q2 = crossing(pi, pk, a2, b2);
    const Q dx = Q(pi[1]) - Q(pk[1]), dy = Q(pk[0]) - Q(pi[0]);
    const int want_cmp = sgn(dx * (q2[0] - q[0]) + dy * (q2[1] - q[1]));
    const int got_cmp = to_int(compare_on_bisector2d(pi.data(), pk.data(), a.data(), b.data(),
                                                     a2.data(), b2.data(), idx[0], idx[1]));

    // Circumcentre of p_i, p_k, p_l (translated to p_i, Cramer's rule).
    const Q bx = Q(pk[0]) - Q(pi[0]), by = Q(pk[1]) - Q(pi[1]);
    const Q cx = Q(pl[0]) - Q(pi[0]), cy = Q(pl[1]) - Q(pi[1]);
    const Q det = 2 * (bx * cy - by * cx);
    const Q b2l = bx * bx + by * by, c2l = cx * cx + cy * cy;
    const std::array<Q, 2> x = {Q(pi[0]) + (cy * b2l - by * c2l) / det,
                                Q(pi[1]) + (bx * c2l - cx * b2l) / det};
    const int want_vor = sgn(dist2(x, pi) - dist2(x, pj));
    const int got_vor = to_int(bisector_side_voronoi2d(pi.data(), pk.data(), pl.data(), pj.data(),
                                                       idx[0], idx[1], idx[3], idx[2]));
    if (want_edge == 0 || want_cmp == 0 || want_vor == 0) continue;  // (never, for random)
    if (got_edge != want_edge || got_cmp != want_cmp || got_vor != want_vor) {
      ++failures;
      FAIL_CHECK("pi {" << hex(pi[0]) << ", " << hex(pi[1]) << "} pk {" << hex(pk[0]) << ", "
                        << hex(pk[1]) << "} pj {" << hex(pj[0]) << ", " << hex(pj[1]) << "}: edge "
                        << got_edge << " want " << want_edge << ", compare " << got_cmp << " want "
                        << want_cmp << ", voronoi " << got_vor << " want " << want_vor);
    }
  }
  CHECK(failures == 0);
}

TEST_CASE("symmetries of the edge and compare predicates", "[predicates][exact][degenerate]") {
  const std::uint64_t seed = seed_for(0xb15ec5);
  INFO("seed " << seed);
  Rng rng(seed);
  std::size_t failures = 0, order_checks = 0;
  for (const Family fam : kFamilies) {
    INFO("family " << name(fam));
    for (std::size_t it = 0; it < scaled(3000); ++it) {
      const EdgeCase e = make_edge(fam, rng);
      const Got g = run(e);
      if (!g.threw) {
        // q depends on the segment and bisector(i, k) only; f_kj(q) = f_ij(q) there.
        EdgeCase ba = e;
        std::swap(ba.a, ba.b);
        EdgeCase ki = e;
        std::swap(ki.pi, ki.pk);
        std::swap(ki.i, ki.k);
        const Got gba = run(ba), gki = run(ki);
        // Antisymmetry along the line: with q_k = L ∩ bisector(i, k) and q_j = L ∩
        // bisector(i, j), f_ij(q_k) sign(D_ij) = -f_ik(q_j) sign(D_ik): both say on which
        // side of the other the crossing lies, seen from the two bisectors.
        EdgeCase jk = e;
        std::swap(jk.pj, jk.pk);
        std::swap(jk.j, jk.k);
        const Got gjk = run(jk);
        const auto side = [&](const P2& px) {
          return sgn((sq_dist(e.a, e.pi) - sq_dist(e.a, px)) -
                     (sq_dist(e.b, e.pi) - sq_dist(e.b, px)));
        };
        bool ok = !gba.threw && gba.sign == g.sign && !gki.threw && gki.sign == g.sign;
        if (!gjk.threw) {
          ++order_checks;
          ok = ok && g.sign * side(e.pj) == -gjk.sign * side(e.pk);
        }
        if (!ok) {
          ++failures;
          FAIL_CHECK("edge symmetry " << describe(e) << ": " << g.sign << " swapped ends "
                                      << gba.sign << " swapped i,k " << gki.sign << " swapped j,k "
                                      << gjk.sign);
        }
      }
      const CompareCase c = make_compare(fam, rng);
      const Got gc = run(c);
      if (!gc.threw) {
        CompareCase sw = c;  // q1 <-> q2
        std::swap(sw.a1, sw.a2);
        std::swap(sw.b1, sw.b2);
        CompareCase ends = c;  // the crossings do not depend on the orientation of segments
        std::swap(ends.a1, ends.b1);
        CompareCase ki = c;  // d = rot90(p_k - p_i) reverses
        std::swap(ki.pi, ki.pk);
        std::swap(ki.i, ki.k);
        const Got gsw = run(sw), gends = run(ends), gki = run(ki);
        if (gsw.threw || gsw.sign != -gc.sign || gends.threw || gends.sign != gc.sign ||
            gki.threw || gki.sign != -gc.sign) {
          ++failures;
          FAIL_CHECK("compare symmetry " << describe(c) << ": " << gc.sign << " swapped "
                                         << gsw.sign << " ends " << gends.sign << " i,k "
                                         << gki.sign);
        }
      }
    }
  }
  INFO(order_checks << " crossing-order checks");
  CHECK(failures == 0);
  CHECK(order_checks > 1000);
}

TEST_CASE("every Voronoi vertex of a Delaunay2 triangle is closer to its sites",
          "[predicates][exact][degenerate]") {
  const std::uint64_t seed = seed_for(0xb15ec6);
  INFO("seed " << seed);
  Rng rng(seed);
  // Random points, then an integer grid (every 4 neighbours cocircular: all ties go to the
  // perturbation, which must be the one Delaunay2 used through incircle_sos), then a grid
  // with its points shuffled (other indices, so another perturbed triangulation).
  for (int kind = 0; kind < 3; ++kind) {
    INFO("kind " << kind);
    std::vector<double> xy;
    if (kind == 0) {
      for (int p = 0; p < 150; ++p) {
        xy.push_back(uniform(rng, 0, 1));
        xy.push_back(uniform(rng, 0, 1));
      }
    } else {
      std::vector<P2> pts;
      for (int x = 0; x < 9; ++x)
        for (int y = 0; y < 9; ++y) pts.push_back({static_cast<double>(x), static_cast<double>(y)});
      if (kind == 2) shuffle(pts, rng);
      for (const P2& p : pts) {
        xy.push_back(p[0]);
        xy.push_back(p[1]);
      }
    }
    const auto n = static_cast<std::uint32_t>(xy.size() / 2);
    const Delaunay2 dt(xy.data(), n);
    REQUIRE(dt.nb_triangles() > 0);
    std::size_t failures = 0, calls = 0, oracle_checks = 0;
    for (std::uint32_t t = 0; t < dt.nb_triangles(); ++t) {
      const std::uint32_t v[3] = {dt.tri_vertex(t, 0), dt.tri_vertex(t, 1), dt.tri_vertex(t, 2)};
      for (std::uint32_t j = 0; j < n; ++j) {
        if (j == v[0] || j == v[1] || j == v[2]) continue;
        // All six argument orders of the triangle.
        static constexpr int kPerm[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1},
                                            {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};
        for (const auto& p : kPerm) {
          const std::uint32_t i = v[p[0]], k = v[p[1]], l = v[p[2]];
          const Sign s =
              bisector_side_voronoi2d(&xy[2 * i], &xy[2 * k], &xy[2 * l], &xy[2 * j], i, k, l, j);
          ++calls;
          if (s != Sign::negative) {
            ++failures;
            if (failures <= 10)
              FAIL_CHECK("triangle " << i << " " << k << " " << l << ", site " << j << ": "
                                     << to_int(s));
          }
        }
        if (kind > 0 && (t + j) % 7 == 0) {
          const P2 a = {xy[2 * v[0]], xy[2 * v[0] + 1]}, b = {xy[2 * v[1]], xy[2 * v[1] + 1]};
          const P2 c = {xy[2 * v[2]], xy[2 * v[2] + 1]}, d = {xy[2 * j], xy[2 * j + 1]};
          ++oracle_checks;
          if (oracle_voronoi({a, b, c, d, v[0], v[1], v[2], j}).sign != -1) ++failures;
        }
      }
    }
    INFO(calls << " calls, " << oracle_checks << " oracle checks");
    CHECK(failures == 0);
  }
}

TEST_CASE("bisector predicates: violated preconditions and non-finite input throw",
          "[predicates]") {
  const P2 p0 = {0, 0}, p1 = {2, 0}, p2 = {1, 3}, a = {-1, 0}, b = {3, 0};
  const double inf = std::numeric_limits<double>::infinity();
  const P2 bad = {inf, 0}, nan = {0, std::nan("")};
  CHECK_THROWS_AS(bisector_side_vertex2d(p0.data(), p1.data(), a.data(), 3, 3), Error);
  CHECK_THROWS_AS(bisector_side_vertex2d(p0.data(), p1.data(), bad.data(), 3, 4), Error);
  CHECK_THROWS_AS(bisector_side_vertex2d(nan.data(), p1.data(), a.data(), 3, 4), Error);
  CHECK_THROWS_AS(
      bisector_side_edge2d(p0.data(), p1.data(), p2.data(), a.data(), b.data(), 0, 1, 0), Error);
  CHECK_THROWS_AS(
      bisector_side_edge2d(p0.data(), p1.data(), p2.data(), a.data(), b.data(), 1, 1, 2), Error);
  // A segment parallel to the bisector x = 1, and a degenerate one.
  const P2 c = {0, -1}, d = {0, 5};
  CHECK_THROWS_AS(
      bisector_side_edge2d(p0.data(), p1.data(), p2.data(), c.data(), d.data(), 0, 1, 2), Error);
  CHECK_THROWS_AS(
      bisector_side_edge2d(p0.data(), p1.data(), p2.data(), a.data(), a.data(), 0, 1, 2), Error);
  // Coincident sites i, k: no bisector.
  CHECK_THROWS_AS(
      bisector_side_edge2d(p0.data(), p0.data(), p2.data(), a.data(), b.data(), 0, 1, 2), Error);
  for (const P2* x : {&bad, &nan}) {
    CHECK_THROWS_AS(
        bisector_side_edge2d(x->data(), p1.data(), p2.data(), a.data(), b.data(), 0, 1, 2), Error);
    CHECK_THROWS_AS(
        bisector_side_edge2d(p0.data(), p1.data(), x->data(), a.data(), b.data(), 0, 1, 2), Error);
    CHECK_THROWS_AS(
        bisector_side_edge2d(p0.data(), p1.data(), p2.data(), a.data(), x->data(), 0, 1, 2), Error);
    CHECK_THROWS_AS(
        compare_on_bisector2d(p0.data(), p1.data(), a.data(), b.data(), x->data(), b.data(), 0, 1),
        Error);
    CHECK_THROWS_AS(bisector_side_voronoi2d(p0.data(), p1.data(), p2.data(), x->data(), 0, 1, 2, 3),
                    Error);
    CHECK_THROWS_AS(bisector_side_voronoi2d(x->data(), p1.data(), p2.data(), a.data(), 0, 1, 2, 3),
                    Error);
  }
  CHECK_THROWS_AS(
      compare_on_bisector2d(p0.data(), p1.data(), a.data(), b.data(), c.data(), d.data(), 0, 1),
      Error);
  CHECK_THROWS_AS(
      compare_on_bisector2d(p0.data(), p1.data(), a.data(), b.data(), a.data(), b.data(), 4, 4),
      Error);
  // Collinear Voronoi triple, repeated indices.
  const P2 m = {1, 0};
  CHECK_THROWS_AS(bisector_side_voronoi2d(p0.data(), m.data(), p1.data(), p2.data(), 0, 1, 2, 3),
                  Error);
  CHECK_THROWS_AS(bisector_side_voronoi2d(p0.data(), p1.data(), p2.data(), a.data(), 0, 1, 2, 1),
                  Error);
}
