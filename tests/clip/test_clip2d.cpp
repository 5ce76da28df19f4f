// Tests of ClippedVoronoi2 (voroclip/clip.h). Every diagram goes through check_diagram:
// cell areas sum to the domain's area (relative 1e-12), each cell's rings are closed and
// consistent with its area, and random points of the domain lie in the cell of their
// nearest site (decided exactly) and in no other cell's rings.
#include <catch2/catch.hpp>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "support/threads.h"
#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/delaunay.h"
#include "voroclip/predicates.h"

using voroclip::ClippedVoronoi2;
using voroclip::ClipVertex2;
using voroclip::Delaunay2;
using voroclip::Domain2;
using voroclip::PolygonRings;
using voroclip::Sign;

namespace {

const std::string kData = VOROCLIP_SHARED_DATA_DIR;

double test_scale() {
  const char* s = std::getenv("VOROCLIP_TEST_SCALE");
  return s ? std::max(0.05, std::atof(s)) : 1.0;
}

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

// Uniform random points strictly inside the domain (rejection from the bounding box).
std::vector<double> sample_inside(const Domain2& d, std::uint32_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> ux(d.bbox_lo()[0], d.bbox_hi()[0]);
  std::uniform_real_distribution<double> uy(d.bbox_lo()[1], d.bbox_hi()[1]);
  std::vector<double> xy;
  while (xy.size() < 2 * std::size_t{n}) {
    const double p[2] = {ux(rng), uy(rng)};
    if (d.locate(p) == Sign::positive) xy.insert(xy.end(), p, p + 2);
  }
  return xy;
}

// Winding number of the rings [rb, re) of the diagram around p (floating point: the test
// points are random, far from the rings compared to rounding).
int winding(const ClippedVoronoi2& cv, std::uint32_t rb, std::uint32_t re, const double* p) {
  const std::vector<double>& xy = cv.vertex_coords();
  int w = 0;
  for (std::uint32_t r = rb; r < re; ++r) {
    const std::uint32_t b = cv.ring_vertex_begin(r), e = cv.ring_vertex_begin(r + 1);
    for (std::uint32_t k = b; k < e; ++k) {
      const double* u = &xy[2 * std::size_t{k}];
      const double* v = &xy[2 * std::size_t{k + 1 == e ? b : k + 1}];
      const double cross = (v[0] - u[0]) * (p[1] - u[1]) - (p[0] - u[0]) * (v[1] - u[1]);
      if (u[1] <= p[1]) {
        if (v[1] > p[1] && cross > 0) ++w;
      } else if (v[1] <= p[1] && cross < 0) {
        --w;
      }
    }
  }
  return w;
}

double ring_area(const ClippedVoronoi2& cv, std::uint32_t r) {
  const std::vector<double>& xy = cv.vertex_coords();
  const std::uint32_t b = cv.ring_vertex_begin(r), e = cv.ring_vertex_begin(r + 1);
  double a = 0;
  for (std::uint32_t k = b; k < e; ++k) {
    const double* u = &xy[2 * std::size_t{k}];
    const double* v = &xy[2 * std::size_t{k + 1 == e ? b : k + 1}];
    a += (u[0] - xy[2 * b]) * (v[1] - xy[2 * b + 1]) - (v[0] - xy[2 * b]) * (u[1] - xy[2 * b + 1]);
  }
  return a / 2;
}

struct Checked {
  std::uint32_t boundary = 0;
  std::uint32_t probes = 0;
};

Checked check_diagram(const Domain2& d, const Delaunay2& dt, const ClippedVoronoi2& cv,
                      std::uint32_t nb_probes, std::uint64_t seed) {
  INFO("domain " << d.source() << ", " << dt.nb_points() << " sites, seed " << seed);
  REQUIRE(cv.nb_sites() == dt.nb_points());
  REQUIRE(cv.has_geometry());
  // Areas: the cells partition the domain.
  REQUIRE(std::fabs(cv.total_area() - d.area()) <= 1e-12 * std::fabs(d.area()));
  double sum = 0;
  std::uint32_t boundary = 0;
  for (std::uint32_t i = 0; i < cv.nb_sites(); ++i) {
    REQUIRE(cv.area(i) >= -1e-14 * d.area());
    sum += cv.area(i);
    // The rings of the cell enclose its area.
    double rings = 0;
    for (std::uint32_t r = cv.cell_ring_begin(i); r < cv.cell_ring_begin(i + 1); ++r) {
      REQUIRE(cv.ring_vertex_begin(r + 1) - cv.ring_vertex_begin(r) >= 3);
      rings += ring_area(cv, r);
    }
    REQUIRE(std::fabs(rings - cv.area(i)) <= 1e-9 * d.area());
    if (cv.is_boundary(i)) ++boundary;
    if (dt.duplicate_of(i) != i) REQUIRE(cv.area(i) == 0);
  }
  REQUIRE(boundary == cv.nb_boundary_sites());
  REQUIRE(std::fabs(sum - d.area()) <= 1e-12 * std::fabs(d.area()));
  // Random points of the domain: in the rings of the cell of their nearest site only.
  const std::vector<double> probes = sample_inside(d, nb_probes, seed ^ 0x9e3779b97f4a7c15ull);
  for (std::uint32_t q = 0; q < nb_probes; ++q) {
    const double* p = &probes[2 * std::size_t{q}];
    const std::uint32_t s = dt.nearest_vertex(p[0], p[1]);
    INFO("probe " << q << " (" << p[0] << ", " << p[1] << "), nearest site " << s);
    REQUIRE(winding(cv, cv.cell_ring_begin(s), cv.cell_ring_begin(s + 1), p) == 1);
  }
  return {boundary, nb_probes};
}

ClippedVoronoi2 clip(const Domain2& d, const Delaunay2& dt) {
  ClippedVoronoi2 cv;
  voroclip::Clip2Options o;
  o.keep_geometry = true;
  cv.compute(d, dt, o);
  return cv;
}

}  // namespace

