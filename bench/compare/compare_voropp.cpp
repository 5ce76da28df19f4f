// ClippedVoronoi3 against voro++ (Rycroft 2009; its Debian package, modified BSD licence)
// on the same task, in one process: the Voronoi cells of n uniform random sites clipped to
// the unit cube, with the volume and the centroid of every cell. voro++ computes each cell
// by cutting a box with the planes of nearby particles (container with walls, blocks
// chosen by its pre_container); voroclip triangulates the sites (Delaunay3) and clips
// against the cube given as a tet mesh (a k x k x k grid of cubes, 6 tets each). Prints
// the best wall and CPU time of a few interleaved runs and the cells per second per core
// from the wall times on one thread (all of voro++'s time; voroclip's total and its
// clipping alone, as bench_table1's column: the phases are timed by the wall clock, so run
// it on a quiet machine), voroclip on two threads, and checks that both found n cells whose volumes
// sum to 1 and agree (issue 5: "voro++ clips about 89k cells/s per core in a box"; target >= 500k
// cells/s per core of clipping).
//   compare_voropp [n = 100000] [runs = 3] [k = 8]
#include <tbb/global_control.h>
#include <voro++/voro++.hh>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "best_time.h"
#include "voroclip/clip.h"
#include "voroclip/core.h"

namespace {

// The unit cube as k^3 cubes of 6 tets each (Kuhn's subdivision: the tets around the
// cube's diagonal from corner 0 to corner 7, consistently oriented across cubes).
voroclip::TetMeshInput unit_cube(std::uint32_t k) {
  voroclip::TetMeshInput mesh;
  mesh.source = "unit cube";
  const std::uint32_t side = k + 1;
  for (std::uint32_t z = 0; z < side; ++z) {
    for (std::uint32_t y = 0; y < side; ++y) {
      for (std::uint32_t x = 0; x < side; ++x) {
        mesh.xyz.push_back(static_cast<double>(x) / k);
        mesh.xyz.push_back(static_cast<double>(y) / k);
        mesh.xyz.push_back(static_cast<double>(z) / k);
      }
    }
  }
  // Corner c of a cube: bit 0 x, bit 1 y, bit 2 z. Each path 0 -> 7 along the axes in
  // one of the 6 orders gives a tet (0, a, b, 7); Domain3 orients every tet positively.
  const int paths[6][2] = {{1, 3}, {1, 5}, {2, 3}, {2, 6}, {4, 5}, {4, 6}};
  for (std::uint32_t z = 0; z < k; ++z) {
    for (std::uint32_t y = 0; y < k; ++y) {
      for (std::uint32_t x = 0; x < k; ++x) {
        const auto corner = [&](int c) {
          return (x + (c & 1)) + side * ((y + ((c >> 1) & 1)) + side * (z + ((c >> 2) & 1)));
        };
        for (const auto& p : paths) {
          mesh.tets.insert(mesh.tets.end(), {corner(0), corner(p[0]), corner(p[1]), corner(7)});
        }
      }
    }
  }
  return mesh;
}

struct VoroppResult {
  std::uint32_t cells = 0;
  double volume = 0;
  std::vector<double> volumes;
  std::vector<double> centroids;
};

void run_voropp(const std::vector<double>& xyz, std::uint32_t n, VoroppResult& out) {
  voro::pre_container pcon(0, 1, 0, 1, 0, 1, false, false, false);
  for (std::uint32_t i = 0; i < n; ++i) {
    pcon.put(static_cast<int>(i), xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
  }
  int nx = 0, ny = 0, nz = 0;
  pcon.guess_optimal(nx, ny, nz);
  voro::container con(0, 1, 0, 1, 0, 1, nx, ny, nz, false, false, false, 8);
  pcon.setup(con);
  voro::voronoicell c;
  voro::c_loop_all loop(con);
  out.cells = 0;
  out.volume = 0;
  double cx = 0, cy = 0, cz = 0, sum = 0, x = 0, y = 0, z = 0;
  if (loop.start()) {
    do {
      if (con.compute_cell(c, loop)) {
        const double v = c.volume();
        c.centroid(cx, cy, cz);  // relative to the particle
        loop.pos(x, y, z);
        const auto id = static_cast<std::size_t>(loop.pid());
        out.volumes[id] = v;
        out.centroids[3 * id] = x + cx;
        out.centroids[3 * id + 1] = y + cy;
        out.centroids[3 * id + 2] = z + cz;
        sum += v;
        ++out.cells;
      }
    } while (loop.inc());
  }
  out.volume = sum;
}

}  // namespace

int main(int argc, char** argv) {
  const std::uint32_t n = argc > 1 ? static_cast<std::uint32_t>(std::atol(argv[1])) : 100000u;
  const int runs = argc > 2 ? std::atoi(argv[2]) : 3;
  const std::uint32_t k = argc > 3 ? static_cast<std::uint32_t>(std::atol(argv[3])) : 8u;
  if (n < 4 || runs < 1 || k < 1) {
    std::fprintf(stderr, "usage: compare_voropp [n >= 4] [runs >= 1] [k >= 1]\n");
    return 2;
  }
  std::mt19937_64 rng(20261122);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> xyz(3 * static_cast<std::size_t>(n));
  for (double& x : xyz) x = u(rng);
  const voroclip::Domain3 domain(unit_cube(k));

  VoroppResult voropp;  // its arrays allocated here, not in the timed runs
  voropp.volumes.assign(n, 0.0);
  voropp.centroids.assign(3 * static_cast<std::size_t>(n), 0.0);
  voroclip::ClippedVoronoi3 ours, ours2;
  double best_clip = 1e300, best_clip2 = 1e300;
  double best_split[3] = {0, 0, 0};  // surface, boundary cells, inner cells of best_clip
  const auto on_threads = [](std::size_t threads, auto&& f) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    f();
  };
  const auto clipping = [](const voroclip::ClippedVoronoi3& cv) {
    return cv.seconds_surface() + cv.seconds_boundary_cells() + cv.seconds_inner_cells();
  };
  const auto best = voroclip::bench::best_times(
      runs, {[&] { run_voropp(xyz, n, voropp); },
             [&] {
               on_threads(1, [&] { ours.compute(domain, xyz.data(), n); });
               if (clipping(ours) < best_clip) {
                 best_clip = clipping(ours);
                 best_split[0] = ours.seconds_surface();
                 best_split[1] = ours.seconds_boundary_cells();
                 best_split[2] = ours.seconds_inner_cells();
               }
             },
             [&] {
               on_threads(2, [&] { ours2.compute(domain, xyz.data(), n); });
               best_clip2 = std::min(best_clip2, clipping(ours2));
             }});

