// Tests of the 3D CVT (voroclip/cvt.h): the gradient against central differences of the
// energy (constant and linear density), a known minimiser, Lloyd decreasing the energy,
// sites constrained to a plane and a line, cancellation, 1 vs 2 threads, the sampler.
#include <catch2/catch.hpp>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "support/threads.h"
#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/cvt.h"

using voroclip::Cvt3Options;
using voroclip::CvtMethod;
using voroclip::Domain3;
using Kind3 = voroclip::SiteConstraint3::Kind;

namespace {

// [0, k]^3 cut into k^3 unit cubes of 6 tets each (Kuhn's triangulation: conforming).
voroclip::TetMeshInput kuhn_cube(std::uint32_t k, double scale = 1.0) {
  voroclip::TetMeshInput m;
  m.source = "cube";
  const auto id = [&](std::uint32_t x, std::uint32_t y, std::uint32_t z) {
    return (z * (k + 1) + y) * (k + 1) + x;
  };
  for (std::uint32_t z = 0; z <= k; ++z) {
    for (std::uint32_t y = 0; y <= k; ++y) {
      for (std::uint32_t x = 0; x <= k; ++x) {
        m.xyz.insert(m.xyz.end(), {scale * x, scale * y, scale * z});
      }
    }
  }
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (std::uint32_t z = 0; z < k; ++z) {
    for (std::uint32_t y = 0; y < k; ++y) {
      for (std::uint32_t x = 0; x < k; ++x) {
        for (const auto& p : perms) {
          std::uint32_t c[3] = {x, y, z};
          std::uint32_t tet[4];
          tet[0] = id(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[p[s]];
            tet[s + 1] = id(c[0], c[1], c[2]);
          }
          m.tets.insert(m.tets.end(), tet, tet + 4);
          m.tet_line.push_back(0);
        }
      }
    }
  }
  return m;
}

// Central differences of the energy along every coordinate against the gradient.
void check_gradient(const Domain3& d, const std::vector<double>& sites,
                    const voroclip::Clip3Options& o) {
  std::vector<double> g;
  voroclip::cvt_energy3(d, sites, o, &g);
  const double h = 1e-6;
  double max_err = 0, max_g = 0;
  for (std::size_t k = 0; k < sites.size(); ++k) {
    std::vector<double> plus = sites, minus = sites;
    plus[k] += h;
    minus[k] -= h;
    const double fd =
        (voroclip::cvt_energy3(d, plus, o) - voroclip::cvt_energy3(d, minus, o)) / (2 * h);
    max_err = std::max(max_err, std::fabs(fd - g[k]));
    max_g = std::max(max_g, std::fabs(g[k]));
  }
  INFO("max |fd - g| = " << max_err << ", max |g| = " << max_g);
  REQUIRE(max_g > 0);
  REQUIRE(max_err <= 1e-6 * max_g);
}

}  // namespace

TEST_CASE("cvt3d: gradient equals finite differences of the energy", "[cvt]") {
  const Domain3 d(kuhn_cube(2));
  const std::uint64_t seed = 17;
  INFO("seed " << seed);
  const std::vector<double> sites = voroclip::random_points3(d, 30, seed);
  SECTION("constant density") { check_gradient(d, sites, {}); }
  SECTION("linear density") {
    voroclip::Clip3Options o;
    std::vector<double> values;
    for (std::uint32_t v = 0; v < d.nb_vertices(); ++v) {
      const double* p = d.vertex(v);
      values.push_back(1 + p[0] + 0.5 * p[2]);
    }
    o.density = voroclip::Density3::vertex_linear(values);
    check_gradient(d, sites, o);
  }
}

