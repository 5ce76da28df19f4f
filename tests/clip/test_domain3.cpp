// Domain3: every shared model validated and checked against facts independent of the
// implementation (the file's own boundary triangles, the Euler characteristic of each
// surface's genus, the divergence-theorem volume, exact orientation), hand-made meshes for
// each defect with the whole message checked, scale sweeps and 1-vs-N threads.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <unistd.h>
#include <utility>
#include <vector>

#include <tbb/global_control.h>

#include "../core/tagged_mesh.h"
#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/predicates.h"

using voroclip::Domain3;
using voroclip::Sign;
using voroclip::TetMeshInput;

namespace {

const std::string kData = std::string(VOROCLIP_SHARED_DATA_DIR) + "/tetmeshes/";
constexpr std::uint32_t kNone = Domain3::kNone;

using Tri = std::array<std::uint32_t, 3>;

// A triangle rotated so that its smallest vertex comes first (orientation kept).
Tri canonical(Tri t) {
  while (t[0] > t[1] || t[0] > t[2]) t = {t[1], t[2], t[0]};
  return t;
}

std::array<std::uint32_t, 3> facet(const Domain3& d, std::uint32_t t, int f) {
  return {d.tet_vertex(t, Domain3::kTetFacetVertex[f][0]),
          d.tet_vertex(t, Domain3::kTetFacetVertex[f][1]),
          d.tet_vertex(t, Domain3::kTetFacetVertex[f][2])};
}

// Checks every invariant of the contract in clip.h; returns the first violation, or "".
std::string check_domain3(const Domain3& d) {
  std::ostringstream err;
  for (std::uint32_t t = 0; t < d.nb_tets(); ++t) {
    if (d.source_tet(t) != t) return "source_tet(" + std::to_string(t) + ") != t";
    const Sign s = voroclip::orient3d(d.vertex(d.tet_vertex(t, 0)), d.vertex(d.tet_vertex(t, 1)),
                                      d.vertex(d.tet_vertex(t, 2)), d.vertex(d.tet_vertex(t, 3)));
    if (s != Sign::positive) return "tet " + std::to_string(t) + " is not positive";
    for (int f = 0; f < 4; ++f) {
      const std::uint32_t n = d.tet_adjacent(t, f);
      const std::uint32_t b = d.tet_boundary(t, f);
      if ((n == kNone) == (b == kNone)) {
        return "tet " + std::to_string(t) + " facet " + std::to_string(f) +
               ": neither or both of adjacent and boundary";
      }
      // The facet as listed is on the positive side of orient3d away from the tet.
      const Tri tri = facet(d, t, f);
      if (voroclip::orient3d(d.vertex(tri[0]), d.vertex(tri[1]), d.vertex(tri[2]),
                             d.vertex(d.tet_vertex(t, f))) != Sign::negative) {
        return "tet " + std::to_string(t) + " facet " + std::to_string(f) + " is not outward";
      }
      if (n != kNone) {
        // Symmetric, the same triangle listed the other way round.
        int back = -1;
        for (int g = 0; g < 4; ++g) {
          if (d.tet_adjacent(n, g) == t) back = g;
        }
        if (back < 0) return "adjacency not symmetric at tet " + std::to_string(t);
        const Tri other = facet(d, n, back);
        if (canonical(tri) != canonical({other[0], other[2], other[1]})) {
          return "tets " + std::to_string(t) + " and " + std::to_string(n) +
                 " do not share their facet with opposite orientations";
        }
      } else {
        if (d.boundary_tet(b) != t || d.boundary_facet(b) != f) {
          return "tet_boundary and boundary_tet/facet disagree at tet " + std::to_string(t);
        }
      }
    }
  }
  for (std::uint32_t b = 0; b < d.surface().nb_triangles(); ++b) {
    const std::uint32_t t = d.boundary_tet(b);
    const int f = d.boundary_facet(b);
    if (b > 0 &&
        std::make_pair(d.boundary_tet(b - 1), d.boundary_facet(b - 1)) >= std::make_pair(t, f)) {
      return "boundary triangles not ordered by (tet, facet) at " + std::to_string(b);
    }
    if (d.tet_adjacent(t, f) != kNone || d.tet_boundary(t, f) != b) {
      return "boundary triangle " + std::to_string(b) + " is not a boundary facet";
    }
    // The surface triangle is the facet reversed (outward by the right-hand rule).
    const Tri f3 = facet(d, t, f);
    const Tri tri = {f3[0], f3[2], f3[1]};
    for (int k = 0; k < 3; ++k) {
      if (d.surface().triangle_vertex(b, k) != tri[static_cast<std::size_t>(k)] ||
          d.surface().triangle(b)[k] != tri[static_cast<std::size_t>(k)]) {
        return "boundary triangle " + std::to_string(b) + " is not its facet reversed";
      }
    }
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t u = d.surface().triangle_vertex(b, (e + 1) % 3);
      const std::uint32_t w = d.surface().triangle_vertex(b, (e + 2) % 3);
      const std::uint32_t n = d.surface().adjacent(b, e);
      if (n == kNone || n == b) return "boundary triangle " + std::to_string(b) + " open edge";
      int back = -1;
      for (int g = 0; g < 3; ++g) {
        if (d.surface().triangle_vertex(n, (g + 1) % 3) == w &&
            d.surface().triangle_vertex(n, (g + 2) % 3) == u) {
          back = g;
        }
      }
      if (back < 0 || d.surface().adjacent(n, back) != b) {
        return "boundary adjacency not symmetric at triangle " + std::to_string(b);
      }
    }
  }
  // surface_order: every boundary triangle once; each one adjacent to a triangle before it,
  // or, once the component listed so far is complete (no listed triangle has an unlisted
  // neighbour), the lowest-numbered triangle not listed yet.
  const std::vector<std::uint32_t>& order = d.surface().order();
  const std::uint32_t nb = d.surface().nb_triangles();
  if (order.size() != nb) return "surface_order has the wrong length";
  std::vector<char> listed(nb, 0);
  std::uint32_t lowest = 0;    // the lowest-numbered triangle not listed yet
  std::size_t open_edges = 0;  // edges of listed triangles to unlisted ones
  for (const std::uint32_t b : order) {
    if (b >= nb || listed[b]) return "surface_order is not a permutation";
    bool after_neighbour = false;
    for (int e = 0; e < 3; ++e) {
      after_neighbour = after_neighbour || listed[d.surface().adjacent(b, e)];
    }
    if (!after_neighbour && (b != lowest || open_edges != 0)) {
      return "surface_order: triangle " + std::to_string(b) + " does not continue the surface";
    }
    listed[b] = 1;
    for (int e = 0; e < 3; ++e) {
      if (listed[d.surface().adjacent(b, e)] && d.surface().adjacent(b, e) != b) {
        --open_edges;
      } else {
        ++open_edges;
      }
    }
    while (lowest < nb && listed[lowest]) ++lowest;
  }
  return "";
}

