// Tests of ClippedVoronoi3 (voroclip/clip.h): cell volumes sum to the domain's volume
// (relative 1e-12), random points of the volume lie in a piece of the cell of their
// nearest site (decided exactly), an exhaustive reference (every cell against every tet,
// with every other site's bisector) gives the same cell volumes, the paper's robustness
// cases (Fig. 10: the sphere's boundary vertices as the only sites; Fig. 11: the cube's
// corners), integer grids, sites outside, 1 vs 2 threads.
#include <catch2/catch.hpp>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/delaunay.h"

using voroclip::ClippedVoronoi3;
using voroclip::Delaunay3;
using voroclip::Domain3;

namespace {

const std::string kData = VOROCLIP_SHARED_DATA_DIR;

double test_scale() {
  const char* s = std::getenv("VOROCLIP_TEST_SCALE");
  return s ? std::max(0.05, std::atof(s)) : 1.0;
}

// [0, k]^3 cut into k^3 unit cubes of 6 tets each (Kuhn's triangulation: conforming).
voroclip::TetMeshInput cube_mesh(std::uint32_t k) {
  voroclip::TetMeshInput m;
  m.source = "cube";
  const auto id = [&](std::uint32_t x, std::uint32_t y, std::uint32_t z) {
    return (z * (k + 1) + y) * (k + 1) + x;
  };
  for (std::uint32_t z = 0; z <= k; ++z) {
    for (std::uint32_t y = 0; y <= k; ++y) {
      for (std::uint32_t x = 0; x <= k; ++x)
        m.xyz.insert(m.xyz.end(), {double(x), double(y), double(z)});
    }
  }
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (std::uint32_t z = 0; z < k; ++z) {
    for (std::uint32_t y = 0; y < k; ++y) {
      for (std::uint32_t x = 0; x < k; ++x) {
        for (const auto& p : perms) {
          std::uint32_t c[3] = {x, y, z};
          std::uint32_t tet[4];
          tet[0] = id(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[p[s]];
            tet[s + 1] = id(c[0], c[1], c[2]);
          }
          m.tets.insert(m.tets.end(), tet, tet + 4);
          m.tet_line.push_back(0);
        }
      }
    }
  }
  return m;
}

// Uniform random points in the volume: a tet by volume, then uniform in it.
std::vector<double> sample_volume(const Domain3& d, std::uint32_t n, std::uint64_t seed,
                                  std::vector<std::uint32_t>* tet_of = nullptr) {
  std::vector<double> cumulative;
  double total = 0;
  for (std::uint32_t t = 0; t < d.nb_tets(); ++t) {
    const double* a = d.vertex(d.tet_vertex(t, 0));
    double u[3][3];
    for (int k = 0; k < 3; ++k) {
      const double* b = d.vertex(d.tet_vertex(t, k + 1));
      for (int c = 0; c < 3; ++c) u[k][c] = b[c] - a[c];
    }
    total += std::fabs(u[0][0] * (u[1][1] * u[2][2] - u[1][2] * u[2][1]) -
                       u[0][1] * (u[1][0] * u[2][2] - u[1][2] * u[2][0]) +
                       u[0][2] * (u[1][0] * u[2][1] - u[1][1] * u[2][0]));
    cumulative.push_back(total);
  }
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u01(0, 1);
  std::vector<double> xyz;
  for (std::uint32_t i = 0; i < n; ++i) {
    const double r = u01(rng) * total;
    const auto t = static_cast<std::uint32_t>(std::min<std::size_t>(
        std::lower_bound(cumulative.begin(), cumulative.end(), r) - cumulative.begin(),
        d.nb_tets() - 1));
    double b[4] = {u01(rng), u01(rng), u01(rng), 0};
    // Uniform barycentric coordinates: sort three uniforms, take the gaps.
    std::sort(b, b + 3);
    const double w[4] = {b[0], b[1] - b[0], b[2] - b[1], 1 - b[2]};
    double p[3] = {0, 0, 0};
    for (int k = 0; k < 4; ++k) {
      for (int c = 0; c < 3; ++c) p[c] += w[k] * d.vertex(d.tet_vertex(t, k))[c];
    }
    xyz.insert(xyz.end(), p, p + 3);
    if (tet_of) tet_of->push_back(t);
  }
  return xyz;
}

ClippedVoronoi3 clip(const Domain3& d, const Delaunay3& dt, bool geometry = true) {
  ClippedVoronoi3 cv;
  voroclip::Clip3Options o;
  o.keep_geometry = geometry;
  cv.compute(d, dt, o);
  return cv;
}

// Volumes sum to the domain's; random points in the pieces of their nearest site's cell.
void check_diagram(const Domain3& d, const Delaunay3& dt, const ClippedVoronoi3& cv,
                   std::uint32_t nb_probes, std::uint64_t seed) {
  INFO(d.source() << ", " << dt.nb_points() << " sites, seed " << seed);
  REQUIRE(std::fabs(cv.total_volume() - d.volume()) <= 1e-12 * d.volume());
  std::uint32_t boundary = 0;
  for (std::uint32_t i = 0; i < cv.nb_sites(); ++i) {
    REQUIRE(cv.volume(i) >= -1e-14 * d.volume());
    if (cv.is_boundary(i)) {
      ++boundary;  // its restricted surface is non-empty, possibly of zero area
      REQUIRE(cv.surface_area(i) >= 0);
    } else {
      REQUIRE(cv.surface_area(i) == 0);
    }
    if (dt.duplicate_of(i) != i) REQUIRE(cv.volume(i) == 0);
  }
  REQUIRE(boundary == cv.nb_boundary_sites());
  // Pieces of boundary cells: planes of their faces (inward: kTetFacetVertex order).
  const ClippedVoronoi3::Polygons& f = cv.cell_faces();
  std::vector<std::uint32_t> piece_first(1, 0);
  for (std::size_t k = 1; k < f.piece.size(); ++k) {
    if (f.piece[k] != f.piece[k - 1]) piece_first.push_back(static_cast<std::uint32_t>(k));
  }
  piece_first.push_back(static_cast<std::uint32_t>(f.piece.size()));
  std::vector<std::vector<std::uint32_t>> cell_pieces(cv.nb_sites());
  for (std::size_t q = 0; q + 1 < piece_first.size(); ++q) {
    cell_pieces[f.site[piece_first[q]]].push_back(static_cast<std::uint32_t>(q));
  }
  const auto in_piece = [&](std::uint32_t q, const double* x) {
    // Faces of (numerically) zero area carry no orientation: the perturbation makes them,
    // e.g. where a bisector runs through a mesh edge. Their planes are skipped.
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (std::uint32_t v = f.polygon_begin[piece_first[q]]; v < f.polygon_begin[piece_first[q + 1]];
         ++v) {
      for (int c = 0; c < 3; ++c) {
        lo[c] = std::min(lo[c], f.xyz[3 * std::size_t{v} + c]);
        hi[c] = std::max(hi[c], f.xyz[3 * std::size_t{v} + c]);
      }
    }
    const double size2 = (hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                         (hi[2] - lo[2]) * (hi[2] - lo[2]);
    for (std::uint32_t k = piece_first[q]; k < piece_first[q + 1]; ++k) {
      const double* a = &f.xyz[3 * std::size_t{f.polygon_begin[k]}];
      const std::uint32_t nv = f.polygon_begin[k + 1] - f.polygon_begin[k];
      // Newell normal of the face (robust to tiny edges).
      double nrm[3] = {0, 0, 0};
      for (std::uint32_t v = 0; v < nv; ++v) {
        const double* p = &f.xyz[3 * std::size_t{f.polygon_begin[k] + v}];
        const double* r = &f.xyz[3 * std::size_t{f.polygon_begin[k] + (v + 1) % nv}];
        nrm[0] += (p[1] - r[1]) * (p[2] + r[2]);
        nrm[1] += (p[2] - r[2]) * (p[0] + r[0]);
        nrm[2] += (p[0] - r[0]) * (p[1] + r[1]);
      }
      const double area2 = nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2];
      if (area2 <= 1e-20 * size2 * size2) continue;
      const double side = nrm[0] * (x[0] - a[0]) + nrm[1] * (x[1] - a[1]) + nrm[2] * (x[2] - a[2]);
      if (side < 0) return false;  // faces are inward-oriented
    }
    return true;
  };
  const std::vector<double> probes = sample_volume(d, nb_probes, seed + 1000);
  for (std::uint32_t q = 0; q < nb_probes; ++q) {
    const double* x = &probes[3 * std::size_t{q}];
    const std::uint32_t s = dt.nearest_vertex(x);
    INFO("probe " << q << " nearest site " << s);
    if (!cv.is_boundary(s)) {
      REQUIRE(cv.volume(s) > 0);
      continue;
    }
    bool found = false;
    for (const std::uint32_t p : cell_pieces[s]) found = found || in_piece(p, x);
    REQUIRE(found);
  }
}

}  // namespace