TEST_CASE("clip2d: random sites in a square", "[clip]") {
  const Domain2 d(rings_of({square(0, 0, 1, 1)}));
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    for (std::uint32_t n : {3u, 10u, 100u, 2000u}) {
      const std::vector<double> sites = sample_inside(d, n, seed);
      const Delaunay2 dt(sites.data(), n);
      const ClippedVoronoi2 cv = clip(d, dt);
      check_diagram(d, dt, cv, 2000, seed);
    }
  }
}

TEST_CASE("clip2d: cells with several pieces and holes", "[clip][degenerate]") {
  // A comb: thin teeth make a few cells split into many pieces.
  std::vector<double> comb = {0, 0, 10, 0, 10, 1};
  for (int t = 9; t >= 0; --t) {
    comb.insert(comb.end(), {t + 0.8, 1.0, t + 0.8, 5.0, t + 0.2, 5.0, t + 0.2, 1.0});
  }
  comb.insert(comb.end(), {0.0, 1.0});
  const Domain2 d(rings_of({comb}));
  const std::vector<double> sites = {5, 0.5, 2, 0.2, 8, 0.7, 5, 7};
  const Delaunay2 dt(sites.data(), 4);
  const ClippedVoronoi2 cv = clip(d, dt);
  check_diagram(d, dt, cv, 20000, 7);
  // The site above the comb owns the tips of several teeth: several pieces.
  REQUIRE(cv.cell_ring_begin(4) - cv.cell_ring_begin(3) > 1);

  // One site and a square with two holes: the cell is the whole domain, three rings.
  const Domain2 holes(
      rings_of({square(0, 0, 4, 4), square(1, 1, 1.5, 1.5), square(2.5, 2.5, 3, 3)}));
  const std::vector<double> three = {0.5, 0.5, 100, 100, -100, 100};
  const Delaunay2 dt3(three.data(), 3);
  const ClippedVoronoi2 cv3 = clip(holes, dt3);
  check_diagram(holes, dt3, cv3, 5000, 8);
  REQUIRE(cv3.cell_ring_begin(1) - cv3.cell_ring_begin(0) == 3);
  REQUIRE(cv3.area(1) == 0);
  REQUIRE(cv3.area(2) == 0);
}

