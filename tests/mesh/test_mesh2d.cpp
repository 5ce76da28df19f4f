// Tests of the 2D CVT mesher (voroclip/mesh.h, mesh_domain2): every mesh is checked
// exactly (check_mesh2: counter-clockwise non-degenerate triangles inside the closed
// domain, conforming, no unused vertex); quality thresholds are facts about our output
// for fixed seeds; fixed vertices present; sliding vertices on their edge; sharp corners
// cut; 1 vs 2 threads bitwise identical; bad options and cancellation.
#include <catch2/catch.hpp>
#include <tbb/global_control.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "support/threads.h"
#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/mesh.h"

using voroclip::Domain2;
using voroclip::Mesh2;
using voroclip::Mesh2Options;
using voroclip::Mesh2Stats;
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

Mesh2 mesh_of(const Domain2& d, std::uint32_t n, Mesh2Stats* st = nullptr,
              Mesh2Options o = Mesh2Options{}) {
  o.nb_vertices = n;
  Mesh2Stats local;
  Mesh2 m = voroclip::mesh_domain2(d, o, st ? st : &local);
  INFO("domain " << d.source() << ", " << n << " vertices asked, seed " << o.seed);
  REQUIRE(voroclip::check_mesh2(d, m).empty());
  if (o.conforming && o.corner_angle_deg == 0) {
    REQUIRE(voroclip::check_mesh2_conforming(d, m).empty());
  }
  REQUIRE((st ? st : &local)->check.empty());
  return m;
}

// Issue 31's angle bound, per triangle: 30 degrees, or min(30, the corner's interior
// angle) for a triangle with a vertex at an input corner sharper than 60 degrees (its
// sharpest one). The triangles below 30 degrees and how many of them miss their bound
// (1e-9 degrees of rounding allowed: the tip of a cut corner has the corner's own angle,
// computed from other coordinates).
struct AngleBound {
  std::uint32_t below_30 = 0, at_sharp_corner = 0, missed = 0;
  double worst = 180;  // the smallest angle of a triangle that misses its bound
  double bound = 30;   // the lowest bound of a triangle below 30 degrees
};
AngleBound angle_bound(const Domain2& d, const Mesh2& m) {
  AngleBound r;
  const std::vector<double> angles = voroclip::triangle_min_angles(m);
  for (std::uint32_t t = 0; t < m.nb_triangles(); ++t) {
    if (angles[t] >= 30) continue;
    ++r.below_30;
    double corner = 180;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = m.vertex_domain[m.triangles[3 * std::size_t{t} + std::size_t(k)]];
      if (v == Mesh2::kNone) continue;
      const double* a = d.vertex(d.prev(v));
      const double* p = d.vertex(v);
      const double* c = d.vertex(d.next(v));
      const double ux = p[0] - a[0], uy = p[1] - a[1], wx = c[0] - p[0], wy = c[1] - p[1];
      const double interior =
          180 - std::atan2(ux * wy - uy * wx, ux * wx + uy * wy) * 180 / 3.14159265358979323846;
      if (interior < 60) corner = std::min(corner, interior);
    }
    r.at_sharp_corner += corner < 60;
    const double bound = std::min(30.0, corner);
    r.bound = std::min(r.bound, bound);
    if (angles[t] < bound - 1e-9) {
      ++r.missed;
      r.worst = std::min(r.worst, angles[t]);
    }
  }
  return r;
}

bool has_vertex_at(const Mesh2& m, const double* p) {
  for (std::uint32_t v = 0; v < m.nb_vertices(); ++v) {
    if (m.xy[2 * v] == p[0] && m.xy[2 * v + 1] == p[1]) return true;
  }
  return false;
}

// Every reflex vertex and every convex vertex turning by at least `corner` degrees is a
// mesh vertex, recorded as fixed at that domain vertex.
void check_fixed_vertices(const Domain2& d, const Mesh2& m, double corner) {
  std::vector<std::uint8_t> seen(d.nb_vertices(), 0);
  for (std::uint32_t v = 0; v < m.nb_vertices(); ++v) {
    if (m.vertex_domain[v] == Mesh2::kNone) continue;
    REQUIRE(m.vertex_kind[v] == Mesh2::VertexKind::kFixed);
    const double* p = d.vertex(m.vertex_domain[v]);
    REQUIRE(m.xy[2 * v] == p[0]);
    REQUIRE(m.xy[2 * v + 1] == p[1]);
    seen[m.vertex_domain[v]] = 1;
  }
  for (std::uint32_t v = 0; v < d.nb_vertices(); ++v) {
    const double* a = d.vertex(d.prev(v));
    const double* p = d.vertex(v);
    const double* c = d.vertex(d.next(v));
    const double ux = p[0] - a[0], uy = p[1] - a[1], wx = c[0] - p[0], wy = c[1] - p[1];
    const double turn = std::atan2(ux * wy - uy * wx, ux * wx + uy * wy) * 180 / M_PI;
    const Sign side = voroclip::orient2d(a, p, c);
    const bool required = side == Sign::negative || (side == Sign::positive && turn >= corner);
    INFO("domain vertex " << v << " (" << p[0] << ", " << p[1] << "), turn " << turn);
    if (required) REQUIRE(seen[v]);
  }
}

// Boundary vertices lie in the closed domain, on their edge up to a few ulps; `exact`:
// exactly on it (orient2d zero), as on horizontal and vertical edges.
void check_boundary_vertices(const Domain2& d, const Mesh2& m, bool exact) {
  std::uint32_t nb = 0;
  for (std::uint32_t v = 0; v < m.nb_vertices(); ++v) {
    if (m.vertex_kind[v] != Mesh2::VertexKind::kBoundary) continue;
    const std::uint32_t e = m.vertex_edge[v];
    REQUIRE(e != Mesh2::kNone);
    ++nb;
    const double* p = &m.xy[2 * v];
    const double* a = d.vertex(e);
    const double* b = d.vertex(d.next(e));
    REQUIRE(d.locate(p) != Sign::negative);
    REQUIRE(voroclip::orient2d(a, b, p) != Sign::negative);
    if (exact) {
      REQUIRE(voroclip::orient2d(a, b, p) == Sign::zero);
      REQUIRE(d.locate(p) == Sign::zero);
    }
    REQUIRE(std::min(a[0], b[0]) <= p[0]);
    REQUIRE(p[0] <= std::max(a[0], b[0]));
    REQUIRE(std::min(a[1], b[1]) <= p[1]);
    REQUIRE(p[1] <= std::max(a[1], b[1]));
    const double len = std::hypot(b[0] - a[0], b[1] - a[1]);
    const double dist =
        std::fabs((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])) / len;
    const double ulp = std::numeric_limits<double>::epsilon() *
                       std::max({std::fabs(p[0]), std::fabs(p[1]), 1e-300});
    REQUIRE(dist <= 8 * ulp);
  }
  REQUIRE(nb > 0);
}

// The issue's angle bound: a triangle at a domain corner sharper than 60 degrees has its
// smallest angle >= min(30, that corner's angle); every other triangle >= 30. Returns the
// number of triangles that miss it.
std::uint32_t triangles_below_bound(const Domain2& d, const Mesh2& m) {
  std::uint32_t below = 0;
  for (std::uint32_t t = 0; t < m.nb_triangles(); ++t) {
    double smallest = 180, bound = 30;
    for (std::uint32_t k = 0; k < 3; ++k) {
      const std::uint32_t v = m.triangles[3 * t + k];
      const double* a = &m.xy[2 * v];
      const double* b = &m.xy[2 * m.triangles[3 * t + (k + 1) % 3]];
      const double* c = &m.xy[2 * m.triangles[3 * t + (k + 2) % 3]];
      const double ux = b[0] - a[0], uy = b[1] - a[1], wx = c[0] - a[0], wy = c[1] - a[1];
      smallest = std::min(smallest,
                          std::atan2(std::fabs(ux * wy - uy * wx), ux * wx + uy * wy) * 180 / M_PI);
      const std::uint32_t dv = m.vertex_domain[v];
      if (dv == Mesh2::kNone || voroclip::orient2d(d.vertex(d.prev(dv)), d.vertex(dv),
                                                   d.vertex(d.next(dv))) != Sign::positive) {
        continue;
      }
      const double* p = d.vertex(d.prev(dv));
      const double* q = d.vertex(dv);
      const double* r = d.vertex(d.next(dv));
      const double px = p[0] - q[0], py = p[1] - q[1], rx = r[0] - q[0], ry = r[1] - q[1];
      const double corner =
          std::atan2(std::fabs(px * ry - py * rx), px * rx + py * ry) * 180 / M_PI;
      if (corner < 60) bound = std::min(bound, corner - 1e-9);
    }
    below += smallest < bound;
  }
  return below;
}

}  // namespace

