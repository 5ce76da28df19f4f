// Step 5a of mesh3d (mesh3d_pipeline.h): the boundary's distance to the input. The input
// vertices farthest from the boundary of the mesh the sites would give (the tips, ridges
// and thin parts that the spacing of the sites cuts off) get a site fixed on them, round
// after round with a short constrained CVT in between, until every input vertex is within
// facet_distance times the local spacing of that boundary (Mesh3Options::facet_distance).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "mesh3d_pipeline.h"
#include "mesh3d_tags.h"

namespace voroclip::mesh3 {

namespace {

double distance2(const double* a, const double* b) {
  const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
  return dx * dx + dy * dy + dz * dz;
}

}  // namespace

void Pipeline::approximate_boundary(const TetExtractor3& extractor, Cvt3Options& cvt,
                                    const Spacing& local_spacing,
                                    const std::vector<std::uint8_t>& boundary,
                                    const Projection& project,
                                    const std::function<SurfacePatches()>& site_patches_now) {
  if (!(options.facet_distance > 0) || options.facet_distance_rounds == 0) return;
  const Surface3& input = domain.surface();
  // The points tested: the input's boundary vertices, increasing. (Midpoints of the input's
  // edges too, with a surface site there, measured on bunny at 10k: 0.75 -> 0.70 % of the
  // diagonal but no convergence, the surface sites drifting off the knife edges in the
  // CVT, and 50 % more time.)
  std::vector<std::uint32_t> targets;
  {
    std::vector<std::uint8_t> used(domain.nb_vertices(), 0);
    for (std::uint32_t b = 0; b < input.nb_triangles(); ++b) {
      for (int k = 0; k < 3; ++k) used[input.triangle_vertex(b, k)] = 1;
    }
    for (std::uint32_t v = 0; v < domain.nb_vertices(); ++v) {
      if (used[v] != 0) targets.push_back(v);
    }
  }
  std::vector<std::uint8_t> has_site(domain.nb_vertices(), 0);  // a site is fixed there
  for (const std::uint32_t v : corner_vertex) {
    if (v != SurfaceTree::kNone) has_site[v] = 1;
  }
  // At most this many sites moved or added in all (a few % of the count asked).
  const auto budget = static_cast<std::uint32_t>(options.facet_distance_budget * n);
  std::vector<double> excess(targets.size());

  for (std::uint32_t round = 0; round < options.facet_distance_rounds; ++round) {
    // The mesh of the current sites, as step 6 extracts it, and its boundary.
    const Delaunay3 dt(sites.data(), n);
    const SurfacePatches patches = site_patches_now();
    Extract3Options eo = options.perturbation.extraction;
    eo.surface = &patches;
    TriangleSurface mesh_boundary;
    mesh_boundary.source = "mesh3d (boundary)";
    std::vector<std::uint32_t> face_tet;
    boundary_triangles(extractor.extract(dt, eo), mesh_boundary.triangles, face_tet);
    if (mesh_boundary.triangles.empty()) return;
    mesh_boundary.xyz = sites;
    const SurfaceTree tree(mesh_boundary);
    // Each input vertex's distance to it, over the local spacing (in slots: the same for
    // any thread count).
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, targets.size(), 256), [&](const auto& range) {
          for (std::size_t i = range.begin(); i != range.end(); ++i) {
            const double* p = domain.vertex(targets[i]);
            const SurfaceTree::Closest c = tree.closest(p);
            excess[i] =
                c.triangle == SurfaceTree::kNone ? 0 : std::sqrt(c.distance2) / local_spacing(p);
          }
        });
    std::vector<std::uint32_t> order;
    for (std::uint32_t i = 0; i < targets.size(); ++i) {
      if (excess[i] > options.facet_distance && has_site[targets[i]] == 0) order.push_back(i);
    }
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
      return excess[a] != excess[b] ? excess[a] > excess[b] : a < b;
    });
    // Farthest first, one per neighbourhood of a local spacing per round: the nearest
    // surface site moves onto the vertex and is fixed there when it is within a spacing,
    // else a new fixed site is added; when the nearest site is a feature or corner site
    // within a quarter spacing, nothing (a site there would make a short edge).
    std::vector<std::uint32_t> taken;  // sites placed this round
    std::uint32_t placed = 0;
    for (const std::uint32_t i : order) {
      if (result.nb_distance_sites == budget) break;
      const std::uint32_t v = targets[i];
      const double* p = domain.vertex(v);
      const double h = local_spacing(p);
      bool near = false;
      for (const std::uint32_t s : taken) {
        near = near || distance2(&sites[3 * std::size_t{s}], p) < h * h;
      }
      if (near) continue;
      std::uint32_t nearest = 0;
      double best = std::numeric_limits<double>::infinity();
      for (std::uint32_t s = 0; s < n; ++s) {
        const double d2 = distance2(&sites[3 * std::size_t{s}], p);
        if (d2 < best) {
          best = d2;
          nearest = s;
        }
      }
      std::uint32_t s = nearest;
      if (kinds[nearest] == Kind::kSurface && best < h * h) {
        --result.nb_boundary_sites;
      } else if (kinds[nearest] != Kind::kSurface && kinds[nearest] != Kind::kFree &&
                 best < 0.0625 * h * h) {
        continue;
      } else {
        s = n++;
        sites.insert(sites.end(), 3, 0.0);
        kinds.push_back(Kind::kFixed);
        line_of.push_back(SurfaceTree::kNone);
        corner_vertex.push_back(SurfaceTree::kNone);
        ++result.nb_distance_sites_added;
      }
      std::copy_n(p, 3, &sites[3 * std::size_t{s}]);
      kinds[s] = Kind::kFixed;
      line_of[s] = SurfaceTree::kNone;
      corner_vertex[s] = v;
      has_site[v] = 1;
      taken.push_back(s);
      ++placed;
      ++result.nb_distance_sites;
      ++result.nb_corner_sites;
    }
    if (placed == 0) break;
    // Spread the sites around them: a short constrained CVT; free sites whose cells now
    // reach the surface go onto it (as after step 5).
    cvt.constraints = kinds;
    cvt.max_iterations = options.facet_distance_iterations;
    const CvtResult r = optimize_cvt3(domain, sites, cvt);
    if (r.cancelled) throw Cancelled{};
    snap_boundary_free_sites(boundary, project);
  }
  result.nb_sites = n;
}

}  // namespace voroclip::mesh3
