// Tests of densities in the cell integrals and the CVT (issue 35): cell masses, centroids
// and energies against an independent quadrature on the cells' own geometry (exact for
// the degrees tested, decomposed from the cells' vertices instead of their sites), the
// gradient against finite differences with a non-polynomial density, and the CVT's site
// density following rho^(d/(d+2)).
#include <catch2/catch.hpp>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "support/threads.h"
#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/cvt.h"

namespace {

voroclip::Domain2 unit_square() {
  voroclip::PolygonRings p;
  p.source = "unit square";
  p.xy = {0, 0, 1, 0, 1, 1, 0, 1};
  p.ring_begin = {0, 4};
  p.ring_polygon = {0};
  p.ring_line = {0};
  return voroclip::Domain2(p);
}

voroclip::Domain3 unit_cube() {
  voroclip::TriangleSurface box;
  box.source = "unit cube";
  for (int i = 0; i < 8; ++i) {
    for (int k = 0; k < 3; ++k) box.xyz.push_back((i >> k) & 1 ? 1.0 : 0.0);
  }
  box.triangles = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                   2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
  return voroclip::Domain3(box);
}

// Radon's 7-point rule on a triangle (degree 5), barycentric (a, b, 1 - a - b).
struct TriPoint {
  double a, b, w;
};
std::vector<TriPoint> radon7() {
  const double s = std::sqrt(15.0);
  const double a1 = (6 - s) / 21, b1 = (9 + 2 * s) / 21, w1 = (155 - s) / 1200;
  const double a2 = (6 + s) / 21, b2 = (9 - 2 * s) / 21, w2 = (155 + s) / 1200;
  return {{1.0 / 3, 1.0 / 3, 9.0 / 40},
          {a1, a1, w1},
          {a1, b1, w1},
          {b1, a1, w1},
          {a2, a2, w2},
          {a2, b2, w2},
          {b2, a2, w2}};
}

// Keast's 4-point rule on a tetrahedron (degree 2): barycentric (b, b, b, a) and permutations.
constexpr double kKeastA = 0.5854101966249685;  // (5 + 3 sqrt 5) / 20
constexpr double kKeastB = 0.1381966011250105;  // (5 - sqrt 5) / 20

}  // namespace

TEST_CASE("density 2D: cell integrals exact for rho of degree <= 2 (independent quadrature)",
          "[cvt][density]") {
  const voroclip::Domain2 d = unit_square();
  const std::uint64_t seed = 5;
  INFO("seed " << seed);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> sites;
  for (int i = 0; i < 400; ++i) sites.insert(sites.end(), {u(rng), u(rng)});
  const voroclip::Delaunay2 dt(sites.data(), 200);
  const std::vector<std::function<double(double, double)>> rhos = {
      [](double x, double) { return 1 + 10 * x; },                        // the issue's
      [](double x, double y) { return 2 + x * x - 0.5 * x * y + y * y; }  // degree 2
  };
  for (std::size_t r = 0; r < rhos.size(); ++r) {
    INFO("density " << r);
    voroclip::Clip2Options o;
    o.density = voroclip::Density2::function(rhos[r]);
    o.keep_geometry = true;
    voroclip::ClippedVoronoi2 cv;
    cv.compute(d, dt, o);
    const std::vector<double>& xy = cv.vertex_coords();
    double total_mass = 0;
    for (std::uint32_t i = 0; i < 200; ++i) {
      // Fan of each ring from its first vertex (not the site), Radon's degree-5 rule: exact
      // for rho, rho x and rho |x - s|^2 (degree <= 4).
      double m = 0, mx = 0, my = 0, e = 0;
      for (std::uint32_t ring = cv.cell_ring_begin(i); ring < cv.cell_ring_begin(i + 1); ++ring) {
        const std::uint32_t b = cv.ring_vertex_begin(ring), end = cv.ring_vertex_begin(ring + 1);
        const double* p0 = &xy[2 * std::size_t{b}];
        for (std::uint32_t k = b + 1; k + 1 < end; ++k) {
          const double* p1 = &xy[2 * std::size_t{k}];
          const double* p2 = &xy[2 * std::size_t{k} + 2];
          const double area =
              0.5 * ((p1[0] - p0[0]) * (p2[1] - p0[1]) - (p2[0] - p0[0]) * (p1[1] - p0[1]));
          for (const TriPoint& q : radon7()) {
            const double c = 1 - q.a - q.b;
            const double x = q.a * p0[0] + q.b * p1[0] + c * p2[0];
            const double y = q.a * p0[1] + q.b * p1[1] + c * p2[1];
            const double w = area * q.w * rhos[r](x, y);
            const double dx = x - sites[2 * i], dy = y - sites[2 * i + 1];
            m += w;
            mx += w * x;
            my += w * y;
            e += w * (dx * dx + dy * dy);
          }
        }
      }
      REQUIRE(cv.mass(i) == Approx(m).epsilon(1e-12));
      REQUIRE(cv.centroid(i)[0] == Approx(mx / m).epsilon(1e-12));
      REQUIRE(cv.centroid(i)[1] == Approx(my / m).epsilon(1e-12));
      REQUIRE(cv.energy(i) == Approx(e).epsilon(1e-11));
      total_mass += m;
    }
    // The exact integral over the square: 6 for 1 + 10x; 2 + 1/3 - 1/8 + 1/3 for the other.
    CHECK(total_mass == Approx(r == 0 ? 6.0 : 2.0 + 2.0 / 3 - 0.125).epsilon(1e-12));
  }
}

