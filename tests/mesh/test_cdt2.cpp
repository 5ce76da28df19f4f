// Tests of the constrained Delaunay triangulation (mesh/src/cdt2.h): after inserting
// segments, the triangulation is valid (counter-clockwise triangles, mutual adjacency,
// area of the convex hull), every segment is a chain of constrained edges, and every
// unconstrained edge is locally Delaunay (exact incircle), which makes the whole
// triangulation constrained Delaunay; segments through vertices are split; crossing
// segments are refused.
#include <catch2/catch.hpp>

#include <cstdint>
#include <random>
#include <vector>

#include "cdt2.h"
#include "voroclip/core.h"
#include "voroclip/delaunay.h"
#include "voroclip/predicates.h"

using voroclip::Delaunay2;
using voroclip::Sign;
using voroclip::mesh2d::Cdt2;

namespace {

// Checks validity and the constrained Delaunay property; returns the sum of the
// triangles' doubled areas.
double check_cdt(const Cdt2& cdt, const std::vector<double>& xy) {
  const auto p = [&](std::uint32_t v) { return &xy[2 * std::size_t{v}]; };
  double area2 = 0;
  for (std::uint32_t t = 0; t < cdt.nb_triangles(); ++t) {
    const double* a = p(cdt.vertex(t, 0));
    const double* b = p(cdt.vertex(t, 1));
    const double* c = p(cdt.vertex(t, 2));
    REQUIRE(voroclip::orient2d(a, b, c) == Sign::positive);
    area2 += (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t code = cdt.across(t, k);
      if (code == Cdt2::kNone) continue;
      const std::uint32_t u = code / 3;
      const int j = static_cast<int>(code % 3);
      REQUIRE(cdt.across(u, j) == 3 * t + static_cast<std::uint32_t>(k));
      REQUIRE(cdt.constrained(u, j) == cdt.constrained(t, k));
      // The shared edge, in opposite directions.
      REQUIRE(cdt.vertex(t, (k + 1) % 3) == cdt.vertex(u, (j + 2) % 3));
      REQUIRE(cdt.vertex(t, (k + 2) % 3) == cdt.vertex(u, (j + 1) % 3));
      if (!cdt.constrained(t, k)) {
        REQUIRE(voroclip::incircle(a, b, c, p(cdt.vertex(u, j))) != Sign::positive);
      }
    }
  }
  return area2;
}

double hull_area2(const Delaunay2& dt) {
  double area2 = 0;
  for (std::uint32_t t = 0; t < dt.nb_triangles(); ++t) {
    const double* a = dt.point(dt.tri_vertex(t, 0));
    const double* b = dt.point(dt.tri_vertex(t, 1));
    const double* c = dt.point(dt.tri_vertex(t, 2));
    area2 += (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
  }
  return area2;
}

// True when the closed segments [a, b] and [c, d] meet other than at a shared end.
bool segments_meet(const double* a, const double* b, const double* c, const double* d) {
  const Sign s1 = voroclip::orient2d(a, b, c), s2 = voroclip::orient2d(a, b, d);
  const Sign s3 = voroclip::orient2d(c, d, a), s4 = voroclip::orient2d(c, d, b);
  if (s1 == Sign::zero && s2 == Sign::zero) {
    // Collinear: overlap of the projections on the longer axis.
    const int k = std::abs(b[0] - a[0]) >= std::abs(b[1] - a[1]) ? 0 : 1;
    const double lo1 = std::min(a[k], b[k]), hi1 = std::max(a[k], b[k]);
    const double lo2 = std::min(c[k], d[k]), hi2 = std::max(c[k], d[k]);
    return std::max(lo1, lo2) < std::min(hi1, hi2);
  }
  return s1 * s2 != Sign::positive && s3 * s4 != Sign::positive;
}

}  // namespace

TEST_CASE(
    "cdt2: random points and non-crossing segments give a constrained Delaunay "
    "triangulation",
    "[mesh][exact]") {
  for (std::uint32_t seed = 1; seed <= 20; ++seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    const std::uint32_t n = 300;
    std::vector<double> xy(2 * n);
    for (double& x : xy) x = u(rng);
    const Delaunay2 dt(xy.data(), n);
    Cdt2 cdt(dt);
    const double hull = hull_area2(dt);
    // Long random segments, kept when they meet no kept one and pass through no point.
    std::vector<std::uint32_t> segs;
    std::uniform_int_distribution<std::uint32_t> pick(0, n - 1);
    for (int attempt = 0; attempt < 400 && segs.size() < 60; ++attempt) {
      const std::uint32_t a = pick(rng), b = pick(rng);
      if (a == b) continue;
      bool ok = true;
      for (std::size_t s = 0; s < segs.size() && ok; s += 2) {
        const std::uint32_t c = segs[s], d = segs[s + 1];
        if (a == c || a == d || b == c || b == d) {
          // Sharing an end: only collinear overlap is a conflict.
          const std::uint32_t shared = (a == c || a == d) ? a : b;
          const std::uint32_t x = shared == a ? b : a, y = (c == shared) ? d : c;
          ok = !(voroclip::orient2d(&xy[2 * shared], &xy[2 * x], &xy[2 * y]) == Sign::zero);
          continue;
        }
        ok = !segments_meet(&xy[2 * a], &xy[2 * b], &xy[2 * c], &xy[2 * d]);
      }
      if (!ok) continue;
      std::vector<std::uint32_t> pieces;
      cdt.insert_segment(a, b, &pieces);
      REQUIRE(pieces.size() == 2);  // random points: none exactly on a segment
      REQUIRE(pieces[0] == a);
      REQUIRE(pieces[1] == b);
      segs.push_back(a);
      segs.push_back(b);
    }
    REQUIRE(segs.size() >= 20);
    cdt.make_delaunay();
    INFO("seed " << seed);
    CHECK(check_cdt(cdt, xy) == Approx(hull).epsilon(1e-12));
    for (std::size_t s = 0; s < segs.size(); s += 2) {
      int k = 0;
      std::uint32_t t = cdt.find_edge(segs[s], segs[s + 1], &k);
      if (t == Cdt2::kNone) t = cdt.find_edge(segs[s + 1], segs[s], &k);
      REQUIRE(t != Cdt2::kNone);
      CHECK(cdt.constrained(t, k));
    }
  }
}

TEST_CASE("cdt2: a segment through vertices is split there; crossing segments are refused",
          "[mesh][exact]") {
  // A 9 x 9 grid of integer points: every row and diagonal holds vertices.
  std::vector<double> xy;
  for (int j = 0; j < 9; ++j) {
    for (int i = 0; i < 9; ++i) {
      xy.push_back(i);
      xy.push_back(j);
    }
  }
  const auto id = [](int i, int j) { return static_cast<std::uint32_t>(9 * j + i); };
  const Delaunay2 dt(xy.data(), 81);
  Cdt2 cdt(dt);
  std::vector<std::uint32_t> pieces;
  cdt.insert_segment(id(0, 0), id(8, 8), &pieces);  // the diagonal: 8 pieces
  REQUIRE(pieces.size() == 16);
  for (int k = 0; k < 8; ++k) {
    CHECK(pieces[2 * k] == id(k, k));
    CHECK(pieces[2 * k + 1] == id(k + 1, k + 1));
  }
  pieces.clear();
  cdt.insert_segment(id(0, 4), id(2, 5), &pieces);  // slope 1/2: through no vertex
  CHECK(pieces.size() == 2);
  pieces.clear();
  cdt.insert_segment(id(8, 0), id(4, 2), &pieces);  // slope -1/2, from (8,0) to (4,2): via (6,1)
  REQUIRE(pieces.size() == 4);
  CHECK(pieces[1] == id(6, 1));
  cdt.make_delaunay();
  check_cdt(cdt, xy);
  // The anti-diagonal crosses the diagonal at (4, 4), a vertex: split, no crossing.
  pieces.clear();
  cdt.insert_segment(id(0, 8), id(8, 0), &pieces);
  CHECK(pieces.size() == 16);
  // (0, 1) to (2, 0) crosses the constrained diagonal edge (0,0)-(1,1) at (2/3, 2/3).
  CHECK_THROWS_AS(cdt.insert_segment(id(0, 1), id(2, 0)), voroclip::Error);
}
