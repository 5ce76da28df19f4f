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

#include "support/surfaces.h"
#include "support/threads.h"
#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/mesh.h"

namespace voroclip_test {

using voroclip_test::icosphere;

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
