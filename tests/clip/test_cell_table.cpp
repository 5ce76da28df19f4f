// Tests of the cell tables (clip.h "Tables of cells", core.h "Tables of the cells"):
// cell_neighbors in 2D and 3D against the diagram's own facts and the Delaunay
// triangulation: pairs symmetric (cell j's edges/faces on bisector(i, j) measure what cell
// i's do), a subset of the Delaunay edges (all of them when the domain holds every Voronoi
// vertex), inner cells' measures by the pyramid formula (area = sum of l_ij d_ij / 4 in 2D,
// volume = sum of a_ij d_ij / 6 in 3D, d_ij = |s_j - s_i|), the 2D lengths equal to the
// distances of the circumcentres; the table's columns equal the diagram's values; the
// CSV/JSON text.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "support/surfaces.h"
#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/delaunay.h"

using voroclip::CellTable;
using voroclip::ClippedVoronoi2;
using voroclip::ClippedVoronoi3;
using voroclip::Delaunay2;
using voroclip::Delaunay3;
using voroclip::Domain2;
using voroclip::Domain3;
using voroclip::NeighborTable;

namespace {

using Pair = std::pair<std::uint32_t, std::uint32_t>;

Domain2 square_domain(double lo, double hi) {
  voroclip::PolygonRings p;
  p.source = "square";
  p.xy = {lo, lo, hi, lo, hi, hi, lo, hi};
  p.ring_begin = {0, 4};
  p.ring_polygon = {0};
  p.ring_line = {0};
  return Domain2(p);
}

std::vector<double> uniform(std::uint32_t n, int dim, double lo, double hi, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  std::vector<double> v(static_cast<std::size_t>(dim) * n);
  for (double& x : v) x = u(rng);
  return v;
}

std::map<Pair, double> rows(const NeighborTable& t) {
  std::map<Pair, double> m;
  for (std::uint32_t r = 0; r < t.nb_pairs(); ++r) {
    const Pair p{t.pairs[2 * r], t.pairs[2 * r + 1]};
    CHECK(p.first < p.second);
    CHECK(m.emplace(p, t.measure[r]).second);  // each pair once
  }
  // Sorted rows.
  for (std::uint32_t r = 1; r < t.nb_pairs(); ++r) {
    CHECK(Pair{t.pairs[2 * r - 2], t.pairs[2 * r - 1]} < Pair{t.pairs[2 * r], t.pairs[2 * r + 1]});
  }
  return m;
}

std::set<Pair> delaunay_edges(const Delaunay2& dt) {
  std::set<Pair> e;
  for (std::uint32_t t = 0; t < dt.nb_triangles(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = dt.tri_vertex(t, k), b = dt.tri_vertex(t, (k + 1) % 3);
      e.insert({std::min(a, b), std::max(a, b)});
    }
  }
  return e;
}

// Cell i's measure of what it shares with each neighbour j, from its own side (i > j
// included), recomputed here from the rings: the mirror of cell_neighbors' rows.
std::map<Pair, double> lengths_from_both_sides(const ClippedVoronoi2& cv) {
  std::map<Pair, double> m;
  const auto& vs = cv.vertices();
  const auto& xy = cv.vertex_coords();
  const auto sites_of = [](const voroclip::ClipVertex2& v) {
    std::set<std::uint32_t> s;
    if (v.kind == voroclip::ClipVertex2::Kind::kEdgeBisector) s = {v.b, v.c};
    if (v.kind == voroclip::ClipVertex2::Kind::kVoronoi) s = {v.a, v.b, v.c};
    return s;
  };
  for (std::uint32_t i = 0; i < cv.nb_sites(); ++i) {
    for (std::uint32_t r = cv.cell_ring_begin(i); r < cv.cell_ring_begin(i + 1); ++r) {
      const std::uint32_t b = cv.ring_vertex_begin(r), e = cv.ring_vertex_begin(r + 1);
      for (std::uint32_t k = b; k < e; ++k) {
        const std::uint32_t l = k + 1 == e ? b : k + 1;
        std::set<std::uint32_t> common;
        const auto su = sites_of(vs[k]), sv = sites_of(vs[l]);
        std::set_intersection(su.begin(), su.end(), sv.begin(), sv.end(),
                              std::inserter(common, common.end()));
        common.erase(i);
        if (common.size() != 1) continue;
        m[{i, *common.begin()}] += std::hypot(xy[2 * l] - xy[2 * k], xy[2 * l + 1] - xy[2 * k + 1]);
      }
    }
  }
  return m;
}

}  // namespace

