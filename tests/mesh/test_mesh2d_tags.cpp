// Tags of 2D meshes read from a JSON file of several polygons: each ring its own boundary
// tag (its position in the file from 1), each polygon its own region (from 1), checked
// against brute-force point location in the polygons given separately.
#include <catch2/catch.hpp>

#include <cstdint>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/mesh.h"
#include "voroclip/predicates.h"

namespace {

using voroclip::Domain2;
using voroclip::Mesh2;
using voroclip::PolygonRings;
using voroclip::Sign;

// Three polygons: a square with a square hole, a second square with a hole to its right,
// and an island in the first one's hole (its outer ring inside polygon 0's hole).
const char* kJson = R"([
  [[[0, 0], [4, 0], [4, 4], [0, 4]], [[1, 1], [1, 3], [3, 3], [3, 1]]],
  [[[5, 0], [9, 0], [9, 4], [5, 4]], [[6, 1], [6, 2], [8, 2], [8, 1]]],
  [[[1.5, 1.5], [2.5, 1.5], [2.5, 2.5], [1.5, 2.5]]]
])";

// The rings as a domain of their own each (for point location).
std::vector<std::vector<double>> rings() {
  return {{0, 0, 4, 0, 4, 4, 0, 4},
          {1, 1, 1, 3, 3, 3, 3, 1},
          {5, 0, 9, 0, 9, 4, 5, 4},
          {6, 1, 6, 2, 8, 2, 8, 1},
          {1.5, 1.5, 2.5, 1.5, 2.5, 2.5, 1.5, 2.5}};
}

Domain2 ring_domain(const std::vector<double>& xy) {
  PolygonRings r;
  r.source = "ring";
  r.xy = xy;
  r.ring_begin = {0, static_cast<std::uint32_t>(xy.size() / 2)};
  r.ring_polygon = {0};
  r.ring_line = {0};
  return Domain2(r);
}

// Which ring (from 0) point p lies on: exactly on one of its segments (orient2d zero and
// within the segment's box), or -1.
int ring_on(const std::vector<std::vector<double>>& all, const double* p) {
  for (std::size_t r = 0; r < all.size(); ++r) {
    const std::vector<double>& xy = all[r];
    const std::size_t n = xy.size() / 2;
    for (std::size_t i = 0; i < n; ++i) {
      const double* a = &xy[2 * i];
      const double* b = &xy[2 * ((i + 1) % n)];
      if (voroclip::orient2d(a, b, p) != Sign::zero) continue;
      if (p[0] < std::min(a[0], b[0]) || p[0] > std::max(a[0], b[0])) continue;
      if (p[1] < std::min(a[1], b[1]) || p[1] > std::max(a[1], b[1])) continue;
      return static_cast<int>(r);
    }
  }
  return -1;
}

}  // namespace