TEST_CASE(
    "cvt3d: gradient against finite differences on a surface domain, non-polynomial "
    "density",
    "[cvt]") {
  // The unit cube given by 12 triangles; rho = 1 / (0.1 + |x - c|^2), integrated by the
  // degree-5 rule on the cells' cone decompositions.
  voroclip::TriangleSurface box;
  box.source = "box";
  for (int i = 0; i < 8; ++i) {
    for (int k = 0; k < 3; ++k) box.xyz.push_back((i >> k) & 1 ? 1.0 : 0.0);
  }
  box.triangles = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                   2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
  const Domain3 d(box);
  REQUIRE(!d.has_tets());
  const std::vector<double> sites = voroclip::random_points3(d, 40, 23);
  voroclip::Clip3Options o;
  o.density = voroclip::Density3::function(
      [](double x, double y, double z) { return std::exp(0.5 * x + 0.3 * y - 0.2 * z); });
  check_gradient(d, sites, o);
}

TEST_CASE("cvt3d: eight sites in a cube converge to the centres of its octants", "[cvt]") {
  // [0, 2]^3: the 2 x 2 x 2 grid of unit-cube centres; energy 8 * (3 / 12) = 2.
  const Domain3 d(kuhn_cube(2));
  for (const CvtMethod method : {CvtMethod::kLbfgs, CvtMethod::kLloyd}) {
    INFO((method == CvtMethod::kLloyd ? "Lloyd" : "L-BFGS"));
    std::vector<double> sites;
    for (int k = 0; k < 8; ++k) {
      const double c[3] = {0.5 + (k & 1), 0.5 + ((k >> 1) & 1), 0.5 + ((k >> 2) & 1)};
      // A deterministic perturbation of up to 0.2 per coordinate.
      for (int a = 0; a < 3; ++a) sites.push_back(c[a] + 0.2 * std::sin(1.7 * k + 2.3 * a + 0.4));
    }
    Cvt3Options o;
    o.method = method;
    o.max_iterations = 400;
    o.gradient_tolerance = 1e-6;
    const auto r = voroclip::optimize_cvt3(d, sites, o);
    REQUIRE(r.converged);
    for (int k = 0; k < 8; ++k) {
      const double c[3] = {0.5 + (k & 1), 0.5 + ((k >> 1) & 1), 0.5 + ((k >> 2) & 1)};
      for (int a = 0; a < 3; ++a) REQUIRE(std::fabs(sites[3 * k + a] - c[a]) < 1e-5);
    }
    REQUIRE(std::fabs(r.energy - 2.0) < 1e-9);
  }
}

TEST_CASE("cvt3d: one site, sites on a line, sites in a plane (degenerate site sets)",
          "[cvt][degenerate]") {
  // [0, 2]^3. The CVT of sites in a symmetric position keeps them there (their centroids
  // lie on their line / plane), so each case has a closed-form optimum: the centre (energy
  // 2^5 / 4 = 8), two slabs 1 x 2 x 2 (2 * 4 (1 + 4 + 4) / 12 = 6), three slabs
  // 2/3 x 2 x 2 (3 * (8/3) (4/9 + 8) / 12 = 152/27), four prisms 1 x 1 x 2 (4 * 2 (1 + 1 + 4)
  // / 12 = 4). Fewer than 4 affinely independent sites: ClippedVoronoi3::compute(domain,
  // sites, n) computes their diagram exactly (auxiliary far sites).
  const Domain3 d(kuhn_cube(2));
  struct Case {
    const char* name;
    std::vector<double> start, optimum;
    double energy;
  };
  const std::vector<Case> cases = {
      {"one site", {0.3, 0.4, 0.5}, {1, 1, 1}, 8.0},
      {"two sites on a line", {0.3, 1, 1, 1.6, 1, 1}, {0.5, 1, 1, 1.5, 1, 1}, 6.0},
      {"three sites on a line",
       {0.2, 1, 1, 1.1, 1, 1, 1.7, 1, 1},
       {1.0 / 3, 1, 1, 1, 1, 1, 5.0 / 3, 1, 1},
       152.0 / 27},
      {"four sites in a plane",
       {0.4, 0.6, 1, 1.7, 0.4, 1, 0.6, 1.3, 1, 1.4, 1.6, 1},
       {0.5, 0.5, 1, 1.5, 0.5, 1, 0.5, 1.5, 1, 1.5, 1.5, 1},
       4.0},
  };
  for (const Case& c : cases) {
    INFO(c.name);
    std::vector<double> sites = c.start;
    Cvt3Options o;
    o.max_iterations = 200;
    o.gradient_tolerance = 1e-8;
    const auto r = voroclip::optimize_cvt3(d, sites, o);
    REQUIRE(r.converged);
    for (std::size_t k = 0; k < sites.size(); ++k)
      REQUIRE(std::fabs(sites[k] - c.optimum[k]) < 1e-6);
    REQUIRE(std::fabs(r.energy - c.energy) < 1e-9 * c.energy);
    voroclip::ClippedVoronoi3 cv;
    cv.compute(d, sites.data(), static_cast<std::uint32_t>(sites.size() / 3));
    REQUIRE(std::fabs(cv.total_volume() - 8.0) < 1e-12 * 8.0);
  }
}

