// Timing helpers of the comparison benchmarks: the best wall and CPU time of a few runs,
// the runs of the contenders interleaved so that a change in the machine's load affects
// them alike. CPU time is the process's (all threads); on one thread it is the figure
// least disturbed by other processes.
#pragma once

#include <algorithm>
#include <chrono>
#include <ctime>
#include <functional>
#include <vector>

namespace voroclip::bench {

struct Best {
  double wall = 1e300;
  double cpu = 1e300;
};

inline double process_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// Runs each of `contenders` `runs` times, round robin; returns the best times of each.
inline std::vector<Best> best_times(int runs,
                                    const std::vector<std::function<void()>>& contenders) {
  std::vector<Best> best(contenders.size());
  for (int r = 0; r < runs; ++r) {
    for (std::size_t i = 0; i < contenders.size(); ++i) {
      const double cpu = process_cpu_seconds();
      const auto start = std::chrono::steady_clock::now();
      contenders[i]();
      const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
      best[i].wall = std::min(best[i].wall, elapsed.count());
      best[i].cpu = std::min(best[i].cpu, process_cpu_seconds() - cpu);
    }
  }
  return best;
}

}  // namespace voroclip::bench