void require_valid(const Domain3& d) {
  const std::string problem = check_domain3(d);
  INFO(problem);
  REQUIRE(problem.empty());
}

// The Triangles section of a Medit file (0-based), as written.
std::vector<Tri> medit_triangles(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line) && line != "Triangles") {
  }
  std::size_t n = 0;
  in >> n;
  std::vector<Tri> tris(n);
  for (auto& t : tris) {
    long long ref = 0;
    in >> t[0] >> t[1] >> t[2] >> ref;
    for (auto& v : t) --v;
  }
  return tris;
}

// Compensated sum, in the order given.
struct Sum {
  double s = 0, c = 0;
  void add(double x) {
    const double t = s + x;
    c += std::fabs(s) >= std::fabs(x) ? (s - t) + x : (x - t) + s;
    s = t;
  }
  double value() const { return s + c; }
};

double det3(const double* a, const double* b, const double* c) {
  return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
         a[2] * (b[0] * c[1] - b[1] * c[0]);
}

// The Euler characteristic V - E + F of the boundary surface.
long long boundary_euler(const Domain3& d) {
  std::set<std::uint32_t> vertices;
  for (std::uint32_t b = 0; b < d.surface().nb_triangles(); ++b) {
    for (int k = 0; k < 3; ++k) vertices.insert(d.surface().triangle_vertex(b, k));
  }
  std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
  for (std::uint32_t b = 0; b < d.surface().nb_triangles(); ++b) {
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t u = d.surface().triangle_vertex(b, (e + 1) % 3);
      const std::uint32_t w = d.surface().triangle_vertex(b, (e + 2) % 3);
      edges.emplace(std::min(u, w), std::max(u, w));
    }
  }
  return static_cast<long long>(vertices.size()) - static_cast<long long>(edges.size()) +
         static_cast<long long>(d.surface().nb_triangles());
}

