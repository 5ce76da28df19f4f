// Tests of the expansion arithmetic (predicates/src/expansion.h) against exact rationals:
// the error-free transformations on random doubles of wide exponent range and on special
// values, and the expansion operations on random expansions, checking the exact value and
// the representation invariants (non-overlapping, increasing magnitude, no zeros).
#include <catch2/catch.hpp>

#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "exact_oracle.h"
#include "expansion.h"

namespace ex = voroclip::expansion;
using namespace voroclip::test;

namespace {

// The exact value of a finite double (a non-finite one fails the test and counts as 0).
mpq_class exact(double x) {
  if (!std::isfinite(x)) {
    FAIL_CHECK("non-finite value " << x);
    return 0;
  }
  return mpq_class(x);
}

mpq_class value(const double* e, int n) {
  mpq_class v = 0;
  for (int i = 0; i < n; ++i) v += exact(e[i]);
  return v;
}
mpq_class value(const std::vector<double>& e) {
  return value(e.data(), static_cast<int>(e.size()));
}

std::string hex_list(const double* e, int n) {
  std::ostringstream os;
  os << "{";
  for (int i = 0; i < n; ++i) os << (i ? ", " : "") << hex(e[i]);
  os << "}";
  return os.str();
}
std::string hex_list(const std::vector<double>& e) {
  return hex_list(e.data(), static_cast<int>(e.size()));
}

// Exponent of the most and of the least significant non-zero bit of x != 0.
int msb(double x) { return std::ilogb(x); }
int lsb(double x) {
  int e = 0;
  const double m = std::ldexp(std::frexp(x, &e), 53);
  auto bits = static_cast<std::uint64_t>(std::llabs(static_cast<long long>(m)));
  int tz = 0;
  while ((bits & 1) == 0) {
    bits >>= 1;
    ++tz;
  }
  return e - 53 + tz;
}
double ulp(double x) { return std::ldexp(1.0, msb(x) - 52); }

// "" when e is a valid expansion (no zeros, increasing magnitude, non-overlapping; also
// non-adjacent when asked), else what is wrong.
std::string invalid(const double* e, int n, bool nonadjacent = false) {
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(e[i])) return "component " + std::to_string(i) + " not finite";
    if (e[i] == 0) return "component " + std::to_string(i) + " is zero";
  }
  for (int i = 0; i + 1 < n; ++i) {
    if (!(std::fabs(e[i]) < std::fabs(e[i + 1])))
      return "components " + std::to_string(i) + ", " + std::to_string(i + 1) +
             " not increasing in magnitude";
    if (!(msb(e[i]) < lsb(e[i + 1])))
      return "components " + std::to_string(i) + ", " + std::to_string(i + 1) + " overlap";
    if (nonadjacent && !(msb(e[i]) + 1 < lsb(e[i + 1])))
      return "components " + std::to_string(i) + ", " + std::to_string(i + 1) + " adjacent";
  }
  return "";
}
std::string invalid(const std::vector<double>& e, bool nonadjacent = false) {
  return invalid(e.data(), static_cast<int>(e.size()), nonadjacent);
}

// An output buffer of exactly the documented size followed by a guard zone, to catch a
// routine writing past what its contract asks the caller to provide.
class Buffer {
 public:
  explicit Buffer(std::size_t size) : size_(size), v_(size + kGuard, kPoison) {}
  double* data() { return v_.data(); }
  double operator[](std::size_t i) const { return v_[i]; }
  bool guard_intact() const {
    for (std::size_t i = size_; i < v_.size(); ++i)
      if (!(v_[i] == kPoison)) return false;
    return true;
  }

 private:
  static constexpr std::size_t kGuard = 256;
  static constexpr double kPoison = -0x1.2345p-777;
  std::size_t size_;
  std::vector<double> v_;
};

// Special operands: zeros, subnormals, powers of two, values that round to even (ties).
const std::vector<double>& specials() {
  static const std::vector<double> v = {0.0,
                                        -0.0,
                                        0x1p-1074,
                                        -0x1p-1074,
                                        0x1p-1022 - 0x1p-1074,
                                        DBL_MIN,
                                        3 * 0x1p-1074,
                                        0x1p-1000,
                                        1.0,
                                        -1.0,
                                        0x1p-53,
                                        -0x1p-53,
                                        0x1p-54,
                                        3 * 0x1p-53,
                                        1 + 0x1p-52,
                                        -(1 + 0x1p-52),
                                        1 - 0x1p-53,
                                        0x1p53,
                                        0x1p53 + 2,
                                        0x1p52 + 1,
                                        0.1,
                                        1.0 / 3,
                                        -2.0 / 3,
                                        0x1p500,
                                        0x1p1000,
                                        -0x1p1000,
                                        0x1.fffffffffffffp999,
                                        0x1.0000000000001p-500};
  return v;
}