TEST_CASE("mesh2d: a JSON file of several polygons tags each ring and each polygon",
          "[mesh][tags]") {
  std::istringstream in(kJson);
  const Domain2 d(voroclip::read_polygon(in, "three.json"));
  REQUIRE(d.nb_rings() == 5);
  // Domain2: the ring tags are the rings' positions in the file from 1.
  for (std::uint32_t r = 0; r < d.nb_rings(); ++r) {
    CHECK(d.ring_polygon(r) == (r < 2 ? 0 : r < 4 ? 1 : 2));
    for (std::uint32_t e = d.ring_begin(r); e < d.ring_end(r); ++e) {
      CHECK(d.edge_tag(e) == static_cast<std::int32_t>(r + 1));
    }
  }

  voroclip::Mesh2Options o;
  o.nb_vertices = 600;
  o.seed = 3;
  voroclip::Mesh2Stats st;
  const Mesh2 m = voroclip::mesh_domain2(d, o, &st);
  REQUIRE(voroclip::check_mesh2(d, m).empty());

  // Boundary edges: the tag of the ring both ends lie on (the rings' corners are mesh
  // vertices and every boundary vertex of these axis-parallel rings is exactly on its
  // side: one coordinate is a copy of the side's).
  const std::vector<std::vector<double>> all = rings();
  REQUIRE(m.boundary_edges.size() == 2 * m.boundary_tags.size());
  std::set<std::int32_t> tags_seen;
  for (std::size_t e = 0; e < m.boundary_tags.size(); ++e) {
    const double* a = &m.xy[2 * std::size_t{m.boundary_edges[2 * e]}];
    const double* b = &m.xy[2 * std::size_t{m.boundary_edges[2 * e + 1]}];
    const int ra = ring_on(all, a), rb = ring_on(all, b);
    INFO("boundary edge " << e << " (" << a[0] << ", " << a[1] << ") - (" << b[0] << ", " << b[1]
                          << ")");
    REQUIRE(ra >= 0);
    REQUIRE(ra == rb);
    CHECK(m.boundary_tags[e] == ra + 1);
    tags_seen.insert(m.boundary_tags[e]);
  }
  CHECK(tags_seen == std::set<std::int32_t>{1, 2, 3, 4, 5});

  // Triangles: the region of the polygon holding the centroid, found by exact location
  // in each polygon's outer ring and out of its hole.
  std::vector<Domain2> ring_domains;
  for (const auto& r : all) ring_domains.push_back(ring_domain(r));
  const auto inside = [&](std::size_t r, const double* p) {
    return ring_domains[r].locate(p) == Sign::positive;
  };
  std::set<std::int32_t> regions_seen;
  REQUIRE(m.triangle_regions.size() == m.nb_triangles());
  for (std::uint32_t t = 0; t < m.nb_triangles(); ++t) {
    double c[2] = {0, 0};
    for (int k = 0; k < 3; ++k) {
      c[0] += m.xy[2 * std::size_t{m.triangles[3 * std::size_t{t} + k]}] / 3;
      c[1] += m.xy[2 * std::size_t{m.triangles[3 * std::size_t{t} + k]} + 1] / 3;
    }
    const int polygon = inside(4, c)                    ? 2
                        : inside(0, c) && !inside(1, c) ? 0
                        : inside(2, c) && !inside(3, c) ? 1
                                                        : -1;
    INFO("triangle " << t << ", centroid (" << c[0] << ", " << c[1] << ")");
    REQUIRE(polygon >= 0);
    CHECK(m.triangle_regions[t] == polygon + 1);
    regions_seen.insert(m.triangle_regions[t]);
  }
  CHECK(regions_seen == std::set<std::int32_t>{1, 2, 3});
}

TEST_CASE("mesh2d: one JSON polygon keeps outer ring 1, holes 2, 3, ... and region 1",
          "[mesh][tags]") {
  std::istringstream in(R"([[[0, 0], [4, 0], [4, 4], [0, 4]],
                            [[1, 1], [1, 2], [2, 2], [2, 1]],
                            [[2.5, 2.5], [2.5, 3], [3, 3], [3, 2.5]]])");
  const Domain2 d(voroclip::read_polygon(in, "one.json"));
  for (std::uint32_t r = 0; r < d.nb_rings(); ++r) {
    CHECK(d.ring_polygon(r) == 0);
    for (std::uint32_t e = d.ring_begin(r); e < d.ring_end(r); ++e) {
      CHECK(d.edge_tag(e) == static_cast<std::int32_t>(r + 1));
    }
  }
  voroclip::Mesh2Options o;
  o.nb_vertices = 300;
  const Mesh2 m = voroclip::mesh_domain2(d, o);
  REQUIRE(voroclip::check_mesh2(d, m).empty());
  CHECK(std::set<std::int32_t>(m.triangle_regions.begin(), m.triangle_regions.end()) ==
        std::set<std::int32_t>{1});
  CHECK(std::set<std::int32_t>(m.boundary_tags.begin(), m.boundary_tags.end()) ==
        std::set<std::int32_t>{1, 2, 3});
}
