// Delaunay3 construction: uniform random points in the unit cube (1e4 ... 1e6), an integer
// grid (cospherical everywhere) and points on a sphere, on one thread, and 1M uniform
// points on 1 and 2 threads; points per second, finite tets, the bytes the triangulation's
// arrays hold per tet at the end (capacities) and at their peak during the build (the
// construction's copies and scratch included), and the share of the points inserted in
// parallel zones that were deferred to a later pass; and 1M uniform points on 2 threads
// with smaller zones (Options::points_per_zone 65536 and 32768 against the default 131072:
// 4 and 8 zones in the last round instead of 2, more points deferred); uniform points on one
// thread with the SSE2 insphere determinant (Options::InsphereSimd::sse2, "_baseline") and with the
// AVX2 one (InsphereSimd::avx2, "_avx2", the SSE2 one on a CPU without AVX2), against the default
// (automatic: AVX2 when the CPU has it, but not on AMD Zen 1) in BM_delaunay3_uniform, and
// the same on 2 threads against BM_delaunay3_uniform_threads/1000000/2. Fixed seeds.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "voroclip/delaunay.h"

namespace {

std::vector<double> uniform_points(std::size_t n) {
  std::mt19937_64 rng(20261121);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> xyz(3 * n);
  for (double& x : xyz) x = u(rng);
  return xyz;
}

std::vector<double> grid_points(int m) {
  std::vector<double> xyz;
  for (int x = 0; x < m; ++x)
    for (int y = 0; y < m; ++y)
      for (int z = 0; z < m; ++z) xyz.insert(xyz.end(), {double(x), double(y), double(z)});
  return xyz;
}

std::vector<double> sphere_points(std::size_t n) {
  std::mt19937_64 rng(20261121);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> xyz(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    double v[3] = {g(rng), g(rng), g(rng)};
    const double r = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int j = 0; j < 3; ++j) xyz[3 * i + static_cast<std::size_t>(j)] = v[j] / r;
  }
  return xyz;
}

void run(benchmark::State& state, const std::vector<double>& xyz, std::size_t threads = 1,
         const voroclip::Delaunay3Options& options = {}) {
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  const auto n = static_cast<std::uint32_t>(xyz.size() / 3);
  voroclip::Delaunay3 dt(options);
  for (auto _ : state) {
    dt.build(xyz.data(), n);
    benchmark::DoNotOptimize(dt.nb_finite_tets());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * n);
  state.SetComplexityN(n);
  const auto tets = static_cast<double>(dt.nb_finite_tets());
  state.counters["tets"] = tets;
  state.counters["bytes_per_tet"] = static_cast<double>(dt.memory_bytes()) / tets;
  state.counters["peak_bytes_per_tet"] = static_cast<double>(dt.peak_memory_bytes()) / tets;
  const auto& stats = dt.stats();
  state.counters["deferred"] =
      stats.zoned_points == 0
          ? 0.0
          : static_cast<double>(stats.deferred_points) / static_cast<double>(stats.zoned_points);
}

void BM_delaunay3_uniform(benchmark::State& state) {
  run(state, uniform_points(static_cast<std::size_t>(state.range(0))));
}
void BM_delaunay3_uniform_threads(benchmark::State& state) {
  run(state, uniform_points(static_cast<std::size_t>(state.range(0))),
      static_cast<std::size_t>(state.range(1)));
}
void BM_delaunay3_uniform_zones(benchmark::State& state) {
  voroclip::Delaunay3Options options;
  options.points_per_zone = static_cast<std::uint32_t>(state.range(2));
  run(state, uniform_points(static_cast<std::size_t>(state.range(0))),
      static_cast<std::size_t>(state.range(1)), options);
}
// Uniform points (range(0)) on range(1) threads with the given insphere determinant.
void uniform_simd(benchmark::State& state, voroclip::Delaunay3Options::InsphereSimd simd) {
  voroclip::Delaunay3Options options;
  options.insphere_simd = simd;
  run(state, uniform_points(static_cast<std::size_t>(state.range(0))),
      static_cast<std::size_t>(state.range(1)), options);
}
void BM_delaunay3_uniform_baseline(benchmark::State& state) {
  uniform_simd(state, voroclip::Delaunay3Options::InsphereSimd::sse2);
}
void BM_delaunay3_uniform_avx2(benchmark::State& state) {
  uniform_simd(state, voroclip::Delaunay3Options::InsphereSimd::avx2);
}
void BM_delaunay3_grid(benchmark::State& state) {
  run(state, grid_points(static_cast<int>(state.range(0))));
}
void BM_delaunay3_sphere(benchmark::State& state) {
  run(state, sphere_points(static_cast<std::size_t>(state.range(0))));
}

}  // namespace

BENCHMARK(BM_delaunay3_uniform)
    ->RangeMultiplier(10)
    ->Range(10000, 1000000)
    ->Unit(benchmark::kMillisecond)
    ->Complexity();
BENCHMARK(BM_delaunay3_uniform_threads)
    ->Args({1000000, 1})
    ->Args({1000000, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_delaunay3_uniform_zones)
    ->Args({1000000, 2, 65536})
    ->Args({1000000, 2, 32768})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_delaunay3_uniform_baseline)
    ->Args({100000, 1})
    ->Args({1000000, 1})
    ->Args({1000000, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_delaunay3_uniform_avx2)
    ->Args({100000, 1})
    ->Args({1000000, 1})
    ->Args({1000000, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_delaunay3_grid)->Arg(100)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_delaunay3_sphere)->Arg(1000000)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
