// Shared helpers of the predicate tests: an exact rational oracle (GMP), seeded random
// generators, ulp nudging and the input families of tests/predicates/*.cpp.
//
// The oracle evaluates the defining determinant of each predicate, rows = arguments in
// order, row = (p, 1) for orient2d/orient3d and (p, |p|^2, 1) for incircle/insphere
// (predicates.h), exactly. Every finite double is m * 2^e with an integer m, so multiplying
// all coordinates of one call by 2^-emin turns them into integers; each determinant is
// homogeneous with a positive factor under that scaling (s^d * s^2 for the lifted ones), so
// its sign is unchanged and the computation runs on mpz integers (fraction-free Bareiss
// elimination) instead of mpq. test_predicates.cpp cross-checks it against a plain mpq
// permutation expansion.
//
// Counts of random tests are multiplied by VOROCLIP_TEST_SCALE (default 1; the sanitizer
// CI run uses 0.1). Seeds are fixed; VOROCLIP_TEST_SEED, when set, is xor-ed into every
// seed to explore other inputs. Each random test reports its seed with INFO.
#pragma once

#include <gmpxx.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "voroclip/predicates.h"

namespace voroclip::test {

// ---------------------------------------------------------------------------------------
// Scale and seeds.

inline double test_scale() {
  static const double scale = [] {
    const char* s = std::getenv("VOROCLIP_TEST_SCALE");
    if (s == nullptr || *s == '\0') return 1.0;
    const double v = std::strtod(s, nullptr);
    return v > 0 ? v : 1.0;
  }();
  return scale;
}

// n * VOROCLIP_TEST_SCALE, at least 1.
inline std::size_t scaled(std::size_t n) {
  const double v = std::round(static_cast<double>(n) * test_scale());
  return v < 1 ? std::size_t{1} : static_cast<std::size_t>(v);
}

inline std::uint64_t seed_for(std::uint64_t base) {
  const char* s = std::getenv("VOROCLIP_TEST_SEED");
  if (s == nullptr || *s == '\0') return base;
  return base ^ std::strtoull(s, nullptr, 0);
}

using Rng = std::mt19937_64;

// Uniform in [0, 1) with 53 random bits (portable, unlike std::uniform_real_distribution).
inline double u01(Rng& rng) { return static_cast<double>(rng() >> 11) * 0x1p-53; }

inline double uniform(Rng& rng, double lo, double hi) { return lo + (hi - lo) * u01(rng); }

// Uniform integer in [lo, hi].
inline long long rand_int(Rng& rng, long long lo, long long hi) {
  const auto span = static_cast<std::uint64_t>(hi - lo) + 1;
  return lo + static_cast<long long>(rng() % span);
}

inline bool coin(Rng& rng) { return (rng() & 1) != 0; }

// A random double with a random sign, a random 52-bit fraction and a binary exponent
// uniform in [emin, emax] (values below 2^-1022 become subnormals, rounded).
inline double random_wide(Rng& rng, int emin, int emax) {
  const double mant = 1.0 + static_cast<double>(rng() >> 12) * 0x1p-52;
  const auto e = static_cast<int>(rand_int(rng, emin, emax));
  const double v = std::ldexp(mant, e);
  return coin(rng) ? -v : v;
}

// x moved by k ulps (k > 0 toward +inf, k < 0 toward -inf).
inline double nudge(double x, int k) {
  for (; k > 0; --k) x = std::nextafter(x, HUGE_VAL);
  for (; k < 0; ++k) x = std::nextafter(x, -HUGE_VAL);
  return x;
}

template <class T>
void shuffle(std::vector<T>& v, Rng& rng) {
  for (std::size_t i = v.size(); i > 1; --i) {
    const auto j = static_cast<std::size_t>(rng() % i);
    std::swap(v[i - 1], v[j]);
  }
}

// ---------------------------------------------------------------------------------------
// Formatting (hex floats reproduce inputs bit for bit).

inline std::string hex(double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%a", x);
  return buf;
}

inline int to_int(Sign s) { return static_cast<int>(s); }

// ---------------------------------------------------------------------------------------
// The four predicates, handled generically by the tests.

enum class Pred { orient2d, incircle, orient3d, insphere };
inline constexpr std::array<Pred, 4> kAllPreds = {Pred::orient2d, Pred::incircle, Pred::orient3d,
                                                  Pred::insphere};

struct PredInfo {
  const char* name;
  int k;  // number of points
  int d;  // dimension
  bool lifted;
};

inline constexpr PredInfo info(Pred p) {
  switch (p) {
    case Pred::orient2d:
      return {"orient2d", 3, 2, false};
    case Pred::incircle:
      return {"incircle", 4, 2, true};
    case Pred::orient3d:
      return {"orient3d", 4, 3, false};
    case Pred::insphere:
      return {"insphere", 5, 3, true};
  }
  return {"?", 0, 0, false};
}

using Pt = std::array<double, 3>;  // 2D predicates use the first two coordinates

struct Input {
  std::array<Pt, 5> p{};
};

using Indices = std::array<std::uint32_t, 5>;

inline std::string describe(Pred pred, const Input& in) {
  const PredInfo pi = info(pred);
  std::ostringstream os;
  os << pi.name << "(";
  for (int i = 0; i < pi.k; ++i) {
    os << (i ? ", " : "") << "{";
    for (int j = 0; j < pi.d; ++j)
      os << (j ? ", " : "") << hex(in.p[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)]);
    os << "}";
  }
  os << ")";
  return os.str();
}

