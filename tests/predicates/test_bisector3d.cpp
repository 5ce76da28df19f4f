// Tests of the 3D Voronoi clipping predicates (predicates.h, "Voronoi clipping predicates in
// 3D"): bisector_side_vertex3d, bisector_side_edge3d, bisector_side_facet3d and
// bisector_side_voronoi3d.
//
// The oracle is written from the contract alone, in rationals (GMP), and does the symbolic
// perturbation on its own (EpsPoly, eps_poly.h): every quantity is a polynomial in the eps_x
// of the call's sites with exact rational coefficients, built from
// pi_x(y) = |y - p_x|^2 + eps_x by the contract's formulas, not from the implementation's
// reduced forms (bisector3d.h):
//   vertex    f_ij(a)
//   edge      (f_ik(a) f_ij(b) - f_ij(a) f_ik(b)) * sign(f_ik(a) - f_ik(b))
//   facet     det[f_ij; f_ik; f_il] * sign(det[1; f_ik; f_il]), rows = values at a, b, c,
//             the full 3 x 3 determinants of polynomials
//   voronoi   f_ij(x) at the power centre x of i, k, l, m (solved by Cramer's rule, x affine
//             in the eps)
// and the oracle reports the degree of the deciding monomial: the contract's predicates
// are all decided by terms of degree <= 1.
//
// The geometric tests construct the crossing points, facet points and Voronoi vertices
// explicitly in rationals as a third formulation; the Delaunay3 test checks
// bisector_side_voronoi3d against the triangulation built with insphere_sos.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <gmpxx.h>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "bisector3d.h"
#include "eps_poly.h"
#include "exact_oracle.h"
#include "voroclip/core.h"
#include "voroclip/delaunay.h"
#include "voroclip/predicates.h"

using namespace voroclip;
using namespace voroclip::test;

