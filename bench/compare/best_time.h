// Timing helper of the comparison benchmarks: the best wall time of a few runs.
#pragma once

#include <algorithm>
#include <chrono>

namespace voroclip::bench {

template <class F>
double best_seconds(int runs, F&& f) {
  double best = 1e300;
  for (int r = 0; r < runs; ++r) {
    const auto start = std::chrono::steady_clock::now();
    f();
    const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
    best = std::min(best, elapsed.count());
  }
  return best;
}

}  // namespace voroclip::bench