TEST_CASE("clip2d: sites on the boundary, bisectors through domain vertices, cocircular",
          "[clip][degenerate]") {
  // Sites on an integer grid (cocircular quadruples everywhere) over a square domain
  // whose edges and corners are grid points: sites on vertices and edges, bisectors
  // through corners and along edges.
  const Domain2 d(rings_of({square(0, 0, 6, 6), square(2, 2, 4, 4)}));
  std::vector<double> grid;
  for (int i = -1; i <= 7; ++i) {
    for (int j = -1; j <= 7; ++j) grid.insert(grid.end(), {double(i), double(j)});
  }
  const auto n = static_cast<std::uint32_t>(grid.size() / 2);
  const Delaunay2 dt(grid.data(), n);
  check_diagram(d, dt, clip(d, dt), 20000, 11);
  // Half-integer grid: bisectors run exactly along the domain's edges.
  std::vector<double> half;
  for (int i = -2; i <= 7; ++i) {
    for (int j = -2; j <= 7; ++j) half.insert(half.end(), {i + 0.5, j + 0.5});
  }
  const Delaunay2 dth(half.data(), static_cast<std::uint32_t>(half.size() / 2));
  check_diagram(d, dth, clip(d, dth), 20000, 12);
  // The domain's own vertices as the only sites, plus duplicates.
  std::vector<double> corners = d.coords();
  corners.insert(corners.end(), d.coords().begin(), d.coords().begin() + 4);
  const Delaunay2 dtc(corners.data(), static_cast<std::uint32_t>(corners.size() / 2));
  const ClippedVoronoi2 cvc = clip(d, dtc);
  check_diagram(d, dtc, cvc, 20000, 13);
  REQUIRE(cvc.nb_boundary_sites() == 8);
}

TEST_CASE("clip2d: sites outside the domain", "[clip][degenerate]") {
  const Domain2 d(rings_of({square(0, 0, 1, 1), square(0.4, 0.4, 0.6, 0.6)}));
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1, 2);
  std::vector<double> sites(2 * 300);
  for (double& x : sites) x = u(rng);
  const Delaunay2 dt(sites.data(), 300);
  const ClippedVoronoi2 cv = clip(d, dt);
  check_diagram(d, dt, cv, 20000, 5);
  for (std::uint32_t i = 0; i < 300; ++i) {
    const Sign s = d.locate(&sites[2 * i]);
    if (s == Sign::negative && !cv.is_boundary(i)) REQUIRE(cv.area(i) == 0);
    if (s == Sign::positive && !cv.is_boundary(i)) REQUIRE(cv.area(i) > 0);
  }
}

TEST_CASE("clip2d: every valid polygon of shared/data", "[clip][data]") {
  const char* files[] = {"building", "dude",    "earcut",  "eberly-6", "hilbert",
                         "issue29",  "issue34", "issue35", "issue52"};
  for (const char* f : files) {
    const Domain2 d(voroclip::read_polygon(kData + "/polygons/valid/" + f + ".json"));
    for (std::uint32_t n : {5u, 200u, static_cast<std::uint32_t>(3000 * test_scale())}) {
      const std::vector<double> sites = sample_inside(d, n, n);
      const Delaunay2 dt(sites.data(), n);
      check_diagram(d, dt, clip(d, dt), 3000, n);
    }
  }
}

TEST_CASE("clip2d: 10^5 random points in the cells of their nearest sites", "[clip][data]") {
  const Domain2 d(voroclip::read_polygon(kData + "/polygons/valid/issue35.json"));
  const auto n = static_cast<std::uint32_t>(5000 * test_scale());
  const std::vector<double> sites = sample_inside(d, n, 21);
  const Delaunay2 dt(sites.data(), n);
  check_diagram(d, dt, clip(d, dt), static_cast<std::uint32_t>(100000 * test_scale()), 21);
}

TEST_CASE("clip2d: identical results with 1 and 2 threads", "[clip][threads]") {
  const Domain2 d(voroclip::read_polygon(kData + "/polygons/valid/issue35.json"));
  const std::vector<double> sites = sample_inside(d, 20000, 3);
  const Delaunay2 dt(sites.data(), 20000);
  ClippedVoronoi2 one, two;
  voroclip::Clip2Options o;
  o.keep_geometry = true;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one.compute(d, dt, o);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism,
                          voroclip_test::test_threads());
    two.compute(d, dt, o);
  }
  for (std::uint32_t i = 0; i < one.nb_sites(); ++i) {
    REQUIRE(one.area(i) == two.area(i));
    REQUIRE(one.energy(i) == two.energy(i));
    REQUIRE(one.centroid(i)[0] == two.centroid(i)[0]);
    REQUIRE(one.centroid(i)[1] == two.centroid(i)[1]);
  }
  REQUIRE(one.vertex_coords() == two.vertex_coords());
  REQUIRE(one.vertices() == two.vertices());
}

