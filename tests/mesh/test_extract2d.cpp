// Tests of the 2D extraction and the exact mesh checker (voroclip/mesh.h): the circumcenter
// rule against the clipped diagram's own Voronoi vertices, degenerate circumcenters on
// the boundary, grids whose extraction is known, and check_mesh2 on broken meshes.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/delaunay.h"
#include "voroclip/mesh.h"

using voroclip::ClippedVoronoi2;
using voroclip::ClipVertex2;
using voroclip::Delaunay2;
using voroclip::Domain2;
using voroclip::Mesh2;
using voroclip::PolygonRings;
using voroclip::Sign;

namespace {

const std::string kData = VOROCLIP_SHARED_DATA_DIR;

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

// The Voronoi vertices (i < k < l) that appear in the rings of the clipped cells: exactly
// the ones inside the domain (the clipper decides them with the same perturbation).
std::set<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>> clipped_voronoi_vertices(
    const Domain2& d, const Delaunay2& dt) {
  ClippedVoronoi2 cv;
  voroclip::Clip2Options o;
  o.keep_geometry = true;
  cv.compute(d, dt, o);
  std::set<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>> out;
  for (const ClipVertex2& v : cv.vertices()) {
    if (v.kind == ClipVertex2::Kind::kVoronoi) out.insert({v.a, v.b, v.c});
  }
  return out;
}

// Compares circumcenter_location2 with the clipped diagram on every Delaunay triangle.
void check_against_clip(const Domain2& d, const std::vector<double>& sites) {
  const Delaunay2 dt(sites.data(), static_cast<std::uint32_t>(sites.size() / 2));
  const auto inside = clipped_voronoi_vertices(d, dt);
  std::uint32_t nb_in = 0;
  for (std::uint32_t t = 0; t < dt.nb_triangles(); ++t) {
    std::uint32_t v[3] = {dt.tri_vertex(t, 0), dt.tri_vertex(t, 1), dt.tri_vertex(t, 2)};
    std::sort(v, v + 3);
    const Sign s = voroclip::circumcenter_location2(d, dt, t);
    REQUIRE(s != Sign::zero);
    INFO("triangle " << t << " sites " << v[0] << " " << v[1] << " " << v[2]);
    REQUIRE((s == Sign::positive) == (inside.count({v[0], v[1], v[2]}) > 0));
    nb_in += s == Sign::positive;
  }
  REQUIRE(nb_in > 0);
}

double mesh_area(const Mesh2& m) {
  double a = 0;
  for (std::uint32_t t = 0; t < m.nb_triangles(); ++t) {
    const double* p = &m.xy[2 * std::size_t{m.triangles[3 * t]}];
    const double* q = &m.xy[2 * std::size_t{m.triangles[3 * t + 1]}];
    const double* r = &m.xy[2 * std::size_t{m.triangles[3 * t + 2]}];
    a += 0.5 * ((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]));
  }
  return a;
}

}  // namespace

TEST_CASE("extract2d: circumcenter location agrees with the clipped diagram", "[mesh][exact]") {
  SECTION("random sites in issue35.json (29 holes)") {
    const Domain2 d(voroclip::read_polygon(kData + "/polygons/valid/issue35.json"));
    const std::uint64_t seed = 35;
    INFO("seed " << seed);
    check_against_clip(d, sample_inside(d, 400, seed));
  }
  SECTION("random sites in a square with holes, some outside the domain") {
    const Domain2 d(
        rings_of({square(0, 0, 1, 1), square(0.2, 0.2, 0.4, 0.45), square(0.6, 0.55, 0.8, 0.8)}));
    const std::uint64_t seed = 7;
    INFO("seed " << seed);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-0.2, 1.2);
    std::vector<double> sites;
    for (int k = 0; k < 300; ++k) sites.push_back(u(rng));
    check_against_clip(d, sites);
  }
}

TEST_CASE("extract2d: degenerate circumcenters exactly on the boundary",
          "[mesh][exact][degenerate]") {
  SECTION("on an edge") {
    // (1, 2), (3, 2), (4, 1) have their circumcenter exactly at (2, 0), on the bottom edge
    // of [0, 4]^2, and the other sites lie outside that circle (a Delaunay triangle).
    const Domain2 d(rings_of({square(0, 0, 4, 4)}));
    check_against_clip(d, {1, 2, 3, 2, 4, 1, 2, 3, 0, 4, 4, 4, 1, 3.5});
  }
  SECTION("at a vertex") {
    // Four cocircular sites around the corner (0, 0) of [0, 8]^2: the Voronoi vertex of
    // any three of them is exactly the corner.
    const Domain2 d(rings_of({square(0, 0, 8, 8)}));
    check_against_clip(d, {5, 0, 4, 3, 3, 4, 0, 5, 8, 8, 8, 0, 0, 8});
  }
  SECTION("a grid with cocircular quadruples") {
    const Domain2 d(rings_of({square(0, 0, 4, 4)}));
    std::vector<double> grid;
    for (int j = -1; j <= 5; ++j) {
      for (int i = -1; i <= 5; ++i) {
        grid.push_back(i);
        grid.push_back(j);
      }
    }
    check_against_clip(d, grid);
  }
}

