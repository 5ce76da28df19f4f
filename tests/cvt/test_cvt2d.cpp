// Tests of the 2D CVT (voroclip/cvt.h): the gradient against finite differences of the
// energy, known minimisers, monotone Lloyd, constraints, cancellation, determinism.
#include <catch2/catch.hpp>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "support/threads.h"
#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/cvt.h"

using voroclip::Cvt2Options;
using voroclip::CvtMethod;
using voroclip::Domain2;
using voroclip::PolygonRings;

namespace {

PolygonRings rings_of(const std::vector<std::vector<double>>& rings) {
  PolygonRings p;
  p.source = "test";
  p.ring_begin.push_back(0);
  for (const auto& r : rings) {
    p.xy.insert(p.xy.end(), r.begin(), r.end());
    p.ring_begin.push_back(static_cast<std::uint32_t>(p.xy.size() / 2));
    p.ring_polygon.push_back(0);
    p.ring_line.push_back(0);
  }
  return p;
}

std::vector<double> square(double x0, double y0, double x1, double y1) {
  return {x0, y0, x1, y0, x1, y1, x0, y1};
}

std::vector<double> random_inside(const Domain2& d, std::uint32_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> ux(d.bbox_lo()[0], d.bbox_hi()[0]);
  std::uniform_real_distribution<double> uy(d.bbox_lo()[1], d.bbox_hi()[1]);
  std::vector<double> xy;
  while (xy.size() < 2 * std::size_t{n}) {
    const double p[2] = {ux(rng), uy(rng)};
    if (d.locate(p) == voroclip::Sign::positive) xy.insert(xy.end(), p, p + 2);
  }
  return xy;
}

}  // namespace

TEST_CASE("cvt2d: gradient equals finite differences of the energy", "[cvt]") {
  const Domain2 d(rings_of({square(0, 0, 1, 1), square(0.3, 0.3, 0.55, 0.6)}));
  for (const auto& density :
       {voroclip::Density2::constant(1.0),
        voroclip::Density2::function([](double x, double y) { return 1 + x * x + 2 * y; })}) {
    const std::vector<double> sites = random_inside(d, 60, 4);
    std::vector<double> g;
    voroclip::cvt_energy2(d, sites, density, &g);
    const double h = 1e-6;
    double max_err = 0, max_g = 0;
    for (std::size_t k = 0; k < sites.size(); ++k) {
      std::vector<double> plus = sites, minus = sites;
      plus[k] += h;
      minus[k] -= h;
      const double fd =
          (voroclip::cvt_energy2(d, plus, density) - voroclip::cvt_energy2(d, minus, density)) /
          (2 * h);
      max_err = std::max(max_err, std::fabs(fd - g[k]));
      max_g = std::max(max_g, std::fabs(g[k]));
    }
    INFO("max |fd - g| = " << max_err << ", max |g| = " << max_g);
    REQUIRE(max_g > 0);
    REQUIRE(max_err <= 1e-6 * max_g + 1e-9);
  }
}

TEST_CASE("cvt2d: known minimisers", "[cvt]") {
  // Six sites in [0, 3] x [0, 2] started near the 3 x 2 grid of unit-square centres converge
  // to it. Four sites in the unit square: the 2 x 2 grid.
  const Domain2 rect(rings_of({square(0, 0, 3, 2)}));
  const Domain2 unit(rings_of({square(0, 0, 1, 1)}));
  for (const CvtMethod method : {CvtMethod::kLbfgs, CvtMethod::kLloyd}) {
    Cvt2Options o;
    o.method = method;
    o.max_iterations = 500;
    // The energy is known to ~1e-17 relative; the line search cannot resolve gradients
    // much below sqrt of that.
    o.gradient_tolerance = 1e-6;
    INFO((method == CvtMethod::kLloyd ? "Lloyd" : "L-BFGS"));
    std::vector<double> six = {0.6, 0.4, 1.45, 0.58, 2.4, 0.45, 0.55, 1.6, 1.4, 1.45, 2.58, 1.55};
    const auto r6 = voroclip::optimize_cvt2(rect, six, o);
    REQUIRE(r6.converged);
    for (int k = 0; k < 6; ++k) {
      REQUIRE(std::fabs(six[2 * k] - (0.5 + k % 3)) < 1e-5);
      REQUIRE(std::fabs(six[2 * k + 1] - (0.5 + k / 3)) < 1e-5);
    }
    std::vector<double> four = {0.2, 0.3, 0.7, 0.2, 0.8, 0.7, 0.3, 0.9};
    const auto r4 = voroclip::optimize_cvt2(unit, four, o);
    REQUIRE(r4.converged);
    // Energy of the 2 x 2 grid: 4 squares of side 1/2, each ∫|x - c|^2 = (1/2)^4 / 6.
    REQUIRE(std::fabs(r4.energy - 4 * 0.0625 / 6) < 1e-11);
  }
}

