// Mesh quality and surface queries (issue 6): closest-point queries on a triangle surface,
// the tet quality report and the sampled Hausdorff distance.
//
// BM_surface_tree_build/<model>: SurfaceTree construction.
// BM_closest/<model>/<near>: 10^5 closest-point queries in one loop on one thread, from
//   points near the surface (near = 1: each vertex of the surface moved by up to 1 % of the
//   bounding-box diagonal, as when sites are re-projected) or uniform in the bounding box
//   enlarged by 10 % (near = 0). Target (brief Q3): 10^5 queries on a 100k-triangle
//   surface (gargoyle) well under a second.
// BM_closest_hint/<model>: the near queries with the previous answer's triangle as hint.
// BM_tet_quality/<model>: tet_quality (all threads).
// BM_hausdorff/<model>: the boundary of the model's tet mesh against its source surface,
//   default sampling (all threads).
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "voroclip/core.h"
#include "voroclip/mesh.h"

namespace {

constexpr std::uint64_t kSeed = 20261124;
constexpr std::uint32_t kQueries = 100000;
const char* kSurfaces[] = {"sphere.obj", "fandisk.obj", "gargoyle.off"};
const char* kMeshes[] = {"sphere-fine", "rocker-arm", "gargoyle"};
const std::string kData = VOROCLIP_SHARED_DATA_DIR;

const voroclip::TriangleSurface& surface(int k) {
  static std::map<int, voroclip::TriangleSurface> cache;
  auto it = cache.find(k);
  if (it == cache.end()) {
    it = cache.emplace(k, voroclip::read_surface(kData + "/surfaces/" + kSurfaces[k])).first;
  }
  return it->second;
}

const voroclip::TetMeshInput& mesh(int k) {
  static std::map<int, voroclip::TetMeshInput> cache;
  auto it = cache.find(k);
  if (it == cache.end()) {
    it = cache.emplace(k, voroclip::read_tet_mesh(kData + "/tetmeshes/" + kMeshes[k] + ".mesh"))
             .first;
  }
  return it->second;
}

std::vector<double> query_points(const voroclip::TriangleSurface& s,
                                 const voroclip::SurfaceTree& tree, bool near) {
  std::mt19937_64 rng(kSeed);
  std::uniform_real_distribution<double> u(-1, 1);
  double diag = 0;
  for (int c = 0; c < 3; ++c) {
    diag += (tree.bbox_hi()[c] - tree.bbox_lo()[c]) * (tree.bbox_hi()[c] - tree.bbox_lo()[c]);
  }
  diag = std::sqrt(diag);
  std::vector<double> p(3 * std::size_t{kQueries});
  for (std::uint32_t i = 0; i < kQueries; ++i) {
    for (int c = 0; c < 3; ++c) {
      const std::size_t k = 3 * std::size_t{i} + static_cast<std::size_t>(c);
      if (near) {
        const std::size_t v = 3 * std::size_t{i % s.nb_vertices()} + static_cast<std::size_t>(c);
        p[k] = s.xyz[v] + 0.01 * diag * u(rng) / std::sqrt(3.0);
      } else {
        const double lo = tree.bbox_lo()[c], hi = tree.bbox_hi()[c];
        p[k] = lo + (hi - lo) * (0.5 + 0.55 * u(rng));
      }
    }
  }
  return p;
}

void BM_surface_tree_build(benchmark::State& state) {
  const voroclip::TriangleSurface& s = surface(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    voroclip::SurfaceTree tree(s);
    benchmark::DoNotOptimize(tree.bbox_lo());
  }
  state.SetLabel(kSurfaces[state.range(0)]);
  state.counters["triangles"] = s.nb_triangles();
}

void BM_closest(benchmark::State& state) {
  const voroclip::TriangleSurface& s = surface(static_cast<int>(state.range(0)));
  const voroclip::SurfaceTree tree(s);
  const std::vector<double> p = query_points(s, tree, state.range(1) != 0);
  for (auto _ : state) {
    double sum = 0;
    for (std::uint32_t i = 0; i < kQueries; ++i) {
      sum += tree.closest(&p[3 * std::size_t{i}]).distance2;
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetLabel(std::string(kSurfaces[state.range(0)]) + (state.range(1) ? " near" : " box"));
  state.SetItemsProcessed(state.iterations() * kQueries);
}

void BM_closest_hint(benchmark::State& state) {
  const voroclip::TriangleSurface& s = surface(static_cast<int>(state.range(0)));
  const voroclip::SurfaceTree tree(s);
  const std::vector<double> p = query_points(s, tree, true);
  // Hints as a re-projection has them: each point's answer before it moved.
  std::vector<std::uint32_t> hint(kQueries);
  for (std::uint32_t i = 0; i < kQueries; ++i) {
    hint[i] = tree.closest(&s.xyz[3 * std::size_t{i % s.nb_vertices()}]).triangle;
  }
  for (auto _ : state) {
    double sum = 0;
    for (std::uint32_t i = 0; i < kQueries; ++i) {
      sum += tree.closest(&p[3 * std::size_t{i}], hint[i]).distance2;
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetLabel(std::string(kSurfaces[state.range(0)]) + " near, hinted");
  state.SetItemsProcessed(state.iterations() * kQueries);
}

void BM_tet_quality(benchmark::State& state) {
  const voroclip::TetMeshInput& m = mesh(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    const voroclip::TetQuality q = voroclip::tet_quality(m);
    benchmark::DoNotOptimize(q.q4.mean);
  }
  state.SetLabel(kMeshes[state.range(0)]);
  state.SetItemsProcessed(state.iterations() * m.nb_tets());
}

void BM_hausdorff(benchmark::State& state) {
  const voroclip::TetMeshInput& m = mesh(static_cast<int>(state.range(0)));
  const voroclip::TriangleSurface boundary = voroclip::tet_mesh_boundary(m);
  const voroclip::TriangleSurface& ref = surface(state.range(0) == 0 ? 0 : 2);
  std::uint64_t samples = 0;
  for (auto _ : state) {
    const voroclip::HausdorffDistance d = voroclip::hausdorff_distance(boundary, ref);
    samples = d.forward.nb_samples + d.backward.nb_samples;
    benchmark::DoNotOptimize(d.max);
  }
  state.SetLabel(std::string(kMeshes[state.range(0)]) + " boundary vs " +
                 kSurfaces[state.range(0) == 0 ? 0 : 2]);
  state.counters["samples"] = static_cast<double>(samples);
}

}  // namespace

BENCHMARK(BM_surface_tree_build)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_closest)->ArgsProduct({{0, 1, 2}, {0, 1}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_closest_hint)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_tet_quality)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_hausdorff)->Arg(0)->Arg(2)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