inline std::string describe(Pred pred, const Input& in, const Indices& idx) {
  std::ostringstream os;
  os << describe(pred, in) << " indices {";
  for (int i = 0; i < info(pred).k; ++i) os << (i ? ", " : "") << idx[static_cast<std::size_t>(i)];
  os << "}";
  return os.str();
}

inline Sign eval(Pred pred, const Input& in) {
  const auto& p = in.p;
  switch (pred) {
    case Pred::orient2d:
      return orient2d(p[0].data(), p[1].data(), p[2].data());
    case Pred::incircle:
      return incircle(p[0].data(), p[1].data(), p[2].data(), p[3].data());
    case Pred::orient3d:
      return orient3d(p[0].data(), p[1].data(), p[2].data(), p[3].data());
    case Pred::insphere:
      return insphere(p[0].data(), p[1].data(), p[2].data(), p[3].data(), p[4].data());
  }
  return Sign::zero;
}

inline Sign eval_fast(Pred pred, const Input& in) {
  const auto& p = in.p;
  switch (pred) {
    case Pred::orient2d:
      return orient2d_fast(p[0].data(), p[1].data(), p[2].data());
    case Pred::incircle:
      return incircle_fast(p[0].data(), p[1].data(), p[2].data(), p[3].data());
    case Pred::orient3d:
      return orient3d_fast(p[0].data(), p[1].data(), p[2].data(), p[3].data());
    case Pred::insphere:
      return insphere_fast(p[0].data(), p[1].data(), p[2].data(), p[3].data(), p[4].data());
  }
  return Sign::zero;
}

// The exact stage alone, bypassing the filter.
inline Sign eval_exact_stage(Pred pred, const Input& in) {
  const auto& p = in.p;
  switch (pred) {
    case Pred::orient2d:
      return detail::orient2d_exact(p[0].data(), p[1].data(), p[2].data());
    case Pred::incircle:
      return detail::incircle_exact(p[0].data(), p[1].data(), p[2].data(), p[3].data());
    case Pred::orient3d:
      return detail::orient3d_exact(p[0].data(), p[1].data(), p[2].data(), p[3].data());
    case Pred::insphere:
      return detail::insphere_exact(p[0].data(), p[1].data(), p[2].data(), p[3].data(),
                                    p[4].data());
  }
  return Sign::zero;
}

// The filter's decision: +1/-1 when it decides, 0 when the exact stage runs.
inline int filter_decision(Pred pred, const Input& in) {
  const auto& p = in.p;
  switch (pred) {
    case Pred::orient2d:
      return detail::orient2d_filter(p[0].data(), p[1].data(), p[2].data());
    case Pred::incircle:
      return detail::incircle_filter(p[0].data(), p[1].data(), p[2].data(), p[3].data());
    case Pred::orient3d:
      return detail::orient3d_filter(p[0].data(), p[1].data(), p[2].data(), p[3].data());
    case Pred::insphere:
      return detail::insphere_filter(p[0].data(), p[1].data(), p[2].data(), p[3].data(),
                                     p[4].data());
  }
  return 0;
}