namespace {

using P3 = std::array<double, 3>;
using Q3 = std::array<Q, 3>;

Q sq_dist(const P3& x, const P3& p) {
  Q s = 0;
  for (std::size_t t = 0; t < 3; ++t) {
    const Q d = Q(x[t]) - Q(p[t]);
    s += d * d;
  }
  return s;
}
Q sq_dist(const Q3& x, const P3& p) {
  Q s = 0;
  for (std::size_t t = 0; t < 3; ++t) {
    const Q d = x[t] - Q(p[t]);
    s += d * d;
  }
  return s;
}
Q lift(const P3& p) { return Q(p[0]) * Q(p[0]) + Q(p[1]) * Q(p[1]) + Q(p[2]) * Q(p[2]); }

// f_xy(y) = pi_x(y) - pi_y(y) for sites in slots sx, sy.
EpsPoly f(const P3& y, const P3& px, int sx, const P3& py, int sy) {
  return EpsPoly(sq_dist(y, px) - sq_dist(y, py)) + EpsPoly::eps(sx) - EpsPoly::eps(sy);
}

template <class T>
T det3(const std::array<T, 3>& r0, const std::array<T, 3>& r1, const std::array<T, 3>& r2) {
  return r0[0] * (r1[1] * r2[2] - r1[2] * r2[1]) - r0[1] * (r1[0] * r2[2] - r1[2] * r2[0]) +
         r0[2] * (r1[0] * r2[1] - r1[1] * r2[0]);
}

// Solves the rational 3 x 3 system A x = r (rows of A), x = adj(A) r / det(A), for a
// right-hand side in any ring T over Q (Q or EpsPoly). False when det(A) == 0.
template <class T>
bool solve3(const std::array<Q3, 3>& a, const std::array<T, 3>& r, std::array<T, 3>& x) {
  const Q det = det3(a[0], a[1], a[2]);
  if (sgn(det) == 0) return false;
  const Q inv = 1 / det;
  for (std::size_t c = 0; c < 3; ++c) {
    // Cramer: column c of A replaced by r, expanded along that column.
    T s = T(Q(0));
    for (std::size_t row = 0; row < 3; ++row) {
      const std::size_t r1 = (row + 1) % 3, r2 = (row + 2) % 3;
      const std::size_t c1 = (c + 1) % 3, c2 = (c + 2) % 3;
      const Q cof = a[r1][c1] * a[r2][c2] - a[r1][c2] * a[r2][c1];
      s = s + r[row] * T(cof);
    }
    x[c] = s * T(inv);
  }
  return true;
}

struct Expected {
  bool throws = false;  // a precondition is violated
  int sign = 0;         // the perturbed sign
  int unperturbed = 0;  // the sign with eps = 0 (what a filter may decide)
  int degree = 0;       // degree of the deciding monomial
  int depth = 0;        // eps_x (by increasing index) with a zero coefficient before it
};
const Expected kThrows{true, 0, 0, 0, 0};

// How many of the eps of the slots (site indices index[s]) have a zero coefficient in v
// before the first non-zero one, in increasing index order (the perturbation's levels that
// tied too).
template <std::size_t N>
int tie_depth(const EpsPoly& v, const std::array<std::uint32_t, N>& index) {
  std::array<int, N> slots{};
  for (std::size_t s = 0; s < N; ++s) slots[s] = static_cast<int>(s);
  std::sort(slots.begin(), slots.end(), [&](int x, int y) {
    return index[static_cast<std::size_t>(x)] < index[static_cast<std::size_t>(y)];
  });
  int depth = 0;
  for (const int s : slots) {
    if (sgn(v.linear(s)) != 0) break;
    ++depth;
  }
  return depth;
}

std::string str(const P3& p) { return "{" + hex(p[0]) + ", " + hex(p[1]) + ", " + hex(p[2]) + "}"; }

// ---------------------------------------------------------------------------------------
// The oracles.

Expected oracle_vertex(const P3& pi, const P3& pj, const P3& a, std::uint32_t i, std::uint32_t j) {
  if (i == j) return kThrows;
  Expected r;
  const EpsPoly v = f(a, pi, 0, pj, 1);
  r.sign = v.sign({i, j, 0, 0, 0}, 2, r.degree);
  r.unperturbed = sgn(v.constant());
  return r;
}

struct EdgeCase {
  P3 pi, pk, pj, a, b;
  std::uint32_t i, k, j;
};

std::string describe(const EdgeCase& c) {
  return "edge pi " + str(c.pi) + " pk " + str(c.pk) + " pj " + str(c.pj) + " a " + str(c.a) +
         " b " + str(c.b) + " i " + std::to_string(c.i) + " k " + std::to_string(c.k) + " j " +
         std::to_string(c.j);
}

Expected oracle_edge(const EdgeCase& c) {
  if (c.i == c.j || c.i == c.k || c.j == c.k) return kThrows;
  // slots: i 0, k 1, j 2
  const EpsPoly fik_a = f(c.a, c.pi, 0, c.pk, 1), fik_b = f(c.b, c.pi, 0, c.pk, 1);
  const EpsPoly fij_a = f(c.a, c.pi, 0, c.pj, 2), fij_b = f(c.b, c.pi, 0, c.pj, 2);
  const EpsPoly d = fik_a - fik_b;
  REQUIRE(d.is_constant());
  const int sd = sgn(d.constant());
  if (sd == 0) return kThrows;
  const EpsPoly n = fik_a * fij_b - fij_a * fik_b;
  Expected r;
  r.sign = n.sign({c.i, c.k, c.j, 0, 0}, 3, r.degree) * sd;
  r.unperturbed = sgn(n.constant()) * sd;
  r.depth = tie_depth(n, std::array<std::uint32_t, 3>{c.i, c.k, c.j});
  return r;
}

struct FacetCase {
  P3 pi, pk, pl, pj, a, b, c;
  std::uint32_t i, k, l, j;
};

std::string describe(const FacetCase& c) {
  return "facet pi " + str(c.pi) + " pk " + str(c.pk) + " pl " + str(c.pl) + " pj " + str(c.pj) +
         " a " + str(c.a) + " b " + str(c.b) + " c " + str(c.c) + " i " + std::to_string(c.i) +
         " k " + std::to_string(c.k) + " l " + std::to_string(c.l) + " j " + std::to_string(c.j);
}

Expected oracle_facet(const FacetCase& c) {
  const std::uint32_t ids[] = {c.i, c.k, c.l, c.j};
  for (int x = 0; x < 4; ++x)
    for (int y = x + 1; y < 4; ++y)
      if (ids[x] == ids[y]) return kThrows;
  // slots: i 0, k 1, l 2, j 3; rows of values at a, b, c.
  const auto row = [&](const P3& px, int sx) {
    return std::array<EpsPoly, 3>{f(c.a, c.pi, 0, px, sx), f(c.b, c.pi, 0, px, sx),
                                  f(c.c, c.pi, 0, px, sx)};
  };
  const std::array<EpsPoly, 3> fij = row(c.pj, 3), fik = row(c.pk, 1), fil = row(c.pl, 2);
  const std::array<EpsPoly, 3> one = {EpsPoly(Q(1)), EpsPoly(Q(1)), EpsPoly(Q(1))};
  const EpsPoly d = det3(one, fik, fil);
  REQUIRE(d.is_constant());
  const int sd = sgn(d.constant());
  if (sd == 0) return kThrows;
  const EpsPoly n = det3(fij, fik, fil);
  Expected r;
  r.sign = n.sign({c.i, c.k, c.l, c.j, 0}, 4, r.degree) * sd;
  r.unperturbed = sgn(n.constant()) * sd;
  r.depth = tie_depth(n, std::array<std::uint32_t, 4>{c.i, c.k, c.l, c.j});
  return r;
}

struct VoronoiCase {
  P3 pi, pk, pl, pm, pj;
  std::uint32_t i, k, l, m, j;
};

std::string describe(const VoronoiCase& c) {
  return "voronoi pi " + str(c.pi) + " pk " + str(c.pk) + " pl " + str(c.pl) + " pm " + str(c.pm) +
         " pj " + str(c.pj) + " i " + std::to_string(c.i) + " k " + std::to_string(c.k) + " l " +
         std::to_string(c.l) + " m " + std::to_string(c.m) + " j " + std::to_string(c.j);
}

Expected oracle_voronoi(const VoronoiCase& c) {
  const std::uint32_t ids[] = {c.i, c.k, c.l, c.m, c.j};
  for (int x = 0; x < 5; ++x)
    for (int y = x + 1; y < 5; ++y)
      if (ids[x] == ids[y]) return kThrows;
  // slots: i 0, k 1, l 2, m 3, j 4. The power centre x: f_ix(x) = 0 for x = k, l, m, i.e.
  // 2 (p_x - p_i) . x = |p_x|^2 - |p_i|^2 + eps_x - eps_i.
  std::array<Q3, 3> a;
  std::array<EpsPoly, 3> rhs;
  const P3* sites[3] = {&c.pk, &c.pl, &c.pm};
  for (std::size_t r = 0; r < 3; ++r) {
    for (std::size_t t = 0; t < 3; ++t) a[r][t] = 2 * (Q((*sites[r])[t]) - Q(c.pi[t]));
    rhs[r] = EpsPoly(lift(*sites[r]) - lift(c.pi)) + EpsPoly::eps(static_cast<int>(r) + 1) -
             EpsPoly::eps(0);
  }
  std::array<EpsPoly, 3> x;
  if (!solve3(a, rhs, x)) return kThrows;
  // f_ij(x) = 2 x . (p_j - p_i) + |p_i|^2 - |p_j|^2 + eps_i - eps_j
  EpsPoly v = EpsPoly(lift(c.pi) - lift(c.pj)) + EpsPoly::eps(0) - EpsPoly::eps(4);
  for (std::size_t t = 0; t < 3; ++t) v = v + x[t] * EpsPoly(2 * (Q(c.pj[t]) - Q(c.pi[t])));
  Expected r;
  r.sign = v.sign({c.i, c.k, c.l, c.m, c.j}, 5, r.degree);
  r.unperturbed = sgn(v.constant());
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

bool same(const Got& x, const Got& y) { return x.threw == y.threw && x.sign == y.sign; }

Got run(const EdgeCase& c) {
  return call([&] {
    return bisector_side_edge3d(c.pi.data(), c.pk.data(), c.pj.data(), c.a.data(), c.b.data(), c.i,
                                c.k, c.j);
  });
}
Got run_exact(const EdgeCase& c) {
  return call([&] {
    return detail::bisector_side_edge3d_exact(c.pi.data(), c.pk.data(), c.pj.data(), c.a.data(),
                                              c.b.data(), c.i, c.k, c.j);
  });
}
int run_filter(const EdgeCase& c) {
  return detail::bisector_edge3d_filter(c.pi.data(), c.pk.data(), c.pj.data(), c.a.data(),
                                        c.b.data());
}
Got run(const FacetCase& c) {
  return call([&] {
    return bisector_side_facet3d(c.pi.data(), c.pk.data(), c.pl.data(), c.pj.data(), c.a.data(),
                                 c.b.data(), c.c.data(), c.i, c.k, c.l, c.j);
  });
}
Got run_exact(const FacetCase& c) {
  return call([&] {
    return detail::bisector_side_facet3d_exact(c.pi.data(), c.pk.data(), c.pl.data(), c.pj.data(),
                                               c.a.data(), c.b.data(), c.c.data(), c.i, c.k, c.l,
                                               c.j);
  });
}
int run_filter(const FacetCase& c) {
  return detail::bisector_facet3d_filter(c.pi.data(), c.pk.data(), c.pl.data(), c.pj.data(),
                                         c.a.data(), c.b.data(), c.c.data());
}
Got run(const VoronoiCase& c) {
  return call([&] {
    return bisector_side_voronoi3d(c.pi.data(), c.pk.data(), c.pl.data(), c.pm.data(), c.pj.data(),
                                   c.i, c.k, c.l, c.m, c.j);
  });
}
Got run_vertex(const P3& pi, const P3& pj, const P3& a, std::uint32_t i, std::uint32_t j) {
  return call([&] { return bisector_side_vertex3d(pi.data(), pj.data(), a.data(), i, j); });
}

// Statistics of one family: how often the exact zero was perturbed, and the filter failed.
struct Tally {
  std::size_t n = 0, failures = 0, perturbed = 0, throws = 0, undecided = 0, zeros = 0;
  std::size_t deep = 0;  // perturbed, and the first eps tied too
};

// Checks the full predicate, the exact stage alone and the filter against the oracle.
template <class Case, class Oracle>
void check_case(const Case& c, Oracle oracle, Tally& t) {
  const Expected want = oracle(c);
  ++t.n;
  t.throws += want.throws;
  t.perturbed += !want.throws && want.unperturbed == 0;
  t.deep += !want.throws && want.unperturbed == 0 && want.depth > 0;
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

P3 random_point(Rng& rng) {
  return {uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)};
}
P3 grid_point(Rng& rng, long long top) {
  return {static_cast<double>(rand_int(rng, -top, top)),
          static_cast<double>(rand_int(rng, -top, top)),
          static_cast<double>(rand_int(rng, -top, top))};
}
P3 mixed_point(Rng& rng) {
  return {random_mixed_coordinate(rng), random_mixed_coordinate(rng), random_mixed_coordinate(rng)};
}
// A generator of the mixed-magnitudes family, fixed for one case: half of the time
// random_mixed_coordinate (tiny, subnormal, huge, zero...: big integers decide), else
// coordinates 2^e (1 + random fraction), |e| <= s for one s in {20, 45, 70, 120}: exponent
// spans of about 2s + 53 bits, which reach the fixed-width integer, expansion and
// big-integer tiers of the exact stage in turn.
struct MixedGenerator {
  int spread;
  explicit MixedGenerator(Rng& rng) {
    static constexpr int kSpreads[4] = {20, 45, 70, 120};
    spread = coin(rng) ? 0 : kSpreads[rng() % 4];
  }
  P3 operator()(Rng& rng) const {
    if (spread == 0) return mixed_point(rng);
    return {random_wide(rng, -spread, spread), random_wide(rng, -spread, spread),
            random_wide(rng, -spread, spread)};
  }
};
P3 nudged(P3 p, Rng& rng, int ulps) {
  for (double& x : p) x = nudge(x, static_cast<int>(rand_int(rng, -ulps, ulps)));
  return p;
}
P3 scaled_point(const P3& p, int e) {
  return {std::ldexp(p[0], e), std::ldexp(p[1], e), std::ldexp(p[2], e)};
}
P3 add(const P3& p, const P3& q, double s = 1) {
  return {p[0] + s * q[0], p[1] + s * q[1], p[2] + s * q[2]};
}
P3 sub(const P3& p, const P3& q) { return {p[0] - q[0], p[1] - q[1], p[2] - q[2]}; }
P3 scale(const P3& p, double s) { return {s * p[0], s * p[1], s * p[2]}; }
P3 cross(const P3& p, const P3& q) {
  return {p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0]};
}
double dot(const P3& p, const P3& q) { return p[0] * q[0] + p[1] * q[1] + p[2] * q[2]; }

// Half of the time p, else p moved by a random vector of length about 2^-m, m in [8, 60]:
// from clearly decided by the filter down to within rounding of the degenerate position,
// so that the filter's bound is exercised where it matters.
P3 off_by(const P3& p, Rng& rng) {
  if (coin(rng)) return p;
  const double h = std::ldexp(1.0, -static_cast<int>(rand_int(rng, 8, 60)));
  return add(p, random_point(rng), h);
}

// The centre of the circle through a, b, c (in their plane), in floating point.
P3 circumcenter(const P3& a, const P3& b, const P3& c) {
  const P3 u = sub(b, a), v = sub(c, a), n = cross(u, v);
  const double nn = dot(n, n);
  const P3 t = add(scale(cross(n, u), dot(v, v)), cross(v, n), dot(u, u));
  return add(a, t, 0.5 / nn);
}

// The centre of the sphere through a, b, c, d, in floating point.
P3 circumcenter(const P3& a, const P3& b, const P3& c, const P3& d) {
  const P3 u = sub(b, a), v = sub(c, a), w = sub(d, a);
  const double det = 2 * dot(u, cross(v, w));
  const P3 t =
      add(add(scale(cross(v, w), dot(u, u)), cross(w, u), dot(v, v)), cross(u, v), dot(w, w));
  return add(a, t, 1 / det);
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

// Lattice vectors of squared length r2 for a few small r2: sites at the same distance from
// a lattice point (exact ties of f at that point).
const std::vector<std::array<long long, 3>>& lattice_shell(Rng& rng) {
  static const std::vector<std::array<long long, 3>> shells[4] = {
      lattice_sphere(3, 3), lattice_sphere(5, 3), lattice_sphere(6, 3), lattice_sphere(9, 3)};
  return shells[rng() % 4];
}
P3 shell_point(const P3& x, const std::vector<std::array<long long, 3>>& s, Rng& rng) {
  const auto& v = s[static_cast<std::size_t>(rng() % s.size())];
  return {x[0] + static_cast<double>(v[0]), x[1] + static_cast<double>(v[1]),
          x[2] + static_cast<double>(v[2])};
}

EdgeCase make_edge(Family fam, Rng& rng) {
  EdgeCase c{};
  const auto idx = distinct_indices<3>(rng);
  c.i = idx[0];
  c.k = idx[1];
  c.j = idx[2];
  switch (fam) {
    case Family::random:
      for (P3* p : {&c.pi, &c.pk, &c.pj, &c.a, &c.b}) *p = random_point(rng);
      break;
    case Family::grid: {
      if (coin(rng)) {
        // Small integers: F == 0, N0 == 0 and E == 0 all occur often.
        const long long top = coin(rng) ? 2 : 4;
        for (P3* p : {&c.pi, &c.pk, &c.pj, &c.a, &c.b}) *p = grid_point(rng, top);
        if (rng() % 4 == 0) c.pj = c.pk;  // duplicate sites: f_ij = f_ik + eps terms
      } else {
        // Sites on a lattice sphere around x, the segment through x: f_ij(q) = 0 exactly.
        const P3 x = grid_point(rng, 2);
        const auto& shell = lattice_shell(rng);
        for (P3* p : {&c.pi, &c.pk, &c.pj}) *p = shell_point(x, shell, rng);
        const P3 d = grid_point(rng, 2);
        c.a = add(x, d, static_cast<double>(rand_int(rng, 1, 2)));
        c.b = add(x, d, -static_cast<double>(rand_int(rng, 0, 2)));
      }
      break;
    }
    case Family::near: {
      // The segment passes within ulps of the Voronoi edge line of i, k, j: f_ij(q) ~ 0.
      for (P3* p : {&c.pi, &c.pk, &c.pj}) *p = random_point(rng);
      const P3 o = circumcenter(c.pi, c.pk, c.pj);
      const P3 nrm = cross(sub(c.pk, c.pi), sub(c.pj, c.pi));
      const P3 v = off_by(add(o, nrm, uniform(rng, -1, 1)), rng);
      const P3 dir = random_point(rng);
      const double s = uniform(rng, 0.1, 1), t = uniform(rng, 0.1, 1);
      c.a = nudged(add(v, dir, s), rng, 2);
      c.b = nudged(add(v, dir, -t), rng, 2);
      if (coin(rng)) c.a = nudged(v, rng, 1);  // an endpoint on the Voronoi edge
      break;
    }
    case Family::mixed: {
      const MixedGenerator gen(rng);
      for (P3* p : {&c.pi, &c.pk, &c.pj, &c.a, &c.b}) *p = gen(rng);
      break;
    }
    case Family::scaled: {
      // A grid or random configuration times 2^e, |e| <= 1000 (exact, no overflow).
      EdgeCase base = make_edge(coin(rng) ? Family::grid : Family::random, rng);
      const auto e = static_cast<int>(rand_int(rng, -1000, 1000));
      for (P3* p : {&base.pi, &base.pk, &base.pj, &base.a, &base.b}) *p = scaled_point(*p, e);
      return base;
    }
  }
  return c;
}

// Three points of a plane through x: x = (a + b + c) / 3.
void plane_through(const P3& x, const P3& d1, const P3& d2, P3& a, P3& b, P3& c) {
  a = add(x, d1);
  b = add(x, d2);
  c = sub(sub(x, d1), d2);
}

FacetCase make_facet(Family fam, Rng& rng) {
  FacetCase c{};
  const auto idx = distinct_indices<4>(rng);
  c.i = idx[0];
  c.k = idx[1];
  c.l = idx[2];
  c.j = idx[3];
  switch (fam) {
    case Family::random:
      for (P3* p : {&c.pi, &c.pk, &c.pl, &c.pj, &c.a, &c.b, &c.c}) *p = random_point(rng);
      break;
    case Family::grid: {
      if (coin(rng)) {
        // Small integers: D == 0 (collinear sites or triangle, a plane parallel to the
        // Voronoi edge) and N' == 0 occur often.
        const long long top = coin(rng) ? 2 : 3;
        for (P3* p : {&c.pi, &c.pk, &c.pl, &c.pj, &c.a, &c.b, &c.c}) *p = grid_point(rng, top);
        if (rng() % 6 == 0) c.pj = c.pk;  // duplicate sites
      } else {
        // Sites on a lattice sphere around x, the plane through x: f_ij(x) = 0 exactly, and
        // the perturbation decides whenever D != 0.
        const P3 x = grid_point(rng, 2);
        const auto& shell = lattice_shell(rng);
        for (P3* p : {&c.pi, &c.pk, &c.pl, &c.pj}) *p = shell_point(x, shell, rng);
        plane_through(x, grid_point(rng, 2), grid_point(rng, 2), c.a, c.b, c.c);
        if (rng() % 4 == 0) std::swap(c.a, c.c);
      }
      break;
    }
    case Family::near: {
      // The plane passes within ulps of the Voronoi vertex of i, k, l, j: f_ij(x) ~ 0.
      for (P3* p : {&c.pi, &c.pk, &c.pl, &c.pj}) *p = random_point(rng);
      const P3 v = off_by(circumcenter(c.pi, c.pk, c.pl, c.pj), rng);
      P3 a, b, cc;
      plane_through(v, random_point(rng), random_point(rng), a, b, cc);
      c.a = nudged(a, rng, 2);
      c.b = nudged(b, rng, 2);
      c.c = nudged(cc, rng, 2);
      if (coin(rng)) c.a = nudged(v, rng, 1);  // a vertex at the Voronoi vertex
      break;
    }
    case Family::mixed: {
      const MixedGenerator gen(rng);
      for (P3* p : {&c.pi, &c.pk, &c.pl, &c.pj, &c.a, &c.b, &c.c}) *p = gen(rng);
      break;
    }
    case Family::scaled: {
      FacetCase base = make_facet(coin(rng) ? Family::grid : Family::random, rng);
      const auto e = static_cast<int>(rand_int(rng, -1000, 1000));
      for (P3* p : {&base.pi, &base.pk, &base.pl, &base.pj, &base.a, &base.b, &base.c})
        *p = scaled_point(*p, e);
      return base;
    }
  }
  return c;
}

VoronoiCase make_voronoi(Family fam, Rng& rng) {
  VoronoiCase c{};
  const auto idx = distinct_indices<5>(rng);
  c.i = idx[0], c.k = idx[1], c.l = idx[2], c.m = idx[3], c.j = idx[4];
  switch (fam) {
    case Family::random:
      for (P3* p : {&c.pi, &c.pk, &c.pl, &c.pm, &c.pj}) *p = random_point(rng);
      break;
    case Family::grid:
      if (coin(rng)) {
        for (P3* p : {&c.pi, &c.pk, &c.pl, &c.pm, &c.pj}) *p = grid_point(rng, 2);
      } else {
        const P3 x = grid_point(rng, 2);  // five sites on one lattice sphere
        const auto& shell = lattice_shell(rng);
        for (P3* p : {&c.pi, &c.pk, &c.pl, &c.pm, &c.pj}) *p = shell_point(x, shell, rng);
      }
      break;
    case Family::near: {
      for (P3* p : {&c.pi, &c.pk, &c.pl, &c.pm}) *p = random_point(rng);
      // p_j on the sphere through the four, up to rounding.
      const P3 o = circumcenter(c.pi, c.pk, c.pl, c.pm);
      const double r = std::sqrt(dot(sub(c.pi, o), sub(c.pi, o)));
      P3 d = random_point(rng);
      const double len = std::sqrt(dot(d, d));
      c.pj = nudged(add(o, d, r / len), rng, 2);
      break;
    }
    case Family::mixed: {
      const MixedGenerator gen(rng);
      for (P3* p : {&c.pi, &c.pk, &c.pl, &c.pm, &c.pj}) *p = gen(rng);
      break;
    }
    case Family::scaled: {
      VoronoiCase base = make_voronoi(coin(rng) ? Family::grid : Family::random, rng);
      const auto e = static_cast<int>(rand_int(rng, -1000, 1000));
      for (P3* p : {&base.pi, &base.pk, &base.pl, &base.pm, &base.pj}) *p = scaled_point(*p, e);
      return base;
    }
  }
  return c;
}

// The facet point in rationals: the solution of n . x = n . a, 2 c_x . x = |p_x|^2 - |p_i|^2
// (x = k, l). False when the system is singular.
bool facet_point(const FacetCase& c, Q3& x) {
  Q3 u, v;
  for (std::size_t t = 0; t < 3; ++t) {
    u[t] = Q(c.b[t]) - Q(c.a[t]);
    v[t] = Q(c.c[t]) - Q(c.a[t]);
  }
  const Q3 n = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  std::array<Q3, 3> m;
  std::array<Q, 3> r;
  m[0] = n;
  r[0] = n[0] * Q(c.a[0]) + n[1] * Q(c.a[1]) + n[2] * Q(c.a[2]);
  const P3* sites[2] = {&c.pk, &c.pl};
  for (std::size_t s = 0; s < 2; ++s) {
    for (std::size_t t = 0; t < 3; ++t) m[s + 1][t] = 2 * (Q((*sites[s])[t]) - Q(c.pi[t]));
    r[s + 1] = lift(*sites[s]) - lift(c.pi);
  }
  return solve3(m, r, x);
}

}  // namespace

// ---------------------------------------------------------------------------------------

TEST_CASE("3D oracle: hand-derived cases", "[predicates][exact]") {
  // Vertex: sites (0,0,0) and (2,0,0), bisector x = 1; the tie goes to the larger index.
  const P3 p0 = {0, 0, 0}, p2 = {2, 0, 0}, on = {1, 5, -3}, left = {0.5, 0, 9};
  CHECK(oracle_vertex(p0, p2, on, 3, 7).sign == 1);
  CHECK(oracle_vertex(p0, p2, on, 7, 3).sign == -1);
  CHECK(run_vertex(p0, p2, on, 3, 7).sign == 1);
  CHECK(run_vertex(p0, p2, on, 7, 3).sign == -1);
  CHECK(run_vertex(p0, p2, left, 7, 3).sign == -1);
  CHECK(run_vertex(p2, p0, left, 3, 7).sign == 1);

  // Edge: the 2D hand case lifted to z = 5 (the sites stay at z = 0 and z = 0: the
  // distances grow by the same 25). Segment from (-1,0,5) to (3,0,5) crosses bisector(i =
  // (0,0,0), k = (2,0,0)) at q = (1,0,5). j = (1,3,0): q closer to i. j = (1,-1,0): a tie,
  // N = eps_i (E_k - E_j) - eps_j E_k + eps_k E_j with E_k = 8, E_j = 4.
  EdgeCase e{{0, 0, 0}, {2, 0, 0}, {1, 3, 0}, {-1, 0, 5}, {3, 0, 5}, 0, 1, 2};
  CHECK(oracle_edge(e).sign == -1);
  CHECK(run(e).sign == -1);
  e.pj = {1, -1, 0};
  CHECK(oracle_edge(e).unperturbed == 0);
  CHECK(oracle_edge(e).sign == 1);  // i = 0 first: E_k - E_j = 4 > 0
  CHECK(run(e).sign == 1);
  e.i = 5;  // k = 1 first: E_j > 0
  CHECK(oracle_edge(e).sign == 1);
  CHECK(run(e).sign == 1);
  e.k = 9;  // j = 2 first: -E_k < 0
  CHECK(oracle_edge(e).sign == -1);
  CHECK(run(e).sign == -1);

  // Facet: sites i = (0,0,0), k = (2,0,0), l = (0,2,0): bisectors x = 1 and y = 1, their
  // line (1, 1, t) meets the plane z = 0 of (a, b, c) at x = (1, 1, 0).
  FacetCase fc{{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {1, 1, 3}, {-5, -5, 0}, {5, -5, 0}, {0, 5, 0},
               0,         1,         2,         3};
  CHECK(oracle_facet(fc).sign == -1);  // |x - p_j|^2 = 9 > 2
  CHECK(run(fc).sign == -1);
  fc.pj = {1, 1, -1};  // |x - p_j|^2 = 1 < 2
  CHECK(oracle_facet(fc).sign == 1);
  CHECK(run(fc).sign == 1);
  // j = (2,2,0): a tie. Perturbed, x = (1 - e_ik / 4, 1 - e_il / 4, 0) and
  // f_ij(x) = 4x + 4y - 8 + e_ij = -eps_i + eps_k + eps_l - eps_j (m_1 = -m_2 = -m_3).
  fc.pj = {2, 2, 0};
  CHECK(oracle_facet(fc).unperturbed == 0);
  CHECK(oracle_facet(fc).sign == -1);  // i = 0 first
  CHECK(run(fc).sign == -1);
  fc.i = 5;  // k = 1 first: +eps_k
  CHECK(oracle_facet(fc).sign == 1);
  CHECK(run(fc).sign == 1);
  fc.k = 4, fc.l = 6;  // j = 3 first: -eps_j
  CHECK(oracle_facet(fc).sign == -1);
  CHECK(run(fc).sign == -1);
  fc.j = 7;  // k = 4 first
  CHECK(oracle_facet(fc).sign == 1);
  CHECK(run(fc).sign == 1);
  // A plane containing the Voronoi edge line (x = 1, y = 1 contains (1, 1, t)): D == 0.
  fc.a = {1, 1, 0}, fc.b = {1, 1, 7}, fc.c = {3, -1, 2};
  CHECK(oracle_facet(fc).throws);
  CHECK(run(fc).threw);
  // A plane parallel to it, not containing it: D == 0 too.
  fc.a = {0, 1, 0}, fc.b = {0, 1, 7}, fc.c = {2, -1, 2};
  CHECK(oracle_facet(fc).throws);
  CHECK(run(fc).threw);
}

TEST_CASE("3D Voronoi vertex sign convention: a site outside the sphere is farther",
          "[predicates][exact]") {
  // Tet (0,0,0), (4,0,0), (0,4,0), (0,0,4): Voronoi vertex (2,2,2), radius^2 12.
  const P3 a = {0, 0, 0}, b = {4, 0, 0}, c = {0, 4, 0}, d = {0, 0, 4};
  const P3 far = {10, 10, 10}, near = {2, 2, 3}, co = {4, 4, 0};
  for (int odd = 0; odd < 2; ++odd) {
    // Both orientations of the tet.
    const P3& k = odd ? c : b;
    const P3& l = odd ? b : c;
    INFO("orientation " << to_int(orient3d(a.data(), k.data(), l.data(), d.data())));
    CHECK(run(VoronoiCase{a, k, l, d, far, 0, 1, 2, 3, 4}).sign == -1);
    CHECK(run(VoronoiCase{a, k, l, d, near, 0, 1, 2, 3, 4}).sign == 1);
    CHECK(oracle_voronoi({a, k, l, d, far, 0, 1, 2, 3, 4}).sign == -1);
    CHECK(oracle_voronoi({a, k, l, d, near, 0, 1, 2, 3, 4}).sign == 1);
    // Cospherical j = (4, 4, 0): decided by the perturbation, like insphere_sos.
    for (std::uint32_t jj : {4u, 9u}) {
      for (std::uint32_t ii : {0u, 7u}) {
        const VoronoiCase v{a, k, l, d, co, ii, 1, 2, 3, jj};
        const Expected t = oracle_voronoi(v);
        CHECK(t.unperturbed == 0);
        CHECK(t.degree == 1);
        CHECK(run(v).sign == t.sign);
      }
    }
  }
  // p_j a duplicate of p_k: pi_j = pi_k - eps_k + eps_j, so f_ij(x) = eps_k - eps_j, the
  // sign of k - j (Delaunay3 keeps the smaller index of duplicates: clipping must skip the
  // others, see predicates.h).
  for (const auto& [kk, jj] : {std::pair{1u, 4u}, std::pair{6u, 2u}}) {
    const VoronoiCase v{a, b, c, d, b, 0, kk, 7, 8, jj};
    const int want = kk < jj ? 1 : -1;
    CHECK(oracle_voronoi(v).sign == want);
    CHECK(run(v).sign == want);
  }
}

TEST_CASE("3D edge and facet predicates agree with the rational oracle on every family",
          "[predicates][exact][degenerate]") {
  const std::uint64_t seed = seed_for(0xb15e3d);
  INFO("seed " << seed);
  Rng rng(seed);
  for (const Family fam : kFamilies) {
    INFO("family " << name(fam));
    // (The mixed family costs the oracle numbers of thousands of bits: fewer of them.)
    const std::size_t n =
        scaled(fam == Family::random ? 20000 : (fam == Family::mixed ? 2000 : 8000));
    Tally edge, facet;
    for (std::size_t it = 0; it < n; ++it) {
      check_case(make_edge(fam, rng), oracle_edge, edge);
      check_case(make_facet(fam, rng), oracle_facet, facet);
    }
    INFO("edge: " << edge.perturbed << " perturbed (" << edge.deep << " beyond the first eps), "
                  << edge.throws << " throw, " << edge.undecided << " filter undecided of "
                  << edge.n);
    INFO("facet: " << facet.perturbed << " perturbed (" << facet.deep << " beyond the first eps), "
                   << facet.throws << " throw, " << facet.undecided << " filter undecided of "
                   << facet.n);
    CHECK(edge.failures == 0);
    CHECK(facet.failures == 0);
    CHECK(edge.zeros == 0);
    CHECK(facet.zeros == 0);
    if (fam == Family::random) {
      // The filter decides random input (almost) always.
      CHECK(edge.undecided * 1000 <= edge.n);
      CHECK(facet.undecided * 1000 <= facet.n);
    }
    if (fam == Family::grid) {
      // The families reach what they are meant to: exact ties decided by eps, violated
      // preconditions.
      CHECK(edge.perturbed > n / 10);
      CHECK(facet.perturbed > n / 10);
      CHECK(edge.throws > n / 50);
      CHECK(facet.throws > n / 50);
      // Ties at every level: the coefficient of the first eps vanishes too.
      CHECK(edge.deep > n / 100);
      CHECK(facet.deep > n / 100);
    }
    if (fam == Family::near) {
      // Both stages at work: the filter near its bound, the exact stage below it.
      CHECK(edge.undecided > n / 8);
      CHECK(facet.undecided > n / 8);
      CHECK(edge.undecided < n - n / 8);
      CHECK(facet.undecided < n - n / 8);
    }
  }
}

TEST_CASE("bisector_side_vertex3d and bisector_side_voronoi3d agree with the oracle",
          "[predicates][exact][degenerate]") {
  const std::uint64_t seed = seed_for(0xb15e3e);
  INFO("seed " << seed);
  Rng rng(seed);
  for (const Family fam : kFamilies) {
    INFO("family " << name(fam));
    const std::size_t n = scaled(fam == Family::mixed ? 1000 : 4000);
    std::size_t failures = 0, ties = 0, voronoi_ties = 0, voronoi_throws = 0;
    for (std::size_t it = 0; it < n; ++it) {
      // Vertex: a on the bisector of p_i, p_j half of the time (exactly for the grid).
      const auto idx = distinct_indices<2>(rng);
      P3 pi, pj, a;
      if (fam == Family::grid) {
        pi = grid_point(rng, 3), pj = grid_point(rng, 3), a = grid_point(rng, 3);
        if (coin(rng)) {
          const auto& shell = lattice_shell(rng);
          pi = shell_point(a, shell, rng), pj = shell_point(a, shell, rng);
        }
      } else if (fam == Family::mixed) {
        pi = mixed_point(rng), pj = mixed_point(rng), a = mixed_point(rng);
      } else {
        pi = random_point(rng), pj = random_point(rng);
        // a = midpoint + a vector orthogonal to p_j - p_i, up to rounding.
        const P3 d = sub(pj, pi), r = cross(d, random_point(rng));
        a = nudged(add(add(pi, d, 0.5), r, uniform(rng, -2, 2)), rng, 1);
        if (fam == Family::scaled) {
          const auto e = static_cast<int>(rand_int(rng, -1000, 1000));
          pi = scaled_point(pi, e), pj = scaled_point(pj, e), a = scaled_point(a, e);
        }
      }
      const Expected want = oracle_vertex(pi, pj, a, idx[0], idx[1]);
      ties += want.unperturbed == 0;
      const Got got = run_vertex(pi, pj, a, idx[0], idx[1]);
      // Antisymmetry: f_ji = -f_ij.
      const Got swapped = run_vertex(pj, pi, a, idx[1], idx[0]);
      if (got.threw || got.sign != want.sign || swapped.threw || swapped.sign != -want.sign) {
        ++failures;
        FAIL_CHECK("vertex pi " << str(pi) << " pj " << str(pj) << " a " << str(a) << " i "
                                << idx[0] << " j " << idx[1] << ": want " << want.sign << " got "
                                << got.sign << " swapped " << swapped.sign);
      }

      const VoronoiCase v = make_voronoi(fam, rng);
      const Expected vw = oracle_voronoi(v);
      voronoi_ties += !vw.throws && vw.unperturbed == 0;
      voronoi_throws += vw.throws;
      const Got vg = run(v);
      if (vg.threw != vw.throws || (!vw.throws && (vg.sign != vw.sign || vw.degree > 1))) {
        ++failures;
        FAIL_CHECK(describe(v) << ": want " << (vw.throws ? "throw" : std::to_string(vw.sign))
                               << " got " << (vg.threw ? "throw" : std::to_string(vg.sign)));
      }
    }
    INFO(ties << " vertex ties, " << voronoi_ties << " Voronoi ties, " << voronoi_throws
              << " coplanar");
    CHECK(failures == 0);
    if (fam == Family::grid) {
      CHECK(ties > n / 10);
      CHECK(voronoi_ties > n / 10);
    }
  }
}

TEST_CASE("3D scale sweep: inputs times 2^e, e in [-500, 500], give identical signs",
          "[predicates][exact][degenerate]") {
  const std::uint64_t seed = seed_for(0xb15e3f);
  INFO("seed " << seed);
  Rng rng(seed);
  std::size_t failures = 0, compared = 0;
  for (std::size_t it = 0; it < scaled(300); ++it) {
    const Family fam = it % 3 == 0 ? Family::near : (it % 3 == 1 ? Family::grid : Family::random);
    const EdgeCase e0 = make_edge(fam, rng);
    const FacetCase f0 = make_facet(fam, rng);
    const VoronoiCase v0 = make_voronoi(fam, rng);
    const Got ge = run(e0), gf = run(f0), gv = run(v0);
    const Got gx = run_vertex(e0.pi, e0.pj, e0.a, e0.i, e0.j);
    for (int ex = -500; ex <= 500; ex += 25 + static_cast<int>(rng() % 5)) {
      EdgeCase e = e0;
      for (P3* p : {&e.pi, &e.pk, &e.pj, &e.a, &e.b}) *p = scaled_point(*p, ex);
      FacetCase fc = f0;
      for (P3* p : {&fc.pi, &fc.pk, &fc.pl, &fc.pj, &fc.a, &fc.b, &fc.c}) *p = scaled_point(*p, ex);
      VoronoiCase v = v0;
      for (P3* p : {&v.pi, &v.pk, &v.pl, &v.pm, &v.pj}) *p = scaled_point(*p, ex);
      const Got se = run(e), sf = run(fc), sv = run(v);
      const Got sx = run_vertex(e.pi, e.pj, e.a, e.i, e.j);
      ++compared;
      if (!same(se, ge) || !same(sf, gf) || !same(sv, gv) || !same(sx, gx)) {
        ++failures;
        FAIL_CHECK("scale 2^" << ex << ": " << describe(e0) << " / " << describe(f0) << " / "
                              << describe(v0));
      }
    }
  }
  INFO(compared << " scaled inputs");
  CHECK(failures == 0);
}

TEST_CASE("3D geometric meaning: explicit crossings, facet points and Voronoi vertices",
          "[predicates][exact]") {
  const std::uint64_t seed = seed_for(0xb15e40);
  INFO("seed " << seed);
  Rng rng(seed);
  std::size_t failures = 0, checked = 0;
  for (std::size_t it = 0; it < scaled(3000); ++it) {
    const auto idx = distinct_indices<5>(rng, 1000);
    // Edge: q = a + t (b - a) on the bisector of p_i, p_k, for a segment crossing it.
    EdgeCase e{};
    e.i = idx[0], e.k = idx[1], e.j = idx[2];
    for (P3* p : {&e.pi, &e.pk, &e.pj}) *p = random_point(rng);
    for (;;) {
      e.a = random_point(rng), e.b = random_point(rng);
      if (sgn(sq_dist(e.a, e.pi) - sq_dist(e.a, e.pk)) *
              sgn(sq_dist(e.b, e.pi) - sq_dist(e.b, e.pk)) <
          0)
        break;
    }
    const Q fa = sq_dist(e.a, e.pi) - sq_dist(e.a, e.pk),
            fb = sq_dist(e.b, e.pi) - sq_dist(e.b, e.pk);
    const Q t = fa / (fa - fb);
    Q3 q;
    for (std::size_t c = 0; c < 3; ++c) q[c] = Q(e.a[c]) + t * (Q(e.b[c]) - Q(e.a[c]));
    const int want_edge = sgn(sq_dist(q, e.pi) - sq_dist(q, e.pj));

    // Facet: x = plane ∩ bisector(i, k) ∩ bisector(i, l).
    FacetCase fc{};
    fc.i = idx[0], fc.k = idx[1], fc.l = idx[3], fc.j = idx[2];
    for (P3* p : {&fc.pi, &fc.pk, &fc.pl, &fc.pj, &fc.a, &fc.b, &fc.c}) *p = random_point(rng);
    Q3 x;
    REQUIRE(facet_point(fc, x));
    // x is on both bisectors and in the plane (checks facet_point itself).
    CHECK(sq_dist(x, fc.pi) == sq_dist(x, fc.pk));
    CHECK(sq_dist(x, fc.pi) == sq_dist(x, fc.pl));
    const int want_facet = sgn(sq_dist(x, fc.pi) - sq_dist(x, fc.pj));

    // Voronoi vertex of i, k, l, m: the circumcentre.
    VoronoiCase v{};
    v.i = idx[0], v.k = idx[1], v.l = idx[3], v.m = idx[4], v.j = idx[2];
    for (P3* p : {&v.pi, &v.pk, &v.pl, &v.pm, &v.pj}) *p = random_point(rng);
    std::array<Q3, 3> m;
    std::array<Q, 3> r;
    const P3* sites[3] = {&v.pk, &v.pl, &v.pm};
    for (std::size_t s = 0; s < 3; ++s) {
      for (std::size_t c = 0; c < 3; ++c) m[s][c] = 2 * (Q((*sites[s])[c]) - Q(v.pi[c]));
      r[s] = lift(*sites[s]) - lift(v.pi);
    }
    Q3 o;
    REQUIRE(solve3(m, r, o));
    const int want_vor = sgn(sq_dist(o, v.pi) - sq_dist(o, v.pj));

    if (want_edge == 0 || want_facet == 0 || want_vor == 0) continue;  // (never, for random)
    ++checked;
    const Got ge = run(e), gf = run(fc), gv = run(v);
    if (ge.threw || ge.sign != want_edge || gf.threw || gf.sign != want_facet || gv.threw ||
        gv.sign != want_vor) {
      ++failures;
      FAIL_CHECK(describe(e) << " -> " << ge.sign << " want " << want_edge << "; " << describe(fc)
                             << " -> " << gf.sign << " want " << want_facet << "; " << describe(v)
                             << " -> " << gv.sign << " want " << want_vor);
    }
  }
  CHECK(checked > scaled(3000) / 2);
  CHECK(failures == 0);
}

TEST_CASE("symmetries of the 3D edge and facet predicates", "[predicates][exact][degenerate]") {
  const std::uint64_t seed = seed_for(0xb15e41);
  INFO("seed " << seed);
  Rng rng(seed);
  std::size_t failures = 0, facet_checks = 0;
  for (const Family fam : kFamilies) {
    INFO("family " << name(fam));
    for (std::size_t it = 0; it < scaled(fam == Family::mixed ? 200 : 1000); ++it) {
      const EdgeCase e = make_edge(fam, rng);
      const Got g = run(e);
      if (!g.threw) {
        // q depends on the segment and bisector(i, k) only; f_kj(q) = f_ij(q) there.
        EdgeCase ba = e;
        std::swap(ba.a, ba.b);
        EdgeCase ki = e;
        std::swap(ki.pi, ki.pk);
        std::swap(ki.i, ki.k);
        if (!same(run(ba), g) || !same(run(ki), g)) {
          ++failures;
          FAIL_CHECK("edge symmetry " << describe(e));
        }
      }
      const FacetCase fc = make_facet(fam, rng);
      const Got gf = run(fc);
      // Every order of (a, b, c); k <-> l; and i, k, l in any roles: x is the point of the
      // plane where pi_i = pi_k = pi_l, and f_ij(x) = f_kj(x) = f_lj(x) there. A violated
      // precondition (D == 0) is the same for all of them.
      static constexpr int kPerm[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1},
                                          {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};
      const P3 pts[3] = {fc.a, fc.b, fc.c};
      const P3 sites[3] = {fc.pi, fc.pk, fc.pl};
      const std::uint32_t ids[3] = {fc.i, fc.k, fc.l};
      bool ok = true;
      for (const auto& p : kPerm) {
        for (const auto& s : kPerm) {
          FacetCase o = fc;
          o.a = pts[p[0]], o.b = pts[p[1]], o.c = pts[p[2]];
          o.pi = sites[s[0]], o.pk = sites[s[1]], o.pl = sites[s[2]];
          o.i = ids[s[0]], o.k = ids[s[1]], o.l = ids[s[2]];
          ok = ok && same(run(o), gf);
          ++facet_checks;
        }
      }
      if (!ok) {
        ++failures;
        FAIL_CHECK("facet symmetry " << describe(fc) << ": " << (gf.threw ? "throw" : "")
                                     << gf.sign);
      }
    }
  }
  INFO(facet_checks << " facet permutations");
  CHECK(failures == 0);
}

TEST_CASE("facet and edge predicates agree where the facet point lies on an edge",
          "[predicates][exact][degenerate]") {
  // Sites i, k, l on a lattice sphere around a grid point x, a segment [a, b] through x
  // and a triangle (a, b, c): the crossing of [a, b] with bisector(i, k) and the facet
  // point of bisectors (i, k), (i, l) are both x, so where f_ij(x) != 0 unperturbed the two
  // predicates return the same sign (the perturbations differ: they move different
  // points).
  const std::uint64_t seed = seed_for(0xb15e42);
  INFO("seed " << seed);
  Rng rng(seed);
  std::size_t failures = 0, compared = 0;
  for (std::size_t it = 0; it < scaled(3000); ++it) {
    const auto idx = distinct_indices<4>(rng);
    const P3 x = grid_point(rng, 2);
    const auto& shell = lattice_shell(rng);
    P3 pi = shell_point(x, shell, rng), pk = shell_point(x, shell, rng);
    P3 pl = shell_point(x, shell, rng);
    const P3 pj = grid_point(rng, 4);
    const P3 d = grid_point(rng, 2);
    const P3 a = add(x, d), b = sub(x, d), c = add(x, grid_point(rng, 2));
    const EdgeCase e{pi, pk, pj, a, b, idx[0], idx[1], idx[3]};
    const FacetCase fc{pi, pk, pl, pj, a, b, c, idx[0], idx[1], idx[2], idx[3]};
    const Expected we = oracle_edge(e), wf = oracle_facet(fc);
    if (we.throws || wf.throws || we.unperturbed == 0) continue;
    ++compared;
    const Got ge = run(e), gf = run(fc);
    if (ge.sign != we.sign || gf.sign != wf.sign || ge.sign != gf.sign) {
      ++failures;
      FAIL_CHECK(describe(e) << " / " << describe(fc) << ": edge " << ge.sign << " facet "
                             << gf.sign);
    }
  }
  INFO(compared << " compared");
  CHECK(compared > scaled(3000) / 10);
  CHECK(failures == 0);
}

TEST_CASE("every Voronoi vertex of a Delaunay3 tet is closer to its sites",
          "[predicates][exact][degenerate]") {
  const std::uint64_t seed = seed_for(0xb15e43);
  INFO("seed " << seed);
  Rng rng(seed);
  // Random points, then an integer grid (every cube's 8 corners cospherical: all ties go to
  // the perturbation, which must be the one Delaunay3 used through insphere_sos), then the
  // grid with its points shuffled (other indices, so another perturbed triangulation).
  for (int kind = 0; kind < 3; ++kind) {
    INFO("kind " << kind);
    std::vector<double> xyz;
    if (kind == 0) {
      for (int p = 0; p < 3 * 120; ++p) xyz.push_back(uniform(rng, 0, 1));
    } else {
      std::vector<P3> pts;
      for (int x = 0; x < 5; ++x)
        for (int y = 0; y < 5; ++y)
          for (int z = 0; z < 5; ++z)
            pts.push_back({static_cast<double>(x), static_cast<double>(y), static_cast<double>(z)});
      if (kind == 2) shuffle(pts, rng);
      for (const P3& p : pts) xyz.insert(xyz.end(), p.begin(), p.end());
    }
    const auto n = static_cast<std::uint32_t>(xyz.size() / 3);
    const Delaunay3 dt(xyz.data(), n);
    REQUIRE(dt.nb_finite_tets() > 0);
    REQUIRE(dt.nb_unique_points() == n);
    std::size_t failures = 0, calls = 0, oracle_checks = 0, ties = 0;
    // The 12 even permutations of the tet's vertices (the odd ones flip orient3d and
    // insphere together; a sample of them below).
    static constexpr int kPerm[14][4] = {{0, 1, 2, 3}, {0, 2, 3, 1}, {0, 3, 1, 2}, {1, 0, 3, 2},
                                         {1, 2, 0, 3}, {1, 3, 2, 0}, {2, 0, 1, 3}, {2, 1, 3, 0},
                                         {2, 3, 0, 1}, {3, 0, 2, 1}, {3, 1, 0, 2}, {3, 2, 1, 0},
                                         {1, 0, 2, 3}, {0, 1, 3, 2}};
    const auto pt = [&](std::uint32_t v) { return &xyz[3 * static_cast<std::size_t>(v)]; };
    for (std::uint32_t t = 0; t < dt.nb_tet_slots(); ++t) {
      if (dt.is_free(t) || dt.is_infinite(t)) continue;
      const std::uint32_t v[4] = {dt.tet_vertex(t, 0), dt.tet_vertex(t, 1), dt.tet_vertex(t, 2),
                                  dt.tet_vertex(t, 3)};
      for (std::uint32_t j = 0; j < n; ++j) {
        if (j == v[0] || j == v[1] || j == v[2] || j == v[3]) continue;
        for (const auto& p : kPerm) {
          const std::uint32_t i = v[p[0]], k = v[p[1]], l = v[p[2]], m = v[p[3]];
          const Sign s = bisector_side_voronoi3d(pt(i), pt(k), pt(l), pt(m), pt(j), i, k, l, m, j);
          ++calls;
          if (s != Sign::negative) {
            ++failures;
            if (failures <= 10)
              FAIL_CHECK("tet " << i << " " << k << " " << l << " " << m << ", site " << j << ": "
                                << to_int(s));
          }
        }
        if (kind > 0 && (t + j) % 5 == 0) {
          P3 q[5];
          const std::uint32_t w[5] = {v[0], v[1], v[2], v[3], j};
          for (int r = 0; r < 5; ++r) std::copy(pt(w[r]), pt(w[r]) + 3, q[r].begin());
          const Expected want =
              oracle_voronoi({q[0], q[1], q[2], q[3], q[4], w[0], w[1], w[2], w[3], w[4]});
          ++oracle_checks;
          ties += want.unperturbed == 0;
          if (want.throws || want.sign != -1) ++failures;
        }
      }
    }
    INFO(calls << " calls, " << oracle_checks << " oracle checks, " << ties << " ties");
    CHECK(failures == 0);
    if (kind > 0) CHECK(ties > 0);
  }
}

TEST_CASE("3D bisector predicates: violated preconditions and non-finite input throw",
          "[predicates]") {
  const P3 p0 = {0, 0, 0}, p1 = {2, 0, 0}, p2 = {0, 2, 0}, p3 = {1, 1, 3}, p4 = {0, 0, 2};
  const P3 a = {-1, 0, 0}, b = {3, 0, 0}, c = {0, 5, 1};
  const double inf = std::numeric_limits<double>::infinity();
  const P3 bad = {0, inf, 0}, nan = {0, 0, std::nan("")}, ninf = {-inf, 0, 0};
  // Vertex.
  CHECK_THROWS_AS(bisector_side_vertex3d(p0.data(), p1.data(), a.data(), 3, 3), Error);
  for (const P3* x : {&bad, &nan, &ninf}) {
    CHECK_THROWS_AS(bisector_side_vertex3d(p0.data(), p1.data(), x->data(), 3, 4), Error);
    CHECK_THROWS_AS(bisector_side_vertex3d(x->data(), p1.data(), a.data(), 3, 4), Error);
  }
  // Edge: repeated indices; a segment parallel to the bisector x = 1, a degenerate one,
  // coincident sites i, k.
  const auto edge = [](const P3& pi, const P3& pk, const P3& pj, const P3& ea, const P3& eb,
                       std::uint32_t i, std::uint32_t k, std::uint32_t j) {
    return bisector_side_edge3d(pi.data(), pk.data(), pj.data(), ea.data(), eb.data(), i, k, j);
  };
  CHECK_THROWS_AS(edge(p0, p1, p2, a, b, 0, 1, 0), Error);
  CHECK_THROWS_AS(edge(p0, p1, p2, a, b, 1, 1, 2), Error);
  CHECK_THROWS_AS(edge(p0, p1, p2, a, b, 0, 2, 2), Error);
  CHECK_THROWS_AS(edge(p0, p1, p2, P3{0, -1, 4}, P3{0, 5, -2}, 0, 1, 2), Error);
  CHECK_THROWS_AS(edge(p0, p1, p2, a, a, 0, 1, 2), Error);
  CHECK_THROWS_AS(edge(p0, p0, p2, a, b, 0, 1, 2), Error);
  CHECK_NOTHROW(edge(p0, p1, p2, a, b, 0, 1, 2));
  for (const P3* x : {&bad, &nan, &ninf}) {
    CHECK_THROWS_AS(edge(*x, p1, p2, a, b, 0, 1, 2), Error);
    CHECK_THROWS_AS(edge(p0, *x, p2, a, b, 0, 1, 2), Error);
    CHECK_THROWS_AS(edge(p0, p1, *x, a, b, 0, 1, 2), Error);
    CHECK_THROWS_AS(edge(p0, p1, p2, *x, b, 0, 1, 2), Error);
    CHECK_THROWS_AS(edge(p0, p1, p2, a, *x, 0, 1, 2), Error);
  }
  // Facet.
  const auto facet = [](const P3& pi, const P3& pk, const P3& pl, const P3& pj, const P3& fa,
                        const P3& fb, const P3& fc, std::uint32_t i, std::uint32_t k,
                        std::uint32_t l, std::uint32_t j) {
    return bisector_side_facet3d(pi.data(), pk.data(), pl.data(), pj.data(), fa.data(), fb.data(),
                                 fc.data(), i, k, l, j);
  };
  CHECK_NOTHROW(facet(p0, p1, p2, p3, a, b, c, 0, 1, 2, 3));
  CHECK_THROWS_AS(facet(p0, p1, p2, p3, a, b, c, 0, 1, 2, 2), Error);
  CHECK_THROWS_AS(facet(p0, p1, p2, p3, a, b, c, 0, 1, 0, 3), Error);
  CHECK_THROWS_AS(facet(p0, p1, p2, p3, a, b, c, 1, 1, 2, 3), Error);
  // D == 0: a degenerate triangle (collinear, or two equal vertices), collinear sites i, k,
  // l (parallel bisectors), coincident sites i, k, and a plane parallel to the Voronoi edge
  // (1, 1, t) of sites i, k, l: y = 0, through a, b and (0, 0, 7).
  const P3 mid = {1, 0, 0}, far_x = {4, 0, 0};
  CHECK_THROWS_AS(facet(p0, p1, p2, p3, a, b, mid, 0, 1, 2, 3), Error);
  CHECK_THROWS_AS(facet(p0, p1, p2, p3, a, a, c, 0, 1, 2, 3), Error);
  CHECK_THROWS_AS(facet(p0, p1, far_x, p3, a, b, c, 0, 1, 2, 3), Error);
  CHECK_THROWS_AS(facet(p0, p0, p2, p3, a, b, c, 0, 1, 2, 3), Error);
  CHECK_THROWS_AS(facet(p0, p1, p2, p3, a, b, P3{0, 0, 7}, 0, 1, 2, 3), Error);
  for (const P3* x : {&bad, &nan, &ninf}) {
    CHECK_THROWS_AS(facet(*x, p1, p2, p3, a, b, c, 0, 1, 2, 3), Error);
    CHECK_THROWS_AS(facet(p0, *x, p2, p3, a, b, c, 0, 1, 2, 3), Error);
    CHECK_THROWS_AS(facet(p0, p1, *x, p3, a, b, c, 0, 1, 2, 3), Error);
    CHECK_THROWS_AS(facet(p0, p1, p2, *x, a, b, c, 0, 1, 2, 3), Error);
    CHECK_THROWS_AS(facet(p0, p1, p2, p3, *x, b, c, 0, 1, 2, 3), Error);
    CHECK_THROWS_AS(facet(p0, p1, p2, p3, a, *x, c, 0, 1, 2, 3), Error);
    CHECK_THROWS_AS(facet(p0, p1, p2, p3, a, b, *x, 0, 1, 2, 3), Error);
  }
  // Voronoi: coplanar sites, repeated indices, non-finite input.
  const auto vor = [](const P3& pi, const P3& pk, const P3& pl, const P3& pm, const P3& pj,
                      std::uint32_t i, std::uint32_t k, std::uint32_t l, std::uint32_t m,
                      std::uint32_t j) {
    return bisector_side_voronoi3d(pi.data(), pk.data(), pl.data(), pm.data(), pj.data(), i, k, l,
                                   m, j);
  };
  CHECK_NOTHROW(vor(p0, p1, p2, p4, p3, 0, 1, 2, 3, 4));
  CHECK_THROWS_AS(vor(p0, p1, p2, P3{5, 5, 0}, p3, 0, 1, 2, 3, 4), Error);
  CHECK_THROWS_AS(vor(p0, p1, p2, p4, p3, 0, 1, 2, 3, 1), Error);
  CHECK_THROWS_AS(vor(p0, p1, p2, p4, p3, 0, 1, 2, 2, 4), Error);
  for (const P3* x : {&bad, &nan, &ninf}) {
    CHECK_THROWS_AS(vor(*x, p1, p2, p4, p3, 0, 1, 2, 3, 4), Error);
    CHECK_THROWS_AS(vor(p0, p1, p2, p4, *x, 0, 1, 2, 3, 4), Error);
  }
  // Finite coordinates whose differences overflow are valid input: decided exactly.
  const P3 huge = {0x1p1023, 0, 0}, nhuge = {-0x1p1023, 1, 0};
  CHECK_NOTHROW(bisector_side_vertex3d(huge.data(), nhuge.data(), p0.data(), 0, 1));
  CHECK_NOTHROW(facet(huge, nhuge, p2, p3, a, b, c, 0, 1, 2, 3));
}

// voronoi_edge_direction3d: sign(((p_k - p_i) x (p_l - p_i)) . ((b - a) x (c - a))), the
// oracle's cross and dot products in rationals; it is the sign of the facet predicate's
// D = det[1; F_ik; F_il] (rows of values at a, b, c), which the oracle computes too.
namespace {

int oracle_direction(const FacetCase& c) {
  Q3 u, v, w1, w2;
  for (std::size_t t = 0; t < 3; ++t) {
    u[t] = Q(c.pk[t]) - Q(c.pi[t]);
    v[t] = Q(c.pl[t]) - Q(c.pi[t]);
    w1[t] = Q(c.b[t]) - Q(c.a[t]);
    w2[t] = Q(c.c[t]) - Q(c.a[t]);
  }
  const auto cross = [](const Q3& x, const Q3& y) {
    return Q3{x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0]};
  };
  const Q3 n = cross(u, v), m = cross(w1, w2);
  return sgn(n[0] * m[0] + n[1] * m[1] + n[2] * m[2]);
}

// sign(D) of the facet predicate's contract, from the values F_ix at a, b, c.
int oracle_d(const FacetCase& c) {
  const auto row = [&](const P3& px) {
    return std::array<Q, 3>{sq_dist(c.a, c.pi) - sq_dist(c.a, px),
                            sq_dist(c.b, c.pi) - sq_dist(c.b, px),
                            sq_dist(c.c, c.pi) - sq_dist(c.c, px)};
  };
  const std::array<Q, 3> one = {Q(1), Q(1), Q(1)};
  return sgn(det3(one, row(c.pk), row(c.pl)));
}

Got run_direction(const FacetCase& c) {
  return call([&] {
    return voronoi_edge_direction3d(c.pi.data(), c.pk.data(), c.pl.data(), c.a.data(), c.b.data(),
                                    c.c.data());
  });
}

}  // namespace

TEST_CASE("voronoi_edge_direction3d agrees with the rational oracle on every family",
          "[predicates][exact][degenerate]") {
  const std::uint64_t seed = seed_for(0xb15e50);
  INFO("seed " << seed);
  Rng rng(seed);
  for (const Family fam : kFamilies) {
    INFO("family " << name(fam));
    const std::size_t n = scaled(fam == Family::mixed ? 2000 : 8000);
    std::size_t failures = 0, zeros = 0, undecided = 0;
    for (std::size_t it = 0; it < n; ++it) {
      FacetCase c = make_facet(fam, rng);
      if (fam == Family::near) {
        // The plane within rounding of parallel to the Voronoi edge: c moved off the plane
        // through a, b spanned by the edge direction, by a few ulps.
        const P3 dir = cross(sub(c.pk, c.pi), sub(c.pl, c.pi));
        c.c = nudged(add(c.a, dir, uniform(rng, -1, 1)), rng, 2);
      }
      const int want = oracle_direction(c);
      zeros += want == 0;
      const Got got = run_direction(c);
      const int d = oracle_d(c);
      undecided += detail::voronoi_edge_direction3d_filter(c.pi.data(), c.pk.data(), c.pl.data(),
                                                           c.a.data(), c.b.data(), c.c.data()) == 0;
      // Swapping k, l or two triangle vertices flips it; (i, k, l) rotated keeps it.
      FacetCase kl = c, ab = c, rot = c;
      std::swap(kl.pk, kl.pl);
      std::swap(ab.a, ab.b);
      rot.pi = c.pk, rot.pk = c.pl, rot.pl = c.pi;
      if (got.threw || got.sign != want || d != want || run_direction(kl).sign != -want ||
          run_direction(ab).sign != -want || run_direction(rot).sign != want) {
        ++failures;
        FAIL_CHECK(describe(c) << ": want " << want << " (D " << d << ") got "
                               << (got.threw ? "throw" : std::to_string(got.sign)));
      }
    }
    INFO(zeros << " zero, " << undecided << " filter undecided of " << n);
    CHECK(failures == 0);
    if (fam == Family::random) CHECK(undecided * 1000 <= n);
    if (fam == Family::grid) CHECK(zeros > n / 50);
    if (fam == Family::near) CHECK(undecided > n / 8);
  }
  // Scale sweep: the sign is that of a homogeneous polynomial.
  for (std::size_t it = 0; it < scaled(200); ++it) {
    const FacetCase c0 = make_facet(it % 2 ? Family::grid : Family::near, rng);
    const Got g0 = run_direction(c0);
    for (int ex = -500; ex <= 500; ex += 50) {
      FacetCase c = c0;
      for (P3* p : {&c.pi, &c.pk, &c.pl, &c.a, &c.b, &c.c}) *p = scaled_point(*p, ex);
      CHECK(same(run_direction(c), g0));
    }
  }
  // Non-finite input throws; finite input whose differences overflow is decided exactly.
  const P3 o = {0, 0, 0}, x = {1, 0, 0}, y = {0, 1, 0}, z = {0, 0, 1};
  const double inf = std::numeric_limits<double>::infinity();
  CHECK(voronoi_edge_direction3d(o.data(), x.data(), y.data(), o.data(), x.data(), y.data()) ==
        Sign::positive);
  CHECK(voronoi_edge_direction3d(o.data(), x.data(), y.data(), o.data(), x.data(), z.data()) ==
        Sign::zero);
  const P3 bad = {0, inf, 0}, nan = {std::nan(""), 0, 0};
  for (const P3* b : {&bad, &nan}) {
    CHECK_THROWS_AS(
        voronoi_edge_direction3d(b->data(), x.data(), y.data(), o.data(), x.data(), z.data()),
        Error);
    CHECK_THROWS_AS(
        voronoi_edge_direction3d(o.data(), x.data(), y.data(), o.data(), b->data(), z.data()),
        Error);
  }
  const P3 huge = {0x1p1023, 0, 0}, nhuge = {-0x1p1023, 1, 0};
  CHECK(voronoi_edge_direction3d(huge.data(), nhuge.data(), y.data(), o.data(), x.data(),
                                 y.data()) == Sign::negative);
}
