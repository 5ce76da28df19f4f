// Tests of the symbolically perturbed predicates (*_sos in predicates.h).
//
// The oracle here is written from the definition alone. For a call with k points, sorted by
// index (rank r = 0..k-1, smallest index rank 0), dimension d and coordinate j = 0..d-1:
//   orient2d_sos, orient3d_sos:      pos(r, j) = d r + (d - 1 - j)
//   incircle_sos, insphere_sos:      pos(r, w) = r (the lift), pos(r, j) = k + d r + (d - 1 - j)
// The point of rank r gets x_{r,j} + eps^(2^pos(r,j)) and, lifted, w_r = |p_r|^2 +
// eps^(2^pos(r,w)). The predicate is the sign, as eps -> 0+, of the determinant of the
// perturbed matrix whose rows are the arguments in order: (p, 1) or (p, w, 1). The
// determinant is a polynomial in independent perturbation variables, multilinear, each
// variable in one matrix entry; its dominant monomial is the one with the smallest
// exponent sum of 2^pos, i.e. the smallest bitmask, among those with a non-zero
// coefficient. The oracle expands the determinant over all permutations with polynomial
// entries (constant + one variable) and exact integer coefficients (the constants are the
// coordinates scaled by a common power of two, which multiplies every coefficient by a
// positive factor: each coefficient is a minor of the constant matrix up to sign).
//
// The consistency tests build Delaunay triangulations (Bowyer-Watson, O(n^2)) of exactly
// degenerate point sets with incircle_sos/insphere_sos and check that they are valid,
// Delaunay for the perturbed points, and independent of the insertion order.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "exact_oracle.h"
#include "voroclip/core.h"
#include "voroclip/predicates.h"

using namespace voroclip;
using namespace voroclip::test;