inline Sign eval_sos(Pred pred, const Input& in, const Indices& i) {
  const auto& p = in.p;
  switch (pred) {
    case Pred::orient2d:
      return orient2d_sos(p[0].data(), p[1].data(), p[2].data(), i[0], i[1], i[2]);
    case Pred::incircle:
      return incircle_sos(p[0].data(), p[1].data(), p[2].data(), p[3].data(), i[0], i[1], i[2],
                          i[3]);
    case Pred::orient3d:
      return orient3d_sos(p[0].data(), p[1].data(), p[2].data(), p[3].data(), i[0], i[1], i[2],
                          i[3]);
    case Pred::insphere:
      return insphere_sos(p[0].data(), p[1].data(), p[2].data(), p[3].data(), p[4].data(), i[0],
                          i[1], i[2], i[3], i[4]);
  }
  return Sign::zero;
}

// ---------------------------------------------------------------------------------------
// Exact arithmetic.

// All `count` doubles of x (finite) as integers with one common power-of-two scale:
// out[i] = x[i] * 2^-emin, emin the smallest exponent of an integer mantissa.
inline void scaled_integers(const double* x, int count, mpz_class* out) {
  int emin = INT_MAX;
  for (int i = 0; i < count; ++i) {
    if (x[i] == 0) continue;
    int e = 0;
    (void)std::frexp(x[i], &e);
    emin = std::min(emin, e - 53);
  }
  for (int i = 0; i < count; ++i) {
    if (x[i] == 0) {
      out[i] = 0;
      continue;
    }
    int e = 0;
    const double m = std::ldexp(std::frexp(x[i], &e), 53);  // an integer, |m| < 2^53
    mpz_set_d(out[i].get_mpz_t(), m);
    mpz_mul_2exp(out[i].get_mpz_t(), out[i].get_mpz_t(), static_cast<mp_bitcnt_t>(e - 53 - emin));
  }
}

// Sign of the determinant of the n x n row-major integer matrix m (destroyed), by
// fraction-free Bareiss elimination with row pivoting.
inline int bareiss_sign(mpz_class* m, int n) {
  int sign = 1;
  mpz_class prev = 1, t;
  const auto at = [&](int i, int j) -> mpz_class& {
    return m[static_cast<std::size_t>(i * n + j)];
  };
  for (int k = 0; k < n - 1; ++k) {
    if (sgn(at(k, k)) == 0) {
      int r = k + 1;
      while (r < n && sgn(at(r, k)) == 0) ++r;
      if (r == n) return 0;
      for (int j = k; j < n; ++j) std::swap(at(k, j), at(r, j));
      sign = -sign;
    }
    for (int i = k + 1; i < n; ++i) {
      for (int j = k + 1; j < n; ++j) {
        mpz_mul(t.get_mpz_t(), at(i, j).get_mpz_t(), at(k, k).get_mpz_t());
        mpz_submul(t.get_mpz_t(), at(i, k).get_mpz_t(), at(k, j).get_mpz_t());
        mpz_divexact(at(i, j).get_mpz_t(), t.get_mpz_t(), prev.get_mpz_t());
      }
    }
    prev = at(k, k);
  }
  return sign * sgn(at(n - 1, n - 1));
}

// The exact sign of the predicate's defining determinant.
inline int oracle_sign(Pred pred, const Input& in) {
  const PredInfo pi = info(pred);
  const int k = pi.k, d = pi.d;
  double x[15];
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < d; ++j)
      x[i * d + j] = in.p[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
  thread_local std::vector<mpz_class> ints(15), mat(25);
  scaled_integers(x, k * d, ints.data());
  const int n = k;  // d + 1 columns, d + 2 when lifted: always k
  for (int i = 0; i < k; ++i) {
    mpz_class* row = &mat[static_cast<std::size_t>(i * n)];
    mpz_class lift = 0;
    for (int j = 0; j < d; ++j) {
      const mpz_class& c = ints[static_cast<std::size_t>(i * d + j)];
      row[j] = c;
      if (pi.lifted) lift += c * c;
    }
    if (pi.lifted) row[d] = lift;
    row[n - 1] = 1;
  }
  return bareiss_sign(mat.data(), n);
}