// two_product is exact when neither the splitting nor the product overflows and the
// product's error term does not underflow (expansion.h).
bool product_safe(double a, double b) {
  // Dekker's splitting multiplies by 2^27 + 1: |a|, |b| < 2^996 even when the other is 0.
  if (std::fabs(a) >= 0x1p996 || std::fabs(b) >= 0x1p996) return false;
  if (a == 0 || b == 0) return true;
  const int ea = std::ilogb(a), eb = std::ilogb(b);
  return ea <= 995 && eb <= 995 && ea + eb <= 1020 && lsb(a) + lsb(b) >= -1074 && ea + eb >= -960;
}

// A random double pair for the error-free transformations: independent exponents in
// [-1074, 1000], or exponents within 60 of each other (where the error terms are
// non-trivial).
std::pair<double, double> random_pair(Rng& rng) {
  const double a = random_wide(rng, -1074, 1000);
  if (coin(rng)) return {a, random_wide(rng, -1074, 1000)};
  const int ea = std::max(std::ilogb(a), -1074);
  const int lo = std::max(-1074, ea - 60), hi = std::min(1000, ea + 60);
  return {a, random_wide(rng, lo, hi)};
}

std::pair<double, double> random_product_pair(Rng& rng) {
  const auto ea = static_cast<int>(rand_int(rng, -965, 995));
  const int lo = std::max(-965, -960 - ea), hi = std::min(995, 1020 - ea);
  const auto eb = static_cast<int>(rand_int(rng, lo, hi));
  return {random_wide(rng, ea, ea), random_wide(rng, eb, eb)};
}

// One check of each error-free transformation; returns the number of failures.
int check_error_free(double a, double b) {
  int failures = 0;
  double x = 0, y = 0;
  const auto fail = [&](const char* what, const mpq_class& want) {
    ++failures;
    FAIL_CHECK(what << "(" << hex(a) << ", " << hex(b) << ") = (" << hex(x) << ", " << hex(y)
                    << "), exact " << want.get_str());
  };
  {
    ex::two_sum(a, b, x, y);
    const mpq_class want = exact(a) + exact(b);
    if (x != a + b || exact(x) + exact(y) != want) fail("two_sum", want);
  }
  {
    ex::two_diff(a, b, x, y);
    const mpq_class want = exact(a) - exact(b);
    if (x != a - b || exact(x) + exact(y) != want) fail("two_diff", want);
  }
  {
    const double big = std::fabs(a) >= std::fabs(b) ? a : b;
    const double small = std::fabs(a) >= std::fabs(b) ? b : a;
    ex::fast_two_sum(big, small, x, y);
    const mpq_class want = exact(a) + exact(b);
    if (x != big + small || exact(x) + exact(y) != want) fail("fast_two_sum", want);
  }
  if (product_safe(a, b)) {
    ex::two_product(a, b, x, y);
    const mpq_class want = exact(a) * exact(b);
    if (x != a * b || exact(x) + exact(y) != want) fail("two_product", want);
  }
  return failures;
}

// Builds a random expansion by adding random doubles one at a time with expansion_sum;
// about one addend in five cancels an earlier one exactly. Exponents lie in a window of
// `width` below a random top in [top_lo, top_hi].
std::vector<double> random_expansion(Rng& rng, int terms, int top_lo, int top_hi, int width) {
  const auto top = static_cast<int>(rand_int(rng, top_lo, top_hi));
  std::vector<double> e, h, added;
  for (int i = 0; i < terms; ++i) {
    double d = 0;
    if (!added.empty() && rng() % 5 == 0)
      d = -added[static_cast<std::size_t>(rng() % added.size())];
    else
      d = random_wide(rng, std::max(-1074, top - width), top);
    added.push_back(d);
    h.resize(e.size() + 1);
    const int n = ex::expansion_sum(e.data(), static_cast<int>(e.size()), &d, 1, h.data());
    h.resize(static_cast<std::size_t>(n));
    e.swap(h);
  }
  return e;
}

}  // namespace