TEST_CASE("density 3D: cell integrals exact for rho of degree <= 2 (independent quadrature)",
          "[cvt][density]") {
  const voroclip::Domain3 d = unit_cube();
  const std::vector<double> sites = voroclip::random_points3(d, 150, 11);
  const std::vector<std::function<double(double, double, double)>> rhos = {
      [](double x, double, double) { return 1 + 10 * x; },  // the issue's
      [](double x, double y, double z) { return 2 + x * x - 0.5 * y * z + z * z; }};
  for (std::size_t r = 0; r < rhos.size(); ++r) {
    INFO("density " << r);
    voroclip::Clip3Options o;
    o.density = voroclip::Density3::function(rhos[r]);
    o.keep_geometry = true;
    voroclip::ClippedVoronoi3 cv;
    cv.compute(d, sites.data(), 150, o);
    const voroclip::ClippedVoronoi3::Polygons& f = cv.cell_faces();
    // Per cell: mass and first moments by cones from the cell's first face vertex over its
    // faces (fanned from their first vertex), Keast's degree-2 rule: exact for rho and,
    // with rho linear, for rho x.
    std::vector<double> m(150, 0), mx(150 * 3, 0), vol(150, 0), apex(150 * 3, 0);
    std::vector<std::uint8_t> has_apex(150, 0);
    for (std::size_t p = 0; p + 1 < f.polygon_begin.size(); ++p) {
      if (f.across[p] == voroclip::ClippedVoronoi3::kInterior) continue;
      const std::uint32_t i = f.site[p];
      const double* v0 = &f.xyz[3 * std::size_t{f.polygon_begin[p]}];
      if (!has_apex[i]) {
        std::copy(v0, v0 + 3, &apex[3 * i]);
        has_apex[i] = 1;
      }
      const double* a = &apex[3 * i];
      for (std::uint32_t k = f.polygon_begin[p] + 1; k + 1 < f.polygon_begin[p + 1]; ++k) {
        const double* v1 = &f.xyz[3 * std::size_t{k}];
        const double* v2 = &f.xyz[3 * std::size_t{k} + 3];
        double e[3][3];
        for (int c = 0; c < 3; ++c) {
          e[0][c] = v0[c] - a[c];
          e[1][c] = v1[c] - a[c];
          e[2][c] = v2[c] - a[c];
        }
        // Faces face inwards: the cone's signed volume is minus det / 6.
        const double det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                           e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                           e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
        const double v = -det / 6;
        vol[i] += v;
        const double* corner[4] = {a, v0, v1, v2};
        for (int q = 0; q < 4; ++q) {
          double x[3];
          for (int c = 0; c < 3; ++c) {
            x[c] = 0;
            for (int l = 0; l < 4; ++l) x[c] += (l == q ? kKeastA : kKeastB) * corner[l][c];
          }
          const double w = v / 4 * rhos[r](x[0], x[1], x[2]);
          m[i] += w;
          for (int c = 0; c < 3; ++c) mx[3 * i + static_cast<std::size_t>(c)] += w * x[c];
        }
      }
    }
    double total = 0;
    for (std::uint32_t i = 0; i < 150; ++i) {
      INFO("cell " << i);
      REQUIRE(vol[i] == Approx(cv.volume(i)).epsilon(1e-11));
      REQUIRE(cv.mass(i) == Approx(m[i]).epsilon(1e-11));
      if (r == 0) {
        for (int c = 0; c < 3; ++c) {
          REQUIRE(
              cv.centroid(i)[c] ==
              Approx(mx[3 * i + static_cast<std::size_t>(c)] / m[i]).epsilon(1e-11).margin(1e-13));
        }
      }
      total += m[i];
    }
    // Exact: 6 for 1 + 10x; 2 + 1/3 - 1/8 + 1/3 for the other.
    CHECK(total == Approx(r == 0 ? 6.0 : 2.0 + 2.0 / 3 - 0.125).epsilon(1e-12));
    CHECK(cv.total_mass() == Approx(total).epsilon(1e-12));
  }
}