TEST_CASE("mesh2d: square with holes — valid, quality, corners, exact boundary vertices",
          "[mesh][exact]") {
  const Domain2 d(voroclip::square_with_holes(2, 0.4));
  Mesh2Stats st;
  const Mesh2 m = mesh_of(d, 800, &st);
  const voroclip::TriangleQuality2 q = voroclip::triangle_quality2(m);
  INFO(voroclip::quality_text(q));
  CHECK(q.min_angle >= 30);
  CHECK(q.mean_min_angle >= 51);
  CHECK(st.nb_sharp_corners == 0);
  CHECK(m.nb_vertices() > 700);
  CHECK(m.nb_vertices() < 1000);
  check_fixed_vertices(d, m, 0);
  check_boundary_vertices(d, m, true);
  CHECK(std::fabs(st.covered_fraction - 1) <= 1e-12);
}

TEST_CASE("mesh2d: building.json and an annulus — quality facts", "[mesh][exact]") {
  SECTION("building.json") {
    const Domain2 d(voroclip::read_polygon(kData + "/polygons/valid/building.json"));
    const Mesh2 m = mesh_of(d, 1000);
    const voroclip::TriangleQuality2 q = voroclip::triangle_quality2(m);
    INFO(voroclip::quality_text(q));
    CHECK(q.min_angle >= 30);
    CHECK(q.mean_min_angle >= 51);
    check_fixed_vertices(d, m, 0);
    check_boundary_vertices(d, m, false);
  }
  SECTION("annulus, 48 segments") {
    const Domain2 d(voroclip::annulus_rings(0.5, 1.0, 48));
    Mesh2Stats st;
    const Mesh2 m = mesh_of(d, 700, &st);
    const voroclip::TriangleQuality2 q = voroclip::triangle_quality2(m);
    INFO(voroclip::quality_text(q));
    CHECK(q.min_angle >= 30);
    CHECK(q.mean_min_angle >= 51);
    // Every vertex is a corner (the outer ring turns by 7.5 degrees at each): all fixed.
    CHECK(st.nb_fixed == 96);
    check_fixed_vertices(d, m, 0);
    check_boundary_vertices(d, m, false);
    CHECK(std::fabs(st.covered_fraction - 1) <= 1e-12);
  }
  SECTION("annulus, 48 segments, coarsened: corner_angle_deg = 20 passes the outer bends") {
    const Domain2 d(voroclip::annulus_rings(0.5, 1.0, 48));
    Mesh2Options o;
    o.corner_angle_deg = 20;
    Mesh2Stats st;
    const Mesh2 m = mesh_of(d, 700, &st, o);
    const voroclip::TriangleQuality2 q = voroclip::triangle_quality2(m);
    INFO(voroclip::quality_text(q));
    CHECK(q.min_angle >= 30);
    // Inner ring: reflex vertices, all fixed; outer ring: 7.5-degree turns, passed, so
    // the mesh misses a sliver of each outer bend that its edges cut.
    CHECK(st.nb_fixed == 48);
    check_fixed_vertices(d, m, 20);
    CHECK(st.covered_fraction < 1 - 1e-6);
    CHECK(st.covered_fraction > 0.99);
  }
}

TEST_CASE("mesh2d: a sharp corner is cut, the rest stays valid and good", "[mesh][exact]") {
  // A quadrilateral whose corner at the origin has an interior angle of 2 atan(0.13) =
  // 14.8 degrees.
  const Domain2 d(rings_of({{0, 0, 10, -1.3, 12, 0, 10, 1.3}}));
  Mesh2Stats st;
  const Mesh2 m = mesh_of(d, 600, &st);
  const voroclip::TriangleQuality2 q = voroclip::triangle_quality2(m);
  INFO(voroclip::quality_text(q));
  CHECK(st.nb_sharp_corners == 1);
  CHECK(st.nb_tip_triangles == 1);
  CHECK(std::fabs(st.covered_fraction - 1) <= 1e-12);
  // The tip is one triangle at the corner vertex, isosceles, its smallest angle the
  // corner's; every other triangle has its angles >= 30 degrees.
  const double tip[2] = {0, 0};
  REQUIRE(has_vertex_at(m, tip));
  const double corner = 2 * std::atan(0.13) * 180 / M_PI;
  std::uint32_t at_tip = 0;
  double others = 180;
  for (std::uint32_t t = 0; t < m.nb_triangles(); ++t) {
    bool touches = false;
    double angle[3];
    for (int k = 0; k < 3; ++k) {
      const double* a = &m.xy[2 * m.triangles[3 * t + k]];
      const double* b = &m.xy[2 * m.triangles[3 * t + (k + 1) % 3]];
      const double* c = &m.xy[2 * m.triangles[3 * t + (k + 2) % 3]];
      touches = touches || (a[0] == 0 && a[1] == 0);
      const double ux = b[0] - a[0], uy = b[1] - a[1], wx = c[0] - a[0], wy = c[1] - a[1];
      angle[k] = std::atan2(std::fabs(ux * wy - uy * wx), ux * wx + uy * wy) * 180 / M_PI;
    }
    const double smallest = std::min({angle[0], angle[1], angle[2]});
    if (touches) {
      ++at_tip;
      CHECK(smallest == Approx(corner).epsilon(1e-9));
      CHECK(std::max({angle[0], angle[1], angle[2]}) == Approx((180 - corner) / 2).epsilon(1e-6));
    } else {
      others = std::min(others, smallest);
    }
  }
  CHECK(at_tip == 1);
  CHECK(others >= 30);
  // The chord's ends: fixed vertices on the two edges at the tip (edges 3 and 0).
  std::uint32_t cut_points = 0;
  for (std::uint32_t v = 0; v < m.nb_vertices(); ++v) {
    if (m.vertex_kind[v] != Mesh2::VertexKind::kFixed || m.vertex_domain[v] != Mesh2::kNone) {
      continue;
    }
    ++cut_points;
    const std::uint32_t e = m.vertex_edge[v];
    REQUIRE((e == 0 || e == 3));
    CHECK(d.locate(&m.xy[2 * v]) != Sign::negative);
  }
  CHECK(cut_points == 2);
  // Without the cut (sharp_angle_deg = 0) the tip is a fixed site; the mesh is still
  // valid and conforming.
  Mesh2Options o;
  o.sharp_angle_deg = 0;
  Mesh2Stats uncut_stats;
  mesh_of(d, 600, &uncut_stats, o);
  CHECK(uncut_stats.nb_sharp_corners == 0);
  CHECK(uncut_stats.nb_fixed == st.nb_fixed - 2 + 1);
}

