// The static-filter overloads: same signs as the plain predicates (checked against GMP
// elsewhere and, on a sample, here), real decisions by the static bound, and a disabled
// bound for boxes whose extents leave the safe range.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "exact_oracle.h"
#include "voroclip/core.h"
#include "voroclip/predicates.h"

using namespace voroclip;
using namespace voroclip::test;

namespace {

Sign eval_static(Pred pred, const Input& in, const StaticFilter& f) {
  const auto& p = in.p;
  switch (pred) {
    case Pred::orient2d:
      return orient2d(p[0].data(), p[1].data(), p[2].data(), f);
    case Pred::incircle:
      return incircle(p[0].data(), p[1].data(), p[2].data(), p[3].data(), f);
    case Pred::orient3d:
      return orient3d(p[0].data(), p[1].data(), p[2].data(), p[3].data(), f);
    case Pred::insphere:
      return insphere(p[0].data(), p[1].data(), p[2].data(), p[3].data(), p[4].data(), f);
  }
  return Sign::zero;
}

double bound_of(Pred pred, const StaticFilter& f) {
  switch (pred) {
    case Pred::orient2d:
      return f.orient2d_bound();
    case Pred::incircle:
      return f.incircle_bound();
    case Pred::orient3d:
      return f.orient3d_bound();
    case Pred::insphere:
      return f.insphere_bound();
  }
  return 0;
}

// The filter of the box spanned by the points of `in` (a box containing them).
StaticFilter box_of(Pred pred, const Input& in) {
  const PredInfo pi = info(pred);
  std::vector<double> coords;
  for (int k = 0; k < pi.k; ++k) {
    for (int j = 0; j < pi.d; ++j)
      coords.push_back(in.p[static_cast<std::size_t>(k)][static_cast<std::size_t>(j)]);
  }
  return StaticFilter::bounding(coords.data(), static_cast<std::size_t>(pi.k), pi.d);
}

}  // namespace

TEST_CASE("static-filter overloads agree with the exact predicates", "[predicates][exact]") {
  const std::uint64_t seed = seed_for(0x57a71c);
  INFO("seed " << seed);
  Rng rng(seed);
  const double lo[3] = {-1, -1, -1}, hi[3] = {1, 1, 1};
  const StaticFilter unit2(lo, hi, 2), unit3(lo, hi, 3);
  for (const Pred pred : kAllPreds) {
    const StaticFilter& unit = info(pred).d == 2 ? unit2 : unit3;
    REQUIRE(bound_of(pred, unit) < 1e-10);  // enabled
    std::size_t checked = 0, failures = 0;
    const std::size_t n = scaled(20000);
    for (std::size_t i = 0; i < n; ++i) {
      // Random points of [-1,1]^d, near-degenerate and exactly degenerate families, all
      // inside the unit box, each with the unit box's filter and with its own tight box.
      Input in = i % 3 == 0
                     ? random_box(pred, rng)
                     : (i % 3 == 1 ? near_degenerate(pred, rng) : exactly_degenerate(pred, rng));
      bool inside = true;
      for (int k = 0; k < info(pred).k; ++k) {
        for (int j = 0; j < info(pred).d; ++j) {
          const double x = in.p[static_cast<std::size_t>(k)][static_cast<std::size_t>(j)];
          inside = inside && x >= -1 && x <= 1;
        }
      }
      const Sign plain = eval(pred, in);
      if (inside) {
        ++checked;
        if (eval_static(pred, in, unit) != plain) ++failures;
      }
      const StaticFilter tight = box_of(pred, in);
      if (eval_static(pred, in, tight) != plain) ++failures;
      if (i % 97 == 0 && to_int(eval_static(pred, in, tight)) != oracle_sign(pred, in)) ++failures;
    }
    INFO(info(pred).name << ": " << checked << " calls inside the unit box");
    CHECK(checked > n / 2);
    CHECK(failures == 0);
  }
}

TEST_CASE("the static bound decides random input on its own", "[predicates]") {
  // On uniform random points of the unit box the static bound must decide (almost) every
  // call: it is what makes the overloads cheap. Checked through the bound itself.
  Rng rng(seed_for(0xb0c5));
  const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
  const StaticFilter f2(lo, hi, 2), f3(lo, hi, 3);
  std::size_t decided = 0, total = 0;
  for (int i = 0; i < 10000; ++i) {
    double p[5][3];
    for (auto& q : p)
      for (double& x : q) x = u01(rng);
    total += 4;
    decided += std::fabs(detail::orient2d_approx(p[0], p[1], p[2]).det) > f2.orient2d_bound();
    decided += std::fabs(detail::incircle_approx(p[0], p[1], p[2], p[3]).det) > f2.incircle_bound();
    decided += std::fabs(detail::orient3d_approx(p[0], p[1], p[2], p[3]).det) > f3.orient3d_bound();
    decided +=
        std::fabs(detail::insphere_approx(p[0], p[1], p[2], p[3], p[4]).det) > f3.insphere_bound();
  }
  CHECK(decided > total * 99 / 100);
}

TEST_CASE("static filter: disabled outside the safe range, errors on bad boxes", "[predicates]") {
  const double lo[3] = {0, 0, 0};
  const double flat[3] = {1, 1, 0};  // zero z extent: orient3d/insphere bounds disabled
  const StaticFilter f(lo, flat, 3);
  CHECK(f.orient2d_bound() < 1);
  CHECK(f.orient3d_bound() == std::numeric_limits<double>::infinity());
  CHECK(f.insphere_bound() == std::numeric_limits<double>::infinity());
  const double huge[3] = {0x1p400, 0x1p400, 0x1p400};
  const StaticFilter g(lo, huge, 3);
  CHECK(g.orient3d_bound() == std::numeric_limits<double>::infinity());
  // A disabled filter still gives exact answers (through the semi-static path).
  const double a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, c[3] = {0, 1, 0}, d[3] = {0, 0, 1};
  CHECK(orient3d(a, b, c, d, g) == orient3d(a, b, c, d));
  CHECK(orient3d(a, b, c, d, StaticFilter()) == orient3d(a, b, c, d));
  const double bad_hi[3] = {-1, 1, 1};
  CHECK_THROWS_AS(StaticFilter(lo, bad_hi, 3), Error);
  const double nan_hi[3] = {1, std::nan(""), 1};
  CHECK_THROWS_AS(StaticFilter(lo, nan_hi, 3), Error);
  CHECK_THROWS_AS(StaticFilter(lo, flat, 4), Error);
}
