// Canonical form of a 3D triangulation or tet mesh for comparisons in tests: its (finite)
// tets as sorted vertex quadruples, sorted.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "voroclip/delaunay.h"

namespace voroclip::test {

using Tet = std::array<std::uint32_t, 4>;

inline std::vector<Tet> finite_tets(const Delaunay3& dt) {
  std::vector<Tet> out;
  for (std::uint32_t t = 0; t < dt.nb_tet_slots(); ++t) {
    if (dt.is_free(t) || dt.is_infinite(t)) continue;
    Tet v = {dt.tet_vertex(t, 0), dt.tet_vertex(t, 1), dt.tet_vertex(t, 2), dt.tet_vertex(t, 3)};
    std::sort(v.begin(), v.end());
    out.push_back(v);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// The same for tets given as 4 vertex indices each (a tet mesh: extract3d, mesh3d).
inline std::vector<Tet> tet_set(const std::vector<std::uint32_t>& tets) {
  std::vector<Tet> out;
  for (std::size_t t = 0; t + 3 < tets.size(); t += 4) {
    Tet v = {tets[t], tets[t + 1], tets[t + 2], tets[t + 3]};
    std::sort(v.begin(), v.end());
    out.push_back(v);
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace voroclip::test
