// read_tet_mesh / write_tet_mesh: every shared model read with the counts of the data
// README, written in every format and read back identically, hand-made files for each
// format's features, and one named error per defect, checking the whole message.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include <zlib.h>

#include "tagged_mesh.h"
#include "voroclip/core.h"

using voroclip::TetMeshFormat;
using voroclip::TetMeshInput;

namespace {

const std::string kData = std::string(VOROCLIP_SHARED_DATA_DIR) + "/tetmeshes/";

// A scratch directory for the files these tests write, removed at exit.
struct TempDir {
  std::filesystem::path path;
  TempDir() {
    path = std::filesystem::temp_directory_path() /
           ("voroclip_test_tetmesh_io_" + std::to_string(::getpid()));
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
    voroclip::read_tet_mesh(path);
  } catch (const voroclip::Error& e) {
    return e.what();
  }
  return "(no error)";
}

struct Model {
  const char* name;
  std::uint32_t vertices, tets;
};

// The data README's table.
const Model kModels[] = {
    {"sphere", 763, 2413},       {"sphere-fine", 22049, 105250},
    {"bunny", 4083, 14050},      {"skull_low_resolution", 6260, 21774},
    {"elk", 7379, 29125},        {"fandisk", 8636, 32914},
    {"homer", 8926, 36893},      {"rocker-arm", 16157, 68468},
    {"gargoyle", 50002, 170710},
};

// The line of the Tetrahedra keyword in a Medit file.
std::uint32_t medit_keyword_line(const std::string& path, const std::string& keyword) {
  std::ifstream in(path);
  std::string line;
  for (std::uint32_t n = 1; std::getline(in, line); ++n) {
    if (line == keyword) return n;
  }
  return 0;
}

// One tet: (0,0,0), (1,0,0), (0,1,0), (0,0,1).
const char* kOneTetMedit =
    "MeshVersionFormatted 2\n"
    "Dimension 3\n"
    "Vertices\n"
    "4\n"
    "0 0 0 0\n"
    "1 0 0 0\n"
    "0 1 0 0\n"
    "0 0 1 0\n"
    "Tetrahedra\n"
    "1\n"
    "1 2 3 4 0\n"
    "End\n";

const std::vector<double> kOneTetXyz = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};

}  // namespace

TEST_CASE("read_tet_mesh reads every shared model with the README's counts", "[core]") {
  for (const Model& m : kModels) {
    const std::string path = kData + m.name + ".mesh";
    INFO(path);
    const TetMeshInput mesh = voroclip::read_tet_mesh(path);
    CHECK(mesh.source == path);
    CHECK(mesh.nb_vertices() == m.vertices);
    CHECK(mesh.nb_tets() == m.tets);
    REQUIRE(mesh.tet_line.size() == mesh.nb_tets());
    // Tet t is on the line t + 2 after the keyword (the count comes first).
    const std::uint32_t tets_line = medit_keyword_line(path, "Tetrahedra");
    CHECK(mesh.tet_line.front() == tets_line + 2);
    CHECK(mesh.tet_line.back() == tets_line + 1 + m.tets);
    std::uint32_t max_index = 0;
    for (const std::uint32_t v : mesh.tets) max_index = std::max(max_index, v);
    CHECK(max_index < mesh.nb_vertices());
  }
  // Spot values: the first vertex of sphere.mesh, its first tet (1-based in the file).
  const TetMeshInput sphere = voroclip::read_tet_mesh(kData + "sphere.mesh");
  CHECK(sphere.xyz[0] == 0.0);
  CHECK(sphere.xyz[1] == -1.0);
  CHECK(sphere.xyz[3] == 0.723607);
  CHECK(sphere.xyz[5] == 0.525725);
  // Its boundary Triangles (ref 1) are read, its tets' refs (all 0) give no tags.
  CHECK(sphere.nb_triangles() == 1280);
  CHECK(sphere.triangle_ref == std::vector<std::int32_t>(1280, 1));
  CHECK(sphere.tet_ref.empty());
  CHECK(sphere.tag_names.empty());
  CHECK(voroclip::tet_mesh_boundary(sphere).nb_triangles() == 1280);
  const TetMeshInput fine = voroclip::read_tet_mesh(kData + "sphere-fine.mesh");
  CHECK(fine.tet_ref == std::vector<std::int32_t>(105250, 1));
  CHECK(fine.nb_triangles() == 20480);
}

TEST_CASE("write_tet_mesh round-trips every model in every format", "[core]") {
  const std::vector<std::pair<TetMeshFormat, std::string>> formats = {
      {TetMeshFormat::kMedit, "rt.mesh"},
      {TetMeshFormat::kTetGen, "rt.node"},
      {TetMeshFormat::kGmsh22, "rt.msh"},
      {TetMeshFormat::kGmsh41, "rt41.msh"},
      {TetMeshFormat::kVtk, "rt.vtk"},
      {TetMeshFormat::kVtu, "rt.vtu"},
      {TetMeshFormat::kVtuAscii, "rta.vtu"},
      {TetMeshFormat::kGmsh41Binary, "rt41b.msh"},
      {TetMeshFormat::kVtuCompressed, "rtz.vtu"},
  };
  for (const Model& m : kModels) {
    const TetMeshInput mesh = voroclip::read_tet_mesh(kData + m.name + ".mesh");
    for (const auto& [format, name] : formats) {
      INFO(m.name << " as " << name);
      const std::string path = temp().file(name);
      voroclip::write_tet_mesh(path, mesh, format);
      const TetMeshInput back =
          voroclip::read_tet_mesh(format == TetMeshFormat::kTetGen ? temp().file("rt.ele") : path);
      CHECK(back.xyz == mesh.xyz);  // bitwise: shortest round-trip decimals
      CHECK(back.tets == mesh.tets);
      CHECK(back.tet_line.size() == mesh.nb_tets());
      CHECK(back.tet_ref == mesh.tet_ref);
      CHECK(back.triangles == mesh.triangles);
      CHECK(back.triangle_ref == mesh.triangle_ref);
    }
  }
}

TEST_CASE("write_tet_mesh picks the format by extension", "[core]") {
  TetMeshInput mesh;
  mesh.xyz = kOneTetXyz;
  mesh.tets = {0, 1, 2, 3};
  voroclip::write_tet_mesh(temp().file("ext.mesh"), mesh);
  voroclip::write_tet_mesh(temp().file("ext.ele"), mesh);
  voroclip::write_tet_mesh(temp().file("ext.msh"), mesh);
  voroclip::write_tet_mesh(temp().file("ext.vtk"), mesh);
  voroclip::write_tet_mesh(temp().file("ext.vtu"), mesh);
  std::ifstream medit(temp().file("ext.mesh"));
  std::string first;
  std::getline(medit, first);
  CHECK(first == "MeshVersionFormatted 2");
  std::ifstream msh(temp().file("ext.msh"));
  std::string l1, l2;
  std::getline(msh, l1);
  std::getline(msh, l2);
  CHECK(l2 == "4.1 0 8");
  CHECK(std::filesystem::exists(temp().file("ext.node")));
  for (const char* name : {"ext.mesh", "ext.node", "ext.msh", "ext.vtk", "ext.vtu"}) {
    const TetMeshInput back = voroclip::read_tet_mesh(temp().file(name));
    CHECK(back.xyz == mesh.xyz);
    CHECK(back.tets == mesh.tets);
  }
  // Unused vertices are written too.
  mesh.xyz.insert(mesh.xyz.end(), {5, 5, 5});
  voroclip::write_tet_mesh(temp().file("unused.msh"), mesh);
  CHECK(voroclip::read_tet_mesh(temp().file("unused.msh")).xyz == mesh.xyz);
  // Errors name the file.
  mesh.tets = {0, 1, 2, 9};
  CHECK_THROWS_WITH(voroclip::write_tet_mesh(temp().file("bad.mesh"), mesh),
                    "cannot write '" + temp().file("bad.mesh") +
                        "': tet 0 has vertex 9, the mesh has 5 vertices");
  CHECK_THROWS_WITH(voroclip::write_tet_mesh(temp().file("bad.obj"), mesh),
                    Catch::Matchers::StartsWith("cannot write '" + temp().file("bad.obj") +
                                                "': unknown tetrahedral mesh format '.obj'"));
  CHECK_FALSE(std::filesystem::exists(temp().file("bad.mesh")));
}

TEST_CASE("read_tet_mesh: Medit keywords, comments and skipped sections", "[core]") {
  const std::string path = write_temp("features.MESH",
                                      "# a comment line\n"
                                      "meshversionformatted 1\n"
                                      "DIMENSION\n3\n"
                                      "Vertices 5\n"
                                      "0 0 0 1  1 0 0 1\n"  // free format: two per line
                                      "0 1 0 1\n"
                                      "0 0 1 1 # trailing comment\n"
                                      "+2.5e0 -0.0 1e-3 7\n"
                                      "Edges\n1\n1 2 0\n"
                                      "Corners 2 1 2\n"
                                      "Triangles\n2\n1 2 3 0\n1 3 4 0\n"
                                      "NormalAtVertices 1 1 1\n"
                                      "Normals 1 0 0 1\n"
                                      "tetrahedra\n"
                                      "2\n"
                                      "1 2 3 4 3\n"
                                      "\n"
                                      "2 3 4 5 3\n"
                                      "end\n");
  const TetMeshInput mesh = voroclip::read_tet_mesh(path);
  CHECK(mesh.xyz == std::vector<double>{0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 2.5, -0.0, 1e-3});
  CHECK(mesh.tets == std::vector<std::uint32_t>{0, 1, 2, 3, 1, 2, 3, 4});
  CHECK(mesh.tet_line == std::vector<std::uint32_t>{22, 24});
  CHECK(mesh.tet_ref == std::vector<std::int32_t>{3, 3});
  CHECK(mesh.triangles == std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3});
  CHECK(mesh.triangle_ref.empty());  // all 0
}

TEST_CASE("read_tet_mesh: TetGen .node/.ele from either name, numbered from 0 or 1", "[core]") {
  // From 0, with an attribute and a marker per node, 10-node tets with a region attribute.
  write_temp("tg0.node",
             "# nodes\n5 3 1 1\n"
             "0 0 0 0 9.5 1\n"
             "1 1 0 0 9.5 1\n"
             "2 0 1 0 9.5 1\n"
             "3 0 0 1 9.5 1\n"
             "4 1 1 1 9.5 0\n");
  write_temp("tg0.ele",
             "2 10 1\n"
             "0 0 1 2 3 4 4 4 4 4 4 1\n"
             "# comment between tets\n"
             "1 1 2 3 4 0 0 0 0 0 0 1\n");
  for (const char* name : {"tg0.node", "tg0.ele"}) {
    const TetMeshInput mesh = voroclip::read_tet_mesh(temp().file(name));
    CHECK(mesh.source == temp().file("tg0.ele"));
    CHECK(mesh.xyz == std::vector<double>{0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1});
    CHECK(mesh.tets == std::vector<std::uint32_t>{0, 1, 2, 3, 1, 2, 3, 4});
    CHECK(mesh.tet_line == std::vector<std::uint32_t>{2, 4});
    CHECK(mesh.tet_ref == std::vector<std::int32_t>{1, 1});  // the region attribute
    CHECK(mesh.triangles.empty());                           // no .face file
    CHECK(mesh.nb_higher_order_tets == 2);                   // read by their corners
  }
  // From 1, no attributes.
  write_temp("tg1.node", "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n");
  write_temp("tg1.ele", "1 4 0\n1 4 3 2 1\n");
  const TetMeshInput mesh = voroclip::read_tet_mesh(temp().file("tg1.ele"));
  CHECK(mesh.xyz == kOneTetXyz);
  CHECK(mesh.tets == std::vector<std::uint32_t>{3, 2, 1, 0});
}

TEST_CASE("read_tet_mesh: Gmsh 2.2 with other elements and sparse node tags", "[core]") {
  const std::string path = write_temp("g22.msh",
                                      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
                                      "$PhysicalNames\n1\n3 1 \"volume\"\n$EndPhysicalNames\n"
                                      "$Nodes\n5\n"
                                      "10 0 0 0\n"
                                      "30 0 1 0\n"
                                      "20 1 0 0\n"
                                      "40 0 0 1\n"
                                      "7 1 1 1\n"
                                      "$EndNodes\n"
                                      "$Elements\n5\n"
                                      "1 15 2 0 1 10\n"
                                      "2 1 2 0 1 10 20\n"
                                      "3 2 2 0 1 10 20 30\n"
                                      "4 4 2 1 1 10 20 30 40\n"
                                      "9 4 0 20 30 40 7\n"
                                      "$EndElements\n"
                                      "$NodeData\n1\n\"t\"\n$EndNodeData\n");
  const TetMeshInput mesh = voroclip::read_tet_mesh(path);
  CHECK(mesh.xyz == std::vector<double>{0, 0, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1, 1, 1, 1});
  CHECK(mesh.tets == std::vector<std::uint32_t>{0, 2, 1, 3, 2, 1, 3, 4});
  CHECK(mesh.tet_line == std::vector<std::uint32_t>{21, 22});
  // Physical tags: element 4's first tag, none for element 9; the triangle's is 0.
  CHECK(mesh.tet_ref == std::vector<std::int32_t>{1, 0});
  CHECK(mesh.triangles == std::vector<std::uint32_t>{0, 2, 1});
  CHECK(mesh.triangle_ref.empty());
  CHECK(mesh.tag_names == std::vector<TetMeshInput::TagName>{{3, 1, "volume"}});
}

TEST_CASE("read_tet_mesh: Gmsh 4.1 with entities, blocks and parametric nodes", "[core]") {
  const std::string path = write_temp("g41.msh",
                                      "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
                                      "$Entities\n1 0 0 1\n"
                                      "1 0 0 0 0\n"
                                      "1 0 0 0 1 1 1 0 0\n"
                                      "$EndEntities\n"
                                      "$Nodes\n"
                                      "2 5 3 9000000000\n"
                                      "0 1 0 1\n"
                                      "9000000000\n"  // sparse tags: a hash map
                                      "1 1 1\n"
                                      "1 7 1 4\n"  // a parametric block on a curve: x y z u
                                      "3\n"
                                      "50\n"
                                      "51\n"
                                      "52\n"
                                      "0 0 0 0.0\n"
                                      "1 0 0 0.5\n"
                                      "0 1 0 0.7\n"
                                      "0 0 1 1.0\n"
                                      "$EndNodes\n"
                                      "$Elements\n"
                                      "2 3 1 3\n"
                                      "2 1 2 1\n"
                                      "1 3 50 51\n"
                                      "3 1 4 2\n"
                                      "2 3 50 51 52\n"
                                      "3 50 51 52 9000000000\n"
                                      "$EndElements\n");
  const TetMeshInput mesh = voroclip::read_tet_mesh(path);
  CHECK(mesh.xyz == std::vector<double>{1, 1, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1});
  CHECK(mesh.tets == std::vector<std::uint32_t>{1, 2, 3, 4, 2, 3, 4, 0});
  CHECK(mesh.tet_line == std::vector<std::uint32_t>{29, 30});
  // The triangle's surface 1 is not in $Entities, volume 1 has no physical tag.
  CHECK(mesh.triangles == std::vector<std::uint32_t>{1, 2, 3});
  CHECK(mesh.triangle_ref.empty());
  CHECK(mesh.tet_ref.empty());
}