struct Model {
  const char* name;
  std::uint32_t vertices, tets, boundary;
  int genus;
};

// The data README's table; genus from the surfaces README.
const Model kModels[] = {
    {"sphere", 763, 2413, 1280, 0},         {"sphere-fine", 22049, 105250, 20480, 0},
    {"bunny", 4083, 14050, 6598, 0},        {"skull_low_resolution", 6260, 21774, 10312, 2},
    {"elk", 7379, 29125, 10388, 1},         {"fandisk", 8636, 32914, 12946, 0},
    {"homer", 8926, 36893, 12000, 0},       {"rocker-arm", 16157, 68468, 20088, 1},
    {"gargoyle", 50002, 170710, 100000, 0},
};

// The unit cube split into the 6 Kuhn tets around its diagonal (0,0,0)-(1,1,1), vertex
// i = x + 2y + 4z at (x, y, z); `orientations` alternate so that some need a swap.
TetMeshInput kuhn_cube(double scale = 1, double shift = 0) {
  TetMeshInput m;
  m.source = "kuhn";
  for (int i = 0; i < 8; ++i) {
    for (int k = 0; k < 3; ++k) m.xyz.push_back(((i >> k) & 1) * scale + shift);
  }
  // Paths 0 -> 7 along the axes in the 6 orders.
  const int orders[6][3] = {{1, 2, 4}, {1, 4, 2}, {2, 1, 4}, {2, 4, 1}, {4, 1, 2}, {4, 2, 1}};
  for (const auto& o : orders) {
    const std::uint32_t a = 0, b = static_cast<std::uint32_t>(o[0]),
                        c = static_cast<std::uint32_t>(o[0] + o[1]), d = 7;
    m.tets.insert(m.tets.end(), {a, b, c, d});
    m.tet_line.push_back(static_cast<std::uint32_t>(10 + m.tet_line.size()));
  }
  return m;
}

TetMeshInput make(std::vector<double> xyz, std::vector<std::uint32_t> tets) {
  TetMeshInput m;
  m.source = "hand";
  m.xyz = std::move(xyz);
  m.tets = std::move(tets);
  for (std::uint32_t t = 0; t < m.nb_tets(); ++t) m.tet_line.push_back(100 + t);
  return m;
}

std::string error_of(const TetMeshInput& m) {
  try {
    Domain3 d(m);
  } catch (const voroclip::Error& e) {
    return e.what();
  }
  return "(no error)";
}

// The unit tet (0,0,0) (1,0,0) (0,1,0) (0,0,1) and a fifth vertex per test.
std::vector<double> tet_and(double x, double y, double z) {
  return {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, x, y, z};
}

}  // namespace

