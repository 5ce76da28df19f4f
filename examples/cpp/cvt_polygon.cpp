// Embedding voroclip: a centroidal Voronoi tessellation of 100 sites in an annulus (L-BFGS),
// then the clipped cells of the result. Checked: the energy went down and the cells' areas
// add up to the domain's.
#include <cmath>
#include <cstdio>
#include <vector>

#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/cvt.h"
#include "voroclip/delaunay.h"

int main() {
  // The annulus 0.5 <= r <= 1 as two 64-gons (outer ring, then the hole).
  const voroclip::Domain2 domain(voroclip::annulus_rings(0.5, 1.0, 64));

  // 100 sites inside: a grid's points that the domain contains (exact point location).
  std::vector<double> sites;
  for (int j = 0; j < 40 && sites.size() < 200; ++j) {
    for (int i = 0; i < 40 && sites.size() < 200; ++i) {
      const double p[2] = {-1 + (i + 0.5) / 20 + 0.001 * j, -1 + (j + 0.5) / 20};
      if (domain.locate(p) == voroclip::Sign::positive) sites.insert(sites.end(), p, p + 2);
    }
  }
  const double energy0 = voroclip::cvt_energy2(domain, sites, voroclip::Density2{});

  voroclip::Cvt2Options options;
  options.max_iterations = 200;
  const voroclip::Cvt2Result r = voroclip::optimize_cvt2(domain, sites, options);

  const auto n = static_cast<std::uint32_t>(sites.size() / 2);
  const voroclip::Delaunay2 dt(sites.data(), n);
  voroclip::ClippedVoronoi2 cells;
  cells.compute(domain, dt);
  const bool areas_sum = std::fabs(cells.total_area() - domain.area()) <= 1e-12 * domain.area();
  std::printf("CVT of %u sites: energy %s after %u iterations; cells' area %s the domain's\n", n,
              r.energy < energy0 ? "decreased" : "did not decrease", r.iterations,
              areas_sum ? "equals" : "differs from");
  return r.energy < energy0 && areas_sum ? 0 : 1;
}