TEST_CASE("cvt2d: Lloyd decreases the energy; L-BFGS reaches the tolerance", "[cvt]") {
  const Domain2 d(voroclip::annulus_rings(0.4, 1.0, 64));
  std::vector<double> sites = random_inside(d, 300, 11);
  std::vector<double> energies;
  Cvt2Options o;
  o.method = CvtMethod::kLloyd;
  o.max_iterations = 30;
  o.gradient_tolerance = 0;
  o.progress = [&](const voroclip::CvtProgress& p) {
    energies.push_back(p.energy);
    return true;
  };
  std::vector<double> lloyd = sites;
  const auto rl = voroclip::optimize_cvt2(d, lloyd, o);
  REQUIRE(rl.iterations == 30);
  REQUIRE(energies.size() == 31);
  for (std::size_t k = 1; k < energies.size(); ++k) REQUIRE(energies[k] <= energies[k - 1]);

  Cvt2Options ob;
  ob.max_iterations = 300;
  ob.gradient_tolerance = 1e-3;
  std::vector<double> lbfgs = sites;
  const auto rb = voroclip::optimize_cvt2(d, lbfgs, ob);
  REQUIRE(rb.converged);
  REQUIRE(rb.gradient_norm <= 1e-3 * rb.initial_gradient_norm);
  REQUIRE(rb.energy < energies.front());
}

TEST_CASE("cvt2d: sliding and fixed sites", "[cvt]") {
  const Domain2 d(rings_of({square(0, 0, 1, 1)}));
  std::vector<std::uint32_t> corners;
  const auto paths = voroclip::boundary_paths(d, 30.0, &corners);
  REQUIRE(corners.size() == 4);
  REQUIRE(paths.size() == 4);
  std::vector<double> sites = random_inside(d, 40, 2);
  Cvt2Options o;
  o.paths = paths;
  o.constraints.assign(40 + 4 + 8, {});
  // The corners fixed; two sites sliding on each side.
  for (std::uint32_t c = 0; c < 4; ++c) {
    sites.insert(sites.end(), d.vertex(corners[c]), d.vertex(corners[c]) + 2);
    o.constraints[40 + c].kind = voroclip::SiteConstraint2::Kind::kFixed;
  }
  for (std::uint32_t p = 0; p < 4; ++p) {
    const voroclip::PathParam2 param(d, paths[p]);
    for (const double s : {0.3, 0.6}) {
      double xy[2];
      param.eval(s * param.length(), xy);
      sites.insert(sites.end(), xy, xy + 2);
      o.constraints[44 + 2 * p + (s > 0.5 ? 1 : 0)] = {voroclip::SiteConstraint2::Kind::kSlide, p};
    }
  }
  const std::vector<double> start = sites;
  o.max_iterations = 200;
  const auto r = voroclip::optimize_cvt2(d, sites, o);
  REQUIRE(r.iterations > 0);
  for (std::uint32_t c = 0; c < 4; ++c) {
    REQUIRE(sites[2 * (40 + c)] == start[2 * (40 + c)]);
    REQUIRE(sites[2 * (40 + c) + 1] == start[2 * (40 + c) + 1]);
  }
  for (std::uint32_t k = 44; k < 52; ++k) {
    const double x = sites[2 * k], y = sites[2 * k + 1];
    // On the boundary of the unit square, within its side.
    const double dist = std::min(std::min(std::fabs(x), std::fabs(1 - x)),
                                 std::min(std::fabs(y), std::fabs(1 - y)));
    REQUIRE(dist < 1e-15);
    REQUIRE(x >= 0);
    REQUIRE(x <= 1);
    REQUIRE(y >= 0);
    REQUIRE(y <= 1);
  }
}

