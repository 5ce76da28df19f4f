// A small tagged tet mesh shared by test_tetmesh_io.cpp and write_tagged_meshes.cpp: the
// Kuhn cube (6 tets around the diagonal from vertex 0 to vertex 7, vertex v at (v & 1,
// v >> 1 & 1, v >> 2 & 1), scaled and shifted so that no coordinate is a short decimal),
// one unused vertex, two regions in interleaved order, the 12 boundary triangles in three
// patches by the axis their face is normal to (x: 10, y: 11, z: 12, interleaved), and
// names for four of the five tags.
#pragma once

#include <cstdint>
#include <vector>

#include "voroclip/core.h"

namespace voroclip_test {

inline voroclip::TetMeshInput tagged_kuhn_cube() {
  voroclip::TetMeshInput m;
  for (std::uint32_t v = 0; v < 8; ++v) {
    for (std::uint32_t k = 0; k < 3; ++k) {
      m.xyz.push_back(0.1 * static_cast<double>((v >> k) & 1u) + 1.0 / 3.0);
    }
  }
  m.xyz.insert(m.xyz.end(), {-2.5e-7, 1e10, 7.0 / 9.0});  // vertex 8, unused
  m.tets = {0, 1, 3, 7, 0, 2, 3, 7, 0, 1, 5, 7, 0, 2, 6, 7, 0, 4, 5, 7, 0, 4, 6, 7};
  m.tet_ref = {1, 2, 1, 2, 2, 1};
  // Per face of the cube (x = 0, y = 0, z = 0, x = 1, y = 1, z = 1), its two triangles
  // split along the diagonal the Kuhn tets use.
  m.triangles = {0, 2, 6, 0, 4, 6, 0, 1, 5, 0, 4, 5, 0, 1, 3, 0, 2, 3,
                 1, 3, 7, 1, 5, 7, 2, 3, 7, 2, 6, 7, 4, 5, 7, 4, 6, 7};
  m.triangle_ref = {10, 10, 11, 11, 12, 12, 10, 10, 11, 11, 12, 12};
  m.tag_names = {{3, 1, "steel"}, {3, 2, "copper region"}, {2, 10, "x faces"}, {2, 12, "z"}};
  return m;
}

}  // namespace voroclip_test