TEST_CASE("mesh2d: the neighbours of a cut corner's chord meet the angle bound",
          "[mesh][regression]") {
  // issue34.json's outer ring and its hole 2, whose corners of 24.4 and 25.1 degrees are
  // cut. A cut point landed 3.0 short of a fixed vertex (and on issue35.json 0.16 short),
  // the short edge left next to the chord made triangles of 15-19 degrees there, and the
  // refinement skipped them (a chord is never split). Now a fixed vertex within half the
  // chord's length beyond the cut is the cut.
  const voroclip::PolygonRings all = voroclip::read_polygon(kData + "/polygons/valid/issue34.json");
  PolygonRings two = all;
  two.xy.clear();
  two.ring_begin = {0};
  two.ring_polygon.clear();
  two.ring_line.clear();
  for (const std::uint32_t r : {0u, 2u}) {
    two.xy.insert(two.xy.end(), all.xy.begin() + 2 * all.ring_begin[r],
                  all.xy.begin() + 2 * all.ring_begin[r + 1]);
    two.ring_begin.push_back(static_cast<std::uint32_t>(two.xy.size() / 2));
    two.ring_polygon.push_back(all.ring_polygon[r]);
    two.ring_line.push_back(all.ring_line[r]);
  }
  two.segment_marker.clear();
  two.point_number.clear();
  const Domain2 d(two);
  Mesh2Stats st;
  const Mesh2 m = mesh_of(d, 300, &st);
  INFO(voroclip::quality_text(voroclip::triangle_quality2(m)));
  CHECK(st.nb_sharp_corners == 2);
  CHECK(st.nb_tip_triangles == 2);
  CHECK(triangles_below_bound(d, m) == 0);
}

TEST_CASE("mesh2d: --fix-input-vertices keeps every domain vertex", "[mesh]") {
  const Domain2 d(voroclip::annulus_rings(0.5, 1.0, 24));
  Mesh2Options o;
  o.corner_angle_deg = 20;
  const Mesh2 passed = mesh_of(d, 400, nullptr, o);
  o.fix_input_vertices = true;
  const Mesh2 fixed = mesh_of(d, 400, nullptr, o);
  std::uint32_t in_passed = 0, in_fixed = 0;
  for (std::uint32_t v = 0; v < d.nb_vertices(); ++v) {
    in_passed += has_vertex_at(passed, d.vertex(v));
    in_fixed += has_vertex_at(fixed, d.vertex(v));
  }
  CHECK(in_fixed == d.nb_vertices());
  CHECK(in_passed < d.nb_vertices());  // the outer ring's 15-degree turns are passed
  CHECK(in_passed >= 24);              // the inner ring's reflex vertices are not
}

TEST_CASE("mesh2d: a user density grades the mesh", "[mesh]") {
  const Domain2 d(rings_of({{0, 0, 1, 0, 1, 1, 0, 1}}));
  Mesh2Options o;
  o.density = voroclip::Density2::function([](double x, double) { return 1 + 10 * x; });
  const Mesh2 m = mesh_of(d, 800, nullptr, o);
  std::uint32_t left = 0, right = 0;
  for (std::uint32_t v = 0; v < m.nb_vertices(); ++v) (m.xy[2 * v] < 0.5 ? left : right) += 1;
  // Point density goes as rho^(1/2): sqrt(8.5 / 3.5) = 1.56 between the halves' centres.
  INFO(left << " left, " << right << " right");
  CHECK(right > 1.3 * left);
  CHECK(voroclip::triangle_quality2(m).min_angle >= 25);
}

TEST_CASE("mesh2d: a user density is asked only inside the domain", "[mesh][regression]") {
  // A sizing defined only on the domain: h = 0.02 + 0.05 sqrt(x - y) on the triangle
  // y <= x, with a hole. Before, mesh2d asked it in the bounding box (sampling), at
  // circumcentres outside the domain (gap filling) and the CVT's integration asked it
  // across holes; each gave NaN there ("--sizing ... is -nan at (0.0125, 0.0375)").
  const Domain2 d(rings_of({{0, 0, 1, 0, 1, 1}, {0.6, 0.2, 0.8, 0.2, 0.8, 0.4}}));
  std::atomic<std::uint64_t> outside{0}, asked{0};
  Mesh2Options o;
  o.density = voroclip::Density2::function([&](double x, double y) {
    const double p[2] = {x, y};
    ++asked;
    if (d.locate(p) == Sign::negative) {
      ++outside;
      return std::nan("");
    }
    const double h = 0.02 + 0.05 * std::sqrt(x - y);
    return 1 / (h * h * h * h);
  });
  Mesh2Stats st;
  const Mesh2 m = mesh_of(d, 600, &st, o);
  CHECK(asked > 0);
  CHECK(outside == 0);
  CHECK(std::fabs(st.covered_fraction - 1) <= 1e-12);
  // Graded: vertices per area about (h_far / h_near)^2 = (0.067 / 0.038)^2 = 3.1 times
  // denser in the band x - y < 0.25 (area 0.21875) than in x - y > 0.75 (area 0.03125).
  std::uint32_t near = 0, far = 0;
  for (std::uint32_t v = 0; v < m.nb_vertices(); ++v) {
    const double t = m.xy[2 * v] - m.xy[2 * v + 1];
    near += t < 0.25;
    far += t > 0.75;
  }
  INFO(near << " vertices with x - y < 0.25, " << far << " with x - y > 0.75");
  CHECK(near / 0.21875 > 2 * far / 0.03125);
}

TEST_CASE("mesh2d: identical with 1 and 2 threads", "[mesh][threads]") {
  const Domain2 d(voroclip::read_polygon(kData + "/polygons/valid/issue29.json"));
  Mesh2Options o;
  o.nb_vertices = 500;
  o.seed = 3;
  INFO("seed " << o.seed);
  Mesh2 one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = voroclip::mesh_domain2(d, o);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism,
                          voroclip_test::test_threads());
    two = voroclip::mesh_domain2(d, o);
  }
  REQUIRE(one.nb_triangles() > 0);
  REQUIRE(one.xy == two.xy);
  REQUIRE(one.triangles == two.triangles);
  REQUIRE(one.vertex_site == two.vertex_site);
}

TEST_CASE("mesh2d: identical with 1 and N threads through the coloured smoothing",
          "[mesh][threads]") {
  // Steps 9 and 10 move the vertices of one colour in parallel (blocks of 64): at 2000
  // vertices a colour holds a few hundred, split over the threads.
  const Domain2 d(voroclip::read_polygon(kData + "/polygons/valid/earcut.json"));
  Mesh2Options o;
  o.nb_vertices = 2000;
  o.raise_for_mean_angle = false;
  Mesh2 one, two;
  Mesh2Stats st_one, st_two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = voroclip::mesh_domain2(d, o, &st_one);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism,
                          voroclip_test::test_threads());
    two = voroclip::mesh_domain2(d, o, &st_two);
  }
  REQUIRE(one.nb_triangles() > 0);
  CHECK(st_one.check.empty());
  CHECK(st_one.smoothed > 0);
  CHECK(st_one.smoothed == st_two.smoothed);
  CHECK(st_one.flips == st_two.flips);
  REQUIRE(one.xy == two.xy);
  REQUIRE(one.triangles == two.triangles);
}

TEST_CASE("mesh2d: steps 8-10 report their rounds; a cancel there keeps a valid mesh", "[mesh]") {
  // At 128,000 vertices these steps took 157 s of 242 with no progress shown.
  using voroclip::Mesh2Phase;
  const Domain2 d(voroclip::square_with_holes(2, 0.4));
  Mesh2Options o;
  o.nb_vertices = 400;
  o.raise_for_mean_angle = false;
  std::vector<voroclip::Mesh2Progress> seen;
  o.progress = [&](const voroclip::Mesh2Progress& p) {
    seen.push_back(p);
    return true;
  };
  Mesh2Stats st;
  const Mesh2 m = voroclip::mesh_domain2(d, o, &st);
  REQUIRE(st.check.empty());
  // Each phase's rounds from 0 up by one, the phases in the pipeline's order.
  const auto rounds = [&](Mesh2Phase phase) {
    std::vector<std::uint32_t> r;
    for (const auto& p : seen) {
      if (p.phase == phase) r.push_back(p.iteration);
    }
    return r;
  };
  for (const Mesh2Phase phase :
       {Mesh2Phase::kRefinement, Mesh2Phase::kSmoothing, Mesh2Phase::kFlips}) {
    INFO(voroclip::phase_name(phase));
    const std::vector<std::uint32_t> r = rounds(phase);
    REQUIRE(!r.empty());
    for (std::size_t k = 0; k < r.size(); ++k) CHECK(r[k] == k);
  }
  CHECK(rounds(Mesh2Phase::kSmoothing).size() <= o.smooth_passes);
  CHECK(rounds(Mesh2Phase::kFlips).size() <= o.flip_rounds);
  CHECK(std::string(voroclip::phase_name(Mesh2Phase::kSmoothing)) == "smoothing");
  std::vector<Mesh2Phase> order;
  for (const auto& p : seen) {
    if (order.empty() || order.back() != p.phase) order.push_back(p.phase);
  }
  const std::vector<Mesh2Phase> tail(order.end() - 3, order.end());
  CHECK(tail == std::vector<Mesh2Phase>{Mesh2Phase::kRefinement, Mesh2Phase::kSmoothing,
                                        Mesh2Phase::kFlips});

  SECTION("a cancel at the second smoothing pass: no flips, a valid conforming mesh") {
    o.progress = [](const voroclip::Mesh2Progress& p) {
      return !(p.phase == Mesh2Phase::kSmoothing && p.iteration == 1);
    };
    Mesh2Stats cut;
    const Mesh2 c = voroclip::mesh_domain2(d, o, &cut);
    CHECK(cut.cancelled);
    CHECK(cut.flips == 0);
    CHECK(cut.smoothed > 0);
    CHECK(cut.smoothed < st.smoothed);
    REQUIRE(c.nb_triangles() > 0);
    CHECK(cut.check.empty());
    CHECK(voroclip::check_mesh2(d, c).empty());
  }
}