TEST_CASE("density 3D: the quadratic rule is exact for rho of degree <= 2, not beyond",
          "[cvt][density]") {
  // Both rules are exact for rho of degree <= 2 (the degree-5 rule up to degree 3): every
  // cell's mass, centroid and energy agree to rounding. For a cubic rho the quadratic
  // interpolant is not rho, and the two differ.
  const voroclip::Domain3 d = unit_cube();
  const std::uint32_t n = 150;
  const std::vector<double> sites = voroclip::random_points3(d, n, 11);
  const std::vector<std::function<double(double, double, double)>> rhos = {
      [](double x, double, double) { return 1 + 10 * x; },
      [](double x, double y, double z) { return 2 + x * x - 0.5 * y * z + z * z; },
      [](double x, double y, double z) { return 1 + x * x * x + y * z * z; }};
  for (std::size_t r = 0; r < rhos.size(); ++r) {
    INFO("density " << r);
    voroclip::ClippedVoronoi3 five, quadratic;
    voroclip::Clip3Options o;
    o.density = voroclip::Density3::function(rhos[r]);
    five.compute(d, sites.data(), n, o);
    o.density.rule = voroclip::Density3::Rule::kQuadratic;
    quadratic.compute(d, sites.data(), n, o);
    double worst = 0;
    for (std::uint32_t i = 0; i < n; ++i) {
      INFO("cell " << i);
      REQUIRE(quadratic.volume(i) == five.volume(i));
      worst = std::max(worst, std::fabs(quadratic.mass(i) - five.mass(i)) / five.mass(i));
      worst = std::max(worst, std::fabs(quadratic.energy(i) - five.energy(i)) / five.energy(i));
      for (int c = 0; c < 3; ++c) {
        worst = std::max(worst, std::fabs(quadratic.centroid(i)[c] - five.centroid(i)[c]));
      }
    }
    INFO("largest difference " << worst);
    if (r < 2) {
      CHECK(worst < 1e-12);
      // The exact mass of the cube: 6 and 2 + 1/3 - 1/8 + 1/3.
      CHECK(quadratic.total_mass() == Approx(r == 0 ? 6.0 : 2.0 + 2.0 / 3 - 0.125).epsilon(1e-12));
    } else {
      CHECK(worst > 1e-6);
    }
  }
}

TEST_CASE("density 2D: gradient equals finite differences with a non-polynomial density",
          "[cvt][density]") {
  // The gradient 2 m (x_i - c_i) is the derivative of the exact energy; the computed energy
  // has the quadrature's error, so the two agree to about that error: with 400 sites,
  // 2e-7 of max |g| (50 sites: 3.7e-6; with the former degree-4 rule 1.2e-5).
  const voroclip::Domain2 d = unit_square();
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> sites;
  for (int i = 0; i < 400; ++i) sites.insert(sites.end(), {u(rng), u(rng)});
  const voroclip::Density2 rho = voroclip::Density2::function(
      [](double x, double y) { return std::exp(0.5 * x - 0.3 * y) + 1 / (1 + x * x + y * y); });
  std::vector<double> g;
  voroclip::cvt_energy2(d, sites, rho, &g);
  const double h = 1e-6;
  double max_err = 0, max_g = 0;
  for (std::size_t k = 0; k < sites.size(); ++k) {
    std::vector<double> plus = sites, minus = sites;
    plus[k] += h;
    minus[k] -= h;
    const double fd =
        (voroclip::cvt_energy2(d, plus, rho) - voroclip::cvt_energy2(d, minus, rho)) / (2 * h);
    max_err = std::max(max_err, std::fabs(fd - g[k]));
    max_g = std::max(max_g, std::fabs(g[k]));
  }
  INFO("max |fd - g| = " << max_err << ", max |g| = " << max_g);
  REQUIRE(max_g > 0);
  REQUIRE(max_err <= 1e-6 * max_g);
}