TEST_CASE("cvt3d: Lloyd decreases the energy; L-BFGS goes lower in as many evaluations", "[cvt]") {
  const Domain3 d(
      voroclip::read_tet_mesh(std::string(VOROCLIP_SHARED_DATA_DIR) + "/tetmeshes/sphere.mesh"));
  const std::uint64_t seed = 5;
  INFO("seed " << seed);
  const std::vector<double> start = voroclip::random_points3(d, 150, seed);
  std::vector<double> energies;
  Cvt3Options o;
  o.method = CvtMethod::kLloyd;
  o.max_iterations = 12;
  o.gradient_tolerance = 0;
  o.progress = [&](const voroclip::CvtProgress& p) {
    energies.push_back(p.energy);
    return true;
  };
  std::vector<double> lloyd = start;
  const auto rl = voroclip::optimize_cvt3(d, lloyd, o);
  REQUIRE(energies.size() == 13);
  for (std::size_t k = 1; k < energies.size(); ++k) REQUIRE(energies[k] < energies[k - 1]);
  REQUIRE(rl.gradient_norm < 0.5 * rl.initial_gradient_norm);

  o.method = CvtMethod::kLbfgs;
  o.max_iterations = 1000;
  o.progress = nullptr;
  std::vector<double> lbfgs = start;
  // Stop L-BFGS at Lloyd's evaluation budget.
  std::uint32_t evaluations = 0;
  o.progress = [&](const voroclip::CvtProgress&) { return ++evaluations <= rl.evaluations; };
  const auto rb = voroclip::optimize_cvt3(d, lbfgs, o);
  REQUIRE(rb.energy < rl.energy);
}

TEST_CASE("cvt3d: sites on a plane and on a line stay there and move along them", "[cvt]") {
  const Domain3 d(kuhn_cube(2));
  const std::uint64_t seed = 23;
  INFO("seed " << seed);
  std::vector<double> sites = voroclip::random_points3(d, 40, seed);
  Cvt3Options o;
  o.constraints.assign(40, Kind3::kFree);
  // Sites 0-7 on the face z = 0, sites 8-11 on the edge y = z = 0, site 12 fixed.
  for (int i = 0; i < 8; ++i) o.constraints[i] = Kind3::kSurface;
  for (int i = 8; i < 12; ++i) o.constraints[i] = Kind3::kCurve;
  o.constraints[12] = Kind3::kFixed;
  const std::vector<double> fixed(sites.begin() + 36, sites.begin() + 39);
  std::uint32_t calls = 0;
  o.project = [&](std::uint32_t site, Kind3 kind, const double* p, double* q, double* dir) {
    ++calls;
    REQUIRE(kind == o.constraints[site]);
    if (kind == Kind3::kSurface) {
      q[0] = std::clamp(p[0], 0.0, 2.0);
      q[1] = std::clamp(p[1], 0.0, 2.0);
      q[2] = 0;
      dir[0] = 0, dir[1] = 0, dir[2] = -1;
    } else {
      q[0] = std::clamp(p[0], 0.0, 2.0);
      q[1] = q[2] = 0;
      dir[0] = 1, dir[1] = 0, dir[2] = 0;
    }
  };
  o.max_iterations = 60;
  o.gradient_tolerance = 1e-8;
  const auto r = voroclip::optimize_cvt3(d, sites, o);
  REQUIRE(calls > 0);
  REQUIRE(r.gradient_norm < 1e-2 * r.initial_gradient_norm);
  for (int i = 0; i < 8; ++i) REQUIRE(sites[3 * i + 2] == 0);
  for (int i = 8; i < 12; ++i) {
    REQUIRE(sites[3 * i + 1] == 0);
    REQUIRE(sites[3 * i + 2] == 0);
  }
  REQUIRE(std::vector<double>(sites.begin() + 36, sites.begin() + 39) == fixed);
  // At the optimum the tangential gradient vanishes: on the face, site 0's cell centroid
  // lies above it (same x, y).
  std::vector<double> g;
  voroclip::cvt_energy3(d, sites, {}, &g);
  double tangential = 0, normal = 0;
  for (int i = 0; i < 8; ++i) {
    tangential = std::max({tangential, std::fabs(g[3 * i]), std::fabs(g[3 * i + 1])});
    normal = std::max(normal, std::fabs(g[3 * i + 2]));
  }
  INFO("tangential " << tangential << ", normal " << normal);
  REQUIRE(tangential < 1e-2 * normal);
}