TEST_CASE("Domain3 validates every shared model", "[clip]") {
  for (const Model& m : kModels) {
    const std::string path = kData + m.name + ".mesh";
    INFO(path);
    const TetMeshInput mesh = voroclip::read_tet_mesh(path);
    const Domain3 d(mesh);
    require_valid(d);
    CHECK(d.source() == path);
    CHECK(d.nb_vertices() == m.vertices);
    CHECK(d.nb_tets() == m.tets);
    CHECK(d.surface().nb_triangles() == m.boundary);
    CHECK(boundary_euler(d) == 2 - 2 * m.genus);

    // The surface triangles are the file's Triangles, outward as they are (Surface3).
    std::vector<Tri> ours, file;
    for (std::uint32_t b = 0; b < d.surface().nb_triangles(); ++b) {
      const std::uint32_t* v = d.surface().triangle(b);
      ours.push_back(canonical({v[0], v[1], v[2]}));
    }
    for (const Tri& t : medit_triangles(path)) file.push_back(canonical(t));
    std::sort(ours.begin(), ours.end());
    std::sort(file.begin(), file.end());
    CHECK(ours == file);

    // Volume = the volume enclosed by the boundary (divergence theorem): +sum det / 6 over
    // the file's triangles and over ours; the tets' volumes sum to it too.
    Sum enclosed_file, enclosed_ours;
    for (const Tri& t : medit_triangles(path)) {
      enclosed_file.add(det3(d.vertex(t[0]), d.vertex(t[1]), d.vertex(t[2])) / 6);
    }
    for (std::uint32_t b = 0; b < d.surface().nb_triangles(); ++b) {
      const std::uint32_t* v = d.surface().triangle(b);
      enclosed_ours.add(det3(d.vertex(v[0]), d.vertex(v[1]), d.vertex(v[2])) / 6);
    }
    CHECK(d.volume() > 0);
    CHECK(std::fabs(d.volume() - enclosed_file.value()) <= 1e-12 * d.volume());
    CHECK(std::fabs(d.volume() - enclosed_ours.value()) <= 1e-12 * d.volume());
    CHECK(std::fabs(d.volume() - d.tet_volume()) <= 1e-12 * d.volume());
    REQUIRE(d.surface().shells().size() == 1);
    CHECK(d.surface().shells()[0].genus == static_cast<std::uint32_t>(m.genus));

    // TetGen writes det(p1 - p0, p2 - p0, p3 - p0) > 0: orient3d < 0, so every tet was
    // swapped (vertices 2 and 3), nothing else changed.
    for (std::uint32_t t = 0; t < d.nb_tets(); ++t) {
      const std::uint32_t* v = mesh.tets.data() + 4 * static_cast<std::size_t>(t);
      REQUIRE(d.tet_vertex(t, 0) == v[0]);
      REQUIRE(d.tet_vertex(t, 1) == v[1]);
      REQUIRE(d.tet_vertex(t, 2) == v[3]);
      REQUIRE(d.tet_vertex(t, 3) == v[2]);
    }
    // The bounding box is that of the vertices (all used).
    for (int k = 0; k < 3; ++k) {
      double lo = mesh.xyz[static_cast<std::size_t>(k)], hi = lo;
      for (std::size_t i = 0; i < mesh.nb_vertices(); ++i) {
        lo = std::min(lo, mesh.xyz[3 * i + static_cast<std::size_t>(k)]);
        hi = std::max(hi, mesh.xyz[3 * i + static_cast<std::size_t>(k)]);
      }
      CHECK(d.bbox_lo()[k] == lo);
      CHECK(d.bbox_hi()[k] == hi);
    }
  }
}