TEST_CASE("read_tet_mesh: legacy VTK, classic and 5.1 cell layouts", "[core]") {
  const std::string classic = write_temp("classic.vtk",
                                         "# vtk DataFile Version 3.0\n"
                                         "a title with CELLS in it\n"
                                         "ASCII\n"
                                         "DATASET UNSTRUCTURED_GRID\n"
                                         "POINTS 5 float\n"
                                         "0 0 0 1 0 0 0 1 0\n"
                                         "0 0 1 1 1 1\n"
                                         "CELLS 3 14\n"
                                         "3 0 1 2\n"
                                         "4 0 1 2 3\n"
                                         "4 1 2 3 4\n"
                                         "CELL_TYPES 3\n"
                                         "5\n10\n10\n"
                                         "CELL_DATA 3\n"
                                         "SCALARS id int 1\nLOOKUP_TABLE default\n0\n1\n2\n");
  TetMeshInput mesh = voroclip::read_tet_mesh(classic);
  CHECK(mesh.xyz == std::vector<double>{0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1});
  CHECK(mesh.tets == std::vector<std::uint32_t>{0, 1, 2, 3, 1, 2, 3, 4});
  CHECK(mesh.tet_line == std::vector<std::uint32_t>{10, 11});
  CHECK(mesh.triangles == std::vector<std::uint32_t>{0, 1, 2});
  CHECK(mesh.tet_ref.empty());  // the cell data "id" is not a tag
  const std::string v51 = write_temp("v51.vtk",
                                     "# vtk DataFile Version 5.1\n"
                                     "vtk output\n"
                                     "ASCII\n"
                                     "DATASET UNSTRUCTURED_GRID\n"
                                     "POINTS 5 double\n"
                                     "0 0 0 1 0 0 0 1 0\n"
                                     "0 0 1 1 1 1\n"
                                     "METADATA\n"
                                     "INFORMATION 0\n"
                                     "\n"
                                     "CELLS 4 11\n"
                                     "OFFSETS vtktypeint64\n"
                                     "0 3 7 11\n"
                                     "CONNECTIVITY vtktypeint64\n"
                                     "0 1 2\n"
                                     "0 1 2 3\n"
                                     "1 2 3 4\n"
                                     "CELL_TYPES 3\n"
                                     "5\n10\n10\n");
  mesh = voroclip::read_tet_mesh(v51);
  CHECK(mesh.xyz == std::vector<double>{0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1});
  CHECK(mesh.tets == std::vector<std::uint32_t>{0, 1, 2, 3, 1, 2, 3, 4});
  CHECK(mesh.tet_line == std::vector<std::uint32_t>{16, 17});
}

TEST_CASE("read_tet_mesh: missing files, unknown formats and versions, binary files", "[core]") {
  const std::string missing = temp().file("missing.mesh");
  CHECK(error_of(missing) == missing + ": cannot open the file");
  const std::string obj = write_temp("a.obj", "v 0 0 0\n");
  CHECK(error_of(obj) == obj +
                             ": unknown tetrahedral mesh format '.obj': expected .mesh, "
                             ".node/.ele, .msh, .vtk or .vtu");
  CHECK(error_of(temp().file("noext")) ==
        temp().file("noext") +
            ": unknown tetrahedral mesh format (no extension): expected .mesh, .node/.ele, "
            ".msh, .vtk or .vtu");
  CHECK(error_of(temp().file("a.meshb")) ==
        temp().file("a.meshb") +
            ": binary Medit files (.meshb) are not read: convert to ASCII .mesh");
  // TetGen: the other file is missing.
  const std::string node = write_temp("lonely.node", "4 3 0 0\n");
  CHECK(error_of(node) == temp().file("lonely.ele") + ": cannot open the file");

  const std::string medit = write_temp("v9.mesh", "MeshVersionFormatted 9\nDimension 3\n");
  CHECK(error_of(medit) == medit + ":1: MeshVersionFormatted 9: unknown version (1 to 4)");
  const std::string medit2d = write_temp("2d.mesh", "MeshVersionFormatted 2\nDimension 2\n");
  CHECK(error_of(medit2d) == medit2d + ":2: Dimension 2: only 3D meshes are read");
  const std::string garbage = write_temp("garbage.mesh", std::string("\x01\x02\xff\0abc", 7));
  CHECK(error_of(garbage) ==
        garbage +
            ":1: not a Medit mesh: expected MeshVersionFormatted, found '\\x01\\x02\\xff\\x00abc'");
  const std::string keyword = write_temp("kw.mesh", "MeshVersionFormatted 2\nFoo 3\n");
  CHECK(error_of(keyword) == keyword + ":2: unknown Medit keyword 'Foo'");

  const std::string msh40 = write_temp("v40.msh", "$MeshFormat\n4 0 8\n$EndMeshFormat\n");
  CHECK(error_of(msh40) == msh40 + ":2: Gmsh format version '4' is not supported (2.2 or 4.1)");
  // Binary files are read: these are only their first lines.
  const std::string binary =
      write_temp("bin.msh", std::string("$MeshFormat\n4.1 1 8\n\x01\0\0\0\n", 24));
  CHECK(error_of(binary) == binary +
                                ": section $MeshFormat: expected $EndMeshFormat after its data, "
                                "found the end of the file");
  const std::string filetype = write_temp("ft.msh", "$MeshFormat\n4.1 2 8\n$EndMeshFormat\n");
  CHECK(error_of(filetype) == filetype + ":2: Gmsh file-type '2': 0 (ASCII) or 1 (binary)");
  const std::string vtkbin = write_temp("bin.vtk",
                                        "# vtk DataFile Version 3.0\nt\nBINARY\n"
                                        "DATASET UNSTRUCTURED_GRID\n");
  CHECK(error_of(vtkbin) == vtkbin + ": no POINTS section");
  const std::string poly =
      write_temp("poly.vtk", "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\n");
  CHECK(error_of(poly) == poly + ":4: DATASET 'POLYDATA': only UNSTRUCTURED_GRID is read");
  const std::string notvtk = write_temp("not.vtk", "hello\n");
  CHECK(error_of(notvtk) ==
        notvtk + ":1: not a legacy VTK file: line 1 should start with '# vtk DataFile Version'");
}

TEST_CASE("read_tet_mesh: truncated sections name the section and the counts", "[core]") {
  std::string text = kOneTetMedit;
  // A Vertices section that announces 6 vertices holds 4 before Tetrahedra.
  std::string bad = text;
  bad.replace(bad.find("Vertices\n4"), 10, "Vertices\n6");
  std::string path = write_temp("trunc1.mesh", bad);
  CHECK(error_of(path) == path +
                              ":9: section Vertices is truncated: expected 6 vertices, found 4 "
                              "before 'Tetrahedra'");
  // The file ends inside Tetrahedra.
  path = write_temp("trunc2.mesh", text.substr(0, text.find("1 2 3 4 0") + 6));
  CHECK(error_of(path) == path +
                              ":11: section Tetrahedra is truncated: expected 1 tetrahedra, "
                              "found 0 before the end of the file");
  // A skipped section too.
  path = write_temp("trunc3.mesh", "MeshVersionFormatted 2\nEdges\n2\n1 2 0\nEnd\n");
  CHECK(error_of(path) == path +
                              ":5: section Edges is truncated: expected 2 entries, found 1 "
                              "before 'End'");
  // Triangles, a tag missing.
  path = write_temp("trunc4.mesh", "MeshVersionFormatted 2\nTriangles\n2\n1 2 3 0\n1 2 3\nEnd\n");
  CHECK(error_of(path) == path +
                              ":6: section Triangles is truncated: expected 2 triangles, found 1 "
                              "before 'End'");
  // Gmsh: $EndNodes comes early.
  path = write_temp("trunc.msh",
                    "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n"
                    "$EndNodes\n");
  CHECK(error_of(path) == path +
                              ":8: section $Nodes is truncated: expected 3 nodes, found 2 "
                              "before '$EndNodes'");
  // Gmsh: more nodes than announced.
  path = write_temp("long.msh",
                    "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\n1 0 0 0\n2 1 0 0\n"
                    "$EndNodes\n");
  CHECK(error_of(path) == path + ":7: section $Nodes: expected $EndNodes after 1 nodes, found '2'");
  // Gmsh: a section without its end.
  path = write_temp("noend.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Comments\nabc\n");
  CHECK(error_of(path) == path + ":4: section $Comments has no $EndComments");
  // VTK: fewer points than announced.
  path = write_temp("trunc.vtk",
                    "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                    "POINTS 3 double\n0 0 0 1 0 0\nCELLS 1 5\n4 0 1 2 3\n");
  CHECK(error_of(path) == path +
                              ":7: section POINTS is truncated: expected 3 points, found 2 "
                              "before 'CELLS'");
  // TetGen: a node line too short, a missing node.
  write_temp("short.node", "2 3 0 0\n1 0 0 0\n2 1 0\n");
  write_temp("short.ele", "0 4 0\n");
  CHECK(error_of(temp().file("short.ele")) ==
        temp().file("short.node") + ":3: node 2: expected 4 values on the line, found 3");
  write_temp("few.node", "3 3 0 0\n1 0 0 0\n2 1 0 0\n");
  write_temp("few.ele", "0 4 0\n");
  CHECK(error_of(temp().file("few.ele")) ==
        temp().file("few.node") +
            ":3: section nodes is truncated: expected 3 nodes, found 2 before the end of the "
            "file");
}

TEST_CASE("read_tet_mesh: values that are not numbers or not finite", "[core]") {
  std::string text = kOneTetMedit;
  std::string bad = text;
  bad.replace(bad.find("1 0 0 0\n"), 8, "1 0x 0 0\n");
  std::string path = write_temp("nan1.mesh", bad);
  CHECK(error_of(path) == path + ":6: '0x' is not a number");
  bad = text;
  bad.replace(bad.find("0 1 0 0\n"), 8, "0 nan 0 0\n");
  path = write_temp("nan2.mesh", bad);
  CHECK(error_of(path) == path + ":7: 'nan' is not a finite number");
  bad = text;
  bad.replace(bad.find("0 0 1 0\n"), 8, "0 0 1e999 0\n");
  path = write_temp("nan3.mesh", bad);
  CHECK(error_of(path) == path + ":8: '1e999' is out of the range of a double");
  bad = text;
  bad.replace(bad.find("1 2 3 4 0"), 9, "1 2 -3 4 0");
  path = write_temp("neg.mesh", bad);
  CHECK(error_of(path) == path + ":11: '-3' is not a valid vertex index (a non-negative integer)");
  path = write_temp("inf.msh",
                    "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\n1 0 inf 0\n$EndNodes\n");
  CHECK(error_of(path) == path + ":6: 'inf' is not a finite number");
  write_temp("nan.node", "1 3 0 0\n1 0 0 NaN\n");
  write_temp("nan.ele", "0 4 0\n");
  CHECK(error_of(temp().file("nan.ele")) ==
        temp().file("nan.node") + ":2: 'NaN' is not a finite number");
}

TEST_CASE("read_tet_mesh: vertex indices out of range name the element", "[core]") {
  std::string bad = kOneTetMedit;
  bad.replace(bad.find("1 2 3 4 0"), 9, "1 2 3 5 0");
  std::string path = write_temp("range.mesh", bad);
  CHECK(error_of(path) == path + ":11: tetrahedron 1: vertex 5 is out of range 1..4");
  bad = kOneTetMedit;
  bad.replace(bad.find("1 2 3 4 0"), 9, "0 2 3 4 0");
  path = write_temp("range0.mesh", bad);
  CHECK(error_of(path) == path + ":11: tetrahedron 1: vertex 0 is out of range 1..4");
  write_temp("range.node", "4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n");
  write_temp("range.ele", "2 4 0\n7 0 1 2 3\n8 1 2 3 4\n");
  CHECK(error_of(temp().file("range.node")) ==
        temp().file("range.ele") + ":3: tetrahedron 8: vertex 4 is out of range 0..3");
  path = write_temp("range.msh",
                    "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n"
                    "3 0 1 0\n4 0 0 1\n$EndNodes\n$Elements\n1\n"
                    "77 4 2 0 1 1 2 3 5\n$EndElements\n");
  CHECK(error_of(path) == path + ":13: element 77: node 5 is not in section $Nodes");
  path = write_temp("dup.msh",
                    "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n2\n1 0 0 0\n1 1 0 0\n"
                    "$EndNodes\n$Elements\n1\n1 4 0 1 1 1 1\n$EndElements\n");
  CHECK(error_of(path) == path + ":7: node tag 1 is repeated (first at line 6)");
  path = write_temp("range.vtk",
                    "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                    "POINTS 4 double\n0 0 0 1 0 0 0 1 0 0 0 1\nCELLS 1 5\n4 0 1 2 4\n"
                    "CELL_TYPES 1\n10\n");
  CHECK(error_of(path) == path + ":8: cell 0: vertex 4 is out of range 0..3");
}

TEST_CASE("read_tet_mesh: files without tetrahedra", "[core]") {
  std::string path =
      write_temp("notet.mesh", "MeshVersionFormatted 2\nVertices\n1\n0 0 0 0\nEnd\n");
  CHECK(error_of(path) == path + ": no tetrahedra (no Tetrahedra section)");
  path = write_temp("notet2.mesh", "MeshVersionFormatted 2\nTetrahedra\n0\nEnd\n");
  CHECK(error_of(path) == path + ": the Tetrahedra section is empty");
  path = write_temp("notet.msh",
                    "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n"
                    "3 0 1 0\n$EndNodes\n$Elements\n1\n1 2 0 1 2 3\n$EndElements\n");
  CHECK(error_of(path) == path + ": no tetrahedra (element type 4, 11, ...) in $Elements");
  path = write_temp("notet.vtk",
                    "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                    "POINTS 3 double\n0 0 0 1 0 0 0 1 0\nCELLS 1 4\n3 0 1 2\n"
                    "CELL_TYPES 1\n5\n");
  CHECK(error_of(path) == path + ": no tetrahedra (cell type 10 or 24)");
  write_temp("notet.node", "0 3 0 0\n");
  write_temp("notet.ele", "0 4 0\n");
  CHECK(error_of(temp().file("notet.ele")) == temp().file("notet.ele") + ": no tetrahedra");
}

namespace {

// Test-side base64 (RFC 4648) and little/big-endian bytes, to build .vtu files by hand.
std::string base64(const std::string& bytes) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(bytes[k]); };
  for (; i + 3 <= bytes.size(); i += 3) {
    const unsigned v = (byte(i) << 16) | (byte(i + 1) << 8) | byte(i + 2);
    for (int s = 18; s >= 0; s -= 6) out += kAlphabet[(v >> s) & 63];
  }
  if (i < bytes.size()) {
    const unsigned v = (byte(i) << 16) | (i + 1 < bytes.size() ? byte(i + 1) << 8 : 0u);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

template <class T>
std::string bytes_of(const std::vector<T>& values, bool big_endian) {
  std::string out;
  for (const T v : values) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (big_endian) std::reverse(b, b + sizeof(T));  // the test machine is little endian
    out.append(b, sizeof(T));
  }
  return out;
}

std::string vtu_file(const std::string& header_attrs, const std::string& arrays,
                     const std::string& appended) {
  return "<?xml version=\"1.0\"?>\n<!-- made by hand -->\n<VTKFile type=\"UnstructuredGrid\" " +
         header_attrs +
         ">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\"5\" NumberOfCells=\"3\">\n" + arrays +
         "</Piece>\n</UnstructuredGrid>\n" + appended + "</VTKFile>\n";
}

// Two tets and a triangle (skipped) on 5 points.
const std::vector<double> kVtuXyz = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1};
const std::vector<std::int32_t> kVtuConn = {0, 1, 2, 3, 1, 2, 3, 4, 0, 1, 2};
const std::vector<std::int32_t> kVtuOffsets = {4, 8, 11};
const std::vector<std::uint8_t> kVtuTypes = {10, 10, 5};

}  // namespace

