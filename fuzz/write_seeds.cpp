// The seeding step of scripts/fuzz.sh: small meshes and surfaces written by the library's
// own writers in every format and encoding they have, one directory per fuzz target:
//   fuzz_write_seeds OUT  ->  OUT/fuzz_medit/cube.mesh, OUT/fuzz_gmsh/cube41b.msh, ...
// A cube of 5 tets (tags 1 and 2) with its 12 boundary triangles (tags 3..8), and the
// cube's surface. The TetGen seed is .node, .ele and .face joined by NUL bytes, as
// fuzz_tetgen.cpp splits its input.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include "voroclip/core.h"

namespace {

namespace fs = std::filesystem;

voroclip::TetMeshInput cube() {
  voroclip::TetMeshInput m;
  m.xyz = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1.5};
  m.tets = {0, 1, 3, 4, 1, 2, 3, 6, 1, 4, 5, 6, 3, 4, 6, 7, 1, 3, 4, 6};
  m.tet_ref = {1, 1, 1, 1, 2};
  m.triangles = {0, 3, 1, 1, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 4, 1, 5, 4,
                 2, 3, 6, 3, 7, 6, 1, 2, 6, 1, 6, 5, 0, 4, 3, 3, 4, 7};
  m.triangle_ref = {3, 3, 4, 4, 5, 5, 6, 6, 7, 7, 8, 8};
  m.tag_names = {{3, 1, "inside"}, {2, 3, "bottom"}};
  return m;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: fuzz_write_seeds OUT_DIR\n";
    return 2;
  }
  const fs::path out = argv[1];
  using F = voroclip::TetMeshFormat;
  const voroclip::TetMeshInput m = cube();
  const struct {
    const char* dir;
    const char* file;
    F format;
  } meshes[] = {
      {"fuzz_medit", "cube.mesh", F::kMedit},
      {"fuzz_gmsh", "cube22.msh", F::kGmsh22},
      {"fuzz_gmsh", "cube41.msh", F::kGmsh41},
      {"fuzz_gmsh", "cube41b.msh", F::kGmsh41Binary},
      {"fuzz_vtk", "cube.vtk", F::kVtk},
      {"fuzz_vtu", "cube_b64.vtu", F::kVtu},
      {"fuzz_vtu", "cube_ascii.vtu", F::kVtuAscii},
      {"fuzz_vtu", "cube_zlib.vtu", F::kVtuCompressed},
  };
  try {
    for (const auto& e : meshes) {
      fs::create_directories(out / e.dir);
      voroclip::write_tet_mesh((out / e.dir / e.file).string(), m, e.format);
    }
    const fs::path tmp = out / "tetgen_tmp";
    fs::create_directories(tmp);
    voroclip::write_tet_mesh((tmp / "cube.node").string(), m, F::kTetGen);
    fs::create_directories(out / "fuzz_tetgen");
    std::ofstream(out / "fuzz_tetgen" / "cube", std::ios::binary)
        << slurp(tmp / "cube.node") << '\0' << slurp(tmp / "cube.ele") << '\0'
        << slurp(tmp / "cube.face");
    std::ofstream(out / "fuzz_tetgen" / "cube_noface", std::ios::binary)
        << slurp(tmp / "cube.node") << '\0' << slurp(tmp / "cube.ele");
    fs::remove_all(tmp);

    const voroclip::TriangleSurface s = voroclip::tet_mesh_boundary(m);
    using S = voroclip::SurfaceFormat;
    const struct {
      const char* file;
      S format;
    } surfaces[] = {{"cube.obj", S::kObj},
                    {"cube.off", S::kOff},
                    {"cube_ascii.stl", S::kStlAscii},
                    {"cube_bin.stl", S::kStlBinary},
                    {"cube_ascii.ply", S::kPlyAscii},
                    {"cube_bin.ply", S::kPlyBinary}};
    fs::create_directories(out / "fuzz_surface");
    for (const auto& e : surfaces) {
      voroclip::write_surface((out / "fuzz_surface" / e.file).string(), s, e.format);
    }
  } catch (const std::exception& e) {
    std::cerr << "fuzz_write_seeds: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