TEST_CASE("Domain3 is identical for 1 and N threads", "[clip][threads]") {
  const TetMeshInput mesh = voroclip::read_tet_mesh(kData + "bunny.mesh");
  const auto build = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                              static_cast<std::size_t>(threads));
    return Domain3(mesh);
  };
  const Domain3 one = build(1), many = build(8);
  CHECK(one.volume() == many.volume());
  REQUIRE(one.surface().nb_triangles() == many.surface().nb_triangles());
  for (std::uint32_t t = 0; t < one.nb_tets(); ++t) {
    for (int f = 0; f < 4; ++f) {
      REQUIRE(one.tet_adjacent(t, f) == many.tet_adjacent(t, f));
      REQUIRE(one.tet_vertex(t, f) == many.tet_vertex(t, f));
    }
  }
  for (std::uint32_t b = 0; b < one.surface().nb_triangles(); ++b) {
    for (int e = 0; e < 3; ++e)
      REQUIRE(one.surface().adjacent(b, e) == many.surface().adjacent(b, e));
  }
}

TEST_CASE("Domain3: the Kuhn cube, mixed orientations, scale sweep", "[clip][exact]") {
  for (const double scale : {1e-9, 1e-3, 1.0, 1e3, 1e9}) {
    for (const double shift : {0.0, 1e3 * scale, -0.75 * scale}) {
      INFO("scale " << scale << " shift " << shift);
      TetMeshInput m = kuhn_cube(scale, shift);
      // Flip every other tet: each is accepted and made positive.
      for (std::size_t t = 0; t < m.nb_tets(); t += 2) std::swap(m.tets[4 * t], m.tets[4 * t + 1]);
      const Domain3 d(m);
      require_valid(d);
      CHECK(d.surface().nb_triangles() == 12);
      CHECK(boundary_euler(d) == 2);
      // (The shifted coordinates are rounded: the cube is a cube to ~1e-13 relative.)
      CHECK(d.volume() == Approx(scale * scale * scale).epsilon(1e-11));
      CHECK(d.bbox_lo()[0] == shift);
      CHECK(d.bbox_hi()[2] == scale + shift);
      // All 6 tets share the diagonal: the 12 boundary triangles are the cube's faces.
      for (std::uint32_t b = 0; b < 12; ++b) {
        const double* p = d.vertex(d.surface().triangle_vertex(b, 0));
        const double* q = d.vertex(d.surface().triangle_vertex(b, 1));
        const double* r = d.vertex(d.surface().triangle_vertex(b, 2));
        bool on_face = false;
        for (int k = 0; k < 3; ++k) on_face = on_face || (p[k] == q[k] && q[k] == r[k]);
        CHECK(on_face);
      }
    }
  }
}

TEST_CASE("Domain3: a flipped tet is accepted and reoriented", "[clip]") {
  // The unit tet in the right-handed order: det(p1 - p0, p2 - p0, p3 - p0) = 1 > 0, so
  // orient3d (Shewchuk's sign) < 0; vertex 4 duplicates vertex 0 but is used by no tet.
  const TetMeshInput m = make(tet_and(0, 0, 0), {0, 1, 2, 3});
  REQUIRE(voroclip::orient3d(&m.xyz[0], &m.xyz[3], &m.xyz[6], &m.xyz[9]) == Sign::negative);
  const Domain3 d(m);
  require_valid(d);
  CHECK(d.tet_vertex(0, 0) == 0);
  CHECK(d.tet_vertex(0, 1) == 1);
  CHECK(d.tet_vertex(0, 2) == 3);
  CHECK(d.tet_vertex(0, 3) == 2);
  CHECK(d.volume() == 1.0 / 6);
  CHECK(d.surface().nb_triangles() == 4);
  CHECK(boundary_euler(d) == 2);
  // Vertex 4 is used by no tet: ignored (not a duplicate), kept in the array.
  CHECK(d.nb_vertices() == 5);
  CHECK(d.bbox_hi()[0] == 1);
}

