// Nearest vertex on a Delaunay graph, shared by Delaunay2 and Delaunay3.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "voroclip/predicates.h"

namespace voroclip::detail {

// From vertex `start`, greedy descent on the Delaunay graph: a vertex with no strictly
// closer neighbour is a nearest vertex (Voronoi cells are convex and hold their sites).
// The nearest vertices then lie on an empty circle/sphere around the query and are
// connected by Delaunay edges; the smallest index among them is returned.
//   neighbors(v, out): fills out with the Delaunay neighbours of v
//   compare(w, v):     sign of |p - w|^2 - |p - v|^2, exact
template <class Neighbors, class Compare>
std::uint32_t nearest_on_delaunay_graph(std::uint32_t start, Neighbors&& neighbors,
                                        Compare&& compare) {
  std::vector<std::uint32_t> around;
  std::uint32_t v = start;
  for (bool improved = true; improved;) {
    improved = false;
    neighbors(v, around);
    for (const std::uint32_t w : around) {
      if (compare(w, v) == Sign::negative) {
        v = w;
        improved = true;
        break;
      }
    }
  }
  std::vector<std::uint32_t> tied = {v};
  std::uint32_t best = v;
  for (std::size_t i = 0; i < tied.size(); ++i) {
    neighbors(tied[i], around);
    for (const std::uint32_t w : around) {
      if (compare(w, v) == Sign::zero && std::find(tied.begin(), tied.end(), w) == tied.end()) {
        tied.push_back(w);
        best = std::min(best, w);
      }
    }
  }
  return best;
}

}  // namespace voroclip::detail