TEST_CASE("clip2d: densities", "[clip]") {
  // rho = 1 + 2x + 3y on the unit square with a hole: linear, so the grid density is
  // exact, and the degree-4 rule of the callback too (the integrands are of degree <= 3).
  const Domain2 d(rings_of({square(0, 0, 1, 1), square(0.25, 0.5, 0.5, 0.75)}));
  const auto rho = [](double x, double y) { return 1 + 2 * x + 3 * y; };
  const double lo[2] = {0, 0}, hi[2] = {1, 1};
  std::vector<double> values;
  for (int j = 0; j < 7; ++j) {
    for (int i = 0; i < 7; ++i) values.push_back(rho(i / 6.0, j / 6.0));
  }
  const std::vector<double> sites = sample_inside(d, 500, 9);
  const Delaunay2 dt(sites.data(), 500);
  voroclip::Clip2Options og, oc;
  og.density = voroclip::Density2::linear_grid(7, 7, lo, hi, values);
  oc.density = voroclip::Density2::function(rho);
  ClippedVoronoi2 g, c;
  g.compute(d, dt, og);
  c.compute(d, dt, oc);
  // ∫rho over the domain: square 1 + 1 + 1.5 = 3.5, minus the hole 0.0625 * rho(centre).
  const double mass = 3.5 - 0.0625 * rho(0.375, 0.625);
  REQUIRE(std::fabs(g.total_mass() - mass) <= 1e-12 * mass);
  REQUIRE(std::fabs(c.total_mass() - mass) <= 1e-12 * mass);
  for (std::uint32_t i = 0; i < 500; ++i) {
    REQUIRE(std::fabs(g.mass(i) - c.mass(i)) <= 1e-12 * mass);
    REQUIRE(std::fabs(g.energy(i) - c.energy(i)) <= 1e-12 * c.total_energy());
    REQUIRE(std::fabs(g.centroid(i)[0] - c.centroid(i)[0]) <= 1e-10);
    REQUIRE(std::fabs(g.centroid(i)[1] - c.centroid(i)[1]) <= 1e-10);
  }
}

