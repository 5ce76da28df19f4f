// 3D clipped Voronoi diagram speed (issue 5), and a reproduction of the paper's Table 1.
//
// Reference figures on this machine: Geogram's volumetric restricted Voronoi diagram of
// sphere-fine.mesh (105k tets), sites uniform in the ball, mass and centroid of every
// cell: 10^4 sites 0.06 s Delaunay + 0.89 s clipping on one thread; 10^5 sites 1.0 + 4.1 s
// on one thread; 10^6 sites 7.3 + 11.6 s on two threads. The paper (2011 laptop, CGAL's
// Delaunay): Homer (16.2k tets, 10k sites) 6.3 s, Bust (68.5k tets, 30k sites) 16.2 s.
//
// BM_clip3d/<model>/<sites>: Delaunay + clipped diagram, sites uniform in the volume
// (fixed seed); counters: the per-phase seconds of the last run, boundary sites and
// clipped (cell, tet) pairs.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/delaunay.h"

namespace {

constexpr std::uint64_t kSeed = 20261122;
const char* kModels[] = {"sphere-fine", "bunny", "elk", "homer", "rocker-arm", "fandisk"};

const voroclip::Domain3& model(int k) {
  static std::map<int, voroclip::Domain3> cache;
  auto it = cache.find(k);
  if (it == cache.end()) {
    it =
        cache
            .emplace(
                k, voroclip::Domain3(voroclip::read_tet_mesh(std::string(VOROCLIP_SHARED_DATA_DIR) +
                                                             "/tetmeshes/" + kModels[k] + ".mesh")))
            .first;
  }
  return it->second;
}

std::vector<double> sites_in(const voroclip::Domain3& d, std::uint32_t n) {
  std::vector<double> cumulative(d.nb_tets());
  double total = 0;
  for (std::uint32_t t = 0; t < d.nb_tets(); ++t) {
    const double* a = d.vertex(d.tet_vertex(t, 0));
    double u[3][3];
    for (int k = 0; k < 3; ++k) {
      const double* b = d.vertex(d.tet_vertex(t, k + 1));
      for (int c = 0; c < 3; ++c) u[k][c] = b[c] - a[c];
    }
    total += std::fabs(u[0][0] * (u[1][1] * u[2][2] - u[1][2] * u[2][1]) -
                       u[0][1] * (u[1][0] * u[2][2] - u[1][2] * u[2][0]) +
                       u[0][2] * (u[1][0] * u[2][1] - u[1][1] * u[2][0]));
    cumulative[t] = total;
  }
  std::mt19937_64 rng(kSeed);
  const auto uniform = [&] { return static_cast<double>(rng() >> 11) * 0x1p-53; };
  std::vector<double> xyz;
  for (std::uint32_t i = 0; i < n; ++i) {
    const auto t = static_cast<std::uint32_t>(std::min<std::size_t>(
        static_cast<std::size_t>(
            std::upper_bound(cumulative.begin(), cumulative.end(), uniform() * total) -
            cumulative.begin()),
        d.nb_tets() - 1));
    double b[3] = {uniform(), uniform(), uniform()};
    std::sort(b, b + 3);
    const double w[4] = {b[0], b[1] - b[0], b[2] - b[1], 1 - b[2]};
    double p[3] = {0, 0, 0};
    for (int k = 0; k < 4; ++k) {
      for (int c = 0; c < 3; ++c) p[c] += w[k] * d.vertex(d.tet_vertex(t, k))[c];
    }
    xyz.insert(xyz.end(), p, p + 3);
  }
  return xyz;
}

void BM_clip3d(benchmark::State& state) {
  const voroclip::Domain3& d = model(static_cast<int>(state.range(0)));
  const auto n = static_cast<std::uint32_t>(state.range(1));
  const std::vector<double> xyz = sites_in(d, n);
  voroclip::ClippedVoronoi3 cv;
  double t_delaunay = 0;
  for (auto _ : state) {
    // As the CLI runs it: the triangulation of the sites in spatial order, then the cells.
    cv.compute(d, xyz.data(), n);
    t_delaunay = cv.seconds_delaunay();
    benchmark::DoNotOptimize(cv.total_volume());
  }
  state.SetLabel(kModels[state.range(0)]);
  state.counters["tets"] = d.nb_tets();
  state.counters["boundary_sites"] = cv.nb_boundary_sites();
  state.counters["pairs"] = static_cast<double>(cv.nb_clipped_pairs());
  state.counters["multi_crossing"] = cv.nb_multi_crossing_cells();
  state.counters["s_delaunay"] = t_delaunay;
  state.counters["s_surface"] = cv.seconds_surface();
  state.counters["s_boundary"] = cv.seconds_boundary_cells();
  state.counters["s_inner"] = cv.seconds_inner_cells();
  state.counters["volume_error"] = std::fabs(cv.total_volume() - d.volume()) / d.volume();
}

}  // namespace

// The sphere with the peer benchmarks' sizes; Table 1's models with their site counts
// (bunny 2k, elk 2k, homer 10k, rocker-arm 3k) and fandisk.
BENCHMARK(BM_clip3d)
    ->Args({0, 10000})
    ->Args({0, 100000})
    ->Args({1, 2000})
    ->Args({2, 2000})
    ->Args({3, 10000})
    ->Args({4, 3000})
    ->Args({5, 10000})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_clip3d)
    ->Args({0, 1000000})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

BENCHMARK_MAIN();
