// Builds a triangulation on a limited number of threads, for the thread-count tests of
// Delaunay2 and Delaunay3.
#pragma once

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "voroclip/delaunay.h"

namespace voroclip::test {

// T (Delaunay2 or Delaunay3) built on the packed coordinates with at most `threads`
// threads (an arena of that many slots, so that a 2-core machine still runs 4 threads).
template <class T>
T build_with_threads(const std::vector<double>& coords, std::size_t threads,
                     const typename T::Options& options) {
  constexpr std::size_t kDim = std::is_same_v<T, Delaunay2> ? 2 : 3;
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  tbb::task_arena arena(static_cast<int>(threads));
  T triangulation(options);
  arena.execute([&] {
    triangulation.build(coords.data(), static_cast<std::uint32_t>(coords.size() / kDim));
  });
  return triangulation;
}

}  // namespace voroclip::test