TEST_CASE("clip2d: a variable density is evaluated only inside the cells", "[clip][regression]") {
  // Regression (mesh2d issue35.json --vertices 7000: "Delaunay2: point 4259 has a non-finite
  // coordinate"): a boundary cell holding a small hole was integrated by a fan of signed
  // triangles from one of its vertices, whose quadrature points lay in the hole, where
  // mesh2d's sizing density is huge; the cancellation failed and the cell's mass came out
  // at -2.7e9. Here the density is NaN outside the domain, so a single evaluation outside
  // shows; inside it is of degree 1, so every cell's mass, centroid and energy must equal
  // an independent exact integration (signed fans from the origin, Radon's degree-5 rule,
  // of the polynomial defined everywhere).
  std::vector<double> outer = {0, 0, 6, 0, 6, 4, 4, 4, 4, 2, 2, 2, 2, 4, 0, 4};  // a U
  const Domain2 d(rings_of(
      {outer, square(0.5, 0.5, 0.8, 0.9), square(4.6, 3.1, 4.7, 3.3), {3, 0.5, 3.4, 1, 2.7, 1.2}}));
  const auto poly = [](double x, double y) { return 1 + 2 * x + 3 * y; };
  const auto inside_only = [&](double x, double y) {
    const double p[2] = {x, y};
    return d.locate(p) == Sign::negative ? std::nan("") : poly(x, y);
  };
  const std::vector<double> sites = sample_inside(d, 7, 4);
  const Delaunay2 dt(sites.data(), 7);
  voroclip::Clip2Options o;
  o.density = voroclip::Density2::function(inside_only);
  o.keep_geometry = true;
  ClippedVoronoi2 cv;
  cv.compute(d, dt, o);
  const std::vector<double>& xy = cv.vertex_coords();
  const double s15 = std::sqrt(15.0);
  const double ra[3] = {1.0 / 3, (6 - s15) / 21, (6 + s15) / 21};
  const double rw[3] = {9.0 / 40, (155 - s15) / 1200, (155 + s15) / 1200};
  bool holed = false, reflex = false;
  double total = 0;
  for (std::uint32_t i = 0; i < 7; ++i) {
    INFO("cell " << i);
    holed = holed || cv.cell_ring_begin(i + 1) - cv.cell_ring_begin(i) > 1;
    double m = 0, mx = 0, my = 0, e = 0;
    for (std::uint32_t r = cv.cell_ring_begin(i); r < cv.cell_ring_begin(i + 1); ++r) {
      const std::uint32_t b = cv.ring_vertex_begin(r), end = cv.ring_vertex_begin(r + 1);
      for (std::uint32_t k = b; k < end; ++k) {
        const double* p = &xy[2 * std::size_t{k}];
        const double* q = &xy[2 * std::size_t{k + 1 < end ? k + 1 : b}];
        const double* n = &xy[2 * std::size_t{k + 2 < end ? k + 2 : b + (k + 2 - end)}];
        reflex = reflex || voroclip::orient2d(p, q, n) == Sign::negative;
        const double area = 0.5 * (p[0] * q[1] - p[1] * q[0]);  // (origin, p, q)
        for (int j = 0; j < 7; ++j) {
          // Radon's points: the centroid, then (a, a, 1 - 2a) and its permutations.
          const double a = ra[j == 0 ? 0 : (j - 1) / 3 + 1];
          const double w = rw[j == 0 ? 0 : (j - 1) / 3 + 1];
          const double bp = j == 0 ? a : (j - 1) % 3 == 0 ? a : (j - 1) % 3 == 1 ? a : 1 - 2 * a;
          const double bq = j == 0 ? a : (j - 1) % 3 == 0 ? a : (j - 1) % 3 == 1 ? 1 - 2 * a : a;
          const double x = bp * p[0] + bq * q[0], y = bp * p[1] + bq * q[1];
          const double f = area * w * poly(x, y);
          const double dx = x - sites[2 * i], dy = y - sites[2 * i + 1];
          m += f;
          mx += f * x;
          my += f * y;
          e += f * (dx * dx + dy * dy);
        }
      }
    }
    REQUIRE(std::isfinite(cv.mass(i)));
    REQUIRE(cv.mass(i) == Approx(m).epsilon(1e-12));
    REQUIRE(cv.centroid(i)[0] == Approx(mx / m).epsilon(1e-12));
    REQUIRE(cv.centroid(i)[1] == Approx(my / m).epsilon(1e-12));
    REQUIRE(cv.energy(i) == Approx(e).epsilon(1e-11));
    total += m;
  }
  REQUIRE(holed);   // the test has cells with holes
  REQUIRE(reflex);  // and non-convex cells
  // ∫(1 + 2x + 3y) over the U (24 - 4 of the notch) minus the holes: area + 2 Mx + 3 My.
  const auto rect = [&](double x0, double y0, double x1, double y1) {
    const double a = (x1 - x0) * (y1 - y0);
    return a * poly(0.5 * (x0 + x1), 0.5 * (y0 + y1));
  };
  const double tri_area = 0.5 * std::fabs((3.4 - 3) * (1.2 - 0.5) - (2.7 - 3) * (1 - 0.5));
  const double exact = rect(0, 0, 6, 4) - rect(2, 2, 4, 4) - rect(0.5, 0.5, 0.8, 0.9) -
                       rect(4.6, 3.1, 4.7, 3.3) - tri_area * poly(9.1 / 3, 2.7 / 3);
  REQUIRE(total == Approx(exact).epsilon(1e-13));
  REQUIRE(cv.total_mass() == Approx(exact).epsilon(1e-13));
}

