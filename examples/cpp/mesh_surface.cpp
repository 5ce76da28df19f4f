// Embedding voroclip: a tetrahedral mesh of a volume given by its closed surface (a box
// here; voroclip::read_surface reads OBJ, OFF, STL, PLY), written as Gmsh .msh 4.1 with its
// boundary triangles and tags, and read back.
#include <cstdio>
#include <vector>

#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/mesh.h"

int main() {
  // The box [0, 2] x [0, 1] x [0, 1], 12 triangles counter-clockwise seen from outside.
  voroclip::TriangleSurface box;
  box.source = "box";
  for (int i = 0; i < 8; ++i) {
    box.xyz.insert(box.xyz.end(), {i & 1 ? 2.0 : 0.0, i & 2 ? 1.0 : 0.0, i & 4 ? 1.0 : 0.0});
  }
  box.triangles = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                   2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
  const voroclip::Domain3 domain(box);

  voroclip::Mesh3Options options;
  options.nb_vertices = 400;
  const voroclip::Mesh3Result r = voroclip::mesh3d(domain, options);

  voroclip::TetMeshInput mesh;
  mesh.source = "box.msh";
  mesh.xyz = r.xyz;
  mesh.tets = r.tets;
  mesh.triangles = r.boundary_triangles;  // outward, one patch tag per box face
  mesh.triangle_ref = r.boundary_tags;
  mesh.tet_ref = r.tet_tags;
  const char* path = "example_mesh_surface_box.msh";
  voroclip::write_tet_mesh(path, mesh);  // by extension: Gmsh 4.1

  const voroclip::TetMeshInput back = voroclip::read_tet_mesh(path);
  std::remove(path);
  const bool same = back.xyz == mesh.xyz && back.tets == mesh.tets;
  const voroclip::TetQuality q = voroclip::tet_quality(back);
  std::printf("mesh of the box: %s; read back %s; %s\n",
              back.nb_tets() > 0 ? "tets written" : "no tets", same ? "identical" : "different",
              q.nb_negative == 0 && q.degenerate.empty() ? "every tet positive" : "bad tets");
  return same && back.nb_tets() > 0 && q.nb_negative == 0 && q.degenerate.empty() ? 0 : 1;
}