TEST_CASE("clip3d: every model of shared/data/tetmeshes", "[clip][data]") {
  const char* models[] = {"sphere", "bunny",     "skull_low_resolution", "elk", "fandisk",
                          "homer",  "rocker-arm"};
  for (const char* m : models) {
    const Domain3 d(voroclip::read_tet_mesh(kData + "/tetmeshes/" + m + ".mesh"));
    for (const std::uint32_t n : {1000u, static_cast<std::uint32_t>(10000 * test_scale())}) {
      const std::vector<double> sites = sample_volume(d, n, n);
      const Delaunay3 dt(sites.data(), n);
      check_diagram(d, dt, clip(d, dt), 2000, n);
    }
  }
}

TEST_CASE("clip3d: 10^5 sites in sphere-fine, 10^5 probes", "[clip][data]") {
  const Domain3 d(voroclip::read_tet_mesh(kData + "/tetmeshes/sphere-fine.mesh"));
  const auto n = static_cast<std::uint32_t>(100000 * test_scale());
  const std::vector<double> sites = sample_volume(d, n, 5);
  const Delaunay3 dt(sites.data(), n);
  check_diagram(d, dt, clip(d, dt), static_cast<std::uint32_t>(100000 * test_scale()), 5);
}

TEST_CASE("clip3d: exhaustive reference on small cases", "[clip]") {
  // Every cell against every tet, independently of the library: a floating-point convex
  // clipper (triangulated surface, cap by angular order) cuts each tet by the bisectors
  // of ALL the other sites; a cell's volume is the sum over all tets. Generic random
  // input, so floating point is reliable here.
  const Domain3 d(voroclip::read_tet_mesh(kData + "/tetmeshes/sphere.mesh"));
  using Tri = std::array<std::array<double, 3>, 3>;
  const auto clip_surface = [](const std::vector<Tri>& in, const double* nrm, double off) {
    // Keep nrm.x + off <= 0.
    std::vector<Tri> out;
    std::vector<std::array<double, 3>> cut;
    for (const Tri& t : in) {
      std::vector<std::array<double, 3>> poly;
      for (int k = 0; k < 3; ++k) {
        const auto& a = t[static_cast<std::size_t>(k)];
        const auto& b = t[static_cast<std::size_t>((k + 1) % 3)];
        const double fa = nrm[0] * a[0] + nrm[1] * a[1] + nrm[2] * a[2] + off;
        const double fb = nrm[0] * b[0] + nrm[1] * b[1] + nrm[2] * b[2] + off;
        if (fa <= 0) poly.push_back(a);
        if ((fa < 0) != (fb < 0)) {
          const double s = fa / (fa - fb);
          const std::array<double, 3> x = {a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]),
                                           a[2] + s * (b[2] - a[2])};
          poly.push_back(x);
          cut.push_back(x);
        }
      }
      for (std::size_t k = 1; k + 1 < poly.size(); ++k)
        out.push_back({poly[0], poly[k], poly[k + 1]});
    }
    if (cut.size() >= 3 && !out.empty()) {
      // The cap: cut points around their centroid, fanned; orientation fixed by volume.
      std::array<double, 3> c = {0, 0, 0};
      for (const auto& x : cut) {
        for (int q = 0; q < 3; ++q)
          c[static_cast<std::size_t>(q)] += x[static_cast<std::size_t>(q)] / double(cut.size());
      }
      double e1[3] = {cut[0][0] - c[0], cut[0][1] - c[1], cut[0][2] - c[2]};
      const double e2[3] = {nrm[1] * e1[2] - nrm[2] * e1[1], nrm[2] * e1[0] - nrm[0] * e1[2],
                            nrm[0] * e1[1] - nrm[1] * e1[0]};
      std::sort(cut.begin(), cut.end(), [&](const auto& x, const auto& y) {
        const double ax =
            std::atan2((x[0] - c[0]) * e2[0] + (x[1] - c[1]) * e2[1] + (x[2] - c[2]) * e2[2],
                       (x[0] - c[0]) * e1[0] + (x[1] - c[1]) * e1[1] + (x[2] - c[2]) * e1[2]);
        const double ay =
            std::atan2((y[0] - c[0]) * e2[0] + (y[1] - c[1]) * e2[1] + (y[2] - c[2]) * e2[2],
                       (y[0] - c[0]) * e1[0] + (y[1] - c[1]) * e1[1] + (y[2] - c[2]) * e1[2]);
        return ax < ay;
      });
      for (std::size_t k = 0; k < cut.size(); ++k) {
        // Outward normal of the cap is +nrm: (c, x_k, x_k+1) counter-clockwise around nrm.
        out.push_back({c, cut[k], cut[(k + 1) % cut.size()]});
      }
    }
    return out;
  };
  const auto volume_of = [](const std::vector<Tri>& s) {
    double v = 0;
    for (const Tri& t : s) {
      const auto& a = t[0];
      const auto& b = t[1];
      const auto& c = t[2];
      v += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
           a[2] * (b[0] * c[1] - b[1] * c[0]);
    }
    return v / 6;
  };
  for (std::uint64_t seed = 1; seed <= 2; ++seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1.3, 1.3);
    const std::uint32_t n = 20;
    std::vector<double> sites(3 * n);
    for (double& x : sites) x = u(rng);  // some outside the unit ball
    const Delaunay3 dt(sites.data(), n);
    const ClippedVoronoi3 cv = clip(d, dt, false);
    for (std::uint32_t i = 0; i < n; ++i) {
      INFO("seed " << seed << " site " << i);
      double volume = 0;
      const double* pi = &sites[3 * i];
      for (std::uint32_t t = 0; t < d.nb_tets(); ++t) {
        std::array<std::array<double, 3>, 4> v;
        for (int k = 0; k < 4; ++k) {
          for (int c = 0; c < 3; ++c)
            v[static_cast<std::size_t>(k)][static_cast<std::size_t>(c)] =
                d.vertex(d.tet_vertex(t, k))[c];
        }
        // Outward faces of a tet with orient3d > 0 (negative standard volume): reversed
        // kTetFacetVertex.
        std::vector<Tri> surface;
        for (int f = 0; f < 4; ++f) {
          const int* fv = Domain3::kTetFacetVertex[f];
          surface.push_back({v[static_cast<std::size_t>(fv[2])], v[static_cast<std::size_t>(fv[1])],
                             v[static_cast<std::size_t>(fv[0])]});
        }
        for (std::uint32_t j = 0; j < n && !surface.empty(); ++j) {
          if (j == i) continue;
          const double* pj = &sites[3 * j];
          // |x - pi|^2 <= |x - pj|^2  <=>  2 x.(pj - pi) + |pi|^2 - |pj|^2 <= 0
          const double nrm[3] = {2 * (pj[0] - pi[0]), 2 * (pj[1] - pi[1]), 2 * (pj[2] - pi[2])};
          const double off = pi[0] * pi[0] + pi[1] * pi[1] + pi[2] * pi[2] - pj[0] * pj[0] -
                             pj[1] * pj[1] - pj[2] * pj[2];
          surface = clip_surface(surface, nrm, off);
        }
        volume += volume_of(surface);
      }
      REQUIRE(std::fabs(volume - cv.volume(i)) <= 1e-11 * d.volume());
    }
  }
}