TEST_CASE("Domain3: a non-convex mesh (a Kuhn cube without one tet) is accepted", "[clip]") {
  TetMeshInput m = kuhn_cube();
  m.tets.erase(m.tets.begin() + 8, m.tets.begin() + 12);
  m.tet_line.erase(m.tet_line.begin() + 2);
  const Domain3 d(m);
  require_valid(d);
  CHECK(d.surface().nb_triangles() == 12);
  CHECK(boundary_euler(d) == 2);
  CHECK(d.volume() == Approx(5.0 / 6).epsilon(1e-14));
}

TEST_CASE("Domain3 rejects zero-volume tets and repeated vertices", "[clip][degenerate]") {
  CHECK(error_of(make(tet_and(0.5, 0.5, 0), {0, 1, 2, 4})) ==
        "hand:100: tet 0 has zero volume: its vertices 0 1 2 4 are coplanar (exact orient3d; "
        "numbered from 0)");
  // Coplanar only exactly: 1e-300 off the plane is a valid (tiny) tet.
  CHECK(error_of(make(tet_and(0.5, 0.5, 1e-300), {0, 1, 2, 4})) == "(no error)");
  // Nearly coplanar in floating point, exactly coplanar: (1/3, 1/3, 1/3) is not a double,
  // but 0.25 + 0.25 + 0.5 = 1 is, on the plane x + y + z = 1.
  CHECK(error_of(make(tet_and(0.25, 0.25, 0.5), {0, 1, 2, 3, 1, 2, 3, 4})) ==
        "hand:101: tet 1 has zero volume: its vertices 1 2 3 4 are coplanar (exact orient3d; "
        "numbered from 0)");
  CHECK(error_of(make(tet_and(0, 0, 0), {0, 1, 2, 3, 1, 2, 1, 3})) ==
        "hand:101: tet 1 has a repeated vertex (vertices 1 2 1 3; numbered from 0)");
}

TEST_CASE("Domain3 rejects duplicate vertices", "[clip][degenerate]") {
  // Two tets sharing the facet (1, 2, 3), but the second names a copy of vertex 1.
  TetMeshInput m = make(tet_and(1, 1, 1), {0, 1, 2, 3, 5, 3, 2, 4});
  m.xyz.insert(m.xyz.end(), {1, 0, 0});
  CHECK(error_of(m) ==
        "hand: vertices 1 and 5 have the same coordinates (1, 0, 0) (duplicate vertices), "
        "used by tet 0 (line 100) and tet 1 (line 101) (numbered from 0)");
}

TEST_CASE("Domain3 rejects overlapping tets and facets of three tets", "[clip][degenerate]") {
  // (0, 1, 2, 4) is on the same side of (0, 1, 2) as the unit tet.
  CHECK(error_of(make(tet_and(0.2, 0.2, 0.2), {0, 1, 2, 3, 0, 1, 2, 4})) ==
        "hand:100: tet 0 and tet 1 (line 101) overlap: both lie on the same side of their "
        "shared facet (vertices 0 1 2; numbered from 0)");
  // The same tet twice.
  CHECK(error_of(make(tet_and(0, 0, 0), {0, 1, 2, 3, 3, 1, 2, 0})) ==
        "hand:100: tet 0 and tet 1 (line 101) overlap: both lie on the same side of their "
        "shared facet (vertices 0 1 2; numbered from 0)");
  // Three tets on the facet (0, 1, 2): z = 1, z = -1 and z = -2.
  TetMeshInput m = make(tet_and(0.1, 0.1, -1), {0, 1, 2, 3, 0, 1, 2, 4, 0, 1, 2, 5});
  m.xyz.insert(m.xyz.end(), {0.2, 0.2, -2});
  CHECK(error_of(m) ==
        "hand:100: tet 0: the facet (vertices 0 1 2; numbered from 0) is shared by 3 tets (at "
        "most 2): tet 0 "
        "(line 100), tet 1 (line 101) and tet 2 (line 102)");
}

