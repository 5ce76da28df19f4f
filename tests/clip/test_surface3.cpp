// Surface3 (voroclip/clip.h): every shared surface validated and checked against facts
// independent of the implementation (the tet meshes TetGen made of them: same volume, their
// interior vertices inside, boundary vertices on the surface; the README's genus), each
// defect family rejected with its message, several shells nested and oriented, welding,
// reorientation, 1 vs N threads.
#include <catch2/catch.hpp>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "support/surfaces.h"
#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/predicates.h"

using voroclip::Sign;
using voroclip::Surface3;
using voroclip::TriangleSurface;
using voroclip_test::box_surface;
using voroclip_test::icosphere;
using voroclip_test::merged;
using voroclip_test::reversed;

namespace {

const std::string kData = std::string(VOROCLIP_SHARED_DATA_DIR);

// Every invariant of the contract in clip.h that a test can see; the first violation, or "".
std::string check_surface3(const Surface3& s) {
  const std::uint32_t nt = s.nb_triangles();
  for (std::uint32_t t = 0; t < nt; ++t) {
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t u = s.triangle_vertex(t, (e + 1) % 3);
      const std::uint32_t w = s.triangle_vertex(t, (e + 2) % 3);
      const std::uint32_t n = s.adjacent(t, e);
      if (n >= nt || n == t) return "triangle " + std::to_string(t) + ": bad neighbour";
      int back = -1;
      for (int g = 0; g < 3; ++g) {
        if (s.triangle_vertex(n, (g + 1) % 3) == w && s.triangle_vertex(n, (g + 2) % 3) == u) {
          back = g;
        }
      }
      if (back < 0 || s.adjacent(n, back) != t) {
        return "adjacency not symmetric at triangle " + std::to_string(t);
      }
      if (s.shell_of(n) != s.shell_of(t)) return "neighbours in two shells";
    }
  }
  // order: a permutation; each shell's triangles consecutive, from its first triangle.
  std::vector<char> listed(nt, 0);
  if (s.order().size() != nt) return "order has the wrong length";
  std::uint32_t shell = Surface3::kNone;
  for (const std::uint32_t t : s.order()) {
    if (t >= nt || listed[t]) return "order is not a permutation";
    listed[t] = 1;
    if (s.shell_of(t) != shell) {
      shell = s.shell_of(t);
      if (shell >= s.shells().size() || s.shells()[shell].first_triangle != t) {
        return "a shell does not start at its first triangle in the order";
      }
    }
  }
  // Each shell: counts, Euler characteristic, orientation as its role says.
  double volume = 0;
  for (std::uint32_t k = 0; k < s.shells().size(); ++k) {
    const Surface3::Shell& sh = s.shells()[k];
    std::set<std::uint32_t> vertices;
    std::uint32_t triangles = 0;
    double det_sum = 0;
    for (std::uint32_t t = 0; t < nt; ++t) {
      if (s.shell_of(t) != k) continue;
      ++triangles;
      const std::uint32_t* v = s.triangle(t);
      vertices.insert(v, v + 3);
      const double *a = s.vertex(v[0]), *b = s.vertex(v[1]), *c = s.vertex(v[2]);
      det_sum += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                  a[2] * (b[0] * c[1] - b[1] * c[0])) /
                 6;
    }
    if (triangles != sh.nb_triangles || vertices.size() != sh.nb_vertices ||
        2 * sh.nb_edges != 3 * sh.nb_triangles) {
      return "shell " + std::to_string(k) + ": wrong counts";
    }
    const long long chi = static_cast<long long>(sh.nb_vertices) - sh.nb_edges + sh.nb_triangles;
    if (chi != 2 - 2 * static_cast<long long>(sh.genus)) return "shell genus";
    if ((sh.volume > 0) == sh.cavity()) return "shell " + std::to_string(k) + ": volume sign";
    if (std::fabs(det_sum - sh.volume) > 1e-9 * std::fabs(sh.volume)) {
      return "shell " + std::to_string(k) + ": volume " + std::to_string(sh.volume) + " against " +
             std::to_string(det_sum);
    }
    volume += sh.volume;
  }
  if (std::fabs(volume - s.volume()) > 1e-12 * std::fabs(s.volume())) return "total volume";
  return "";
}