TEST_CASE("mesh2d: bad options throw voroclip::Error; cancellation", "[mesh]") {
  const Domain2 d(voroclip::square_with_holes(1, 0.5));
  Mesh2Options o;
  CHECK_THROWS_AS(voroclip::mesh_domain2(d, o), voroclip::Error);  // no size
  o.nb_vertices = 100;
  o.gradation = 0;
  CHECK_THROWS_AS(voroclip::mesh_domain2(d, o), voroclip::Error);
  o.gradation = 0.3;
  o.sharp_angle_deg = 200;
  CHECK_THROWS_AS(voroclip::mesh_domain2(d, o), voroclip::Error);
  o.sharp_angle_deg = 30;
  o.density = voroclip::Density2::function([](double x, double) { return x - 0.5; });
  CHECK_THROWS_WITH(voroclip::mesh_domain2(d, o), Catch::Contains("density"));
  o.density = voroclip::Density2::constant(1);
  CHECK_THROWS_AS(voroclip::mesh_domain2(Domain2(), o), voroclip::Error);

  SECTION("stopped at once: an empty mesh") {
    o.progress = [](const voroclip::Mesh2Progress&) { return false; };
    Mesh2Stats st;
    const Mesh2 m = voroclip::mesh_domain2(d, o, &st);
    CHECK(st.cancelled);
    CHECK(m.nb_triangles() == 0);
  }
  SECTION("stopped in the unconstrained CVT: a valid mesh of the sites reached") {
    std::vector<voroclip::Mesh2Phase> phases;
    o.progress = [&](const voroclip::Mesh2Progress& p) {
      phases.push_back(p.phase);
      return !(p.phase == voroclip::Mesh2Phase::kUnconstrained && p.iteration == 3);
    };
    Mesh2Stats st;
    const Mesh2 m = voroclip::mesh_domain2(d, o, &st);
    CHECK(st.cancelled);
    CHECK(st.unconstrained_iterations == 3);
    CHECK(st.constrained_iterations == 0);
    CHECK(m.nb_triangles() > 0);
    CHECK(voroclip::check_mesh2(d, m).empty());
    CHECK(phases.front() == voroclip::Mesh2Phase::kSampling);
    CHECK(std::count(phases.begin(), phases.end(), voroclip::Mesh2Phase::kConstrained) == 0);
  }
}

// Issue 31's quality target on a mesh: min angle >= 30 degrees but at input corners
// sharper than 60 degrees (there >= min(30, the corner's angle)), mean per-triangle min
// angle >= 53; coverage exactly 1 (mesh_of checks it); the vertex count within 10 % of the
// request or a note saying why.
void check_issue31_target(const Domain2& d, std::uint32_t n) {
  Mesh2Stats st;
  const Mesh2 m = mesh_of(d, n, &st);
  const voroclip::TriangleQuality2 q = voroclip::triangle_quality2(m);
  const AngleBound b = angle_bound(d, m);
  INFO(d.source() << " at " << n << " vertices asked: " << voroclip::quality_text(q) << b.below_30
                  << " triangles below 30 degrees, " << b.at_sharp_corner << " at sharp corners, "
                  << b.missed << " below their bound (worst " << b.worst << "); "
                  << st.vertex_count_note);
  CHECK(b.missed == 0);
  CHECK(q.mean_min_angle >= 53);
  CHECK(st.mean_angle_note.empty());
  CHECK(std::fabs(st.covered_fraction - 1) <= 1e-12);
  const bool within = std::fabs(double(m.nb_vertices()) - n) <= 0.1 * n;
  CHECK(within == st.vertex_count_note.empty());
}

TEST_CASE("mesh2d: issue 31's target on three polygons at 1000 vertices", "[mesh]") {
  // building: corners of 90 degrees and reflex ones; dude: curves; issue34: a 24.4-degree
  // corner, cut, whose tip triangle is the only one below 30 degrees.
  for (const char* name : {"building", "dude", "issue34"}) {
    check_issue31_target(
        Domain2(voroclip::read_polygon(kData + "/polygons/valid/" + name + ".json")), 1000);
  }
  const Domain2 d(voroclip::read_polygon(kData + "/polygons/valid/issue34.json"));
  const AngleBound b = angle_bound(d, mesh_of(d, 1000));
  CHECK(b.at_sharp_corner == b.below_30);
  CHECK(b.below_30 >= 1);
}

TEST_CASE("mesh2d: a triangle whose own vertex encroaches its boundary edge is refined",
          "[mesh][regression]") {
  // issue35.json at 5000 vertices kept a 20.4-degree triangle (23.5 after smoothing)
  // against a boundary edge next to a 243-degree reflex vertex: its circumcenter was
  // outside the domain but in no boundary edge's diametral circle, so the refinement
  // neither inserted it nor split an edge, 30 rounds running. Only the tips of the three
  // cut corners (20.2, 24.2 and 29.3 degrees) may stay below 30.
  const Domain2 d(voroclip::read_polygon(kData + "/polygons/valid/issue35.json"));
  const Mesh2 m = mesh_of(d, 5000);
  const AngleBound b = angle_bound(d, m);
  INFO(b.below_30 << " triangles below 30 degrees, worst missing its bound " << b.worst);
  CHECK(b.missed == 0);
  CHECK(b.below_30 == b.at_sharp_corner);
  CHECK(b.below_30 == 3);
}

