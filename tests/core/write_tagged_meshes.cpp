// write_tagged_meshes DIR: writes the tagged Kuhn cube of tagged_mesh.h in every tet mesh
// format, and a variant whose tets are untagged, into DIR, with expected.json, what
// check_tags.py compares third-party readers (meshio, Gmsh) against:
//   DIR/<name>.mesh, .node/.ele/.face, 22.msh, 41.msh, 41b.msh (binary), .vtk, .vtu,
//   _ascii.vtu, _zlib.vtu (compressed)
//   DIR/expected.json  {"<name>": {"points": [[x, y, z]...], "tets": [[a, b, c, d]...],
//                      "tet_ref": [...], "triangles": [...], "triangle_ref": [...],
//                      "names": [[dimension, tag, name]...]}, ...}  (indices from 0; tag
//                      lists one per element, zeros for an empty tag vector)
// for <name> = tagged (two regions, three patches, four names) and patches_only.
//
// write_tagged_meshes --read FILE: prints what read_tet_mesh reads from FILE, as one
// mesh of expected.json, so that check_tags.py can check files other programs wrote.
#include <charconv>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "tagged_mesh.h"
#include "voroclip/core.h"

namespace {

using voroclip::TetMeshFormat;
using voroclip::TetMeshInput;

std::string number(double v) {
  char buf[32];
  return std::string(buf, std::to_chars(buf, buf + sizeof(buf), v).ptr);
}

// A JSON string for a name without control characters (the names of tagged_mesh.h).
std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string json_cells(const std::vector<std::uint32_t>& cells, std::size_t per) {
  std::string out = "[";
  for (std::size_t c = 0; c < cells.size() / per; ++c) {
    out += c == 0 ? "[" : ", [";
    for (std::size_t k = 0; k < per; ++k) {
      out += (k == 0 ? "" : ", ") + std::to_string(cells[per * c + k]);
    }
    out += "]";
  }
  return out + "]";
}

std::string json_tags(const std::vector<std::int32_t>& ref, std::size_t n) {
  std::string out = "[";
  for (std::size_t i = 0; i < n; ++i) {
    out += (i == 0 ? "" : ", ") + std::to_string(ref.empty() ? 0 : ref[i]);
  }
  return out + "]";
}

std::string json_mesh(const TetMeshInput& m) {
  std::string out = "{\"points\": [";
  for (std::size_t i = 0; i < m.nb_vertices(); ++i) {
    out += (i == 0 ? "[" : ", [") + number(m.xyz[3 * i]) + ", " + number(m.xyz[3 * i + 1]) + ", " +
           number(m.xyz[3 * i + 2]) + "]";
  }
  out += "],\n \"tets\": " + json_cells(m.tets, 4) +
         ",\n \"tet_ref\": " + json_tags(m.tet_ref, m.nb_tets()) +
         ",\n \"triangles\": " + json_cells(m.triangles, 3) +
         ",\n \"triangle_ref\": " + json_tags(m.triangle_ref, m.nb_triangles()) +
         ",\n \"names\": [";
  for (std::size_t i = 0; i < m.tag_names.size(); ++i) {
    const TetMeshInput::TagName& n = m.tag_names[i];
    out += (i == 0 ? "[" : ", [") + std::to_string(n.dimension) + ", " + std::to_string(n.tag) +
           ", " + json_string(n.name) + "]";
  }
  return out + "]}";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2 && !(argc == 3 && std::string(argv[1]) == "--read")) {
    std::cerr << "usage: write_tagged_meshes DIR | write_tagged_meshes --read FILE\n";
    return 2;
  }
  try {
    if (argc == 3) {
      std::cout << json_mesh(voroclip::read_tet_mesh(argv[2])) << '\n';
      return 0;
    }
    const std::filesystem::path dir = argv[1];
    std::filesystem::create_directories(dir);
    TetMeshInput patches_only = voroclip_test::tagged_kuhn_cube();
    patches_only.tet_ref.clear();
    const std::vector<std::pair<std::string, TetMeshInput>> meshes = {
        {"tagged", voroclip_test::tagged_kuhn_cube()}, {"patches_only", patches_only}};
    std::string json = "{";
    for (const auto& [name, mesh] : meshes) {
      const auto file = [&, &name = name](const std::string& suffix) {
        return (dir / (name + suffix)).string();
      };
      voroclip::write_tet_mesh(file(".mesh"), mesh, TetMeshFormat::kMedit);
      voroclip::write_tet_mesh(file(".node"), mesh, TetMeshFormat::kTetGen);
      voroclip::write_tet_mesh(file("22.msh"), mesh, TetMeshFormat::kGmsh22);
      voroclip::write_tet_mesh(file("41.msh"), mesh, TetMeshFormat::kGmsh41);
      voroclip::write_tet_mesh(file(".vtk"), mesh, TetMeshFormat::kVtk);
      voroclip::write_tet_mesh(file(".vtu"), mesh, TetMeshFormat::kVtu);
      voroclip::write_tet_mesh(file("_ascii.vtu"), mesh, TetMeshFormat::kVtuAscii);
      voroclip::write_tet_mesh(file("41b.msh"), mesh, TetMeshFormat::kGmsh41Binary);
      voroclip::write_tet_mesh(file("_zlib.vtu"), mesh, TetMeshFormat::kVtuCompressed);
      json += (json.size() == 1 ? "" : ",\n") + json_string(name) + ": " + json_mesh(mesh);
    }
    voroclip::write_file_atomically((dir / "expected.json").string(),
                                    [&](std::ostream& out) { out << json << "}\n"; });
  } catch (const std::exception& e) {
    std::cerr << "write_tagged_meshes: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
