// 2D clipped Voronoi diagram and CVT speed (issue 4).
//
// Targets: the clipped diagram of 10^6 uniform random sites in shared/data issue35.json
// (29 holes) and in an annulus in at most 1.0 s in total (Delaunay + clipping) on two
// cores, with clipping at most 0.5x the Delaunay time. Geogram's 2D restricted Voronoi
// diagram takes 0.62 s + 2.2 s of Delaunay for 10^6 sites in a square with a hole on this
// machine. BM_clip2d_* time the clipping alone on a fixed triangulation, BM_delaunay2_*
// the triangulation of the same sites, BM_total_* both. BM_cvt2d_iteration times one CVT
// iteration (Delaunay + clipped diagram), BM_cvt2d_to_tolerance Lloyd against L-BFGS to
// |g| / |g_0| = 1e-3.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/cvt.h"
#include "voroclip/delaunay.h"

namespace {

constexpr std::uint64_t kSeed = 20261122;

const voroclip::Domain2& issue35() {
  static const voroclip::Domain2 d(voroclip::read_polygon(std::string(VOROCLIP_SHARED_DATA_DIR) +
                                                          "/polygons/valid/issue35.json"));
  return d;
}

const voroclip::Domain2& annulus() {
  static const voroclip::Domain2 d(voroclip::annulus_rings(0.5, 1.0, 512));
  return d;
}

const voroclip::Domain2& domain_of(int which) { return which == 0 ? issue35() : annulus(); }

std::vector<double> sites_in(const voroclip::Domain2& d, std::uint32_t n) {
  std::mt19937_64 rng(kSeed);
  std::vector<double> xy;
  xy.reserve(2 * std::size_t{n});
  while (xy.size() < 2 * std::size_t{n}) {
    const double u = static_cast<double>(rng() >> 11) * 0x1p-53;
    const double v = static_cast<double>(rng() >> 11) * 0x1p-53;
    const double p[2] = {d.bbox_lo()[0] + u * (d.bbox_hi()[0] - d.bbox_lo()[0]),
                         d.bbox_lo()[1] + v * (d.bbox_hi()[1] - d.bbox_lo()[1])};
    if (d.locate(p) == voroclip::Sign::positive) xy.insert(xy.end(), p, p + 2);
  }
  return xy;
}

void BM_delaunay2(benchmark::State& state) {
  const auto n = static_cast<std::uint32_t>(state.range(1));
  const std::vector<double> xy = sites_in(domain_of(static_cast<int>(state.range(0))), n);
  voroclip::Delaunay2 dt;
  for (auto _ : state) {
    dt.build(xy.data(), n);
    benchmark::DoNotOptimize(dt.nb_triangles());
  }
  state.counters["sites_per_second"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_clip2d(benchmark::State& state) {
  const voroclip::Domain2& d = domain_of(static_cast<int>(state.range(0)));
  const auto n = static_cast<std::uint32_t>(state.range(1));
  const std::vector<double> xy = sites_in(d, n);
  const voroclip::Delaunay2 dt(xy.data(), n);
  voroclip::ClippedVoronoi2 cv;
  for (auto _ : state) {
    cv.compute(d, dt);
    benchmark::DoNotOptimize(cv.total_area());
  }
  state.counters["boundary_sites"] = cv.nb_boundary_sites();
  state.counters["sites_per_second"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_total2d(benchmark::State& state) {
  const voroclip::Domain2& d = domain_of(static_cast<int>(state.range(0)));
  const auto n = static_cast<std::uint32_t>(state.range(1));
  const std::vector<double> xy = sites_in(d, n);
  voroclip::Delaunay2 dt;
  voroclip::ClippedVoronoi2 cv;
  for (auto _ : state) {
    dt.build(xy.data(), n);
    cv.compute(d, dt);
    benchmark::DoNotOptimize(cv.total_area());
  }
}

// CVT, time per iteration: one Delaunay rebuild and one clipped diagram with its
// integrals (what an energy-and-gradient evaluation costs), on the sites after 20 Lloyd
// steps from the random start (a CVT's sites, not random ones).
void BM_cvt2d_iteration(benchmark::State& state) {
  const voroclip::Domain2& d = domain_of(static_cast<int>(state.range(0)));
  const auto n = static_cast<std::uint32_t>(state.range(1));
  std::vector<double> sites = sites_in(d, n);
  voroclip::Cvt2Options o;
  o.method = voroclip::CvtMethod::kLloyd;
  o.max_iterations = 20;
  o.gradient_tolerance = 0;
  voroclip::optimize_cvt2(d, sites, o);
  voroclip::Delaunay2 dt;
  voroclip::ClippedVoronoi2 cv;
  for (auto _ : state) {
    dt.build(sites.data(), n);
    cv.compute(d, dt);
    benchmark::DoNotOptimize(cv.total_energy());
  }
  state.counters["boundary_sites"] = cv.nb_boundary_sites();
}

// CVT to a tolerance: the time Lloyd and L-BFGS take from the same random start to reach
// |g| <= 1e-3 |g_0| (or their iteration budget, 3000; `reached` says which).
void BM_cvt2d_to_tolerance(benchmark::State& state) {
  const voroclip::Domain2& d = domain_of(static_cast<int>(state.range(0)));
  const auto n = static_cast<std::uint32_t>(state.range(2));
  const std::vector<double> start = sites_in(d, n);
  voroclip::Cvt2Options o;
  o.method = state.range(1) == 0 ? voroclip::CvtMethod::kLloyd : voroclip::CvtMethod::kLbfgs;
  o.max_iterations = 3000;
  o.gradient_tolerance = 1e-3;
  voroclip::Cvt2Result r;
  for (auto _ : state) {
    std::vector<double> sites = start;
    r = voroclip::optimize_cvt2(d, sites, o);
    benchmark::DoNotOptimize(sites.data());
  }
  state.counters["iterations"] = r.iterations;
  state.counters["evaluations"] = r.evaluations;
  state.counters["reached"] = r.converged ? 1 : 0;
  state.counters["relative_gradient"] = r.gradient_norm / r.initial_gradient_norm;
  state.counters["energy"] = r.energy;
  state.counters["seconds_per_evaluation"] = r.seconds / r.evaluations;
}

}  // namespace

// range(0): 0 = issue35.json, 1 = annulus; range(1): sites.
BENCHMARK(BM_delaunay2)->ArgsProduct({{0, 1}, {10000, 1000000}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_clip2d)->ArgsProduct({{0, 1}, {10000, 1000000}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_total2d)->ArgsProduct({{0, 1}, {1000000}})->Unit(benchmark::kMillisecond);
// range(0): 0 = issue35.json, 1 = annulus; range(1): sites.
BENCHMARK(BM_cvt2d_iteration)
    ->ArgsProduct({{0, 1}, {10000, 100000}})
    ->Unit(benchmark::kMillisecond);
// range(0): domain; range(1): 0 = Lloyd, 1 = L-BFGS; range(2): sites.
BENCHMARK(BM_cvt2d_to_tolerance)
    ->ArgsProduct({{0, 1}, {0, 1}, {10000}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

BENCHMARK_MAIN();
