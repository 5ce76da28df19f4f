// Tests of SizingField3 (voroclip/mesh.h): lfs on a sphere is its radius, the grid values
// are the Lipschitz envelope of the boundary lfs (checked against the brute-force minimum
// over all boundary vertices), the floor h_min, densities, errors.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "mesh_test_shapes.h"
#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/mesh.h"

using voroclip::Domain3;
using voroclip::SizingField3;

namespace {

const std::string kData = VOROCLIP_SHARED_DATA_DIR;

Domain3 model(const std::string& name) {
  return Domain3(voroclip::read_tet_mesh(kData + "/tetmeshes/" + name + ".mesh"));
}

std::vector<std::uint32_t> boundary_vertices(const Domain3& d) {
  std::vector<std::uint32_t> v;
  for (std::uint32_t b = 0; b < d.surface().nb_triangles(); ++b) {
    for (int k = 0; k < 3; ++k) v.push_back(d.surface().triangle_vertex(b, k));
  }
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

// Every grid node against min over boundary vertices of lfs(v) + g |x - v| (and h_min); the
// boundary vertices of `d` with f's vertex_lfs, or of each of `parts` with its own lfs.
void check_envelope(const Domain3& d, const SizingField3& f, double g,
                    const std::vector<const Domain3*>& parts = {},
                    const std::vector<const SizingField3*>& part_fields = {}) {
  std::vector<std::pair<const double*, double>> seeds;  // position, lfs
  if (parts.empty()) {
    for (const std::uint32_t v : boundary_vertices(d))
      seeds.emplace_back(d.vertex(v), f.vertex_lfs()[v]);
  }
  for (std::size_t i = 0; i < parts.size(); ++i) {
    for (const std::uint32_t v : boundary_vertices(*parts[i])) {
      seeds.emplace_back(parts[i]->vertex(v), part_fields[i]->vertex_lfs()[v]);
    }
  }
  const std::uint32_t* n = f.grid_size();
  std::size_t exact = 0, nodes = 0;
  double worst = 0;
  for (std::uint32_t k = 0; k < n[2]; ++k) {
    for (std::uint32_t j = 0; j < n[1]; ++j) {
      for (std::uint32_t i = 0; i < n[0]; ++i) {
        const double x[3] = {f.grid_origin()[0] + f.grid_spacing() * i,
                             f.grid_origin()[1] + f.grid_spacing() * j,
                             f.grid_origin()[2] + f.grid_spacing() * k};
        double best = HUGE_VAL;
        for (const auto& [p, lfs] : seeds) {
          best = std::min(best, lfs + g * std::sqrt((x[0] - p[0]) * (x[0] - p[0]) +
                                                    (x[1] - p[1]) * (x[1] - p[1]) +
                                                    (x[2] - p[2]) * (x[2] - p[2])));
        }
        best = std::max(best, f.min_size());
        const double h = f.grid_values()[(std::size_t{k} * n[1] + j) * n[0] + i];
        if (h == best) ++exact;
        worst = std::max(worst, (h - best) / best);
        ++nodes;
      }
    }
  }
  INFO(exact << " of " << nodes << " nodes exact, worst relative excess " << worst);
  REQUIRE(exact == nodes);
}

}  // namespace

TEST_CASE("sizing3d: the lfs of a sphere is its radius", "[mesh]") {
  const Domain3 d = model("sphere");
  voroclip::Sizing3Options o;
  o.resolution = 24;
  const SizingField3 f(d, o);
  const std::vector<std::uint32_t> bv = boundary_vertices(d);
  REQUIRE(bv.size() == 642);
  for (const std::uint32_t v : bv) {
    INFO("vertex " << v << " lfs " << f.vertex_lfs()[v]);
    // Inner poles of a fine sampling of the unit sphere are near its centre.
    REQUIRE(f.vertex_lfs()[v] > 0.9);
    REQUIRE(f.vertex_lfs()[v] <= 1.0);
  }
  check_envelope(d, f, o.gradation);
  // At the centre h = min_v (lfs(v) + g |v|) ~ 1 + g.
  const double centre[3] = {0, 0, 0};
  REQUIRE(f.size(centre) > 0.9 * (1 + o.gradation));
  REQUIRE(f.size(centre) <= 1 + o.gradation);
}

TEST_CASE("sizing3d: bunny: envelope, floor and densities", "[mesh]") {
  const Domain3 d = model("bunny");
  voroclip::Sizing3Options o;
  o.resolution = 20;
  o.gradation = 0.3;
  o.max_ratio = 8;
  const SizingField3 f(d, o);
  double lfs_max = 0;
  for (const double l : f.vertex_lfs()) {
    REQUIRE(std::isfinite(l));
    REQUIRE(l >= 0);
    lfs_max = std::max(lfs_max, l);
  }
  REQUIRE(f.min_size() == lfs_max / o.max_ratio);
  for (const double h : f.grid_values()) REQUIRE(h >= f.min_size());
  check_envelope(d, f, o.gradation);
  const std::vector<double> rho = f.vertex_density(d);
  REQUIRE(rho.size() == d.nb_vertices());
  for (std::uint32_t v = 0; v < d.nb_vertices(); ++v) {
    const double h = f.size(d.vertex(v));
    REQUIRE(rho[v] == 1 / (h * h * h * h * h));
  }
}

TEST_CASE("sizing3d: a domain of regions is sized by each region's boundary", "[mesh]") {
  // The unit cube in 6^3 voxels, the box [1/3, 2/3]^3 region 2 (an inclusion), the rest 1.
  const voroclip::TetMeshInput in =
      voroclip_test::region_grid(6, [](std::uint32_t i, std::uint32_t j, std::uint32_t k) {
        return i >= 2 && i < 4 && j >= 2 && j < 4 && k >= 2 && k < 4 ? 2 : 1;
      });
  const Domain3 whole(in);
  const auto region = [&](std::int32_t tag) {
    voroclip::TetMeshInput r;
    r.source = "region " + std::to_string(tag);
    r.xyz = in.xyz;
    for (std::size_t t = 0; t < in.tet_ref.size(); ++t) {
      if (in.tet_ref[t] == tag) r.tets.insert(r.tets.end(), &in.tets[4 * t], &in.tets[4 * t] + 4);
    }
    return Domain3(r);
  };
  const Domain3 outer = region(1), inner = region(2);
  voroclip::Sizing3Options o;
  o.resolution = 16;
  const SizingField3 one(whole, o), f_outer(outer, o), f_inner(inner, o);
  const SizingField3 f(whole, {&outer, &inner}, o);
  // The grid is the domain's; every node is the minimum over both regions' boundary vertices,
  // each with its lfs in its own region, exactly.
  REQUIRE(f.grid_spacing() == one.grid_spacing());
  REQUIRE(f.min_size() == std::max(f_outer.min_size(), f_inner.min_size()));
  check_envelope(whole, f, o.gradation, {&outer, &inner}, {&f_outer, &f_inner});
  // A vertex's lfs is the smaller of its regions' (the interface's vertices have both).
  std::size_t on_interface = 0;
  for (std::uint32_t v = 0; v < whole.nb_vertices(); ++v) {
    const double a = f_outer.vertex_lfs()[v], b = f_inner.vertex_lfs()[v];
    if (a > 0 && b > 0) ++on_interface;
    REQUIRE(f.vertex_lfs()[v] == (a == 0 ? b : b == 0 ? a : std::min(a, b)));
  }
  REQUIRE(on_interface == 3 * 3 * 3 - 1);  // the grid points on the inner box's surface
  // The inclusion sizes the field around it: at the centre, within its half width (1/6) plus
  // the gradation over that distance; the outer boundary alone gives more.
  const double centre[3] = {0.5, 0.5, 0.5};
  REQUIRE(f.size(centre) <= 1.0 / 6 * (1 + o.gradation) + 1e-12);
  REQUIRE(one.size(centre) > 1.5 * f.size(centre));
  // A part on other vertices is refused.
  const Domain3 sphere = model("sphere");
  REQUIRE_THROWS_AS(SizingField3(whole, {&outer, &sphere}, o), voroclip::Error);
}

TEST_CASE("sizing3d: invalid options", "[mesh]") {
  const Domain3 d = model("sphere");
  voroclip::Sizing3Options o;
  o.resolution = 1;
  REQUIRE_THROWS_WITH(SizingField3(d, o), Catch::Contains("resolution"));
  o = {};
  o.gradation = 0;
  REQUIRE_THROWS_WITH(SizingField3(d, o), Catch::Contains("gradation"));
}
