// Exact point location in a closed surface (clip/src/surface_locate.h): build and query
// speed on the shared surfaces.
//
// BM_surface_locate_build/<model>          SurfaceLocator from the surface's arrays
// BM_surface_locate_point/<model>          points uniform in the bounding box
// BM_surface_locate_near/<model>           points on the triangles, rounded (within ulps of
//                                          the surface: filters fail more often)
// BM_surface_locate_circumcenter/<model>   circumcentres of the tet mesh's own tets (the
//                                          mesh extraction's queries: near the surface)
// BM_surface_locate_random_tet/<model>     circumcentres of small random tets in the box
// Per-query times are the reported time divided by the items (items_per_second).
#include <benchmark/benchmark.h>

#include <array>
#include <cstdint>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "surface_locate.h"
#include "voroclip/core.h"
#include "voroclip/predicates.h"

namespace {

using voroclip::detail::SurfaceLocator;
using P3 = std::array<double, 3>;

constexpr std::uint64_t kSeed = 20261128;
const char* const kModels[] = {"sphere", "bunny", "rocker-arm", "gargoyle"};
const char* const kFiles[] = {"sphere.obj", "bunny.obj", "rocker-arm.obj", "gargoyle.off"};

struct Model {
  voroclip::TriangleSurface surface;
  SurfaceLocator locator;
  P3 lo, hi;
};

const Model& model(int k) {
  static std::map<int, Model> cache;
  auto it = cache.find(k);
  if (it == cache.end()) {
    Model m;
    m.surface =
        voroclip::read_surface(std::string(VOROCLIP_SHARED_DATA_DIR) + "/surfaces/" + kFiles[k]);
    m.locator = SurfaceLocator(m.surface.xyz, m.surface.triangles);
    m.lo = {m.surface.xyz[0], m.surface.xyz[1], m.surface.xyz[2]};
    m.hi = m.lo;
    for (std::size_t i = 0; i < m.surface.xyz.size(); ++i) {
      m.lo[i % 3] = std::min(m.lo[i % 3], m.surface.xyz[i]);
      m.hi[i % 3] = std::max(m.hi[i % 3], m.surface.xyz[i]);
    }
    it = cache.emplace(k, std::move(m)).first;
  }
  return it->second;
}

void set_label(benchmark::State& state) { state.SetLabel(kModels[state.range(0)]); }

void BM_surface_locate_build(benchmark::State& state) {
  const Model& m = model(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    SurfaceLocator l(m.surface.xyz, m.surface.triangles);
    benchmark::DoNotOptimize(&l);
  }
  state.counters["triangles"] = static_cast<double>(m.surface.nb_triangles());
  set_label(state);
}

template <class Make>
void run_points(benchmark::State& state, const Make& make) {
  const Model& m = model(static_cast<int>(state.range(0)));
  std::mt19937_64 rng(kSeed);
  std::vector<P3> pts(1 << 16);
  for (auto& p : pts) p = make(m, rng);
  std::size_t i = 0, inside = 0;
  for (auto _ : state) {
    inside += m.locator.locate(pts[i].data()) == voroclip::Sign::positive;
    i = (i + 1) & (pts.size() - 1);
  }
  benchmark::DoNotOptimize(inside);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
  set_label(state);
}

void BM_surface_locate_point(benchmark::State& state) {
  run_points(state, [](const Model& m, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(0, 1);
    P3 p;
    for (int k = 0; k < 3; ++k) p[k] = m.lo[k] + (m.hi[k] - m.lo[k]) * u(rng);
    return p;
  });
}

void BM_surface_locate_near(benchmark::State& state) {
  run_points(state, [](const Model& m, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(0, 1);
    const auto& s = m.surface;
    const std::size_t t = rng() % s.nb_triangles();
    double a = u(rng), b = u(rng);
    if (a + b > 1) {
      a = 1 - a;
      b = 1 - b;
    }
    P3 p;
    for (int k = 0; k < 3; ++k) {
      const double x0 = s.xyz[3 * std::size_t{s.triangles[3 * t]} + k];
      const double x1 = s.xyz[3 * std::size_t{s.triangles[3 * t + 1]} + k];
      const double x2 = s.xyz[3 * std::size_t{s.triangles[3 * t + 2]} + k];
      p[k] = x0 + a * (x1 - x0) + b * (x2 - x0);
    }
    return p;
  });
}

void run_circumcenters(benchmark::State& state, const std::vector<std::array<P3, 4>>& tets,
                       const SurfaceLocator& locator) {
  std::size_t i = 0, inside = 0;
  for (auto _ : state) {
    const auto& s = tets[i];
    inside += locator.locate_circumcenter(s[0].data(), s[1].data(), s[2].data(), s[3].data()) ==
              voroclip::Sign::positive;
    i = i + 1 == tets.size() ? 0 : i + 1;
  }
  benchmark::DoNotOptimize(inside);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
  set_label(state);
}

void BM_surface_locate_circumcenter(benchmark::State& state) {
  const Model& m = model(static_cast<int>(state.range(0)));
  const voroclip::TetMeshInput mesh = voroclip::read_tet_mesh(
      std::string(VOROCLIP_SHARED_DATA_DIR) + "/tetmeshes/" + kModels[state.range(0)] + ".mesh");
  std::vector<std::array<P3, 4>> tets(mesh.nb_tets());
  for (std::size_t t = 0; t < tets.size(); ++t) {
    for (std::size_t k = 0; k < 4; ++k) {
      const std::size_t v = mesh.tets[4 * t + k];
      tets[t][k] = {mesh.xyz[3 * v], mesh.xyz[3 * v + 1], mesh.xyz[3 * v + 2]};
    }
  }
  run_circumcenters(state, tets, m.locator);
}

void BM_surface_locate_random_tet(benchmark::State& state) {
  const Model& m = model(static_cast<int>(state.range(0)));
  std::mt19937_64 rng(kSeed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<std::array<P3, 4>> tets(1 << 14);
  const double r = 0.02 * (m.hi[0] - m.lo[0]);
  for (auto& s : tets) {
    for (int k = 0; k < 3; ++k) s[0][k] = m.lo[k] + (m.hi[k] - m.lo[k]) * u(rng);
    for (std::size_t j = 1; j < 4; ++j) {
      for (int k = 0; k < 3; ++k) s[j][k] = s[0][k] + r * (2 * u(rng) - 1);
    }
  }
  run_circumcenters(state, tets, m.locator);
}

}  // namespace

BENCHMARK(BM_surface_locate_build)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_surface_locate_point)->DenseRange(0, 3);
BENCHMARK(BM_surface_locate_near)->DenseRange(0, 3);
BENCHMARK(BM_surface_locate_circumcenter)->DenseRange(0, 3);
BENCHMARK(BM_surface_locate_random_tet)->DenseRange(0, 3);
BENCHMARK_MAIN();