TEST_CASE("read_tet_mesh: VTK XML .vtu in ASCII, inline binary and appended raw", "[core]") {
  SECTION("ASCII, other cell types skipped") {
    const std::string path = write_temp(
        "ascii.vtu", vtu_file("version=\"0.1\" byte_order=\"LittleEndian\"",
                              "<Points>\n<DataArray type=\"Float32\" NumberOfComponents=\"3\" "
                              "format=\"ascii\">0 0 0 1 0 0 0 1 0 0 0 1 1 1 1</DataArray>\n"
                              "</Points>\n<Cells>\n<DataArray type=\"Int32\" "
                              "Name=\"connectivity\" format=\"ascii\">0 1 2 3 1 2 3 4 0 1 2"
                              "</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" "
                              "format=\"ascii\">4 8 11</DataArray>\n<DataArray type=\"UInt8\" "
                              "Name=\"types\" format=\"ascii\">10 10 5</DataArray>\n</Cells>\n",
                              ""));
    const TetMeshInput mesh = voroclip::read_tet_mesh(path);
    CHECK(mesh.xyz == kVtuXyz);
    CHECK(mesh.tets == std::vector<std::uint32_t>{0, 1, 2, 3, 1, 2, 3, 4});
    CHECK(mesh.tet_line == std::vector<std::uint32_t>{10, 10});
    CHECK(mesh.triangles == std::vector<std::uint32_t>{0, 1, 2});
  }
  for (const bool big : {false, true}) {
    SECTION(std::string("inline binary, header and data in one base64 stream, ") +
            (big ? "big" : "little") + " endian, UInt32 headers") {
      const auto block = [&](const std::string& data) {
        return base64(
            bytes_of(std::vector<std::uint32_t>{static_cast<std::uint32_t>(data.size())}, big) +
            data);
      };
      const std::string arrays =
          "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"binary\">" +
          block(bytes_of(kVtuXyz, big)) +
          "</DataArray></Points>\n<Cells>\n<DataArray type=\"Int32\" Name=\"connectivity\" "
          "format=\"binary\">\n  " +
          block(bytes_of(kVtuConn, big)) +
          "\n</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"binary\">" +
          block(bytes_of(kVtuOffsets, big)) +
          "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"binary\">" +
          block(bytes_of(kVtuTypes, big)) + "</DataArray>\n</Cells>\n";
      const std::string path =
          write_temp("inline.vtu", vtu_file(std::string("version=\"0.1\" byte_order=\"") +
                                                (big ? "Big" : "Little") + "Endian\"",
                                            arrays, ""));
      const TetMeshInput mesh = voroclip::read_tet_mesh(path);
      CHECK(mesh.xyz == kVtuXyz);
      CHECK(mesh.tets == std::vector<std::uint32_t>{0, 1, 2, 3, 1, 2, 3, 4});
    }
  }
  SECTION("appended raw, UInt64 headers") {
    std::string data;
    std::vector<std::size_t> offsets;
    for (const std::string& bytes : {bytes_of(kVtuXyz, false), bytes_of(kVtuConn, false),
                                     bytes_of(kVtuOffsets, false), bytes_of(kVtuTypes, false)}) {
      offsets.push_back(data.size());
      data += bytes_of(std::vector<std::uint64_t>{bytes.size()}, false) + bytes;
    }
    const auto array = [&](const std::string& type, const std::string& name, std::size_t i) {
      return "<DataArray type=\"" + type + "\" Name=\"" + name + "\" NumberOfComponents=\"" +
             (i == 0 ? "3" : "1") + "\" format=\"appended\" offset=\"" +
             std::to_string(offsets[i]) + "\"/>\n";
    };
    const std::string path = write_temp(
        "raw.vtu",
        vtu_file("version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\"",
                 "<Points>\n" + array("Float64", "Points", 0) + "</Points>\n<Cells>\n" +
                     array("Int32", "connectivity", 1) + array("Int32", "offsets", 2) +
                     array("UInt8", "types", 3) + "</Cells>\n",
                 "<AppendedData encoding=\"raw\">\n   _" + data + "\n</AppendedData>\n"));
    const TetMeshInput mesh = voroclip::read_tet_mesh(path);
    CHECK(mesh.xyz == kVtuXyz);
    CHECK(mesh.tets == std::vector<std::uint32_t>{0, 1, 2, 3, 1, 2, 3, 4});
  }
  SECTION("the writer's binary file: base64 appended, parsed as text") {
    TetMeshInput mesh;
    mesh.xyz = kVtuXyz;
    mesh.tets = {0, 1, 2, 3, 1, 2, 3, 4};
    const std::string path = temp().file("written.vtu");
    voroclip::write_tet_mesh(path, mesh, TetMeshFormat::kVtu);
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string text = ss.str();
    CHECK(text.find("<AppendedData encoding=\"base64\">") != std::string::npos);
    CHECK(text.find("header_type=\"UInt64\"") != std::string::npos);
    // The Points array comes first at offset 0: its header is the byte count 15 * 8 = 120,
    // as a UInt64 base64-encoded on its own ("eAAAAAAAAAA=").
    const std::size_t underscore = text.find('_', text.find("<AppendedData"));
    CHECK(text.substr(underscore + 1, 12) ==
          base64(bytes_of(std::vector<std::uint64_t>{120}, false)));
    CHECK(text.substr(underscore + 13, 160) == base64(bytes_of(kVtuXyz, false)));
  }
}

TEST_CASE("read_tet_mesh: .vtu errors name the file, the line and the defect", "[core]") {
  const std::string compressed =
      write_temp("z.vtu",
                 "<VTKFile type=\"UnstructuredGrid\" compressor=\"vtkLZ4DataCompressor\">\n"
                 "</VTKFile>\n");
  CHECK(error_of(compressed) == compressed +
                                    ":1: compressor 'vtkLZ4DataCompressor' is not read "
                                    "(vtkZLibDataCompressor, or no compressor)");
  const std::string poly = write_temp("p.vtu", "<?xml?>\n<VTKFile type=\"PolyData\">\n</VTKFile>");
  CHECK(error_of(poly) == poly + ":2: VTKFile type 'PolyData': only UnstructuredGrid is read");
  const std::string short_points =
      write_temp("s.vtu", vtu_file("",
                                   "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" "
                                   "format=\"ascii\">0 0 0 1</DataArray></Points>\n",
                                   ""));
  CHECK(error_of(short_points) ==
        short_points + ":6: DataArray Points: expected 15 values, found 4");
  const std::string bad_index = write_temp(
      "i.vtu",
      vtu_file("",
               "<Points>\n<DataArray type=\"Float32\" NumberOfComponents=\"3\" "
               "format=\"ascii\">0 0 0 1 0 0 0 1 0 0 0 1 1 1 1</DataArray>\n</Points>\n<Cells>\n"
               "<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">0 1 2 3 1 2 3 5 "
               "0 1 2</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">4 "
               "8 11</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">10 10 "
               "5</DataArray>\n</Cells>\n",
               ""));
  CHECK(error_of(bad_index) == bad_index + ":10: cell 1: point 5 is out of range 0..4");
  const std::string mismatch = write_temp("m.vtu", "<VTKFile>\n<Piece>\n</VTKFile>\n");
  CHECK(error_of(mismatch) == mismatch + ":3: closing tag </VTKFile> does not match <Piece>");
}

// ---------------------------------------------------------------------------------------
// Triangles and tags.

