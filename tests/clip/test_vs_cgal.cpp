// Cross-check of ClippedVoronoi2 against CGAL (tests only; the only clip test that includes
// CGAL). Each cell is recomputed by brute force with exact rational arithmetic: the Voronoi
// cell as the intersection of the half-planes of all the other sites within a box around
// the domain, then CGAL's exact Boolean intersection with the domain. Pieces, holes, area
// and vertices must agree.
#include <CGAL/Boolean_set_operations_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/Polygon_with_holes_2.h>
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/delaunay.h"

namespace {

using K = CGAL::Exact_predicates_exact_constructions_kernel;
using Point = K::Point_2;
using Polygon = CGAL::Polygon_2<K>;
using PolygonWithHoles = CGAL::Polygon_with_holes_2<K>;

Polygon ring_polygon(const voroclip::Domain2& d, std::uint32_t r) {
  Polygon p;
  for (std::uint32_t v = d.ring_begin(r); v < d.ring_end(r); ++v) {
    p.push_back(Point(d.vertex(v)[0], d.vertex(v)[1]));
  }
  return p;
}

// The domain as polygons with holes (a hole belongs to the outer ring that contains it).
std::vector<PolygonWithHoles> domain_polygons(const voroclip::Domain2& d) {
  std::vector<PolygonWithHoles> out;
  for (std::uint32_t r = 0; r < d.nb_rings(); ++r) {
    if (!d.is_hole(r)) out.emplace_back(ring_polygon(d, r));
  }
  for (std::uint32_t r = 0; r < d.nb_rings(); ++r) {
    if (!d.is_hole(r)) continue;
    const Polygon hole = ring_polygon(d, r);
    for (PolygonWithHoles& p : out) {
      if (p.outer_boundary().bounded_side(hole[0]) == CGAL::ON_BOUNDED_SIDE) {
        p.add_hole(hole);
        break;
      }
    }
  }
  return out;
}

// Convex polygon (counter-clockwise) cut by the half-plane a x + b y + c <= 0.
Polygon cut(const Polygon& poly, const K::FT& a, const K::FT& b, const K::FT& c) {
  Polygon out;
  const std::size_t n = poly.size();
  for (std::size_t k = 0; k < n; ++k) {
    const Point& p = poly[static_cast<std::ptrdiff_t>(k)];
    const Point& q = poly[static_cast<std::ptrdiff_t>((k + 1) % n)];
    const K::FT fp = a * p.x() + b * p.y() + c, fq = a * q.x() + b * q.y() + c;
    if (fp <= 0) out.push_back(p);
    if ((fp < 0 && fq > 0) || (fp > 0 && fq < 0)) {
      const K::FT t = fp / (fp - fq);
      out.push_back(Point(p.x() + t * (q.x() - p.x()), p.y() + t * (q.y() - p.y())));
    }
  }
  return out;
}

void compare(const voroclip::Domain2& d, const std::vector<double>& sites, std::uint64_t seed) {
  const auto n = static_cast<std::uint32_t>(sites.size() / 2);
  const voroclip::Delaunay2 dt(sites.data(), n);
  voroclip::ClippedVoronoi2 cv;
  voroclip::Clip2Options o;
  o.keep_geometry = true;
  cv.compute(d, dt, o);
  const std::vector<PolygonWithHoles> domain = domain_polygons(d);
  const double span = std::max(d.bbox_hi()[0] - d.bbox_lo()[0], d.bbox_hi()[1] - d.bbox_lo()[1]);
  Polygon box;
  box.push_back(Point(d.bbox_lo()[0] - span, d.bbox_lo()[1] - span));
  box.push_back(Point(d.bbox_hi()[0] + span, d.bbox_lo()[1] - span));
  box.push_back(Point(d.bbox_hi()[0] + span, d.bbox_hi()[1] + span));
  box.push_back(Point(d.bbox_lo()[0] - span, d.bbox_hi()[1] + span));
  const std::vector<double>& xy = cv.vertex_coords();
  for (std::uint32_t i = 0; i < n; ++i) {
    INFO("seed " << seed << ", site " << i);
    Polygon cell = box;
    const Point pi(sites[2 * i], sites[2 * i + 1]);
    for (std::uint32_t j = 0; j < n && !cell.is_empty(); ++j) {
      if (j == i) continue;
      const Point pj(sites[2 * j], sites[2 * j + 1]);
      // |x - pi|^2 <= |x - pj|^2  <=>  2 x.(pj - pi) + |pi|^2 - |pj|^2 <= 0
      cell = cut(cell, 2 * (pj.x() - pi.x()), 2 * (pj.y() - pi.y()),
                 pi.x() * pi.x() + pi.y() * pi.y() - pj.x() * pj.x() - pj.y() * pj.y());
    }
    std::vector<PolygonWithHoles> pieces;
    if (cell.size() >= 3) {
      for (const PolygonWithHoles& p : domain) {
        CGAL::intersection(cell, p, std::back_inserter(pieces));
      }
    }
    K::FT area = 0;
    std::size_t holes = 0;
    std::vector<Point> vertices;
    for (const PolygonWithHoles& p : pieces) {
      area += p.outer_boundary().area();
      vertices.insert(vertices.end(), p.outer_boundary().vertices_begin(),
                      p.outer_boundary().vertices_end());
      for (auto h = p.holes_begin(); h != p.holes_end(); ++h) {
        area += h->area();
        ++holes;
        vertices.insert(vertices.end(), h->vertices_begin(), h->vertices_end());
      }
    }
    REQUIRE(std::fabs(CGAL::to_double(area) - cv.area(i)) <= 1e-12 * d.area());
    // Rings: counter-clockwise ones are pieces, clockwise ones holes.
    std::size_t ours_pieces = 0, ours_holes = 0;
    for (std::uint32_t r = cv.cell_ring_begin(i); r < cv.cell_ring_begin(i + 1); ++r) {
      double a = 0;
      const std::uint32_t b = cv.ring_vertex_begin(r), e = cv.ring_vertex_begin(r + 1);
      for (std::uint32_t k = b; k < e; ++k) {
        const std::uint32_t l = k + 1 == e ? b : k + 1;
        a += (xy[2 * k] - xy[2 * b]) * (xy[2 * l + 1] - xy[2 * b + 1]) -
             (xy[2 * l] - xy[2 * b]) * (xy[2 * k + 1] - xy[2 * b + 1]);
      }
      (a > 0 ? ours_pieces : ours_holes)++;
    }
    REQUIRE(ours_pieces == pieces.size());
    REQUIRE(ours_holes == holes);
    // Every vertex of CGAL's result is one of ours (ours may add vertices on straight
    // lines: domain vertices where the domain boundary is straight).
    for (const Point& p : vertices) {
      const double px = CGAL::to_double(p.x()), py = CGAL::to_double(p.y());
      double best = INFINITY;
      for (std::uint32_t r = cv.cell_ring_begin(i); r < cv.cell_ring_begin(i + 1); ++r) {
        for (std::uint32_t k = cv.ring_vertex_begin(r); k < cv.ring_vertex_begin(r + 1); ++k) {
          best = std::min(best, std::hypot(xy[2 * k] - px, xy[2 * k + 1] - py));
        }
      }
      REQUIRE(best <= 1e-9 * span);
    }
  }
}

std::vector<double> random_inside(const voroclip::Domain2& d, std::uint32_t n, std::uint64_t seed) {
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

TEST_CASE("clip2d equals CGAL's exact Boolean intersection of cells and domain", "[clip][cgal]") {
  const std::string data = VOROCLIP_SHARED_DATA_DIR;
  const voroclip::Domain2 holes(voroclip::square_with_holes(3, 0.5));
  const voroclip::Domain2 dude(voroclip::read_polygon(data + "/polygons/valid/dude.json"));
  const voroclip::Domain2 issue34(voroclip::read_polygon(data + "/polygons/valid/issue34.json"));
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    compare(holes, random_inside(holes, 25, seed), seed);
    compare(dude, random_inside(dude, 30, seed), seed);
    compare(issue34, random_inside(issue34, 12, seed), seed);
  }
}