TEST_CASE("mesh2d: a unit square with a hole of side 1e-6 is meshed", "[mesh][regression]") {
  // The hole sits on a node of the sizing table, which is 1e-6 there and about 2e-4 at the
  // other nodes around it: the sampler's envelope for that coarse cell (its smallest size
  // over all of it) accepted about one proposal in 10^5 and took nearly all of them, and
  // the initial sampling gave up ("cannot sample points inside the domain").
  const double lo = 0.5 - 0.5e-6, hi = 0.5 + 0.5e-6;
  const Domain2 d(rings_of({{0, 0, 1, 0, 1, 1, 0, 1}, {lo, lo, hi, lo, hi, hi, lo, hi}}));
  Mesh2Options o;
  o.raise_for_mean_angle = false;
  o.seed = 1;
  Mesh2Stats st;
  const Mesh2 m = mesh_of(d, 300, &st, o);
  check_fixed_vertices(d, m, 0);
  check_boundary_vertices(d, m, true);
  // The hole is a boundary loop of the mesh: its edges (tag 2) join the hole's 4 corners
  // and points on its sides, each vertex entered once and left once, one cycle.
  REQUIRE(m.boundary_edges.size() == 2 * m.boundary_tags.size());
  std::vector<std::uint32_t> next(m.nb_vertices(), Mesh2::kNone);
  std::uint32_t nb_hole = 0, start = Mesh2::kNone;
  for (std::size_t e = 0; e < m.boundary_tags.size(); ++e) {
    if (m.boundary_tags[e] != 2) continue;
    const std::uint32_t a = m.boundary_edges[2 * e], b = m.boundary_edges[2 * e + 1];
    REQUIRE(d.locate(&m.xy[2 * a]) == Sign::zero);
    REQUIRE(lo <= m.xy[2 * a]);
    REQUIRE(m.xy[2 * a] <= hi);
    REQUIRE(lo <= m.xy[2 * a + 1]);
    REQUIRE(m.xy[2 * a + 1] <= hi);
    REQUIRE(next[a] == Mesh2::kNone);
    next[a] = b;
    start = a;
    ++nb_hole;
  }
  REQUIRE(nb_hole >= 4);
  std::uint32_t steps = 0, corners = 0;
  std::uint32_t v = start;
  do {
    REQUIRE(next[v] != Mesh2::kNone);
    corners += m.vertex_domain[v] != Mesh2::kNone;
    v = next[v];
    ++steps;
  } while (v != start && steps <= nb_hole);
  CHECK(v == start);
  CHECK(steps == nb_hole);
  CHECK(corners == 4);
  // The triangles at the hole are as small as the hole: sites were sampled near it.
  double shortest = 1;
  for (std::uint32_t t = 0; t < m.nb_triangles(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const double* p = &m.xy[2 * m.triangles[3 * t + k]];
      const double* q = &m.xy[2 * m.triangles[3 * t + (k + 1) % 3]];
      shortest = std::min(shortest, std::hypot(q[0] - p[0], q[1] - p[1]));
    }
  }
  CHECK(shortest <= 1e-6);
  const voroclip::TriangleQuality2 q = voroclip::triangle_quality2(m);
  INFO(voroclip::quality_text(q));
  CHECK(q.min_angle >= 30);
  // The same bits with 1 and N threads (the envelope's squares are built in parallel).
  Mesh2 one;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    o.nb_vertices = 300;
    one = voroclip::mesh_domain2(d, o);
  }
  CHECK(one.xy == m.xy);
  CHECK(one.triangles == m.triangles);
}

TEST_CASE("mesh2d: every valid polygon and a 10^4-vertex annulus meet the target",
          "[mesh][.slow]") {
  // N per input as in bench/RESULTS.md, but where the mean of 53 degrees needs more: hilbert
  // (corridors a few triangles wide: 51.5 at 3000 vertices, 50.4 at 5000, 53.0 at 6000),
  // issue35 (graded to its small features: 51.5 at 3000, 51.6 at 5000, 53.8 at 7000) and
  // eberly-6 (its features ask for about 6,661: 51.6 at 3000, 53.2 at 10^4), with step 10;
  // bench/compare/RESULTS_mesh2.md has the earlier sweep.
  struct Case {
    const char* name;
    std::uint32_t n;
  };
  for (const Case& c :
       {Case{"building", 5000}, Case{"dude", 5000}, Case{"earcut", 3000}, Case{"eberly-6", 10000},
        Case{"hilbert", 8000}, Case{"issue29", 5000}, Case{"issue34", 5000}, Case{"issue35", 7000},
        Case{"issue52", 5000}, Case{"annulus", 10000}}) {
    const std::string name = c.name;
    const Domain2 d(name == "annulus"
                        ? voroclip::annulus_rings(0.5, 1.0, 256)
                        : voroclip::read_polygon(kData + "/polygons/valid/" + name + ".json"));
    check_issue31_target(d, c.n);
  }
}

TEST_CASE("mesh2d: features that need more vertices than asked are counted", "[mesh]") {
  // 36 holes 0.7 of their cell wide: corridors of width 0.05 between them. The feature
  // sizes alone ask for several times the 60 vertices asked, and the mesh has more.
  // (With the count kept: the mean smallest angle, 48.7 degrees, would raise it.)
  const Domain2 d(voroclip::square_with_holes(6, 0.7));
  Mesh2Stats st;
  Mesh2Options exact;
  exact.raise_for_mean_angle = false;
  const Mesh2 m = mesh_of(d, 60, &st, exact);
  INFO(m.nb_vertices() << " vertices, the features ask for " << st.feature_vertices);
  CHECK(st.feature_vertices > 1.1 * 60);
  CHECK(m.nb_vertices() > 1.1 * 60);
  // The estimate (equilateral triangles of the feature size) is a floor here: corridors
  // one or two triangles wide take more (544 vertices for 347 estimated).
  CHECK(m.nb_vertices() >= st.feature_vertices);
  // The note says so, with the counts.
  INFO(st.vertex_count_note);
  CHECK(st.vertex_count_note.find(std::to_string(m.nb_vertices()) + " vertices for 60 asked") == 0);
  CHECK(st.vertex_count_note.find("the small features force more") != std::string::npos);
  CHECK(st.vertex_count_note.find("about " + std::to_string(st.feature_vertices) + " vertices") !=
        std::string::npos);
  // No sampling lowers the count to the request: the first run is kept, not redone.
  CHECK(st.vertex_count_runs == 0);
  const voroclip::TriangleQuality2 q = voroclip::triangle_quality2(m);
  INFO(voroclip::quality_text(q));
  CHECK(q.min_angle >= 30);
}

TEST_CASE("mesh2d: a domain whose features ask for fewer lands within 10% of the count", "[mesh]") {
  const Domain2 d(voroclip::square_with_holes(2, 0.4));
  Mesh2Stats st;
  const Mesh2 m = mesh_of(d, 600, &st);
  INFO(m.nb_vertices() << " vertices, the features ask for " << st.feature_vertices);
  CHECK(st.feature_vertices < 600);
  CHECK(std::fabs(double(m.nb_vertices()) - 600) <= 60);
  CHECK(st.vertex_count_note.empty());
}

TEST_CASE("mesh2d: smoothing raises the mean smallest angle, keeps the smallest and the boundary",
          "[mesh]") {
  const Domain2 d(voroclip::square_with_holes(2, 0.4));
  Mesh2Options o;
  o.raise_for_mean_angle = false;  // the same sites either way
  o.smooth_passes = 0;
  Mesh2Stats st0, st1;
  const Mesh2 m0 = mesh_of(d, 400, &st0, o);
  o.smooth_passes = 10;
  const Mesh2 m1 = mesh_of(d, 400, &st1, o);
  const voroclip::TriangleQuality2 q0 = voroclip::triangle_quality2(m0);
  const voroclip::TriangleQuality2 q1 = voroclip::triangle_quality2(m1);
  INFO("without: " << voroclip::quality_text(q0) << "with: " << voroclip::quality_text(q1));
  CHECK(st0.smoothed == 0);
  CHECK(st1.smoothed > 0);
  CHECK(q1.min_angle >= q0.min_angle);
  CHECK(q1.mean_min_angle > q0.mean_min_angle);
  // Same vertices but the free ones moved and the sliding ones slid: the fixed vertices
  // are where they were, the sliding ones on their domain edge (exactly: the square's
  // edges are axis-parallel), strictly between its ends.
  REQUIRE(m0.nb_vertices() == m1.nb_vertices());
  std::uint32_t moved = 0, slid = 0;
  for (std::uint32_t v = 0; v < m0.nb_vertices(); ++v) {
    const bool same = m0.xy[2 * v] == m1.xy[2 * v] && m0.xy[2 * v + 1] == m1.xy[2 * v + 1];
    REQUIRE(m0.vertex_kind[v] == m1.vertex_kind[v]);
    if (m0.vertex_kind[v] == Mesh2::VertexKind::kFixed) CHECK(same);
    if (m1.vertex_kind[v] == Mesh2::VertexKind::kBoundary) {
      REQUIRE(m1.vertex_edge[v] == m0.vertex_edge[v]);
      const double* a = d.vertex(m1.vertex_edge[v]);
      const double* b = d.vertex(d.next(m1.vertex_edge[v]));
      const double* x = &m1.xy[2 * v];
      CHECK(voroclip::orient2d(a, b, x) == Sign::zero);
      CHECK(std::min(a[0], b[0]) <= x[0]);
      CHECK(x[0] <= std::max(a[0], b[0]));
      CHECK(std::min(a[1], b[1]) <= x[1]);
      CHECK(x[1] <= std::max(a[1], b[1]));
      CHECK(!((x[0] == a[0] && x[1] == a[1]) || (x[0] == b[0] && x[1] == b[1])));
      slid += !same;
    }
    moved += !same;
  }
  CHECK(moved > slid);
  CHECK(slid > 0);
  // Without the sliding, the sliding vertices stay where the CVT put them.
  o.smooth_boundary = false;
  const Mesh2 m2 = mesh_of(d, 400, nullptr, o);
  REQUIRE(m2.nb_vertices() == m0.nb_vertices());
  for (std::uint32_t v = 0; v < m0.nb_vertices(); ++v) {
    if (m0.vertex_kind[v] != Mesh2::VertexKind::kInterior) {
      CHECK((m0.xy[2 * v] == m2.xy[2 * v] && m0.xy[2 * v + 1] == m2.xy[2 * v + 1]));
    }
  }
}