TEST_CASE("Domain3 rejects a boundary that is not a closed 2-manifold", "[clip][degenerate]") {
  // Two tets sharing only the edge (0, 1): it is in 4 boundary triangles. (A single tet,
  // or a tet mesh with one tet removed, is always closed modulo 2: this is how an "open"
  // boundary shows.) Two of them are facets of tet 0, two of tet 1: their vertices tell
  // them apart (regression: both were "the boundary facet of tet 0 (line 100)").
  TetMeshInput m = make(tet_and(0, -1, 0), {0, 1, 2, 3, 0, 1, 4, 5});
  m.xyz.insert(m.xyz.end(), {0, 0, -1});
  CHECK(error_of(m) ==
        "hand:100: the boundary facet (vertices 0 1 2) of tet 0: the surface is not a "
        "2-manifold: the edge (vertices 0 1) is in 4 triangles (2 expected): the boundary facet "
        "(vertices 0 1 2) of tet 0 (line 100), the boundary facet (vertices 0 1 3) of tet 0 "
        "(line 100), the boundary facet (vertices 0 1 4) of tet 1 (line 101) and the boundary "
        "facet (vertices 0 1 5) of tet 1 (line 101)");
  // The Kuhn cube without two opposite tets: two wedges touching along the diagonal.
  TetMeshInput k = kuhn_cube();
  k.tets.erase(k.tets.begin() + 20, k.tets.begin() + 24);  // order {4, 2, 1}
  k.tets.erase(k.tets.begin(), k.tets.begin() + 4);        // order {1, 2, 4}
  k.tet_line = {11, 12, 13, 14};
  const std::string e = error_of(k);
  CHECK(e.find("kuhn:11: the boundary facet (vertices 0 1 7) of tet 0: the surface is not a "
               "2-manifold: the edge (vertices 0 7) is in 4 triangles") == 0);
  // Two tets sharing only vertex 0: every edge is fine, vertex 0 has two fans.
  TetMeshInput v = make(tet_and(-1, 0, 0), {0, 1, 2, 3, 0, 4, 5, 6});
  v.xyz.insert(v.xyz.end(), {0, -1, 0, 0, 0, -1});
  CHECK(error_of(v) ==
        "hand: the surface is not a 2-manifold at vertex 0 (0, 0, 0) (a pinched vertex): its "
        "triangles form several fans, one with the boundary facet (vertices 0 2 3) of tet 0 "
        "(line 100), another with the boundary facet (vertices 0 5 6) of tet 1 (line 101)");
}

TEST_CASE("Domain3 rejects non-finite coordinates and bad indices", "[clip][degenerate]") {
  const double nan = std::nan("");
  CHECK(error_of(make(tet_and(0, 0, 0), {0, 1, 2, 3, 1, 2, 3, 9})) ==
        "hand:101: tet 1: vertex index 9 is out of range (the mesh has 5 vertices; tets and "
        "vertices numbered from 0)");
  TetMeshInput m = make(tet_and(nan, 0, 0), {0, 1, 2, 4});
  CHECK(error_of(m) ==
        "hand:100: tet 0: vertex 4 has a non-finite coordinate (nan, 0, 0) (numbered from 0)");
  // Unused: ignored.
  m.tets = {0, 1, 2, 3};
  CHECK(error_of(m) == "(no error)");
  // No line known: the message says so by leaving it out.
  TetMeshInput n = make(tet_and(0.5, 0.5, 0), {0, 1, 2, 4});
  n.tet_line.clear();
  CHECK(error_of(n) ==
        "hand: tet 0 has zero volume: its vertices 0 1 2 4 are coplanar (exact orient3d; numbered "
        "from 0)");
  // An empty mesh is an empty domain.
  const Domain3 empty{TetMeshInput{}};
  CHECK(empty.nb_tets() == 0);
  CHECK(empty.surface().nb_triangles() == 0);
  CHECK(empty.volume() == 0);
}