TEST_CASE("clip3d: the paper's robustness cases", "[clip][degenerate]") {
  // Fig. 10: the sites are the vertices of the sphere's boundary; no inner site.
  const Domain3 sphere(voroclip::read_tet_mesh(kData + "/tetmeshes/sphere.mesh"));
  std::vector<double> sites;
  std::vector<std::uint8_t> on_boundary(sphere.nb_vertices(), 0);
  for (std::uint32_t b = 0; b < sphere.nb_boundary_triangles(); ++b) {
    for (int k = 0; k < 3; ++k) on_boundary[sphere.boundary_vertex(b, k)] = 1;
  }
  for (std::uint32_t v = 0; v < sphere.nb_vertices(); ++v) {
    if (on_boundary[v]) sites.insert(sites.end(), sphere.vertex(v), sphere.vertex(v) + 3);
  }
  const auto n = static_cast<std::uint32_t>(sites.size() / 3);
  REQUIRE(n == 642);
  const Delaunay3 dt(sites.data(), n);
  const ClippedVoronoi3 cv = clip(sphere, dt);
  check_diagram(sphere, dt, cv, 20000, 10);
  REQUIRE(cv.nb_boundary_sites() == n);

  // Fig. 11: the 8 corners of a cube meshed by 2 x 2 x 2 Kuhn cubes: every bisector runs
  // through mesh edges and facets; each cell is an eighth of the cube, exactly.
  const Domain3 cube(cube_mesh(2));
  std::vector<double> corners;
  for (int c = 0; c < 8; ++c)
    corners.insert(corners.end(), {2.0 * (c & 1), 2.0 * ((c >> 1) & 1), 2.0 * (c >> 2)});
  const Delaunay3 dtc(corners.data(), 8);
  const ClippedVoronoi3 cvc = clip(cube, dtc);
  check_diagram(cube, dtc, cvc, 20000, 11);
  for (std::uint32_t i = 0; i < 8; ++i) {
    REQUIRE(std::fabs(cvc.volume(i) - 1.0) < 1e-14);
    REQUIRE(cvc.is_boundary(i));
    REQUIRE(std::fabs(cvc.surface_area(i) - 3.0) < 1e-13);
  }
}

