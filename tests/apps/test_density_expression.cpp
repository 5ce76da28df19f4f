// The command line's --density formulas (apps/density_options.cpp, issue 35): muparser's
// bytecode run by columns (Expression::evaluate) gives muparser's own Eval() bit for bit,
// and the batch density of make_density3 gives the cells of the same density evaluated point
// by point, with 1 and 2 threads.
#include <tbb/global_control.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "density_options.h"
#include "support/surfaces.h"
#include "support/threads.h"
#include "voroclip/clip.h"
#include "voroclip/core.h"

namespace {

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

std::vector<double> random_points(std::size_t n, int dimension, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 2);
  std::vector<double> p(n * static_cast<std::size_t>(dimension));
  for (double& v : p) v = u(rng);
  return p;
}

}  // namespace

TEST_CASE("--density formulas: evaluated by columns, muparser's values bit for bit",
          "[apps][density]") {
  struct Case {
    const char* text;
    bool compiled;  // run by columns (else muparser's Eval() point by point)
  };
  // No v^2 of a non-variable v here: muparser computes it with pow (below).
  const Case cases[] = {
      {"1", true},
      {"z", true},
      {"2*x+3*y-z/7", true},
      {"x^2 + y^3 + z^4 + 3*x*y", true},
      {"(x+1)^3 + (y+2)^0.5 + 2^x + (1+z*z)^(-1) + (x-y)^2.5", true},
      {"exp(0.5*x+0.3*y-0.2*z) * sqrt(x^2+y^2+z^2+1)", true},
      {"sin(x)*cos(y) + tan(z/4) + log(x+2) + abs(y) + _pi*_e", true},
      {"min(x, y, z) + max(x, 2) + sum(x, y, z, 1) + avg(x, y)", true},
      {"-x + (x < y) + (x >= z)*2 + (x != y) + (y == y) + (x <= 0.5 && y > 0.1) + (x > 2 || z < "
       "0.5)",
       true},
      {"x < 0.5 ? 1 + x : 2 - y", false},
  };
  const std::size_t n = 300;  // more than one block of the column program
  const std::vector<double> p = random_points(n, 3, 3501);
  for (const Case& c : cases) {
    INFO(c.text);
    const voroclip::cli::Expression e(c.text, 3, "--density");
    REQUIRE(e.compiled() == c.compiled);
    std::vector<double> out(n);
    e.evaluate(p.data(), n, out.data());
    for (std::size_t k = 0; k < n; ++k) {
      INFO("point " << k);
      const double ref = e.parser_value(p.data() + 3 * k);
      REQUIRE(same_bits(out[k], ref));
      REQUIRE(same_bits(e(p.data() + 3 * k), ref));
    }
  }
  // v^2 is v * v, the correctly rounded square (as muparser's own x^2 of a variable), where
  // muparser's (x-0.5)^2 calls pow, whose result is one ulp off for about 1 square in 1000
  // (glibc): the C++ formula with products is the reference.
  const voroclip::cli::Expression sq("1/(0.01+(x-0.5)^2+y^2)", 3, "--density");
  REQUIRE(sq.compiled());
  std::vector<double> out(n);
  sq.evaluate(p.data(), n, out.data());
  for (std::size_t k = 0; k < n; ++k) {
    const double x = p[3 * k], y = p[3 * k + 1];
    const double ref = 1 / (0.01 + (x - 0.5) * (x - 0.5) + y * y);
    REQUIRE(same_bits(out[k], ref));
    REQUIRE(same_bits(sq(p.data() + 3 * k), ref));
    REQUIRE(std::fabs(sq.parser_value(p.data() + 3 * k) - ref) <= 4e-16 * ref);
  }
  // 2D: two coordinates per point.
  const std::vector<double> q = random_points(n, 2, 3502);
  const voroclip::cli::Expression e2("x*y + (x-1)^3 + 1", 2, "--density");
  REQUIRE(e2.compiled());
  e2.evaluate(q.data(), n, out.data());
  for (std::size_t k = 0; k < n; ++k) REQUIRE(same_bits(out[k], e2.parser_value(q.data() + 2 * k)));
}

TEST_CASE("--density in batches: the cells of the point-by-point density, 1 and 2 threads",
          "[apps][density][threads]") {
  const voroclip::Domain3 box(voroclip_test::box_surface({0, 0, 0}, {1, 1, 1}));
  const std::uint32_t n = 300;
  std::vector<double> sites = random_points(n, 3, 3503);
  for (double& v : sites) v = (v + 1) / 3;  // in the box
  voroclip::cli::DensityArgs args;
  args.density = "1/(0.01+(x-0.5)^2+y^2)";
  const voroclip::Density3 batch = voroclip::cli::make_density3(args, box);
  REQUIRE(batch.batch);
  // The same formula in C++: muparser's x - 0.5 is x * 1 + (-0.5) and its v^2 is v * v, the
  // same bits.
  const voroclip::Density3 cpp = voroclip::Density3::function(
      [](double x, double y, double) { return 1 / (0.01 + (x - 0.5) * (x - 0.5) + y * y); });
  for (const auto rule :
       {voroclip::Density3::Rule::kDegree5, voroclip::Density3::Rule::kQuadratic}) {
    INFO("rule " << static_cast<int>(rule));
    voroclip::Clip3Options ob, oc;
    ob.density = batch;
    ob.density.rule = rule;
    oc.density = cpp;
    oc.density.rule = rule;
    voroclip::ClippedVoronoi3 one, two, ref;
    {
      tbb::global_control g(tbb::global_control::max_allowed_parallelism, 1);
      one.compute(box, sites.data(), n, ob);
    }
    {
      tbb::global_control g(tbb::global_control::max_allowed_parallelism,
                            voroclip_test::test_threads());
      two.compute(box, sites.data(), n, ob);
      ref.compute(box, sites.data(), n, oc);
    }
    for (std::uint32_t i = 0; i < n; ++i) {
      INFO("cell " << i);
      REQUIRE(one.mass(i) > 0);
      REQUIRE(same_bits(one.mass(i), two.mass(i)));
      REQUIRE(same_bits(one.mass(i), ref.mass(i)));
      REQUIRE(same_bits(one.energy(i), ref.energy(i)));
      for (int c = 0; c < 3; ++c) REQUIRE(same_bits(one.centroid(i)[c], ref.centroid(i)[c]));
    }
  }
  // A value that is not positive stops the computation with the point, from a batch too.
  args.density = "x - 0.5";
  voroclip::Clip3Options bad;
  bad.density = voroclip::cli::make_density3(args, box);
  voroclip::ClippedVoronoi3 cv;
  CHECK_THROWS_WITH(cv.compute(box, sites.data(), n, bad),
                    Catch::Contains("--density \"x - 0.5\" is") &&
                        Catch::Contains("must be finite and positive"));
}