TEST_CASE("cell_neighbors 2D: symmetric, the Delaunay edges, pyramid areas", "[clip][table]") {
  // Sites in a small square, the domain far larger: every Voronoi vertex is inside, so the
  // pairs are exactly the Delaunay edges and every bounded Voronoi edge is whole.
  const std::uint64_t seed = 17;
  INFO("seed " << seed);
  const std::uint32_t n = 300;
  const std::vector<double> sites = uniform(n, 2, 0.4, 0.6, seed);
  const Domain2 domain = square_domain(-1e3, 1e3);
  const Delaunay2 dt(sites.data(), n);
  ClippedVoronoi2 cv;
  voroclip::Clip2Options o;
  o.keep_geometry = true;
  cv.compute(domain, dt, o);
  const NeighborTable t = voroclip::cell_neighbors(cv);
  CHECK(t.dimension == 2);
  const std::map<Pair, double> m = rows(t);
  std::set<Pair> pairs;
  for (const auto& [p, len] : m) pairs.insert(p);
  CHECK(pairs == delaunay_edges(dt));

  // Both sides measure the same edge.
  const std::map<Pair, double> both = lengths_from_both_sides(cv);
  CHECK(both.size() == 2 * m.size());
  for (const auto& [p, len] : m) {
    const double other = both.at({p.second, p.first});
    CHECK(std::fabs(len - other) <= 1e-12 * std::max(1.0, len));
    CHECK(both.at(p) == len);
  }

  // An edge between two finite triangles is the segment of their circumcentres.
  std::map<Pair, std::vector<std::array<double, 2>>> centres;
  for (std::uint32_t tr = 0; tr < dt.nb_triangles(); ++tr) {
    const double* a = dt.point(dt.tri_vertex(tr, 0));
    const double* b = dt.point(dt.tri_vertex(tr, 1));
    const double* c = dt.point(dt.tri_vertex(tr, 2));
    const double bx = b[0] - a[0], by = b[1] - a[1], cx = c[0] - a[0], cy = c[1] - a[1];
    const double d = 2 * (bx * cy - by * cx);
    const double ux = (cy * (bx * bx + by * by) - by * (cx * cx + cy * cy)) / d;
    const double uy = (bx * (cx * cx + cy * cy) - cx * (bx * bx + by * by)) / d;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t p = dt.tri_vertex(tr, k), q = dt.tri_vertex(tr, (k + 1) % 3);
      centres[{std::min(p, q), std::max(p, q)}].push_back({a[0] + ux, a[1] + uy});
    }
  }
  std::size_t compared = 0;
  for (const auto& [p, cs] : centres) {
    if (cs.size() != 2) continue;
    const auto inside = [](const std::array<double, 2>& c) {
      return std::fabs(c[0]) < 1e3 && std::fabs(c[1]) < 1e3;
    };
    if (!inside(cs[0]) || !inside(cs[1])) continue;
    const double expected = std::hypot(cs[0][0] - cs[1][0], cs[0][1] - cs[1][1]);
    CHECK(std::fabs(m.at(p) - expected) <= 1e-9 * std::max(1e-3, expected));
    ++compared;
  }
  CHECK(compared > n);

  // Inner cells: area = sum over neighbours of length * distance / 4.
  std::vector<double> pyramid(n, 0);
  for (const auto& [p, len] : m) {
    const double d = std::hypot(sites[2 * p.first] - sites[2 * p.second],
                                sites[2 * p.first + 1] - sites[2 * p.second + 1]);
    pyramid[p.first] += len * d / 4;
    pyramid[p.second] += len * d / 4;
  }
  std::size_t inner = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (cv.is_boundary(i)) continue;
    ++inner;
    CHECK(std::fabs(pyramid[i] - cv.area(i)) <= 1e-9 * cv.area(i));
  }
  CHECK(inner > n / 2);

  // The table: one row per cell with the diagram's values and the neighbour counts.
  const CellTable table = voroclip::cell_table(cv, sites.data(), &t);
  REQUIRE(table.nb_cells() == n);
  double area_sum = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    CHECK(table.measure[i] == cv.area(i));
    CHECK(table.centroids[2 * i] == cv.centroid(i)[0]);
    CHECK(table.energy[i] == cv.energy(i));
    CHECK(table.boundary[i] == (cv.is_boundary(i) ? 1 : 0));
    CHECK(table.sites[2 * i + 1] == sites[2 * i + 1]);
    std::uint32_t count = 0;
    for (const auto& p : pairs) count += p.first == i || p.second == i;
    CHECK(table.nb_neighbors[i] == count);
    area_sum += table.measure[i];
  }
  CHECK(std::fabs(area_sum - domain.area()) <= 1e-12 * domain.area());
}