void require_valid(const Surface3& s) {
  const std::string problem = check_surface3(s);
  INFO(problem);
  REQUIRE(problem.empty());
}

std::string error_of(const TriangleSurface& t, bool reorient = false) {
  try {
    voroclip::Surface3Options o;
    o.reorient = reorient;
    const Surface3 s(t, o);
  } catch (const voroclip::Error& e) {
    return e.what();
  }
  return "(no error)";
}

// The volume the triangles enclose, sum of det / 6.
double enclosed(const TriangleSurface& t) {
  double v = 0;
  for (std::size_t k = 0; k < t.triangles.size(); k += 3) {
    const double* a = &t.xyz[3 * std::size_t{t.triangles[k]}];
    const double* b = &t.xyz[3 * std::size_t{t.triangles[k + 1]}];
    const double* c = &t.xyz[3 * std::size_t{t.triangles[k + 2]}];
    v += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
          a[2] * (b[0] * c[1] - b[1] * c[0])) /
         6;
  }
  return v;
}

struct Model {
  const char* name;
  const char* file;
  std::uint32_t vertices, triangles, genus;
};

// shared/data/surfaces/README.md.
const Model kModels[] = {
    {"bunny", "bunny.obj", 3301, 6598, 0},
    {"homer", "homer.obj", 6002, 12000, 0},
    {"rocker-arm", "rocker-arm.obj", 10044, 20088, 1},
    {"elk", "elk.off", 5194, 10388, 1},
    {"fandisk", "fandisk.obj", 6475, 12946, 0},
    {"skull_low_resolution", "skull_low_resolution.obj", 5154, 10312, 2},
    {"sphere", "sphere.obj", 642, 1280, 0},
    {"gargoyle", "gargoyle.off", 50002, 100000, 0},
};

}  // namespace

TEST_CASE("Surface3 validates every shared surface; its volume and inside are the tets'",
          "[clip][data]") {
  for (const Model& m : kModels) {
    const std::string path = kData + "/surfaces/" + m.file;
    INFO(path);
    const auto t0 = std::chrono::steady_clock::now();
    const TriangleSurface input = voroclip::read_surface(path);
    const auto t1 = std::chrono::steady_clock::now();
    const Surface3 s(input);
    const auto t2 = std::chrono::steady_clock::now();
    WARN(m.name << ": read " << std::chrono::duration<double>(t1 - t0).count()
                << " s, validated in " << std::chrono::duration<double>(t2 - t1).count() << " s");
    require_valid(s);
    CHECK(s.source() == path);
    CHECK(s.nb_vertices() == m.vertices);
    CHECK(s.nb_triangles() == m.triangles);
    REQUIRE(s.shells().size() == 1);
    CHECK(s.shells()[0].genus == m.genus);
    CHECK(s.shells()[0].depth == 0);
    CHECK(!s.shells()[0].reoriented);
    CHECK(s.area() > 0);
    // TetGen's mesh of the surface: the same volume, its vertices inside or on the surface.
    const voroclip::Domain3 tets(voroclip::read_tet_mesh(kData + "/tetmeshes/" + m.name + ".mesh"));
    CHECK(std::fabs(s.volume() - tets.tet_volume()) <= 1e-12 * s.volume());
    std::vector<std::uint8_t> on_surface(tets.nb_vertices(), 0);
    for (const std::uint32_t v : tets.surface().triangles()) on_surface[v] = 1;
    std::uint32_t inside = 0;
    for (std::uint32_t v = 0; v < tets.nb_vertices(); v += 7) {
      INFO("tet mesh vertex " << v);
      REQUIRE(s.locate(tets.vertex(v)) == (on_surface[v] ? Sign::zero : Sign::positive));
      inside += on_surface[v] ? 0 : 1;
    }
    // (gargoyle's mesh was made without interior points: tetgen -pY without -q.)
    CHECK((inside > 0) == (std::string(m.name) != "gargoyle"));
    // Tet centroids are inside; points beyond the bounding box outside.
    for (std::uint32_t t = 0; t < tets.nb_tets(); t += 101) {
      double c[3] = {0, 0, 0};
      for (int k = 0; k < 4; ++k) {
        for (int q = 0; q < 3; ++q) c[q] += 0.25 * tets.vertex(tets.tet_vertex(t, k))[q];
      }
      REQUIRE(s.locate(c) == Sign::positive);
    }
    const double far[3] = {s.bbox_hi()[0] + 1, s.bbox_lo()[1], s.bbox_lo()[2]};
    CHECK(s.locate(far) == Sign::negative);
  }
}