TEST_CASE("the test's invariant checks accept valid and reject invalid expansions",
          "[predicates][exact]") {
  CHECK(invalid({}) == "");
  CHECK(invalid({1.0}) == "");
  CHECK(invalid({0x1p-60, 1.0, 0x1p60}) == "");
  CHECK(invalid({0.5, 1.0}) == "");  // non-overlapping, but adjacent
  CHECK(invalid({0.5, 1.0}, true) != "");
  CHECK(invalid({0.25, 1.0}, true) == "");
  CHECK(invalid({0.75, 1.5}) != "");  // overlap
  CHECK(invalid({0.75, 1.0}) == "");  // 0.11b and 1b do not overlap
  CHECK(invalid({1.0, 0.5}) != "");   // decreasing
  CHECK(invalid({0.0, 1.0}) != "");   // zero component
  CHECK(lsb(0x1p-1074) == -1074);
  CHECK(lsb(3.0) == 0);
  CHECK(lsb(0.75) == -2);
  CHECK(msb(0x1p-1074) == -1074);
}

TEST_CASE("error-free transformations on special values", "[predicates][exact]") {
  int failures = 0;
  for (double a : specials())
    for (double b : specials()) failures += check_error_free(a, b);
  CHECK(failures == 0);
  // Ties round to even: the error term carries what fl() dropped.
  double x = 0, y = 0;
  ex::two_sum(1.0, 0x1p-53, x, y);
  CHECK(x == 1.0);
  CHECK(y == 0x1p-53);
  ex::two_sum(1 + 0x1p-52, 0x1p-53, x, y);
  CHECK(x == 1 + 0x1p-51);
  CHECK(y == -0x1p-53);
  ex::two_product(1 + 0x1p-52, 1 + 0x1p-52, x, y);
  CHECK(x == 1 + 0x1p-51);
  CHECK(y == 0x1p-104);
  ex::two_product(0x1p-537, 0x1p-537, x, y);  // exactly representable: no error term
  CHECK(x == 0x1p-1074);
  CHECK(y == 0);
}

TEST_CASE("error-free transformations on random doubles of wide exponent range",
          "[predicates][exact]") {
  const std::uint64_t seed = seed_for(20);
  INFO("seed " << seed);
  Rng rng(seed);
  const std::size_t n = scaled(100000);
  int failures = 0;
  for (std::size_t i = 0; i < n && failures < 10; ++i) {
    const auto [a, b] = random_pair(rng);
    failures += check_error_free(a, b);
    const auto [c, d] = random_product_pair(rng);
    REQUIRE(product_safe(c, d));
    failures += check_error_free(c, d);
  }
  CHECK(failures == 0);
}

TEST_CASE("expansion_sum and expansion_diff are exact and keep the invariants",
          "[predicates][exact]") {
  const std::uint64_t seed = seed_for(21);
  INFO("seed " << seed);
  Rng rng(seed);
  const std::size_t n = scaled(20000);
  int failures = 0;
  for (std::size_t it = 0; it < n && failures < 10; ++it) {
    // Windows anywhere from the subnormals to 2^1000 (sums never overflow there).
    const int width = static_cast<int>(rand_int(rng, 0, 3)) == 0 ? 1200 : 150;
    const auto e =
        random_expansion(rng, static_cast<int>(rand_int(rng, 0, 12)), -1000, 1000, width);
    const auto f = coin(rng) ? random_expansion(rng, static_cast<int>(rand_int(rng, 0, 12)), -1000,
                                                1000, width)
                             : e;  // f == e: the difference cancels to the empty expansion
    const std::string e_bad = invalid(e), f_bad = invalid(f);
    if (!e_bad.empty() || !f_bad.empty()) {
      ++failures;
      FAIL_CHECK("expansion_sum built an invalid expansion: "
                 << hex_list(e) << " " << e_bad << " / " << hex_list(f) << " " << f_bad);
      continue;
    }
    const auto ne = static_cast<int>(e.size()), nf = static_cast<int>(f.size());
    const mpq_class ve = value(e), vf = value(f);
    for (int op = 0; op < 2; ++op) {
      Buffer h(e.size() + f.size());
      const int nh = op == 0 ? ex::expansion_sum(e.data(), ne, f.data(), nf, h.data())
                             : ex::expansion_diff(e.data(), ne, f.data(), nf, h.data());
      if (!h.guard_intact()) {
        ++failures;
        FAIL_CHECK((op == 0 ? "expansion_sum" : "expansion_diff")
                   << " wrote past ne + nf components: " << hex_list(e) << ", " << hex_list(f));
        continue;
      }
      const mpq_class want = op == 0 ? mpq_class(ve + vf) : mpq_class(ve - vf);
      const char* name = op == 0 ? "expansion_sum" : "expansion_diff";
      const bool length_ok = nh >= 0 && nh <= ne + nf;
      const std::string bad = length_ok ? invalid(h.data(), nh) : "bad length";
      if (!length_ok || !bad.empty() || value(h.data(), nh) != want ||
          ex::sign(h.data(), nh) != sgn(want)) {
        ++failures;
        FAIL_CHECK(name << "(" << hex_list(e) << ", " << hex_list(f)
                        << ") = " << (length_ok ? hex_list(h.data(), nh) : std::to_string(nh))
                        << " " << bad << "; exact " << want.get_str());
      }
    }
    if (ex::sign(e.data(), ne) != sgn(ve)) {
      ++failures;
      FAIL_CHECK("sign(" << hex_list(e) << ")");
    }
  }
  CHECK(failures == 0);
  // Empty operands.
  const double one = 1.0;
  double out[2] = {7, 7};
  CHECK(ex::expansion_sum(nullptr, 0, nullptr, 0, out) == 0);
  CHECK(ex::expansion_sum(&one, 1, nullptr, 0, out) == 1);
  CHECK(out[0] == 1.0);
  CHECK(ex::expansion_diff(nullptr, 0, &one, 1, out) == 1);
  CHECK(out[0] == -1.0);
  CHECK(ex::expansion_diff(&one, 1, &one, 1, out) == 0);
  CHECK(ex::sign(out, 0) == 0);
}

