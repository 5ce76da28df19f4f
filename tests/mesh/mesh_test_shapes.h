// Shapes and checks shared by the mesh tests (test_mesh, test_mesh3d).
#pragma once

#include <catch2/catch.hpp>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/mesh.h"

namespace voroclip_test {

// The icosahedron subdivided `levels` times, its vertices on the sphere of radius r (each
// new vertex the normalised sum of its edge's endpoints), triangles outward by the
// right-hand rule.
inline voroclip::TriangleSurface icosphere(int levels, double r = 1) {
  const double g = (1 + std::sqrt(5.0)) / 2;
  std::vector<std::array<double, 3>> v = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
                                          {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
                                          {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  const auto unit = [](const std::array<double, 3>& p) {
    const double n = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    return std::array<double, 3>{p[0] / n, p[1] / n, p[2] / n};
  };
  for (auto& p : v) p = unit(p);
  std::vector<std::uint32_t> tri = {0, 11, 5, 0, 5,  1,  0,  1,  7,  0,  7, 10, 0, 10, 11,
                                    1, 5,  9, 5, 11, 4,  11, 10, 2,  10, 7, 6,  7, 1,  8,
                                    3, 9,  4, 3, 4,  2,  3,  2,  6,  3,  6, 8,  3, 8,  9,
                                    4, 9,  5, 2, 4,  11, 6,  2,  10, 8,  6, 7,  9, 8,  1};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> middle;
    const auto mid = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      const auto it = middle.find(key);
      if (it != middle.end()) return it->second;
      v.push_back(unit({v[a][0] + v[b][0], v[a][1] + v[b][1], v[a][2] + v[b][2]}));
      return middle[key] = static_cast<std::uint32_t>(v.size() - 1);
    };
    std::vector<std::uint32_t> next;
    for (std::size_t t = 0; t < tri.size(); t += 3) {
      const std::uint32_t a = tri[t], b = tri[t + 1], c = tri[t + 2];
      const std::uint32_t ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
      next.insert(next.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
    }
    tri = std::move(next);
  }
  voroclip::TriangleSurface s;
  s.source = "icosphere";
  for (const auto& p : v) s.xyz.insert(s.xyz.end(), {r * p[0], r * p[1], r * p[2]});
  s.triangles = std::move(tri);
  return s;
}

// mesh3d on `domain` gives the same vertices, tets and vertex kinds with 1 and 2 threads;
// returns the one-thread result.
inline voroclip::Mesh3Result check_same_mesh3d_with_1_and_2_threads(
    const voroclip::Domain3& domain, const voroclip::Mesh3Options& options) {
  voroclip::Mesh3Result one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = voroclip::mesh3d(domain, options);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = voroclip::mesh3d(domain, options);
  }
  CHECK(one.xyz == two.xyz);
  CHECK(one.tets == two.tets);
  CHECK(one.kinds == two.kinds);
  return one;
}

}  // namespace voroclip_test