TEST_CASE("cvt3d: cancel from the progress callback; identical with 1 and 2 threads",
          "[cvt][threads]") {
  const Domain3 d(
      voroclip::read_tet_mesh(std::string(VOROCLIP_SHARED_DATA_DIR) + "/tetmeshes/sphere.mesh"));
  const std::vector<double> start = voroclip::random_points3(d, 200, 99);
  Cvt3Options o;
  o.max_iterations = 8;
  o.gradient_tolerance = 0;
  std::vector<double> one = start, two = start;
  voroclip::Cvt3Result r1, r2;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    r1 = voroclip::optimize_cvt3(d, one, o);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism,
                          voroclip_test::test_threads());
    r2 = voroclip::optimize_cvt3(d, two, o);
  }
  REQUIRE(one == two);
  REQUIRE(r1.energy == r2.energy);
  REQUIRE(r1.evaluations == r2.evaluations);

  std::vector<double> sites = start;
  o.progress = [](const voroclip::CvtProgress& p) { return p.iteration < 3; };
  const auto rc = voroclip::optimize_cvt3(d, sites, o);
  REQUIRE(rc.cancelled);
  REQUIRE(rc.iterations == 3);
}

TEST_CASE("cvt3d: the result's energy, |g| and boundary flags are those of the returned sites",
          "[cvt][regression]") {
  // The L-BFGS run does not re-evaluate its best point when that was its last evaluation,
  // and the boundary flags come from the run's last diagram: both must describe the
  // returned sites exactly, as a fresh diagram does.
  const Domain3 d(
      voroclip::read_tet_mesh(std::string(VOROCLIP_SHARED_DATA_DIR) + "/tetmeshes/sphere.mesh"));
  for (const std::uint32_t iterations : {1u, 5u, 12u}) {
    for (const CvtMethod method : {CvtMethod::kLbfgs, CvtMethod::kLloyd}) {
      const std::uint64_t seed = 31 + iterations;
      INFO("seed " << seed << ", iterations " << iterations << ", Lloyd "
                   << (method == CvtMethod::kLloyd));
      std::vector<double> sites = voroclip::random_points3(d, 300, seed);
      std::vector<std::uint8_t> flags;
      Cvt3Options o;
      o.method = method;
      o.max_iterations = iterations;
      o.gradient_tolerance = 0;
      o.boundary_sites = &flags;
      const auto r = voroclip::optimize_cvt3(d, sites, o);
      std::vector<double> g;
      const double energy = voroclip::cvt_energy3(d, sites, {}, &g);
      REQUIRE(r.energy == energy);
      double g2 = 0;
      for (const double x : g) g2 += x * x;
      REQUIRE(std::fabs(r.gradient_norm - std::sqrt(g2)) <= 1e-12 * std::sqrt(g2));
      const voroclip::Delaunay3 dt(sites.data(), 300);
      voroclip::ClippedVoronoi3 cv;
      cv.compute(d, dt, {});
      REQUIRE(flags.size() == 300);
      std::uint32_t nb_boundary = 0;
      for (std::uint32_t i = 0; i < 300; ++i) {
        REQUIRE(flags[i] == (cv.is_boundary(i) ? 1 : 0));
        nb_boundary += flags[i];
      }
      REQUIRE(nb_boundary > 0);
      REQUIRE(nb_boundary < 300);
    }
  }
}