TEST_CASE("scale_expansion and expansion_product are exact and keep the invariants",
          "[predicates][exact]") {
  const std::uint64_t seed = seed_for(22);
  INFO("seed " << seed);
  Rng rng(seed);
  const std::size_t n = scaled(5000);
  int failures = 0;
  for (std::size_t it = 0; it < n && failures < 10; ++it) {
    // Exponents in [-320, 200]: products and their error terms stay normal and finite.
    const auto e = random_expansion(rng, static_cast<int>(rand_int(rng, 0, 10)), -200, 200, 120);
    const auto f = random_expansion(rng, static_cast<int>(rand_int(rng, 0, 10)), -200, 200, 120);
    const auto ne = static_cast<int>(e.size()), nf = static_cast<int>(f.size());
    const mpq_class ve = value(e), vf = value(f);
    {
      const double b = rng() % 8 == 0 ? 0.0 : random_wide(rng, -200, 200);
      Buffer h(2 * e.size());
      const int nh = ex::scale_expansion(e.data(), ne, b, h.data());
      if (!h.guard_intact()) {
        ++failures;
        FAIL_CHECK("scale_expansion wrote past 2 ne components: " << hex_list(e) << ", " << hex(b));
        continue;
      }
      const mpq_class want = ve * exact(b);
      const bool length_ok = nh >= 0 && nh <= 2 * ne;
      const std::string bad = length_ok ? invalid(h.data(), nh) : "bad length";
      if (!length_ok || !bad.empty() || value(h.data(), nh) != want ||
          ex::sign(h.data(), nh) != sgn(want)) {
        ++failures;
        FAIL_CHECK("scale_expansion(" << hex_list(e) << ", " << hex(b) << ") = "
                                      << (length_ok ? hex_list(h.data(), nh) : "?") << " " << bad);
      }
    }
    {
      // expansion.h: h needs room for 2 ne nf components, scratch for 2 ne nf + 2 ne.
      const std::size_t cap = 2 * e.size() * f.size();
      Buffer h(cap), scratch(cap + 2 * e.size());
      const int nh = ex::expansion_product(e.data(), ne, f.data(), nf, h.data(), scratch.data());
      if (!h.guard_intact() || !scratch.guard_intact()) {
        ++failures;
        FAIL_CHECK("expansion_product wrote past the documented size of "
                   << (h.guard_intact() ? "scratch" : "h") << ": " << hex_list(e) << ", "
                   << hex_list(f));
        continue;
      }
      const mpq_class want = ve * vf;
      const bool length_ok = nh >= 0 && nh <= 2 * ne * nf;
      const std::string bad = length_ok ? invalid(h.data(), nh) : "bad length";
      if (!length_ok || !bad.empty() || value(h.data(), nh) != want ||
          ex::sign(h.data(), nh) != sgn(want)) {
        ++failures;
        FAIL_CHECK("expansion_product(" << hex_list(e) << ", " << hex_list(f)
                                        << ") = " << (length_ok ? hex_list(h.data(), nh) : "?")
                                        << " " << bad);
      }
    }
  }
  CHECK(failures == 0);
}