TEST_CASE("clip3d: integer grid sites in a grid mesh, duplicates, sites outside",
          "[clip][degenerate]") {
  const Domain3 cube(cube_mesh(4));
  std::vector<double> grid;
  for (int z = -1; z <= 5; ++z) {
    for (int y = -1; y <= 5; ++y) {
      for (int x = -1; x <= 5; ++x) grid.insert(grid.end(), {double(x), double(y), double(z)});
    }
  }
  grid.insert(grid.end(), grid.begin(), grid.begin() + 30);  // ten duplicates
  const Delaunay3 dt(grid.data(), static_cast<std::uint32_t>(grid.size() / 3));
  const ClippedVoronoi3 cv = clip(cube, dt);
  check_diagram(cube, dt, cv, 20000, 12);
  // Half-integer grid: bisectors along the mesh's facets.
  std::vector<double> half;
  for (int z = -1; z <= 4; ++z) {
    for (int y = -1; y <= 4; ++y) {
      for (int x = -1; x <= 4; ++x) half.insert(half.end(), {x + 0.5, y + 0.5, z + 0.5});
    }
  }
  const Delaunay3 dth(half.data(), static_cast<std::uint32_t>(half.size() / 3));
  const ClippedVoronoi3 cvh = clip(cube, dth);
  check_diagram(cube, dth, cvh, 20000, 13);
  for (std::uint32_t i = 0; i < cvh.nb_sites(); ++i) {
    const double* p = &half[3 * i];
    const bool inside = p[0] > 0 && p[0] < 4 && p[1] > 0 && p[1] < 4 && p[2] > 0 && p[2] < 4;
    REQUIRE(std::fabs(cvh.volume(i) - (inside ? 1.0 : 0.0)) < 1e-13);
  }
}

