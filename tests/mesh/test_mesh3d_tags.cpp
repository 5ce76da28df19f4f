// Tests of what mesh3d hands to a solver (voroclip/mesh.h, Mesh3Result): the boundary
// triangles (the faces of exactly one tet, found here by brute force, oriented outward:
// their cones from the origin add up to the mesh's volume), the patch tags (one per face of
// a box, or the file's triangle tags, checked against the face each triangle lies on), the
// region tags (the input tet holding each tet's centroid, by exact orientation tests; one
// region per volume component otherwise), the shape check (check_mesh3_shape), the
// topology refinement (sites added, or an error with VertexCount::kExact), and the NaN of
// sites snapped onto the faces of a cube given as six tets.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "../core/tagged_mesh.h"
#include "mesh3d_pipeline.h"
#include "mesh_test_shapes.h"
#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/mesh.h"
#include "voroclip/predicates.h"

using voroclip::Domain3;
using voroclip::Mesh3Options;
using voroclip::Mesh3Result;
using voroclip::Sign;
using voroclip_test::region_grid;
using voroclip_test::small_options;

namespace {

const std::string kData = VOROCLIP_SHARED_DATA_DIR;

// Two triangles per face of the box [lo, hi], outward, appended to `s`.
void add_box(voroclip::TriangleSurface& s, const double lo[3], const double hi[3],
             bool inward = false) {
  const auto base = static_cast<std::uint32_t>(s.xyz.size() / 3);
  for (std::uint32_t i = 0; i < 8; ++i) {
    s.xyz.insert(s.xyz.end(),
                 {i & 1 ? hi[0] : lo[0], i & 2 ? hi[1] : lo[1], i & 4 ? hi[2] : lo[2]});
  }
  const std::uint32_t t[36] = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                               2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
  for (std::uint32_t k = 0; k < 36; k += 3) {
    s.triangles.insert(s.triangles.end(), {base + t[k], base + t[inward ? k + 2 : k + 1],
                                           base + t[inward ? k + 1 : k + 2]});
  }
}

// det(b - a, c - a, d - a) / 6, in floating point.
double signed_volume(const double* a, const double* b, const double* c, const double* d) {
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double w[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
  return (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
          u[2] * (v[0] * w[1] - v[1] * w[0])) /
         6;
}

// The unit cube and, apart from it, the box [2, 3] x [0, y] x [0, 1]: two shells.
voroclip::TriangleSurface two_boxes(double y) {
  voroclip::TriangleSurface s;
  s.source = "two boxes";
  const double a0[3] = {0, 0, 0}, a1[3] = {1, 1, 1}, b0[3] = {2, 0, 0}, b1[3] = {3, y, 1};
  add_box(s, a0, a1);
  add_box(s, b0, b1);
  return s;
}

// The box [lo, hi] alone, named `source`.
Domain3 box_domain(const char* source, const double lo[3], const double hi[3]) {
  voroclip::TriangleSurface s;
  s.source = source;
  add_box(s, lo, hi);
  return Domain3(s);
}

const double* point(const Mesh3Result& r, std::uint32_t v) { return &r.xyz[3 * std::size_t{v}]; }

// The faces of exactly one tet, by brute force over sorted vertex triples.
std::multiset<std::array<std::uint32_t, 3>> single_faces(const Mesh3Result& r) {
  std::map<std::array<std::uint32_t, 3>, int> count;
  for (std::size_t t = 0; t < r.tets.size(); t += 4) {
    for (int f = 0; f < 4; ++f) {
      std::array<std::uint32_t, 3> k;
      for (int j = 0, m = 0; j < 4; ++j) {
        if (j != f) k[m++] = r.tets[t + j];
      }
      std::sort(k.begin(), k.end());
      ++count[k];
    }
  }
  std::multiset<std::array<std::uint32_t, 3>> once;
  for (const auto& [k, c] : count) {
    if (c == 1) once.insert(k);
  }
  return once;
}

// Boundary triangles: the brute-force faces, each once, oriented outward.
void check_boundary(const Mesh3Result& r) {
  REQUIRE(r.boundary_triangles.size() % 3 == 0);
  REQUIRE(r.boundary_tags.size() == r.boundary_triangles.size() / 3);
  REQUIRE(r.tet_tags.size() == r.tets.size() / 4);
  // Grouped by patch tag, increasing (one block per patch in a file).
  CHECK(std::is_sorted(r.boundary_tags.begin(), r.boundary_tags.end()));
  std::multiset<std::array<std::uint32_t, 3>> got;
  double cones = 0, volume = 0;
  const double o[3] = {0, 0, 0};
  for (std::size_t b = 0; b < r.boundary_triangles.size(); b += 3) {
    std::array<std::uint32_t, 3> k = {r.boundary_triangles[b], r.boundary_triangles[b + 1],
                                      r.boundary_triangles[b + 2]};
    cones += signed_volume(o, point(r, k[0]), point(r, k[1]), point(r, k[2]));
    std::sort(k.begin(), k.end());
    got.insert(k);
  }
  CHECK(got == single_faces(r));
  for (std::size_t t = 0; t < r.tets.size(); t += 4) {
    volume += signed_volume(point(r, r.tets[t]), point(r, r.tets[t + 1]), point(r, r.tets[t + 2]),
                            point(r, r.tets[t + 3]));
  }
  CHECK(volume > 0);
  CHECK(cones == Approx(volume).epsilon(1e-9));
}

// Face-connected components of the tets: per tet, its component's smallest tet.
std::vector<std::uint32_t> components(const Mesh3Result& r) {
  const auto nt = static_cast<std::uint32_t>(r.tets.size() / 4);
  std::vector<std::uint32_t> parent(nt);
  for (std::uint32_t t = 0; t < nt; ++t) parent[t] = t;
  const auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::map<std::array<std::uint32_t, 3>, std::uint32_t> first;
  for (std::uint32_t t = 0; t < nt; ++t) {
    for (int f = 0; f < 4; ++f) {
      std::array<std::uint32_t, 3> k;
      for (int j = 0, m = 0; j < 4; ++j) {
        if (j != f) k[m++] = r.tets[4 * std::size_t{t} + j];
      }
      std::sort(k.begin(), k.end());
      const auto [it, fresh] = first.emplace(k, t);
      if (!fresh) {
        const std::uint32_t a = find(it->second), b = find(t);
        parent[std::max(a, b)] = std::min(a, b);
      }
    }
  }
  std::vector<std::uint32_t> c(nt);
  for (std::uint32_t t = 0; t < nt; ++t) c[t] = find(t);
  return c;
}

// The axis (0, 1, 2) and side (0: lo, 1: hi) of the box face a triangle lies on, from its
// centroid's distance to the face planes (snapped vertices are on them up to rounding).
int box_face(const Mesh3Result& r, const std::uint32_t* tri, const double lo[3],
             const double hi[3]) {
  int face = -1;
  for (int k = 0; k < 3; ++k) {
    const double c = (point(r, tri[0])[k] + point(r, tri[1])[k] + point(r, tri[2])[k]) / 3;
    const double tol = 1e-9 * (hi[k] - lo[k]);
    if (std::abs(c - lo[k]) <= tol) face = face < 0 ? 2 * k : 99;
    if (std::abs(c - hi[k]) <= tol) face = face < 0 ? 2 * k + 1 : 99;
  }
  return face;
}

}  // namespace

TEST_CASE("mesh3d tags a box's six faces as six patches, one region", "[mesh]") {
  voroclip::TriangleSurface s;
  s.source = "box";
  const double lo[3] = {0, 0, 0}, hi[3] = {2, 3, 1};
  add_box(s, lo, hi);
  const Mesh3Result r = voroclip::mesh3d(Domain3(s), small_options(400));
  CHECK(r.shape_problem.empty());
  check_boundary(r);
  // Each face's triangles carry one tag, and different faces different tags.
  std::map<int, std::set<std::int32_t>> tags_of_face;
  std::map<std::int32_t, std::set<int>> faces_of_tag;
  for (std::size_t b = 0; b < r.boundary_tags.size(); ++b) {
    const int f = box_face(r, &r.boundary_triangles[3 * b], lo, hi);
    REQUIRE(f >= 0);
    REQUIRE(f < 6);
    tags_of_face[f].insert(r.boundary_tags[b]);
    faces_of_tag[r.boundary_tags[b]].insert(f);
  }
  CHECK(tags_of_face.size() == 6);
  CHECK(faces_of_tag.size() == 6);
  for (const auto& [f, tags] : tags_of_face) CHECK(tags.size() == 1);
  for (const auto& [t, faces] : faces_of_tag) {
    CHECK(faces.size() == 1);
    CHECK(t >= 1);
    CHECK(t <= 6);
  }
  CHECK(std::all_of(r.tet_tags.begin(), r.tet_tags.end(), [](std::int32_t t) { return t == 1; }));
  // A surface has no tag names: every group gets one ("patch <tag>", "region <tag>").
  using Name = voroclip::TetMeshInput::TagName;
  const std::vector<Name> names = {{2, 1, "patch 1"}, {2, 2, "patch 2"}, {2, 3, "patch 3"},
                                   {2, 4, "patch 4"}, {2, 5, "patch 5"}, {2, 6, "patch 6"},
                                   {3, 1, "region 1"}};
  CHECK(r.tag_names == names);
  CHECK(r.nb_input_regions == 0);
  CHECK(r.nb_tets_across_regions == 0);
}

TEST_CASE("mesh3d keeps a tet mesh's region and boundary tags", "[mesh][exact]") {
  // The tagged Kuhn cube: six tets in two interleaved regions (1, 2); its faces tagged by
  // axis (x 10, y 11, z 12); tag names.
  const voroclip::TetMeshInput in = voroclip_test::tagged_kuhn_cube();
  const Domain3 d(in);
  Mesh3Options o = small_options(500);
  const Mesh3Result r = voroclip::mesh3d(d, o);
  CHECK(r.shape_problem.empty());
  check_boundary(r);
  // The input's names, then one for its unnamed y faces (tag 11).
  std::vector<voroclip::TetMeshInput::TagName> names = in.tag_names;
  names.push_back({2, 11, "patch 11"});
  CHECK(r.tag_names == names);
  const double lo[3] = {1.0 / 3, 1.0 / 3, 1.0 / 3};
  const double hi[3] = {0.1 + 1.0 / 3, 0.1 + 1.0 / 3, 0.1 + 1.0 / 3};
  std::set<std::int32_t> seen;
  for (std::size_t b = 0; b < r.boundary_tags.size(); ++b) {
    const int f = box_face(r, &r.boundary_triangles[3 * b], lo, hi);
    REQUIRE(f >= 0);
    REQUIRE(f < 6);
    CHECK(r.boundary_tags[b] == 10 + f / 2);
    seen.insert(r.boundary_tags[b]);
  }
  CHECK(seen == std::set<std::int32_t>{10, 11, 12});
  // Each tet's region: the input tet that holds its centroid (strictly, or on a face of
  // two tets of the same region), by exact orientation tests.
  // The tags of the input tets (closed) that hold c.
  const auto holders_of = [&in](const double* c) {
    std::set<std::int32_t> holders;
    for (std::size_t u = 0; u < in.tets.size(); u += 4) {
      const double* p[4];
      for (int j = 0; j < 4; ++j) p[j] = &in.xyz[3 * std::size_t{in.tets[u + j]}];
      const Sign whole = voroclip::orient3d(p[0], p[1], p[2], p[3]);
      bool inside = true;
      for (int j = 0; j < 4 && inside; ++j) {
        const double* q[4] = {p[0], p[1], p[2], p[3]};
        q[j] = c;
        const Sign s = voroclip::orient3d(q[0], q[1], q[2], q[3]);
        inside = s == whole || s == Sign::zero;
      }
      if (inside) holders.insert(in.tet_ref[u / 4]);
    }
    return holders;
  };
  std::size_t checked = 0;
  std::uint32_t across = 0;  // tets with a vertex in the input but not in their region
  std::set<std::int32_t> regions;
  for (std::size_t t = 0; t < r.tets.size(); t += 4) {
    double c[3] = {0, 0, 0};
    for (int j = 0; j < 4; ++j) {
      for (int k = 0; k < 3; ++k) c[k] += point(r, r.tets[t + j])[k] / 4;
    }
    const std::set<std::int32_t> holders = holders_of(c);
    bool crosses = false;
    for (int j = 0; j < 4; ++j) {
      const std::set<std::int32_t> h = holders_of(point(r, r.tets[t + j]));
      crosses = crosses || (!h.empty() && h.count(r.tet_tags[t / 4]) == 0);
    }
    across += crosses ? 1 : 0;
    if (holders.size() == 1) {
      CHECK(r.tet_tags[t / 4] == *holders.begin());
      ++checked;
    }
    regions.insert(r.tet_tags[t / 4]);
  }
  CHECK(checked * 10 > r.tets.size() / 4 * 9);
  CHECK(regions == std::set<std::int32_t>{1, 2});
  // The cube's two regions are interleaved, their tets meeting along edges only: no region is
  // a volume of its own, so the interfaces are not followed (the sites follow the boundary
  // only), and mesh3d counts the tets across them, as this brute force does.
  CHECK(r.nb_input_regions == 2);
  CHECK(r.nb_interfaces_followed == 0);
  CHECK(r.interfaces_not_followed.find("meet along an edge only") != std::string::npos);
  CHECK(across > 0);
  CHECK(r.nb_tets_across_regions == across);
}

TEST_CASE("mesh3d gives the input's untagged boundary and regions fresh positive tags",
          "[mesh][regression]") {
  // Trial 04: a Gmsh box whose physical surfaces are its inlet and outlet only (the walls'
  // triangles, untagged, are not even in the file) meshed fully, then failed writing .msh
  // ("physical tags are positive"); .mesh gave the walls tag 0, and tets of ref 0 or -3 kept
  // those. Here the Kuhn cube with its x faces tagged 10 and its y and z faces untagged (0),
  // its tets of refs 0 and -3, and names taking tags 1 and 2 in both dimensions.
  voroclip::TetMeshInput in = voroclip_test::tagged_kuhn_cube();
  in.triangle_ref = {10, 10, 0, 0, 0, 0, 10, 10, 0, 0, 0, 0};
  in.tet_ref = {0, -3, 0, -3, -3, 0};
  in.tag_names = {{3, 1, "steel"}, {3, 2, "copper"}, {2, 2, "unused"}, {2, 10, "x faces"}};
  const Domain3 d(in);
  const Mesh3Result r = voroclip::mesh3d(d, small_options(300));
  CHECK(r.shape_problem.empty());
  check_boundary(r);
  // The untagged boundary: the smallest positive triangle tag the input does not use (1);
  // the regions: 0 the smallest free region tag (3), -3 the next (4).
  const double lo[3] = {1.0 / 3, 1.0 / 3, 1.0 / 3};
  const double hi[3] = {0.1 + 1.0 / 3, 0.1 + 1.0 / 3, 0.1 + 1.0 / 3};
  std::map<std::int32_t, std::size_t> patch_count;
  for (std::size_t b = 0; b < r.boundary_tags.size(); ++b) {
    const int f = box_face(r, &r.boundary_triangles[3 * b], lo, hi);
    REQUIRE(f >= 0);
    REQUIRE(f < 6);
    CHECK(r.boundary_tags[b] == (f / 2 == 0 ? 10 : 1));  // box_face: x faces 0, 1
    ++patch_count[r.boundary_tags[b]];
  }
  CHECK(patch_count.size() == 2);
  CHECK(patch_count[1] > 0);
  CHECK(patch_count[10] > 0);
  const std::set<std::int32_t> regions(r.tet_tags.begin(), r.tet_tags.end());
  CHECK(regions == std::set<std::int32_t>{3, 4});
  // The input's names of tags no element has are not kept (a Gmsh group without elements).
  std::vector<voroclip::TetMeshInput::TagName> names = {in.tag_names[3]};
  names.push_back({2, 1, "untagged boundary"});
  names.push_back({3, 3, "untagged region"});
  names.push_back({3, 4, "region tagged -3"});
  CHECK(r.tag_names == names);
  // The same tags in every format, read back (Gmsh wrote none of them before).
  voroclip::TetMeshInput out;
  out.xyz = r.xyz;
  out.tets = r.tets;
  out.tet_ref = r.tet_tags;
  out.triangles = r.boundary_triangles;
  out.triangle_ref = r.boundary_tags;
  out.tag_names = r.tag_names;
  const voroclip_test::TempDir dir("mesh3d_untagged");
  const std::pair<const char*, voroclip::TetMeshFormat> formats[] = {
      {"out.msh", voroclip::TetMeshFormat::kGmsh41},
      {"out22.msh", voroclip::TetMeshFormat::kGmsh22},
      {"out.mesh", voroclip::TetMeshFormat::kMedit},
      {"out.vtu", voroclip::TetMeshFormat::kVtu}};
  for (const auto& [name, format] : formats) {
    INFO(name);
    const std::string path = dir.file(name);
    REQUIRE_NOTHROW(voroclip::write_tet_mesh(path, out, format));
    const voroclip::TetMeshInput back = voroclip::read_tet_mesh(path);
    CHECK(back.triangle_ref == r.boundary_tags);
    CHECK(back.tet_ref == r.tet_tags);
    if (format == voroclip::TetMeshFormat::kGmsh41 || format == voroclip::TetMeshFormat::kGmsh22)
      CHECK(back.tag_names == names);
  }
  // Tets all of ref 0: region 1, as a file without tet tags gets.
  in.tet_ref.assign(6, 0);
  in.tag_names.clear();
  const Mesh3Result all_zero = voroclip::mesh3d(Domain3(in), small_options(300));
  CHECK(std::set<std::int32_t>(all_zero.tet_tags.begin(), all_zero.tet_tags.end()) ==
        std::set<std::int32_t>{1});
  CHECK(std::all_of(all_zero.boundary_tags.begin(), all_zero.boundary_tags.end(),
                    [](std::int32_t t) { return t == 1 || t == 10; }));
}

TEST_CASE("mesh3d names no tag that no element of the mesh has", "[mesh][regression]") {
  // Trial 10: an embedded surface tagged 9, "sensor", inside the volume is not kept, and the
  // output .msh listed '2 9 "sensor"' in $PhysicalNames with no element. Here names of a
  // triangle tag and a tet tag the input does not use, and of a curve.
  voroclip::TetMeshInput in = voroclip_test::tagged_kuhn_cube();
  const std::vector<voroclip::TetMeshInput::TagName> used = in.tag_names;
  in.tag_names.push_back({2, 9, "sensor"});
  in.tag_names.push_back({3, 7, "air"});
  in.tag_names.push_back({1, 10, "edge"});
  const Mesh3Result r = voroclip::mesh3d(Domain3(in), small_options(300));
  std::vector<voroclip::TetMeshInput::TagName> names = used;
  names.push_back({2, 11, "patch 11"});
  CHECK(r.tag_names == names);
}

TEST_CASE("mesh3d lists the embedded surfaces it does not follow", "[mesh][regression]") {
  // Trial 10 again: the sensor's triangles, inside the volume with one region on both sides,
  // were dropped without a word. Here the Kuhn cube with two inner triangles tagged: (0, 1, 7)
  // between tets 0 and 2, both region 1 (embedded, tag 8, no name), and (0, 3, 7) between
  // tets 0 and 1, regions 1 and 2 (an interface, tag 9, not embedded).
  voroclip::TetMeshInput in = voroclip_test::tagged_kuhn_cube();
  in.triangles.insert(in.triangles.end(), {0, 1, 7, 7, 3, 0});
  in.triangle_ref.insert(in.triangle_ref.end(), {8, 9});
  in.tag_names.push_back({2, 9, "glue"});
  const Mesh3Result r = voroclip::mesh3d(Domain3(in), small_options(300));
  using E = Mesh3Result::EmbeddedTag;
  CHECK(r.embedded_tags_dropped == std::vector<E>{{8, "", 1}});
  // One region: both are embedded, named as the file names them.
  in.tet_ref.assign(6, 1);
  in.tag_names.push_back({2, 8, "sensor"});
  const Mesh3Result one = voroclip::mesh3d(Domain3(in), small_options(300));
  CHECK(one.embedded_tags_dropped == std::vector<E>{{8, "sensor", 1}, {9, "glue", 1}});
  CHECK(std::find(one.boundary_tags.begin(), one.boundary_tags.end(), 8) ==
        one.boundary_tags.end());
  // Without tet tags too; none without inner triangles.
  in.tet_ref.clear();
  CHECK(voroclip::mesh3d(Domain3(in), small_options(300)).embedded_tags_dropped.size() == 2);
  CHECK(voroclip::mesh3d(Domain3(voroclip_test::tagged_kuhn_cube()), small_options(300))
            .embedded_tags_dropped.empty());
}

// The unit cube as a grid of n^3 voxels, six Kuhn tets each (around the diagonal of the
// voxel), region 2 for the voxels with every index in [lo, hi), region 1 elsewhere: an
// inclusion, the box [lo / n, hi / n]^3, whose interface meets neither the boundary nor
// another interface when 0 < lo < hi < n. The boundary triangles tagged by the face they lie
// on (10 + axis, 13 + axis on the far side) when `tag_faces`.
voroclip::TetMeshInput inclusion_grid(std::uint32_t n, std::uint32_t lo, std::uint32_t hi,
                                      bool tag_faces) {
  voroclip::TetMeshInput m = region_grid(n, [&](std::uint32_t i, std::uint32_t j, std::uint32_t k) {
    return i >= lo && i < hi && j >= lo && j < hi && k >= lo && k < hi ? 2 : 1;
  });
  if (tag_faces) {
    const Domain3 d(m);
    const voroclip::Surface3& s = d.surface();
    for (std::uint32_t t = 0; t < s.nb_triangles(); ++t) {
      double c[3] = {0, 0, 0};
      for (int q = 0; q < 3; ++q) {
        for (int a = 0; a < 3; ++a) c[a] += s.vertex(s.triangle_vertex(t, q))[a] / 3;
      }
      int tag = 0;
      for (int a = 0; a < 3; ++a) {
        if (c[a] < 1e-9) tag = 10 + a;
        if (c[a] > 1 - 1e-9) tag = 13 + a;
      }
      m.triangles.insert(m.triangles.end(), s.triangle(t), s.triangle(t) + 3);
      m.triangle_ref.push_back(tag);
    }
  }
  return m;
}

// Region 2's tets have their vertices in the box [lo, hi] (closed), the others none strictly
// inside it (a vertex on an interface is projected onto it: within 1e-12); region 2's volume.
double region2_in_box(const Mesh3Result& r, const std::array<double, 3>& lo,
                      const std::array<double, 3>& hi) {
  const double eps = 1e-12;
  double volume = 0;
  for (std::size_t t = 0; t < r.tets.size(); t += 4) {
    for (int j = 0; j < 4; ++j) {
      const double* p = point(r, r.tets[t + j]);
      bool closed = true, open = true;
      for (int a = 0; a < 3; ++a) {
        closed = closed && p[a] >= lo[a] - eps && p[a] <= hi[a] + eps;
        open = open && p[a] > lo[a] + eps && p[a] < hi[a] - eps;
      }
      if (r.tet_tags[t / 4] == 2) {
        CHECK(closed);
      } else {
        CHECK_FALSE(open);
      }
    }
    if (r.tet_tags[t / 4] == 2) {
      volume += signed_volume(point(r, r.tets[t]), point(r, r.tets[t + 1]), point(r, r.tets[t + 2]),
                              point(r, r.tets[t + 3]));
    }
  }
  return volume;
}

TEST_CASE("mesh3d follows the interface around an inclusion", "[mesh][threads]") {
  // The inclusion [1/3, 2/3]^3 in the unit cube, regions 2 and 1.
  const voroclip::TetMeshInput in = inclusion_grid(9, 3, 6, true);
  const Domain3 d(in);
  const Mesh3Result r =
      voroclip_test::check_same_mesh3d_with_1_and_2_threads(d, small_options(2000));
  CHECK(r.shape_problem.empty());
  check_boundary(r);
  CHECK(r.nb_input_regions == 2);
  CHECK(r.nb_interfaces_followed == 1);
  CHECK(r.interfaces_not_followed.empty());
  CHECK(r.nb_tets_across_regions == 0);
  CHECK(r.interface_distance_to_edge_length > 0);
  CHECK(r.interface_distance_to_edge_length <= 1);
  // The boundary keeps the faces' tags; the interface adds none.
  std::set<std::int32_t> patch_tags(r.boundary_tags.begin(), r.boundary_tags.end());
  CHECK(patch_tags == std::set<std::int32_t>{10, 11, 12, 13, 14, 15});
  // Each tet on its side of the box [a, b]^3, by its vertices (a vertex on the interface is
  // projected onto it: within 1e-12).
  const double a = 3.0 / 9, b = 6.0 / 9, eps = 1e-12;
  const auto inside = [&](const double* p, double margin) {
    return p[0] > a + margin && p[0] < b - margin && p[1] > a + margin && p[1] < b - margin &&
           p[2] > a + margin && p[2] < b - margin;
  };
  double volume[3] = {0, 0, 0};
  std::size_t tets_in_2 = 0;
  for (std::size_t t = 0; t < r.tets.size(); t += 4) {
    const std::int32_t tag = r.tet_tags[t / 4];
    REQUIRE((tag == 1 || tag == 2));
    for (int j = 0; j < 4; ++j) {
      const double* p = point(r, r.tets[t + j]);
      if (tag == 2) {
        CHECK(inside(p, -eps));
      } else {
        CHECK_FALSE(inside(p, eps));
      }
    }
    volume[tag] += signed_volume(point(r, r.tets[t]), point(r, r.tets[t + 1]),
                                 point(r, r.tets[t + 2]), point(r, r.tets[t + 3]));
    tets_in_2 += tag == 2 ? 1 : 0;
  }
  CHECK(tets_in_2 > 100);
  // The volumes: the cube's whole; the inclusion's up to the chamfers at its edges.
  CHECK(volume[1] + volume[2] == Approx(1).epsilon(1e-9));
  CHECK(volume[2] == Approx(1.0 / 27).epsilon(0.03));
  // The interface (the faces between the two regions) lies on the box's surface, and the
  // inclusion's tets make one closed volume of genus 0 around it.
  std::map<std::array<std::uint32_t, 3>, std::set<std::int32_t>> face_tags;
  voroclip::TetMeshInput inner;
  inner.source = "region 2";
  inner.xyz = r.xyz;
  for (std::size_t t = 0; t < r.tets.size(); t += 4) {
    for (int f = 0; f < 4; ++f) {
      std::array<std::uint32_t, 3> key{};
      std::size_t k = 0;
      for (int j = 0; j < 4; ++j) {
        if (j != f) key[k++] = r.tets[t + j];
      }
      std::sort(key.begin(), key.end());
      face_tags[key].insert(r.tet_tags[t / 4]);
    }
    if (r.tet_tags[t / 4] == 2) inner.tets.insert(inner.tets.end(), &r.tets[t], &r.tets[t] + 4);
  }
  std::size_t interface_faces = 0;
  for (const auto& [key, tags] : face_tags) {
    if (tags.size() < 2) continue;
    ++interface_faces;
    for (const std::uint32_t v : key) {
      const double* p = point(r, v);
      CHECK(inside(p, -eps));
      CHECK_FALSE(inside(p, eps));
    }
  }
  CHECK(interface_faces > 50);
  // They are the output's interface triangles, one tag after the boundary's (10 .. 15),
  // named by the regions on their sides, oriented outward from region 1: their cones from
  // the box's centre make minus region 2's volume.
  REQUIRE(r.interface_triangles.size() == 3 * interface_faces);
  CHECK(std::all_of(r.interface_tags.begin(), r.interface_tags.end(),
                    [](std::int32_t t) { return t == 16; }));
  CHECK(std::count(r.tag_names.begin(), r.tag_names.end(),
                   voroclip::TetMeshInput::TagName{2, 16, "interface 1-2"}) == 1);
  const double centre[3] = {0.5, 0.5, 0.5};
  double cones = 0;
  for (std::size_t i = 0; i < r.interface_triangles.size(); i += 3) {
    std::array<std::uint32_t, 3> key = {r.interface_triangles[i], r.interface_triangles[i + 1],
                                        r.interface_triangles[i + 2]};
    cones += signed_volume(centre, point(r, key[0]), point(r, key[1]), point(r, key[2]));
    std::sort(key.begin(), key.end());
    CHECK(face_tags[key].size() == 2);
  }
  CHECK(cones == Approx(-volume[2]).epsilon(1e-9));
  const Domain3 region2(inner);
  REQUIRE(region2.surface().shells().size() == 1);
  CHECK(region2.surface().shells()[0].genus == 0);
  CHECK(region2.volume() == Approx(volume[2]).epsilon(1e-9));
}

TEST_CASE("mesh3d keeps the file's tags of an interface's triangles", "[mesh]") {
  // The inclusion of the test above, its interface's triangles listed with tags: 42 on the
  // side x < 1/2, 43 on the rest; the name of 43 given.
  voroclip::TetMeshInput in = inclusion_grid(6, 2, 4, false);
  {
    const Domain3 d(in);
    for (std::uint32_t t = 0; t < d.nb_tets(); ++t) {
      for (int f = 0; f < 4; ++f) {
        const std::uint32_t u = d.tet_adjacent(t, f);
        if (u == Domain3::kNone || u < t || in.tet_ref[t] == in.tet_ref[u]) continue;
        double x = 0;
        for (int k = 0; k < 3; ++k) {
          const std::uint32_t v = d.tet_vertex(t, Domain3::kTetFacetVertex[f][k]);
          in.triangles.push_back(v);
          x += d.vertex(v)[0] / 3;
        }
        in.triangle_ref.push_back(x < 0.5 ? 42 : 43);
      }
    }
  }
  in.tag_names = {{2, 43, "right half"}};
  const Domain3 d(in);
  CHECK(d.boundary_refs().empty());
  const Mesh3Result r = voroclip::mesh3d(d, small_options(1500));
  CHECK(r.shape_problem.empty());
  CHECK(r.nb_interfaces_followed == 1);
  REQUIRE(!r.interface_tags.empty());
  // Each interface triangle keeps the tag of the side it lies on (away from the border x = 1/2).
  std::size_t far = 0;
  for (std::size_t i = 0; i < r.interface_tags.size(); ++i) {
    double lo = 1, hi = 0;
    for (int k = 0; k < 3; ++k) {
      const double x = point(r, r.interface_triangles[3 * i + static_cast<std::size_t>(k)])[0];
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
    if (hi < 0.45) {
      CHECK(r.interface_tags[i] == 42);
      ++far;
    } else if (lo > 0.55) {
      CHECK(r.interface_tags[i] == 43);
      ++far;
    }
  }
  CHECK(far * 2 > r.interface_tags.size());
  using Name = voroclip::TetMeshInput::TagName;
  CHECK(std::count(r.tag_names.begin(), r.tag_names.end(), Name{2, 42, "interface 1-2"}) == 1);
  CHECK(std::count(r.tag_names.begin(), r.tag_names.end(), Name{2, 43, "right half"}) == 1);
  // The boundary, untagged in the file: its patches between the feature lines (1 .. 6).
  const std::set<std::int32_t> patches(r.boundary_tags.begin(), r.boundary_tags.end());
  CHECK(patches == std::set<std::int32_t>{1, 2, 3, 4, 5, 6});
}

TEST_CASE("mesh3d follows interfaces that meet the boundary", "[mesh]") {
  // The box [0, 1/2]^3 at a corner of the unit cube, region 2: its interface meets three
  // faces of the cube along lines where the boundary is flat on both sides.
  const Domain3 d(inclusion_grid(6, 0, 3, false));
  const Mesh3Result r = voroclip::mesh3d(d, small_options(1500));
  CHECK(r.shape_problem.empty());
  CHECK(r.nb_interfaces_followed == 1);
  CHECK(r.nb_tets_across_regions == 0);
  CHECK(region2_in_box(r, {0, 0, 0}, {0.5, 0.5, 0.5}) == Approx(0.125).epsilon(0.01));
}

TEST_CASE("mesh3d follows three regions that meet along a line", "[mesh]") {
  // Region 1 below z = 1/2, 2 above it with x < 1/2, 3 above it with x > 1/2: three
  // interfaces, meeting along the line x = z = 1/2, each meeting the boundary.
  const Domain3 d(region_grid(4, [](std::uint32_t i, std::uint32_t, std::uint32_t k) {
    return k < 2 ? 1 : i < 2 ? 2 : 3;
  }));
  const Mesh3Result r = voroclip::mesh3d(d, small_options(1500));
  CHECK(r.shape_problem.empty());
  CHECK(r.nb_input_regions == 3);
  CHECK(r.nb_interfaces_followed == 3);
  CHECK(r.nb_tets_across_regions == 0);
  // Each tet in its region's box (vertices on an interface projected onto it: 1e-12).
  const double eps = 1e-12;
  double volume[4] = {0, 0, 0, 0};
  for (std::size_t t = 0; t < r.tets.size(); t += 4) {
    const std::int32_t tag = r.tet_tags[t / 4];
    REQUIRE((tag >= 1 && tag <= 3));
    for (int j = 0; j < 4; ++j) {
      const double* p = point(r, r.tets[t + j]);
      CHECK((tag == 1 ? p[2] <= 0.5 + eps : p[2] >= 0.5 - eps));
      if (tag == 2) CHECK(p[0] <= 0.5 + eps);
      if (tag == 3) CHECK(p[0] >= 0.5 - eps);
    }
    volume[tag] += signed_volume(point(r, r.tets[t]), point(r, r.tets[t + 1]),
                                 point(r, r.tets[t + 2]), point(r, r.tets[t + 3]));
  }
  CHECK(volume[1] == Approx(0.5).epsilon(1e-9));
  CHECK(volume[2] == Approx(0.25).epsilon(1e-9));
  CHECK(volume[3] == Approx(0.25).epsilon(1e-9));
  // Three interface tags after the boundary's, named by their regions.
  std::set<std::int32_t> tags(r.interface_tags.begin(), r.interface_tags.end());
  CHECK(tags.size() == 3);
  using Name = voroclip::TetMeshInput::TagName;
  for (const char* name : {"interface 1-2", "interface 1-3", "interface 2-3"}) {
    CHECK(std::count_if(r.tag_names.begin(), r.tag_names.end(), [&](const Name& n) {
            return n.dimension == 2 && n.name == name && tags.count(n.tag) == 1;
          }) == 1);
  }
}

namespace {
// mesh3d of region 2, the plate [8/25, 17/25]^2 x [12/25, 13/25] (0.04 thick), in the unit
// cube, and the facts every mesh of it must have: the right shape, the interface followed
// (no tet across it), the plate's volume.
Mesh3Result mesh_plate(const Mesh3Options& o) {
  const Domain3 d(region_grid(25, [](std::uint32_t i, std::uint32_t j, std::uint32_t k) {
    return i >= 8 && i < 17 && j >= 8 && j < 17 && k == 12 ? 2 : 1;
  }));
  const Mesh3Result r = voroclip::mesh3d(d, o);
  CHECK(r.shape_problem.empty());
  CHECK(r.nb_interfaces_followed == 1);
  CHECK(r.nb_tets_across_regions == 0);
  CHECK(region2_in_box(r, {0.32, 0.32, 0.48}, {0.68, 0.68, 0.52}) ==
        Approx(0.36 * 0.36 * 0.04).epsilon(0.05));
  return r;
}
}  // namespace

TEST_CASE("mesh3d follows a plate region thinner than the spacing", "[mesh][regression]") {
  // Region 2: the plate [8/25, 17/25]^2 x [12/25, 13/25] (0.04 thick) in the unit cube, at
  // 2000 vertices (spacing about 0.08): the topology refinement adds sites on it, and the
  // flips insert a vertex (whose surface patches, none, tag_mesh3 reads: before, past the
  // end of the patches' table, which threw at random).
  Mesh3Options o;
  o.nb_vertices = 2000;
  const Mesh3Result r = mesh_plate(o);
  CHECK(r.nb_topology_sites > 0);
}

TEST_CASE("mesh3d's lfs cap sizes a region thinner than the spacing by its own thickness",
          "[mesh]") {
  // The plate of the case above: its thickness (0.04, half of the spacing) is the local
  // feature size of region 2, whose interfaces now seed the field as the boundary does. With
  // lfs_cap 1 the cap binds around the plate, and its tets are smaller than the rest.
  Mesh3Options o = small_options(1500);
  o.lfs_cap = 1;
  const Mesh3Result r = mesh_plate(o);
  CHECK(r.lfs_capped_fraction > 0.03);
  // Mean edge length of each region's tets.
  double sum[3] = {0, 0, 0}, count[3] = {0, 0, 0};
  for (std::size_t t = 0; t < r.tet_tags.size(); ++t) {
    const auto tag = static_cast<std::size_t>(r.tet_tags[t]);
    REQUIRE((tag == 1 || tag == 2));
    for (int a = 0; a < 4; ++a) {
      for (int b = a + 1; b < 4; ++b) {
        const double* p = point(r, r.tets[4 * t + a]);
        const double* q = point(r, r.tets[4 * t + b]);
        sum[tag] += std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                              (p[2] - q[2]) * (p[2] - q[2]));
        count[tag] += 1;
      }
    }
  }
  // 0.41 here; 0.51 when the field was the outer boundary's only (session 36).
  INFO("mean edge: region 1 " << sum[1] / count[1] << ", region 2 " << sum[2] / count[2]);
  CHECK(sum[2] / count[2] < 0.45 * sum[1] / count[1]);
}

TEST_CASE("mesh3d does not follow a region that is no volume on its own, and says why", "[mesh]") {
  // Region 2: two voxels that share an edge only.
  const Domain3 d(region_grid(2, [](std::uint32_t i, std::uint32_t j, std::uint32_t k) {
    return k == 0 && i == j ? 2 : 1;
  }));
  const Mesh3Result r = voroclip::mesh3d(d, small_options(500));
  CHECK(r.nb_input_regions == 2);
  CHECK(r.nb_interfaces_followed == 0);
  CHECK(r.interfaces_not_followed.find("meet along an edge only") != std::string::npos);
  CHECK(r.nb_tets_across_regions > 0);
}

TEST_CASE("mesh3d: one region per volume component; a cavity is no region", "[mesh]") {
  // Two boxes apart: two components, tagged 1 and 2 in the order of their shells.
  const Domain3 d2(two_boxes(1.5));
  const Mesh3Result r = voroclip::mesh3d(d2, small_options(500));
  CHECK(r.shape_problem.empty());
  check_boundary(r);
  const std::vector<std::uint32_t> comp = components(r);
  std::map<std::uint32_t, std::set<std::int32_t>> tags;
  for (std::size_t t = 0; t < comp.size(); ++t) tags[comp[t]].insert(r.tet_tags[t]);
  REQUIRE(tags.size() == 2);
  std::set<std::int32_t> all;
  for (const auto& [c, ts] : tags) {
    CHECK(ts.size() == 1);
    all.insert(*ts.begin());
  }
  CHECK(all == std::set<std::int32_t>{1, 2});
  // The component left of x = 1.5 is the first shell's: tag 1.
  for (std::size_t t = 0; t < comp.size(); ++t) {
    const double x = point(r, r.tets[4 * t])[0];
    CHECK(r.tet_tags[t] == (x < 1.5 ? 1 : 2));
  }

  // A box with a box-shaped cavity: one component, one region; two boundary shells.
  voroclip::TriangleSurface hollow;
  hollow.source = "hollow box";
  const double o0[3] = {0, 0, 0}, o1[3] = {3, 3, 3}, i0[3] = {1, 1, 1}, i1[3] = {2, 2, 2};
  add_box(hollow, o0, o1);
  add_box(hollow, i0, i1, true);
  const Mesh3Result h = voroclip::mesh3d(Domain3(hollow), small_options(800));
  CHECK(h.shape_problem.empty());
  check_boundary(h);
  CHECK(std::all_of(h.tet_tags.begin(), h.tet_tags.end(), [](std::int32_t t) { return t == 1; }));
  // Twelve faces: twelve patch tags.
  CHECK(std::set<std::int32_t>(h.boundary_tags.begin(), h.boundary_tags.end()).size() == 12);
}

TEST_CASE("check_mesh3_shape names a missing shell and a stray tet", "[mesh]") {
  const Domain3 d(two_boxes(1));
  // One Kuhn cube (6 tets) per box.
  const auto kuhn = [](std::vector<double>& xyz, std::vector<std::uint32_t>& tets, double x0) {
    const auto base = static_cast<std::uint32_t>(xyz.size() / 3);
    for (std::uint32_t v = 0; v < 8; ++v) {
      xyz.insert(xyz.end(), {x0 + (v & 1), double((v >> 1) & 1), double((v >> 2) & 1)});
    }
    const std::uint32_t t[24] = {0, 1, 3, 7, 0, 2, 3, 7, 0, 1, 5, 7,
                                 0, 2, 6, 7, 0, 4, 5, 7, 0, 4, 6, 7};
    for (const std::uint32_t v : t) tets.push_back(base + v);
  };
  std::vector<double> xyz;
  std::vector<std::uint32_t> tets;
  kuhn(xyz, tets, 0);
  // Fix orientation: make each tet right-handed.
  const auto orient = [&]() {
    for (std::size_t t = 0; t < tets.size(); t += 4) {
      if (voroclip::orient3d(&xyz[3 * tets[t]], &xyz[3 * tets[t + 1]], &xyz[3 * tets[t + 2]],
                             &xyz[3 * tets[t + 3]]) == Sign::negative) {
        std::swap(tets[t + 2], tets[t + 3]);
      }
    }
  };
  orient();
  const std::string one = voroclip::check_mesh3_shape(d, xyz, tets);
  CHECK(one.find("1 shell where the domain has 2") != std::string::npos);
  // The box [2, 3] x [0, 1]^2 has no mesh vertex nearest to it: named, with its size (the
  // diagonal, sqrt 3).
  CHECK(one.find("none of its vertices is nearest to the domain's shell at (") !=
        std::string::npos);
  CHECK(one.find(", 12 triangles, 1.732051 across") != std::string::npos);
  const std::size_t at = one.find("shell at (") + 10;
  CHECK((one.compare(at, 2, "2.") == 0 || one.compare(at, 2, "3.") == 0));
  kuhn(xyz, tets, 2);
  orient();
  CHECK(voroclip::check_mesh3_shape(d, xyz, tets).empty());
  // A stray tet far away: a third shell, named as the smallest.
  xyz.insert(xyz.end(), {10, 0, 0, 10.1, 0, 0, 10, 0.1, 0, 10, 0, 0.1});
  const auto s = static_cast<std::uint32_t>(xyz.size() / 3 - 4);
  tets.insert(tets.end(), {s, s + 1, s + 2, s + 3});
  orient();
  const std::string stray = voroclip::check_mesh3_shape(d, xyz, tets);
  CHECK(stray.find("3 shells where the domain has 2") != std::string::npos);
  CHECK(stray.find("4 triangles") != std::string::npos);
  CHECK(voroclip::check_mesh3_shape(d, xyz, {}) == "the mesh has no tets");
}

TEST_CASE("mesh3d adds the sites the surface's topology needs, or says how many", "[mesh]") {
  const Domain3 bunny = voroclip::read_domain3(kData + "/surfaces/bunny.obj");
  Mesh3Options o = small_options(400);
  const Mesh3Result r = voroclip::mesh3d(bunny, o);
  CHECK(r.nb_topology_sites > 0);
  CHECK(r.topology_defects_left == 0);
  CHECK(r.shape_problem.empty());
  CHECK(r.nb_sites >= 400 + r.nb_topology_sites);
  check_boundary(r);
  o.vertex_count = Mesh3Options::VertexCount::kExact;
  try {
    voroclip::mesh3d(bunny, o);
    FAIL("no error with kExact");
  } catch (const voroclip::Error& e) {
    const std::string what = e.what();
    INFO(what);
    CHECK(what.find("400 vertices do not resolve the surface of") != std::string::npos);
    CHECK(what.find("vertices would") != std::string::npos);
  }
}

TEST_CASE("mesh3d meshes again with twice the vertices when the shape is wrong", "[mesh]") {
  // Without the topology refinement (max_topology_rounds = 0), the peeling, the sliver
  // insertion and the lfs cap (which puts enough of the 400 sites in the ears), 400 sites do
  // not resolve the bunny's surface (the test above); kRaise then runs the pipeline again
  // with 800, 1600, ... vertices until the boundary has the input's shape, and says so.
  const Domain3 bunny = voroclip::read_domain3(kData + "/surfaces/bunny.obj");
  Mesh3Options o = small_options(400);
  o.max_topology_rounds = 0;
  o.lfs_cap = 0;
  o.peel_dihedral_deg = 0;        // the peeling can repair it (then no retry is needed)
  o.sliver_insertion_passes = 0;  // so can the sites at slivers' circumcentres
  // The topology alone: at 800, 1600 and 6400 vertices these options cut the ear's tip off
  // by 1.5 to 2.4 edge lengths (the next test), so the distance check would go on retrying.
  o.max_boundary_distance = 0;
  std::vector<std::uint32_t> retries;
  o.progress = [&retries](const voroclip::Mesh3Progress& p) {
    if (p.retry_vertices > 0) retries.push_back(p.retry_vertices);
    return true;
  };
  const Mesh3Result r = voroclip::mesh3d(bunny, o);
  INFO("retries " << r.shape_retries << ", first problem: " << r.raised_because
                  << ", last: " << r.shape_problem);
  REQUIRE(r.shape_retries >= 1);
  CHECK(r.shape_problem.empty());
  CHECK(!r.raised_because.empty());
  CHECK(r.requested_vertices == 400);
  CHECK(r.nb_sites >= (400u << r.shape_retries));
  REQUIRE(retries.size() == r.shape_retries);
  for (std::size_t i = 0; i < retries.size(); ++i) CHECK(retries[i] == (400u << (i + 1)));
  check_boundary(r);
  // kExact keeps the count: the wrong shape is reported, not repaired.
  o.vertex_count = Mesh3Options::VertexCount::kExact;
  const Mesh3Result exact = voroclip::mesh3d(bunny, o);
  CHECK(exact.shape_retries == 0);
  CHECK(exact.shape_problem == r.raised_because);
}

TEST_CASE("mesh3d: a boundary farther from the surface than an edge is the wrong shape", "[mesh]") {
  // The options of the test above at 800 vertices: the right topology, but the tip of an ear
  // is cut off, 0.29 from the mesh's boundary against an edge length of 0.12.
  const Domain3 bunny = voroclip::read_domain3(kData + "/surfaces/bunny.obj");
  Mesh3Options o = small_options(800);
  o.max_topology_rounds = 0;
  o.lfs_cap = 0;
  o.peel_dihedral_deg = 0;
  o.sliver_insertion_passes = 0;
  o.max_shape_retries = 0;
  const Mesh3Result r = voroclip::mesh3d(bunny, o);
  INFO(r.shape_problem);
  // The ratio is the larger one-sided maximum over the uniform edge length cbrt(1.9 V / N).
  const double edge = std::cbrt(voroclip::kMesh3VerticesPerEdgeVolume * bunny.volume() / 800);
  CHECK(r.distance_to_edge_length ==
        Approx(std::max(r.distance.forward.max, r.distance.backward.max) / edge).epsilon(1e-12));
  CHECK(r.distance_to_edge_length > 2);
  // The Hausdorff distance the result carries is hausdorff_distance's, measured again here.
  voroclip::TriangleSurface mine;
  mine.source = "mine";
  mine.xyz = r.xyz;
  mine.triangles = r.boundary_triangles;
  const voroclip::HausdorffDistance again =
      voroclip::hausdorff_distance(mine, voroclip::boundary_surface(bunny));
  CHECK(again.max == r.distance.max);
  CHECK(again.backward.max == r.distance.backward.max);
  CHECK(again.forward.max == r.distance.forward.max);
  // Named: where on the surface, how far, against which edge length.
  CHECK(r.shape_problem.find("the domain's surface at (") == 0);
  CHECK(r.shape_problem.find("more than the local edge length 0.1212") != std::string::npos);
  CHECK(r.shape_problem.find("is cut off") != std::string::npos);
  // A bound of 3 edge lengths accepts it (the same tets); a negative bound is an error.
  o.max_boundary_distance = 3;
  const Mesh3Result loose = voroclip::mesh3d(bunny, o);
  CHECK(loose.shape_problem.empty());
  CHECK(loose.tets == r.tets);
  o.max_boundary_distance = -1;
  CHECK_THROWS_AS(voroclip::mesh3d(bunny, o), voroclip::Error);
}

TEST_CASE("mesh3d: topology refinement goes on while the defects fall", "[mesh][regression]") {
  // elk.mesh at 500 vertices, seed 2: the refinement's defective cells first rise as its
  // sites split the cells reaching across the thin parts, then fall (41, 48, 64, 98, 124, 155,
  // 147, 87, 42, 6, 1, 0). Stopping after 8 rounds without a new fewest (before session 32)
  // meshed round 0's sites: a part of the elk cut off, the Hausdorff distance 19 % of the
  // diagonal, and no shape problem reported. Step 7c's surface moves then made boundary
  // triangles cross (redone without them since). Too slow for the sanitizer builds.
  const char* scale = std::getenv("VOROCLIP_TEST_SCALE");
  if (scale != nullptr && *scale != '\0' && std::atof(scale) < 1) return;
  const Domain3 elk = voroclip::read_domain3(kData + "/tetmeshes/elk.mesh");
  Mesh3Options o;
  o.nb_vertices = 500;
  o.seed = 2;
  o.max_shape_retries = 0;
  o.max_boundary_distance = 0;  // the topology's result itself
  const Mesh3Result r = voroclip::mesh3d(elk, o);
  INFO(r.shape_problem << "; topology rounds " << r.topology_rounds << ", sites "
                       << r.nb_topology_sites << ", defects left " << r.topology_defects_left);
  CHECK(r.topology_defects_left == 0);
  CHECK(r.topology_rounds > 8);
  CHECK(r.nb_topology_sites > 400);
  CHECK(r.shape_problem.empty());
  // The boundary within 1.5 edge lengths of the surface (4.4 before: 52.2 against 11.8).
  CHECK(r.distance_to_edge_length < 1.5);
}

TEST_CASE("mesh3d: sites snapped onto a cube's faces (the NaN of issue 30)", "[mesh][exact]") {
  // The unit cube as six tets, 5000 vertices, seed 2: the constrained CVT's sites on a
  // face are coplanar to the last bit, their Delaunay tets flat slivers whose floating
  // circumcentre was 0/0. Too slow for the sanitizer builds' reduced scale.
  const char* scale = std::getenv("VOROCLIP_TEST_SCALE");
  if (scale != nullptr && *scale != '\0' && std::atof(scale) < 1) return;
  voroclip::TetMeshInput m;
  m.source = "unit cube";
  for (std::uint32_t k = 0; k < 8; ++k) {
    m.xyz.insert(m.xyz.end(), {double(k & 1), double((k >> 1) & 1), double((k >> 2) & 1)});
  }
  m.tets = {0, 1, 3, 7, 0, 3, 2, 7, 0, 5, 1, 7, 0, 2, 6, 7, 0, 4, 5, 7, 0, 6, 4, 7};
  Mesh3Options o;
  o.nb_vertices = 5000;
  o.seed = 2;
  const Mesh3Result r = voroclip::mesh3d(Domain3(m), o);
  CHECK(std::all_of(r.xyz.begin(), r.xyz.end(), [](double x) { return std::isfinite(x); }));
  CHECK(r.shape_problem.empty());
  check_boundary(r);
}

TEST_CASE("mesh3d uses the caller's extraction settings", "[mesh]") {
  voroclip::TriangleSurface s;
  s.source = "box";
  const double lo[3] = {0, 0, 0}, hi[3] = {2, 3, 1};
  add_box(s, lo, hi);
  const Domain3 d(s);
  for (const bool perturb : {false, true}) {
    INFO("perturb " << perturb);
    Mesh3Options o = small_options(300);
    o.perturb = perturb;
    const Mesh3Result def = voroclip::mesh3d(d, o);
    CHECK(def.extraction.nb_repair_passes > 0);
    o.perturbation.extraction.repair_manifold = false;
    o.perturbation.extraction.max_fill_passes = 0;
    const Mesh3Result off = voroclip::mesh3d(d, o);
    CHECK(off.extraction.nb_repair_passes == 0);
    CHECK(off.extraction.nb_filled == 0);
    CHECK(off.extraction.nb_creases == 0);
  }
}

TEST_CASE("mesh3d: a wedge with a knife edge (25 degrees) keeps its shape", "[mesh]") {
  // A prism over the triangle (0, 0), (4, 0), (4 cos 25°, 4 sin 25°), 1 high: along the
  // edge x = y = 0 the normals differ by 155 degrees, 102.5 at the other two long edges.
  // No sampling gives the cells near them the closed-ball property (the wedge thins to
  // nothing); the refinement must not feed on it.
  voroclip::TriangleSurface s;
  s.source = "wedge";
  const double a = 25 * M_PI / 180;
  const double base[3][2] = {{0, 0}, {4, 0}, {4 * std::cos(a), 4 * std::sin(a)}};
  for (int z = 0; z < 2; ++z) {
    for (const auto& p : base) s.xyz.insert(s.xyz.end(), {p[0], p[1], double(z)});
  }
  s.triangles = {0, 2, 1, 3, 4, 5, 0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4, 2, 0, 3, 2, 3, 5};
  const Mesh3Result r = voroclip::mesh3d(Domain3(s), small_options(600));
  // The cells near the edge stay defective however many sites go there: the refinement
  // stops when it no longer improves (max_topology_stall) and the shape check passes.
  CHECK(r.nb_topology_sites < 200);
  CHECK(r.topology_rounds <= 30);
  CHECK(r.shape_problem.empty());
  check_boundary(r);
  // The dihedral verdict: alpha = 25 at the knife edge, the bound 12.5, and the tets below
  // it counted as tet_quality counts them.
  CHECK(r.input_sharpest_dihedral_deg == Approx(25).epsilon(1e-12));
  CHECK(r.dihedral_bound_deg == Approx(12.5).epsilon(1e-12));
  voroclip::TetQualityOptions qo;
  qo.keep_per_tet = true;
  const voroclip::TetQuality q =
      voroclip::tet_quality(r.xyz.data(), r.nb_vertices(), r.tets.data(), r.nb_tets(), qo);
  std::uint32_t below = 0;
  for (const auto& t : q.per_tet) below += t.q1_deg < 12.5;
  CHECK(r.nb_tets_below_bound == below);
}

TEST_CASE("sharpest_dihedral_deg: convex edges count, reflex ones do not", "[mesh]") {
  // A 4 x 2 x 1 block with a V-groove along y = 2 at x = 2, 30 degrees open and 1 deep.
  // Inside the volume: 90 at the block's edges, 105 at the groove's rims, 330 at its
  // bottom (a reflex edge, whose normals differ by 150 degrees: read as convex it would
  // give 30).
  const double a = std::tan(15 * M_PI / 180);
  const double ring[7][2] = {{0, 0}, {4, 0}, {4, 2}, {2 + a, 2}, {2, 1}, {2 - a, 2}, {0, 2}};
  voroclip::TriangleSurface s;
  s.source = "grooved block";
  for (int z = 0; z < 2; ++z) {
    for (const auto& p : ring) s.xyz.insert(s.xyz.end(), {p[0], p[1], double(z)});
  }
  for (std::uint32_t i = 0; i < 7; ++i) {  // the walls, outward
    const std::uint32_t j = (i + 1) % 7;
    s.triangles.insert(s.triangles.end(), {i, j, j + 7, i, j + 7, i + 7});
  }
  // The caps: fans from the groove's bottom (4), which sees every corner.
  const std::uint32_t fan[5][2] = {{5, 6}, {6, 0}, {0, 1}, {1, 2}, {2, 3}};
  for (const auto& f : fan) {
    s.triangles.insert(s.triangles.end(), {4, f[1], f[0]});              // bottom, facing -z
    s.triangles.insert(s.triangles.end(), {4 + 7, f[0] + 7, f[1] + 7});  // top, facing +z
  }
  const voroclip::Surface3 block(s);
  CHECK(voroclip::mesh3::sharpest_dihedral_deg(block) == Approx(90).epsilon(1e-12));
  // The box alone: 90; a regular tetrahedron: acos(1/3).
  CHECK(voroclip::mesh3::sharpest_dihedral_deg(voroclip::Surface3(
            voroclip_test::box_surface({0, 0, 0}, {1, 2, 3}))) == Approx(90).epsilon(1e-12));
  voroclip::TriangleSurface t;
  t.source = "tetrahedron";
  t.xyz = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
  t.triangles = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
  CHECK(voroclip::mesh3::sharpest_dihedral_deg(voroclip::Surface3(t)) ==
        Approx(std::acos(1.0 / 3) * 180 / M_PI).epsilon(1e-12));
}

TEST_CASE("mesh3d meshes bodies 0.01 apart each on its own", "[mesh][regression]") {
  // One CVT over both boxes gave cells across the gap: tets bridging it, then a topology
  // refinement that fed itself (an error after three retries at 1,000 vertices). Each body
  // is now meshed apart, with its share of the vertices.
  voroclip::TriangleSurface s;
  s.source = "two boxes 0.01 apart";
  const double a0[3] = {0, 0, 0}, a1[3] = {1, 1, 1}, b0[3] = {1.01, 0, 0}, b1[3] = {2.01, 1, 1};
  add_box(s, a0, a1);
  add_box(s, b0, b1);
  const Domain3 d(s);
  Mesh3Options o = small_options(500);
  std::vector<std::array<std::uint32_t, 3>> starts;  // body, bodies, vertices
  bool numbered = true;
  o.progress = [&](const voroclip::Mesh3Progress& p) {
    if (p.body_vertices > 0) starts.push_back({p.body, p.nb_bodies, p.body_vertices});
    numbered = numbered && p.nb_bodies == 2 && p.body >= 1 && p.body <= 2;
    return true;
  };
  const Mesh3Result r = voroclip::mesh3d(d, o);
  CHECK(numbered);
  CHECK(starts == std::vector<std::array<std::uint32_t, 3>>{{1, 2, 250}, {2, 2, 250}});
  CHECK(r.shape_problem.empty());
  CHECK(r.shape_retries == 0);
  CHECK(r.requested_vertices == 500);
  CHECK(voroclip::check_mesh3_shape(d, r.xyz, r.tets).empty());
  check_boundary(r);
  const std::vector<std::uint32_t> comp = components(r);
  CHECK(std::set<std::uint32_t>(comp.begin(), comp.end()).size() == 2);
  // No tet reaches across the gap; the region is the body's (in shell order).
  std::uint32_t wrong = 0;
  for (std::size_t t = 0; t < comp.size(); ++t) {
    int side = 0;
    for (int k = 0; k < 4; ++k)
      side += point(r, r.tets[4 * t + static_cast<std::size_t>(k)])[0] > 1.005;
    wrong += (side == 0 && r.tet_tags[t] == 1) || (side == 4 && r.tet_tags[t] == 2) ? 0 : 1;
  }
  CHECK(wrong == 0);
  // Patches body after body: the first box's six faces 1..6, the second's 7..12.
  std::set<std::int32_t> left, right;
  for (std::size_t b = 0; b < r.boundary_tags.size(); ++b) {
    const bool second = point(r, r.boundary_triangles[3 * b])[0] > 1.005;
    (second ? right : left).insert(r.boundary_tags[b]);
  }
  CHECK(left == std::set<std::int32_t>{1, 2, 3, 4, 5, 6});
  CHECK(right == std::set<std::int32_t>{7, 8, 9, 10, 11, 12});
  CHECK(r.tag_names.size() == 14);
  // The figures are the whole mesh's.
  CHECK(r.quality.nb_tets == r.nb_tets());
  CHECK(r.q1_by_boundary_vertices[0].nb_tets + r.q1_by_boundary_vertices[1].nb_tets +
            r.q1_by_boundary_vertices[2].nb_tets ==
        r.nb_tets());
  CHECK(r.distance.max_relative() < 1e-9);
  std::uint32_t kinds[4] = {0, 0, 0, 0};
  for (const auto k : r.kinds) ++kinds[static_cast<int>(k)];
  CHECK(kinds[3] == 16);  // the two boxes' corners
  CHECK(kinds[1] == r.nb_boundary_sites);
  // The same bits with 1 and N threads.
  o.progress = nullptr;
  voroclip_test::check_same_mesh3d_with_1_and_2_threads(d, o);
}

TEST_CASE("mesh3d: a body inside another's cavity is a body of its own", "[mesh]") {
  // A hollow box (its cavity [1, 2]^3) and a box [1.2, 1.8]^3 inside the cavity: two
  // bodies, the inner one at depth 2.
  voroclip::TriangleSurface s;
  s.source = "box in a hollow box";
  const double o0[3] = {0, 0, 0}, o1[3] = {3, 3, 3}, c0[3] = {1, 1, 1}, c1[3] = {2, 2, 2};
  const double i0[3] = {1.2, 1.2, 1.2}, i1[3] = {1.8, 1.8, 1.8};
  add_box(s, o0, o1);
  add_box(s, c0, c1, true);
  add_box(s, i0, i1);
  const Domain3 d(s);
  REQUIRE(voroclip::mesh3::domain_bodies(d).size() == 2);
  const Mesh3Result r = voroclip::mesh3d(d, small_options(800));
  CHECK(r.shape_problem.empty());
  CHECK(r.shape_retries == 0);
  check_boundary(r);
  std::uint32_t wrong = 0;
  for (std::size_t t = 0; t < r.tet_tags.size(); ++t) {
    int inner = 0;
    for (int k = 0; k < 4; ++k) {
      const double* p = point(r, r.tets[4 * t + static_cast<std::size_t>(k)]);
      inner += p[0] > 1.1 && p[0] < 1.9 && p[1] > 1.1 && p[1] < 1.9 && p[2] > 1.1 && p[2] < 1.9;
    }
    wrong += (inner == 0 && r.tet_tags[t] == 1) || (inner == 4 && r.tet_tags[t] == 2) ? 0 : 1;
  }
  CHECK(wrong == 0);
  // 18 faces: the outer box's and the cavity's (body 1), then the inner box's.
  CHECK(std::set<std::int32_t>(r.boundary_tags.begin(), r.boundary_tags.end()).size() == 18);
}

TEST_CASE("mesh3d keeps the tags of a tet mesh of two bodies", "[mesh]") {
  // The tagged Kuhn cube and a copy of it 0.2 along x whose tets are region 3 and whose
  // triangles are patch 13.
  voroclip::TetMeshInput in = voroclip_test::tagged_kuhn_cube();
  const auto nv = static_cast<std::uint32_t>(in.xyz.size() / 3);
  for (std::uint32_t v = 0; v < 8; ++v) {
    in.xyz.insert(in.xyz.end(), {in.xyz[3 * v] + 0.2, in.xyz[3 * v + 1], in.xyz[3 * v + 2]});
  }
  const std::size_t nt = in.tets.size(), ntri = in.triangles.size();
  for (std::size_t i = 0; i < nt; ++i) in.tets.push_back(in.tets[i] + nv);
  for (std::size_t i = 0; i < ntri; ++i) in.triangles.push_back(in.triangles[i] + nv);
  in.tet_ref.resize(2 * (nt / 4), 3);
  in.triangle_ref.resize(2 * (ntri / 3), 13);
  in.tag_names.push_back({3, 3, "lead"});
  const Domain3 d(in);
  REQUIRE(voroclip::mesh3::domain_bodies(d).size() == 2);
  const Mesh3Result r = voroclip::mesh3d(d, small_options(600));
  CHECK(r.shape_problem.empty());
  check_boundary(r);
  std::set<std::int32_t> first_regions, second_regions, first_patches, second_patches;
  const double middle = 1.0 / 3 + 0.15;
  for (std::size_t t = 0; t < r.tet_tags.size(); ++t) {
    (point(r, r.tets[4 * t])[0] > middle ? second_regions : first_regions).insert(r.tet_tags[t]);
  }
  for (std::size_t b = 0; b < r.boundary_tags.size(); ++b) {
    (point(r, r.boundary_triangles[3 * b])[0] > middle ? second_patches : first_patches)
        .insert(r.boundary_tags[b]);
  }
  CHECK(first_regions == std::set<std::int32_t>{1, 2});
  CHECK(second_regions == std::set<std::int32_t>{3});
  CHECK(first_patches == std::set<std::int32_t>{10, 11, 12});
  CHECK(second_patches == std::set<std::int32_t>{13});
  CHECK(r.nb_input_regions == 3);
  std::vector<voroclip::TetMeshInput::TagName> names = in.tag_names;
  names.push_back({2, 11, "patch 11"});
  names.push_back({2, 13, "patch 13"});
  CHECK(r.tag_names == names);
}

TEST_CASE("mesh3d picks the fresh tags of two bodies' untagged parts once, over both",
          "[mesh][regression]") {
  // Each body picked the fresh tag of its untagged boundary and regions among its own tags:
  // the first body's untagged walls took patch 1, the second body's real tag, and its
  // untagged tets region 1, the second body's too. Here the Kuhn cube, its x faces 5 and the
  // rest untagged, its tets untagged, and a copy 0.2 along x all of patch 1 and region 1:
  // the untagged boundary is patch 2, the untagged region 2, as for one body.
  voroclip::TetMeshInput in = voroclip_test::tagged_kuhn_cube();
  in.triangle_ref = {5, 5, 0, 0, 0, 0, 5, 5, 0, 0, 0, 0};
  in.tet_ref.assign(6, 0);
  in.tag_names.clear();
  const auto nv = static_cast<std::uint32_t>(in.xyz.size() / 3);
  for (std::uint32_t v = 0; v < 8; ++v) {
    in.xyz.insert(in.xyz.end(), {in.xyz[3 * v] + 0.2, in.xyz[3 * v + 1], in.xyz[3 * v + 2]});
  }
  const std::size_t nt = in.tets.size(), ntri = in.triangles.size();
  for (std::size_t i = 0; i < nt; ++i) in.tets.push_back(in.tets[i] + nv);
  for (std::size_t i = 0; i < ntri; ++i) in.triangles.push_back(in.triangles[i] + nv);
  in.tet_ref.resize(2 * (nt / 4), 1);
  in.triangle_ref.resize(2 * (ntri / 3), 1);
  const double middle = 1.0 / 3 + 0.15;
  const auto sides = [&](const Mesh3Result& r, std::set<std::int32_t> patches[2],
                         std::set<std::int32_t> regions[2]) {
    for (std::size_t t = 0; t < r.tet_tags.size(); ++t)
      regions[point(r, r.tets[4 * t])[0] > middle ? 1 : 0].insert(r.tet_tags[t]);
    for (std::size_t b = 0; b < r.boundary_tags.size(); ++b)
      patches[point(r, r.boundary_triangles[3 * b])[0] > middle ? 1 : 0].insert(r.boundary_tags[b]);
  };
  {
    const Domain3 d(in);
    REQUIRE(voroclip::mesh3::domain_bodies(d).size() == 2);
    const Mesh3Result r = voroclip::mesh3d(d, small_options(600));
    CHECK(r.shape_problem.empty());
    std::set<std::int32_t> patches[2], regions[2];
    sides(r, patches, regions);
    CHECK(patches[0] == std::set<std::int32_t>{2, 5});
    CHECK(patches[1] == std::set<std::int32_t>{1});
    CHECK(regions[0] == std::set<std::int32_t>{2});
    CHECK(regions[1] == std::set<std::int32_t>{1});
    const std::vector<voroclip::TetMeshInput::TagName> names = {{2, 2, "untagged boundary"},
                                                                {3, 2, "untagged region"},
                                                                {2, 1, "patch 1"},
                                                                {2, 5, "patch 5"},
                                                                {3, 1, "region 1"}};
    for (const auto& n : names) {
      INFO(n.dimension << " " << n.tag << " " << n.name);
      CHECK(std::find(r.tag_names.begin(), r.tag_names.end(), n) != r.tag_names.end());
    }
  }
  // The copy all untagged (its own patches the mesher's: one per face): its boundary takes
  // the untagged tag of the whole (1), not 1 to 6 beside the first body's 5.
  std::fill(in.triangle_ref.begin() + static_cast<std::ptrdiff_t>(ntri / 3), in.triangle_ref.end(),
            0);
  const Mesh3Result r = voroclip::mesh3d(Domain3(in), small_options(600));
  std::set<std::int32_t> patches[2], regions[2];
  sides(r, patches, regions);
  CHECK(patches[0] == std::set<std::int32_t>{1, 5});
  CHECK(patches[1] == std::set<std::int32_t>{1});
}

TEST_CASE("lattice_sites: about n sites, or none in a part thinner than its layers",
          "[mesh][regression]") {
  // A plate 0.1 thick at 1,000 sites: the layers (0.135 apart) held 0, then 950,544 sites as
  // the spacing was corrected, and mesh3d's CVT of a million sites ran for hours. Now the
  // count is within 10 % of n or the lattice gives up (mesh3d draws the sites at random).
  const double p0[3] = {0, 0, 0}, p1[3] = {10, 10, 0.1};
  const Domain3 plate = box_domain("plate", p0, p1);
  const voroclip::TetExtractor3 in_plate(plate);
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const std::vector<double> sites = voroclip::mesh3::lattice_sites(plate, in_plate, 1000, seed);
    INFO("seed " << seed << ": " << sites.size() / 3 << " sites");
    CHECK((sites.empty() || (sites.size() / 3 >= 900 && sites.size() / 3 <= 1100)));
  }
  // A cube: within 10 % (its counts jump by whole layers: 1,024 here), strictly inside.
  const double c0[3] = {0, 0, 0}, c1[3] = {1, 1, 1};
  const Domain3 cube = box_domain("cube", c0, c1);
  const voroclip::TetExtractor3 in_cube(cube);
  const std::vector<double> sites = voroclip::mesh3::lattice_sites(cube, in_cube, 1000, 1);
  CHECK(sites.size() / 3 >= 900);
  CHECK(sites.size() / 3 <= 1100);
  for (std::size_t i = 0; i < sites.size(); i += 3) CHECK(cube.locate(&sites[i]) == Sign::positive);
}