TEST_CASE("regression: expansion_product writes only the documented scratch",
          "[predicates][exact][regression]") {
  // expansion.h: "h needs room for 2 * ne * nf components and scratch for 2 * ne * nf +
  // 2 * ne". Smallest case that needs a second partial product: ne = 1, nf = 2.
  const double e[1] = {1.0}, f[2] = {1.0, 0x1p60};
  Buffer h(4), scratch(6);
  const int n = ex::expansion_product(e, 1, f, 2, h.data(), scratch.data());
  CHECK(h.guard_intact());
  CHECK(scratch.guard_intact());
  REQUIRE(n == 2);
  CHECK(h[0] == 1.0);
  CHECK(h[1] == 0x1p60);
}

TEST_CASE("compress keeps the value, never grows, and leaves a non-adjacent expansion",
          "[predicates][exact]") {
  const std::uint64_t seed = seed_for(23);
  INFO("seed " << seed);
  Rng rng(seed);
  const std::size_t n = scaled(20000);
  int failures = 0;
  std::size_t shrunk = 0;
  for (std::size_t it = 0; it < n && failures < 10; ++it) {
    const int width = coin(rng) ? 150 : 1200;
    auto e = random_expansion(rng, static_cast<int>(rand_int(rng, 0, 16)), -1000, 1000, width);
    const std::vector<double> before = e;
    const mpq_class want = value(e);
    const int nh = ex::compress(e.data(), static_cast<int>(e.size()));
    const bool length_ok = nh >= 0 && nh <= static_cast<int>(before.size());
    const std::string bad = length_ok ? invalid(e.data(), nh, /*nonadjacent=*/true) : "bad length";
    bool ok = length_ok && bad.empty() && value(e.data(), nh) == want &&
              ex::sign(e.data(), nh) == sgn(want);
    // The largest component approximates the value to within one ulp.
    if (ok && nh > 0) {
      mpq_class err = want - exact(e[static_cast<std::size_t>(nh - 1)]);
      if (err < 0) err = -err;
      ok = err <= exact(ulp(e[static_cast<std::size_t>(nh - 1)]));
    }
    if (!ok) {
      ++failures;
      FAIL_CHECK("compress(" << hex_list(before)
                             << ") = " << (length_ok ? hex_list(e.data(), nh) : "?") << " " << bad);
    }
    if (length_ok && nh < static_cast<int>(before.size())) ++shrunk;
  }
  CHECK(failures == 0);
  CHECK(shrunk > 0);  // the family does contain compressible expansions
}

TEST_CASE("expansion operations on more and longer inputs", "[predicates][exact][.slow]") {
  const std::uint64_t seed = seed_for(24);
  INFO("seed " << seed);
  Rng rng(seed);
  int failures = 0;
  for (int it = 0; it < 20000 && failures < 10; ++it) {
    const auto e = random_expansion(rng, static_cast<int>(rand_int(rng, 0, 40)), -200, 200, 120);
    const auto f = random_expansion(rng, static_cast<int>(rand_int(rng, 0, 40)), -200, 200, 120);
    const auto ne = static_cast<int>(e.size()), nf = static_cast<int>(f.size());
    Buffer h(2 * e.size() * f.size()), scratch(2 * e.size() * f.size());
    int nh = ex::expansion_product(e.data(), ne, f.data(), nf, h.data(), scratch.data());
    if (!h.guard_intact() || !scratch.guard_intact() || !invalid(h.data(), nh).empty() ||
        value(h.data(), nh) != value(e) * value(f)) {
      ++failures;
      FAIL_CHECK("expansion_product(" << hex_list(e) << ", " << hex_list(f) << ")");
    }
    Buffer g(e.size() + f.size());
    nh = ex::expansion_sum(e.data(), ne, f.data(), nf, g.data());
    if (!g.guard_intact() || !invalid(g.data(), nh).empty() ||
        value(g.data(), nh) != value(e) + value(f)) {
      ++failures;
      FAIL_CHECK("expansion_sum(" << hex_list(e) << ", " << hex_list(f) << ")");
    }
  }
  CHECK(failures == 0);
}