// The same determinant with mpq entries straight from the doubles, by permutation
// expansion: slow and simple, used to validate oracle_sign.
inline mpq_class permutation_det(const std::vector<mpq_class>& m, int n) {
  std::vector<int> perm(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) perm[static_cast<std::size_t>(i)] = i;
  mpq_class det = 0;
  do {
    int inversions = 0;
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j)
        if (perm[static_cast<std::size_t>(i)] > perm[static_cast<std::size_t>(j)]) ++inversions;
    mpq_class term = 1;
    for (int i = 0; i < n; ++i)
      term *= m[static_cast<std::size_t>(i * n + perm[static_cast<std::size_t>(i)])];
    if (inversions % 2)
      det -= term;
    else
      det += term;
  } while (std::next_permutation(perm.begin(), perm.end()));
  return det;
}

inline int oracle_sign_mpq(Pred pred, const Input& in) {
  const PredInfo pi = info(pred);
  const int n = pi.k;
  std::vector<mpq_class> m(static_cast<std::size_t>(n * n));
  for (int i = 0; i < n; ++i) {
    mpq_class lift = 0;
    for (int j = 0; j < pi.d; ++j) {
      const mpq_class c(in.p[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)]);
      m[static_cast<std::size_t>(i * n + j)] = c;
      lift += c * c;
    }
    if (pi.lifted) m[static_cast<std::size_t>(i * n + pi.d)] = lift;
    m[static_cast<std::size_t>(i * n + n - 1)] = 1;
  }
  return sgn(permutation_det(m, n));
}

// ---------------------------------------------------------------------------------------
// Integer lattice points on circles and spheres (brute force).

inline std::vector<std::array<long long, 3>> lattice_sphere(long long r2, int dim) {
  std::vector<std::array<long long, 3>> out;
  long long r = 0;
  while ((r + 1) * (r + 1) <= r2) ++r;
  for (long long x = -r; x <= r; ++x)
    for (long long y = -r; y <= r; ++y) {
      if (dim == 2) {
        if (x * x + y * y == r2) out.push_back({x, y, 0});
        continue;
      }
      for (long long z = -r; z <= r; ++z)
        if (x * x + y * y + z * z == r2) out.push_back({x, y, z});
    }
  return out;
}

inline const std::vector<std::array<long long, 3>>& circle_points() {
  static const auto pts = lattice_sphere(4225, 2);  // 65^2 = 5^2 13^2: 36 points
  return pts;
}
inline const std::vector<std::array<long long, 3>>& sphere_points() {
  static const auto pts = lattice_sphere(441, 3);  // 21^2
  return pts;
}

// ---------------------------------------------------------------------------------------
// Input families. Each fills the first k points of the predicate.

inline void permute_points(Input& in, int k, Rng& rng) {
  for (int i = k; i > 1; --i) {
    const auto j = static_cast<std::size_t>(rng() % static_cast<std::uint64_t>(i));
    std::swap(in.p[static_cast<std::size_t>(i - 1)], in.p[j]);
  }
}