TEST_CASE("cvt2d: cancel from the progress callback; identical with 1 and 2 threads",
          "[cvt][threads]") {
  const Domain2 d(voroclip::square_with_holes(3, 0.4));
  const std::vector<double> sites = random_inside(d, 500, 3);
  Cvt2Options o;
  o.progress = [](const voroclip::CvtProgress& p) { return p.iteration < 3; };
  std::vector<double> s = sites;
  const auto r = voroclip::optimize_cvt2(d, s, o);
  REQUIRE(r.cancelled);
  REQUIRE(r.iterations == 3);

  Cvt2Options od;
  od.max_iterations = 15;
  std::vector<double> one = sites, two = sites;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    voroclip::optimize_cvt2(d, one, od);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism,
                          voroclip_test::test_threads());
    voroclip::optimize_cvt2(d, two, od);
  }
  REQUIRE(one == two);
}

namespace {

// The rings of `p` with every coordinate times k.
PolygonRings scaled(PolygonRings p, double k) {
  for (double& x : p.xy) x *= k;
  return p;
}

}  // namespace

TEST_CASE("cvt2d: L-BFGS does not depend on the domain's units", "[cvt]") {
  // earcut.json is 14,000 units wide: L-BFGS-B's first step (one unit along the normalised
  // gradient) used to be tiny there, and its line search gave up after 30 small
  // extrapolations ("no progress" at |g|/|g0| 0.91), while the same polygon at 1/1000 of the
  // size converged.
  const PolygonRings rings =
      voroclip::read_polygon(std::string(VOROCLIP_SHARED_DATA_DIR) + "/polygons/valid/earcut.json");
  const double k = 1e-3;
  const Domain2 big(rings), small(scaled(rings, k));
  std::vector<double> a = random_inside(big, 2000, 5);
  std::vector<double> b = a;
  for (double& x : b) x *= k;
  const auto ra = voroclip::optimize_cvt2(big, a, Cvt2Options{});
  const auto rb = voroclip::optimize_cvt2(small, b, Cvt2Options{});
  REQUIRE(ra.converged);
  REQUIRE(rb.converged);
  // Energies scale as length^4; both minima agree to the tolerance's order.
  REQUIRE(std::fabs(ra.energy * k * k * k * k - rb.energy) <= 1e-3 * rb.energy);
}

TEST_CASE("cvt2d: the default budget reaches the default tolerance on the shared polygons",
          "[cvt]") {
  for (const char* name : {"building", "dude", "earcut", "eberly-6", "hilbert", "issue29",
                           "issue34", "issue35", "issue52"}) {
    INFO(name);
    const Domain2 d(voroclip::read_polygon(std::string(VOROCLIP_SHARED_DATA_DIR) +
                                           "/polygons/valid/" + name + ".json"));
    std::vector<double> sites = random_inside(d, 1000, 3);
    const auto r = voroclip::optimize_cvt2(d, sites, Cvt2Options{});
    CHECK(r.converged);
    CHECK(r.stop == voroclip::CvtStop::kConverged);
  }
}