TEST_CASE("mesh2d: step 10's flips and search raise the mean smallest angle, keep the rest",
          "[mesh]") {
  // Same sites either way (step 10 comes last): the vertex count, the fixed vertices and
  // the sliding vertices' edges are the same; the smallest angle stays at or above
  // min(itself, 40 degrees), the mesh stays valid and conforming (mesh_of).
  const Domain2 d(voroclip::square_with_holes(2, 0.4));
  Mesh2Options o;
  o.raise_for_mean_angle = false;  // the same sites either way
  o.flip_rounds = 0;
  Mesh2Stats st0, st1;
  const Mesh2 m0 = mesh_of(d, 400, &st0, o);
  o.flip_rounds = 10;
  const Mesh2 m1 = mesh_of(d, 400, &st1, o);
  const voroclip::TriangleQuality2 q0 = voroclip::triangle_quality2(m0);
  const voroclip::TriangleQuality2 q1 = voroclip::triangle_quality2(m1);
  INFO("without: " << voroclip::quality_text(q0) << "with: " << voroclip::quality_text(q1));
  CHECK(st0.flips == 0);
  CHECK(st1.smoothed > st0.smoothed);
  CHECK(q1.mean_min_angle > q0.mean_min_angle);
  CHECK(q1.min_angle >= std::min(q0.min_angle, 40.0));
  REQUIRE(m0.nb_vertices() == m1.nb_vertices());
  REQUIRE(m0.nb_triangles() == m1.nb_triangles());
  for (std::uint32_t v = 0; v < m0.nb_vertices(); ++v) {
    REQUIRE(m0.vertex_kind[v] == m1.vertex_kind[v]);
    if (m0.vertex_kind[v] == Mesh2::VertexKind::kFixed) {
      CHECK((m0.xy[2 * v] == m1.xy[2 * v] && m0.xy[2 * v + 1] == m1.xy[2 * v + 1]));
    }
    if (m1.vertex_kind[v] == Mesh2::VertexKind::kBoundary) {
      REQUIRE(m1.vertex_edge[v] == m0.vertex_edge[v]);
      const double* a = d.vertex(m1.vertex_edge[v]);
      const double* b = d.vertex(d.next(m1.vertex_edge[v]));
      CHECK(voroclip::orient2d(a, b, &m1.xy[2 * v]) == Sign::zero);
    }
  }
  // The areas add up to the domain's (no triangle flipped over).
  CHECK(std::fabs(st1.covered_fraction - 1) <= 1e-12);
}

TEST_CASE("mesh2d: issue 31's polygons below the mean target at 1000 vertices kept", "[mesh]") {
  // With the count kept (raise_for_mean_angle = false):
  // earcut: its features force 2,258 vertices, graded; step 10 lifts the mean smallest
  // angle from 51.24 to 51.78 degrees (the smallest from 32.8 to 36.4) and the note says
  // why it stays below 53. hilbert: corridors one triangle wide, every vertex on the
  // boundary (45.4 degrees, right triangles between facing corners): the note says so.
  const std::string dir = kData + "/polygons/valid/";
  Mesh2Options exact;
  exact.raise_for_mean_angle = false;
  {
    const Domain2 d(voroclip::read_polygon(dir + "earcut.json"));
    Mesh2Options o = exact;
    o.flip_rounds = 0;
    Mesh2Stats st0, st1;
    const voroclip::TriangleQuality2 q0 = voroclip::triangle_quality2(mesh_of(d, 1000, &st0, o));
    const Mesh2 m = mesh_of(d, 1000, &st1, exact);
    const voroclip::TriangleQuality2 q1 = voroclip::triangle_quality2(m);
    INFO("without: " << voroclip::quality_text(q0) << "with: " << voroclip::quality_text(q1)
                     << st1.mean_angle_note);
    CHECK(q1.mean_min_angle >= q0.mean_min_angle + 0.4);
    CHECK(q1.min_angle >= std::min(q0.min_angle, 40.0));
    CHECK(angle_bound(d, m).missed == 0);
    CHECK(q1.mean_min_angle < 53);
    CHECK(st1.mean_angle_note.find("mean smallest angle") == 0);
    CHECK(st1.mean_angle_note.find("graded to the small features") != std::string::npos);
  }
  {
    const Domain2 d(voroclip::read_polygon(dir + "hilbert.json"));
    Mesh2Stats st;
    const Mesh2 m = mesh_of(d, 1000, &st, exact);
    INFO(st.mean_angle_note);
    CHECK(st.mean_angle_runs == 0);
    CHECK(st.mean_angle_raise.empty());
    for (const Mesh2::VertexKind k : m.vertex_kind) CHECK(k != Mesh2::VertexKind::kInterior);
    // Every triangle has a vertex on the boundary: 1047 of mean 45.4 degrees on the Zen 5
    // host, 1048 of mean 45.5 on the Xeon one (the meshes differ in their last bits).
    const double mean = voroclip::triangle_quality2(m).mean_min_angle;
    std::ostringstream expected;
    expected << m.nb_triangles() << " triangles with a vertex on the boundary (mean " << std::fixed
             << std::setprecision(1) << mean << "), 0 inside; corridors a few triangles wide";
    CHECK(mean < 46);
    CHECK(st.mean_angle_note.find(expected.str()) != std::string::npos);
    // The estimate written out: 1049 vertices at edge length 1.029 for a feature of 1 (1.027
    // and 6900 before the 2D CVT's energy was scaled, 1ddda63).
    CHECK(st.mean_angle_note.find("about 7000 vertices (estimate)") != std::string::npos);
  }
}