  double max_diff = 0, max_centroid_diff = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    max_diff = std::max(max_diff, std::fabs(ours.volume(i) - voropp.volumes[i]));
    for (int c = 0; c < 3; ++c) {
      max_centroid_diff =
          std::max(max_centroid_diff, std::fabs(ours.centroid(i)[c] - voropp.centroids[3 * i + c]));
    }
  }
  std::printf("sites                  %u in the unit cube (%u tets), best of %d, wall / CPU\n", n,
              domain.nb_tets(), runs);
  std::printf("voro++                 %.3f / %.3f s  %7.0fk cells/s  (one thread)\n", best[0].wall,
              best[0].cpu, n / best[0].wall / 1000);
  std::printf("voroclip, total        %.3f / %.3f s  %7.0fk cells/s  (one thread)\n", best[1].wall,
              best[1].cpu, n / best[1].wall / 1000);
  std::printf(
      "voroclip, clipping     %.3f s          %7.0fk cells/s  (one thread, %u boundary "
      "cells)\n",
      best_clip, n / best_clip / 1000, ours.nb_boundary_sites());
  std::printf("  surface / boundary cells / inner cells  %.3f / %.3f / %.3f s\n", best_split[0],
              best_split[1], best_split[2]);
  std::printf("ratio voroclip / voro++ cells/s: total %.2f, clipping %.2f\n",
              best[0].wall / best[1].wall, best[0].wall / best_clip);
  std::printf("voroclip, two threads  %.3f / %.3f s  (clipping %.3f s, %.0fk cells/s per core)\n",
              best[2].wall, best[2].cpu, best_clip2, n / best_clip2 / 2 / 1000);
  std::printf("volume sums            voro++ %.15f (%u cells), voroclip %.15f (%u cells)\n",
              voropp.volume, voropp.cells, ours.total_volume(), ours.nb_sites());
  std::printf("largest difference       cell volume %.3g, centroid coordinate %.3g\n", max_diff,
              max_centroid_diff);
  const bool same = voropp.cells == n && ours.nb_sites() == n && max_diff < 1e-9 &&
                    max_centroid_diff < 1e-6 && std::fabs(voropp.volume - 1) < 1e-9 &&
                    std::fabs(ours.total_volume() - 1) < 1e-12;
  if (!same) {
    std::printf("MISMATCH: the two disagree\n");
    return 1;
  }
  return 0;
}