TEST_CASE("cvt2d: a scale sweep 2^-60 .. 2^60, the same run in every unit", "[cvt][regression]") {
  // The gradient in L-BFGS-B's variables scaled as the fourth power of the units: at 2^-20
  // LBFGSpp's projected gradient rounded to 0 against the variables, the solver returned
  // without a step and the run reported 0 iterations, stopped by the "iteration budget" of
  // 30. The energy is now scaled by a power of two too, so that with powers of two the
  // run is the same, bit for bit, in every unit, with and without preconditioning.
  const PolygonRings l_shape = rings_of({{0, 0, 1, 0, 1, 0.6, 0.4, 0.6, 0.4, 1, 0, 1}});
  const Domain2 unit(l_shape);
  const std::vector<double> start = random_inside(unit, 300, 11);
  for (const bool precondition : {false, true}) {
    Cvt2Options o;
    o.max_iterations = 30;
    o.precondition = precondition;
    std::vector<double> reference = start;
    const auto r0 = voroclip::optimize_cvt2(unit, reference, o);
    REQUIRE(r0.iterations == 30);
    REQUIRE(r0.stop == voroclip::CvtStop::kIterationBudget);
    REQUIRE(r0.gradient_norm < 0.1 * r0.initial_gradient_norm);
    for (const int e : {-60, -40, -20, -1, 1, 20, 40, 60}) {
      INFO("precondition " << precondition << ", scale 2^" << e);
      const double k = std::ldexp(1.0, e);
      const Domain2 d(scaled(l_shape, k));
      std::vector<double> sites = start;
      for (double& x : sites) x *= k;
      const auto r = voroclip::optimize_cvt2(d, sites, o);
      CHECK(r.iterations == r0.iterations);
      CHECK(r.evaluations == r0.evaluations);
      CHECK(r.stop == r0.stop);
      CHECK(r.gradient_norm / r.initial_gradient_norm ==
            r0.gradient_norm / r0.initial_gradient_norm);
      std::size_t same = 0;
      for (std::size_t i = 0; i < sites.size(); ++i) same += sites[i] == reference[i] * k ? 1 : 0;
      CHECK(same == sites.size());
    }
  }
}

TEST_CASE("cvt2d: a domain scaled by 2^+-180 and 2^+-200 runs as in unit size",
          "[cvt][regression]") {
  // The gradient grows as L^3 for a domain of size L and its norm summed the squares: they
  // overflowed from 2^170 (|g| inf) and underflowed below 2^-170 (|g| 0), and the run
  // stopped "converged" at iteration 0 with the sites unchanged. The squares are now summed
  // scaled by a power of two (projected_norm, set_uniform_scale, set_scales), exactly. (The
  // clipped cells there are no longer the unit domain's scaled bit for bit, so the runs
  // differ in the last bits.)
  const PolygonRings l_shape = rings_of({{0, 0, 1, 0, 1, 0.6, 0.4, 0.6, 0.4, 1, 0, 1}});
  const Domain2 unit(l_shape);
  const std::vector<double> start = random_inside(unit, 300, 11);
  for (const bool precondition : {false, true}) {
    Cvt2Options o;
    o.max_iterations = 30;
    o.precondition = precondition;
    std::vector<double> reference = start;
    const auto r0 = voroclip::optimize_cvt2(unit, reference, o);
    REQUIRE(r0.iterations == 30);
    REQUIRE(r0.gradient_norm < 0.1 * r0.initial_gradient_norm);
    for (const int e : {-200, -180, 180, 200}) {
      INFO("precondition " << precondition << ", scale 2^" << e);
      const double k = std::ldexp(1.0, e);
      const Domain2 d(scaled(l_shape, k));
      std::vector<double> sites = start;
      for (double& x : sites) x *= k;
      const auto r = voroclip::optimize_cvt2(d, sites, o);
      CHECK(r.iterations == r0.iterations);
      CHECK(r.stop == voroclip::CvtStop::kIterationBudget);
      CHECK(std::ldexp(r.initial_gradient_norm, -3 * e) ==
            Approx(r0.initial_gradient_norm).epsilon(1e-12));
      CHECK(std::ldexp(r.energy, -4 * e) == Approx(r0.energy).epsilon(1e-3));
      CHECK(r.gradient_norm < 0.1 * r.initial_gradient_norm);
    }
  }
}