TEST_CASE("Surface3 is identical for 1 and N threads", "[clip][threads]") {
  const TriangleSurface input = voroclip::read_surface(kData + "/surfaces/gargoyle.off");
  const auto build = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                              static_cast<std::size_t>(threads));
    return Surface3(input);
  };
  const Surface3 one = build(1), many = build(4);
  CHECK(one.triangles() == many.triangles());
  CHECK(one.order() == many.order());
  CHECK(one.volume() == many.volume());
  CHECK(one.area() == many.area());
  for (std::uint32_t t = 0; t < one.nb_triangles(); ++t) {
    for (int e = 0; e < 3; ++e) REQUIRE(one.adjacent(t, e) == many.adjacent(t, e));
  }
}

TEST_CASE("Surface3: shells, cavities and their nesting", "[clip]") {
  const TriangleSurface outer = icosphere(2, 2), inner = icosphere(2, 1);
  SECTION("a hollow ball: the inner shell faces into the cavity") {
    const Surface3 s(merged(outer, reversed(inner)));
    require_valid(s);
    REQUIRE(s.shells().size() == 2);
    CHECK(s.shells()[0].depth == 0);
    CHECK(s.shells()[1].depth == 1);
    CHECK(s.shells()[1].parent == 0);
    CHECK(s.shells()[1].cavity());
    CHECK(s.volume() == Approx(enclosed(outer) - enclosed(inner)).epsilon(1e-14));
    const double centre[3] = {0, 0, 0}, wall[3] = {1.5, 0, 0}, beyond[3] = {2.5, 0, 0};
    CHECK(s.locate(centre) == Sign::negative);
    CHECK(s.locate(wall) == Sign::positive);
    CHECK(s.locate(beyond) == Sign::negative);
    CHECK(s.locate(&inner.xyz[0]) == Sign::zero);
  }
  SECTION("a ball in the cavity of a hollow ball, and a ball beside it") {
    const TriangleSurface core = icosphere(1, 0.5);
    const TriangleSurface other = icosphere(1, 1, {5, 0, 0});
    const Surface3 s(merged(merged(merged(outer, reversed(inner)), core), other));
    require_valid(s);
    REQUIRE(s.shells().size() == 4);
    CHECK(s.shells()[2].depth == 2);
    CHECK(s.shells()[2].parent == 1);
    CHECK(!s.shells()[2].cavity());
    CHECK(s.shells()[3].depth == 0);
    CHECK(s.volume() ==
          Approx(enclosed(outer) - enclosed(inner) + enclosed(core) + enclosed(other)));
    const double centre[3] = {0, 0, 0}, gap[3] = {0.75, 0, 0}, far[3] = {5, 0, 0};
    CHECK(s.locate(centre) == Sign::positive);
    CHECK(s.locate(gap) == Sign::negative);
    CHECK(s.locate(far) == Sign::positive);
  }
  SECTION("a cavity facing outward, an outer shell inside out: rejected, or reoriented") {
    const TriangleSurface wrong = merged(outer, inner);
    const std::string e = error_of(wrong);
    CHECK(e ==
          "icosphere: shell 1 (320 triangles, the first triangle 320) lies inside 1 shell (the "
          "innermost is shell 0) and faces outward; as the wall of a cavity it must face into "
          "the cavity (reverse the order of its faces' corners, or let voroclip reorient it: "
          "Surface3Options::reorient, --reorient)");
    const Surface3 fixed(wrong, voroclip::Surface3Options{true});
    require_valid(fixed);
    CHECK(!fixed.shells()[0].reoriented);
    CHECK(fixed.shells()[1].reoriented);
    CHECK(fixed.volume() == Approx(enclosed(outer) - enclosed(inner)).epsilon(1e-14));

    const TriangleSurface inside_out = reversed(icosphere(2));
    CHECK(error_of(inside_out)
              .find("icosphere: the surface is inside out: shell 0 (320 "
                    "triangles, the first triangle 0) faces inward") == 0);
    const Surface3 turned(inside_out, voroclip::Surface3Options{true});
    require_valid(turned);
    CHECK(turned.shells()[0].reoriented);
    CHECK(turned.volume() > 0);
    CHECK(turned.volume() == Approx(enclosed(icosphere(2))).epsilon(1e-14));
  }
}