// Regression: for sites far outside the domain the bisector's point on a domain edge came
// from (x - (p + q) / 2).(q - p), which keeps nothing for sites 1e20 away, and the Voronoi
// vertex from its offset to a site 1e20 away: (1e20, 0.3), (-1e20, 0.2), (0.3, 1e20) gave
// areas 0.15, 0, 0.85 in the unit square. Exact answers for (s, 0.3), (-s, 0.3), (0.3, s):
// the bisectors are x = 0 and y = x, so areas 1/2, 0, 1/2 and centroids (2/3, 1/3),
// (1/3, 2/3); for the reported sites the second cell is a sliver at the corner 0 (area
// below 1e-20) and the others the same. Within 1e-12 of them (measured: to the last bit).
TEST_CASE("clip2d: sites far outside the domain", "[clip][regression]") {
  const Domain2 d(rings_of({square(0, 0, 1, 1)}));
  const auto near = [](double a, double b) { return std::fabs(a - b) <= 1e-12; };
  const auto check = [&](const std::vector<double>& sites) {
    const Delaunay2 dt(sites.data(), 3);
    const ClippedVoronoi2 cv = clip(d, dt);
    CHECK(near(cv.area(0), 0.5));
    CHECK(near(cv.area(1), 0));
    CHECK(near(cv.area(2), 0.5));
    CHECK(near(cv.centroid(0)[0], 2.0 / 3));
    CHECK(near(cv.centroid(0)[1], 1.0 / 3));
    CHECK(near(cv.centroid(2)[0], 1.0 / 3));
    CHECK(near(cv.centroid(2)[1], 2.0 / 3));
  };
  for (const double s : {1e3, 1e6, 1e10, 1e20, 1e100}) {
    INFO("s = " << s);
    check({s, 0.3, -s, 0.3, 0.3, s});
  }
  check({1e20, 0.3, -1e20, 0.2, 0.3, 1e20});
  // Beyond 2^500 from the domain the energy (~ s^2 area) may overflow: an Error, not inf.
  const std::vector<double> three = {1e200, 0.3, -1e200, 0.2, 0.3, 1e200};
  const Delaunay2 dt(three.data(), 3);
  CHECK_THROWS_WITH(clip(d, dt), Catch::Contains("too far from the domain"));
}