TEST_CASE("mesh2d: a mean smallest angle below 53 degrees is raised with more vertices", "[mesh]") {
  // Corridors (36 holes 0.7 of their cell wide, 60 vertices asked): 48.7 degrees with the
  // count the features force. The mesh is made again with the corridors' estimate (capped
  // at 8 times the count), and what is kept is exactly the mesh of that count asked with
  // the count kept.
  const Domain2 d(voroclip::square_with_holes(6, 0.7));
  Mesh2Options o;
  std::vector<std::uint32_t> retries;
  o.progress = [&](const voroclip::Mesh2Progress& p) {
    if (p.retry_vertices > 0) retries.push_back(p.retry_vertices);
    return true;
  };
  Mesh2Stats st;
  const Mesh2 m = mesh_of(d, 60, &st, o);
  const voroclip::TriangleQuality2 q = voroclip::triangle_quality2(m);
  INFO(voroclip::quality_text(q) << st.vertex_count_note);
  CHECK(q.mean_min_angle >= 53);
  CHECK(st.mean_angle_note.empty());
  REQUIRE(retries.size() == 1);
  CHECK(st.mean_angle_runs == 1);
  CHECK(st.requested_vertices == 60);
  CHECK(st.mean_angle_raise.find("the mean smallest angle was ") == 0);
  CHECK(st.mean_angle_raise.find("corridors a few triangles wide") != std::string::npos);
  CHECK(st.mean_angle_raise.find("meshed again with " + std::to_string(m.nb_vertices()) +
                                 " vertices (mean ") != std::string::npos);
  CHECK(st.vertex_count_note.find(std::to_string(m.nb_vertices()) + " vertices for 60 asked") == 0);
  Mesh2Options exact;
  exact.raise_for_mean_angle = false;
  Mesh2Stats first;
  const Mesh2 m0 = mesh_of(d, 60, &first, exact);
  CHECK(retries[0] <= 8 * m0.nb_vertices());
  CHECK(retries[0] >= 1.2 * m0.nb_vertices());
  CHECK(voroclip::triangle_quality2(m0).mean_min_angle < 53);
  const Mesh2 again = mesh_of(d, retries[0], nullptr, exact);
  CHECK(again.xy == m.xy);
  CHECK(again.triangles == m.triangles);

  // Graded (earcut.json, 1000 asked, 2,269 forced by its features, 51.8 degrees): the
  // count model's next count reaches 53.
  const Domain2 e(voroclip::read_polygon(kData + "/polygons/valid/earcut.json"));
  Mesh2Stats se;
  const Mesh2 me = mesh_of(e, 1000, &se);
  const voroclip::TriangleQuality2 qe = voroclip::triangle_quality2(me);
  INFO(voroclip::quality_text(qe) << se.mean_angle_raise);
  CHECK(qe.mean_min_angle >= 53);
  CHECK(se.mean_angle_runs >= 1);
  CHECK(se.mean_angle_raise.find("graded to the small features") != std::string::npos);
  CHECK(angle_bound(e, me).missed == 0);
}

TEST_CASE("mesh2d: a strip of width 1e-6 is a clear, fast error, diagonal or not",
          "[mesh][regression]") {
  // The axis-aligned strip ran for minutes: its sizes (from feature samples 1/256 apart)
  // were about 6e-4, and the refinement split the boundary towards the width, every round
  // looping over every boundary edge per bad triangle. The diagonal one said "the domain
  // has no interior": no point of the size model's 1024 x 1024 grid fell inside it. Both
  // need about (boundary length) / (width) boundary vertices: far more than asked.
  const double w = 1e-6;
  for (const bool diagonal : {false, true}) {
    const double rise = diagonal ? 1 : 0;
    const Domain2 d(rings_of({{0, 0, 1, rise, 1, rise + w, 0, w}}));
    REQUIRE(d.area() > 0);
    Mesh2Options o;
    o.nb_vertices = 300;
    std::string message;
    try {
      voroclip::mesh_domain2(d, o);
    } catch (const voroclip::Error& e) {
      message = e.what();
    }
    INFO(message);
    REQUIRE(message.find("too thin") != std::string::npos);
    CHECK(message.find("no interior") == std::string::npos);
    // The count asked for: the boundary length over the width across the strip.
    const std::size_t at = message.find("about ");
    REQUIRE(at != std::string::npos);
    const double need = std::stod(message.substr(at + 6));
    const double length = 2 * std::hypot(1.0, rise), across = w / std::hypot(1.0, rise);
    CHECK(need > 0.95 * length / across);
    CHECK(need <= length / across);
  }
}

namespace {

// Squares [x, x + s] x [y, y + s], one outer ring each (roles by nesting), the k-th with
// the regional attribute attributes[k] at its centre when given.
PolygonRings far_squares(const std::vector<std::vector<double>>& squares,
                         const std::vector<double>& attributes = {}) {
  PolygonRings p;
  p.source = "test";
  p.ring_begin.push_back(0);
  for (std::size_t k = 0; k < squares.size(); ++k) {
    const double x = squares[k][0], y = squares[k][1], s = squares[k][2];
    p.xy.insert(p.xy.end(), {x, y, x + s, y, x + s, y + s, x, y + s});
    p.ring_begin.push_back(static_cast<std::uint32_t>(p.xy.size() / 2));
    p.ring_polygon.push_back(-1);
    p.ring_line.push_back(0);
    if (k < attributes.size()) {
      p.region_points.insert(p.region_points.end(), {x + 0.5 * s, y + 0.5 * s});
      p.region_attributes.push_back(attributes[k]);
    }
  }
  return p;
}

// Per square of `squares` (as far_squares): the mesh vertices in its closed box, the
// triangles with their three vertices there and their regions, the sum of their areas
// (long double); every vertex and every triangle must be in one square.
struct SquareShare {
  std::uint32_t vertices = 0, triangles = 0;
  std::vector<std::int32_t> regions;
  long double area = 0;
};
std::vector<SquareShare> square_shares(const Mesh2& m,
                                       const std::vector<std::vector<double>>& squares) {
  const Domain2 d(far_squares(squares));
  std::vector<SquareShare> out(squares.size());
  const auto square_of = [&](std::uint32_t v) {
    const double* p = &m.xy[2 * std::size_t{v}];
    for (std::uint32_t r = 0; r < d.nb_rings(); ++r) {
      const double* lo = d.vertex(d.ring_begin(r));
      const double* hi = d.vertex(d.ring_begin(r) + 2);
      if (lo[0] <= p[0] && p[0] <= hi[0] && lo[1] <= p[1] && p[1] <= hi[1]) return r;
    }
    return Mesh2::kNone;
  };
  for (std::uint32_t v = 0; v < m.nb_vertices(); ++v) {
    const std::uint32_t r = square_of(v);
    INFO("vertex " << v << " at (" << m.xy[2 * v] << ", " << m.xy[2 * v + 1] << ")");
    REQUIRE(r != Mesh2::kNone);
    ++out[r].vertices;
  }
  for (std::uint32_t t = 0; t < m.nb_triangles(); ++t) {
    const std::uint32_t* v = &m.triangles[3 * std::size_t{t}];
    const std::uint32_t r = square_of(v[0]);
    REQUIRE(square_of(v[1]) == r);
    REQUIRE(square_of(v[2]) == r);
    ++out[r].triangles;
    out[r].regions.push_back(m.triangle_regions[t]);
    const double* a = &m.xy[2 * std::size_t{v[0]}];
    const double* b = &m.xy[2 * std::size_t{v[1]}];
    const double* c = &m.xy[2 * std::size_t{v[2]}];
    out[r].area +=
        0.5L * ((static_cast<long double>(b[0]) - a[0]) * (static_cast<long double>(c[1]) - a[1]) -
                (static_cast<long double>(b[1]) - a[1]) * (static_cast<long double>(c[0]) - a[0]));
  }
  return out;
}

}  // namespace

TEST_CASE("mesh2d: two squares of side 1e-4 far apart are both meshed, each with its region",
          "[mesh][regression]") {
  // They cover 2e-8 of their bounding box. The count estimate drew its points from a grid
  // of at most 2^20 cells over the box, and none fell inside: "the domain has no interior"
  // (or, for a seed that put one there, the sampler proposed points over the whole box and
  // gave up after 20-50 s: "cannot sample points inside the domain", with 1.7 GB of
  // sizing-table nodes that were all the cap).
  const std::vector<std::vector<double>> squares = {{0, 0, 1e-4}, {1, 1, 1e-4}};
  const Domain2 d(far_squares(squares, {5, 7}));
  for (const std::uint64_t seed : {1, 12}) {
    Mesh2Options o;
    o.seed = seed;
    o.raise_for_mean_angle = false;
    Mesh2Stats st;
    const Mesh2 m = mesh_of(d, 300, &st, o);
    INFO("seed " << seed << ", " << m.nb_vertices() << " vertices");
    check_fixed_vertices(d, m, 0);
    check_boundary_vertices(d, m, true);
    const std::vector<SquareShare> share = square_shares(m, squares);
    for (std::size_t k = 0; k < squares.size(); ++k) {
      const Domain2 alone(far_squares({squares[k]}));
      INFO("square " << k << ": " << share[k].vertices << " vertices, " << share[k].triangles
                     << " triangles");
      // The same density in both (no feature smaller than the squares): a fair share each.
      CHECK(3 * share[k].vertices > m.nb_vertices());
      // Each square is covered exactly (to rounding), and its triangles carry its region.
      CHECK(std::fabs(share[k].area - alone.area()) <= 1e-12L * alone.area());
      const std::int32_t region = k == 0 ? 5 : 7;
      CHECK(std::count(share[k].regions.begin(), share[k].regions.end(), region) ==
            static_cast<std::ptrdiff_t>(share[k].triangles));
    }
    CHECK(voroclip::triangle_quality2(m).min_angle >= 30);
  }
}