namespace {

// ---------------------------------------------------------------------------------------
// The polynomial oracle.

struct Term {
  std::uint64_t mask;  // the monomial: product of the variables whose bit is set
  mpz_class coef;
};
using Poly = std::vector<Term>;

class SosOracle {
 public:
  SosOracle(Pred pred, const Input& in, const Indices& idx) : n_(info(pred).k) {
    const PredInfo pi = info(pred);
    const int k = pi.k, d = pi.d;
    int rank[5] = {};
    for (int i = 0; i < k; ++i)
      for (int j = 0; j < k; ++j)
        if (idx[static_cast<std::size_t>(j)] < idx[static_cast<std::size_t>(i)]) ++rank[i];
    double x[15];
    for (int i = 0; i < k; ++i)
      for (int j = 0; j < d; ++j)
        x[i * d + j] = in.p[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
    mpz_class ints[15];
    scaled_integers(x, k * d, ints);
    for (int i = 0; i < k; ++i) {
      mpz_class lift = 0;
      for (int j = 0; j < d; ++j) {
        const mpz_class& c = ints[i * d + j];
        const int pos = (pi.lifted ? k : 0) + d * rank[i] + (d - 1 - j);
        entry(i, j) = {std::uint64_t{1} << pos, c};
        lift += c * c;
      }
      if (pi.lifted) entry(i, d) = {std::uint64_t{1} << rank[i], lift};
      entry(i, n_ - 1) = {0, 1};
    }
  }

  // The sign of the dominant non-zero coefficient (0 only if the polynomial is zero).
  int sign() {
    acc_.clear();
    expand(0, 0u, 1, Poly{{0, 1}});
    std::sort(acc_.begin(), acc_.end(),
              [](const Term& a, const Term& b) { return a.mask < b.mask; });
    for (std::size_t i = 0; i < acc_.size();) {
      mpz_class sum = 0;
      std::size_t j = i;
      for (; j < acc_.size() && acc_[j].mask == acc_[i].mask; ++j) sum += acc_[j].coef;
      if (sgn(sum) != 0) {
        dominant_ = acc_[i].mask;
        return sgn(sum);
      }
      i = j;
    }
    return 0;
  }
  std::uint64_t dominant_mask() const { return dominant_; }

 private:
  Term& entry(int i, int c) { return m_[static_cast<std::size_t>(i * 5 + c)]; }

  // Rows row..n-1 of the permutation expansion; `used` holds the columns taken by the rows
  // above, `sign` the parity so far, `cur` the product of their entries.
  void expand(int row, unsigned used, int sign, const Poly& cur) {
    if (row == n_) {
      for (const Term& t : cur)
        acc_.push_back({t.mask, sign > 0 ? mpz_class(t.coef) : mpz_class(-t.coef)});
      return;
    }
    for (int c = 0; c < n_; ++c) {
      if (used & (1u << c)) continue;
      // Inversions: rows above that took a column to the right of c.
      const int s = (__builtin_popcount(used >> (c + 1)) & 1) ? -sign : sign;
      const Term& e = entry(row, c);
      Poly next;
      next.reserve(2 * cur.size());
      for (const Term& t : cur) {
        if (sgn(e.coef) != 0) next.push_back({t.mask, t.coef * e.coef});
        if (e.mask != 0) next.push_back({t.mask | e.mask, t.coef});
      }
      if (!next.empty()) expand(row + 1, used | (1u << c), s, next);
    }
  }

  int n_;
  std::array<Term, 25> m_{};
  Poly acc_;
  std::uint64_t dominant_ = 0;
};

int sos_oracle(Pred pred, const Input& in, const Indices& idx) {
  SosOracle o(pred, in, idx);
  return o.sign();
}

// ---------------------------------------------------------------------------------------
// Inputs.

// Distinct random indices: small, medium, near 2^32, anywhere.
Indices random_indices(Rng& rng, int k) {
  Indices idx{};
  for (int i = 0; i < k; ++i) {
    for (;;) {
      std::uint32_t v = 0;
      switch (rng() % 5) {
        case 0:
          v = static_cast<std::uint32_t>(rand_int(rng, 0, 10));
          break;
        case 1:
          v = static_cast<std::uint32_t>(rand_int(rng, 0, 1000));
          break;
        case 2:
          v = std::numeric_limits<std::uint32_t>::max() -
              static_cast<std::uint32_t>(rand_int(rng, 0, 10));
          break;
        case 3:
          v = static_cast<std::uint32_t>(rand_int(rng, 4000000000LL, 4000000010LL));
          break;
        default:
          v = static_cast<std::uint32_t>(rng() >> 32);
          break;
      }
      bool fresh = true;
      for (int j = 0; j < i; ++j) fresh = fresh && idx[static_cast<std::size_t>(j)] != v;
      if (fresh) {
        idx[static_cast<std::size_t>(i)] = v;
        break;
      }
    }
  }
  return idx;
}

// Coordinates from {0, 1} or {0, 1, 2}: duplicates, collinear, cocircular, coplanar and
// cospherical configurations everywhere.
Input tiny_lattice(Pred pred, Rng& rng) {
  const long long top = coin(rng) ? 1 : 2;
  Input in;
  for (int i = 0; i < info(pred).k; ++i)
    for (int j = 0; j < info(pred).d; ++j)
      in.p[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] =
          static_cast<double>(rand_int(rng, 0, top));
  return in;
}

enum class Family { random, near, degenerate, tiny, extreme };

Input make(Family f, Pred pred, Rng& rng) {
  switch (f) {
    case Family::extreme: {
      // Mixed magnitudes, or the tiny lattice scaled exactly into the subnormals or up to
      // 2^1022.
      if (coin(rng)) return mixed_magnitudes(pred, rng);
      static constexpr int exps[] = {-1074, -1073, -1000, -500, 500, 1000, 1021};
      return scaled_by(pred, tiny_lattice(pred, rng), exps[rng() % 7]);
    }
    case Family::random:
      return coin(rng) ? random_box(pred, rng) : random_wide_range(pred, rng);
    case Family::near:
      return near_degenerate(pred, rng, static_cast<int>(rng() % 3));
    case Family::degenerate:
      return exactly_degenerate(pred, rng);
    case Family::tiny:
      return tiny_lattice(pred, rng);
  }
  return {};
}

Sign sos_checked(Pred pred, const Input& in, const Indices& idx, std::size_t& failures) {
  try {
    return eval_sos(pred, in, idx);
  } catch (const std::exception& e) {
    ++failures;
    if (failures <= 10) FAIL_CHECK(describe(pred, in, idx) << " threw: " << e.what());
    return Sign::zero;
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------

TEST_CASE("sos oracle: hand-derived cases", "[predicates][sos]") {
  // Three identical points, indices 0 1 2: with y before x and rank 0 first, the variables
  // are y0 x0 y1 x1 y2 x2 = bits 1 2 4 8 16 32, and
  // det = x0 (y1 - y2) - y0 (x1 - x2) + x1 y2 - x2 y1, whose smallest monomial is
  // x0 y1 (mask 6), coefficient +1.
  Input in;
  in.p[0] = in.p[1] = in.p[2] = {3, 5, 0};
  SosOracle o(Pred::orient2d, in, {0, 1, 2, 0, 0});
  CHECK(o.sign() == 1);
  CHECK(o.dominant_mask() == 6);
  CHECK(orient2d_sos(in.p[0].data(), in.p[1].data(), in.p[2].data(), 0, 1, 2) == Sign::positive);
  CHECK(orient2d_sos(in.p[0].data(), in.p[1].data(), in.p[2].data(), 7, 8, 9) == Sign::positive);
  CHECK(orient2d_sos(in.p[0].data(), in.p[1].data(), in.p[2].data(), 1, 0, 2) == Sign::negative);
  // Non-degenerate: the constant term decides.
  in.p[1] = {4, 5, 0};
  in.p[2] = {3, 6, 0};
  SosOracle o2(Pred::orient2d, in, {5, 1, 3, 0, 0});
  CHECK(o2.sign() == 1);
  CHECK(o2.dominant_mask() == 0);
  // Collinear a=(0,0) b=(1,0) c=(2,0), indices 0 1 2. The y perturbation of a comes first
  // (bit 1); its coefficient is d det / d ay = -(bx - cx) = 1: a moved up by eps makes
  // a b c counter-clockwise.
  in.p[0] = {0, 0, 0};
  in.p[1] = {1, 0, 0};
  in.p[2] = {2, 0, 0};
  SosOracle o3(Pred::orient2d, in, {0, 1, 2, 0, 0});
  CHECK(o3.sign() == 1);
  CHECK(o3.dominant_mask() == 1);
  CHECK(orient2d_sos(in.p[0].data(), in.p[1].data(), in.p[2].data(), 0, 1, 2) == Sign::positive);
  // Reversed indices: c's y comes first, coefficient bx - ax = 1: c moved up, still ccw.
  CHECK(orient2d_sos(in.p[0].data(), in.p[1].data(), in.p[2].data(), 2, 1, 0) == Sign::positive);
  // Swapping two arguments with their indices negates.
  CHECK(orient2d_sos(in.p[1].data(), in.p[0].data(), in.p[2].data(), 1, 0, 2) == Sign::negative);
  // Four cocircular points: the lift of rank 0 comes first. With rank 0 at a (row 0), its
  // coefficient is the cofactor of entry (0, 2): +orient2d(b, c, d). Geometrically a's
  // lifted point rises, so d falls below the plane of a b c: inside, as a b c is ccw.
  in.p[0] = {1, 0, 0};
  in.p[1] = {0, 1, 0};
  in.p[2] = {-1, 0, 0};
  in.p[3] = {0, -1, 0};
  const int expected = to_int(orient2d(in.p[1].data(), in.p[2].data(), in.p[3].data()));
  CHECK(expected == 1);
  CHECK(sos_oracle(Pred::incircle, in, {0, 1, 2, 3, 0}) == expected);
  CHECK(to_int(incircle_sos(in.p[0].data(), in.p[1].data(), in.p[2].data(), in.p[3].data(), 0, 1, 2,
                            3)) == expected);
  // Rank 0 at d (row 3): the cofactor of entry (3, 2) is -orient2d(a, b, c): d rises
  // above the plane, outside.
  const int expected_d = -to_int(orient2d(in.p[0].data(), in.p[1].data(), in.p[2].data()));
  CHECK(expected_d == -1);
  CHECK(sos_oracle(Pred::incircle, in, {1, 2, 3, 0, 0}) == expected_d);
  CHECK(to_int(incircle_sos(in.p[0].data(), in.p[1].data(), in.p[2].data(), in.p[3].data(), 1, 2, 3,
                            0)) == expected_d);
}

TEST_CASE("sos equals the exact sign when it is non-zero, and is never zero",
          "[predicates][sos][exact][degenerate]") {
  // >= 10^5 calls per predicate: random, near-degenerate, exactly degenerate, tiny lattice.
  const std::size_t n = scaled(100000);
  for (Pred pred : kAllPreds) {
    const std::uint64_t seed = seed_for(3000 + static_cast<std::uint64_t>(pred));
    INFO(info(pred).name << "_sos, " << n << " inputs, seed " << seed);
    Rng rng(seed);
    std::size_t failures = 0, decided_by_perturbation = 0;
    for (std::size_t it = 0; it < n; ++it) {
      const auto r = it % 20;
      const Family f = r < 9    ? Family::random
                       : r < 14 ? Family::near
                       : r < 17 ? Family::degenerate
                       : r < 19 ? Family::tiny
                                : Family::extreme;
      const Input in = make(f, pred, rng);
      const Indices idx = random_indices(rng, info(pred).k);
      const Sign exact = eval(pred, in);
      const Sign s = sos_checked(pred, in, idx, failures);
      if (exact == Sign::zero) ++decided_by_perturbation;
      if (s == Sign::zero || (exact != Sign::zero && s != exact)) {
        ++failures;
        if (failures <= 10)
          FAIL_CHECK(describe(pred, in, idx)
                     << ": exact " << to_int(exact) << ", sos " << to_int(s));
      }
    }
    CHECK(failures == 0);
    CHECK(decided_by_perturbation * 10 >= n);  // the family does exercise the perturbation
  }
}

TEST_CASE("sos matches the polynomial oracle", "[predicates][sos][exact][degenerate]") {
  for (Pred pred : kAllPreds) {
    const std::size_t base = pred == Pred::insphere ? 1500 : pred == Pred::orient2d ? 6000 : 3000;
    for (Family f :
         {Family::random, Family::near, Family::degenerate, Family::tiny, Family::extreme}) {
      const std::size_t n = scaled(f == Family::degenerate || f == Family::tiny ? base : base / 4);
      const std::uint64_t seed =
          seed_for(3100 + 10 * static_cast<std::uint64_t>(pred) + static_cast<std::uint64_t>(f));
      INFO(info(pred).name << "_sos, family " << static_cast<int>(f) << ", " << n
                           << " inputs, seed " << seed);
      Rng rng(seed);
      std::size_t failures = 0, perturbed = 0;
      for (std::size_t it = 0; it < n; ++it) {
        const Input in = make(f, pred, rng);
        // Indices: random (often huge), or small and consecutive in a random order.
        Indices idx = random_indices(rng, info(pred).k);
        if (coin(rng)) {
          std::vector<std::uint32_t> v = {0, 1, 2, 3, 4};
          shuffle(v, rng);
          for (std::size_t i = 0; i < 5; ++i) idx[i] = v[i];
        }
        SosOracle o(pred, in, idx);
        const int expected = o.sign();
        if (o.dominant_mask() != 0) ++perturbed;
        const int got = to_int(sos_checked(pred, in, idx, failures));
        if (expected == 0 || got != expected) {
          ++failures;
          if (failures <= 10)
            FAIL_CHECK(describe(pred, in, idx) << ": oracle " << expected << " (monomial "
                                               << o.dominant_mask() << "), sos " << got);
        }
      }
      CHECK(failures == 0);
      // The degenerate families do exercise the perturbation.
      if (f == Family::degenerate) CHECK(perturbed == n);
      if (f == Family::tiny) CHECK(perturbed * 5 >= n);
    }
  }
}

TEST_CASE("sos: duplicates and identical points with every index order",
          "[predicates][sos][degenerate]") {
  // All points identical, or two / three of them equal, for every permutation of ranks.
  Rng rng(seed_for(3200));
  for (Pred pred : kAllPreds) {
    const int k = info(pred).k;
    INFO(info(pred).name);
    std::size_t failures = 0;
    for (int pattern = 0; pattern < 4; ++pattern) {
      Input in = tiny_lattice(pred, rng);
      if (pattern == 0)
        for (int i = 1; i < k; ++i) in.p[static_cast<std::size_t>(i)] = in.p[0];
      if (pattern >= 1) in.p[1] = in.p[0];
      if (pattern >= 2) in.p[2] = in.p[0];
      if (pattern == 3)
        in.p[static_cast<std::size_t>(k - 1)] = in.p[static_cast<std::size_t>(k - 2)];
      std::vector<std::uint32_t> ranks(static_cast<std::size_t>(k));
      for (int i = 0; i < k; ++i)
        ranks[static_cast<std::size_t>(i)] = static_cast<std::uint32_t>(i);
      do {
        Indices idx{};
        for (int i = 0; i < k; ++i)
          idx[static_cast<std::size_t>(i)] = 1000u * ranks[static_cast<std::size_t>(i)] + 17u;
        const int expected = sos_oracle(pred, in, idx);
        const int got = to_int(sos_checked(pred, in, idx, failures));
        if (expected == 0 || got != expected) {
          ++failures;
          if (failures <= 10)
            FAIL_CHECK(describe(pred, in, idx) << ": oracle " << expected << ", sos " << got);
        }
      } while (std::next_permutation(ranks.begin(), ranks.end()));
    }
    CHECK(failures == 0);
  }
}

TEST_CASE("regression: sos on subnormal inputs agrees with the exact sign",
          "[predicates][sos][exact][regression]") {
  // Found by the extreme family: with every coordinate subnormal the exact stage answered
  // zero, and the perturbation then decided, with the opposite of the true sign.
  const double t = 0x1p-1074;
  const double a[2] = {2 * t, 2 * t}, b[2] = {t, t}, c[2] = {2 * t, t};  // det = t^2 > 0
  CHECK(orient2d(a, b, c) == Sign::positive);
  CHECK(orient2d_sos(a, b, c, 3, 1, 0) == Sign::positive);
  CHECK(orient2d_sos(a, b, c, 0, 1, 2) == Sign::positive);
  const double o[3] = {0, 0, 0}, x[3] = {t, 0, 0}, y[3] = {0, t, 0}, z[3] = {0, 0, t};
  CHECK(orient3d_sos(x, o, y, z, 0, 1, 2, 3) == Sign::positive);
  const double far[3] = {4 * t, 4 * t, 0};
  CHECK(incircle_sos(o, x, y, far, 0, 1, 2, 3) == Sign::negative);
  CHECK(insphere_sos(x, o, y, z, far, 0, 1, 2, 3, 4) == Sign::negative);
}

TEST_CASE("sos: equal indices in one call throw voroclip::Error", "[predicates][sos]") {
  Rng rng(seed_for(3300));
  for (Pred pred : kAllPreds) {
    const int k = info(pred).k;
    const Input in = random_box(pred, rng);
    for (int a = 0; a < k; ++a)
      for (int b = a + 1; b < k; ++b) {
        Indices idx = {10, 20, 30, 40, 50};
        idx[static_cast<std::size_t>(b)] = idx[static_cast<std::size_t>(a)];
        INFO(describe(pred, in, idx));
        CHECK_THROWS_AS(eval_sos(pred, in, idx), voroclip::Error);
      }
    Indices same = {7, 7, 7, 7, 7};
    CHECK_THROWS_AS(eval_sos(pred, in, same), voroclip::Error);
    const Input zero{};
    CHECK_THROWS_AS(eval_sos(pred, zero, same), voroclip::Error);
  }
}

TEST_CASE("sos: NaN and infinite coordinates throw voroclip::Error", "[predicates][sos]") {
  const double specials[] = {std::numeric_limits<double>::quiet_NaN(),
                             std::numeric_limits<double>::infinity(),
                             -std::numeric_limits<double>::infinity()};
  Rng rng(seed_for(3400));
  for (Pred pred : kAllPreds) {
    const PredInfo pi = info(pred);
    for (int base = 0; base < 2; ++base) {
      const Input in0 = base == 0 ? random_box(pred, rng) : Input{};
      for (double s : specials)
        for (int i = 0; i < pi.k; ++i)
          for (int j = 0; j < pi.d; ++j) {
            Input in = in0;
            in.p[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = s;
            INFO(describe(pred, in));
            CHECK_THROWS_AS(eval_sos(pred, in, {0, 1, 2, 3, 4}), voroclip::Error);
          }
    }
  }
}

TEST_CASE("sos: swapping two arguments with their indices negates the result",
          "[predicates][sos][degenerate]") {
  for (Pred pred : kAllPreds) {
    const int k = info(pred).k;
    const std::uint64_t seed = seed_for(3500 + static_cast<std::uint64_t>(pred));
    INFO(info(pred).name << "_sos, seed " << seed);
    Rng rng(seed);
    std::size_t failures = 0;
    const std::size_t n = scaled(3000);
    for (std::size_t it = 0; it < n; ++it) {
      const Family f = it % 4 == 0   ? Family::degenerate
                       : it % 4 == 1 ? Family::tiny
                       : it % 4 == 2 ? Family::near
                                     : Family::extreme;
      const Input in = make(f, pred, rng);
      const Indices idx = random_indices(rng, k);
      const Sign s = sos_checked(pred, in, idx, failures);
      for (int a = 0; a < k; ++a)
        for (int b = a + 1; b < k; ++b) {
          Input in2 = in;
          Indices idx2 = idx;
          std::swap(in2.p[static_cast<std::size_t>(a)], in2.p[static_cast<std::size_t>(b)]);
          std::swap(idx2[static_cast<std::size_t>(a)], idx2[static_cast<std::size_t>(b)]);
          if (sos_checked(pred, in2, idx2, failures) != -s) {
            ++failures;
            if (failures <= 10)
              FAIL_CHECK(describe(pred, in, idx) << " swapping " << a << ", " << b);
          }
        }
    }
    CHECK(failures == 0);
  }
}

TEST_CASE("sos depends on the order of the indices only, and is scale invariant",
          "[predicates][sos][degenerate]") {
  for (Pred pred : kAllPreds) {
    const int k = info(pred).k;
    const std::uint64_t seed = seed_for(3600 + static_cast<std::uint64_t>(pred));
    INFO(info(pred).name << "_sos, seed " << seed);
    Rng rng(seed);
    std::size_t failures = 0;
    const std::size_t n = scaled(3000);
    for (std::size_t it = 0; it < n; ++it) {
      const Input in = make(it % 2 ? Family::degenerate : Family::tiny, pred, rng);
      const Indices idx = random_indices(rng, k);
      const Sign s = sos_checked(pred, in, idx, failures);
      // An order-preserving relabelling: sort, then spread over [0, 2^32).
      Indices relabelled{};
      for (int i = 0; i < k; ++i) {
        int rank = 0;
        for (int j = 0; j < k; ++j)
          if (idx[static_cast<std::size_t>(j)] < idx[static_cast<std::size_t>(i)]) ++rank;
        relabelled[static_cast<std::size_t>(i)] =
            static_cast<std::uint32_t>(rank) * 900000000u + 3u;
      }
      if (sos_checked(pred, in, relabelled, failures) != s) {
        ++failures;
        if (failures <= 10) FAIL_CHECK(describe(pred, in, idx) << " relabelled");
      }
      // Scaling every coordinate by 2^e multiplies each coefficient by a positive factor.
      const int e = static_cast<int>(rand_int(rng, -300, 300));
      const Input sc = scaled_by(pred, in, e);
      if (sos_checked(pred, sc, idx, failures) != s) {
        ++failures;
        if (failures <= 10) FAIL_CHECK(describe(pred, in, idx) << " scaled by 2^" << e);
      }
      // The orientations are translation invariant (column operations with the 1 column).
      if (!info(pred).lifted) {
        Input tr = in;
        const double shift = static_cast<double>(rand_int(rng, -1000000, 1000000));
        bool exact = true;
        for (auto& p : tr.p)
          for (auto& x : p) {
            exact = exact && mpq_class(x + shift) == mpq_class(x) + mpq_class(shift);
            x += shift;
          }
        if (exact && sos_checked(pred, tr, idx, failures) != s) {
          ++failures;
          if (failures <= 10) FAIL_CHECK(describe(pred, in, idx) << " shifted by " << shift);
        }
      }
    }
    CHECK(failures == 0);
  }
}

// ---------------------------------------------------------------------------------------
// Consistency: Delaunay triangulations of exactly degenerate inputs.

namespace {

using Tri = std::array<std::uint32_t, 3>;
using Tet = std::array<std::uint32_t, 4>;

const double* P(const std::vector<Pt>& pts, std::uint32_t i) { return pts[i].data(); }

Sign orient2(const std::vector<Pt>& pts, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  return orient2d_sos(P(pts, a), P(pts, b), P(pts, c), a, b, c);
}
Sign incircle4(const std::vector<Pt>& pts, const Tri& t, std::uint32_t d) {
  return incircle_sos(P(pts, t[0]), P(pts, t[1]), P(pts, t[2]), P(pts, d), t[0], t[1], t[2], d);
}
Sign orient3(const std::vector<Pt>& pts, const Tet& t) {
  return orient3d_sos(P(pts, t[0]), P(pts, t[1]), P(pts, t[2]), P(pts, t[3]), t[0], t[1], t[2],
                      t[3]);
}
Sign insphere5(const std::vector<Pt>& pts, const Tet& t, std::uint32_t e) {
  return insphere_sos(P(pts, t[0]), P(pts, t[1]), P(pts, t[2]), P(pts, t[3]), P(pts, e), t[0], t[1],
                      t[2], t[3], e);
}

// Bowyer-Watson with incircle_sos: pts holds n real points followed by the three corners of
// an enclosing triangle (indices n, n+1, n+2, larger than every real index). Inserts the
// real points in `order`; a point whose circumcircle test conflicts with no triangle is
// redundant in the perturbed configuration (a duplicate of a point with a larger index).
std::vector<Tri> delaunay2(const std::vector<Pt>& pts, const std::vector<std::uint32_t>& order) {
  const auto n = static_cast<std::uint32_t>(pts.size() - 3);
  std::vector<Tri> tris = {{n, n + 1, n + 2}};
  if (orient2(pts, n, n + 1, n + 2) != Sign::positive) std::swap(tris[0][1], tris[0][2]);
  for (std::uint32_t p : order) {
    std::vector<Tri> keep, conflict;
    for (const Tri& t : tris)
      (incircle4(pts, t, p) == Sign::positive ? conflict : keep).push_back(t);
    if (conflict.empty()) continue;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
    for (const Tri& t : conflict)
      for (int i = 0; i < 3; ++i)
        edges.emplace_back(t[static_cast<std::size_t>(i)],
                           t[static_cast<std::size_t>((i + 1) % 3)]);
    std::sort(edges.begin(), edges.end());
    for (const auto& [u, v] : edges)
      if (!std::binary_search(edges.begin(), edges.end(), std::make_pair(v, u)))
        keep.push_back({u, v, p});
    tris.swap(keep);
  }
  return tris;
}

// Canonical form of an oriented simplex: the lexicographically smallest of its even
// permutations; of a triangulation: its canonical simplices, sorted.
template <std::size_t K>
std::array<std::uint32_t, K> canonical_simplex(const std::array<std::uint32_t, K>& t) {
  std::array<std::size_t, K> perm{};
  for (std::size_t i = 0; i < K; ++i) perm[i] = i;
  std::array<std::uint32_t, K> best = t;
  do {
    int inversions = 0;
    for (std::size_t i = 0; i < K; ++i)
      for (std::size_t j = i + 1; j < K; ++j) inversions += perm[i] > perm[j] ? 1 : 0;
    if (inversions % 2 != 0) continue;
    std::array<std::uint32_t, K> cand{};
    for (std::size_t i = 0; i < K; ++i) cand[i] = t[perm[i]];
    best = std::min(best, cand);
  } while (std::next_permutation(perm.begin(), perm.end()));
  return best;
}

template <std::size_t K>
std::vector<std::array<std::uint32_t, K>> canonical(std::vector<std::array<std::uint32_t, K>> s) {
  for (auto& t : s) t = canonical_simplex(t);
  std::sort(s.begin(), s.end());
  return s;
}

// The vertex that must survive at each location: the largest index among duplicates
// (smaller indices have larger lift perturbations, so they lie above the paraboloid's
// lower hull and are redundant).
std::set<std::uint32_t> expected_vertices(const std::vector<Pt>& pts, std::size_t n_real) {
  std::map<Pt, std::uint32_t> best;
  for (std::size_t i = 0; i < n_real; ++i) {
    auto& b = best[pts[i]];
    b = std::max(b, static_cast<std::uint32_t>(i));
  }
  std::set<std::uint32_t> out;
  for (const auto& kv : best) out.insert(kv.second);
  return out;
}

mpq_class cross2(const std::vector<Pt>& pts, const Tri& t) {
  const auto q = [&](std::uint32_t i, int j) {
    return mpq_class(pts[i][static_cast<std::size_t>(j)]);
  };
  return (q(t[1], 0) - q(t[0], 0)) * (q(t[2], 1) - q(t[0], 1)) -
         (q(t[1], 1) - q(t[0], 1)) * (q(t[2], 0) - q(t[0], 0));
}

void check_delaunay2(const std::vector<Pt>& pts, const std::vector<Tri>& tris) {
  const std::size_t n = pts.size() - 3;
  const auto N = static_cast<std::uint32_t>(n);
  std::size_t failures = 0;
  const auto fail = [&](const std::string& what) {
    ++failures;
    if (failures <= 10) FAIL_CHECK(what);
  };
  const auto tri_str = [](const Tri& t) {
    return "(" + std::to_string(t[0]) + "," + std::to_string(t[1]) + "," + std::to_string(t[2]) +
           ")";
  };
  // Orientation, exact area.
  mpq_class area = 0;
  std::set<std::uint32_t> vertices;
  for (const Tri& t : tris) {
    if (orient2(pts, t[0], t[1], t[2]) != Sign::positive) fail("not positive: " + tri_str(t));
    if (orient2d(P(pts, t[0]), P(pts, t[1]), P(pts, t[2])) == Sign::negative)
      fail("negative area: " + tri_str(t));
    area += cross2(pts, t);
    for (std::uint32_t v : t)
      if (v < N) vertices.insert(v);
  }
  CHECK(area == cross2(pts, {N, N + 1, N + 2}));
  // Topology: every directed edge once; its reverse present unless on the enclosing triangle.
  std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
  for (const Tri& t : tris)
    for (int i = 0; i < 3; ++i)
      if (!edges.emplace(t[static_cast<std::size_t>(i)], t[static_cast<std::size_t>((i + 1) % 3)])
               .second)
        fail("directed edge twice in " + tri_str(t));
  std::size_t boundary = 0;
  for (const auto& [u, v] : edges)
    if (!edges.count({v, u})) {
      ++boundary;
      if (u < N || v < N) fail("boundary edge " + std::to_string(u) + "-" + std::to_string(v));
    }
  CHECK(boundary == 3);
  // Vertices: one per distinct location, the largest index; Euler: 2m + 1 triangles.
  CHECK(vertices == expected_vertices(pts, n));
  CHECK(tris.size() == 2 * vertices.size() + 1);
  // Locally Delaunay across every interior edge, and globally: no point, present or
  // redundant, inside any circumcircle of the perturbed configuration.
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> apex;
  for (const Tri& t : tris)
    for (int i = 0; i < 3; ++i)
      apex[{t[static_cast<std::size_t>(i)], t[static_cast<std::size_t>((i + 1) % 3)]}] =
          t[static_cast<std::size_t>((i + 2) % 3)];
  for (const Tri& t : tris)
    for (int i = 0; i < 3; ++i) {
      const auto it =
          apex.find({t[static_cast<std::size_t>((i + 1) % 3)], t[static_cast<std::size_t>(i)]});
      if (it != apex.end() && incircle4(pts, t, it->second) != Sign::negative)
        fail("not locally Delaunay: " + tri_str(t) + " vs " + std::to_string(it->second));
    }
  for (const Tri& t : tris)
    for (std::uint32_t v = 0; v < N + 3; ++v)
      if (v != t[0] && v != t[1] && v != t[2] && incircle4(pts, t, v) != Sign::negative)
        fail("point " + std::to_string(v) + " inside the circumcircle of " + tri_str(t));
  CHECK(failures == 0);
}

// Adds the enclosing triangle/tetrahedron corners for points within [-R, R]^d:
// (-K,...,-K) and (-K,..,3K,..,-K), K = 10 R, containing {x >= -K, sum x <= K}.
void add_enclosing(std::vector<Pt>& pts, int d) {
  double R = 1;
  for (const Pt& p : pts)
    for (int j = 0; j < d; ++j) R = std::max(R, std::fabs(p[static_cast<std::size_t>(j)]));
  const double K = 10 * R;
  Pt base{};
  for (int j = 0; j < d; ++j) base[static_cast<std::size_t>(j)] = -K;
  pts.push_back(base);
  for (int j = 0; j < d; ++j) {
    Pt q = base;
    q[static_cast<std::size_t>(j)] = 3 * K;
    pts.push_back(q);
  }
}

// Appends `count` duplicates of random points already in pts.
void add_duplicates(std::vector<Pt>& pts, std::size_t count, Rng& rng) {
  const std::size_t n = pts.size();
  for (std::size_t i = 0; i < count; ++i) pts.push_back(pts[static_cast<std::size_t>(rng() % n)]);
}

void run_delaunay2(std::vector<Pt> pts, Rng& rng) {
  shuffle(pts, rng);  // indices are positions: unrelated to the insertion order below
  const std::size_t n = pts.size();
  add_enclosing(pts, 2);
  std::vector<std::uint32_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = static_cast<std::uint32_t>(i);
  shuffle(order, rng);
  const std::vector<Tri> tris = delaunay2(pts, order);
  check_delaunay2(pts, tris);
  // The perturbed configuration is in general position: its Delaunay triangulation is
  // unique, whatever the insertion order.
  std::reverse(order.begin(), order.end());
  CHECK(canonical(delaunay2(pts, order)) == canonical(tris));
}

// Bowyer-Watson in 3D with insphere_sos, as delaunay2.
std::vector<Tet> delaunay3(const std::vector<Pt>& pts, const std::vector<std::uint32_t>& order) {
  const auto n = static_cast<std::uint32_t>(pts.size() - 4);
  std::vector<Tet> tets = {{n, n + 1, n + 2, n + 3}};
  if (orient3(pts, tets[0]) != Sign::positive) std::swap(tets[0][2], tets[0][3]);
  for (std::uint32_t p : order) {
    std::vector<Tet> keep, conflict;
    for (const Tet& t : tets)
      (insphere5(pts, t, p) == Sign::positive ? conflict : keep).push_back(t);
    if (conflict.empty()) continue;
    std::map<std::array<std::uint32_t, 3>, int> face_count;
    const auto face = [](const Tet& t, int i) {
      std::array<std::uint32_t, 3> f{};
      std::size_t m = 0;
      for (int j = 0; j < 4; ++j)
        if (j != i) f[m++] = t[static_cast<std::size_t>(j)];
      std::sort(f.begin(), f.end());
      return f;
    };
    for (const Tet& t : conflict)
      for (int i = 0; i < 4; ++i) ++face_count[face(t, i)];
    for (const Tet& t : conflict)
      for (int i = 0; i < 4; ++i)
        if (face_count[face(t, i)] == 1) {
          Tet nt = t;  // p replaces the vertex opposite the cavity boundary face
          nt[static_cast<std::size_t>(i)] = p;
          keep.push_back(nt);
        }
    tets.swap(keep);
  }
  return tets;
}

mpq_class volume6(const std::vector<Pt>& pts, const Tet& t) {
  mpq_class m[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      m[i][j] = mpq_class(pts[t[static_cast<std::size_t>(i)]][static_cast<std::size_t>(j)]) -
                mpq_class(pts[t[3]][static_cast<std::size_t>(j)]);
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
         m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

void check_delaunay3(const std::vector<Pt>& pts, const std::vector<Tet>& tets) {
  const std::size_t n = pts.size() - 4;
  const auto N = static_cast<std::uint32_t>(n);
  std::size_t failures = 0;
  const auto fail = [&](const std::string& what) {
    ++failures;
    if (failures <= 10) FAIL_CHECK(what);
  };
  const auto tet_str = [](const Tet& t) {
    return "(" + std::to_string(t[0]) + "," + std::to_string(t[1]) + "," + std::to_string(t[2]) +
           "," + std::to_string(t[3]) + ")";
  };
  mpq_class volume = 0;
  std::set<std::uint32_t> vertices;
  std::map<std::array<std::uint32_t, 3>, std::vector<std::uint32_t>> opposite;  // face → apexes
  for (const Tet& t : tets) {
    if (orient3(pts, t) != Sign::positive) fail("not positive: " + tet_str(t));
    if (orient3d(P(pts, t[0]), P(pts, t[1]), P(pts, t[2]), P(pts, t[3])) == Sign::negative)
      fail("negative volume: " + tet_str(t));
    // orient3d(a,b,c,d) is det[a-d; b-d; c-d], volume6 the same determinant.
    volume += volume6(pts, t);
    for (std::uint32_t v : t)
      if (v < N) vertices.insert(v);
    for (int i = 0; i < 4; ++i) {
      std::array<std::uint32_t, 3> f{};
      std::size_t m = 0;
      for (int j = 0; j < 4; ++j)
        if (j != i) f[m++] = t[static_cast<std::size_t>(j)];
      std::sort(f.begin(), f.end());
      opposite[f].push_back(t[static_cast<std::size_t>(i)]);
    }
  }
  mpq_class total = volume6(pts, {N, N + 1, N + 2, N + 3});
  if (total < 0) total = -total;
  CHECK(volume == total);
  // Each face in exactly two tetrahedra, on opposite sides, except the enclosing faces.
  std::size_t hull_faces = 0;
  for (const auto& [f, apexes] : opposite) {
    if (apexes.size() == 1) {
      ++hull_faces;
      if (f[0] < N) fail("boundary face with a real vertex");
      continue;
    }
    if (apexes.size() != 2) {
      fail("face in " + std::to_string(apexes.size()) + " tetrahedra");
      continue;
    }
    const Tet t1 = {f[0], f[1], f[2], apexes[0]}, t2 = {f[0], f[1], f[2], apexes[1]};
    if (orient3(pts, t1) != -orient3(pts, t2)) fail("apexes on the same side of a face");
    // Locally Delaunay: the other apex is outside the circumsphere.
    const Tet pos = orient3(pts, t1) == Sign::positive ? t1 : Tet{f[0], f[2], f[1], apexes[0]};
    if (insphere5(pts, pos, apexes[1]) != Sign::negative)
      fail("not locally Delaunay: " + tet_str(pos));
  }
  CHECK(hull_faces == 4);
  CHECK(vertices == expected_vertices(pts, n));
  // Globally Delaunay for the perturbed configuration, redundant points included.
  for (const Tet& t : tets)
    for (std::uint32_t v = 0; v < N + 4; ++v)
      if (std::find(t.begin(), t.end(), v) == t.end() && insphere5(pts, t, v) != Sign::negative)
        fail("point " + std::to_string(v) + " inside the circumsphere of " + tet_str(t));
  CHECK(failures == 0);
}

void run_delaunay3(std::vector<Pt> pts, Rng& rng) {
  shuffle(pts, rng);
  const std::size_t n = pts.size();
  add_enclosing(pts, 3);
  std::vector<std::uint32_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = static_cast<std::uint32_t>(i);
  shuffle(order, rng);
  const std::vector<Tet> tets = delaunay3(pts, order);
  check_delaunay3(pts, tets);
  std::reverse(order.begin(), order.end());
  CHECK(canonical(delaunay3(pts, order)) == canonical(tets));
}

}  // namespace

TEST_CASE(
    "a 2D Delaunay triangulation built with the sos predicates is valid on exactly "
    "degenerate input",
    "[predicates][sos][degenerate]") {
  const std::uint64_t seed = seed_for(4000);
  INFO("seed " << seed);
  Rng rng(seed);
  SECTION("12 x 12 integer grid with duplicates") {
    std::vector<Pt> pts;
    for (int x = 0; x < 12; ++x)
      for (int y = 0; y < 12; ++y) pts.push_back({double(x), double(y), 0});
    add_duplicates(pts, 40, rng);
    run_delaunay2(pts, rng);
  }
  SECTION("lattice points on the circle x^2 + y^2 = 5^4 13^2, its centre, duplicates") {
    std::vector<Pt> pts;
    for (const auto& q : lattice_sphere(625 * 169, 2))
      pts.push_back({double(q[0]), double(q[1]), 0});
    REQUIRE(pts.size() == 60);
    pts.push_back({0, 0, 0});
    add_duplicates(pts, 25, rng);
    pts.push_back({0, 0, 0});
    run_delaunay2(pts, rng);
  }
  SECTION("square corners, many copies each, scaled by 2^-600") {
    std::vector<Pt> pts;
    for (int c = 0; c < 10; ++c)
      for (double x : {-1.0, 1.0})
        for (double y : {-1.0, 1.0}) pts.push_back({std::ldexp(x, -600), std::ldexp(y, -600), 0});
    run_delaunay2(pts, rng);
  }
  SECTION("collinear points only") {
    std::vector<Pt> pts;
    for (int i = 0; i < 40; ++i) pts.push_back({double(3 * i - 50), double(2 * i + 7), 0});
    add_duplicates(pts, 10, rng);
    run_delaunay2(pts, rng);
  }
}

TEST_CASE(
    "a 3D Delaunay tetrahedralization built with the sos predicates is valid on "
    "exactly degenerate input",
    "[predicates][sos][degenerate]") {
  const std::uint64_t seed = seed_for(4100);
  INFO("seed " << seed);
  Rng rng(seed);
  SECTION("4 x 4 x 4 integer grid with duplicates") {
    std::vector<Pt> pts;
    for (int x = 0; x < 4; ++x)
      for (int y = 0; y < 4; ++y)
        for (int z = 0; z < 4; ++z) pts.push_back({double(x), double(y), double(z)});
    add_duplicates(pts, 10, rng);
    run_delaunay3(pts, rng);
  }
  SECTION("cube corners, three copies each, and the centre") {
    std::vector<Pt> pts;
    for (int c = 0; c < 3; ++c)
      for (double x : {-1.0, 1.0})
        for (double y : {-1.0, 1.0})
          for (double z : {-1.0, 1.0}) pts.push_back({x, y, z});
    pts.push_back({0, 0, 0});
    run_delaunay3(pts, rng);
  }
  SECTION("lattice points on the sphere x^2 + y^2 + z^2 = 9, its centre, duplicates") {
    std::vector<Pt> pts;
    for (const auto& q : lattice_sphere(9, 3))
      pts.push_back({double(q[0]), double(q[1]), double(q[2])});
    REQUIRE(pts.size() == 30);
    pts.push_back({0, 0, 0});
    add_duplicates(pts, 6, rng);
    run_delaunay3(pts, rng);
  }
  SECTION("coplanar points only") {
    std::vector<Pt> pts;
    for (int x = 0; x < 5; ++x)
      for (int y = 0; y < 5; ++y) pts.push_back({double(x), double(y), double(x + y)});
    run_delaunay3(pts, rng);
  }
}

TEST_CASE("larger degenerate triangulations", "[predicates][sos][degenerate][.slow]") {
  Rng rng(seed_for(4200));
  std::vector<Pt> grid;
  for (int x = 0; x < 30; ++x)
    for (int y = 0; y < 30; ++y) grid.push_back({double(x), double(y), 0});
  add_duplicates(grid, 100, rng);
  run_delaunay2(grid, rng);
  std::vector<Pt> cube;
  for (int x = 0; x < 6; ++x)
    for (int y = 0; y < 6; ++y)
      for (int z = 0; z < 6; ++z) cube.push_back({double(x), double(y), double(z)});
  add_duplicates(cube, 30, rng);
  run_delaunay3(cube, rng);
}