namespace {

// Gersho's asymptotics: a CVT of density rho has about rho^(d/(d+2)) sites per unit
// volume. From uniform random sites in the unit square or cube, the L-BFGS CVT with
// rho = 1 + 10x must move them there: the share of sites in each of `slabs` slabs along x
// against the share of the integral of (1 + 10x)^(d/(d+2)), within `tolerance`. The uniform
// start is far from it (the check can fail): its first slab holds 1.27 (3D, window
// [0.2, 0.8]) to 2.2 (2D, whole square) times the asymptotics' share.
//
// The asymptotics are those of the bulk: within about a cell's diameter of the boundary a
// CVT's cells are cut by it, and the site density there is not rho^(d/(d+2)) (a cut cell
// is flatter than a bulk cell and its site sits nearer the boundary, so more sites fit
// there per unit volume). The law is therefore checked in the interior window
// [margin, 1 - margin]^d, cut into `slabs` slabs along x; margin 0 counts the whole domain.
// In the window the extent across x is the same for every slab, so the expected share of a
// slab is the integral of (1 + 10x)^(d/(d+2)) over its x-range against the window's.
// The margin is set to about 1.5 cell spacings where the cells are largest (x = 0, rho = 1:
// spacing (n rho^(3/5) / integral of rho^(3/5))^(-1/3), 0.066 for 10^4 sites in 3D, 0.11
// for 2000).
struct SiteDensityCheck {
  int d = 2;
  std::uint32_t n = 2000, iterations = 150;
  double margin = 0, tolerance = 0.05;
  int slabs = 5;
  // 3D: start from sites drawn with density rho (too many at high x) instead of uniform
  // sites (too many at low x).
  bool start_rho = false;
};

void check_site_density(const SiteDensityCheck& c) {
  const int d = c.d;
  const std::uint32_t n = c.n;
  const double power = d / (d + 2.0);
  const auto primitive = [&](double x) {
    return std::pow(1 + 10 * x, power + 1) / (10 * (power + 1));
  };
  const double lo = c.margin, hi = 1 - c.margin;
  const double whole = primitive(hi) - primitive(lo);
  std::vector<double> sites;
  voroclip::CvtResult r;
  if (d == 2) {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (std::uint32_t i = 0; i < n; ++i) sites.insert(sites.end(), {u(rng), u(rng)});
  } else if (c.start_rho) {
    sites = voroclip::random_points3(
        unit_cube(), n, 2,
        voroclip::Density3::function([](double x, double, double) { return 1 + 10 * x; }));
  } else {
    sites = voroclip::random_points3(unit_cube(), n, 2);
  }
  const std::vector<double> start = sites;
  if (d == 2) {
    voroclip::Cvt2Options o;
    o.density = voroclip::Density2::function([](double x, double) { return 1 + 10 * x; });
    o.max_iterations = c.iterations;
    o.gradient_tolerance = 1e-6;
    r = voroclip::optimize_cvt2(unit_square(), sites, o);
  } else {
    voroclip::Cvt3Options o;
    o.clip.density =
        voroclip::Density3::function([](double x, double, double) { return 1 + 10 * x; });
    // rho is linear: the quadratic rule integrates it exactly, at a quarter of the calls.
    o.clip.density.rule = voroclip::Density3::Rule::kQuadratic;
    o.max_iterations = c.iterations;
    o.gradient_tolerance = 1e-6;
    r = voroclip::optimize_cvt3(unit_cube(), sites, o);
  }
  INFO(d << "D, " << n << " sites, " << r.iterations << " iterations, |g|/|g0| "
         << r.gradient_norm / r.initial_gradient_norm << ", stop "
         << voroclip::cvt_stop_name(r.stop) << ", window [" << lo << ", " << hi << "]");
  // Sites in the window (every coordinate in [lo, hi)), by slab along x.
  const auto count_slabs = [&](const std::vector<double>& xs) {
    std::vector<std::uint32_t> count(static_cast<std::size_t>(c.slabs), 0);
    std::uint32_t inside = 0;
    for (std::uint32_t i = 0; i < n; ++i) {
      const double* p = &xs[static_cast<std::size_t>(d) * i];
      bool in = true;
      for (int k = 0; k < d; ++k) in = in && p[k] >= lo && p[k] < hi;
      if (!in) continue;
      ++inside;
      const auto s = static_cast<std::size_t>(
          std::min<double>(c.slabs - 1, std::floor((p[0] - lo) / (hi - lo) * c.slabs)));
      ++count[s];
    }
    return std::make_pair(count, inside);
  };
  // For measurements: VOROCLIP_DENSITY_SITES=FILE writes the final sites (d per line).
  if (const char* path = std::getenv("VOROCLIP_DENSITY_SITES")) {
    if (std::FILE* f = std::fopen(path, "w")) {
      for (std::size_t k = 0; k < sites.size(); k += static_cast<std::size_t>(d)) {
        for (int q = 0; q < d; ++q) {
          std::fprintf(f, q + 1 < d ? "%.17g " : "%.17g\n", sites[k + static_cast<std::size_t>(q)]);
        }
      }
      std::fclose(f);
    }
  }
  const auto [count, inside] = count_slabs(sites);
  const auto [count0, inside0] = count_slabs(start);
  for (int s = 0; s < c.slabs; ++s) {
    const double a = lo + (hi - lo) * s / c.slabs, b = lo + (hi - lo) * (s + 1) / c.slabs;
    const double share = (primitive(b) - primitive(a)) / whole;
    const double expected = inside * share;
    const auto k = static_cast<std::size_t>(s);
    INFO("slab " << s << " [" << a << ", " << b << "): " << count[k] << " of " << inside
                 << " sites (start " << count0[k] << " of " << inside0 << "), expected " << expected
                 << ", ratio " << count[k] / expected);
    CHECK(std::fabs(count[k] - expected) <= c.tolerance * expected);
    // The uniform start misses the first slab's share by more than three tolerances.
    if (s == 0 && !c.start_rho) CHECK(count0[k] > (1 + 3 * c.tolerance) * inside0 * share);
  }
}

}  // namespace

