// read_surface / write_surface / tet_mesh_boundary: every shared surface read with the
// data README's counts and volumes, written in every format and read back, hand-made files
// for each format's features, named errors, and the boundary of the shared tet meshes,
// which the data README says is exactly the source surface.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <unistd.h>
#include <vector>

#include "voroclip/core.h"

using voroclip::SurfaceFormat;
using voroclip::TriangleSurface;

namespace {

const std::string kData = std::string(VOROCLIP_SHARED_DATA_DIR);

struct TempDir {
  std::filesystem::path path;
  TempDir() {
    path = std::filesystem::temp_directory_path() /
           ("voroclip_test_surface_io_" + std::to_string(::getpid()));
    std::filesystem::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  std::string file(const std::string& name) const { return (path / name).string(); }
};

const TempDir& temp() {
  static const TempDir dir;
  return dir;
}

std::string write_temp(const std::string& name, const std::string& content) {
  const std::string path = temp().file(name);
  std::ofstream(path, std::ios::binary) << content;
  return path;
}

std::string error_of(const std::string& path) {
  try {
    voroclip::read_surface(path);
  } catch (const voroclip::Error& e) {
    return e.what();
  }
  return "(no error)";
}

struct Surface {
  const char* file;
  std::uint32_t vertices, triangles;
  double volume;  // the data README's, 6 significant digits
};

const Surface kSurfaces[] = {
    {"bunny.obj", 3301, 6598, 0.749334},         {"homer.obj", 6002, 12000, 0.0212419},
    {"rocker-arm.obj", 10044, 20088, 0.0425136}, {"elk.off", 5194, 10388, 429313},
    {"fandisk.obj", 6475, 12946, 20.2434},       {"gargoyle.off", 50002, 100000, 269603},
    {"sphere.obj", 642, 1280, 4.15268},          {"skull_low_resolution.obj", 5154, 10312, 562.521},
};

// The enclosed volume (divergence theorem), positive for outward right-hand orientation.
double signed_volume(const TriangleSurface& s) {
  double v = 0;
  for (std::size_t t = 0; t < s.nb_triangles(); ++t) {
    const double* a = &s.xyz[3 * std::size_t{s.triangles[3 * t]}];
    const double* b = &s.xyz[3 * std::size_t{s.triangles[3 * t + 1]}];
    const double* c = &s.xyz[3 * std::size_t{s.triangles[3 * t + 2]}];
    v += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
         a[2] * (b[0] * c[1] - b[1] * c[0]);
  }
  return v / 6;
}

// Triangles as coordinate triples, each rotated to start at its smallest corner (keeps the
// orientation), sorted: equal for two surfaces with the same oriented triangles.
using Corner = std::array<double, 3>;
std::vector<std::array<Corner, 3>> geometry(const TriangleSurface& s) {
  std::vector<std::array<Corner, 3>> out;
  for (std::size_t t = 0; t < s.nb_triangles(); ++t) {
    std::array<Corner, 3> tri;
    for (std::size_t k = 0; k < 3; ++k) {
      const double* p = &s.xyz[3 * std::size_t{s.triangles[3 * t + k]}];
      tri[k] = {p[0], p[1], p[2]};
    }
    std::rotate(tri.begin(), std::min_element(tri.begin(), tri.end()), tri.end());
    out.push_back(tri);
  }
  std::sort(out.begin(), out.end());
  return out;
}

TriangleSurface float_rounded(TriangleSurface s) {
  for (double& x : s.xyz) x = static_cast<double>(static_cast<float>(x));
  return s;
}

}  // namespace

TEST_CASE("read_surface reads every shared surface with the README's counts and volume", "[core]") {
  for (const Surface& m : kSurfaces) {
    const std::string path = kData + "/surfaces/" + m.file;
    INFO(path);
    const TriangleSurface s = voroclip::read_surface(path);
    CHECK(s.source == path);
    CHECK(s.nb_vertices() == m.vertices);
    CHECK(s.nb_triangles() == m.triangles);
    CHECK(s.triangle_line.size() == m.triangles);
    CHECK(signed_volume(s) == Approx(m.volume).epsilon(1e-5));
  }
  // Spot values: sphere.obj's first vertex and first face (line 643: 642 'v' lines first).
  const TriangleSurface sphere = voroclip::read_surface(kData + "/surfaces/sphere.obj");
  CHECK(sphere.xyz[3] == 0.723607);
  CHECK(sphere.xyz[4] == -0.44722);
  CHECK(sphere.triangle_line.front() == 643);
}

TEST_CASE("write_surface round-trips every shared surface in every format", "[core]") {
  const std::pair<SurfaceFormat, const char*> formats[] = {
      {SurfaceFormat::kObj, "rt.obj"},       {SurfaceFormat::kOff, "rt.off"},
      {SurfaceFormat::kPlyAscii, "rta.ply"}, {SurfaceFormat::kPlyBinary, "rt.ply"},
      {SurfaceFormat::kStlAscii, "rta.stl"}, {SurfaceFormat::kStlBinary, "rt.stl"},
  };
  for (const Surface& m : kSurfaces) {
    // gargoyle (100k triangles) adds time, not cases: read_surface covers it.
    if (std::string(m.file) == "gargoyle.off") continue;
    const TriangleSurface s = voroclip::read_surface(kData + "/surfaces/" + m.file);
    for (const auto& [format, name] : formats) {
      INFO(m.file << " as " << name);
      const std::string path = temp().file(name);
      voroclip::write_surface(path, s, format);
      const TriangleSurface back = voroclip::read_surface(path);
      if (format == SurfaceFormat::kStlAscii) {
        // No indices in STL: the same oriented triangles, vertices merged (these surfaces
        // have no duplicate or unused vertex, so the count is the same).
        CHECK(back.nb_vertices() == s.nb_vertices());
        CHECK(geometry(back) == geometry(s));
      } else if (format == SurfaceFormat::kStlBinary) {
        CHECK(geometry(back) == geometry(float_rounded(s)));
        CHECK(back.triangle_line == std::vector<std::uint32_t>(s.nb_triangles(), 0));
      } else {
        CHECK(back.xyz == s.xyz);  // bitwise
        CHECK(back.triangles == s.triangles);
      }
    }
  }
  // By extension.
  const TriangleSurface s = voroclip::read_surface(kData + "/surfaces/sphere.obj");
  for (const char* name : {"ext.obj", "ext.off", "ext.ply", "ext.stl"}) {
    voroclip::write_surface(temp().file(name), s);
    CHECK(geometry(voroclip::read_surface(temp().file(name))) ==
          geometry(std::string(name) == "ext.stl" ? float_rounded(s) : s));
  }
  std::ifstream stl(temp().file("ext.stl"), std::ios::binary);
  char head[5] = {};
  stl.read(head, 5);
  CHECK(std::string(head, 5) != "solid");  // a binary STL must not look like ASCII
  CHECK_THROWS_WITH(voroclip::write_surface(temp().file("x.png"), s),
                    "cannot write '" + temp().file("x.png") +
                        "': unknown surface format '.png': expected .obj, .off, .stl or .ply");
}

TEST_CASE("read_surface: OBJ corners, negative indices, polygons, continuations", "[core]") {
  const std::string path = write_temp("features.obj",
                                      "# a unit square and a triangle\n"
                                      "mtllib x.mtl\n"
                                      "o square\n"
                                      "v 0 0 0\n"
                                      "v 1 0 0 1.0\n"          // w
                                      "v 1 1 0 0.5 0.5 0.5\n"  // colour
                                      "v 0 1 0\n"
                                      "vn 0 0 1\n"
                                      "vt 0 0\n"
                                      "usemtl red\n"
                                      "s off\n"
                                      "f 1/1/1 2/1/1 3/1/1 4/1/1\n"  // a quad: two triangles
                                      "v 0 0 1 # comment\n"
                                      "f -5//1 -1//1 \\\n"
                                      "  -4//1\n"
                                      "l 1 2\n");
  const TriangleSurface s = voroclip::read_surface(path);
  CHECK(s.xyz == std::vector<double>{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1});
  CHECK(s.triangles == std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3, 0, 4, 1});
  CHECK(s.triangle_line == std::vector<std::uint32_t>{12, 12, 14});
}