TEST_CASE("clip3d: identical results with 1 and 2 threads", "[clip]") {
  const Domain3 d(voroclip::read_tet_mesh(kData + "/tetmeshes/bunny.mesh"));
  const std::vector<double> sites = sample_volume(d, 5000, 3);
  const Delaunay3 dt(sites.data(), 5000);
  ClippedVoronoi3 one, two;
  voroclip::Clip3Options o;
  o.keep_geometry = true;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one.compute(d, dt, o);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two.compute(d, dt, o);
  }
  for (std::uint32_t i = 0; i < one.nb_sites(); ++i) {
    REQUIRE(one.volume(i) == two.volume(i));
    REQUIRE(one.energy(i) == two.energy(i));
    REQUIRE(one.surface_area(i) == two.surface_area(i));
    for (int c = 0; c < 3; ++c) REQUIRE(one.centroid(i)[c] == two.centroid(i)[c]);
  }
  REQUIRE(one.cell_faces().xyz == two.cell_faces().xyz);
  REQUIRE(one.surface_polygons().xyz == two.surface_polygons().xyz);
}

TEST_CASE("clip3d: density linear per tet", "[clip]") {
  const Domain3 d(voroclip::read_tet_mesh(kData + "/tetmeshes/bunny.mesh"));
  const std::vector<double> sites = sample_volume(d, 3000, 8);
  const Delaunay3 dt(sites.data(), 3000);
  const ClippedVoronoi3 constant = clip(d, dt, false);
  // rho = 1 at every vertex: every cell clipped tet by tet, the same cells as the
  // unclipped inner cells of the constant path.
  voroclip::Clip3Options ones;
  ones.vertex_density.assign(d.nb_vertices(), 1.0);
  ClippedVoronoi3 cv1;
  cv1.compute(d, dt, ones);
  for (std::uint32_t i = 0; i < 3000; ++i) {
    INFO("site " << i);
    REQUIRE(std::fabs(cv1.volume(i) - constant.volume(i)) <= 1e-12 * d.volume());
    REQUIRE(std::fabs(cv1.mass(i) - constant.mass(i)) <= 1e-12 * d.volume());
    REQUIRE(std::fabs(cv1.energy(i) - constant.energy(i)) <= 1e-12 * constant.total_energy());
    for (int c = 0; c < 3; ++c) {
      REQUIRE(std::fabs(cv1.centroid(i)[c] - constant.centroid(i)[c]) <= 1e-9);
    }
  }
  // rho linear, from 1 to 7 across the bounding box: the total mass is ∫rho over the tets.
  const double* lo = d.bbox_lo();
  const double* hi = d.bbox_hi();
  const auto rho = [&](const double* p) {
    return 1 + (p[0] - lo[0]) / (hi[0] - lo[0]) + 2 * (p[1] - lo[1]) / (hi[1] - lo[1]) +
           3 * (p[2] - lo[2]) / (hi[2] - lo[2]);
  };
  voroclip::Clip3Options lin;
  double mass = 0;
  for (std::uint32_t v = 0; v < d.nb_vertices(); ++v)
    lin.vertex_density.push_back(rho(d.vertex(v)));
  for (std::uint32_t t = 0; t < d.nb_tets(); ++t) {
    const double* a = d.vertex(d.tet_vertex(t, 0));
    double u[3][3], c[3] = {a[0], a[1], a[2]};
    for (int k = 0; k < 3; ++k) {
      const double* b = d.vertex(d.tet_vertex(t, k + 1));
      for (int q = 0; q < 3; ++q) {
        u[k][q] = b[q] - a[q];
        c[q] += b[q];
      }
    }
    for (double& x : c) x /= 4;
    const double vol = std::fabs(u[0][0] * (u[1][1] * u[2][2] - u[1][2] * u[2][1]) -
                                 u[0][1] * (u[1][0] * u[2][2] - u[1][2] * u[2][0]) +
                                 u[0][2] * (u[1][0] * u[2][1] - u[1][1] * u[2][0])) /
                       6;
    mass += vol * rho(c);
  }
  REQUIRE(mass > 0);
  ClippedVoronoi3 cvl;
  cvl.compute(d, dt, lin);
  REQUIRE(std::fabs(cvl.total_mass() - mass) <= 1e-12 * mass);
  REQUIRE(std::fabs(cvl.total_volume() - d.volume()) <= 1e-12 * d.volume());
  // One-cell check: a cell's mass is the integral of rho over it (rho linear: volume times
  // rho at the volume centroid), with the volume centroid from the constant path.
  for (std::uint32_t i = 0; i < 3000; i += 97) {
    REQUIRE(std::fabs(cvl.mass(i) - constant.volume(i) * rho(constant.centroid(i))) <=
            1e-11 * mass);
  }
}