TEST_CASE("density: 2D CVT sites follow rho^(1/2) within 5 % (rho = 1 + 10x)", "[cvt][density]") {
  // 2000 sites keep the test short; the hidden [.slow] case runs 10^4 in 2D and 3D.
  // Measured (2D, 10^4 sites, converged at |g|/|g0| 1e-6 after 874 iterations): slabs
  // within 1.2 % of the asymptotics over the whole square.
  check_site_density({2, 2000, 150, 0.0, 0.05, 5});
}

TEST_CASE("density: 10^4 CVT sites in 2D follow rho^(1/2) within 5 %", "[cvt][density][.slow]") {
  check_site_density({2, 10000, 1500, 0.0, 0.05, 5});
}

TEST_CASE("density: 3D CVT sites follow rho^(3/5) within 7 % in the interior", "[cvt][density]") {
  // 2000 sites, 150 iterations (|g|/|g0| 1.3e-3; 5 s on one busy core): 421 sites in the
  // window [0.2, 0.8]^3, 110-170 per slab, where one site is 0.6-0.9 %. Measured ratios to
  // the asymptotics 1.028, 0.953, 1.021 (the start's first slab: 1.42), hence 7 % here;
  // the hidden case below checks 5 % with 10^4 sites.
  check_site_density({3, 2000, 150, 0.2, 0.07, 3});
}

TEST_CASE("density: 10^4 CVT sites in 3D follow rho^(3/5) within 5 % in the interior",
          "[cvt][density][.slow][!mayfail]") {
  // Over the whole cube (300 iterations, |g|/|g0| 1.9e-3): slabs 1-4 within 2.7 %, slab 0
  // (x in [0, 0.2), against the face x = 0, where rho is least and the cells largest) 5.3 %
  // above. In the window [0.1, 0.9]^3 (this check): after 301 iterations (|g|/|g0|
  // 1.1e-3) ratios 0.995, 1.062, 1.029, 0.934; run to convergence (|g|/|g0| 7.0e-7 at
  // 1214 iterations, 12 min on 2 busy cores) 0.996, 1.068, 1.029, 0.929 (5133 sites). The
  // iteration budget is not what limits it: the converged CVT misses the asymptotics by
  // 7 % in slabs 1 and 3. Still failing (mayfail); the case below starts from the other
  // side to tell a memory of the start from a bias of the law at this size.
  check_site_density({3, 10000, 1500, 0.1, 0.05, 4});
}

