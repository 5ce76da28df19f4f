// Delaunay2 construction speed (issue 3): uniform random points in the unit square over a
// size sweep, an integer grid and points on a circle (every point on the hull, most
// incircle tests near-degenerate), one thread against two (the strips: "zoned" and
// "deferred" are fractions of the points), plus the BRIO spatial sort alone (2D and 3D,
// whose target is 1M points well under 0.3 s). "points_per_second" is the figure to quote.
// Target: 1M uniform points in at most 0.8x the time of CGAL's Delaunay_triangulation_2
// measured in the same run (bench/compare/compare_delaunay2).

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "spatial_sort.h"
#include "voroclip/delaunay.h"

namespace {

constexpr std::uint64_t kSeed = 20261122;

std::vector<double> uniform_points(std::size_t n, int dim) {
  std::mt19937_64 rng(kSeed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> c(n * static_cast<std::size_t>(dim));
  for (double& x : c) x = u(rng);
  return c;
}

void run(benchmark::State& state, const std::vector<double>& xy) {
  const auto n = static_cast<std::uint32_t>(xy.size() / 2);
  voroclip::Delaunay2 d;
  for (auto _ : state) {
    d.build(xy.data(), n);
    benchmark::DoNotOptimize(d.nb_triangles());
  }
  state.SetComplexityN(n);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * n);
  state.counters["points_per_second"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["triangles"] = static_cast<double>(d.nb_triangles());
}

void BM_delaunay2_uniform(benchmark::State& state) {
  run(state, uniform_points(static_cast<std::size_t>(state.range(0)), 2));
}

// A fresh object each time: the cost of the first build (allocations included).
void BM_delaunay2_uniform_fresh(benchmark::State& state) {
  const auto n = static_cast<std::uint32_t>(state.range(0));
  const std::vector<double> xy = uniform_points(n, 2);
  for (auto _ : state) {
    const voroclip::Delaunay2 d(xy.data(), n);
    benchmark::DoNotOptimize(d.nb_triangles());
  }
  state.counters["points_per_second"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
}

// A fresh object each time on range(1) threads: one thread inserts sequentially, more
// insert the large rounds in strips (the same triangulation).
void BM_delaunay2_uniform_threads(benchmark::State& state) {
  const auto n = static_cast<std::uint32_t>(state.range(0));
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                  static_cast<std::size_t>(state.range(1)));
  const std::vector<double> xy = uniform_points(n, 2);
  voroclip::Delaunay2::Stats stats;
  for (auto _ : state) {
    const voroclip::Delaunay2 d(xy.data(), n);
    benchmark::DoNotOptimize(d.nb_triangles());
    stats = d.stats();
  }
  state.counters["points_per_second"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["zoned"] = static_cast<double>(stats.zoned_points) / n;
  state.counters["deferred"] = static_cast<double>(stats.deferred_points) / n;
}
void BM_delaunay2_grid(benchmark::State& state) {
  const auto side = static_cast<int>(state.range(0));
  std::vector<double> xy;
  for (int i = 0; i < side; ++i) {
    for (int j = 0; j < side; ++j) {
      xy.push_back(j);
      xy.push_back(i);
    }
  }
  run(state, xy);
}

void BM_delaunay2_circle(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  std::vector<double> xy;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = 2 * M_PI * static_cast<double>(i) / static_cast<double>(n);
    xy.push_back(std::cos(a));
    xy.push_back(std::sin(a));
  }
  run(state, xy);
}

void BM_brio_order(benchmark::State& state) {
  const auto n = static_cast<std::uint32_t>(state.range(0));
  const int dim = static_cast<int>(state.range(1));
  const std::vector<double> c = uniform_points(n, dim);
  for (auto _ : state) {
    benchmark::DoNotOptimize(voroclip::detail::brio_order(c.data(), n, dim).data());
  }
  state.counters["points_per_second"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

BENCHMARK(BM_delaunay2_uniform)
    ->RangeMultiplier(10)
    ->Range(10000, 1000000)
    ->Complexity(benchmark::oNLogN)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_delaunay2_uniform_fresh)->Arg(1000000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_delaunay2_uniform_threads)
    ->Args({1000000, 1})
    ->Args({1000000, 2})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_delaunay2_grid)->Arg(1000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_delaunay2_circle)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_brio_order)->Args({1000000, 2})->Args({1000000, 3})->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
