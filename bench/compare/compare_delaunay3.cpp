// Delaunay3 against CGAL's Delaunay_triangulation_3 (Epick kernel, spatially sorted range
// insertion) on the same uniform random points in the unit cube, in one process. Prints
// the best wall and CPU time of a few interleaved runs of each, the ratio ours / CGAL on
// one thread, ours on two threads (wall), and checks that all have the same number of
// finite tetrahedra (issue 3: 1M points, <= 2.0 s on one thread, about half of CGAL;
// <= 1.2 s on two threads).
//   compare_delaunay3 [n = 1000000] [runs = 3]
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <tbb/global_control.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "best_time.h"
#include "voroclip/delaunay.h"

int main(int argc, char** argv) {
  using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
  using CgalDelaunay = CGAL::Delaunay_triangulation_3<Kernel>;
  const std::uint32_t n = argc > 1 ? static_cast<std::uint32_t>(std::atol(argv[1])) : 1000000u;
  const int runs = argc > 2 ? std::atoi(argv[2]) : 3;
  std::mt19937_64 rng(20261122);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> xyz(3 * static_cast<std::size_t>(n));
  for (double& x : xyz) x = u(rng);
  std::vector<Kernel::Point_3> points;
  points.reserve(n);
  for (std::uint32_t i = 0; i < n; ++i)
    points.emplace_back(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);

  std::size_t ours_tets = 0, ours_tets_2 = 0, cgal_tets = 0;
  const auto on_threads = [](std::size_t threads, auto&& f) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    f();
  };
  const auto best =
      voroclip::bench::best_times(runs, {[&] {
                                           on_threads(1, [&] {
                                             const voroclip::Delaunay3 d(xyz.data(), n);
                                             ours_tets = d.nb_finite_tets();
                                           });
                                         },
                                         [&] {
                                           on_threads(1, [&] {
                                             const CgalDelaunay dt(points.begin(), points.end());
                                             cgal_tets = dt.number_of_finite_cells();
                                           });
                                         },
                                         [&] {
                                           on_threads(2, [&] {
                                             const voroclip::Delaunay3 d(xyz.data(), n);
                                             ours_tets_2 = d.nb_finite_tets();
                                           });
                                         }});
  std::printf("points                 %u  (best of %d, wall / CPU)\n", n, runs);
  std::printf("voroclip Delaunay3     %.3f / %.3f s  (%zu tetrahedra, one thread)\n", best[0].wall,
              best[0].cpu, ours_tets);
  std::printf("CGAL Delaunay_3        %.3f / %.3f s  (%zu tetrahedra, one thread)\n", best[1].wall,
              best[1].cpu, cgal_tets);
  std::printf("ratio ours / CGAL      %.2f / %.2f\n", best[0].wall / best[1].wall,
              best[0].cpu / best[1].cpu);
  std::printf("voroclip, two threads  %.3f / %.3f s  (%zu tetrahedra)\n", best[2].wall, best[2].cpu,
              ours_tets_2);
  return ours_tets == cgal_tets && ours_tets_2 == cgal_tets ? 0 : 1;
}
