// Embedding voroclip: the Voronoi cells of 27 sites clipped to a box given by its surface,
// printed as a table (one row per cell: site, volume, centroid, ...), then checked: the
// cells' volumes add up to the box's. Built against the installed package by
// tests/install and in the tree by examples/CMakeLists.txt; both runs check the output.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <vector>

#include "voroclip/clip.h"
#include "voroclip/core.h"

int main() {
  // The box [0, 3] x [0, 3] x [0, 1] as 12 triangles, counter-clockwise seen from outside;
  // vertex i is at (i & 1 ? 3 : 0, i & 2 ? 3 : 0, i & 4 ? 1 : 0).
  voroclip::TriangleSurface box;
  box.source = "box";
  for (int i = 0; i < 8; ++i) {
    box.xyz.insert(box.xyz.end(), {i & 1 ? 3.0 : 0.0, i & 2 ? 3.0 : 0.0, i & 4 ? 1.0 : 0.0});
  }
  box.triangles = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                   2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
  const voroclip::Domain3 domain(box);  // validated exactly; throws voroclip::Error

  // 27 sites: a 3 x 3 x 3 grid, shifted a little so that no four are cospherical.
  std::vector<double> sites;
  for (int k = 0; k < 3; ++k) {
    for (int j = 0; j < 3; ++j) {
      for (int i = 0; i < 3; ++i) {
        sites.insert(sites.end(), {0.5 + i + 0.01 * j, 0.5 + j + 0.01 * k, (0.5 + k) / 3});
      }
    }
  }
  const auto n = static_cast<std::uint32_t>(sites.size() / 3);

  voroclip::ClippedVoronoi3 cells;
  voroclip::Clip3Options options;
  options.keep_geometry = true;  // the cells' faces: needed for the neighbour pairs
  cells.compute(domain, sites.data(), n, options);

  const voroclip::NeighborTable pairs = voroclip::cell_neighbors(cells);
  const voroclip::CellTable table = voroclip::cell_table(cells, sites.data(), &pairs);
  voroclip::write_cell_table_csv(std::cout, table);

  char summary[160];
  std::snprintf(summary, sizeof summary,
                "%u cells, %u neighbour pairs, volume %.12g (domain %.12g), %u boundary cells\n",
                cells.nb_sites(), pairs.nb_pairs(), cells.total_volume(), domain.volume(),
                cells.nb_boundary_sites());
  std::cout << summary;
  return std::fabs(cells.total_volume() - domain.volume()) <= 1e-12 * domain.volume() ? 0 : 1;
}