TEST_CASE("density: 10^4 CVT sites in 3D from sites drawn with density rho, whole cube",
          "[cvt][density][.slow]") {
  // From the other side (the start has too many sites at high x: in [0.1, 0.9]^3 its
  // slabs hold 0.73 ... 1.12 of the asymptotics' share), converged (|g|/|g0| 9.8e-7 at
  // 1363 iterations, 182 s of CPU): in the window [0.1, 0.9]^3 the same misses as
  // from the uniform start above (0.994, 1.064, 1.016, 0.944), so a bias of that window,
  // not a memory of the start. Recounted from the same sites (VOROCLIP_DENSITY_SITES):
  // window [0.2, 0.8]^3, 3 slabs, 0.991, 0.982, 1.021; the whole cube, 5 slabs, 1.009,
  // 0.974, 0.998, 1.009, 1.005. The window's lateral cut at 0.1 lies within the layers
  // the faces y, z = 0, 1 impose on the sites (1.5 spacings where x is small, 2.4 where x is
  // large), a different share of them in each slab; the whole cube counts every layer.
  SiteDensityCheck c{3, 10000, 1500, 0.0, 0.05, 5};
  c.start_rho = true;
  check_site_density(c);
}

TEST_CASE("density 3D: inner cells under the quadratic rule, 4000 sites, exact and 1 vs N threads",
          "[cvt][density][threads]") {
  // Inner cells number their P2 nodes in chunks (DelaunayCells::add_piece_numbered, nodes
  // shared by the chunk's cells, evaluated 1024 at a time); boundary cells find them by
  // their bits. For rho of degree 2 both are exact: every cell agrees with the degree-5
  // rule to rounding, the cube's mass is exact; and the cells are the same bits on 1 and
  // N threads.
  const voroclip::Domain3 d = unit_cube();
  const std::uint32_t n = 4000;
  const std::vector<double> sites = voroclip::random_points3(d, n, 35);
  voroclip::Clip3Options o;
  o.density = voroclip::Density3::function(
      [](double x, double y, double z) { return 2 + x * x - 0.5 * y * z + z * z; });
  voroclip::ClippedVoronoi3 five, one, many;
  five.compute(d, sites.data(), n, o);
  o.density.rule = voroclip::Density3::Rule::kQuadratic;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one.compute(d, sites.data(), n, o);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism,
                          voroclip_test::test_threads());
    many.compute(d, sites.data(), n, o);
  }
  double worst = 0;
  std::uint32_t inner = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    INFO("cell " << i);
    inner += one.is_boundary(i) ? 0 : 1;
    REQUIRE(one.volume(i) == five.volume(i));
    worst = std::max(worst, std::fabs(one.mass(i) - five.mass(i)) / five.mass(i));
    worst = std::max(worst, std::fabs(one.energy(i) - five.energy(i)) / five.energy(i));
    for (int c = 0; c < 3; ++c) {
      worst = std::max(worst, std::fabs(one.centroid(i)[c] - five.centroid(i)[c]));
      REQUIRE(one.centroid(i)[c] == many.centroid(i)[c]);
    }
    REQUIRE(one.mass(i) == many.mass(i));
    REQUIRE(one.energy(i) == many.energy(i));
  }
  INFO("largest difference " << worst << ", inner cells " << inner);
  CHECK(inner > n / 2);
  CHECK(worst < 1e-12);
  CHECK(one.total_mass() == Approx(2.0 + 2.0 / 3 - 0.125).epsilon(1e-12));
}

TEST_CASE("density: CVT results identical with 1 and 2 threads (callback density)",
          "[cvt][density][threads]") {
  const voroclip::Domain3 d = unit_cube();
  std::vector<double> start = voroclip::random_points3(d, 300, 4);
  voroclip::Cvt3Options o;
  o.clip.density = voroclip::Density3::function(
      [](double x, double y, double z) { return std::exp(x - y) + z * z; });
  o.max_iterations = 15;
  // The quadratic rule reads rho through each thread's cache of node values.
  const auto rule =
      GENERATE(voroclip::Density3::Rule::kDegree5, voroclip::Density3::Rule::kQuadratic);
  o.clip.density.rule = rule;
  INFO("rule " << static_cast<int>(rule));
  std::vector<double> a = start, b = start;
  voroclip::Cvt3Result ra, rb;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    ra = voroclip::optimize_cvt3(d, a, o);
  }
  {
    tbb::global_control two(tbb::global_control::max_allowed_parallelism,
                            voroclip_test::test_threads());
    rb = voroclip::optimize_cvt3(d, b, o);
  }
  CHECK(a == b);
  CHECK(ra.energy == rb.energy);
  CHECK(ra.iterations == rb.iterations);
  CHECK(ra.energy < voroclip::cvt_energy3(d, start, o.clip));
}