TEST_CASE("mesh3d meshes a plate thinner than the lattice's layers", "[mesh][regression]") {
  // 150 sites in a plate 3 x 3 x 0.1: the lattice has no spacing near that count (its layers
  // are 0.115 apart), so the sites are drawn at random; the topology refinement then adds
  // the sites the thickness needs (about a thousand), with the plate's shape.
  const double p0[3] = {0, 0, 0}, p1[3] = {3, 3, 0.1};
  const Domain3 plate = box_domain("plate", p0, p1);
  const Mesh3Result r = voroclip::mesh3d(plate, small_options(150));
  CHECK(r.shape_problem.empty());
  CHECK(r.shape_retries == 0);
  CHECK(r.nb_topology_sites > 0);
  CHECK(r.nb_sites < 3000);
  check_boundary(r);
}

TEST_CASE("mesh3d: bodies whose meshes meet are meshed again with more vertices",
          "[mesh][regression]") {
  // A ball of radius 0.95 in a spherical cavity of radius 1 (icospheres of 320 triangles)
  // in the box [-1.5, 1.5]^3. At 200 vertices each body's mesh has its shape, but the
  // cavity's triangles, chords of the cavity, cut into the ball's mesh: the whole is meshed
  // again with 400, whose meshes are apart.
  voroclip::TriangleSurface s;
  s.source = "ball in a cavity";
  const double lo[3] = {-1.5, -1.5, -1.5}, hi[3] = {1.5, 1.5, 1.5};
  add_box(s, lo, hi);
  s = voroclip_test::merged(s, voroclip_test::reversed(voroclip_test::icosphere(2)));
  s = voroclip_test::merged(s, voroclip_test::icosphere(2, 0.95));
  const Domain3 d(s);
  REQUIRE(voroclip::mesh3::domain_bodies(d).size() == 2);
  Mesh3Options o;
  o.nb_vertices = 200;
  std::vector<std::uint32_t> retries;
  o.progress = [&](const voroclip::Mesh3Progress& p) {
    if (p.retry_vertices > 0) retries.push_back(p.retry_vertices);
    return true;
  };
  const Mesh3Result r = voroclip::mesh3d(d, o);
  CHECK(retries == std::vector<std::uint32_t>{400});
  CHECK(r.shape_retries == 1);
  CHECK(r.raised_because.rfind("the meshes of the bodies meet: ", 0) == 0);
  CHECK(r.shape_problem.empty());
  CHECK(voroclip::check_mesh3_shape(d, r.xyz, r.tets).empty());
  check_boundary(r);
  // Without retries, the problem is the result's.
  o.max_shape_retries = 0;
  o.progress = nullptr;
  const Mesh3Result once = voroclip::mesh3d(d, o);
  CHECK(once.shape_retries == 0);
  CHECK(once.shape_problem.find("intersect") != std::string::npos);
}