namespace {

const std::vector<std::pair<TetMeshFormat, std::string>> kTagFormats = {
    {TetMeshFormat::kMedit, "tag.mesh"},
    {TetMeshFormat::kTetGen, "tag.ele"},
    {TetMeshFormat::kGmsh22, "tag22.msh"},
    {TetMeshFormat::kGmsh41, "tag41.msh"},
    {TetMeshFormat::kVtk, "tag.vtk"},
    {TetMeshFormat::kVtu, "tag.vtu"},
    {TetMeshFormat::kVtuAscii, "taga.vtu"},
    {TetMeshFormat::kGmsh41Binary, "tag41b.msh"},
    {TetMeshFormat::kVtuCompressed, "tagz.vtu"},
};

bool is_gmsh(TetMeshFormat f) {
  return f == TetMeshFormat::kGmsh22 || f == TetMeshFormat::kGmsh41 ||
         f == TetMeshFormat::kGmsh41Binary;
}

std::string file_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string write_error(const std::string& path, const TetMeshInput& mesh, TetMeshFormat f) {
  try {
    voroclip::write_tet_mesh(path, mesh, f);
  } catch (const voroclip::Error& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST_CASE("write_tet_mesh round-trips triangles, tags and names in every format", "[core]") {
  TetMeshInput mesh = voroclip_test::tagged_kuhn_cube();
  SECTION("two regions, three patches, names") {}
  SECTION("untagged triangles, tagged tets, no names") {
    mesh.triangle_ref.clear();
    mesh.tag_names.clear();
  }
  SECTION("tagged triangles, untagged tets (Gmsh: physical group 0 for the tets)") {
    mesh.tet_ref.clear();
  }
  SECTION("tets only") {
    mesh.triangles.clear();
    mesh.triangle_ref.clear();
    mesh.tet_ref.clear();
    mesh.tag_names.clear();
  }
  for (const auto& [format, name] : kTagFormats) {
    INFO(name);
    const std::string path = temp().file(name);
    voroclip::write_tet_mesh(path, mesh, format);
    const TetMeshInput back = voroclip::read_tet_mesh(path);
    CHECK(back.xyz == mesh.xyz);
    CHECK(back.tets == mesh.tets);
    CHECK(back.tet_line.size() == mesh.nb_tets());
    CHECK(back.tet_ref == mesh.tet_ref);
    CHECK(back.triangles == mesh.triangles);
    CHECK(back.triangle_ref == mesh.triangle_ref);
    if (is_gmsh(format)) {
      CHECK(back.tag_names == mesh.tag_names);
    } else {
      CHECK(back.tag_names.empty());  // only Gmsh files carry names
    }
  }
}

TEST_CASE("write_tet_mesh: tags of zeros read back empty, negative tags outside Gmsh", "[core]") {
  TetMeshInput mesh = voroclip_test::tagged_kuhn_cube();
  mesh.tag_names.clear();
  mesh.tet_ref.assign(mesh.nb_tets(), 0);
  mesh.triangle_ref.assign(mesh.nb_triangles(), 0);
  for (const auto& [format, name] : kTagFormats) {
    INFO(name);
    voroclip::write_tet_mesh(temp().file(name), mesh, format);
    const TetMeshInput back = voroclip::read_tet_mesh(temp().file(name));
    CHECK(back.tet_ref.empty());
    CHECK(back.triangle_ref.empty());
    CHECK(back.triangles == mesh.triangles);
  }
  mesh.tet_ref = {-1, 2147483647, 0, -2147483647 - 1, 5, 5};
  mesh.triangle_ref.assign(mesh.nb_triangles(), -3);
  for (const auto& [format, name] : kTagFormats) {
    INFO(name);
    const std::string path = temp().file("neg_" + name);
    if (is_gmsh(format)) {
      CHECK(write_error(path, mesh, format) ==
            "cannot write '" + path +
                "' (Gmsh): tet 0 has the tag -1: physical tags are positive (0: none)");
      CHECK_FALSE(std::filesystem::exists(path));
      continue;
    }
    voroclip::write_tet_mesh(path, mesh, format);
    const TetMeshInput back = voroclip::read_tet_mesh(path);
    CHECK(back.tet_ref == mesh.tet_ref);
    CHECK(back.triangle_ref == mesh.triangle_ref);
  }
}

TEST_CASE("write_tet_mesh: what each format's file says about tags", "[core]") {
  const TetMeshInput mesh = voroclip_test::tagged_kuhn_cube();
  voroclip::write_tet_mesh(temp().file("facts.mesh"), mesh, TetMeshFormat::kMedit);
  const std::string medit = file_text(temp().file("facts.mesh"));
  CHECK(medit.find("Triangles\n12\n1 3 7 10\n1 5 7 10\n1 2 6 11\n") != std::string::npos);
  CHECK(medit.find("Tetrahedra\n6\n1 2 4 8 1\n1 3 4 8 2\n") != std::string::npos);
  CHECK(medit.find("Triangles") < medit.find("Tetrahedra"));

  voroclip::write_tet_mesh(temp().file("facts.node"), mesh, TetMeshFormat::kTetGen);
  CHECK(file_text(temp().file("facts.ele")).rfind("6 4 1\n1 1 2 4 8 1\n2 1 3 4 8 2\n", 0) == 0);
  CHECK(file_text(temp().file("facts.face")).rfind("12 1\n1 1 3 7 10\n", 0) == 0);

  voroclip::write_tet_mesh(temp().file("facts22.msh"), mesh, TetMeshFormat::kGmsh22);
  const std::string g22 = file_text(temp().file("facts22.msh"));
  CHECK(g22.find("$PhysicalNames\n4\n3 1 \"steel\"\n3 2 \"copper region\"\n2 10 \"x faces\"\n"
                 "2 12 \"z\"\n$EndPhysicalNames\n") != std::string::npos);
  // Tet 2: region 2, volume entity 2; triangle 1 (element 7): patch 10, surface entity 1.
  CHECK(g22.find("\n2 4 2 2 2 1 3 4 8\n") != std::string::npos);
  CHECK(g22.find("\n7 2 2 10 1 1 3 7\n") != std::string::npos);

  voroclip::write_tet_mesh(temp().file("facts41.msh"), mesh, TetMeshFormat::kGmsh41);
  const std::string g41 = file_text(temp().file("facts41.msh"));
  // Surfaces 1..3 for patches 10, 11, 12, volumes 1..2 for regions 1, 2, each in the
  // physical group of its tag.
  CHECK(g41.find("$Entities\n0 0 3 2\n") != std::string::npos);
  CHECK(g41.find(" 1 12 0\n1 ") != std::string::npos);  // surface 3, then volume 1
  // Runs of equal tags: tets 1 | 2 | 1 | 2 2 | 1, triangles 10 10 | 11 11 | 12 12 | ...
  CHECK(g41.find("$Elements\n11 18 1 18\n3 1 4 1\n1 1 2 4 8\n3 2 4 1\n2 1 3 4 8\n") !=
        std::string::npos);
  CHECK(g41.find("3 2 4 2\n4 1 3 7 8\n5 1 5 6 8\n3 1 4 1\n6 1 5 7 8\n2 1 2 2\n7 1 3 7\n") !=
        std::string::npos);

  voroclip::write_tet_mesh(temp().file("facts.vtk"), mesh, TetMeshFormat::kVtk);
  const std::string vtk = file_text(temp().file("facts.vtk"));
  CHECK(vtk.find("CELLS 18 78\n4 0 1 3 7\n") != std::string::npos);
  CHECK(vtk.find("CELL_TYPES 18\n10\n10\n10\n10\n10\n10\n5\n") != std::string::npos);
  CHECK(vtk.find("SCALARS region int 1\nLOOKUP_TABLE default\n1\n2\n1\n2\n2\n1\n0\n") !=
        std::string::npos);
  CHECK(vtk.find("SCALARS patch int 1\nLOOKUP_TABLE default\n0\n0\n0\n0\n0\n0\n10\n10\n11\n") !=
        std::string::npos);

  voroclip::write_tet_mesh(temp().file("facts.vtu"), mesh, TetMeshFormat::kVtuAscii);
  const std::string vtu = file_text(temp().file("facts.vtu"));
  CHECK(vtu.find("NumberOfCells=\"18\"") != std::string::npos);
  CHECK(vtu.find(
            "<DataArray type=\"Int32\" Name=\"region\" format=\"ascii\">\n1\n2\n1\n2\n2\n1\n0\n") !=
        std::string::npos);
  CHECK(vtu.find("<DataArray type=\"Int32\" Name=\"patch\" format=\"ascii\">\n0\n") !=
        std::string::npos);
  CHECK(vtu.find("Name=\"offsets\" format=\"ascii\">\n4\n8\n12\n16\n20\n24\n27\n30\n") !=
        std::string::npos);
}

TEST_CASE("read_tet_mesh: Medit Triangles and Tetrahedra refs", "[core]") {
  const std::string path = write_temp("refs.mesh",
                                      "MeshVersionFormatted 2\nDimension 3\nVertices\n5\n"
                                      "0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n1 1 1 0\n"
                                      "Tetrahedra\n2\n1 2 3 4 -4\n2 3 4 5 +7\n"
                                      "Triangles\n3\n1 2 3 5\n2 3 4 0\n4 3 2 2147483647\n"
                                      "End\n");
  const TetMeshInput mesh = voroclip::read_tet_mesh(path);
  CHECK(mesh.tet_ref == std::vector<std::int32_t>{-4, 7});
  CHECK(mesh.triangles == std::vector<std::uint32_t>{0, 1, 2, 1, 2, 3, 3, 2, 1});
  CHECK(mesh.triangle_ref == std::vector<std::int32_t>{5, 0, 2147483647});
}

TEST_CASE("write_tet_mesh TetGen: a .face that cannot be written leaves no .node or .ele",
          "[core][regression]") {
  // The three files were written one after the other: .node and .ele stayed behind when
  // the .face failed (a directory of its name), a mesh that reads back without its faces.
  const TetMeshInput mesh = voroclip_test::tagged_kuhn_cube();
  const std::string base = temp().file("partial");
  std::filesystem::create_directory(base + ".face");
  CHECK(voroclip::tet_mesh_files(base + ".ele", TetMeshFormat::kTetGen) ==
        std::vector<std::string>{base + ".node", base + ".ele", base + ".face"});
  CHECK(voroclip::tet_mesh_files(base + ".mesh", TetMeshFormat::kMedit) ==
        std::vector<std::string>{base + ".mesh"});
  CHECK_THROWS_WITH(voroclip::write_tet_mesh(base + ".node", mesh, TetMeshFormat::kTetGen),
                    Catch::StartsWith("cannot write '" + base + ".face'"));
  CHECK_FALSE(std::filesystem::exists(base + ".node"));
  CHECK_FALSE(std::filesystem::exists(base + ".ele"));
  for (const char* ext : {".node", ".ele", ".face"}) {
    CHECK_FALSE(std::filesystem::exists(base + ext + std::string(".voroclip-tmp")));
  }
  // Written whole once the way is clear.
  std::filesystem::remove(base + ".face");
  voroclip::write_tet_mesh(base + ".node", mesh, TetMeshFormat::kTetGen);
  CHECK(voroclip::read_tet_mesh(base + ".ele").triangle_ref == mesh.triangle_ref);
}

TEST_CASE("read_tet_mesh: TetGen .face with markers and extra columns, from 0", "[core]") {
  write_temp("tf.node", "5 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n4 1 1 1\n");
  write_temp("tf.ele", "2 4 2\n0 0 1 2 3 -1 0.5\n1 1 2 3 4 4.0 7\n");
  write_temp("tf.face", "# faces\n3 1\n0 0 1 2 5 0 -1\n1 1 2 3 -6\n2 3 2 1 0 # comment\n");
  const TetMeshInput mesh = voroclip::read_tet_mesh(temp().file("tf.node"));
  CHECK(mesh.tets == std::vector<std::uint32_t>{0, 1, 2, 3, 1, 2, 3, 4});
  CHECK(mesh.tet_ref == std::vector<std::int32_t>{-1, 4});  // the first attribute
  CHECK(mesh.triangles == std::vector<std::uint32_t>{0, 1, 2, 1, 2, 3, 3, 2, 1});
  CHECK(mesh.triangle_ref == std::vector<std::int32_t>{5, -6, 0});
  // Without markers.
  write_temp("tf.face", "1 0\n1 0 1 2\n");
  const TetMeshInput plain = voroclip::read_tet_mesh(temp().file("tf.ele"));
  CHECK(plain.triangles == std::vector<std::uint32_t>{0, 1, 2});
  CHECK(plain.triangle_ref.empty());
}

TEST_CASE("read_tet_mesh: Gmsh 4.1 physical tags by entity, names, sections in any order",
          "[core]") {
  const std::string path = write_temp(
      "phys41.msh",
      "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
      "$Nodes\n1 5 1 5\n3 4 0 5\n1\n2\n3\n4\n5\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\n$EndNodes\n"
      "$Elements\n5 6 1 6\n"
      "3 4 4 1\n1 1 2 3 4\n"         // volume 4: physical 7
      "3 9 4 1\n2 2 3 4 5\n"         // volume 9: no physical tag
      "2 3 2 2\n3 1 2 3\n4 1 3 4\n"  // surface 3: physicals 20 and 21 (the first counts)
      "2 5 2 1\n5 2 3 4\n"           // surface 5: not in $Entities
      "1 1 1 1\n6 1 2\n"             // a line, skipped
      "$EndElements\n"
      "$Entities\n1 0 1 2\n"
      "1 0 0 0 1 99\n"
      "3 0 0 0 1 1 0 2 20 21 0\n"
      "4 0 0 0 1 1 1 1 7 1 3\n"
      "9 0 0 0 1 1 1 0 2 3 -5\n"
      "$EndEntities\n"
      "$PhysicalNames\n3\n3 7 \"inner  region\"\n2 20 \"wall\"\n0 99 \"\"\n$EndPhysicalNames\n");
  const TetMeshInput mesh = voroclip::read_tet_mesh(path);
  CHECK(mesh.tets == std::vector<std::uint32_t>{0, 1, 2, 3, 1, 2, 3, 4});
  CHECK(mesh.tet_ref == std::vector<std::int32_t>{7, 0});
  CHECK(mesh.triangles == std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3, 1, 2, 3});
  CHECK(mesh.triangle_ref == std::vector<std::int32_t>{20, 20, 0});
  CHECK(mesh.tag_names ==
        std::vector<TetMeshInput::TagName>{{3, 7, "inner  region"}, {2, 20, "wall"}, {0, 99, ""}});
}

TEST_CASE("read_tet_mesh: VTK region and patch cell data, .vtk and .vtu", "[core]") {
  // Legacy: POINT_DATA first, region as SCALARS, patch as a FIELD array, other data read
  // past by its size.
  const std::string vtk = write_temp("tags.vtk",
                                     "# vtk DataFile Version 3.0\nt\nASCII\n"
                                     "DATASET UNSTRUCTURED_GRID\n"
                                     "FIELD FieldData 2\nTIME 1 1 double\n0.5\n"
                                     "Names 1 2 string\nCELL DATA%20x\nfoo\n"
                                     "POINTS 5 double\n0 0 0 1 0 0 0 1 0 0 0 1 1 1 1\n"
                                     "CELLS 4 18\n3 0 1 2\n4 0 1 2 3\n3 1 2 3\n4 1 2 3 4\n"
                                     "CELL_TYPES 4\n5 10 5 10\n"
                                     "POINT_DATA 5\nVECTORS v double\n"
                                     "0 0 0 0 0 0 0 0 0 0 0 0 0 0 0\n"
                                     "SCALARS region int 1\nLOOKUP_TABLE default\n1 2 3 4 5\n"
                                     "CELL_DATA 4\n"
                                     "SCALARS q float 2\nLOOKUP_TABLE default\n0 0 0 0 0 0 0 0\n"
                                     "COLOR_SCALARS c 3\n0 0 0 0 0 0 0 0 0 0 0 0\n"
                                     "SCALARS region int\nLOOKUP_TABLE my_table\n-9 3 -9 -4\n"
                                     "LOOKUP_TABLE my_table 1\n0 0 0 1\n"
                                     "FIELD FieldData 2\nother 1 4 int\n1 1 1 1\n"
                                     "patch 1 4 vtktypeint64\n6 0 8 0\n");
  TetMeshInput mesh = voroclip::read_tet_mesh(vtk);
  CHECK(mesh.tets == std::vector<std::uint32_t>{0, 1, 2, 3, 1, 2, 3, 4});
  CHECK(mesh.tet_ref == std::vector<std::int32_t>{3, -4});
  CHECK(mesh.triangles == std::vector<std::uint32_t>{0, 1, 2, 1, 2, 3});
  CHECK(mesh.triangle_ref == std::vector<std::int32_t>{6, 8});
  // XML: region on tets only, the value on the triangle (-1) is not read.
  const std::string vtu = write_temp(
      "tags.vtu", vtu_file("",
                           "<Points>\n<DataArray type=\"Float32\" NumberOfComponents=\"3\" "
                           "format=\"ascii\">0 0 0 1 0 0 0 1 0 0 0 1 1 1 1</DataArray>\n"
                           "</Points>\n<Cells>\n<DataArray type=\"Int32\" "
                           "Name=\"connectivity\" format=\"ascii\">0 1 2 3 1 2 3 4 0 1 2"
                           "</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" "
                           "format=\"ascii\">4 8 11</DataArray>\n<DataArray type=\"UInt8\" "
                           "Name=\"types\" format=\"ascii\">10 10 5</DataArray>\n</Cells>\n"
                           "<CellData>\n<DataArray type=\"Float64\" Name=\"region\" "
                           "format=\"ascii\">2 1 -1</DataArray>\n<DataArray type=\"Int8\" "
                           "Name=\"patch\" format=\"ascii\">0 0 -3</DataArray>\n"
                           "</CellData>\n",
                           ""));
  mesh = voroclip::read_tet_mesh(vtu);
  CHECK(mesh.tet_ref == std::vector<std::int32_t>{2, 1});
  CHECK(mesh.triangles == std::vector<std::uint32_t>{0, 1, 2});
  CHECK(mesh.triangle_ref == std::vector<std::int32_t>{-3});
}

// A .vtu and a legacy .vtk as meshio 5 writes them (ASCII): two triangles, then two tets,
// with `cell_data` the CellData / FIELD arrays, each "name v0 v1 v2 v3" (Int64, per cell).
std::string meshio_vtu(const std::vector<std::string>& cell_data) {
  std::string text =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" "
      "byte_order=\"LittleEndian\">\n<!--This file was created by meshio v5.0.0-->\n"
      "<UnstructuredGrid>\n<Piece NumberOfPoints=\"5\" NumberOfCells=\"4\">\n<Points>\n"
      "<DataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\" "
      "format=\"ascii\">\n0 0 0 1 0 0 0 1 0 0 0 1 1 1 1\n</DataArray>\n</Points>\n<Cells>\n"
      "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n"
      "0 2 1 0 1 3 0 1 2 3 1 2 3 4\n</DataArray>\n"
      "<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n3 6 10 14\n</DataArray>\n"
      "<DataArray type=\"Int64\" Name=\"types\" format=\"ascii\">\n5 5 10 10\n</DataArray>\n"
      "</Cells>\n<CellData>\n";
  for (const std::string& a : cell_data) {
    const std::size_t blank = a.find(' ');
    text += "<DataArray type=\"Int64\" Name=\"" + a.substr(0, blank) + "\" format=\"ascii\">\n" +
            a.substr(blank + 1) + "\n</DataArray>\n";
  }
  return text + "</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
}

std::string meshio_vtk(const std::vector<std::string>& cell_data) {
  std::string text =
      "# vtk DataFile Version 5.1\nwritten by meshio v5.0.0\nASCII\nDATASET UNSTRUCTURED_GRID\n"
      "POINTS 5 double\n0.0 0.0 0.0 1.0 0.0 0.0 0.0 1.0 0.0 0.0 0.0 1.0 1.0 1.0 1.0\n"
      "CELLS 5 14\nOFFSETS vtktypeint64\n0\n3\n6\n10\n14\nCONNECTIVITY vtktypeint64\n"
      "0\n2\n1\n0\n1\n3\n0\n1\n2\n3\n1\n2\n3\n4\nCELL_TYPES 4\n5\n5\n10\n10\n"
      "CELL_DATA 4\nFIELD FieldData " +
      std::to_string(cell_data.size()) + "\n";
  for (const std::string& a : cell_data) {
    const std::size_t blank = a.find(' ');
    text += a.substr(0, blank) + " 1 4 vtktypeint64\n" + a.substr(blank + 1) + "\n";
  }
  return text;
}

TEST_CASE("read_tet_mesh: meshio's tags in .vtu and .vtk, gmsh:physical and medit:ref",
          "[core][regression]") {
  // A .msh or .mesh converted by meshio keeps its tags as the cell data gmsh:physical
  // (gmsh:geometrical holds the entities) or medit:ref, one array for every cell; they were
  // dropped, and a two-region mesh read as one region without interfaces.
  using Arrays = std::vector<std::string>;
  const std::vector<std::pair<std::string, Arrays>> cases = {
      {"gmsh", {"gmsh:physical 7 8 1 2", "gmsh:geometrical 3 4 5 6"}},
      {"gmsh_reversed", {"gmsh:geometrical 3 4 5 6", "gmsh:physical 7 8 1 2"}},
      {"medit", {"medit:ref 7 8 1 2"}},
      // The first of region / gmsh:physical / medit:ref for the tets, of patch /
      // gmsh:physical / medit:ref for the triangles.
      {"region", {"medit:ref 0 0 9 9", "region 0 0 1 2", "gmsh:physical 7 8 5 5"}},
      {"patch", {"patch 7 8 0 0", "medit:ref 9 9 1 2"}},
  };
  for (const auto& [name, arrays] : cases) {
    for (const bool xml : {true, false}) {
      INFO(name << (xml ? ".vtu" : ".vtk"));
      const std::string path = write_temp("meshio_" + name + (xml ? ".vtu" : ".vtk"),
                                          xml ? meshio_vtu(arrays) : meshio_vtk(arrays));
      const TetMeshInput mesh = voroclip::read_tet_mesh(path);
      CHECK(mesh.tets == std::vector<std::uint32_t>{0, 1, 2, 3, 1, 2, 3, 4});
      CHECK(mesh.triangles == std::vector<std::uint32_t>{0, 2, 1, 0, 1, 3});
      CHECK(mesh.tet_ref == std::vector<std::int32_t>{1, 2});
      CHECK(mesh.triangle_ref == std::vector<std::int32_t>{7, 8});
    }
  }
  // Integer cell data of other names is not a tag.
  for (const bool xml : {true, false}) {
    const Arrays other = {"gmsh:geometrical 3 4 5 6", "material 1 1 2 2"};
    const TetMeshInput mesh =
        voroclip::read_tet_mesh(write_temp(std::string("meshio_other") + (xml ? ".vtu" : ".vtk"),
                                           xml ? meshio_vtu(other) : meshio_vtk(other)));
    CHECK(mesh.tet_ref.empty());
    CHECK(mesh.triangle_ref.empty());
  }
}

TEST_CASE("read_tet_mesh: triangle indices out of range name the element", "[core]") {
  std::string path = write_temp("trirange.mesh",
                                "MeshVersionFormatted 2\nVertices\n4\n0 0 0 0\n1 0 0 0\n"
                                "0 1 0 0\n0 0 1 0\nTriangles\n2\n1 2 3 1\n1 2 5 1\n"
                                "Tetrahedra\n1\n1 2 3 4 0\n");
  CHECK(error_of(path) == path + ":11: triangle 2: vertex 5 is out of range 1..4");
  write_temp("trirange.node", "4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n");
  write_temp("trirange.ele", "1 4 0\n0 0 1 2 3\n");
  write_temp("trirange.face", "2 1\n7 0 1 2 1\n8 1 2 4 1\n");
  CHECK(error_of(temp().file("trirange.ele")) ==
        temp().file("trirange.face") + ":3: face 8: vertex 4 is out of range 0..3");
  for (const char* version : {"2.2", "4.1"}) {
    INFO(version);
    const bool v2 = std::string(version) == "2.2";
    path = write_temp(std::string("trirange") + version + ".msh",
                      std::string("$MeshFormat\n") + version + " 0 8\n$EndMeshFormat\n" +
                          (v2 ? "$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n"
                                "$Elements\n2\n1 4 0 1 2 3 4\n12 2 2 5 1 1 2 9\n$EndElements\n"
                              : "$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n0 1 0\n"
                                "0 0 1\n$EndNodes\n$Elements\n2 2 1 12\n3 1 4 1\n1 1 2 3 4\n"
                                "2 1 2 1\n12 1 2 9\n$EndElements\n"));
    CHECK(error_of(path) ==
          path + (v2 ? ":14" : ":21") + ": element 12: node 9 is not in section $Nodes");
  }
  path = write_temp("trirange.vtk",
                    "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                    "POINTS 4 double\n0 0 0 1 0 0 0 1 0 0 0 1\nCELLS 2 9\n4 0 1 2 3\n3 0 1 4\n"
                    "CELL_TYPES 2\n10 5\n");
  CHECK(error_of(path) == path + ":9: cell 1: vertex 4 is out of range 0..3");
  const std::string vtu = write_temp(
      "trirange.vtu",
      vtu_file("",
               "<Points>\n<DataArray type=\"Float32\" NumberOfComponents=\"3\" "
               "format=\"ascii\">0 0 0 1 0 0 0 1 0 0 0 1 1 1 1</DataArray>\n</Points>\n<Cells>\n"
               "<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">0 1 2 3 1 2 3 4 "
               "0 1 5</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">4 "
               "8 11</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">10 10 "
               "5</DataArray>\n</Cells>\n",
               ""));
  CHECK(error_of(vtu) == vtu + ":10: cell 2: point 5 is out of range 0..4");
}

TEST_CASE("read_tet_mesh: tags that are not 32-bit integers", "[core]") {
  std::string bad = kOneTetMedit;
  bad.replace(bad.find("1 2 3 4 0"), 9, "1 2 3 4 1.5");
  std::string path = write_temp("tag1.mesh", bad);
  CHECK(error_of(path) == path + ":11: '1.5' is not a valid reference (an integer)");
  bad = kOneTetMedit;
  bad.replace(bad.find("1 2 3 4 0"), 9, "1 2 3 4 2147483648");
  path = write_temp("tag2.mesh", bad);
  CHECK(error_of(path) == path +
                              ":11: '2147483648' is not a valid reference (out of the range of a "
                              "32-bit integer)");
  write_temp("tag.node", "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n");
  write_temp("tag.ele", "1 4 1\n1 1 2 3 4 0.5\n");
  CHECK(error_of(temp().file("tag.ele")) ==
        temp().file("tag.ele") + ":2: '0.5' is not a valid region attribute (a 32-bit integer)");
  path = write_temp("tag.vtk",
                    "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                    "POINTS 4 double\n0 0 0 1 0 0 0 1 0 0 0 1\nCELLS 1 5\n4 0 1 2 3\n"
                    "CELL_TYPES 1\n10\nCELL_DATA 1\nSCALARS region double\n1e10\n");
  CHECK(error_of(path) == path +
                              ":13: SCALARS region: cell 0: '1e10' is not a tag (a 32-bit "
                              "integer)");
  path = write_temp("tag_count.vtk",
                    "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                    "POINTS 4 double\n0 0 0 1 0 0 0 1 0 0 0 1\nCELLS 1 5\n4 0 1 2 3\n"
                    "CELL_TYPES 1\n10\nCELL_DATA 2\n");
  CHECK(error_of(path) == path + ":11: CELL_DATA 2: CELLS has 1 cell");
  path = write_temp("tag.msh",
                    "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 1 volume\n"
                    "$EndPhysicalNames\n");
  CHECK(error_of(path) == path + ":6: physical name 'volume': expected a name in double quotes");
}

TEST_CASE("write_tet_mesh: tag and triangle errors name the file", "[core]") {
  TetMeshInput mesh = voroclip_test::tagged_kuhn_cube();
  const std::string path = temp().file("bad_tags.mesh");
  mesh.tet_ref.pop_back();
  CHECK(write_error(path, mesh, TetMeshFormat::kMedit) ==
        "cannot write '" + path + "': tet_ref has 5 tags for 6 tets (empty, or one tag per tet)");
  mesh = voroclip_test::tagged_kuhn_cube();
  mesh.triangles[31] = 9;
  CHECK(write_error(path, mesh, TetMeshFormat::kMedit) ==
        "cannot write '" + path + "': triangle 10 has vertex 9, the mesh has 9 vertices");
  mesh.triangles.pop_back();
  CHECK(write_error(path, mesh, TetMeshFormat::kMedit) ==
        "cannot write '" + path +
            "': the mesh arrays hold 27 coordinates, 24 tet indices and 35 triangle indices "
            "(multiples of 3, 4 and 3 needed)");
  mesh = voroclip_test::tagged_kuhn_cube();
  const std::string msh = temp().file("bad_tags.msh");
  mesh.tag_names.push_back({2, 3, "say \"hi\""});
  CHECK(write_error(msh, mesh, TetMeshFormat::kGmsh41) ==
        "cannot write '" + msh +
            "' (Gmsh): the name of tag 3 of dimension 2: a name cannot hold '\"' or a line break");
  mesh.tag_names.back() = {3, 0, "zero"};
  CHECK(write_error(msh, mesh, TetMeshFormat::kGmsh22) ==
        "cannot write '" + msh +
            "' (Gmsh): the name of tag 0 of dimension 3: physical tags are positive");
  CHECK_FALSE(std::filesystem::exists(path));
  CHECK_FALSE(std::filesystem::exists(msh));
}

// ---------------------------------------------------------------------------------------
// Compressed .vtu, binary .msh and BINARY .vtk: hand-made files for each layout, every
// truncation and every corrupted byte of them, counts and sizes that the bytes after them
// cannot hold.

namespace {

// Bytes of one value, in either byte order.
template <class T>
std::string bytes_one(T v, bool big_endian) {
  return bytes_of(std::vector<T>{v}, big_endian);
}

// An array's bytes zlib-compressed as VTK lays them out: {header, blocks}, `block` bytes per
// block, header words UInt32 or UInt64.
std::pair<std::string, std::string> vtk_zlib(const std::string& bytes, std::size_t block,
                                             bool header64, bool big) {
  const auto word = [&](std::uint64_t v) {
    return header64 ? bytes_one<std::uint64_t>(v, big)
                    : bytes_one<std::uint32_t>(static_cast<std::uint32_t>(v), big);
  };
  const std::size_t nb_blocks = (bytes.size() + block - 1) / block;
  std::string header = word(nb_blocks) + word(block) + word(bytes.size() % block), data;
  for (std::size_t b = 0; b < nb_blocks; ++b) {
    const std::size_t size = std::min(block, bytes.size() - b * block);
    uLongf packed = compressBound(static_cast<uLong>(size));
    std::string z(packed, '\0');
    REQUIRE(compress2(reinterpret_cast<Bytef*>(z.data()), &packed,
                      reinterpret_cast<const Bytef*>(bytes.data() + b * block),
                      static_cast<uLong>(size), 9) == Z_OK);
    z.resize(packed);
    header += word(packed);
    data += z;
  }
  return {header, data};
}

enum class VtuLayout { kInline, kAppendedRaw, kAppendedBase64 };

// The two tets and the triangle of kVtuXyz.. with region tags {1, 2, 0}, compressed.
std::string compressed_vtu(VtuLayout layout, bool header64, bool big, std::size_t block) {
  const std::vector<std::int32_t> region = {1, 2, 0};
  const std::string arrays[] = {bytes_of(kVtuXyz, big), bytes_of(kVtuConn, big),
                                bytes_of(kVtuOffsets, big), bytes_of(kVtuTypes, big),
                                bytes_of(region, big)};
  const char* types[] = {"Float64", "Int32", "Int32", "UInt8", "Int32"};
  const char* names[] = {"Points", "connectivity", "offsets", "types", "region"};
  std::string xml[5], appended;
  for (int i = 0; i < 5; ++i) {
    const auto [header, data] = vtk_zlib(arrays[i], block, header64, big);
    std::string head = std::string("<DataArray type=\"") + types[i] + "\" Name=\"" + names[i] +
                       "\" NumberOfComponents=\"" + (i == 0 ? "3" : "1") + "\" ";
    if (layout == VtuLayout::kInline) {
      xml[i] = head + "format=\"binary\">\n" + base64(header) + base64(data) + "\n</DataArray>\n";
    } else {
      xml[i] = head + "format=\"appended\" offset=\"" + std::to_string(appended.size()) + "\"/>\n";
      appended += layout == VtuLayout::kAppendedRaw ? header + data : base64(header) + base64(data);
    }
  }
  return vtu_file(std::string("version=\"1.0\" compressor=\"vtkZLibDataCompressor\" ") +
                      "byte_order=\"" + (big ? "Big" : "Little") + "Endian\" header_type=\"" +
                      (header64 ? "UInt64" : "UInt32") + "\"",
                  "<Points>\n" + xml[0] + "</Points>\n<Cells>\n" + xml[1] + xml[2] + xml[3] +
                      "</Cells>\n<CellData>\n" + xml[4] + "</CellData>\n",
                  layout == VtuLayout::kInline
                      ? ""
                      : std::string("<AppendedData encoding=\"") +
                            (layout == VtuLayout::kAppendedRaw ? "raw" : "base64") + "\">\n_" +
                            appended + "\n</AppendedData>\n");
}

// Every prefix of `content` and `content` with each byte set to 0xff or 0x00: read_tet_mesh
// either throws voroclip::Error or (a prefix that still holds the whole mesh) reads `full`.
void check_truncated_and_corrupted(const std::string& name, const std::string& content,
                                   const TetMeshInput& full) {
  const std::string path = temp().file(name);
  std::size_t errors = 0;
  for (std::size_t n = 0; n < content.size(); ++n) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << content.substr(0, n);
    try {
      const TetMeshInput m = voroclip::read_tet_mesh(path);
      INFO(name << " cut to " << n << " of " << content.size() << " bytes");
      CHECK(m.xyz == full.xyz);
      CHECK(m.tets == full.tets);
      CHECK(m.triangles == full.triangles);
    } catch (const voroclip::Error&) {
      ++errors;
    }
  }
  CHECK(errors > content.size() / 2);
  for (std::size_t i = 0; i < content.size(); ++i) {
    for (const char c : {'\xff', '\0'}) {
      std::string bad = content;
      bad[i] = c;
      std::ofstream(path, std::ios::binary | std::ios::trunc) << bad;
      try {
        voroclip::read_tet_mesh(path);
      } catch (const voroclip::Error&) {
      }
    }
  }
}

}  // namespace

TEST_CASE("read_tet_mesh: zlib-compressed .vtu, inline and appended, every header", "[core]") {
  for (const VtuLayout layout :
       {VtuLayout::kInline, VtuLayout::kAppendedRaw, VtuLayout::kAppendedBase64}) {
    for (const bool header64 : {false, true}) {
      for (const bool big : {false, true}) {
        // Blocks of 16 bytes: several blocks per array and a short last block; 32768: one.
        for (const std::size_t block : {std::size_t{16}, std::size_t{24}, std::size_t{32768}}) {
          INFO("layout " << static_cast<int>(layout) << ", UInt" << (header64 ? 64 : 32) << ", "
                         << (big ? "big" : "little") << " endian, blocks of " << block);
          const std::string path =
              write_temp("zlib.vtu", compressed_vtu(layout, header64, big, block));
          const TetMeshInput mesh = voroclip::read_tet_mesh(path);
          CHECK(mesh.xyz == kVtuXyz);
          CHECK(mesh.tets == std::vector<std::uint32_t>{0, 1, 2, 3, 1, 2, 3, 4});
          CHECK(mesh.triangles == std::vector<std::uint32_t>{0, 1, 2});
          CHECK(mesh.tet_ref == std::vector<std::int32_t>{1, 2});
        }
      }
    }
  }
  SECTION("the writer's compressed file: header and blocks as VTK lays them out") {
    const TetMeshInput mesh = voroclip_test::tagged_kuhn_cube();
    const std::string path = temp().file("written_zlib.vtu");
    voroclip::write_tet_mesh(path, mesh, TetMeshFormat::kVtuCompressed);
    const std::string text = file_text(path);
    CHECK(text.find("compressor=\"vtkZLibDataCompressor\"") != std::string::npos);
    // The Points array at offset 0: 9 points of 24 bytes in one block of 32768 bytes.
    const std::size_t underscore = text.find('_', text.find("<AppendedData"));
    CHECK(text.substr(underscore + 1, 32).substr(0, 24) ==
          base64(bytes_of(std::vector<std::uint64_t>{1, 32768, 216}, false)).substr(0, 24));
    const TetMeshInput back = voroclip::read_tet_mesh(path);
    CHECK(back.xyz == mesh.xyz);
    CHECK(back.tets == mesh.tets);
    CHECK(back.tet_ref == mesh.tet_ref);
    CHECK(back.triangle_ref == mesh.triangle_ref);
  }
  SECTION("every truncation and corrupted byte: an Error or the whole mesh") {
    TetMeshInput full;
    full.xyz = kVtuXyz;
    full.tets = {0, 1, 2, 3, 1, 2, 3, 4};
    full.triangles = {0, 1, 2};
    check_truncated_and_corrupted("cut_inline.vtu",
                                  compressed_vtu(VtuLayout::kInline, false, false, 16), full);
    check_truncated_and_corrupted("cut_raw.vtu",
                                  compressed_vtu(VtuLayout::kAppendedRaw, true, true, 16), full);
  }
}

TEST_CASE("read_tet_mesh: compressed .vtu headers checked against the data", "[core]") {
  // One Points array (line 6) of 15 doubles, its header and blocks given by hand.
  const auto file = [](const std::string& nb_points, const std::string& header,
                       const std::string& data) {
    return write_temp("zbad.vtu",
                      "<?xml version=\"1.0\"?>\n<!-- x -->\n<VTKFile type=\"UnstructuredGrid\" "
                      "compressor=\"vtkZLibDataCompressor\">\n<UnstructuredGrid>\n<Piece "
                      "NumberOfPoints=\"" +
                          nb_points +
                          "\" NumberOfCells=\"0\">\n<Points><DataArray type=\"Float64\" "
                          "NumberOfComponents=\"3\" format=\"binary\">" +
                          base64(header) + base64(data) +
                          "</DataArray></Points>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
  };
  const auto words = [](std::vector<std::uint32_t> w) { return bytes_of(w, false); };
  const auto [header, data] = vtk_zlib(bytes_of(kVtuXyz, false), 32768, false, false);
  const std::string good = file("5", header, data);
  // Points read, then what the file lacks.
  CHECK_THROWS_WITH(voroclip::read_tet_mesh(good),
                    good + ":5: Cells needs the data arrays connectivity, offsets and types");
  // 4 billion points announced: 96 GB, from a file of a few hundred bytes.
  std::string path = file("4000000000", header, data);
  CHECK(error_of(path) ==
        path + ":6: DataArray Points: 120 bytes once inflated, expected 96000000000");
  // A header announcing 2^30 blocks.
  path = file("5", words({1u << 30, 32768, 120}), data);
  CHECK(error_of(path) == path +
                              ":6: DataArray Points: the header announces 1073741824 "
                              "compressed blocks, more than the file can hold");
  // A block that claims 2^31 bytes from 20: more than deflate's 1032:1.
  path = file("5", words({1, 0x80000000u, 0, static_cast<std::uint32_t>(data.size())}), data);
  CHECK(error_of(path) == path + ":6: DataArray Points: block 0 claims 2147483648 bytes from " +
                              std::to_string(data.size()) +
                              " compressed bytes, more than zlib can inflate");
  // A compressed size beyond the data.
  path = file("5", words({1, 32768, 120, 5000}), data);
  CHECK(error_of(path) ==
        path + ":6: DataArray Points: block 0 is truncated: 5000 bytes needed, at most " +
            std::to_string(base64(data).size() / 4 * 3) + " left");  // 3 per 4 characters
  // The block inflates to 120 bytes, the header says 100, then 200.
  path = file("5", words({1, 32768, 100, static_cast<std::uint32_t>(data.size())}), data);
  CHECK(error_of(path) == path +
                              ":6: DataArray Points: block 0: inflates to more than the 100 "
                              "bytes the header says");
  path = file("5", words({1, 32768, 200, static_cast<std::uint32_t>(data.size())}), data);
  CHECK(error_of(path) ==
        path + ":6: DataArray Points: block 0: inflates to 120 bytes, the header says 200");
  // Not zlib data.
  const std::string junk(data.size(), 'x');
  path = file("5", words({1, 32768, 120, static_cast<std::uint32_t>(junk.size())}), junk);
  CHECK(error_of(path) == path + ":6: DataArray Points: block 0: not valid zlib data (data error)");
  // A last block larger than the block size.
  path = file("5", words({1, 16, 120, static_cast<std::uint32_t>(data.size())}), data);
  CHECK(error_of(path) == path +
                              ":6: DataArray Points: the last block has 120 bytes, more than "
                              "the block size 16");
  // Uncompressed: a byte count from the header that the base64 text cannot hold.
  path = write_temp("big.vtu", vtu_file("",
                                        "<Points><DataArray type=\"Float64\" "
                                        "NumberOfComponents=\"3\" format=\"binary\">" +
                                            base64(words({120})) + "</DataArray></Points>\n",
                                        ""));
  CHECK(error_of(path) ==
        path + ":6: DataArray Points: the data is truncated: 120 bytes needed, at most 0 left");
}

namespace {

// Binary MSH 2.2 by hand: the nodes 10, 20, .. 50 (kVtuXyz), a line (type 1, skipped), two
// tets (physical 3 and 4) and a triangle (physical 9), in either byte order.
std::string gmsh22_binary(bool big) {
  const auto i32 = [&](std::int32_t v) { return bytes_one<std::int32_t>(v, big); };
  std::string s = "$MeshFormat\n2.2 1 8\n" + i32(1) +
                  "\n$EndMeshFormat\n$PhysicalNames\n1\n3 "
                  "3 \"steel\"\n$EndPhysicalNames\n$Nodes\n5\n";
  for (int i = 0; i < 5; ++i) {
    s += i32(10 * (i + 1));
    for (int k = 0; k < 3; ++k) s += bytes_one<double>(kVtuXyz[3 * i + k], big);
  }
  s += "\n$EndNodes\n$Elements\n4\n";
  s += i32(1) + i32(1) + i32(2) + i32(7) + i32(0) + i32(0) + i32(10) + i32(20);  // a line
  s += i32(4) + i32(2) + i32(2);                                                 // two tets
  s += i32(1) + i32(3) + i32(1) + i32(10) + i32(20) + i32(30) + i32(40);
  s += i32(2) + i32(4) + i32(1) + i32(20) + i32(30) + i32(40) + i32(50);
  s += i32(2) + i32(1) + i32(2) + i32(3) + i32(9) + i32(5) + i32(10) + i32(20) + i32(30);
  return s + "\n$EndElements\n$NodeData\n" + std::string("\n\x01$\0\n", 5) + "$EndNodeData\n";
}

// Binary MSH 4.1 by hand, size_t of `st` bytes: a surface entity 5 (physical 10) and a
// volume 7 (physical 3); nodes in two blocks, the second parametric on the surface; a
// triangle, a line (skipped), two tets.
std::string gmsh41_binary(bool big, std::size_t st) {
  const auto i32 = [&](std::int32_t v) { return bytes_one<std::int32_t>(v, big); };
  const auto z = [&](std::uint64_t v) {
    return st == 8 ? bytes_one<std::uint64_t>(v, big)
                   : bytes_one<std::uint32_t>(static_cast<std::uint32_t>(v), big);
  };
  const auto d = [&](double v) { return bytes_one<double>(v, big); };
  std::string s = "$MeshFormat\n4.1 1 " + std::to_string(st) + "\n" + i32(1) +
                  "\n$EndMeshFormat\n$Entities\n" + z(0) + z(0) + z(1) + z(1);
  s += i32(5) + d(0) + d(0) + d(0) + d(1) + d(1) + d(1) + z(1) + i32(10) + z(0);
  s += i32(7) + d(0) + d(0) + d(0) + d(1) + d(1) + d(1) + z(1) + i32(3) + z(1) + i32(5);
  s += "\n$EndEntities\n$Nodes\n" + z(2) + z(5) + z(10) + z(50);
  s += i32(3) + i32(7) + i32(0) + z(3) + z(10) + z(20) + z(30);
  for (int i = 0; i < 3; ++i)
    s += d(kVtuXyz[3 * i]) + d(kVtuXyz[3 * i + 1]) + d(kVtuXyz[3 * i + 2]);
  s += i32(2) + i32(5) + i32(1) + z(2) + z(40) + z(50);
  for (int i = 3; i < 5; ++i) {
    s += d(kVtuXyz[3 * i]) + d(kVtuXyz[3 * i + 1]) + d(kVtuXyz[3 * i + 2]) + d(0.5) + d(0.25);
  }
  s += "\n$EndNodes\n$Elements\n" + z(3) + z(4) + z(1) + z(4);
  s += i32(2) + i32(5) + i32(2) + z(1) + z(1) + z(10) + z(20) + z(30);
  s += i32(1) + i32(9) + i32(1) + z(1) + z(2) + z(10) + z(20);
  s += i32(3) + i32(7) + i32(4) + z(2) + z(3) + z(10) + z(20) + z(30) + z(40) + z(4) + z(20) +
       z(30) + z(40) + z(50);
  return s + "\n$EndElements\n";
}

}  // namespace

TEST_CASE("read_tet_mesh: binary Gmsh 2.2 and 4.1, either byte order", "[core]") {
  for (const bool big : {false, true}) {
    INFO((big ? "big" : "little") << " endian");
    const TetMeshInput m22 = voroclip::read_tet_mesh(write_temp("b22.msh", gmsh22_binary(big)));
    CHECK(m22.xyz == kVtuXyz);
    CHECK(m22.tets == std::vector<std::uint32_t>{0, 1, 2, 3, 1, 2, 3, 4});
    CHECK(m22.tet_ref == std::vector<std::int32_t>{3, 4});
    CHECK(m22.tet_line == std::vector<std::uint32_t>{0, 0});
    CHECK(m22.triangles == std::vector<std::uint32_t>{0, 1, 2});
    CHECK(m22.triangle_ref == std::vector<std::int32_t>{9});
    CHECK(m22.tag_names == std::vector<TetMeshInput::TagName>{{3, 3, "steel"}});
    for (const std::size_t st : {std::size_t{4}, std::size_t{8}}) {
      INFO("size_t of " << st << " bytes");
      const TetMeshInput m41 =
          voroclip::read_tet_mesh(write_temp("b41.msh", gmsh41_binary(big, st)));
      CHECK(m41.xyz == kVtuXyz);
      CHECK(m41.tets == std::vector<std::uint32_t>{0, 1, 2, 3, 1, 2, 3, 4});
      CHECK(m41.tet_ref == std::vector<std::int32_t>{3, 3});
      CHECK(m41.triangles == std::vector<std::uint32_t>{0, 1, 2});
      CHECK(m41.triangle_ref == std::vector<std::int32_t>{10});
    }
  }
  TetMeshInput full;
  full.xyz = kVtuXyz;
  full.tets = {0, 1, 2, 3, 1, 2, 3, 4};
  full.triangles = {0, 1, 2};
  check_truncated_and_corrupted("cut22.msh", gmsh22_binary(true), full);
  check_truncated_and_corrupted("cut41.msh", gmsh41_binary(false, 8), full);
}

TEST_CASE("read_tet_mesh: binary Gmsh errors name the section and the element", "[core]") {
  const auto at = [](const std::string& s, const std::string& from, const std::string& with) {
    std::string out = s;
    const std::size_t p = out.find(from);
    REQUIRE(p != std::string::npos);
    return out.replace(p, from.size(), with);
  };
  const std::string s22 = gmsh22_binary(false);
  std::string path = write_temp("e1.msh", at(s22, "$Nodes\n5\n", "$Nodes\n50000000\n"));
  CHECK(error_of(path) == path +
                              ": section $Nodes: 50000000 nodes needs 1400000000 bytes, the "
                              "file has " +
                              std::to_string(s22.size() - s22.find("$Nodes\n5\n") - 9) + " left");
  // Node 50 replaced by 60 in the second tet.
  const std::string tet2 = bytes_of(std::vector<std::int32_t>{40, 50}, false);
  path = write_temp("e2.msh", at(s22, tet2, bytes_of(std::vector<std::int32_t>{40, 60}, false)));
  CHECK(error_of(path) == path + ": element 2: node 60 is not in section $Nodes");
  // An element type Gmsh does not know.
  const std::string line = bytes_of(std::vector<std::int32_t>{1, 1, 2, 7}, false);
  path =
      write_temp("e3.msh", at(s22, line, bytes_of(std::vector<std::int32_t>{77, 1, 2, 7}, false)));
  CHECK(error_of(path) == path +
                              ": section $Elements: element type 77 is unknown (its node count "
                              "is needed to read a binary file)");
  path = write_temp("e4.msh", at(s22, "$EndNodes", "$EndNode$"));
  CHECK(error_of(path) ==
        path + ": section $Nodes: expected $EndNodes after its data, found '$EndNode$'");
  path = write_temp("e5.msh",
                    at(s22, std::string("8\n\x01\0\0\0", 6), std::string("8\n\x02\0\0\0", 6)));
  CHECK(error_of(path) ==
        path + ": $MeshFormat: the binary check reads 2, not 1 in either byte order");
  // 4.1: 2^40 nodes in a block, a file cut in $Elements.
  const std::string s41 = gmsh41_binary(false, 8);
  const std::string block1 =
      bytes_of(std::vector<std::int32_t>{3, 7, 0}, false) + bytes_one<std::uint64_t>(3, false);
  path = write_temp("e6.msh", at(s41, block1,
                                 bytes_of(std::vector<std::int32_t>{3, 7, 0}, false) +
                                     bytes_one<std::uint64_t>(std::uint64_t{1} << 40, false)));
  CHECK(error_of(path) ==
        path + ": section $Nodes: a block of 1099511627776 nodes after 0 of 5 nodes");
  path = write_temp("e7.msh", s41.substr(0, s41.size() - 30));
  CHECK(error_of(path) ==
        path + ": section $Elements: a block of 2 elements needs 80 bytes, the file has 64 left");
  path = write_temp("e9.msh", s41.substr(0, s41.find("$Elements\n") + 13));
  CHECK(error_of(path) == path + ": section $Elements is truncated: 8 more bytes needed, 3 left");
  path = write_temp("e8.msh", at(s41, "4.1 1 8", "4.1 1 2"));
  CHECK(error_of(path) == path + ": $MeshFormat: data-size '2': 4 or 8 (the size of size_t)");
}

TEST_CASE("write_tet_mesh: binary Gmsh 4.1 as Gmsh lays it out", "[core]") {
  const TetMeshInput mesh = voroclip_test::tagged_kuhn_cube();
  const std::string path = temp().file("facts41b.msh");
  voroclip::write_tet_mesh(path, mesh, TetMeshFormat::kGmsh41Binary);
  const std::string b = file_text(path);
  CHECK(b.rfind(std::string("$MeshFormat\n4.1 1 8\n\x01\0\0\0\n$EndMeshFormat\n", 40), 0) == 0);
  // $Entities: 0 points, 0 curves, 3 surfaces, 2 volumes, as size_t.
  CHECK(b.find("$Entities\n" + bytes_of(std::vector<std::uint64_t>{0, 0, 3, 2}, false)) !=
        std::string::npos);
  // $Nodes: two blocks, tags 1..9 in order: the cube's 8 corners on surface entity 1 (tag
  // 10, the lowest of their triangles'), the unused node on volume 1.
  const std::string nodes_8 = bytes_of(std::vector<std::uint64_t>{1, 2, 3, 4, 5, 6, 7, 8}, false);
  CHECK(b.find("$Nodes\n" + bytes_of(std::vector<std::uint64_t>{2, 9, 1, 9}, false) +
               bytes_of(std::vector<std::int32_t>{2, 1, 0}, false) +
               bytes_of(std::vector<std::uint64_t>{8}, false) + nodes_8 +
               bytes_of(std::vector<double>(mesh.xyz.begin(), mesh.xyz.begin() + 24), false) +
               bytes_of(std::vector<std::int32_t>{3, 1, 0}, false) +
               bytes_of(std::vector<std::uint64_t>{1, 9}, false) +
               bytes_of(std::vector<double>(mesh.xyz.begin() + 24, mesh.xyz.end()), false) +
               "\n$EndNodes\n") != std::string::npos);
  // The first element block: volume entity 1 (tag 1), tets, one element: 1, nodes 1 2 4 8.
  CHECK(b.find("$Elements\n" + bytes_of(std::vector<std::uint64_t>{11, 18, 1, 18}, false) +
               bytes_of(std::vector<std::int32_t>{3, 1, 4}, false) +
               bytes_of(std::vector<std::uint64_t>{1, 1, 1, 2, 4, 8}, false)) != std::string::npos);
  CHECK(b.size() >= 14);
  CHECK(b.substr(b.size() - 14) == "\n$EndElements\n");
}

namespace {

// BINARY legacy VTK by hand (big endian): kVtuXyz as float, the two tets and the triangle,
// classic or VTK 5.1 cells, CELL_DATA with SCALARS region and a FIELD with patch.
std::string vtk_binary(bool layout51) {
  std::string s = "# vtk DataFile Version " + std::string(layout51 ? "5.1" : "3.0") +
                  "\nmade by hand\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS 5 float\n";
  s += bytes_of(std::vector<float>(kVtuXyz.begin(), kVtuXyz.end()), true) + "\n";
  if (layout51) {
    s += "CELLS 4 11\nOFFSETS vtktypeint64\n" +
         bytes_of(std::vector<std::int64_t>{0, 4, 8, 11}, true) + "\nCONNECTIVITY vtktypeint32\n" +
         bytes_of(kVtuConn, true) + "\n";
  } else {
    s += "CELLS 3 14\n" +
         bytes_of(std::vector<std::int32_t>{4, 0, 1, 2, 3, 4, 1, 2, 3, 4, 3, 0, 1, 2}, true) + "\n";
  }
  s += "CELL_TYPES 3\n" + bytes_of(std::vector<std::int32_t>{10, 10, 5}, true) + "\n";
  s += "POINT_DATA 5\nVECTORS v double\n" + bytes_of(std::vector<double>(15, 0.5), true) + "\n";
  s += "CELL_DATA 3\nSCALARS region int 1\nLOOKUP_TABLE default\n" +
       bytes_of(std::vector<std::int32_t>{6, 7, 0}, true) + "\n";
  if (layout51) s += "METADATA\nINFORMATION 0\n\n";
  s += "FIELD FieldData 2\nnames 2 3 unsigned_char\nabcdef\npatch 1 3 vtktypeint16\n" +
       bytes_of(std::vector<std::int16_t>{0, 0, -5}, true) + "\n";
  return s;
}

}  // namespace

TEST_CASE("read_tet_mesh: BINARY legacy VTK, classic and 5.1 cell layouts", "[core]") {
  for (const bool layout51 : {false, true}) {
    INFO((layout51 ? "5.1" : "classic"));
    const std::string path = write_temp("bin_ok.vtk", vtk_binary(layout51));
    const TetMeshInput mesh = voroclip::read_tet_mesh(path);
    CHECK(mesh.xyz == kVtuXyz);
    CHECK(mesh.tets == std::vector<std::uint32_t>{0, 1, 2, 3, 1, 2, 3, 4});
    CHECK(mesh.tet_line == std::vector<std::uint32_t>{0, 0});
    CHECK(mesh.tet_ref == std::vector<std::int32_t>{6, 7});
    CHECK(mesh.triangles == std::vector<std::uint32_t>{0, 1, 2});
    CHECK(mesh.triangle_ref == std::vector<std::int32_t>{-5});
  }
  TetMeshInput full;
  full.xyz = kVtuXyz;
  full.tets = {0, 1, 2, 3, 1, 2, 3, 4};
  full.triangles = {0, 1, 2};
  check_truncated_and_corrupted("cut_classic.vtk", vtk_binary(false), full);
  check_truncated_and_corrupted("cut_51.vtk", vtk_binary(true), full);

  const auto with = [](const std::string& from, const std::string& to) {
    std::string s = vtk_binary(false);
    const std::size_t p = s.find(from);
    REQUIRE(p != std::string::npos);
    return write_temp("bin_bad.vtk", s.replace(p, from.size(), to));
  };
  std::string path = with("POINTS 5 float", "POINTS 4000000000 float");
  CHECK(error_of(path) == path +
                              ": POINTS: 12000000000 values needs 48000000000 bytes, the file "
                              "has " +
                              std::to_string(vtk_binary(false).size() - 88) +
                              " left");  // after POINTS
  path = with("CELL_TYPES 3\n" + bytes_of(std::vector<std::int32_t>{10}, true),
              "CELL_TYPES 3\n" + bytes_of(std::vector<std::int32_t>{5}, true));
  CHECK(error_of(path) == path + ": cell 0 of type 5 (triangle) has 4 points, not 3");
  path = with(bytes_of(std::vector<std::int32_t>{4, 1, 2, 3, 4}, true),
              bytes_of(std::vector<std::int32_t>{4, 1, 2, 3, 9}, true));
  CHECK(error_of(path) == path + ": cell 1: vertex 9 is out of range 0..4");
  path = with("SCALARS region int 1", "SCALARS region bit 1");
  CHECK(error_of(path) == path + ": SCALARS region: data type 'bit' is not read in a binary file");
}

// ---------------------------------------------------------------------------------------
// The stream overloads (the fuzz targets' entry points): the same mesh as from the file.

namespace {

void check_same_mesh(const TetMeshInput& a, const TetMeshInput& b) {
  CHECK(a.source == b.source);
  CHECK(a.xyz == b.xyz);
  CHECK(a.tets == b.tets);
  CHECK(a.tet_line == b.tet_line);
  CHECK(a.tet_ref == b.tet_ref);
  CHECK(a.triangles == b.triangles);
  CHECK(a.triangle_ref == b.triangle_ref);
  CHECK(a.tag_names == b.tag_names);
  CHECK(a.tet_label == b.tet_label);
  CHECK(a.vertex_label == b.vertex_label);
  CHECK(a.vertex_base == b.vertex_base);
  CHECK(a.numbering == b.numbering);
}

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

TEST_CASE("read_tet_mesh from a stream reads what read_tet_mesh reads from the file", "[core]") {
  const TetMeshInput mesh = voroclip_test::tagged_kuhn_cube();
  const std::pair<const char*, TetMeshFormat> cases[] = {
      {"s.mesh", TetMeshFormat::kMedit},
      {"s22.msh", TetMeshFormat::kGmsh22},
      {"s41.msh", TetMeshFormat::kGmsh41},
      {"s41b.msh", TetMeshFormat::kGmsh41Binary},
      {"s.vtk", TetMeshFormat::kVtk},
      {"s.vtu", TetMeshFormat::kVtu},
      {"sz.vtu", TetMeshFormat::kVtuCompressed},
      {"sa.vtu", TetMeshFormat::kVtuAscii},
  };
  for (const auto& [name, format] : cases) {
    INFO(name);
    const std::string path = temp().file(name);
    voroclip::write_tet_mesh(path, mesh, format);
    std::istringstream in(file_bytes(path));
    check_same_mesh(voroclip::read_tet_mesh(in, path), voroclip::read_tet_mesh(path));
  }
  SECTION("TetGen, with and without its .face file") {
    const std::string base = temp().file("stg");
    voroclip::write_tet_mesh(base + ".ele", mesh, TetMeshFormat::kTetGen);
    std::istringstream node(file_bytes(base + ".node")), ele(file_bytes(base + ".ele")),
        face(file_bytes(base + ".face"));
    check_same_mesh(voroclip::read_tetgen_mesh(node, ele, &face, base),
                    voroclip::read_tet_mesh(base + ".ele"));
    std::istringstream node2(file_bytes(base + ".node")), ele2(file_bytes(base + ".ele"));
    const TetMeshInput no_face = voroclip::read_tetgen_mesh(node2, ele2, nullptr, base);
    CHECK(no_face.tets == mesh.tets);
    CHECK(no_face.triangles.empty());
  }
  SECTION("the name's extension tells the format; TetGen and .meshb are refused by name") {
    const auto stream_error = [](const std::string& text, const std::string& name) {
      std::istringstream in(text);
      try {
        voroclip::read_tet_mesh(in, name);
      } catch (const voroclip::Error& e) {
        return std::string(e.what());
      }
      return std::string("(no error)");
    };
    CHECK(stream_error("", "a.ele") ==
          "a.ele: a TetGen mesh is several files: read it with read_tetgen_mesh");
    CHECK(stream_error("", "a.meshb") ==
          "a.meshb: binary Medit files (.meshb) are not read: convert to ASCII .mesh");
    CHECK(stream_error("", "a.xyz") ==
          "a.xyz: unknown tetrahedral mesh format '.xyz': expected "
          ".mesh, .node/.ele, .msh, .vtk or .vtu");
    CHECK(stream_error("", "in.mesh") ==
          "in.mesh:1: not a Medit mesh: expected MeshVersionFormatted, found an empty file");
  }
}

// ---------------------------------------------------------------------------------------
// Findings of the fuzz targets (fuzz/, scripts/fuzz.sh): each input, as the fuzzer made
// it, in tests/core/fuzz_regressions/, with the error it must get.

namespace {

const std::string kFuzzRegressions =
    std::string(VOROCLIP_SOURCE_DIR) + "/tests/core/fuzz_regressions/";

}  // namespace

TEST_CASE("fuzz regression: binary Gmsh nodes with a NaN coordinate are refused",
          "[core][regression]") {
  // fuzz_gmsh: a 2.2 binary file whose first node (tag 10) has the bits of a NaN as x; the reader
  // returned it (the ASCII readers refuse non-finite values).
  const std::string path = kFuzzRegressions + "gmsh22_binary_nan_coordinate.msh";
  CHECK(error_of(path) == path + ": section $Nodes: node 10: a coordinate is not finite");
  // The same in 4.1, node 40 (in the parametric block) with an infinite z.
  std::string s41 = gmsh41_binary(false, 8);
  // The second block's tags 40 and 50, then node 40's x, y, z.
  const std::size_t tags =
      s41.find(bytes_one<std::uint64_t>(40, false) + bytes_one<std::uint64_t>(50, false));
  REQUIRE(tags != std::string::npos);
  const std::size_t z = tags + 16 + 16;
  REQUIRE(s41.substr(z, 8) == bytes_one<double>(1.0, false));
  s41.replace(z, 8, bytes_one<double>(std::numeric_limits<double>::infinity(), false));
  const std::string path41 = write_temp("inf41.msh", s41);
  CHECK(error_of(path41) == path41 + ": section $Nodes: node 40: a coordinate is not finite");
}

TEST_CASE("fuzz regression: a negative Int64 in a .vtu array", "[core][regression]") {
  // fuzz_vtu: appended Int64 arrays with values whose sign bit is set; converting them to
  // signed overflowed a 64-bit integer (undefined behaviour, caught by UBSan: this test
  // fails in the ASan/UBSan stage without the fix). The file is refused for its offsets.
  const std::string path = kFuzzRegressions + "vtu_int64_negative.vtu";
  CHECK(error_of(path) == path +
                              ":10: offsets: cell 0 ends at 22521296671735808: not an offset (a "
                              "whole number from 0 to 2^53)");
  // fuzz_vtu, then: offsets and point indices are read as doubles and were converted to
  // integers before their range was checked (undefined for a negative or huge offset, as
  // the fuzzer's file has: its last offset is -4.6e18; a NaN index, from a Float64
  // connectivity, passed the range test). Now checked first; the NaN file is hand-made.
  const std::string offset = kFuzzRegressions + "vtu_negative_offset.vtu";
  CHECK(error_of(offset) == offset +
                                ":10: offsets: cell 0 ends at 4323455642275676160: not an offset "
                                "(a whole number from 0 to 2^53)");
  const std::string nan = kFuzzRegressions + "vtu_nan_point_index.vtu";
  CHECK(error_of(nan) == nan + ":7: cell 0: point nan is out of range 0..3");
}

TEST_CASE("fuzz regression: a .vtu DataArray that is never closed", "[core][regression]") {
  // fuzz_vtu: a binary DataArray without </DataArray> had its content end at "not closed"
  // (SIZE_MAX): the bytes left looked unbounded, 54 PB were reserved for the header it
  // announced, and base64 decoding would have read past the end of the file.
  const std::string path = kFuzzRegressions + "vtu_unclosed_data_array.vtu";
  CHECK(error_of(path) == path + ":6: DataArray Points is not closed");
}

TEST_CASE("read_tet_mesh: Medit Triangles that are no tet face are errors", "[core][regression]") {
  // Both were read and their refs dropped without a word (m_tris_degen.mesh,
  // m_tris_bogus.mesh of a user test).
  const std::string head =
      "MeshVersionFormatted 2\nDimension 3\nVertices\n5\n"
      "0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n1 1 1 0\nTetrahedra\n1\n1 2 3 4 0\nTriangles\n3\n"
      "1 2 3 1\n";
  std::string path = write_temp("tdegen.mesh", head + "4 3 2 1\n1 1 3 0\nEnd\n");
  CHECK(error_of(path) ==
        path +
            ":17: triangle 3: vertices 1 1 3 repeat a vertex (a degenerate triangle, the face "
            "of no tetrahedron)");
  path = write_temp("tbogus.mesh", head + "1 2 5 2\n4 3 2 0\nEnd\n");
  CHECK(error_of(path) == path +
                              ":16: triangle 2: vertices 1 2 5 are not a face of any tetrahedron "
                              "(Triangles lists boundary and interface faces)");
  path = write_temp("toob.mesh", head + "1 2 9999 0\n4 3 2 0\nEnd\n");
  CHECK(error_of(path) == path + ":16: triangle 2: vertex 9999 is out of range 1..5");
  // Faces in either orientation, and in a second Triangles section, are read.
  path = write_temp("tok.mesh", head + "2 4 3 7\n1 4 3 0\nTriangles\n1\n4 2 1 9\nEnd\n");
  const TetMeshInput mesh = voroclip::read_tet_mesh(path);
  CHECK(mesh.triangles == std::vector<std::uint32_t>{0, 1, 2, 1, 3, 2, 0, 3, 2, 3, 1, 0});
  CHECK(mesh.triangle_ref == std::vector<std::int32_t>{1, 7, 0, 9});
}

TEST_CASE("read_tet_mesh: a UTF-8 BOM, CR-only line ends, gzip, directories",
          "[core][regression]") {
  const std::string medit =
      "MeshVersionFormatted 2\nDimension 3\nVertices\n4\n"
      "0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\nTetrahedra\n1\n1 2 3 4 5\nEnd\n";
  const TetMeshInput bom = voroclip::read_tet_mesh(write_temp("bom.mesh", "\xef\xbb\xbf" + medit));
  CHECK(bom.tets == std::vector<std::uint32_t>{0, 1, 2, 3});
  CHECK(bom.tet_ref == std::vector<std::int32_t>{5});
  std::string cr = medit;
  std::replace(cr.begin(), cr.end(), '\n', '\r');
  const TetMeshInput crm = voroclip::read_tet_mesh(write_temp("cr.mesh", cr));
  CHECK(crm.tets == std::vector<std::uint32_t>{0, 1, 2, 3});
  CHECK(crm.tet_line == std::vector<std::uint32_t>{11});
  write_temp("bomtg.node",
             "\xef\xbb\xbf"
             "4 3 0 0\r1 0 0 0\r2 1 0 0\r3 0 1 0\r4 0 0 1\r");
  write_temp("bomtg.ele",
             "\xef\xbb\xbf"
             "1 4 0\n1 1 2 3 4\n");
  CHECK(voroclip::read_tet_mesh(temp().file("bomtg.ele")).tets ==
        std::vector<std::uint32_t>{0, 1, 2, 3});
  const std::string gz = write_temp("gz.mesh", std::string("\x1f\x8b\x08\x00\x01\x02", 6));
  CHECK(error_of(gz) == gz + ": the gzip data is truncated");
  // NAME.mesh.gz is read as a Medit file, compressed (Python's gzip.compress of `medit`,
  // mtime 0) or not.
  const std::string packed(
      "\x1f\x8b\x08\x00\x00\x00\x00\x00\x02\x03\x2d\x8a\x3b\x0e\x80\x20\x10\x44\xfb\x39\xc5\x1e\x81"
      "\x9f\x37\x50\x3b\x3b\x63\x4f\x64\x13\x28\x80\x64\xe1\xfe\x11\x09\x99\xe2\x4d\xde\xcc\xc5\x2d"
      "\x3e\x2c\x2d\xd5\x72\x56\xc9\xbe\x77\x0e\x64\xb0\xa7\xcc\xe5\x97\x64\x31\xe6\x9e\x5e\x6e\x70"
      "\x50\x34\x03\xbd\xa8\x48\x2f\xce\x86\x9b\xbb\xf8\xc8\x41\x3c\xf4\x38\x19\xb2\xe4\x68\xc3\x51"
      "\x02\x3e\xc7\x95\x12\x1c\x69\x00\x00\x00",
      102);
  for (const std::string& named : {write_temp("m.mesh.gz", medit), write_temp("z.mesh.gz", packed),
                                   write_temp("z.mesh", packed)}) {
    INFO(named);
    const TetMeshInput m = voroclip::read_tet_mesh(named);
    CHECK(m.tets == std::vector<std::uint32_t>{0, 1, 2, 3});
    CHECK(m.tet_ref == std::vector<std::int32_t>{5});
  }
  const std::string node = write_temp("t.node.gz", packed);
  CHECK(error_of(node) == node +
                              ": TetGen's files (.node, .ele, .face) are read uncompressed: "
                              "decompress them (gunzip)");
  const std::string dir = temp().file("tdir");
  std::filesystem::create_directories(dir);
  CHECK(error_of(dir) == dir + ": is a directory, not a file");
  std::filesystem::create_directories(dir + ".vtu");
  CHECK(error_of(dir + ".vtu") == dir + ".vtu: is a directory, not a file");
}

// ---------------------------------------------------------------------------------------
// Volume elements other than tets, second-order tets.

namespace {

const std::string kNotTets =
    ": only tetrahedral volume meshes are read; give the boundary surface "
    "(.obj/.stl/.ply/.off) or a tet mesh";

}  // namespace

// Regression: a tet mesh with hexahedra, prisms or pyramids was read as its tets alone,
// without a word (a domain of half the volume).
TEST_CASE("read_tet_mesh: volume elements other than tets are refused in every format", "[core]") {
  std::string path = write_temp("hex22.msh",
                                "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
                                "$Nodes\n8\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 0 0 1\n"
                                "6 1 0 1\n7 1 1 1\n8 0 1 1\n$EndNodes\n"
                                "$Elements\n5\n"
                                "1 4 0 1 2 4 5\n"
                                "7 5 0 1 2 3 4 5 6 7 8\n"
                                "3 2 0 1 2 3\n"
                                "8 5 0 1 2 3 4 5 6 7 8\n"
                                "9 6 0 1 2 3 5 6 7\n"
                                "$EndElements\n");
  CHECK(error_of(path) == path +
                              ":18: 2 hexahedra (the first element 7, type 5) and 1 prism "
                              "(element 9, type 6) are not tetrahedra" +
                              kNotTets);
  path = write_temp("pyr41.msh",
                    "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
                    "$Nodes\n1 5 1 5\n3 1 0 5\n1\n2\n3\n4\n5\n"
                    "0 0 0\n1 0 0\n0 1 0\n0 0 1\n0 0 -1\n$EndNodes\n"
                    "$Elements\n2 2 1 2\n3 1 4 1\n1 1 2 3 4\n3 1 7 1\n2 1 2 3 4 5\n"
                    "$EndElements\n");
  CHECK(error_of(path) ==
        path + ":23: 1 pyramid (element 2, type 7) is not a tetrahedron" + kNotTets);
  path = write_temp("pyr.vtk",
                    "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                    "POINTS 5 double\n0 0 0 1 0 0 0 1 0 0 0 1 0 0 -1\n"
                    "CELLS 2 11\n4 0 1 2 3\n5 0 1 2 3 4\nCELL_TYPES 2\n10\n14\n");
  CHECK(error_of(path) == path + ":9: 1 pyramid (cell 1, type 14) is not a tetrahedron" + kNotTets);
  path = write_temp(
      "hex.vtu",
      vtu_file("",
               "<Points>\n<DataArray type=\"Float32\" NumberOfComponents=\"3\" "
               "format=\"ascii\">0 0 0 1 0 0 0 1 0 0 0 1 1 1 1</DataArray>\n</Points>\n<Cells>\n"
               "<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">0 1 2 3 "
               "0 1 2 3 4 0 1 2 0 1 2 3 4 0</DataArray>\n<DataArray type=\"Int32\" "
               "Name=\"offsets\" format=\"ascii\">4 12 18</DataArray>\n<DataArray "
               "type=\"UInt8\" Name=\"types\" format=\"ascii\">10 12 13</DataArray>\n</Cells>\n",
               ""));
  CHECK(error_of(path) == path +
                              ":12: 1 hexahedron (cell 1, type 12) and 1 wedge (cell 2, type 13) "
                              "are not tetrahedra" +
                              kNotTets);
  std::string medit = kOneTetMedit;
  medit.replace(medit.find("End\n"), 4, "Hexahedra\n1\n1 2 3 4 1 2 3 4 0\nEnd\n");
  path = write_temp("hex.mesh", medit);
  CHECK(error_of(path) ==
        path + ":14: 1 hexahedron (Hexahedra entry 1) is not a tetrahedron" + kNotTets);
  // Quadrilaterals, lines and points are boundary and lower-dimensional elements: read past.
  path = write_temp("quad22.msh",
                    "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
                    "$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n"
                    "$Elements\n4\n1 4 0 1 2 3 4\n2 3 0 1 2 3 4\n3 1 0 1 2\n4 15 0 1\n"
                    "$EndElements\n");
  CHECK(voroclip::read_tet_mesh(path).tets == std::vector<std::uint32_t>{0, 1, 2, 3});
}

// Regression: 10-node tets were refused with "no tetrahedra (element type 4)".
TEST_CASE("read_tet_mesh: second-order tets and triangles read by their corners", "[core]") {
  // A 10-node tet (corners 1..4, then the mid-edge nodes 5..10) and a 6-node triangle.
  std::string nodes =
      "$Nodes\n10\n1 0 0 0\n2 2 0 0\n3 0 2 0\n4 0 0 2\n5 1 0 0\n6 1 1 0\n"
      "7 0 1 0\n8 0 0 1\n9 0 1 1\n10 1 0 1\n$EndNodes\n";
  std::string path = write_temp("o2_22.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n" + nodes +
                                                 "$Elements\n2\n"
                                                 "1 9 1 5 1 2 3 5 6 7\n"
                                                 "2 11 1 4 1 2 3 4 5 6 7 8 10 9\n"
                                                 "$EndElements\n");
  TetMeshInput mesh = voroclip::read_tet_mesh(path);
  CHECK(mesh.xyz.size() == 30);
  CHECK(mesh.tets == std::vector<std::uint32_t>{0, 1, 2, 3});
  CHECK(mesh.tet_ref == std::vector<std::int32_t>{4});
  CHECK(mesh.triangles == std::vector<std::uint32_t>{0, 1, 2});
  CHECK(mesh.triangle_ref == std::vector<std::int32_t>{5});
  // Counted, so that a user is told the curved elements are straight here.
  CHECK(mesh.nb_higher_order_tets == 1);
  CHECK(mesh.nb_higher_order_triangles == 1);
  path = write_temp("o2.vtk",
                    "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                    "POINTS 10 double\n0 0 0 2 0 0 0 2 0 0 0 2 1 0 0 1 1 0 0 1 0 0 0 1 0 1 1 "
                    "1 0 1\nCELLS 2 18\n10 0 1 2 3 4 5 6 7 9 8\n6 0 1 2 4 5 6\nCELL_TYPES 2\n"
                    "24\n22\n");
  mesh = voroclip::read_tet_mesh(path);
  CHECK(mesh.tets == std::vector<std::uint32_t>{0, 1, 2, 3});
  CHECK(mesh.triangles == std::vector<std::uint32_t>{0, 1, 2});
  CHECK(mesh.nb_higher_order_tets == 1);
  CHECK(mesh.nb_higher_order_triangles == 1);
  path = write_temp(
      "o2.vtu",
      "<VTKFile type=\"UnstructuredGrid\">\n<UnstructuredGrid>\n"
      "<Piece NumberOfPoints=\"10\" NumberOfCells=\"2\">\n"
      "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">"
      "0 0 0 2 0 0 0 2 0 0 0 2 1 0 0 1 1 0 0 1 0 0 0 1 0 1 1 1 0 1</DataArray>\n</Points>\n"
      "<Cells>\n<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">"
      "0 1 2 3 4 5 6 7 9 8 0 1 2 4 5 6</DataArray>\n"
      "<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">10 16</DataArray>\n"
      "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">24 22</DataArray>\n"
      "</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
  mesh = voroclip::read_tet_mesh(path);
  CHECK(mesh.tets == std::vector<std::uint32_t>{0, 1, 2, 3});
  CHECK(mesh.triangles == std::vector<std::uint32_t>{0, 1, 2});
  CHECK(mesh.nb_higher_order_tets == 1);
  CHECK(mesh.nb_higher_order_triangles == 1);
  // A quadratic tetra of 4 points is an error naming its type.
  path = write_temp("o2bad.vtk",
                    "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                    "POINTS 4 double\n0 0 0 2 0 0 0 2 0 0 0 2\nCELLS 1 5\n4 0 1 2 3\n"
                    "CELL_TYPES 1\n24\n");
  CHECK(error_of(path) == path + ":8: cell 0 of type 24 (quadratic tetra) has 4 points, not 10");
  // Medit TetrahedraP2 and TrianglesP2 (corners, then mid-edge vertices, then the ref) by
  // their corners, as the other formats' (they were refused: "which are not read").
  path = write_temp("p2.mesh",
                    "MeshVersionFormatted 2\nDimension 3\nVertices\n10\n0 0 0 0\n2 0 0 0\n"
                    "0 2 0 0\n0 0 2 0\n1 0 0 0\n1 1 0 0\n0 1 0 0\n0 0 1 0\n0 1 1 0\n"
                    "1 0 1 0\nTetrahedraP2\n1\n1 2 3 4 5 6 7 8 10 9 7\n"
                    "TrianglesP2\n1\n1 3 2 7 6 5 3\nEnd\n");
  mesh = voroclip::read_tet_mesh(path);
  CHECK(mesh.xyz.size() == 30);
  CHECK(mesh.tets == std::vector<std::uint32_t>{0, 1, 2, 3});
  CHECK(mesh.tet_ref == std::vector<std::int32_t>{7});
  CHECK(mesh.triangles == std::vector<std::uint32_t>{0, 2, 1});
  CHECK(mesh.triangle_ref == std::vector<std::int32_t>{3});
  CHECK(mesh.nb_higher_order_tets == 1);
  CHECK(mesh.nb_higher_order_triangles == 1);
  // A linear mesh has none.
  CHECK(voroclip::read_tet_mesh(kData + "sphere.mesh").nb_higher_order_tets == 0);
}

// Regression: a .vtu cut short inside the connectivity said "Cells needs the data arrays
// connectivity, offsets and types".
TEST_CASE("read_tet_mesh: a .vtu cut short inside Cells names the open DataArray", "[core]") {
  const std::string path = write_temp(
      "cut.vtu",
      "<VTKFile type=\"UnstructuredGrid\">\n<UnstructuredGrid>\n"
      "<Piece NumberOfPoints=\"4\" NumberOfCells=\"1\">\n"
      "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">"
      "0 0 0 1 0 0 0 1 0 0 0 1</DataArray>\n</Points>\n"
      "<Cells>\n<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n0 1 2");
  CHECK(error_of(path) == path + ":8: DataArray connectivity is not closed");
}
