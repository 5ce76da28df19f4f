// Delaunay3 against CGAL's Delaunay_triangulation_3 (Epick kernel, spatially sorted range
// insertion) on the same uniform random points in the unit cube, in one process. Prints
// the best of a few runs of each, the ratio ours / CGAL, and checks that both have the
// same number of finite tetrahedra (issue 3: 1M points, <= 2.0 s on one thread, about half
// of CGAL). Runs on one thread: TBB is limited to one worker for both.
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
  const tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  std::mt19937_64 rng(20261122);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> xyz(3 * static_cast<std::size_t>(n));
  for (double& x : xyz) x = u(rng);
  std::vector<Kernel::Point_3> points;
  points.reserve(n);
  for (std::uint32_t i = 0; i < n; ++i)
    points.emplace_back(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);

  std::size_t ours_tets = 0, cgal_tets = 0;
  const double ours = voroclip::bench::best_seconds(runs, [&] {
    const voroclip::Delaunay3 d(xyz.data(), n);
    ours_tets = d.nb_finite_tets();
  });
  const double cgal = voroclip::bench::best_seconds(runs, [&] {
    const CgalDelaunay dt(points.begin(), points.end());
    cgal_tets = dt.number_of_finite_cells();
  });
  std::printf("points                 %u\n", n);
  std::printf("voroclip Delaunay3     %.3f s  (%zu tetrahedra)\n", ours, ours_tets);
  std::printf("CGAL Delaunay_3        %.3f s  (%zu tetrahedra)\n", cgal, cgal_tets);
  std::printf("ratio ours / CGAL      %.2f\n", ours / cgal);
  return ours_tets == cgal_tets ? 0 : 1;
}