TEST_CASE("random_points3: uniform and linear-density samples", "[cvt]") {
  const Domain3 d(kuhn_cube(2));
  const std::uint32_t n = 200000;
  const auto mean_x = [](const std::vector<double>& xyz) {
    double s = 0;
    for (std::size_t i = 0; i < xyz.size(); i += 3) s += xyz[i];
    return s / static_cast<double>(xyz.size() / 3);
  };
  const std::vector<double> u = voroclip::random_points3(d, n, 1);
  REQUIRE(u.size() == 3 * std::size_t{n});
  for (const double c : u) REQUIRE((c >= 0 && c <= 2));
  REQUIRE(u == voroclip::random_points3(d, n, 1));
  // Uniform on [0, 2]: mean 1, standard error 0.577 / sqrt(n) = 0.0013.
  REQUIRE(std::fabs(mean_x(u) - 1.0) < 0.01);
  // rho = 1 + x: E[x] = ∫x(1 + x) / ∫(1 + x) over [0, 2] = (2 + 8/3) / 4 = 7/6.
  std::vector<double> rho;
  for (std::uint32_t v = 0; v < d.nb_vertices(); ++v) rho.push_back(1 + d.vertex(v)[0]);
  const std::vector<double> w =
      voroclip::random_points3(d, n, 2, voroclip::Density3::vertex_linear(rho));
  REQUIRE(std::fabs(mean_x(w) - 7.0 / 6) < 0.01);
  // The same density as a function, on the surface path.
  const std::vector<double> f = voroclip::random_points3(
      d, n, 2, voroclip::Density3::function([](double x, double, double) { return 1 + x; }));
  REQUIRE(std::fabs(mean_x(f) - 7.0 / 6) < 0.01);
  rho[0] = -1;
  REQUIRE_THROWS_WITH(voroclip::random_points3(d, 10, 2, voroclip::Density3::vertex_linear(rho)),
                      Catch::Contains("density") && Catch::Contains("vertex 0"));
  REQUIRE_THROWS_WITH(
      voroclip::random_points3(
          d, 10, 2, voroclip::Density3::function([](double x, double, double) { return x - 1; })),
      Catch::Contains("density") && Catch::Contains("positive"));
}

TEST_CASE("cvt3d: the same iterations in any units (a cube scaled by 2^-40 and 2^30)", "[cvt]") {
  // LBFGSpp's first step has unit length in the variables: in the coordinates' units, the
  // cube scaled by 2^-40 made no iteration (the step was 10^12 cubes long) and by 2^30 went
  // a few nanometres a step. The variables are scaled by a power of two (cvt3d.cpp,
  // variable_scale), exactly: the runs are the unit cube's bit for bit, times the scale.
  const Domain3 unit(kuhn_cube(2));
  const std::vector<double> start = voroclip::random_points3(unit, 40, 3);
  Cvt3Options o;
  o.max_iterations = 20;
  o.gradient_tolerance = 0;
  std::vector<double> reference = start;
  const auto r = voroclip::optimize_cvt3(unit, reference, o);
  REQUIRE(r.iterations == 20);
  REQUIRE(r.gradient_norm < 0.1 * r.initial_gradient_norm);
  for (const int e : {-40, 30}) {
    INFO("scale 2^" << e);
    const Domain3 scaled(kuhn_cube(2, std::ldexp(1.0, e)));
    std::vector<double> sites = start;
    for (double& x : sites) x = std::ldexp(x, e);
    const auto s = voroclip::optimize_cvt3(scaled, sites, o);
    CHECK(s.iterations == r.iterations);
    CHECK(s.evaluations == r.evaluations);
    CHECK(s.energy == std::ldexp(r.energy, 5 * e));
    CHECK(s.gradient_norm == std::ldexp(r.gradient_norm, 4 * e));
    std::size_t differ = 0;
    for (std::size_t k = 0; k < sites.size(); ++k)
      differ += sites[k] != std::ldexp(reference[k], e);
    CHECK(differ == 0);
  }
}