TEST_CASE("cell_neighbors 2D: a domain with holes, pairs a subset of the Delaunay edges",
          "[clip][table]") {
  const Domain2 domain(voroclip::square_with_holes(3, 0.5));
  const std::uint64_t seed = 5;
  INFO("seed " << seed);
  std::vector<double> sites;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  while (sites.size() < 2 * 200) {
    const double p[2] = {
        domain.bbox_lo()[0] + u(rng) * (domain.bbox_hi()[0] - domain.bbox_lo()[0]),
        domain.bbox_lo()[1] + u(rng) * (domain.bbox_hi()[1] - domain.bbox_lo()[1])};
    if (domain.locate(p) == voroclip::Sign::positive) sites.insert(sites.end(), p, p + 2);
  }
  const Delaunay2 dt(sites.data(), 200);
  ClippedVoronoi2 cv;
  voroclip::Clip2Options o;
  o.keep_geometry = true;
  cv.compute(domain, dt, o);
  const std::map<Pair, double> m = rows(voroclip::cell_neighbors(cv));
  const std::set<Pair> edges = delaunay_edges(dt);
  const std::map<Pair, double> both = lengths_from_both_sides(cv);
  for (const auto& [p, len] : m) {
    CHECK(edges.count(p) == 1);
    CHECK(len > 0);
    CHECK(std::fabs(both.at({p.second, p.first}) - len) <= 1e-12 * std::max(1.0, len));
  }
  CHECK(both.size() == 2 * m.size());
  // Without geometry: an error, not an empty table.
  ClippedVoronoi2 bare;
  bare.compute(domain, dt);
  CHECK_THROWS_AS(voroclip::cell_neighbors(bare), voroclip::Error);
}

TEST_CASE("cell_neighbors 3D: symmetric, Delaunay edges, pyramid volumes", "[clip][table]") {
  const Domain3 domain(voroclip_test::box_surface({0, 0, 0}, {1, 1, 1}));
  const std::uint64_t seed = 3;
  INFO("seed " << seed);
  const std::uint32_t n = 400;
  const std::vector<double> sites = uniform(n, 3, 0.02, 0.98, seed);
  ClippedVoronoi3 cv;
  voroclip::Clip3Options o;
  o.keep_geometry = true;
  cv.compute(domain, sites.data(), n, o);
  const NeighborTable t = voroclip::cell_neighbors(cv);
  CHECK(t.dimension == 3);
  const std::map<Pair, double> m = rows(t);

  // Delaunay edges, in input indices (the triangulation is of the sites in spatial order).
  const Delaunay3& dt = cv.delaunay();
  const std::vector<std::uint32_t>& order = cv.site_order();
  std::set<Pair> edges;
  for (std::uint32_t tt = 0; tt < dt.nb_tet_slots(); ++tt) {
    if (dt.is_infinite(tt)) continue;
    for (int a = 0; a < 4; ++a) {
      for (int b = a + 1; b < 4; ++b) {
        const std::uint32_t p = order[dt.tet_vertex(tt, a)], q = order[dt.tet_vertex(tt, b)];
        edges.insert({std::min(p, q), std::max(p, q)});
      }
    }
  }
  for (const auto& [p, area] : m) CHECK(edges.count(p) == 1);
  CHECK(m.size() > 3 * n);

  // Both sides: cell j's faces across i have the area of cell i's faces across j.
  const ClippedVoronoi3::Polygons& f = cv.cell_faces();
  std::map<Pair, std::array<double, 3>> vec;
  for (std::size_t k = 0; k < f.site.size(); ++k) {
    const std::uint32_t j = f.across[k];
    if (j == ClippedVoronoi3::kSurface || j == ClippedVoronoi3::kInterior) continue;
    std::array<double, 3>& a = vec[{f.site[k], j}];
    const double* p0 = &f.xyz[3 * f.polygon_begin[k]];
    for (std::uint32_t v = f.polygon_begin[k] + 1; v + 1 < f.polygon_begin[k + 1]; ++v) {
      const double* p = &f.xyz[3 * v];
      const double* q = &f.xyz[3 * v + 3];
      a[0] += (p[1] - p0[1]) * (q[2] - p0[2]) - (p[2] - p0[2]) * (q[1] - p0[1]);
      a[1] += (p[2] - p0[2]) * (q[0] - p0[0]) - (p[0] - p0[0]) * (q[2] - p0[2]);
      a[2] += (p[0] - p0[0]) * (q[1] - p0[1]) - (p[1] - p0[1]) * (q[0] - p0[0]);
    }
  }
  CHECK(vec.size() == 2 * m.size());
  for (const auto& [p, area] : m) {
    const std::array<double, 3>& a = vec.at({p.second, p.first});
    CHECK(std::fabs(0.5 * std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]) - area) <=
          1e-10 * std::max(1e-4, area));
  }

  // Inner cells: volume = sum over neighbours of area * distance / 6.
  std::vector<double> pyramid(n, 0);
  for (const auto& [p, area] : m) {
    const double* a = &sites[3 * p.first];
    const double* b = &sites[3 * p.second];
    const double d = std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                               (a[2] - b[2]) * (a[2] - b[2]));
    pyramid[p.first] += area * d / 6;
    pyramid[p.second] += area * d / 6;
  }
  std::size_t inner = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (cv.is_boundary(i)) continue;
    ++inner;
    CHECK(std::fabs(pyramid[i] - cv.volume(i)) <= 1e-9 * cv.volume(i));
  }
  CHECK(inner > 20);

  const CellTable table = voroclip::cell_table(cv, sites.data(), &t);
  REQUIRE(table.nb_cells() == n);
  double volume_sum = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    CHECK(table.measure[i] == cv.volume(i));
    CHECK(table.centroids[3 * i + 2] == cv.centroid(i)[2]);
    CHECK(table.surface_area[i] == cv.surface_area(i));
    CHECK(table.boundary[i] == (cv.is_boundary(i) ? 1 : 0));
    volume_sum += table.measure[i];
  }
  CHECK(std::fabs(volume_sum - 1) <= 1e-12);
}