// (a) Uniform random coordinates in [lo, hi].
inline Input random_box(Pred pred, Rng& rng, double lo = -1, double hi = 1) {
  Input in;
  for (int i = 0; i < info(pred).k; ++i)
    for (int j = 0; j < info(pred).d; ++j)
      in.p[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = uniform(rng, lo, hi);
  return in;
}

// (a') Wide ranges: one random binary magnitude per call in [2^-60, 2^60], coordinates of
// random signs and exponents up to 12 below it, sometimes around an offset.
inline Input random_wide_range(Pred pred, Rng& rng) {
  const auto e = static_cast<int>(rand_int(rng, -60, 60));
  const double offset = coin(rng) ? 0.0 : random_wide(rng, e, e + 20);
  Input in;
  for (int i = 0; i < info(pred).k; ++i)
    for (int j = 0; j < info(pred).d; ++j)
      in.p[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] =
          offset + random_wide(rng, e - 12, e);
  return in;
}

// (b) Near-degenerate: points computed in floating point on a line/plane (orient) or a
// circle/sphere (incircle/insphere), so only approximately on it, the last one nudged by
// up to `ulps` ulps per coordinate; then the arguments are permuted.
inline Input near_degenerate(Pred pred, Rng& rng, int ulps = 4) {
  const PredInfo pi = info(pred);
  Input in;
  const double box = coin(rng) ? 1.0 : 1000.0;
  if (!pi.lifted) {
    for (int i = 0; i < pi.d; ++i)
      for (int j = 0; j < pi.d; ++j)
        in.p[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = uniform(rng, -box, box);
    const double s = uniform(rng, -1, 2), t = uniform(rng, -1, 2);
    Pt& q = in.p[static_cast<std::size_t>(pi.d)];
    for (std::size_t j = 0; j < static_cast<std::size_t>(pi.d); ++j) {
      const auto& a = in.p[0];
      const auto& b = in.p[1];
      q[j] = a[j] + s * (b[j] - a[j]);
      if (pi.d == 3) q[j] += t * (in.p[2][j] - a[j]);
    }
  } else {
    Pt c{};
    for (std::size_t j = 0; j < static_cast<std::size_t>(pi.d); ++j) c[j] = uniform(rng, -box, box);
    const double r = uniform(rng, 0.01, 1.0) * box;
    for (int i = 0; i < pi.k; ++i) {
      Pt u{};
      double norm = 0;
      do {
        norm = 0;
        for (std::size_t j = 0; j < static_cast<std::size_t>(pi.d); ++j) {
          u[j] = uniform(rng, -1, 1);
          norm += u[j] * u[j];
        }
      } while (norm < 0.01 || norm > 1);
      norm = std::sqrt(norm);
      for (std::size_t j = 0; j < static_cast<std::size_t>(pi.d); ++j)
        in.p[static_cast<std::size_t>(i)][j] = c[j] + r * (u[j] / norm);
    }
  }
  Pt& last = in.p[static_cast<std::size_t>(pi.k - 1)];
  for (std::size_t j = 0; j < static_cast<std::size_t>(pi.d); ++j)
    last[j] = nudge(last[j], static_cast<int>(rand_int(rng, -ulps, ulps)));
  permute_points(in, pi.k, rng);
  return in;
}

// Kettner et al.'s "classroom example" (Classroom examples of robustness problems in
// geometric computations, 2008): p = (0.5 + x u, 0.5 + y u) with u = 2^-53 (one ulp of
// 0.5), beside (12, 12) and (24, 24), all near the line y = x.
inline Input kettner_orient2d(int x, int y) {
  Input in;
  in.p[0] = {0.5 + static_cast<double>(x) * 0x1p-53, 0.5 + static_cast<double>(y) * 0x1p-53, 0};
  in.p[1] = {12, 12, 0};
  in.p[2] = {24, 24, 0};
  return in;
}

// Integer lattice configuration whose determinant is exactly zero: collinear/coplanar
// lattice points (orient), lattice points on a circle/sphere (incircle/insphere), or a
// duplicated point; with an integer offset. Coordinates stay below 2^12.
inline Input exactly_degenerate_ints(Pred pred, Rng& rng) {
  const PredInfo pi = info(pred);
  Input in;
  const auto kind = rng() % 8;
  std::array<long long, 3> off{};
  for (auto& o : off) o = rand_int(rng, -1000, 1000);
  if (kind == 0) {
    // A duplicated point among otherwise random lattice points.
    for (int i = 0; i < pi.k; ++i)
      for (std::size_t j = 0; j < 3; ++j)
        in.p[static_cast<std::size_t>(i)][j] = static_cast<double>(rand_int(rng, -30, 30));
    in.p[1] = in.p[0];
  } else if (kind == 1) {
    // All points identical.
    for (std::size_t j = 0; j < 3; ++j) in.p[0][j] = static_cast<double>(rand_int(rng, -30, 30));
    for (int i = 1; i < pi.k; ++i) in.p[static_cast<std::size_t>(i)] = in.p[0];
  } else if (!pi.lifted) {
    // a + s u (+ t v) with small integers: collinear (2D) / coplanar (3D), possibly collinear
    // in 3D as well when v is parallel to u or zero.
    std::array<long long, 3> u{}, v{};
    for (std::size_t j = 0; j < 3; ++j) {
      u[j] = rand_int(rng, -5, 5);
      v[j] = kind == 2 ? 0 : rand_int(rng, -5, 5);
    }
    for (int i = 0; i < pi.k; ++i) {
      const long long s = rand_int(rng, -20, 20), t = rand_int(rng, -20, 20);
      for (std::size_t j = 0; j < 3; ++j)
        in.p[static_cast<std::size_t>(i)][j] =
            static_cast<double>(off[j] + s * u[j] + (pi.d == 3 ? t * v[j] : 0));
    }
  } else {
    const auto& set = pi.d == 2 ? circle_points() : sphere_points();
    for (int i = 0; i < pi.k; ++i) {
      const auto& q = set[static_cast<std::size_t>(rng() % set.size())];
      for (std::size_t j = 0; j < static_cast<std::size_t>(pi.d); ++j)
        in.p[static_cast<std::size_t>(i)][j] = static_cast<double>(off[j] + q[j]);
    }
  }
  for (int i = 0; i < pi.k; ++i)
    for (int j = pi.d; j < 3; ++j)
      in.p[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = 0;
  permute_points(in, pi.k, rng);
  return in;
}

// (c) Exactly degenerate: the lattice configuration moved by a dyadic offset and scaled by
// a power of two (both exact), so its determinant is still exactly zero.
inline Input exactly_degenerate(Pred pred, Rng& rng) {
  Input in = exactly_degenerate_ints(pred, rng);
  const PredInfo pi = info(pred);
  std::array<double, 3> shift{};
  for (auto& s : shift) s = static_cast<double>(rand_int(rng, -(1 << 20), 1 << 20)) * 0x1p-10;
  const auto e = static_cast<int>(rand_int(rng, -30, 30));
  for (int i = 0; i < pi.k; ++i)
    for (std::size_t j = 0; j < static_cast<std::size_t>(pi.d); ++j) {
      double& x = in.p[static_cast<std::size_t>(i)][j];
      x = std::ldexp(x + shift[j], e);
    }
  return in;
}

// Every coordinate of the first k points multiplied by 2^e (exact when no overflow or
// underflow occurs; the callers keep it so).
inline Input scaled_by(Pred pred, Input in, int e) {
  for (int i = 0; i < info(pred).k; ++i)
    for (int j = 0; j < info(pred).d; ++j) {
      double& x = in.p[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
      x = std::ldexp(x, e);
    }
  return in;
}

// (e) One coordinate of any magnitude: tiny, subnormal, huge, extreme, zero, ordinary.
inline double random_mixed_coordinate(Rng& rng) {
  switch (rng() % 9) {
    case 0:
      return uniform(rng, -1, 1);
    case 1:
      return random_wide(rng, -1074, -1000);  // subnormal or tiny
    case 2:
      return random_wide(rng, -1022, -900);
    case 3:
      return random_wide(rng, 600, 1023);
    case 4:
      return 0.0;
    case 5:
      return static_cast<double>(rand_int(rng, -3, 3));
    case 6:
      return random_wide(rng, -1074, 1023);
    case 7: {
      static constexpr double extremes[] = {DBL_MAX, DBL_MIN,  0x1p-1074, 0x1p-1022 - 0x1p-1074,
                                            1.0,     0x1p+1023};
      const double v = extremes[rng() % 6];
      return coin(rng) ? -v : v;
    }
    default:
      return random_wide(rng, -20, 20);
  }
}

inline Input mixed_magnitudes(Pred pred, Rng& rng) {
  Input in;
  for (int i = 0; i < info(pred).k; ++i)
    for (int j = 0; j < info(pred).d; ++j)
      in.p[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = random_mixed_coordinate(rng);
  return in;
}

// (e') An exactly degenerate lattice configuration, moved so that one point is the origin,
// with one coordinate of that point replaced by a tiny (possibly subnormal) or huge value
// beside the others near 1..1000: the sign then hinges on that one coordinate.
inline Input degenerate_plus_extreme(Pred pred, Rng& rng) {
  const PredInfo pi = info(pred);
  Input in = exactly_degenerate_ints(pred, rng);
  const auto r = static_cast<std::size_t>(rng() % static_cast<std::uint64_t>(pi.k));
  const Pt origin = in.p[r];
  for (int i = 0; i < pi.k; ++i)
    for (std::size_t j = 0; j < static_cast<std::size_t>(pi.d); ++j)
      in.p[static_cast<std::size_t>(i)][j] -= origin[j];
  const auto j = static_cast<std::size_t>(rng() % static_cast<std::uint64_t>(pi.d));
  const auto kind = rng() % 4;
  in.p[r][j] = kind == 0   ? random_wide(rng, -1074, -1023)
               : kind == 1 ? random_wide(rng, -1022, -250)
               : kind == 2 ? random_wide(rng, 150, 1023)
                           : 1e-300 * (coin(rng) ? 1 : -1);
  return in;
}

}  // namespace voroclip::test
