// Canonical form of a 3D triangulation for comparisons in tests: its finite tets as sorted
// vertex quadruples, sorted.
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

}  // namespace voroclip::test