TEST_CASE("Surface3 rejects each defect with the triangles and vertices involved",
          "[clip][degenerate]") {
  const TriangleSurface ball = icosphere(1);  // 80 triangles, 42 vertices
  SECTION("open") {
    TriangleSurface open = ball;
    open.triangles.resize(open.triangles.size() - 3);
    CHECK(error_of(open).find("icosphere: triangle ") == 0);
    CHECK(error_of(open).find(": the surface is not closed: its edge (vertices ") !=
          std::string::npos);
  }
  SECTION("pinched vertex: two tetrahedra sharing a vertex") {
    TriangleSurface two;
    two.source = "hand";
    two.xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, -1, 0, 0, 0, -1, 0, 0, 0, -1};
    two.triangles = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3, 0, 4, 5, 0, 6, 4, 0, 5, 6, 4, 6, 5};
    CHECK(error_of(two) ==
          "hand: the surface is not a 2-manifold at vertex 0 (0, 0, 0) (a pinched vertex): its "
          "triangles form several fans, one with triangle 0, another with triangle 4");
  }
  SECTION("self-intersection: a vertex pushed through the far side") {
    TriangleSurface dented = ball;
    for (int c = 0; c < 3; ++c) dented.xyz[static_cast<std::size_t>(c)] *= -1.5;
    const std::string e = error_of(dented);
    CHECK(e.find("icosphere: triangle ") == 0);
    CHECK(e.find(" intersect (they meet other than at a shared edge or vertex)") !=
          std::string::npos);
  }
  SECTION("two shells that cross") {
    const TriangleSurface two = merged(box_surface({0, 0, 0}, {1, 1, 1}),
                                       box_surface({0.5, 0.25, 0.25}, {1.5, 0.75, 0.75}));
    CHECK(error_of(two).find(" intersect ") != std::string::npos);
    // Touching: a face of the second box on a face of the first.
    const TriangleSurface touch =
        merged(box_surface({0, 0, 0}, {1, 1, 1}), box_surface({1, 0.25, 0.25}, {2, 0.75, 0.75}));
    CHECK(error_of(touch).find(" intersect ") != std::string::npos);
  }
  SECTION("duplicate triangles") {
    TriangleSurface dup = ball;
    dup.triangles.insert(dup.triangles.end(),
                         {ball.triangles[3], ball.triangles[4], ball.triangles[5]});
    CHECK(error_of(dup) ==
          "icosphere: triangle 1 and triangle 80 are duplicates: both have the vertices " +
              std::to_string(ball.triangles[3]) + " " + std::to_string(ball.triangles[4]) + " " +
              std::to_string(ball.triangles[5]));
  }
  SECTION("zero area, repeated and welded corners, bad indices, non-finite coordinates") {
    TriangleSurface flat = box_surface({0, 0, 0}, {2, 2, 2});
    flat.xyz.insert(flat.xyz.end(), {1, 0, 0});  // vertex 8, the middle of edge 0-1
    flat.triangles.insert(flat.triangles.end(), {0, 8, 1});
    CHECK(error_of(flat) ==
          "box: triangle 12 has zero area: its corners (vertices 0 8 1) are collinear (exact)");
    TriangleSurface rep = box_surface({0, 0, 0}, {1, 1, 1});
    rep.triangles[4] = rep.triangles[3];
    CHECK(error_of(rep) == "box: triangle 1 has a repeated vertex (vertices 0 0 1)");
    TriangleSurface twin = box_surface({0, 0, 0}, {1, 1, 1});
    twin.xyz.insert(twin.xyz.end(), {0, 0, 0});  // vertex 8, a copy of vertex 0
    twin.triangles[4] = 8;                       // triangle 1: (0, 8, 1)
    CHECK(error_of(twin) ==
          "box: triangle 1 has two corners at one point: vertex 0 and vertex 8 have the same "
          "coordinates (0, 0, 0)");
    TriangleSurface bad = box_surface({0, 0, 0}, {1, 1, 1});
    bad.triangles[7] = 11;
    CHECK(error_of(bad) ==
          "box: triangle 2: vertex index 11 is out of range (the surface has 8 vertices)");
    TriangleSurface nan = box_surface({0, 0, 0}, {1, 1, 1});
    nan.xyz[3 * 7] = std::nan("");
    CHECK(error_of(nan) == "box: triangle 2: vertex 7 has a non-finite coordinate (nan, 1, 1)");
  }
  SECTION("inconsistent orientation") {
    TriangleSurface mixed = ball;
    std::swap(mixed.triangles[1], mixed.triangles[2]);
    const std::string e = error_of(mixed);
    CHECK(e.find("icosphere: triangle 0 and triangle ") == 0);
    CHECK(e.find(" in the same direction: the surface is not consistently oriented") !=
          std::string::npos);
  }
}