namespace {

// The unit cube [0, 1]^3 by 12 triangles, scaled by k.
voroclip::TriangleSurface box_surface(double k) {
  voroclip::TriangleSurface box;
  box.source = "box";
  for (int i = 0; i < 8; ++i) {
    for (int c = 0; c < 3; ++c) box.xyz.push_back((i >> c) & 1 ? k : 0.0);
  }
  box.triangles = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                   2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
  return box;
}

}  // namespace

TEST_CASE("cvt3d: the cube scaled by 2^-120 and 2^120, the same run as in unit size",
          "[cvt][regression]") {
  // The variables are scaled by 1 / L for a model of size L (variable_scale), and the
  // gradient L-BFGS saw grew as L^5: its squared norm overflowed at 2^120 (|g| inf) and
  // underflowed at 2^-120 (|g| 0), and the run stopped "converged" at iteration 0 with
  // the sites unchanged (the sphere scaled by 1e32 or 1e-35). The energy is now scaled by
  // a power of two too (Problem3::objective_scale): the runs are the unit cube's bit for
  // bit, times the scale. (Beyond 2^+-150 the clipped cells themselves are no longer the
  // unit cube's scaled bit for bit; the next test runs there.)
  const Domain3 unit(kuhn_cube(2));
  const std::vector<double> start = voroclip::random_points3(unit, 40, 3);
  Cvt3Options o;
  o.max_iterations = 20;
  o.gradient_tolerance = 0;
  std::vector<double> reference = start;
  const auto r = voroclip::optimize_cvt3(unit, reference, o);
  REQUIRE(r.iterations == 20);
  REQUIRE(r.gradient_norm < 0.1 * r.initial_gradient_norm);
  for (const int e : {-120, -100, 100, 120}) {
    INFO("scale 2^" << e);
    const Domain3 scaled(kuhn_cube(2, std::ldexp(1.0, e)));
    std::vector<double> sites = start;
    for (double& x : sites) x = std::ldexp(x, e);
    const auto s = voroclip::optimize_cvt3(scaled, sites, o);
    CHECK(s.iterations == r.iterations);
    CHECK(s.evaluations == r.evaluations);
    CHECK(s.stop == voroclip::CvtStop::kIterationBudget);
    CHECK(s.energy == std::ldexp(r.energy, 5 * e));
    CHECK(s.initial_gradient_norm == std::ldexp(r.initial_gradient_norm, 4 * e));
    CHECK(s.gradient_norm == std::ldexp(r.gradient_norm, 4 * e));
    std::size_t differ = 0;
    for (std::size_t k = 0; k < sites.size(); ++k)
      differ += sites[k] != std::ldexp(reference[k], e);
    CHECK(differ == 0);
  }
}

TEST_CASE("cvt3d: a cube scaled by 1e32, 1e-35, 2^180, 2^-180 converges as the unit cube does",
          "[cvt][regression]") {
  // The runs differ from the unit cube's in the last bits, but they run (they stopped
  // "converged" at iteration 0, |g| inf or 0) and reach the unit cube's tolerance.
  Cvt3Options o;
  o.gradient_tolerance = 1e-3;
  o.max_iterations = 200;
  const Domain3 unit(kuhn_cube(2));
  std::vector<double> reference = voroclip::random_points3(unit, 40, 5);
  const auto r = voroclip::optimize_cvt3(unit, reference, o);
  REQUIRE(r.converged);
  for (const double k : {1e32, 1e-35, std::ldexp(1.0, 180), std::ldexp(1.0, -180)}) {
    INFO("scale " << k);
    const Domain3 scaled(kuhn_cube(2, k));
    std::vector<double> sites = voroclip::random_points3(scaled, 40, 5);
    const auto s = voroclip::optimize_cvt3(scaled, sites, o);
    CHECK(std::isfinite(s.initial_gradient_norm));
    CHECK(s.initial_gradient_norm > 0);
    CHECK(s.iterations > 10);
    CHECK(s.converged);
    CHECK(s.gradient_norm <= 1e-3 * s.initial_gradient_norm);
    CHECK(s.energy / std::pow(k, 5) == Approx(r.energy).epsilon(1e-2));
  }
}