TEST_CASE("cvt2d: a domain too small or too large for double precision is an error",
          "[cvt][regression]") {
  // A square scaled by 2^-300 has an area (2^-600) but its energy (L^4 = 2^-1200) is 0:
  // the run said "converged" at iteration 0; by 2^300 the energy overflows (inf, and the
  // run said "converged" as well).
  for (const int e : {-300, 300}) {
    INFO("scale 2^" << e);
    const double k = std::ldexp(1.0, e);
    const Domain2 d(rings_of({square(0, 0, k, k)}));
    for (const CvtMethod method : {CvtMethod::kLbfgs, CvtMethod::kLloyd}) {
      std::vector<double> sites = {0.25 * k, 0.5 * k, 0.75 * k, 0.5 * k, 0.5 * k, 0.8 * k};
      Cvt2Options o;
      o.method = method;
      REQUIRE_THROWS_AS(voroclip::optimize_cvt2(d, sites, o), voroclip::Error);
      REQUIRE_THROWS_WITH(
          voroclip::optimize_cvt2(d, sites, o),
          Catch::Contains("cvt2d: test (") &&
              Catch::Contains(e < 0 ? "the CVT energy of the start sites is 0 "
                                    : "the CVT energy of the start sites is NaN ") &&
              Catch::Contains(e < 0 ? "too small" : "too large") &&
              Catch::Contains("rescale the model"));
    }
  }
}

TEST_CASE("cvt2d: 0 iterations return the start, evaluated once", "[cvt][regression]") {
  // LBFGSpp takes max_iterations = 0 for "no limit", and the budget was tested after the
  // first accepted point: L-BFGS made one iteration and moved the sites.
  const Domain2 d(rings_of({square(0, 0, 1, 1)}));
  const std::vector<double> start = random_inside(d, 40, 4);
  std::vector<double> gradient;
  const double energy = voroclip::cvt_energy2(d, start, {}, &gradient);
  double g2 = 0;
  for (const double g : gradient) g2 += g * g;
  for (const CvtMethod method : {CvtMethod::kLbfgs, CvtMethod::kLloyd}) {
    for (const bool precondition : {false, true}) {
      INFO("method " << (method == CvtMethod::kLbfgs ? "lbfgs" : "lloyd") << ", precondition "
                     << precondition);
      std::vector<double> sites = start;
      Cvt2Options o;
      o.method = method;
      o.precondition = precondition;
      o.max_iterations = 0;
      const auto r = voroclip::optimize_cvt2(d, sites, o);
      CHECK(sites == start);
      CHECK(r.iterations == 0);
      CHECK(r.evaluations == 1);
      CHECK(r.stop == voroclip::CvtStop::kIterationBudget);
      CHECK(!r.converged);
      CHECK(r.energy == energy);
      CHECK(r.gradient_norm == r.initial_gradient_norm);
      CHECK(r.gradient_norm == Approx(std::sqrt(g2)).epsilon(1e-14));
    }
  }
}