TEST_CASE("read_surface: OFF variants, colours, comments", "[core]") {
  const std::string off = write_temp("c.off",
                                     "COFF 4 2 0\n"
                                     "# vertices with colours\n"
                                     "0 0 0 255 0 0 255\n"
                                     "1 0 0 0 255 0 255\n"
                                     "1 1 0 0 0 255 255\n"
                                     "0 1 0 1 1 1 1\n"
                                     "4 0 1 2 3 0.5 0.5 0.5\n"
                                     "3 3 2 1\n");
  const TriangleSurface s = voroclip::read_surface(off);
  CHECK(s.xyz == std::vector<double>{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0});
  CHECK(s.triangles == std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3, 3, 2, 1});
  CHECK(s.triangle_line == std::vector<std::uint32_t>{7, 7, 8});
  const std::string four = write_temp("4.off", "4OFF\n1 0 0\n0 0 0 0\n");
  CHECK(error_of(four) == four + ":1: '4OFF': only 3D OFF files are read");
  const std::string bin = write_temp("b.off", "OFF BINARY\n");
  CHECK(error_of(bin) == bin + ":1: binary OFF file: only ASCII OFF is read");
}

TEST_CASE("read_surface: STL ASCII with several solids, binary by size", "[core]") {
  const std::string ascii = write_temp("two.stl",
                                       "solid a\n"
                                       " facet normal 0 0 1\n"
                                       "  outer loop\n"
                                       "   vertex 0 0 0\n"
                                       "   vertex 1 0 0\n"
                                       "   vertex 0 1 0\n"
                                       "  endloop\n"
                                       " endfacet\n"
                                       "endsolid a\n"
                                       "SOLID b\n"
                                       " FACET NORMAL 0 0 0\n"
                                       "  OUTER LOOP\n"
                                       "   VERTEX 1 0 0\n"
                                       "   VERTEX -0 1 0\n"  // merged with (0, 1, 0)
                                       "   VERTEX 1 1 0\n"
                                       "  ENDLOOP\n"
                                       " ENDFACET\n"
                                       "ENDSOLID b\n");
  const TriangleSurface s = voroclip::read_surface(ascii);
  CHECK(s.xyz == std::vector<double>{0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0});
  CHECK(s.triangles == std::vector<std::uint32_t>{0, 1, 2, 1, 2, 3});
  CHECK(s.triangle_line == std::vector<std::uint32_t>{2, 11});
  // A binary STL whose header starts with "solid" (as some exporters write) is binary.
  std::string bin = "solid but binary";
  bin.resize(80, ' ');
  const auto put = [&](const void* p, std::size_t n) {
    bin.append(static_cast<const char*>(p), n);
  };
  const std::uint32_t n = 1;
  put(&n, 4);
  const float tri[12] = {0, 0, 1, 0, 0, 0, 2, 0, 0, 0, 2, 0};
  put(tri, sizeof tri);
  const std::uint16_t attr = 0;
  put(&attr, 2);
  const TriangleSurface b = voroclip::read_surface(write_temp("bin.stl", bin));
  CHECK(b.xyz == std::vector<double>{0, 0, 0, 2, 0, 0, 0, 2, 0});
  CHECK(b.triangles == std::vector<std::uint32_t>{0, 1, 2});
  const std::string bad = write_temp("bad.stl", std::string(100, 'x'));
  CHECK(error_of(bad) == bad +
                             ": binary STL: the header says 2021161080 triangles (84 + 50 x "
                             "2021161080 = 101058054084 bytes) but the file has 100 bytes");
  const std::string trunc = write_temp("t.stl",
                                       "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                                       "vertex 1 0 0\nendloop\n");
  CHECK(error_of(trunc) == trunc + ":6: expected 'vertex', found 'endloop'");
}

TEST_CASE("read_surface: PLY ASCII and binary, extra properties and elements", "[core]") {
  const std::string header_tail =
      "element vertex 4\n"
      "property float x\n"
      "property float y\n"
      "property float z\n"
      "property uchar red\n"
      "element face 2\n"
      "property list uchar int vertex_indices\n"
      "element edge 1\n"
      "property int vertex1\n"
      "property int vertex2\n"
      "end_header\n";
  const std::string ascii =
      write_temp("a.ply", "ply\nformat ascii 1.0\ncomment hello end_header\n" + header_tail +
                              "0 0 0 1\n1 0 0 2\n1 1 0 3\n0 1 0 4\n"
                              "4 0 1 2 3\n3 3 2 1\n0 1\n");
  const TriangleSurface s = voroclip::read_surface(ascii);
  CHECK(s.xyz == std::vector<double>{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0});
  CHECK(s.triangles == std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3, 3, 2, 1});
  CHECK(s.triangle_line == std::vector<std::uint32_t>{19, 19, 20});

  for (const bool big : {false, true}) {
    std::string data = std::string("ply\nformat binary_") + (big ? "big" : "little") +
                       "_endian 1.0\n" + header_tail;
    const auto put = [&](const void* p, std::size_t size) {
      char b[8];
      std::memcpy(b, p, size);
      if (big) std::reverse(b, b + size);  // the test machine is little endian
      data.append(b, size);
    };
    const float xyz[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    for (int v = 0; v < 4; ++v) {
      for (int c = 0; c < 3; ++c) put(&xyz[3 * v + c], 4);
      const std::uint8_t red = 7;
      put(&red, 1);
    }
    const std::int32_t f0[4] = {0, 1, 2, 3}, f1[3] = {3, 2, 1};
    std::uint8_t k = 4;
    put(&k, 1);
    for (const std::int32_t i : f0) put(&i, 4);
    k = 3;
    put(&k, 1);
    for (const std::int32_t i : f1) put(&i, 4);
    const std::int32_t edge[2] = {0, 1};
    put(&edge[0], 4);
    put(&edge[1], 4);
    const TriangleSurface b = voroclip::read_surface(write_temp("b.ply", data));
    CHECK(b.xyz == s.xyz);
    CHECK(b.triangles == s.triangles);
    CHECK(b.triangle_line == std::vector<std::uint32_t>{0, 0, 0});
    data.resize(data.size() - 5);
    const std::string cut = write_temp("cut.ply", data);
    CHECK(error_of(cut) == cut + ": the file is truncated in element edge 0");
  }
}

TEST_CASE("read_surface: errors name the file, the line, the face and the defect", "[core]") {
  const std::string missing = temp().file("missing.obj");
  CHECK(error_of(missing) == missing + ": cannot open the file");
  const std::string unknown = write_temp("a.xyz", "1 2 3\n");
  CHECK(error_of(unknown) ==
        unknown + ": unknown surface format '.xyz': expected .obj, .off, .stl or .ply");
  const std::string range = write_temp("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
  CHECK(error_of(range) == range + ":4: face 1: vertex 4 is out of range 1..3");
  const std::string neg = write_temp("neg.obj", "v 0 0 0\nf -1 -2 -3\n");
  CHECK(error_of(neg) == neg + ":2: face 1: vertex -2 is out of range 1..1");
  const std::string two = write_temp("two.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n");
  CHECK(error_of(two) == two + ":3: face 1 has 2 corners, at least 3 are needed");
  const std::string nan = write_temp("nan.obj", "v 0 nan 0\n");
  CHECK(error_of(nan) == nan + ":1: 'nan' is not a finite number");
  const std::string junk = write_temp("junk.obj", "v 0 0 0\n3 4 5\n");
  CHECK(error_of(junk) == junk + ":2: not an OBJ statement: '3'");
  const std::string corner = write_temp("corner.obj", "v 0 0 0\nf 1 x 1\n");
  CHECK(error_of(corner) == corner +
                                ":2: face 1: 'x' is not a vertex reference (v, v/t, v//n or "
                                "v/t/n, v a non-zero integer)");
  const std::string none = write_temp("none.obj", "v 0 0 0\n");
  CHECK(error_of(none) == none + ": no faces");
  const std::string off_range = write_temp("r.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n");
  CHECK(error_of(off_range) == off_range + ":6: face 0: vertex 3 is out of range 0..2");
  const std::string off_short = write_temp("s.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n");
  CHECK(error_of(off_short) == off_short +
                                   ":4: section vertices is truncated: expected 3 vertices, found "
                                   "2 before the end of the file");
  const std::string ply_nolist =
      write_temp("n.ply",
                 "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
                 "property float z\nelement face 0\nproperty int a\nend_header\n");
  CHECK(error_of(ply_nolist) ==
        ply_nolist + ":7: element face: no integer list property vertex_indices (or vertex_index)");
  const std::string ply_fmt = write_temp("f.ply", "ply\nformat ascii 2.0\nend_header\n");
  CHECK(error_of(ply_fmt) == ply_fmt + ":2: PLY version '2.0': only 1.0 is read");
  const std::string not_ply = write_temp("x.ply", "hello\n");
  CHECK(error_of(not_ply) == not_ply + ":1: not a PLY file: expected 'ply', found 'hello'");
}

TEST_CASE("tet_mesh_boundary is the source surface of every shared tet mesh", "[core]") {
  for (const char* name : {"sphere", "bunny", "fandisk", "rocker-arm"}) {
    INFO(name);
    const voroclip::TetMeshInput mesh =
        voroclip::read_tet_mesh(kData + "/tetmeshes/" + name + ".mesh");
    const TriangleSurface b = voroclip::tet_mesh_boundary(mesh);
    const TriangleSurface s = voroclip::read_surface(kData + "/surfaces/" + name + ".obj");
    CHECK(b.xyz == mesh.xyz);
    CHECK(b.nb_triangles() == s.nb_triangles());
    // Same oriented triangles, outward (TetGen orientation), by exact coordinates.
    CHECK(geometry(b) == geometry(s));
    CHECK(b.triangle_line.size() == b.nb_triangles());
  }
  // One tet: its four facets, outward; with the tet reversed, inward.
  voroclip::TetMeshInput one;
  one.xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  one.tets = {0, 1, 2, 3};
  TriangleSurface b = voroclip::tet_mesh_boundary(one);
  CHECK(b.triangles == std::vector<std::uint32_t>{1, 2, 3, 0, 3, 2, 0, 1, 3, 0, 2, 1});
  CHECK(signed_volume(b) == Approx(1.0 / 6));
  one.tets = {0, 1, 3, 2};
  CHECK(signed_volume(voroclip::tet_mesh_boundary(one)) == Approx(-1.0 / 6));
  // Two tets sharing a facet: 6 boundary triangles; a facet shared by 3 tets is interior.
  one.xyz.insert(one.xyz.end(), {1, 1, 1, -1, -1, -1});
  one.tets = {0, 1, 2, 3, 3, 2, 1, 4};
  CHECK(voroclip::tet_mesh_boundary(one).nb_triangles() == 6);
  one.tets.insert(one.tets.end(), {1, 2, 3, 5});
  CHECK(voroclip::tet_mesh_boundary(one).nb_triangles() == 9);
}

TEST_CASE("read_surface from a stream reads what read_surface reads from the file", "[core]") {
  const TriangleSurface s = voroclip::read_surface(kData + "/surfaces/sphere.obj");
  const std::pair<SurfaceFormat, const char*> formats[] = {
      {SurfaceFormat::kObj, "st.obj"},       {SurfaceFormat::kOff, "st.off"},
      {SurfaceFormat::kPlyAscii, "sta.ply"}, {SurfaceFormat::kPlyBinary, "st.ply"},
      {SurfaceFormat::kStlAscii, "sta.stl"}, {SurfaceFormat::kStlBinary, "st.stl"},
  };
  for (const auto& [format, name] : formats) {
    INFO(name);
    const std::string path = temp().file(name);
    voroclip::write_surface(path, s, format);
    std::ifstream file(path, std::ios::binary);
    std::ostringstream bytes;
    bytes << file.rdbuf();
    std::istringstream in(bytes.str());
    const TriangleSurface a = voroclip::read_surface(in, path);
    const TriangleSurface b = voroclip::read_surface(path);
    CHECK(a.source == b.source);
    CHECK(a.xyz == b.xyz);
    CHECK(a.triangles == b.triangles);
    CHECK(a.triangle_line == b.triangle_line);
    CHECK(a.triangle_face == b.triangle_face);
  }
  std::istringstream empty;
  CHECK_THROWS_WITH(voroclip::read_surface(empty, "x.png"),
                    "x.png: unknown surface format '.png': expected .obj, .off, .stl or .ply");
}

namespace {

// A binary STL of `n` copies of one triangle, with `count` in its header.
std::string binary_stl(std::uint32_t count, std::uint32_t n) {
  std::string bin = "binary";
  bin.resize(80, ' ');
  bin.append(reinterpret_cast<const char*>(&count), 4);
  const float tri[12] = {0, 0, 1, 0, 0, 0, 2, 0, 0, 0, 2, 0};
  for (std::uint32_t i = 0; i < n; ++i) {
    bin.append(reinterpret_cast<const char*>(tri), sizeof tri);
    bin.append(2, '\0');
  }
  return bin;
}

const char* const kCubeObj =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

}  // namespace

TEST_CASE("read_surface: a binary STL whose size disagrees with its count", "[core][regression]") {
  // All were "not an STL file ... size is not 84 + 50 x the triangle count".
  const std::string trunc = write_temp("trunc.stl", binary_stl(5, 4));
  CHECK(error_of(trunc) == trunc +
                               ": binary STL: the header says 5 triangles (84 + 50 x 5 = 334 "
                               "bytes) but the file has 284 bytes");
  const std::string small = write_temp("small.stl", binary_stl(1, 3));
  CHECK(error_of(small) == small +
                               ": binary STL: the header says 1 triangles (84 + 50 x 1 = 134 "
                               "bytes) but the file has 234 bytes (a tail that is not zero "
                               "padding)");
  const std::string tiny = write_temp("tiny.stl", "abc");
  CHECK(error_of(tiny) == tiny +
                              ": not an STL file: it does not start with 'solid' (ASCII), and it "
                              "has 3 bytes, fewer than the 84 of a binary STL's header and "
                              "triangle count");
  // Zero padding after the last triangle is read past (numpy-stl and Gmsh ignore a tail).
  const std::string padded = write_temp("padded.stl", binary_stl(2, 2) + std::string(50, '\0'));
  const TriangleSurface s = voroclip::read_surface(padded);
  CHECK(s.nb_triangles() == 2);
  CHECK(s.xyz == std::vector<double>{0, 0, 0, 2, 0, 0, 0, 2, 0});
}

TEST_CASE("read_surface: a UTF-8 BOM and CR-only line ends", "[core][regression]") {
  // "not an OBJ statement: '???v'", "found '???OFF'", and CR-only lines gave "no faces".
  const std::string obj = write_temp("bom.obj", std::string("\xef\xbb\xbf") + kCubeObj);
  CHECK(voroclip::read_surface(obj).nb_triangles() == 12);
  const std::string off =
      write_temp("bom.off",
                 "\xef\xbb\xbfOFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n"
                 "3 0 3 2\n3 1 2 3\n");
  CHECK(voroclip::read_surface(off).nb_triangles() == 4);
  std::string cr = kCubeObj;
  std::replace(cr.begin(), cr.end(), '\n', '\r');
  const TriangleSurface c = voroclip::read_surface(write_temp("cr.obj", cr));
  CHECK(c.nb_triangles() == 12);
  CHECK(c.triangle_line[11] == 14);  // lines counted at the CRs
  const std::string crstl =
      write_temp("cr.stl",
                 "solid s\rfacet normal 0 0 1\router loop\rvertex 0 0 0\rvertex 1 0 0\r"
                 "vertex 0 1 0\rendloop\rendfacet\rendsolid s\r");
  CHECK(voroclip::read_surface(crstl).triangle_line == std::vector<std::uint32_t>{2});
  const std::string crbad = write_temp("crbad.obj", "v 0 0 0\rv 1 0 0\rf 1 2 x\r");
  CHECK(error_of(crbad).rfind(crbad + ":3: ", 0) == 0);
}

TEST_CASE("read_surface: a gzip file, a directory, bytes that are not printable",
          "[core][regression]") {
  // A gzip file named .obj printed its raw bytes; a directory without an extension was
  // "unknown surface format (no extension)". Gzip data is now read, whatever the name:
  // NAME.obj.gz as an OBJ, and cut short it is named as such.
  const std::string gz = write_temp("gz.obj", std::string("\x1f\x8b\x08\x08\x00\x00v 0", 9));
  CHECK(error_of(gz) == gz + ": the gzip data is truncated");
  const std::string gzstl = write_temp("gz.stl", std::string("\x1f\x8b\x08\x08\x00\x00", 6));
  CHECK(error_of(gzstl) == gzstl + ": the gzip data is truncated");
  const std::string named = write_temp("x.obj.gz", "v 0 0 0\n");
  CHECK(error_of(named) == named + ": no faces");
  const std::string bare = write_temp("x.gz", "v 0 0 0\n");
  CHECK(error_of(bare) == bare +
                              ": a compressed file is read by the extension before .gz "
                              "(bunny.obj.gz as an OBJ), and this one has none that voroclip "
                              "reads");
  const std::string dir = temp().file("adir");
  std::filesystem::create_directories(dir);
  CHECK(error_of(dir) == dir + ": is a directory, not a file");
  std::filesystem::create_directories(dir + ".obj");
  CHECK(error_of(dir + ".obj") == dir + ".obj: is a directory, not a file");
  const std::string ctl = write_temp("ctl.obj", "v 0 0 0\n\x02\x1bv 1 0 0\n");
  CHECK(error_of(ctl) == ctl + ":2: not an OBJ statement: '\\x02\\x1bv'");
}

TEST_CASE("read_surface: gzip-compressed files, by their name or by their bytes", "[core]") {
  // The tetrahedron of 4 vertices and 4 faces, compressed by gzip (Python's gzip.compress,
  // mtime 0).
  const std::string bytes(
      "\x1f\x8b\x08\x00\x00\x00\x00\x00\x02\x03\x2b\x53\x30\x00\x41\xae\x32\x05\x43\x28\x6d\x00\x62"
      "\x81\x69\x20\x8b\x2b\x0d\xc8\x33\x56\x30\x02\xd3\x46\x0a\x26\x60\xda\x44\xc1\x18\x48\x1b\x01"
      "\xc5\x4d\xb8\x00\x19\xf1\x86\xd1\x40\x00\x00\x00",
      58);
  const TriangleSurface plain = voroclip::read_surface(write_temp(
      "tet.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"));
  for (const char* name : {"tet.obj.gz", "tet.OBJ.GZ", "tet_gz.obj"}) {
    INFO(name);
    const TriangleSurface s = voroclip::read_surface(write_temp(name, bytes));
    CHECK(s.xyz == plain.xyz);
    CHECK(s.triangles == plain.triangles);
  }
  // Two members one after the other are one file (as gunzip reads them); other bytes after
  // the data, or data cut short or corrupt, are errors naming the file.
  const std::string twice = write_temp("twice.obj.gz", bytes + bytes);
  const TriangleSurface both = voroclip::read_surface(twice);
  CHECK(both.triangles.size() == 2 * plain.triangles.size());
  CHECK(both.xyz.size() == 2 * plain.xyz.size());
  const std::string tail = write_temp("tail.obj.gz", bytes + "xyz");
  CHECK(error_of(tail) == tail + ": 3 bytes follow the end of the gzip data");
  const std::string cut = write_temp("cut.obj.gz", bytes.substr(0, 40));
  CHECK(error_of(cut) == cut + ": the gzip data is truncated");
  std::string bad = bytes;
  bad[12] = static_cast<char>(bad[12] ^ 0x55);
  const std::string corrupt = write_temp("bad.obj.gz", bad);
  CHECK(error_of(corrupt).rfind(corrupt + ": corrupt gzip data (zlib: ", 0) == 0);
}

// Regression: polygons were fan-triangulated from their first vertex, so a non-convex face
// (an L-shaped cap) gave overlapping triangles and "face 1 and face 1 intersect".
TEST_CASE("read_surface: non-convex polygons are triangulated without overlap", "[core]") {
  const std::string obj =
      "v 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\nv 0 0 0\nv 2 0 0\n"
      "v 2 1 1\nv 1 1 1\nv 1 2 1\nv 0 2 1\nv 0 0 1\nv 2 0 1\n"
      "f 6 5 4 3 2 1\nf 7 8 9 10 11 12\nf 1 2 8 7\nf 2 3 9 8\nf 3 4 10 9\nf 4 5 11 10\n"
      "f 5 6 12 11\nf 6 1 7 12\n";
  std::string off = "OFF\n12 8 0\n";
  for (std::size_t at = 0; (at = obj.find("v ", at)) != std::string::npos; at += 2) {
    off += obj.substr(at + 2, obj.find('\n', at) - at - 1);
  }
  off +=
      "6 5 4 3 2 1 0\n6 6 7 8 9 10 11\n4 0 1 7 6\n4 1 2 8 7\n4 2 3 9 8\n4 3 4 10 9\n"
      "4 4 5 11 10\n4 5 0 6 11\n";
  for (const std::string& path : {write_temp("L.obj", obj), write_temp("L.off", off)}) {
    const TriangleSurface s = voroclip::read_surface(path);
    REQUIRE(s.triangle_face.size() == 4 + 4 + 6 * 2);
    // Each cap (the L of area 3): 4 triangles, all turning the cap's way, of total area 3.
    for (const std::uint32_t face : {0u, 1u}) {
      double total = 0;
      int triangles = 0;
      for (std::size_t t = 0; t < s.triangle_face.size(); ++t) {
        if (s.triangle_face[t] != face + s.triangle_face[0]) continue;
        const double* a = &s.xyz[3 * s.triangles[3 * t]];
        const double* b = &s.xyz[3 * s.triangles[3 * t + 1]];
        const double* c = &s.xyz[3 * s.triangles[3 * t + 2]];
        const double area = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
        CHECK(area * (face == 0 ? -1 : 1) > 0);
        total += area;
        ++triangles;
      }
      CHECK(triangles == 4);
      CHECK(total == (face == 0 ? -3 : 3));
    }
    // The bottom cap's ears, in order (a convex polygon keeps the fan from its first vertex).
    CHECK(std::vector<std::uint32_t>(s.triangles.begin(), s.triangles.begin() + 12) ==
          std::vector<std::uint32_t>{4, 3, 2, 4, 2, 1, 5, 4, 1, 5, 1, 0});
  }
}
