// Validation of a closed surface as a 3D domain (Surface3: welding, manifold checks, exact
// self-intersection test, shells, orientation, the point locator), on the shared models,
// with 1 and 2 threads (tbb::global_control). The file is read once, outside the timing.
//
// BM_surface3/<model>/<threads>   Surface3(read_surface(model))
// Target (issue 29): gargoyle (100,000 triangles) in at most 0.25 s on two threads.
#include <benchmark/benchmark.h>

#include <cstddef>
#include <map>
#include <string>

#include <tbb/global_control.h>

#include "voroclip/clip.h"
#include "voroclip/core.h"

namespace {

const char* const kFiles[] = {"sphere.obj", "bunny.obj", "fandisk.obj", "rocker-arm.obj",
                              "gargoyle.off"};

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

void BM_surface3(benchmark::State& state) {
  const voroclip::TriangleSurface& s = model(static_cast<int>(state.range(0)));
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism,
                              static_cast<std::size_t>(state.range(1)));
  state.SetLabel(kFiles[state.range(0)]);
  for (auto _ : state) {
    const voroclip::Surface3 surface(s);
    benchmark::DoNotOptimize(surface.volume());
  }
  state.counters["triangles"] = static_cast<double>(s.nb_triangles());
}

}  // namespace

BENCHMARK(BM_surface3)
    ->ArgsProduct({{0, 1, 2, 3, 4}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

BENCHMARK_MAIN();