TEST_CASE("mesh3d gives the interfaces of two bodies tags of their own", "[mesh]") {
  // Two unit cubes 1 apart along x, each 3^3 voxels with the middle one an inclusion: regions
  // 1 and 2 in the first, 3 and 4 in the second. Each body is meshed on its own; the tag
  // each run makes up for its interface (after its patch tags) must not be the other's.
  const auto two_bodies = [](bool tag_boundary) {
    voroclip::TetMeshInput in;
    in.source = "two bodies";
    for (int body = 0; body < 2; ++body) {
      const voroclip::TetMeshInput one =
          region_grid(3, [body](std::uint32_t i, std::uint32_t j, std::uint32_t k) {
            return (i == 1 && j == 1 && k == 1 ? 2 : 1) + 2 * body;
          });
      const auto base = static_cast<std::uint32_t>(in.xyz.size() / 3);
      for (std::size_t v = 0; v < one.xyz.size(); v += 3)
        in.xyz.insert(in.xyz.end(), {one.xyz[v] + 2.0 * body, one.xyz[v + 1], one.xyz[v + 2]});
      for (const std::uint32_t v : one.tets) in.tets.push_back(base + v);
      in.tet_ref.insert(in.tet_ref.end(), one.tet_ref.begin(), one.tet_ref.end());
    }
    if (tag_boundary) {
      const Domain3 d(in);
      const voroclip::Surface3& s = d.surface();
      for (std::uint32_t t = 0; t < s.nb_triangles(); ++t) {
        in.triangles.insert(in.triangles.end(), s.triangle(t), s.triangle(t) + 3);
        in.triangle_ref.push_back(5);
      }
    }
    return in;
  };
  for (const bool tag_boundary : {false, true}) {
    INFO("boundary triangles tagged by the file: " << tag_boundary);
    const Mesh3Result r = voroclip::mesh3d(Domain3(two_bodies(tag_boundary)), small_options(1200));
    CHECK(r.shape_problem.empty());
    REQUIRE(r.nb_bodies == 2);
    CHECK(r.nb_interfaces_followed == 2);
    CHECK(r.nb_tets_across_regions == 0);
    const std::int32_t top = *std::max_element(r.boundary_tags.begin(), r.boundary_tags.end());
    if (tag_boundary) CHECK(top == 5);
    // The interface triangles of each body (by x) carry one tag, the bodies' differ, and both
    // follow every patch tag.
    std::set<std::int32_t> tags_of[2];
    for (std::size_t f = 0; f < r.interface_tags.size(); ++f) {
      const double x = point(r, r.interface_triangles[3 * f])[0];
      tags_of[x < 1.5 ? 0 : 1].insert(r.interface_tags[f]);
    }
    REQUIRE(tags_of[0].size() == 1);
    REQUIRE(tags_of[1].size() == 1);
    const std::int32_t first = *tags_of[0].begin(), second = *tags_of[1].begin();
    CHECK(first == top + 1);
    CHECK(second == top + 2);
    // Named by the regions on their two sides.
    const auto name_of = [&](std::int32_t tag) {
      std::string name;
      for (const voroclip::TetMeshInput::TagName& n : r.tag_names) {
        if (n.dimension == 2 && n.tag == tag) {
          CHECK(name.empty());
          name = n.name;
        }
      }
      return name;
    };
    CHECK(name_of(first) == "interface 1-2");
    CHECK(name_of(second) == "interface 3-4");
  }
}