TEST_CASE("cvt3d: a model too small or too large for double precision is an error",
          "[cvt][regression]") {
  // A cube scaled by 1e-300 was a valid surface of volume 0 (the volume underflows): cvt3d
  // said "converged" after 0 iterations. Scaled by 2^-250 its volume is representable but
  // not the energy (L^5 = 2^-1250); by 2^210 the energy overflows (2^1050).
  const auto sites_in = [](double k) {
    std::vector<double> s;
    for (const double f : {0.25, 0.75}) {
      s.insert(s.end(), {f * k, 0.5 * k, 0.5 * k});
    }
    return s;
  };
  struct Case {
    double k;
    const char* quantity;
    const char* size;
  };
  // (Scaled by 1e-300, the volume underflows: the domain itself is an error.)
  REQUIRE_THROWS_WITH(Domain3(box_surface(1e-300)),
                      Catch::Contains("box: its volume is 0 in double precision") &&
                          Catch::Contains("too small") && Catch::Contains("rescale the model"));
  for (const Case& c :
       {Case{std::ldexp(1.0, -250), "the CVT energy of the start sites is 0", "too small"},
        Case{std::ldexp(1.0, 210), "the CVT energy of the start sites is inf", "too large"}}) {
    INFO("scale " << c.k);
    const Domain3 d(box_surface(c.k));
    for (const CvtMethod method : {CvtMethod::kLbfgs, CvtMethod::kLloyd}) {
      std::vector<double> sites = sites_in(c.k);
      Cvt3Options o;
      o.method = method;
      REQUIRE_THROWS_AS(voroclip::optimize_cvt3(d, sites, o), voroclip::Error);
      REQUIRE_THROWS_WITH(voroclip::optimize_cvt3(d, sites, o),
                          Catch::Contains("cvt3d: box (") && Catch::Contains(c.quantity) &&
                              Catch::Contains(c.size) && Catch::Contains("rescale the model"));
    }
  }
}

TEST_CASE("cvt3d: 0 iterations return the start, evaluated once", "[cvt][regression]") {
  // LBFGSpp takes max_iterations = 0 for "no limit" and the budget was tested after the
  // first accepted point: L-BFGS made one iteration and moved the sites (Lloyd did not).
  const Domain3 d(kuhn_cube(2));
  const std::vector<double> start = voroclip::random_points3(d, 30, 7);
  std::vector<double> gradient;
  const double energy = voroclip::cvt_energy3(d, start, {}, &gradient);
  double g2 = 0;
  for (const double g : gradient) g2 += g * g;
  for (const CvtMethod method : {CvtMethod::kLbfgs, CvtMethod::kLloyd}) {
    INFO("method " << (method == CvtMethod::kLbfgs ? "lbfgs" : "lloyd"));
    std::vector<double> sites = start;
    Cvt3Options o;
    o.method = method;
    o.max_iterations = 0;
    std::uint32_t calls = 0;
    o.progress = [&](const voroclip::CvtProgress& p) {
      CHECK(p.iteration == 0);
      ++calls;
      return true;
    };
    const auto r = voroclip::optimize_cvt3(d, sites, o);
    CHECK(sites == start);
    CHECK(r.iterations == 0);
    CHECK(r.evaluations == 1);
    CHECK(calls == 1);
    CHECK(r.stop == voroclip::CvtStop::kIterationBudget);
    CHECK(!r.converged);
    CHECK(r.energy == energy);
    CHECK(r.gradient_norm == r.initial_gradient_norm);
    CHECK(r.gradient_norm == Approx(std::sqrt(g2)).epsilon(1e-14));
  }
}
