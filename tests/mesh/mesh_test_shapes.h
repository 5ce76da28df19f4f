// Shapes and checks shared by the mesh tests (test_mesh, test_mesh3d).
#pragma once

#include <catch2/catch.hpp>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <utility>
#include <vector>

#include "support/surfaces.h"
#include "support/threads.h"
#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/mesh.h"

namespace voroclip_test {

using voroclip_test::icosphere;

// The box [0, sx] x [0, sy] x [0, sz] cut into the six tets around its diagonal from the
// origin, named `source`.
inline voroclip::Domain3 six_tet_box(double sx, double sy, double sz, const char* source) {
  voroclip::TetMeshInput m;
  m.source = source;
  for (int k = 0; k < 8; ++k) {
    m.xyz.insert(m.xyz.end(), {sx * (k & 1), sy * ((k >> 1) & 1), sz * ((k >> 2) & 1)});
  }
  // Paths 0 -> 7 along the axes in every order.
  const int axes[6][3] = {{1, 2, 4}, {1, 4, 2}, {2, 1, 4}, {2, 4, 1}, {4, 1, 2}, {4, 2, 1}};
  for (const auto& a : axes) {
    m.tets.insert(m.tets.end(), {0u, static_cast<std::uint32_t>(a[0]),
                                 static_cast<std::uint32_t>(a[0] + a[1]), 7u});
  }
  return voroclip::Domain3(m);
}

// The cube [0, 2]^3 cut into the six tets around its diagonal (0, 0, 0) - (2, 2, 2).
inline voroclip::Domain3 cube_domain() { return six_tet_box(2, 2, 2, "cube"); }

// The unit cube as a grid of n^3 voxels, six Kuhn tets each, voxel (i, j, k) in region
// tag(i, j, k).
inline voroclip::TetMeshInput region_grid(
    std::uint32_t n,
    const std::function<std::int32_t(std::uint32_t, std::uint32_t, std::uint32_t)>& tag) {
  voroclip::TetMeshInput m;
  m.source = "inclusion grid";
  const auto id = [n](std::uint32_t i, std::uint32_t j, std::uint32_t k) {
    return (k * (n + 1) + j) * (n + 1) + i;
  };
  for (std::uint32_t k = 0; k <= n; ++k) {
    for (std::uint32_t j = 0; j <= n; ++j) {
      for (std::uint32_t i = 0; i <= n; ++i) {
        m.xyz.insert(m.xyz.end(), {static_cast<double>(i) / n, static_cast<double>(j) / n,
                                   static_cast<double>(k) / n});
      }
    }
  }
  const int axes[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (std::uint32_t k = 0; k < n; ++k) {
    for (std::uint32_t j = 0; j < n; ++j) {
      for (std::uint32_t i = 0; i < n; ++i) {
        const std::int32_t ref = tag(i, j, k);
        for (const auto& a : axes) {
          std::uint32_t c[3] = {i, j, k};
          m.tets.push_back(id(c[0], c[1], c[2]));
          for (const int axis : a) {
            ++c[axis];
            m.tets.push_back(id(c[0], c[1], c[2]));
          }
          m.tet_ref.push_back(ref);
        }
      }
    }
  }
  return m;
}

// Mesh3Options for n vertices with short CVT and perturbation phases (the tests' budget).
inline voroclip::Mesh3Options small_options(std::uint32_t n) {
  voroclip::Mesh3Options o;
  o.nb_vertices = n;
  o.unconstrained_iterations = 8;
  o.constrained_iterations = 12;
  o.perturbation.max_rounds = 4;
  return o;
}

// mesh3d on `domain` gives the same vertices, tets and vertex kinds with 1 and N threads
// (VOROCLIP_TEST_THREADS, support/threads.h);
// returns the one-thread result.
inline voroclip::Mesh3Result check_same_mesh3d_with_1_and_2_threads(
    const voroclip::Domain3& domain, const voroclip::Mesh3Options& options) {
  voroclip::Mesh3Result one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = voroclip::mesh3d(domain, options);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism,
                          voroclip_test::test_threads());
    two = voroclip::mesh3d(domain, options);
  }
  CHECK(one.xyz == two.xyz);
  CHECK(one.tets == two.tets);
  CHECK(one.kinds == two.kinds);
  return one;
}

}  // namespace voroclip_test
