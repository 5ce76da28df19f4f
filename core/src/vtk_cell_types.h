// core/src/vtk_cell_types.h — what the VTK readers (legacy .vtk in tetmesh_io.cpp, .vtu in
// vtu_io.cpp) do with each VTK cell type (internal to the core module).
#pragma once

#include <cstdint>

namespace voroclip::vtk {

// What the readers do with a VTK cell type (vtkCellType.h): read it as a tet or triangle
// (`points` > 0) by its first `corners` points, which are its corners (VTK_QUADRATIC_TETRA
// and VTK_QUADRATIC_TRIANGLE: corners, then mid-edge points; the mid-edge points are then
// vertices of no tet), refuse it as a volume cell not read (`other`), or skip it.
struct VtkCellKind {
  std::uint64_t points = 0, corners = 0;
  const char* name = nullptr;  // for messages: "10 (tetra)"
  const char* other = nullptr;
  const char* others = nullptr;
};

inline VtkCellKind vtk_cell_kind(std::uint64_t type) {
  switch (type) {
    case 10:  // VTK_TETRA
      return {4, 4, "10 (tetra)"};
    case 24:
      return {10, 4, "24 (quadratic tetra)"};
    case 5:  // VTK_TRIANGLE
      return {3, 3, "5 (triangle)"};
    case 22:
      return {6, 3, "22 (quadratic triangle)"};
    case 11:
      return {0, 0, nullptr, "voxel", "voxels"};
    case 12:
    case 25:
    case 29:
    case 33:
    case 67:
    case 72:
    case 79:
      return {0, 0, nullptr, "hexahedron", "hexahedra"};
    case 13:
    case 26:
    case 31:
    case 32:
    case 65:
    case 73:
    case 80:
      return {0, 0, nullptr, "wedge", "wedges"};
    case 14:
    case 27:
    case 37:
    case 66:
    case 74:
    case 81:
      return {0, 0, nullptr, "pyramid", "pyramids"};
    case 15:
      return {0, 0, nullptr, "pentagonal prism", "pentagonal prisms"};
    case 16:
      return {0, 0, nullptr, "hexagonal prism", "hexagonal prisms"};
    case 41:
      return {0, 0, nullptr, "convex point set", "convex point sets"};
    case 42:
      return {0, 0, nullptr, "polyhedron", "polyhedra"};
    case 64:
    case 71:
    case 78:
      return {0, 0, nullptr, "tetrahedron of an order not read", "tetrahedra of an order not read"};
    default:
      return {};
  }
}

}  // namespace voroclip::vtk
