// mesh/src/mesh2_io.cpp — 2D triangle meshes (Mesh2) written as VTK .vtu, Medit .mesh and
// Gmsh .msh 2.2 / 4.1 (write_mesh2, mesh.h): the one writer of each, for the CLI's mesh2d
// and the Python package alike, so that both write the same bytes.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <ostream>
#include <string>
#include <vector>

#include "voroclip/mesh.h"

namespace voroclip {

namespace {

int vertex_ref(Mesh2::VertexKind k) {
  return k == Mesh2::VertexKind::kInterior ? 0 : k == Mesh2::VertexKind::kBoundary ? 1 : 2;
}

// VTK XML through core's write_vtu (one VTU writer for every mesh): the triangles then the
// boundary edges (lines); cell data `min_angle` (degrees; 0 on edges), `region` (a
// triangle's region; 0 on edges) and `patch` (an edge's boundary tag; 0 on triangles), the
// names and the zeros of mesh3d's tets and boundary triangles (TetMeshFormat::kVtk);
// point data `kind` (0 interior, 1 sliding, 2 fixed).
void write_vtu2(std::ostream& out, const Mesh2& mesh, VtuEncoding encoding) {
  const std::uint32_t nt = mesh.nb_triangles();
  const std::size_t ne = mesh.boundary_edges.size() / 2;
  std::vector<VtuCellField> fields(1);
  fields[0].name = "min_angle";
  fields[0].values = triangle_min_angles(mesh);
  fields[0].values.resize(nt + ne, 0.0);
  std::vector<VtuCellTags> tags(2);
  tags[0].name = "region";
  tags[0].values = mesh.triangle_regions;
  tags[0].values.resize(nt + ne, 0);
  tags[1].name = "patch";
  tags[1].values.assign(nt, 0);
  tags[1].values.insert(tags[1].values.end(), mesh.boundary_tags.begin(), mesh.boundary_tags.end());
  std::vector<VtuCellTags> kinds(1);
  kinds[0].name = "kind";
  for (const Mesh2::VertexKind k : mesh.vertex_kind) kinds[0].values.push_back(vertex_ref(k));
  const std::vector<VtuCellBlock> blocks = {{mesh.triangles.data(), nt, 3},
                                            {mesh.boundary_edges.data(), ne, 2}};
  write_vtu(out, mesh.xy.data(), mesh.nb_vertices(), 2, blocks, encoding, fields, tags, kinds);
}

// Medit: vertices with reference 0 interior, 1 sliding, 2 fixed; the boundary edges with
// their tags; the triangles with their regions.
void write_medit2(std::ostream& out, const Mesh2& mesh) {
  out << std::setprecision(17);
  out << "MeshVersionFormatted 2\n\nDimension 2\n\nVertices\n" << mesh.nb_vertices() << '\n';
  for (std::uint32_t v = 0; v < mesh.nb_vertices(); ++v) {
    out << mesh.xy[2 * v] << ' ' << mesh.xy[2 * v + 1] << ' ' << vertex_ref(mesh.vertex_kind[v])
        << '\n';
  }
  const std::vector<std::uint32_t>& edges = mesh.boundary_edges;
  out << "\nEdges\n" << edges.size() / 2 << '\n';
  for (std::size_t e = 0; e < edges.size(); e += 2) {
    out << edges[e] + 1 << ' ' << edges[e + 1] + 1 << ' ' << mesh.boundary_tags[e / 2] << '\n';
  }
  out << "\nTriangles\n" << mesh.nb_triangles() << '\n';
  for (std::uint32_t t = 0; t < mesh.nb_triangles(); ++t) {
    out << mesh.triangles[3 * t] + 1 << ' ' << mesh.triangles[3 * t + 1] + 1 << ' '
        << mesh.triangles[3 * t + 2] + 1 << ' ' << mesh.triangle_regions[t] << '\n';
  }
  out << "\nEnd\n";
}

// The distinct tags of a list, sorted.
std::vector<std::int32_t> distinct(std::vector<std::int32_t> tags) {
  std::sort(tags.begin(), tags.end());
  tags.erase(std::unique(tags.begin(), tags.end()), tags.end());
  return tags;
}

// Gmsh: boundary edges (type 1) in physical groups named "boundary <tag>", triangles (type
// 2) in groups named "region <tag>"; version 2.2 or 4.1 (one curve entity per boundary
// tag, one surface entity per region, each in its physical group), ASCII.
void write_gmsh2(std::ostream& out, const Mesh2& mesh, bool v41) {
  const std::vector<std::int32_t> btags = distinct(mesh.boundary_tags);
  const std::vector<std::int32_t> rtags = distinct(mesh.triangle_regions);
  // Gmsh physical tags are positive: Gmsh reads a tag 0 as no physical group (2.2 drops
  // the elements' group) and rejects negative ones.
  for (const std::int32_t t : btags) {
    if (t <= 0) {
      throw Error("write_mesh2: boundary tag " + std::to_string(t) +
                  ": a Gmsh .msh file takes only positive physical tags (write .vtu or .mesh "
                  "for any integer tag)");
    }
  }
  for (const std::int32_t t : rtags) {
    if (t <= 0) {
      throw Error("write_mesh2: region " + std::to_string(t) +
                  ": a Gmsh .msh file takes only positive physical tags (write .vtu or .mesh "
                  "for any integer tag)");
    }
  }
  const std::size_t ne = mesh.boundary_edges.size() / 2;
  const std::uint32_t nt = mesh.nb_triangles(), nv = mesh.nb_vertices();
  out << std::setprecision(17);
  out << "$MeshFormat\n" << (v41 ? "4.1" : "2.2") << " 0 8\n$EndMeshFormat\n";
  out << "$PhysicalNames\n" << btags.size() + rtags.size() << '\n';
  for (const std::int32_t t : btags) out << "1 " << t << " \"boundary " << t << "\"\n";
  for (const std::int32_t t : rtags) out << "2 " << t << " \"region " << t << "\"\n";
  out << "$EndPhysicalNames\n";
  const auto edge_line = [&](std::size_t e) {
    out << mesh.boundary_edges[2 * e] + 1 << ' ' << mesh.boundary_edges[2 * e + 1] + 1 << '\n';
  };
  const auto triangle_line = [&](std::uint32_t t) {
    out << mesh.triangles[3 * t] + 1 << ' ' << mesh.triangles[3 * t + 1] + 1 << ' '
        << mesh.triangles[3 * t + 2] + 1 << '\n';
  };
  if (!v41) {
    out << "$Nodes\n" << nv << '\n';
    for (std::uint32_t v = 0; v < nv; ++v) {
      out << v + 1 << ' ' << mesh.xy[2 * v] << ' ' << mesh.xy[2 * v + 1] << " 0\n";
    }
    out << "$EndNodes\n$Elements\n" << ne + nt << '\n';
    std::size_t id = 1;
    for (std::size_t e = 0; e < ne; ++e) {
      const std::int32_t t = mesh.boundary_tags[e];
      out << id++ << " 1 2 " << t << ' ' << t << ' ';
      edge_line(e);
    }
    for (std::uint32_t t = 0; t < nt; ++t) {
      const std::int32_t r = mesh.triangle_regions[t];
      out << id++ << " 2 2 " << r << ' ' << r << ' ';
      triangle_line(t);
    }
    out << "$EndElements\n";
    return;
  }
  // 4.1: entities (curves 1.. per boundary tag, surfaces 1.. per region) with their boxes.
  double lo[2] = {0, 0}, hi[2] = {0, 0};
  for (std::uint32_t v = 0; v < nv; ++v) {
    for (int c = 0; c < 2; ++c) {
      const double x = mesh.xy[2 * v + static_cast<std::uint32_t>(c)];
      lo[c] = v == 0 ? x : std::min(lo[c], x);
      hi[c] = v == 0 ? x : std::max(hi[c], x);
    }
  }
  const auto box = [&] { out << lo[0] << ' ' << lo[1] << " 0 " << hi[0] << ' ' << hi[1] << " 0"; };
  out << "$Entities\n0 " << btags.size() << ' ' << rtags.size() << " 0\n";
  for (std::size_t k = 0; k < btags.size(); ++k) {
    out << k + 1 << ' ';
    box();
    out << " 1 " << btags[k] << " 0\n";
  }
  for (std::size_t k = 0; k < rtags.size(); ++k) {
    out << k + 1 << ' ';
    box();
    out << " 1 " << rtags[k] << " 0\n";
  }
  out << "$EndEntities\n";
  // Nodes: one block, on the first surface.
  out << "$Nodes\n1 " << nv << " 1 " << nv << "\n2 1 0 " << nv << '\n';
  for (std::uint32_t v = 0; v < nv; ++v) out << v + 1 << '\n';
  for (std::uint32_t v = 0; v < nv; ++v)
    out << mesh.xy[2 * v] << ' ' << mesh.xy[2 * v + 1] << " 0\n";
  out << "$EndNodes\n$Elements\n"
      << btags.size() + rtags.size() << ' ' << ne + nt << " 1 " << ne + nt << '\n';
  std::size_t id = 1;
  for (std::size_t k = 0; k < btags.size(); ++k) {
    const std::size_t count = static_cast<std::size_t>(
        std::count(mesh.boundary_tags.begin(), mesh.boundary_tags.end(), btags[k]));
    out << "1 " << k + 1 << " 1 " << count << '\n';
    for (std::size_t e = 0; e < ne; ++e) {
      if (mesh.boundary_tags[e] != btags[k]) continue;
      out << id++ << ' ';
      edge_line(e);
    }
  }
  for (std::size_t k = 0; k < rtags.size(); ++k) {
    const std::size_t count = static_cast<std::size_t>(
        std::count(mesh.triangle_regions.begin(), mesh.triangle_regions.end(), rtags[k]));
    out << "2 " << k + 1 << " 2 " << count << '\n';
    for (std::uint32_t t = 0; t < nt; ++t) {
      if (mesh.triangle_regions[t] != rtags[k]) continue;
      out << id++ << ' ';
      triangle_line(t);
    }
  }
  out << "$EndElements\n";
}

}  // namespace

void write_mesh2(std::ostream& out, const Mesh2& mesh, Mesh2FileFormat format) {
  const std::size_t nt = mesh.nb_triangles(), nv = mesh.nb_vertices();
  const bool sizes_ok = mesh.triangles.size() == 3 * nt && mesh.vertex_kind.size() == nv &&
                        mesh.boundary_edges.size() % 2 == 0 &&
                        mesh.boundary_tags.size() * 2 == mesh.boundary_edges.size() &&
                        mesh.triangle_regions.size() == nt;
  if (!sizes_ok) {
    throw Error(
        "write_mesh2: the mesh's arrays do not match (3 indices per triangle, a kind per "
        "vertex, 2 indices and a tag per boundary edge, a region per triangle)");
  }
  for (const std::uint32_t v : mesh.triangles) {
    if (v >= nv) throw Error("write_mesh2: a triangle's vertex index is out of range");
  }
  for (const std::uint32_t v : mesh.boundary_edges) {
    if (v >= nv) throw Error("write_mesh2: a boundary edge's vertex index is out of range");
  }
  switch (format) {
    case Mesh2FileFormat::kVtu:
      write_vtu2(out, mesh, VtuEncoding::kAscii);
      break;
    case Mesh2FileFormat::kVtuBinary:
      write_vtu2(out, mesh, VtuEncoding::kBase64);
      break;
    case Mesh2FileFormat::kVtuCompressed:
      write_vtu2(out, mesh, VtuEncoding::kZlibBase64);
      break;
    case Mesh2FileFormat::kMedit:
      write_medit2(out, mesh);
      break;
    case Mesh2FileFormat::kGmsh22:
      write_gmsh2(out, mesh, false);
      break;
    case Mesh2FileFormat::kGmsh41:
      write_gmsh2(out, mesh, true);
      break;
  }
}

}  // namespace voroclip