TEST_CASE("mesh2d: three squares of side 1e-8 far apart, and a user density over two",
          "[mesh][regression]") {
  // Side 1e-8 at distance 1: 3e-16 of the box. The sizing table's cells (at least 1/2000
  // of the box) are 50,000 times wider than a square; the sampler's proposals are cut to
  // the squares by a quadtree, and the 4 million table cells whose nodes would all be the
  // cap store none (they would be 37.7 billion nodes).
  const std::vector<std::vector<double>> squares = {{0, 0, 1e-8}, {0, 1, 1e-8}, {1, 1, 1e-8}};
  const Domain2 d(far_squares(squares));
  Mesh2Options o;
  o.raise_for_mean_angle = false;
  const Mesh2 m = mesh_of(d, 300, nullptr, o);
  const std::vector<SquareShare> share = square_shares(m, squares);
  for (std::size_t k = 0; k < squares.size(); ++k) {
    const Domain2 alone(far_squares({squares[k]}));
    INFO("square " << k << ": " << share[k].vertices << " vertices");
    CHECK(4 * share[k].vertices > m.nb_vertices());
    CHECK(std::fabs(share[k].area - alone.area()) <= 1e-12L * alone.area());
  }
  // A density 10^4 times higher at x = 1 than at x = 0 (h 10 times smaller) puts most
  // vertices in the square there: the density is asked and honoured inside each square.
  const std::vector<std::vector<double>> two = {{0, 0, 1e-4}, {1, 1, 1e-4}};
  const Domain2 d2(far_squares(two));
  o.density = voroclip::Density2::function([](double x, double) { return 1 + 1e4 * x; });
  const Mesh2 g = mesh_of(d2, 300, nullptr, o);
  const std::vector<SquareShare> graded = square_shares(g, two);
  INFO(graded[0].vertices << " and " << graded[1].vertices << " vertices");
  CHECK(graded[1].vertices > 10 * graded[0].vertices);
  CHECK(graded[0].vertices >= 4);
}

TEST_CASE("mesh2d: a small slanted triangle far from the origin passes its area check",
          "[mesh][regression]") {
  // Sliding vertices on a slanted edge are rounded a few ulps into the domain; at (1e6,
  // 1e6) an ulp is 1.2e-10, and a triangle of side 1e-4 lost 2.4e-14 of its 5e-9: the
  // mesh "failed its own check" (relative gap 4.8e-6 against 1e-12), as a defect.
  for (const double at : {1.0, 1e6}) {
    const Domain2 d(rings_of({{at, at, at + 1e-4, at, at + 5e-5, at + 1e-4}}));
    Mesh2Options o;
    o.raise_for_mean_angle = false;
    Mesh2Stats st;
    const Mesh2 m = mesh_of(d, 300, &st, o);
    INFO("at " << at << ": " << m.nb_vertices() << " vertices");
    check_fixed_vertices(d, m, 0);
    check_boundary_vertices(d, m, false);
    // The gap is within the boundary's rounding: 32 ulps of the coordinates times the
    // boundary's length (3.3e-4).
    long double area = 0;
    for (std::uint32_t t = 0; t < m.nb_triangles(); ++t) {
      const double* a = &m.xy[2 * m.triangles[3 * t]];
      const double* b = &m.xy[2 * m.triangles[3 * t + 1]];
      const double* c = &m.xy[2 * m.triangles[3 * t + 2]];
      area += 0.5L *
              ((static_cast<long double>(b[0]) - a[0]) * (static_cast<long double>(c[1]) - a[1]) -
               (static_cast<long double>(b[1]) - a[1]) * (static_cast<long double>(c[0]) - a[0]));
    }
    const double ulp = std::nextafter(at + 1e-4, 2 * at) - (at + 1e-4);
    CHECK(area <= d.area());
    CHECK(d.area() - area <= 32 * ulp * 3.3e-4);
  }
}

namespace {

// The message of mesh_domain2's Error, or "" when it returns (cancelled by `o.progress`
// or not); `st` gets the statistics of a run that returns.
std::string mesh_error(const Domain2& d, const Mesh2Options& o, Mesh2Stats* st = nullptr) {
  try {
    voroclip::mesh_domain2(d, o, st);
  } catch (const voroclip::Error& e) {
    return e.what();
  }
  return "";
}

// Cancels at the first iteration of the unconstrained CVT: the sizing, with its thin-domain
// check, and the sampling are done.
bool until_cvt(const voroclip::Mesh2Progress& p) {
  return p.phase == voroclip::Mesh2Phase::kSampling;
}

}  // namespace

TEST_CASE("mesh2d: the count a too-thin error names passes the check, so does a fine edge length",
          "[mesh][regression]") {
  // A strip of 1 by 1.8e-4 needs about 2 / 1.8e-4 = 11,111 boundary vertices by the check's
  // count, a fraction: the message named it rounded down, which the check refused; and with
  // an edge length the check refused any, 1.2e-4 too (a uniform mesh of that edge has
  // 14,434 vertices).
  const double w = 1.8e-4;
  const Domain2 d(rings_of({{0, 0, 1, 0, 1, w, 0, w}}));
  Mesh2Options o;
  o.nb_vertices = 300;
  const std::string message = mesh_error(d, o);
  INFO(message);
  REQUIRE(message.find("too thin to mesh with 300 vertices") != std::string::npos);
  const std::size_t at = message.find("--vertices ");
  REQUIRE(at != std::string::npos);
  const auto need = static_cast<std::uint32_t>(std::stoul(message.substr(at + 11)));
  CHECK(need > 0.95 * 2 / w);
  CHECK(need <= 2 / w + 1);
  o.progress = until_cvt;
  // One below: still refused, naming the same count.
  o.nb_vertices = need - 1;
  const std::string below = mesh_error(d, o);
  CHECK(below.find("too thin to mesh with " + std::to_string(need - 1) + " vertices") !=
        std::string::npos);
  CHECK(below.find("--vertices " + std::to_string(need) + ",") != std::string::npos);
  o.nb_vertices = need;
  Mesh2Stats st;
  CHECK(mesh_error(d, o, &st).empty());
  CHECK(st.cancelled);
  // An edge length of 2/3 of the width resolves the strip; one of 10 widths does not.
  o.nb_vertices = 0;
  o.edge_length = 1.2e-4;
  CHECK(mesh_error(d, o, &st).empty());
  CHECK(st.cancelled);
  o.edge_length = 1.8e-3;
  CHECK(mesh_error(d, o).find("too thin to mesh at this edge length") != std::string::npos);
}

TEST_CASE("mesh2d: a strip meshed at the count its too-thin error names", "[mesh][.slow]") {
  // The count named was refused again by the second run, which samples fewer sites when
  // the first one makes too many: "too thin to mesh with 14664 vertices", after 60 s.
  const Domain2 d(rings_of({{0, 0, 1, 0, 1, 1e-4, 0, 1e-4}}));
  Mesh2Options o;
  o.nb_vertices = 300;
  const std::string message = mesh_error(d, o);
  const std::size_t at = message.find("--vertices ");
  REQUIRE(at != std::string::npos);
  o.nb_vertices = static_cast<std::uint32_t>(std::stoul(message.substr(at + 11)));
  o.raise_for_mean_angle = false;
  Mesh2Stats st;
  const Mesh2 m = mesh_of(d, o.nb_vertices, &st, o);
  INFO(st.vertex_count_note);
  CHECK(st.vertex_count_runs > 0);
  check_boundary_vertices(d, m, true);
}