TEST_CASE("cell tables as CSV and JSON text", "[core][table]") {
  CellTable c;
  c.dimension = 2;
  c.sites = {0.5, 0.25, 1, 2};
  c.measure = {0.1, 3};
  c.centroids = {0.5, 0.3, 1e-300, 2};
  c.energy = {0, 1.5};
  c.boundary = {1, 0};
  c.nb_neighbors = {1, 1};
  std::ostringstream csv;
  voroclip::write_cell_table_csv(csv, c);
  CHECK(csv.str() ==
        "site,x,y,area,centroid_x,centroid_y,energy,boundary,neighbors\n"
        "0,0.5,0.25,0.1,0.5,0.3,0,1,1\n"
        "1,1,2,3,1e-300,2,1.5,0,1\n");
  c.energy.pop_back();
  std::ostringstream bad;
  CHECK_THROWS_AS(voroclip::write_cell_table_csv(bad, c), voroclip::Error);

  NeighborTable t;
  t.dimension = 3;
  t.pairs = {0, 1};
  t.measure = {0.125};
  std::ostringstream ncsv, njson;
  voroclip::write_neighbor_table_csv(ncsv, t);
  CHECK(ncsv.str() == "site_a,site_b,area\n0,1,0.125\n");
  voroclip::write_neighbor_table_json(njson, t);
  CHECK(njson.str().find("\"site_b\": 1") != std::string::npos);
  CHECK(njson.str().find("\"area\": 0.125") != std::string::npos);
}

TEST_CASE("write_vtu: polygons (VTK_POLYGON) next to triangles", "[core]") {
  // A square (4 points) and a triangle sharing two of its points.
  const double xy[] = {0, 0, 1, 0, 1, 1, 0, 1, 2, 0};
  const std::uint32_t square[] = {0, 1, 2, 3}, begin[] = {0, 4};
  const std::uint32_t triangle[] = {1, 4, 2};
  std::vector<voroclip::VtuCellTags> tags(1);
  tags[0].name = "site_id";
  tags[0].values = {7, 8};
  std::ostringstream out;
  voroclip::write_vtu(out, xy, 5, 2, {{square, 1, 0, begin}, {triangle, 1, 3}},
                      voroclip::VtuEncoding::kAscii, {}, tags);
  const std::string s = out.str();
  const auto array = [&](const std::string& name) {
    const std::string open = "Name=\"" + name + "\" format=\"ascii\">\n";
    const std::size_t b = s.find(open);
    REQUIRE(b != std::string::npos);
    return s.substr(b + open.size(), s.find("</DataArray>", b) - b - open.size());
  };
  CHECK(array("connectivity") == "0\n1\n2\n3\n1\n4\n2\n");
  CHECK(array("offsets") == "4\n7\n");
  CHECK(array("types") == "7\n5\n");  // VTK_POLYGON, VTK_TRIANGLE
  CHECK(array("site_id") == "7\n8\n");
  CHECK(s.find("NumberOfPoints=\"5\" NumberOfCells=\"2\"") != std::string::npos);
  // A polygon block needs its offsets.
  std::ostringstream bad;
  CHECK_THROWS_AS(
      voroclip::write_vtu(bad, xy, 5, 2, {{square, 1, 0, nullptr}}, voroclip::VtuEncoding::kAscii),
      voroclip::Error);
}