TEST_CASE("extract2d: a boundary grid gives the whole square", "[mesh][exact]") {
  // The (k+1)^2 grid on [0, k]^2: the perturbed Delaunay triangulation splits each unit
  // square in two right triangles along a diagonal, whose circumcenter (the square's
  // centre) is inside: every triangle is kept and they tile the square.
  const int k = 6;
  const Domain2 d(rings_of({square(0, 0, k, k)}));
  std::vector<double> grid;
  for (int j = 0; j <= k; ++j) {
    for (int i = 0; i <= k; ++i) {
      grid.push_back(i);
      grid.push_back(j);
    }
  }
  voroclip::Extract2Stats st;
  const Mesh2 m = voroclip::extract_mesh2(d, grid, {}, {}, {}, &st);
  REQUIRE(voroclip::check_mesh2(d, m).empty());
  REQUIRE(st.nb_delaunay == 2 * k * k);
  REQUIRE(st.dropped_outside == 0);
  REQUIRE(st.gap_triangles.empty());
  REQUIRE(m.nb_triangles() == 2 * k * k);
  REQUIRE(m.nb_vertices() == (k + 1) * (k + 1));
  REQUIRE(mesh_area(m) == Approx(k * k).epsilon(1e-14));
}

TEST_CASE("extract2d: triangles over a hole or across a concave part are not kept",
          "[mesh][exact]") {
  // Only the corners of the outer square and of a small central hole: Delaunay triangles
  // cover the hole; none may be in the mesh.
  const Domain2 d(rings_of({square(0, 0, 10, 10), square(4, 4.5, 5.5, 6)}));
  const std::vector<double> sites = {0, 0, 10, 0, 10, 10, 0, 10, 4, 4.5, 5.5, 4.5, 5.5, 6, 4, 6};
  voroclip::Extract2Stats st;
  const Mesh2 m = voroclip::extract_mesh2(d, sites, {}, {}, {}, &st, true);
  REQUIRE(voroclip::check_mesh2(d, m).empty());
  const double c[2] = {4.75, 5.25};  // the hole's centre
  for (std::uint32_t t = 0; t < m.nb_triangles(); ++t) {
    const double* p[3];
    for (int k = 0; k < 3; ++k) p[k] = &m.xy[2 * std::size_t{m.triangles[3 * t + k]}];
    const bool covers = voroclip::orient2d(p[0], p[1], c) == Sign::positive &&
                        voroclip::orient2d(p[1], p[2], c) == Sign::positive &&
                        voroclip::orient2d(p[2], p[0], c) == Sign::positive;
    REQUIRE_FALSE(covers);
  }
  // With every triangle of the region kept (keep_gaps), the 8 vertices and one hole give
  // exactly n + 2h - 2 = 8 triangles of total area 100 - 2.25.
  REQUIRE(m.nb_triangles() == 8);
  REQUIRE(mesh_area(m) == Approx(100 - 2.25).epsilon(1e-14));

  // An L-shaped domain whose reflex corner (1, 1) is not a site: the Delaunay edge from
  // (4, 1) to (1, 4) cuts the notch, so no kept triangle may use it.
  const Domain2 l(rings_of({{0, 0, 4, 0, 4, 1, 1, 1, 1, 4, 0, 4}}));
  const std::vector<double> ls = {0, 0, 4, 0, 4, 1, 1, 4, 0, 4, 0.5, 0.5};
  const Mesh2 lm = voroclip::extract_mesh2(l, ls, {}, {}, {}, nullptr, true);
  REQUIRE(voroclip::check_mesh2(l, lm).empty());
  REQUIRE(lm.nb_triangles() > 0);
  for (std::uint32_t t = 0; t < lm.nb_triangles(); ++t) {
    int ends = 0;
    for (int k = 0; k < 3; ++k) {
      const double* p = &lm.xy[2 * std::size_t{lm.triangles[3 * t + k]}];
      ends += (p[0] == 4 && p[1] == 1) || (p[0] == 1 && p[1] == 4);
    }
    REQUIRE(ends < 2);
  }
  REQUIRE(mesh_area(lm) < 7);
}

TEST_CASE("check_mesh2 reports every kind of defect", "[mesh][exact]") {
  const Domain2 d(rings_of({square(0, 0, 4, 4), square(1, 1, 2, 2)}));
  Mesh2 good;
  good.xy = {4, 0, 4, 4, 0, 4};
  good.triangles = {0, 1, 2};  // touches the hole's corner (2, 2) with its long edge
  REQUIRE(voroclip::check_mesh2(d, good).empty());

  Mesh2 over_hole;
  over_hole.xy = {0, 0, 4, 0, 0, 4};
  over_hole.triangles = {0, 1, 2};
  REQUIRE(voroclip::check_mesh2(d, over_hole).find("crossed") != std::string::npos);

  Mesh2 outside;
  outside.xy = {5, 5, 6, 5, 5, 6};
  outside.triangles = {0, 1, 2};
  REQUIRE_FALSE(voroclip::check_mesh2(d, outside).empty());

  Mesh2 inverted = good;
  inverted.triangles = {1, 0, 2};
  REQUIRE(voroclip::check_mesh2(d, inverted).find("counter-clockwise") != std::string::npos);

  Mesh2 flat;
  flat.xy = {0, 0, 2, 0, 4, 0};
  flat.triangles = {0, 1, 2};
  REQUIRE(voroclip::check_mesh2(d, flat).find("counter-clockwise") != std::string::npos);

  Mesh2 unused = good;
  unused.xy.insert(unused.xy.end(), {3, 3});
  REQUIRE(voroclip::check_mesh2(d, unused).find("used by no triangle") != std::string::npos);

  Mesh2 overlap;
  overlap.xy = {2.5, 0.5, 3.5, 0.5, 3, 3.5, 2.6, 0.6, 3.6, 0.6, 3.1, 3.6};
  overlap.triangles = {0, 1, 2, 3, 4, 5};
  REQUIRE(voroclip::check_mesh2(d, overlap).find("overlaps") != std::string::npos);

  Mesh2 repeated;
  repeated.xy = {2.5, 0.5, 3.5, 0.5, 3, 3.5};
  repeated.triangles = {0, 1, 2, 0, 1, 2};
  REQUIRE(voroclip::check_mesh2(d, repeated).find("directed edge") != std::string::npos);
}
