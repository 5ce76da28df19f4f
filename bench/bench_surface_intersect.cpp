// Exact self-intersection test of a surface (clip/src/surface_intersect.h) on the shared
// models, with 1 and 2 threads (tbb::global_control).
//
// BM_surface_intersect/<model>/<threads>   first_intersecting_pair on the whole surface
//                                          (the models are clean: every pair is tested)
// Budget: gargoyle (100,000 triangles) in 0.12 s on two threads.
#include <benchmark/benchmark.h>

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>

#include <tbb/global_control.h>

#include "surface_intersect.h"
#include "voroclip/core.h"

namespace {

const char* const kFiles[] = {"sphere.obj", "bunny.obj", "rocker-arm.obj", "gargoyle.off"};

const voroclip::TriangleSurface& model(int k) {
  static std::map<int, voroclip::TriangleSurface> cache;
  auto it = cache.find(k);
  if (it == cache.end()) {
    it = cache
             .emplace(k, voroclip::read_surface(std::string(VOROCLIP_SHARED_DATA_DIR) +
                                                "/surfaces/" + kFiles[k]))
             .first;
  }
  return it->second;
}

void BM_surface_intersect(benchmark::State& state) {
  const voroclip::TriangleSurface& s = model(static_cast<int>(state.range(0)));
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism,
                              static_cast<std::size_t>(state.range(1)));
  state.SetLabel(kFiles[state.range(0)]);
  for (auto _ : state) {
    const voroclip::detail::TrianglePair p =
        voroclip::detail::first_intersecting_pair(s.xyz, s.triangles);
    benchmark::DoNotOptimize(p);
    if (p.found()) state.SkipWithError("the model intersects itself");
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(s.nb_triangles()));
}

}  // namespace

BENCHMARK(BM_surface_intersect)
    ->ArgsProduct({{0, 1, 2, 3}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

BENCHMARK_MAIN();
