// Disjoint sets over 0..n-1 (union by smaller root, path halving): the components of the
// restricted cells (topology3d.cpp) and of a tet mesh (mesh3d_tags.cpp). Internal to the
// mesh module.
#pragma once

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

namespace voroclip::mesh3 {

struct UnionFind {
  std::vector<std::uint32_t> parent;
  UnionFind() = default;
  explicit UnionFind(std::size_t n) { reset(n); }
  // n singletons (the storage is reused).
  void reset(std::size_t n) {
    parent.resize(n);
    std::iota(parent.begin(), parent.end(), 0u);
  }
  std::uint32_t find(std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  // The root of the union is the smaller of the two roots.
  void unite(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
  // The number of sets.
  std::uint32_t count() {
    std::uint32_t c = 0;
    for (std::uint32_t x = 0; x < parent.size(); ++x) c += find(x) == x ? 1 : 0;
    return c;
  }
};

}  // namespace voroclip::mesh3