TEST_CASE("Domain3 messages name the file and line of the tet, numbered as the file does",
          "[clip]") {
  const auto dir = std::filesystem::temp_directory_path();
  const std::string path =
      (dir / ("voroclip_test_domain3_flat_" + std::to_string(::getpid()) + ".mesh")).string();
  std::ofstream(path) << "MeshVersionFormatted 2\nDimension 3\nVertices\n5\n"
                         "0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n1 1 0 0\n"
                         "Tetrahedra\n2\n1 2 3 4 0\n1 2 3 5 0\nEnd\n";
  const TetMeshInput mesh = voroclip::read_tet_mesh(path);
  // Medit counts tetrahedra and vertices from 1: the second tetrahedron, on the first three
  // vertices and the fifth.
  CHECK(error_of(mesh) == path +
                              ":13: tetrahedron 2 has zero volume: its vertices 1 2 3 5 are "
                              "coplanar (exact orient3d; Medit numbering, from 1)");
  std::filesystem::remove(path);
}

TEST_CASE("Domain3 keeps a tet mesh's region and boundary tags", "[clip]") {
  const voroclip::TetMeshInput in = voroclip_test::tagged_kuhn_cube();
  const Domain3 d(in);
  CHECK(d.tet_refs() == in.tet_ref);
  REQUIRE(d.tag_names().size() == 4);
  CHECK(d.tag_names()[1].name == "copper region");
  const voroclip::Surface3& s = d.surface();
  REQUIRE(d.boundary_refs().size() == s.nb_triangles());
  // Each boundary triangle lies on a face of the cube: x faces 10, y faces 11, z faces 12.
  for (std::uint32_t b = 0; b < s.nb_triangles(); ++b) {
    int axis = -1;
    for (int k = 0; k < 3; ++k) {
      const double c = s.vertex(s.triangle_vertex(b, 0))[k];
      if (s.vertex(s.triangle_vertex(b, 1))[k] == c && s.vertex(s.triangle_vertex(b, 2))[k] == c) {
        axis = k;
      }
    }
    REQUIRE(axis >= 0);
    CHECK(d.boundary_refs()[b] == 10 + axis);
  }
  // A boundary triangle the file does not list gets 0; untagged files give no refs.
  voroclip::TetMeshInput fewer = in;
  fewer.triangles.resize(fewer.triangles.size() - 3);
  fewer.triangle_ref.pop_back();
  const Domain3 f(fewer);
  CHECK(std::count(f.boundary_refs().begin(), f.boundary_refs().end(), 0) == 1);
  voroclip::TetMeshInput plain = in;
  plain.triangles.clear();
  plain.triangle_ref.clear();
  plain.tet_ref.clear();
  const Domain3 p(plain);
  CHECK(p.boundary_refs().empty());
  CHECK(p.tet_refs().empty());
  // Counts that do not match are errors.
  voroclip::TetMeshInput bad = in;
  bad.tet_ref.pop_back();
  CHECK_THROWS_AS(Domain3(bad), voroclip::Error);
}

TEST_CASE("Domain3 names Gmsh elements and nodes by their tags", "[clip][degenerate]") {
  // Gmsh: element and node tags, whatever they are.
  const std::string gmsh = "test_domain3_numbering.msh";
  std::string error = "(no error)";
  {
    std::ofstream out(gmsh);
    out << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n5\n10 0 0 0\n20 1 0 0\n30 0 1 0\n40 0 "
           "0 1\n50 0.5 0.5 0\n$EndNodes\n$Elements\n2\n7 4 0 10 20 30 40\n9 4 0 30 20 10 "
           "50\n$EndElements\n";
  }
  try {
    const Domain3 d(voroclip::read_tet_mesh(gmsh));
  } catch (const voroclip::Error& e) {
    error = e.what();
  }
  std::remove(gmsh.c_str());
  CHECK(error == gmsh +
                     ":15: element 9 has zero volume: its vertices 30 20 10 50 are coplanar "
                     "(exact orient3d; Gmsh element and node tags)");
}