TEST_CASE("Surface3: duplicates welded; messages name the file's faces and lines", "[clip]") {
  // A vertex given twice (OBJ, PLY and OFF files often do): welded, the surface is valid.
  TriangleSurface twice = icosphere(1);
  const std::uint32_t copy = twice.nb_vertices();
  twice.xyz.insert(twice.xyz.end(), twice.xyz.begin() + 3 * 5, twice.xyz.begin() + 3 * 6);
  std::uint32_t replaced = 0;
  for (std::uint32_t& v : twice.triangles) {
    if (v == 5 && replaced++ % 2 == 0) v = copy;
  }
  REQUIRE(replaced >= 2);
  const Surface3 s(twice);
  require_valid(s);
  CHECK(s.nb_welded_vertices() == 1);
  CHECK(s.nb_vertices() == copy + 1);  // the copy stays, used by no triangle
  for (const std::uint32_t v : s.triangles()) CHECK(v != copy);

  // An OBJ file with a quad (two triangles from face 3) and a duplicate face.
  const voroclip_test::TempDir dir("surface3");
  const std::string path = dir.file("dup.obj");
  std::ofstream(path) << "# a tetrahedron, one face twice\n"
                         "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                         "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\nf 4 3 1\n";
  CHECK(error_of(voroclip::read_surface(path)) ==
        path + ":8: face 3 and face 5 (line 10) are duplicates: both have the vertices 1 4 3");
  const std::string open_path = dir.file("open.obj");
  std::ofstream(open_path) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\n"
                              "f 1 4 3 2\nf 1 2 5\nf 2 3 5\n";
  CHECK(error_of(voroclip::read_surface(open_path)) ==
        open_path +
            ":6: face 1: the surface is not closed: its edge (vertices 1 4) belongs to no other "
            "triangle");
}

TEST_CASE("Surface3: coordinates whose area or volume double cannot hold are an error",
          "[clip][regression]") {
  // A cube scaled by 1e300 was valid with volume and area NaN (clip3d then wrote NaN
  // volumes, exit 0); scaled by 1e-300, valid with volume 0.
  REQUIRE_THROWS_WITH(Surface3(box_surface({0, 0, 0}, {1e300, 1e300, 1e300})),
                      "box: its area and volume are not finite in double precision (coordinates "
                      "up to 1e+300: too large, it overflows); rescale the model (e.g. to a "
                      "size of about 1)");
  REQUIRE_THROWS_WITH(Surface3(box_surface({0, 0, 0}, {1e-300, 1e-300, 1e-300})),
                      "box: its volume is 0 in double precision (coordinates up to 1e-300: too "
                      "small, it underflows); rescale the model (e.g. to a size of about 1)");
  // Within range at both ends: 2^-200 (volume 2^-600) and 2^200 (area 6 2^400).
  for (const double k : {std::ldexp(1.0, -200), std::ldexp(1.0, 200)}) {
    const Surface3 s(box_surface({0, 0, 0}, {k, k, k}));
    CHECK(s.volume() == k * k * k);
    CHECK(s.area() == 6 * k * k);
  }
}