TEST_CASE("clip2d: one site, or sites on one line, with far auxiliary sites",
          "[clip][degenerate]") {
  // They have no Delaunay triangulation of their own; compute(domain, sites, n) adds 3 (a
  // point) or 2 (a line) far sites whose cells miss the domain. Facts checked: areas and
  // centroids from closed forms, the rings, and random probes in the nearest site's cell.
  const Domain2 holed(rings_of({square(0, 0, 1, 1), square(0.1, 0.6, 0.3, 0.9)}));
  const Domain2 unit(rings_of({square(0, 0, 1, 1)}));
  const auto near = [](double a, double b) { return std::fabs(a - b) <= 1e-12; };
  const auto probe = [](const Domain2& d, const ClippedVoronoi2& cv, const std::vector<double>& s) {
    const auto n = static_cast<std::uint32_t>(s.size() / 2);
    const std::vector<double> probes = sample_inside(d, 2000, 7);
    for (std::size_t q = 0; q < probes.size(); q += 2) {
      const double* p = &probes[q];
      std::uint32_t best = 0;  // the nearest site, the first of equal ones (no ties here)
      for (std::uint32_t i = 1; i < n; ++i) {
        const auto d2 = [&](std::uint32_t k) {
          return (p[0] - s[2 * k]) * (p[0] - s[2 * k]) +
                 (p[1] - s[2 * k + 1]) * (p[1] - s[2 * k + 1]);
        };
        if (d2(i) < d2(best)) best = i;
      }
      INFO("probe (" << p[0] << ", " << p[1] << "), nearest site " << best);
      REQUIRE(winding(cv, cv.cell_ring_begin(best), cv.cell_ring_begin(best + 1), p) == 1);
    }
  };
  voroclip::Clip2Options o;
  o.keep_geometry = true;
  ClippedVoronoi2 cv;

  SECTION("one site, inside, outside, or repeated: the whole domain") {
    // Holed square: area 1 - 0.06, centroid from the square's minus the hole's.
    const double area = 0.94;
    const double cx = (0.5 - 0.06 * 0.2) / area, cy = (0.5 - 0.06 * 0.75) / area;
    for (const std::vector<double>& s :
         {std::vector<double>{0.7, 0.2}, {2.5, -3}, {0.7, 0.2, 0.7, 0.2, 0.7, 0.2}}) {
      INFO(s.size() / 2 << " sites at (" << s[0] << ", " << s[1] << ")");
      cv.compute(holed, s.data(), static_cast<std::uint32_t>(s.size() / 2), o);
      CHECK(cv.nb_auxiliary_sites() == 3);
      REQUIRE(cv.nb_sites() == s.size() / 2);
      CHECK(near(cv.area(0), area));
      CHECK(near(cv.total_area(), area));
      CHECK(near(cv.centroid(0)[0], cx));
      CHECK(near(cv.centroid(0)[1], cy));
      // Energy: a rectangle's integral of |x - s|^2 is its area (|c - s|^2 + (w^2 + h^2) / 12).
      const auto moment = [&](double x0, double y0, double w, double h) {
        const double dx = x0 + w / 2 - s[0], dy = y0 + h / 2 - s[1];
        return w * h * (dx * dx + dy * dy + (w * w + h * h) / 12);
      };
      CHECK(std::fabs(cv.energy(0) - (moment(0, 0, 1, 1) - moment(0.1, 0.6, 0.2, 0.3))) <=
            1e-12 * cv.energy(0));
      CHECK(cv.is_boundary(0));
      for (std::uint32_t i = 1; i < cv.nb_sites(); ++i) CHECK(cv.area(i) == 0);
      // Its rings: the domain's two.
      REQUIRE(cv.cell_ring_begin(1) - cv.cell_ring_begin(0) == 2);
      CHECK(near(ring_area(cv, cv.cell_ring_begin(0)) + ring_area(cv, cv.cell_ring_begin(0) + 1),
                 area));
      probe(holed, cv, s);
    }
  }

  SECTION("sites on one line: strips, also through domain vertices") {
    // Along the diagonal: bisectors x + y = a + b; {x + y <= t} in the unit square has area
    // t^2 / 2 (t <= 1) or 1 - (2 - t)^2 / 2.
    const std::vector<double> diagonal = {0.6, 0.6, 0.1, 0.1, 0.9, 0.9, 0.3, 0.3};
    cv.compute(unit, diagonal.data(), 4, o);
    CHECK(cv.nb_auxiliary_sites() == 2);
    REQUIRE(cv.nb_sites() == 4);
    CHECK(near(cv.area(1), 0.08));
    CHECK(near(cv.area(3), 0.405 - 0.08));
    CHECK(near(cv.area(0), 0.875 - 0.405));
    CHECK(near(cv.area(2), 0.125));
    CHECK(near(cv.total_area(), 1));
    probe(unit, cv, diagonal);
    // Two sites whose bisector x + y = 1 runs through the corners (1, 0) and (0, 1).
    const std::vector<double> corners = {0, 0, 1, 1};
    cv.compute(unit, corners.data(), 2, o);
    CHECK(cv.nb_auxiliary_sites() == 2);
    CHECK(near(cv.area(0), 0.5));
    CHECK(near(cv.area(1), 0.5));
    CHECK(near(cv.centroid(0)[0], 1.0 / 3));
    CHECK(near(cv.centroid(1)[1], 2.0 / 3));
    // Horizontal: x = 0.35 and x = 0.7 cut the holed square, the hole in the first strip.
    const std::vector<double> row = {0.2, 0.5, 0.5, 0.5, 0.9, 0.5};
    cv.compute(holed, row.data(), 3, o);
    CHECK(near(cv.area(0), 0.35 - 0.06));
    CHECK(near(cv.area(1), 0.35));
    CHECK(near(cv.area(2), 0.3));
    probe(holed, cv, row);
  }

  SECTION("sites that span the plane: as on their own triangulation, bit for bit") {
    const std::vector<double> s = sample_inside(holed, 300, 11);
    cv.compute(holed, s.data(), 300, o);
    CHECK(cv.nb_auxiliary_sites() == 0);
    const Delaunay2 dt(s.data(), 300);
    const ClippedVoronoi2 ref = clip(holed, dt);
    for (std::uint32_t i = 0; i < 300; ++i) {
      CHECK(cv.area(i) == ref.area(i));
      CHECK(cv.energy(i) == ref.energy(i));
      CHECK(cv.centroid(i)[0] == ref.centroid(i)[0]);
    }
    CHECK(cv.vertex_coords() == ref.vertex_coords());
  }
}
