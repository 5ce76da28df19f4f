// Tests of orient2d, incircle, orient3d and insphere (predicates.h) against an exact
// rational oracle (exact_oracle.h): the defining determinant evaluated with GMP.
//
// Every predicate sees at least 10^5 inputs in the default run (kPerPredicate below):
// uniform random, wide ranges, near-degenerate (the filter fails, the exact stage
// decides), exactly degenerate (answer zero), a power-of-two scale sweep, and mixed
// magnitudes down to subnormals and up to DBL_MAX. Counts scale with VOROCLIP_TEST_SCALE;
// a ten times larger run is hidden behind [.slow].
#include <catch2/catch.hpp>

#include <cfloat>
#include <cmath>
#include <exception>
#include <initializer_list>
#include <limits>
#include <string>
#include <vector>

#include "exact_oracle.h"
#include "voroclip/core.h"
#include "voroclip/predicates.h"

using namespace voroclip;
using namespace voroclip::test;

namespace {

// Default inputs per predicate and family (VOROCLIP_TEST_SCALE = 1).
constexpr std::size_t kUnitBox = 40000;
constexpr std::size_t kWide = 15000;
constexpr std::size_t kNear = 30000;
constexpr std::size_t kDegenerate = 10000;
constexpr std::size_t kMixed = 6000;
constexpr std::size_t kDegenerateExtreme = 4000;
constexpr std::size_t kExtremeSet = 2000;
constexpr int kScales[] = {-500, -300, -100, -40, 0, 40, 100, 300, 500};
constexpr std::size_t kNumScales = sizeof kScales / sizeof kScales[0];
constexpr std::size_t kScaleNear = 1000, kScaleDegenerate = 500, kScaleRandom = 300;
constexpr std::size_t kPerPredicate = kUnitBox + kWide + kNear + kDegenerate + kMixed +
                                      kDegenerateExtreme + kExtremeSet +
                                      kNumScales * (kScaleNear + kScaleDegenerate + kScaleRandom);
static_assert(kPerPredicate >= 100000, "the requirement: >= 10^5 random inputs per predicate");

enum class Family { unit_box, wide, near, degenerate, mixed, degenerate_extreme, extreme_set };

const char* name(Family f) {
  switch (f) {
    case Family::unit_box:
      return "uniform in [-1,1]";
    case Family::wide:
      return "wide ranges";
    case Family::near:
      return "near-degenerate";
    case Family::degenerate:
      return "exactly degenerate";
    case Family::mixed:
      return "mixed magnitudes";
    case Family::degenerate_extreme:
      return "degenerate + one extreme coordinate";
    case Family::extreme_set:
      return "coordinates from {0, +-1, +-DBL_MAX, +-DBL_MIN, +-2^-1074}";
  }
  return "?";
}

Input make(Family f, Pred pred, Rng& rng) {
  switch (f) {
    case Family::unit_box:
      return random_box(pred, rng);
    case Family::wide:
      return random_wide_range(pred, rng);
    case Family::near: {
      static constexpr int ulps[] = {0, 1, 4, 64};
      return near_degenerate(pred, rng, ulps[rng() % 4]);
    }
    case Family::degenerate:
      return exactly_degenerate(pred, rng);
    case Family::mixed:
      return mixed_magnitudes(pred, rng);
    case Family::degenerate_extreme:
      return degenerate_plus_extreme(pred, rng);
    case Family::extreme_set: {
      static constexpr double set[] = {0.0,     1.0,      -1.0,      DBL_MAX,   -DBL_MAX,
                                       DBL_MIN, -DBL_MIN, 0x1p-1074, -0x1p-1074};
      Input in;
      for (int i = 0; i < info(pred).k; ++i)
        for (int j = 0; j < info(pred).d; ++j)
          in.p[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = set[rng() % 9];
      return in;
    }
  }
  return {};
}

struct Tally {
  std::size_t inputs = 0, wrong = 0, zero = 0, fast_wrong = 0, filter_undecided = 0;
};

// Compares predicate `pred` (or its exact stage alone) on `in` with the oracle; reports the
// first mismatches with hex-float inputs. Returns the oracle's sign.
int check_one(Pred pred, const Input& in, Tally& t, bool exact_stage_only = false) {
  const int expected = oracle_sign(pred, in);
  int got = 2;
  try {
    got = to_int(exact_stage_only ? eval_exact_stage(pred, in) : eval(pred, in));
  } catch (const std::exception& e) {
    FAIL_CHECK(describe(pred, in) << " threw: " << e.what());
  }
  ++t.inputs;
  if (expected == 0) ++t.zero;
  if (to_int(eval_fast(pred, in)) != expected) ++t.fast_wrong;
  if (filter_decision(pred, in) == 0) ++t.filter_undecided;
  if (got != expected) {
    ++t.wrong;
    if (t.wrong <= 10)
      FAIL_CHECK(describe(pred, in) << (exact_stage_only ? " [exact stage]" : "") << ": expected "
                                    << expected << ", got " << got);
  }
  return expected;
}

Tally run_family(Pred pred, Family f, std::size_t n, std::uint64_t seed,
                 bool exact_stage_only = false) {
  Rng rng(seed);
  Tally t;
  for (std::size_t i = 0; i < n; ++i) check_one(pred, make(f, pred, rng), t, exact_stage_only);
  return t;
}

std::uint64_t family_seed(std::uint64_t base, Pred pred, Family f) {
  return seed_for(base + 1000 * static_cast<std::uint64_t>(pred) + static_cast<std::uint64_t>(f));
}

// Runs the families over all four predicates: every input must match the oracle.
void run_families(std::initializer_list<Family> families, std::size_t n, std::uint64_t base) {
  for (Pred pred : kAllPreds) {
    for (Family f : families) {
      const std::uint64_t seed = family_seed(base, pred, f);
      INFO(info(pred).name << ", " << name(f) << ", " << n << " inputs, seed " << seed);
      const Tally t = run_family(pred, f, n, seed);
      CHECK(t.inputs == n);
      CHECK(t.wrong == 0);
    }
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------

TEST_CASE("oracle: integer Bareiss determinant equals the mpq permutation expansion",
          "[predicates][exact]") {
  for (Pred pred : kAllPreds) {
    for (Family f : {Family::unit_box, Family::wide, Family::near, Family::degenerate,
                     Family::mixed, Family::degenerate_extreme, Family::extreme_set}) {
      const std::uint64_t seed = family_seed(11, pred, f);
      INFO(info(pred).name << ", " << name(f) << ", seed " << seed);
      Rng rng(seed);
      const std::size_t n = scaled(f == Family::mixed ? 40 : 200);
      std::size_t mismatches = 0;
      for (std::size_t i = 0; i < n; ++i) {
        const Input in = make(f, pred, rng);
        if (oracle_sign(pred, in) != oracle_sign_mpq(pred, in)) {
          ++mismatches;
          FAIL_CHECK(describe(pred, in));
        }
      }
      CHECK(mismatches == 0);
    }
  }
  // The exactly degenerate family is exactly degenerate.
  for (Pred pred : kAllPreds) {
    Rng rng(seed_for(12));
    for (int i = 0; i < 200; ++i) {
      const Input in = exactly_degenerate(pred, rng);
      INFO(describe(pred, in));
      REQUIRE(oracle_sign_mpq(pred, in) == 0);
    }
  }
  CHECK(circle_points().size() == 36);
  CHECK(sphere_points().size() >= 50);
}

TEST_CASE("sign conventions: orientation, inside circle and inside sphere", "[predicates][exact]") {
  const double o[3] = {0, 0, 0}, x[3] = {1, 0, 0}, y[3] = {0, 1, 0}, z[3] = {0, 0, 1};
  const double below[3] = {0, 0, -1}, g2[3] = {0.25, 0.25, 0}, far[3] = {5, 5, 5};
  const double g3[3] = {0.25, 0.25, 0.25};
  CHECK(orient2d(o, x, y) == Sign::positive);
  CHECK(orient2d(o, y, x) == Sign::negative);
  CHECK(orient2d(o, x, x) == Sign::zero);
  CHECK(incircle(o, x, y, g2) == Sign::positive);
  CHECK(incircle(o, x, y, far) == Sign::negative);
  CHECK(incircle(o, y, x, g2) == Sign::negative);
  CHECK(incircle(o, x, y, o) == Sign::zero);
  CHECK(orient3d(o, x, y, below) == Sign::positive);
  CHECK(orient3d(o, x, y, z) == Sign::negative);
  CHECK(orient3d(o, x, y, g2) == Sign::zero);
  REQUIRE(orient3d(o, x, y, below) == Sign::positive);
  // The sphere through o x y below: centre (1/2, 1/2, -1/2), radius^2 3/4.
  CHECK(insphere(o, x, y, below, g3) == Sign::positive);  // distance^2 11/16
  const double c[3] = {0.2, 0.2, -0.2};                   // inside the tetrahedron
  CHECK(insphere(o, x, y, below, c) == Sign::positive);
  CHECK(insphere(o, x, y, below, far) == Sign::negative);
  CHECK(insphere(o, x, y, below, z) == Sign::negative);
  CHECK(insphere(o, x, y, below, x) == Sign::zero);
  // The oracle agrees on these.
  Input in;
  in.p[0] = {0, 0, 0};
  in.p[1] = {1, 0, 0};
  in.p[2] = {0, 1, 0};
  in.p[3] = {0, 0, -1};
  in.p[4] = {0.2, 0.2, -0.2};
  CHECK(oracle_sign(Pred::orient3d, in) == 1);
  CHECK(oracle_sign(Pred::insphere, in) == 1);
  in.p[3] = {0.25, 0.25, 0};
  CHECK(oracle_sign(Pred::orient2d, in) == 1);
  CHECK(oracle_sign(Pred::incircle, in) == 1);
}

TEST_CASE("random inputs: uniform in [-1,1] and wide ranges", "[predicates][exact]") {
  run_families({Family::unit_box}, scaled(kUnitBox), 100);
  run_families({Family::wide}, scaled(kWide), 200);
}

TEST_CASE("near-degenerate inputs: the filter cannot decide, the exact stage does",
          "[predicates][exact][degenerate]") {
  const std::size_t n = scaled(kNear);
  for (Pred pred : kAllPreds) {
    const std::uint64_t seed = family_seed(300, pred, Family::near);
    INFO(info(pred).name << ", " << n << " inputs, seed " << seed);
    const Tally t = run_family(pred, Family::near, n, seed);
    CHECK(t.wrong == 0);
    // The family exercises the exact stage: the filter gives up on a good share of it...
    INFO("filter undecided on " << t.filter_undecided << ", fast wrong on " << t.fast_wrong);
    CHECK(t.filter_undecided * 2 >= n);
    // ... and plain floating point gets the sign wrong on some of it, where the filtered
    // predicate never does.
    if (n >= 1000) CHECK(t.fast_wrong > 0);
  }
}

TEST_CASE("Kettner et al.'s classroom example for orient2d",
          "[predicates][exact][degenerate][regression]") {
  const int side = test_scale() >= 1 ? 256 : 64;
  Tally t;
  for (int x = 0; x < side; ++x)
    for (int y = 0; y < side; ++y) check_one(Pred::orient2d, kettner_orient2d(x, y), t);
  INFO(t.inputs << " inputs, exact zero on " << t.zero << ", fast wrong on " << t.fast_wrong);
  CHECK(t.wrong == 0);
  CHECK(t.zero >= static_cast<std::size_t>(side));  // the diagonal x == y at least
  CHECK(t.fast_wrong > 0);
}

TEST_CASE("exactly degenerate inputs give zero", "[predicates][exact][degenerate]") {
  const std::size_t n = scaled(kDegenerate);
  for (Pred pred : kAllPreds) {
    const std::uint64_t seed = family_seed(400, pred, Family::degenerate);
    INFO(info(pred).name << ", " << n << " inputs, seed " << seed);
    const Tally t = run_family(pred, Family::degenerate, n, seed);
    CHECK(t.wrong == 0);
    CHECK(t.zero == n);  // the oracle confirms the family is degenerate
  }
}

TEST_CASE("scale sweep: inputs times 2^k for k in [-500, 500]", "[predicates][exact][degenerate]") {
  for (Pred pred : kAllPreds) {
    for (Family f : {Family::near, Family::degenerate, Family::unit_box}) {
      const std::size_t n = scaled(f == Family::near         ? kScaleNear
                                   : f == Family::degenerate ? kScaleDegenerate
                                                             : kScaleRandom);
      const std::uint64_t seed = family_seed(500, pred, f);
      INFO(info(pred).name << ", " << name(f) << ", seed " << seed);
      Rng rng(seed);
      std::vector<Input> base(n);
      std::vector<int> expected(n);
      for (std::size_t i = 0; i < n; ++i) {
        base[i] = make(f, pred, rng);
        expected[i] = oracle_sign(pred, base[i]);
      }
      for (int k : kScales) {
        INFO("scale 2^" << k);
        Tally t;
        std::size_t oracle_changed = 0;
        for (std::size_t i = 0; i < n; ++i)
          if (check_one(pred, scaled_by(pred, base[i], k), t) != expected[i]) ++oracle_changed;
        CHECK(t.wrong == 0);
        CHECK(oracle_changed == 0);  // exact scaling by 2^k does not change the sign
      }
    }
  }
}

TEST_CASE("mixed magnitudes: exact for every finite double", "[predicates][exact][degenerate]") {
  run_families({Family::mixed}, scaled(kMixed), 600);
  run_families({Family::degenerate_extreme}, scaled(kDegenerateExtreme), 700);
  run_families({Family::extreme_set}, scaled(kExtremeSet), 800);
}

TEST_CASE("finite inputs whose floating-point evaluation overflows or underflows",
          "[predicates][exact][regression]") {
  const double M = DBL_MAX, t = 0x1p-1074;
  {
    const double a[2] = {M, M}, b[2] = {-M, -M}, c[2] = {0, 0}, c2[2] = {0, t};
    CHECK(orient2d(a, b, c) == Sign::zero);
    CHECK(orient2d(a, b, c2) == Sign::negative);  // det = -2 M t
    CHECK(orient2d(b, a, c2) == Sign::positive);
  }
  {
    // Tiny triangles: every product underflows in floating point.
    const double a[2] = {0, 0}, b[2] = {t, 0}, c[2] = {0, t}, d[2] = {t, t}, e[2] = {2 * t, 0};
    CHECK(orient2d(a, b, c) == Sign::positive);
    CHECK(orient2d(a, b, e) == Sign::zero);
    CHECK(incircle(a, b, c, d) == Sign::zero);    // the unit square's corners, scaled
    const double in[2] = {0x1p-1073, 0x1p-1074};  // (2t, t): outside the circle through a b c
    CHECK(incircle(a, b, c, in) == Sign::negative);
  }
  {
    const double a[3] = {M, 0, 0}, b[3] = {0, M, 0}, c[3] = {0, 0, M}, d[3] = {-M, -M, -M};
    const double e[3] = {0, 0, 0};
    Input in;
    in.p[0] = {M, 0, 0};
    in.p[1] = {0, M, 0};
    in.p[2] = {0, 0, M};
    in.p[3] = {-M, -M, -M};
    in.p[4] = {0, 0, 0};
    CHECK(to_int(orient3d(a, b, c, d)) == oracle_sign(Pred::orient3d, in));
    CHECK(to_int(insphere(a, b, c, d, e)) == oracle_sign(Pred::insphere, in));
    CHECK(orient3d(a, b, c, e) != Sign::zero);
  }
}

TEST_CASE("regression: inputs whose coordinates are all subnormal",
          "[predicates][exact][degenerate][regression]") {
  // Found by the extreme-set family: the exact stage scaled these by 2^1073, a factor that
  // is not a finite double, and answered zero.
  const double t = 0x1p-1074;
  const double a[2] = {t, -t}, b[2] = {t, 0}, c[2] = {0, -t};
  CHECK(orient2d(a, b, c) == Sign::positive);  // det = t^2
  const double a2[2] = {t, t}, b2[2] = {t, 0}, c2[2] = {0, 0};
  CHECK(orient2d(a2, b2, c2) == Sign::negative);  // det = -t^2
  const double s[3] = {0, 0, 0}, x[3] = {t, 0, 0}, y[3] = {0, t, 0}, z[3] = {0, 0, t};
  CHECK(orient3d(s, x, y, z) == Sign::negative);
  CHECK(orient3d(x, s, y, z) == Sign::positive);
  const double in[3] = {t, t, t}, far[3] = {4 * t, 4 * t, 0};
  CHECK(incircle(s, x, y, far) == Sign::negative);
  CHECK(incircle(s, x, y, in) == Sign::zero);          // (t, t) is on the circle through s x y
  CHECK(insphere(x, s, y, z, far) == Sign::negative);  // outside; orient3d(x,s,y,z) > 0
  CHECK(insphere(x, s, y, z, in) == Sign::zero);       // (t, t, t) is on the sphere
  CHECK(insphere(s, x, y, z, far) == Sign::positive);
}

TEST_CASE("the exact stage alone is exact on every family", "[predicates][exact]") {
  for (Pred pred : kAllPreds) {
    for (Family f : {Family::unit_box, Family::wide, Family::near, Family::degenerate,
                     Family::mixed, Family::degenerate_extreme}) {
      const std::uint64_t seed = family_seed(900, pred, f);
      const std::size_t n = scaled(1000);
      INFO(info(pred).name << ", " << name(f) << ", " << n << " inputs, seed " << seed);
      const Tally t = run_family(pred, f, n, seed, /*exact_stage_only=*/true);
      CHECK(t.wrong == 0);
    }
  }
}

TEST_CASE("points sharing one coordinate: zero, and one ulp off it the oracle's sign",
          "[predicates][exact][degenerate]") {
  // Every point with the same value on one axis (the points of a box's face): the matrix of
  // differences has a zero column, which the exact stage decides without its arithmetic.
  // Moving that coordinate of one point by one ulp leaves the shortcut to the arithmetic:
  // both must match the oracle (shared.wrong, off.wrong). The oracle's zero on the first
  // checks the construction, not the predicates.
  Rng rng(seed_for(1150));
  const std::size_t n = scaled(2000);
  for (Pred pred : kAllPreds) {
    const PredInfo pi = info(pred);
    Tally shared, off;
    for (std::size_t i = 0; i < n; ++i) {
      Input in = i % 2 == 0 ? random_box(pred, rng) : random_wide_range(pred, rng);
      const auto axis = static_cast<std::size_t>(rand_int(rng, 0, pi.d - 1));
      const double value = in.p[0][axis];
      for (int k = 0; k < pi.k; ++k) in.p[static_cast<std::size_t>(k)][axis] = value;
      for (bool exact_stage_only : {false, true}) {
        CHECK(check_one(pred, in, shared, exact_stage_only) == 0);
      }
      const auto moved = static_cast<std::size_t>(rand_int(rng, 0, pi.k - 1));
      in.p[moved][axis] = nudge(value, coin(rng) ? 1 : -1);
      for (bool exact_stage_only : {false, true}) check_one(pred, in, off, exact_stage_only);
    }
    INFO(pi.name << ": " << n << " inputs, " << off.zero << " zero one ulp off");
    CHECK(shared.wrong == 0);
    CHECK(off.wrong == 0);
    CHECK(off.zero < off.inputs);  // one ulp off, the points are no longer degenerate
  }
}

TEST_CASE("collinear3d: points on a line exactly, and one ulp off it",
          "[predicates][exact][degenerate]") {
  // a, b = a + m d and c = a + k d with integer coordinates below 2^24 times a power of two:
  // every value is exact, so the three are exactly collinear. Moving one coordinate of c by
  // one ulp adds a multiple of a unit axis, not parallel to d (every component of d is
  // non-zero): no longer collinear. b = a (a duplicate) is collinear with any c.
  Rng rng(seed_for(1100));
  const std::size_t n = scaled(2000);
  for (std::size_t i = 0; i < n; ++i) {
    const double scale = std::ldexp(1.0, static_cast<int>(rand_int(rng, -400, 400)));
    double a[3], d[3], b[3], c[3];
    const auto m = static_cast<double>(rand_int(rng, 1, 64) * (coin(rng) ? 1 : -1));
    const auto k = static_cast<double>(rand_int(rng, -64, 64));
    for (int j = 0; j < 3; ++j) {
      a[j] = static_cast<double>(rand_int(rng, -(1 << 16), 1 << 16)) * scale;
      d[j] = static_cast<double>(rand_int(rng, 1, 1 << 10) * (coin(rng) ? 1 : -1)) * scale;
      b[j] = a[j] + m * d[j];
      c[j] = a[j] + k * d[j];
    }
    INFO("case " << i << ": a " << hex(a[0]) << " " << hex(a[1]) << " " << hex(a[2]) << ", d "
                 << hex(d[0]) << " " << hex(d[1]) << " " << hex(d[2]) << ", m " << m << ", k "
                 << k);
    CHECK(collinear3d(a, b, c));
    CHECK(collinear3d(c, a, b));
    CHECK(collinear3d(a, a, c));
    const auto axis = static_cast<int>(rand_int(rng, 0, 2));
    double off[3] = {c[0], c[1], c[2]};
    off[axis] = nudge(off[axis], coin(rng) ? 1 : -1);
    CHECK_FALSE(collinear3d(a, b, off));
    CHECK_FALSE(collinear3d(off, b, a));
  }
}

TEST_CASE("NaN and infinite coordinates throw voroclip::Error", "[predicates]") {
  const double specials[] = {std::numeric_limits<double>::quiet_NaN(),
                             std::numeric_limits<double>::infinity(),
                             -std::numeric_limits<double>::infinity()};
  Rng rng(seed_for(1000));
  for (Pred pred : kAllPreds) {
    const PredInfo pi = info(pred);
    for (int base = 0; base < 3; ++base) {
      // A random input, an exactly degenerate one and one of all zeros.
      const Input in0 = base == 0   ? random_box(pred, rng)
                        : base == 1 ? exactly_degenerate(pred, rng)
                                    : Input{};
      for (double s : specials)
        for (int i = 0; i < pi.k; ++i)
          for (int j = 0; j < pi.d; ++j) {
            Input in = in0;
            in.p[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = s;
            INFO(describe(pred, in));
            CHECK_THROWS_AS(eval(pred, in), voroclip::Error);
          }
      // Every coordinate special.
      for (double s : specials) {
        Input in;
        for (auto& p : in.p) p = {s, s, s};
        INFO(describe(pred, in));
        CHECK_THROWS_AS(eval(pred, in), voroclip::Error);
      }
    }
  }
}

TEST_CASE("permuting the arguments multiplies the sign by the permutation's parity",
          "[predicates][exact][degenerate]") {
  for (Pred pred : kAllPreds) {
    const PredInfo pi = info(pred);
    const std::uint64_t seed = seed_for(1100 + static_cast<std::uint64_t>(pred));
    INFO(pi.name << ", seed " << seed);
    Rng rng(seed);
    const std::size_t n = scaled(3000);
    std::size_t failures = 0;
    for (std::size_t it = 0; it < n; ++it) {
      const Family f = it % 3 == 0   ? Family::degenerate
                       : it % 3 == 1 ? Family::near
                                     : Family::unit_box;
      const Input in = make(f, pred, rng);
      const Sign s = eval(pred, in);
      if (to_int(s) != oracle_sign(pred, in)) ++failures;
      for (int a = 0; a < pi.k; ++a)
        for (int b = a + 1; b < pi.k; ++b) {
          Input sw = in;
          std::swap(sw.p[static_cast<std::size_t>(a)], sw.p[static_cast<std::size_t>(b)]);
          if (eval(pred, sw) != -s) {
            ++failures;
            if (failures <= 10) FAIL_CHECK(describe(pred, in) << " swapping " << a << ", " << b);
          }
        }
      // A random permutation: sign times parity.
      std::array<int, 5> perm = {0, 1, 2, 3, 4};
      int parity = 1;
      for (int i = pi.k; i > 1; --i) {
        const auto j = static_cast<int>(rng() % static_cast<std::uint64_t>(i));
        if (j != i - 1) {
          std::swap(perm[static_cast<std::size_t>(i - 1)], perm[static_cast<std::size_t>(j)]);
          parity = -parity;
        }
      }
      Input pm;
      for (int i = 0; i < pi.k; ++i)
        pm.p[static_cast<std::size_t>(i)] =
            in.p[static_cast<std::size_t>(perm[static_cast<std::size_t>(i)])];
      if (to_int(eval(pred, pm)) != parity * to_int(s)) {
        ++failures;
        if (failures <= 10) FAIL_CHECK(describe(pred, in) << " permuted to " << describe(pred, pm));
      }
    }
    CHECK(failures == 0);
  }
}

TEST_CASE("the predicates are invariant under exact translations",
          "[predicates][exact][degenerate]") {
  // Lattice points plus a translation that keeps them exact: the sign cannot change.
  Rng rng(seed_for(1200));
  INFO("seed " << seed_for(1200));
  for (Pred pred : kAllPreds) {
    for (int it = 0; it < 2000; ++it) {
      Input in = exactly_degenerate_ints(pred, rng);
      if (it % 2) in.p[0][0] += 1;  // mostly no longer degenerate
      const Sign s = eval(pred, in);
      Input tr = in;
      const double shift = std::ldexp(static_cast<double>(rand_int(rng, -1000, 1000)),
                                      static_cast<int>(rand_int(rng, 0, 30)));
      for (auto& p : tr.p)
        for (auto& x : p) x += shift;
      INFO(describe(pred, in) << " shifted by " << shift);
      CHECK(eval(pred, tr) == s);
    }
  }
}

TEST_CASE("all families, 10^5 inputs each", "[predicates][exact][degenerate][.slow]") {
  run_families({Family::unit_box, Family::wide, Family::near, Family::degenerate, Family::mixed,
                Family::degenerate_extreme, Family::extreme_set},
               scaled(100000), 5000);
}