TEST_CASE("cvt: the stop reason", "[cvt]") {
  const voroclip::Domain2 d = unit_square();
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> start;
  for (int i = 0; i < 100; ++i) start.insert(start.end(), {u(rng), u(rng)});
  for (const voroclip::CvtMethod method :
       {voroclip::CvtMethod::kLbfgs, voroclip::CvtMethod::kLloyd}) {
    voroclip::Cvt2Options o;
    o.method = method;
    std::vector<double> sites = start;
    o.max_iterations = 3;
    voroclip::Cvt2Result r = voroclip::optimize_cvt2(d, sites, o);
    CHECK(r.stop == voroclip::CvtStop::kIterationBudget);
    CHECK(!r.converged);
    CHECK(r.iterations == 3);
    sites = start;
    o.max_iterations = 1000;
    o.gradient_tolerance = 0.3;
    r = voroclip::optimize_cvt2(d, sites, o);
    CHECK(r.stop == voroclip::CvtStop::kConverged);
    CHECK(r.converged);
    sites = start;
    o.progress = [](const voroclip::CvtProgress& p) { return p.iteration < 2; };
    r = voroclip::optimize_cvt2(d, sites, o);
    CHECK(r.stop == voroclip::CvtStop::kCancelled);
    CHECK(r.cancelled);
  }
  const voroclip::Domain3 d3 = unit_cube();
  std::vector<double> sites3 = voroclip::random_points3(d3, 50, 1);
  voroclip::Cvt3Options o3;
  o3.max_iterations = 2;
  CHECK(voroclip::optimize_cvt3(d3, sites3, o3).stop == voroclip::CvtStop::kIterationBudget);
  o3.max_iterations = 1000;
  o3.gradient_tolerance = 0.3;
  CHECK(voroclip::optimize_cvt3(d3, sites3, o3).stop == voroclip::CvtStop::kConverged);
  CHECK(std::string(voroclip::cvt_stop_name(voroclip::CvtStop::kNoProgress)) == "no progress");
}

TEST_CASE("density 3D: gradient against finite differences, both rules, 40 to 2560 sites",
          "[cvt][density][.measure]") {
  // Measurement (hidden): max |fd - g| / max |g| over the coordinates of the first 8 sites,
  // rho = exp(0.5 x + 0.3 y - 0.2 z) in the unit cube, for 40, 320 and 2560 sites (the
  // cells' size halving each time).
  const voroclip::Domain3 d = unit_cube();
  for (const std::uint32_t n : {40u, 320u, 2560u}) {
    const std::vector<double> sites = voroclip::random_points3(d, n, 23);
    for (const auto rule :
         {voroclip::Density3::Rule::kDegree5, voroclip::Density3::Rule::kQuadratic}) {
      voroclip::Clip3Options o;
      o.density = voroclip::Density3::function(
          [](double x, double y, double z) { return std::exp(0.5 * x + 0.3 * y - 0.2 * z); });
      o.density.rule = rule;
      std::vector<double> g;
      voroclip::cvt_energy3(d, sites, o, &g);
      double max_g = 0;
      for (double v : g) max_g = std::max(max_g, std::fabs(v));
      const double h = 1e-6;
      double max_err = 0;
      for (std::size_t k = 0; k < 24; ++k) {
        std::vector<double> plus = sites, minus = sites;
        plus[k] += h;
        minus[k] -= h;
        const double fd =
            (voroclip::cvt_energy3(d, plus, o) - voroclip::cvt_energy3(d, minus, o)) / (2 * h);
        max_err = std::max(max_err, std::fabs(fd - g[k]));
      }
      std::printf("sites %u rule %d: max |fd - g| %.3g, max |g| %.3g, relative %.3g\n", n,
                  static_cast<int>(rule), max_err, max_g, max_err / max_g);
      CHECK(max_g > 0);
    }
  }
}