TEST_CASE("random_points2: uniform, or drawn with the density, strictly inside", "[cvt][density]") {
  // The unit square with a hole [0.4, 0.6]^2.
  const Domain2 d(rings_of({square(0, 0, 1, 1), square(0.4, 0.4, 0.6, 0.6)}));
  const std::uint32_t n = 20000;
  const auto left_fraction = [&](const std::vector<double>& xy) {
    REQUIRE(xy.size() == 2 * std::size_t{n});
    std::size_t left = 0;
    for (std::size_t i = 0; i < n; ++i) {
      CHECK(d.locate(&xy[2 * i]) == voroclip::Sign::positive);
      left += xy[2 * i] < 0.5;
    }
    return static_cast<double>(left) / n;
  };
  // Constant: the candidates of the bounding box kept when inside, u then v from
  // mt19937_64 turned into doubles bit by bit (the CLI's --random sites, as they were).
  const std::vector<double> uniform = voroclip::random_points2(d, n, 5);
  std::mt19937_64 rng(5);
  std::vector<double> expected;
  while (expected.size() < uniform.size()) {
    const double u = static_cast<double>(rng() >> 11) * 0x1p-53;
    const double v = static_cast<double>(rng() >> 11) * 0x1p-53;
    const double p[2] = {u, v};
    if (d.locate(p) == voroclip::Sign::positive) expected.insert(expected.end(), p, p + 2);
  }
  CHECK(uniform == expected);
  CHECK(voroclip::random_points2(d, n, 6) != uniform);
  // The hole is symmetric about x = 0.5: half the points on each side (sigma 0.0035).
  CHECK(left_fraction(uniform) == Approx(0.5).margin(0.015));
  // rho = 1 + 10x, as a function and as a grid: the mass left of x = 0.5 over the whole,
  // (1.75 - 0.11) / (6 - 0.24) = 0.28472 (the hole's masses 0.11 and 0.24).
  const double lo[2] = {0, 0}, hi[2] = {1, 1};
  for (const voroclip::Density2& rho :
       {voroclip::Density2::function([](double x, double) { return 1 + 10 * x; }),
        voroclip::Density2::linear_grid(2, 2, lo, hi, {1, 11, 1, 11})}) {
    CHECK(left_fraction(voroclip::random_points2(d, n, 5, rho)) ==
          Approx(1.64 / 5.76).margin(0.015));
  }
  // A density that is not positive is named where it fails.
  CHECK_THROWS_WITH(
      voroclip::random_points2(
          d, 100, 5, voroclip::Density2::function([](double x, double) { return x - 0.5; })),
      Catch::Contains("random_points2: the density is -") &&
          Catch::Contains("it must be finite and positive in the domain"));
  voroclip::Density2 empty;
  empty.kind = voroclip::Density2::Kind::kCallback;
  CHECK_THROWS_WITH(voroclip::random_points2(d, 100, 5, empty),
                    Catch::Contains("the density function is empty"));
}

TEST_CASE("cvt2d: one site, and two sites, converge (no triangulation of their own)",
          "[cvt][degenerate]") {
  // One site goes to the domain's centroid; two sites on a horizontal line in [0, 2] x [0, 1]
  // stay on it (the gradient has no vertical part) and converge to (0.5, 0.5), (1.5, 0.5).
  // Both used to fail in Delaunay2 ("at least 3 affinely independent points").
  const Domain2 holed(rings_of({square(0, 0, 1, 1), square(0.1, 0.6, 0.3, 0.9)}));
  const Domain2 rect(rings_of({square(0, 0, 2, 1)}));
  for (const CvtMethod method : {CvtMethod::kLbfgs, CvtMethod::kLloyd}) {
    INFO((method == CvtMethod::kLloyd ? "Lloyd" : "L-BFGS"));
    Cvt2Options o;
    o.method = method;
    o.max_iterations = 200;
    o.gradient_tolerance = 1e-9;
    std::vector<double> one = {0.8, 0.1};
    const auto r1 = voroclip::optimize_cvt2(holed, one, o);
    CHECK(r1.converged);
    CHECK(std::fabs(one[0] - (0.5 - 0.06 * 0.2) / 0.94) < 1e-9);
    CHECK(std::fabs(one[1] - (0.5 - 0.06 * 0.75) / 0.94) < 1e-9);
    std::vector<double> two = {0.2, 0.5, 1.1, 0.5};
    const auto r2 = voroclip::optimize_cvt2(rect, two, o);
    CHECK(r2.converged);
    CHECK(std::fabs(two[0] - 0.5) < 1e-7);
    CHECK(std::fabs(two[2] - 1.5) < 1e-7);
    CHECK(two[1] == 0.5);
    CHECK(two[3] == 0.5);
    // Energy: two unit squares, each ∫|x - c|^2 = 1 / 6.
    CHECK(std::fabs(r2.energy - 2.0 / 6) < 1e-12);
  }
}
