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
#include <map>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "support/surfaces.h"
#include "support/threads.h"
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

// A box of nx x ny x nz cells of size (hx, hy, hz) from `lo`, each cut into 6 Kuhn tets.
voroclip::TetMeshInput box_mesh(std::uint32_t nx, std::uint32_t ny, std::uint32_t nz,
                                const double h[3], const double lo[3]) {
  voroclip::TetMeshInput m;
  m.source = "box";
  const auto id = [&](std::uint32_t x, std::uint32_t y, std::uint32_t z) {
    return (z * (ny + 1) + y) * (nx + 1) + x;
  };
  for (std::uint32_t z = 0; z <= nz; ++z) {
    for (std::uint32_t y = 0; y <= ny; ++y) {
      for (std::uint32_t x = 0; x <= nx; ++x)
        m.xyz.insert(m.xyz.end(), {lo[0] + x * h[0], lo[1] + y * h[1], lo[2] + z * h[2]});
    }
  }
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (std::uint32_t z = 0; z < nz; ++z) {
    for (std::uint32_t y = 0; y < ny; ++y) {
      for (std::uint32_t x = 0; x < nx; ++x) {
        for (const auto& p : perms) {
          std::uint32_t c[3] = {x, y, z};
          std::uint32_t tet[4];
          tet[0] = id(c[0], c[1], c[2]);
          for (int k = 0; k < 3; ++k) {
            ++c[p[k]];
            tet[k + 1] = id(c[0], c[1], c[2]);
          }
          m.tets.insert(m.tets.end(), tet, tet + 4);
          m.tet_line.push_back(0);
        }
      }
    }
  }
  return m;
}

// Two meshes as one input (vertices and tets of b after a's).
voroclip::TetMeshInput merged(voroclip::TetMeshInput a, const voroclip::TetMeshInput& b) {
  const auto base = static_cast<std::uint32_t>(a.xyz.size() / 3);
  a.xyz.insert(a.xyz.end(), b.xyz.begin(), b.xyz.end());
  for (const std::uint32_t v : b.tets) a.tets.push_back(v + base);
  a.tet_line.insert(a.tet_line.end(), b.tet_line.begin(), b.tet_line.end());
  return a;
}

// Uniform random points in the volume: a tet by volume, then uniform in it; for a domain
// without tets, points of the bounding box kept when inside (exact location).
std::vector<double> sample_volume(const Domain3& d, std::uint32_t n, std::uint64_t seed,
                                  std::vector<std::uint32_t>* tet_of = nullptr) {
  if (!d.has_tets()) {
    std::mt19937_64 rng(seed);
    std::vector<double> xyz;
    while (xyz.size() < 3 * std::size_t{n}) {
      double p[3];
      for (int c = 0; c < 3; ++c) {
        p[c] = std::uniform_real_distribution<double>(d.bbox_lo()[c], d.bbox_hi()[c])(rng);
      }
      if (d.locate(p) == voroclip::Sign::positive) xyz.insert(xyz.end(), p, p + 3);
    }
    return xyz;
  }
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

// The same cells to the last bit: volume, energy, surface area, centroid.
void require_same_cells(const ClippedVoronoi3& a, const ClippedVoronoi3& b) {
  REQUIRE(a.nb_sites() == b.nb_sites());
  for (std::uint32_t i = 0; i < a.nb_sites(); ++i) {
    INFO("site " << i);
    REQUIRE(a.volume(i) == b.volume(i));
    REQUIRE(a.energy(i) == b.energy(i));
    REQUIRE(a.surface_area(i) == b.surface_area(i));
    for (int c = 0; c < 3; ++c) REQUIRE(a.centroid(i)[c] == b.centroid(i)[c]);
  }
}

// The cells' faces (keep_geometry): every cell with a volume has faces, an inner cell
// one piece; the faces other than kInterior ones close each cell: the signed volume they
// bound (inward faces, fans from the site) is the cell's volume, the faces on the surface
// have the cell's restricted surface area; a face on a bisector has
// its points equidistant from the two sites (up to the rounding of the constructed
// points) and the site across is a Delaunay neighbour.
// The same for cell_boundaries() (joined: no kInterior faces, no pieces).
void check_cell_faces(const Domain3& d, const Delaunay3& dt, const ClippedVoronoi3& cv,
                      const ClippedVoronoi3::Polygons& f, bool joined) {
  const std::uint32_t n = cv.nb_sites();
  REQUIRE(f.across.size() == f.site.size());
  REQUIRE(f.piece.size() == (joined ? 0 : f.site.size()));
  const double scale = std::cbrt(d.volume() / n);  // an average cell's size
  std::vector<double> bounded(n, 0), surface(n, 0);
  std::vector<std::uint32_t> pieces(n, 0), nb_faces(n, 0);
  std::vector<std::uint32_t> nbrs;
  for (std::size_t k = 0; k < f.site.size(); ++k) {
    const std::uint32_t i = f.site[k];
    if (!joined && (k == 0 || f.piece[k] != f.piece[k - 1])) ++pieces[i];
    ++nb_faces[i];
    const std::uint32_t b = f.polygon_begin[k], e = f.polygon_begin[k + 1];
    REQUIRE(e - b >= 3);
    if (joined) REQUIRE(f.across[k] != ClippedVoronoi3::kInterior);
    if (f.across[k] == ClippedVoronoi3::kInterior) continue;
    const double* pi = dt.point(i);
    const auto rel = [&](std::uint32_t v, double* y) {
      for (int c = 0; c < 3; ++c) y[c] = f.xyz[3 * std::size_t{v} + c] - pi[c];
    };
    double a[3], u[3], w[3];
    rel(b, a);
    for (std::uint32_t v = b + 1; v + 1 < e; ++v) {
      rel(v, u);
      rel(v + 1, w);
      bounded[i] -= (a[0] * (u[1] * w[2] - u[2] * w[1]) - a[1] * (u[0] * w[2] - u[2] * w[0]) +
                     a[2] * (u[0] * w[1] - u[1] * w[0])) /
                    6;
    }
    if (f.across[k] == ClippedVoronoi3::kSurface) {
      double nrm[3] = {0, 0, 0};  // twice the area vector
      for (std::uint32_t v = b + 1; v + 1 < e; ++v) {
        rel(v, u);
        rel(v + 1, w);
        const double p[3] = {u[0] - a[0], u[1] - a[1], u[2] - a[2]};
        const double q[3] = {w[0] - a[0], w[1] - a[1], w[2] - a[2]};
        nrm[0] += p[1] * q[2] - p[2] * q[1];
        nrm[1] += p[2] * q[0] - p[0] * q[2];
        nrm[2] += p[0] * q[1] - p[1] * q[0];
      }
      surface[i] += 0.5 * std::sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
      continue;
    }
    const std::uint32_t j = f.across[k];
    INFO("cell " << i << ", face " << k << " on bisector(" << i << ", " << j << ")");
    dt.vertex_neighbors(i, nbrs);
    REQUIRE(std::binary_search(nbrs.begin(), nbrs.end(), j));
    const double* pj = dt.point(j);
    for (std::uint32_t v = b; v < e; ++v) {
      const double* x = &f.xyz[3 * std::size_t{v}];
      double di = 0, dj = 0;
      for (int c = 0; c < 3; ++c) {
        di += (x[c] - pi[c]) * (x[c] - pi[c]);
        dj += (x[c] - pj[c]) * (x[c] - pj[c]);
      }
      REQUIRE(std::fabs(di - dj) <= 1e-7 * (di + dj + scale * scale));
    }
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    INFO("cell " << i << (cv.is_boundary(i) ? " (boundary)" : " (inner)") << ", volume "
                 << cv.volume(i) << ", bounded by its faces " << bounded[i]);
    // (A cell of rounding-error volume may have only faces of zero area.)
    if (cv.volume(i) > 1e-12 * scale * scale * scale) REQUIRE(nb_faces[i] >= 4);
    if (!joined && !cv.is_boundary(i) && cv.volume(i) > 0) REQUIRE(pieces[i] == 1);
    REQUIRE(std::fabs(bounded[i] - cv.volume(i)) <= 1e-10 * scale * scale * scale);
    // The faces on the surface: the restricted surface's area (pieces of faces on
    // interior tet facets would add theirs).
    REQUIRE(std::fabs(surface[i] - cv.surface_area(i)) <= 1e-10 * scale * scale);
  }
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
  // Every probe (a random point of the volume) lies inside the faces of the cell of its
  // nearest site: their winding number about it is 1 (faces inward: -1 by the right-hand
  // rule). A cell's faces close it, whatever its pieces (their kInterior faces cancel in
  // pairs).
  const ClippedVoronoi3::Polygons& f = cv.cell_faces();
  check_cell_faces(d, dt, cv, f, false);
  check_cell_faces(d, dt, cv, cv.cell_boundaries(), true);
  std::vector<std::vector<std::uint32_t>> cell_faces(cv.nb_sites());
  for (std::size_t k = 0; k < f.site.size(); ++k) {
    cell_faces[f.site[k]].push_back(static_cast<std::uint32_t>(k));
  }
  const auto winding = [&](std::uint32_t cell, const double* x) {
    double total = 0;  // solid angles, Van Oosterom and Strackee's formula
    for (const std::uint32_t k : cell_faces[cell]) {
      const std::uint32_t b = f.polygon_begin[k], e = f.polygon_begin[k + 1];
      const auto rel = [&](std::uint32_t v, double* y) {
        for (int c = 0; c < 3; ++c) y[c] = f.xyz[3 * std::size_t{v} + c] - x[c];
        return std::sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
      };
      double a[3], u[3], w[3];
      const double la = rel(b, a);
      for (std::uint32_t v = b + 1; v + 1 < e; ++v) {
        const double lu = rel(v, u), lw = rel(v + 1, w);
        const double det = a[0] * (u[1] * w[2] - u[2] * w[1]) - a[1] * (u[0] * w[2] - u[2] * w[0]) +
                           a[2] * (u[0] * w[1] - u[1] * w[0]);
        const double den = la * lu * lw + (a[0] * u[0] + a[1] * u[1] + a[2] * u[2]) * lw +
                           (a[0] * w[0] + a[1] * w[1] + a[2] * w[2]) * lu +
                           (u[0] * w[0] + u[1] * w[1] + u[2] * w[2]) * la;
        total += 2 * std::atan2(det, den);
      }
    }
    return -total / (4 * 3.14159265358979323846);
  };
  const std::vector<double> probes = sample_volume(d, nb_probes, seed + 1000);
  for (std::uint32_t q = 0; q < nb_probes; ++q) {
    const double* x = &probes[3 * std::size_t{q}];
    const std::uint32_t s = dt.nearest_vertex(x);
    INFO("probe " << q << " nearest site " << s);
    REQUIRE(cv.volume(s) > 0);
    REQUIRE(std::fabs(winding(s, x) - 1) < 1e-6);
  }
}

// The default path (cones over the boundary of cell ∩ volume) against the tet-by-tet
// clipping of every boundary cell (tet_clipping), cell by cell: the restricted surface is
// the same computation (bit for bit); volume, first moment and energy agree to `rel` (1e-12)
// of the cell's scale (its own value, or that of an average cell: V = volume / sites,
// h = V^(1/3)). Both paths round the same constructed points (Voronoi vertices, crossings)
// but triangulate cell ∩ volume differently, so they differ by the points' rounding times
// their conditioning. Returns the number of cells the default path clipped tet by tet.
// `fast_domain`, when given, is the same volume without its tets (its surface alone).
std::uint32_t check_against_tet_clipping(const Domain3& d, const Delaunay3& dt,
                                         const std::string& what, double rel = 1e-12,
                                         const Domain3* fast_domain = nullptr) {
  INFO(what << ": " << dt.nb_points() << " sites in " << d.source());
  ClippedVoronoi3 fast, ref;
  voroclip::Clip3Options o;
  fast.compute(fast_domain ? *fast_domain : d, dt, o);
  o.tet_clipping = true;
  ref.compute(d, dt, o);
  REQUIRE(fast.nb_boundary_sites() == ref.nb_boundary_sites());
  REQUIRE(ref.nb_clipped_pairs() > 0);
  const double vunit = d.volume() / dt.nb_unique_points();
  const double hunit = std::cbrt(vunit);
  std::uint32_t compared = 0;
  for (std::uint32_t i = 0; i < fast.nb_sites(); ++i) {
    INFO("site " << i << " boundary " << ref.is_boundary(i));
    REQUIRE(fast.is_boundary(i) == ref.is_boundary(i));
    if (fast_domain) {
      // Another triangulation of the surface, or its triangles from another first corner:
      // the same areas, to rounding.
      const double aunit = hunit * hunit;
      REQUIRE(std::fabs(fast.surface_area(i) - ref.surface_area(i)) <=
              1e-12 * (ref.surface_area(i) + aunit));
    } else {
      REQUIRE(fast.surface_area(i) == ref.surface_area(i));
    }
    const double v = ref.volume(i);
    REQUIRE(std::fabs(fast.volume(i) - v) <= rel * (v + vunit));
    const double* x = dt.point(i);
    double reach = hunit;  // |centroid - site| + h
    for (int c = 0; c < 3; ++c) reach += std::fabs(ref.centroid(i)[c] - x[c]);
    for (int c = 0; c < 3; ++c) {
      const double mf = fast.volume(i) * (fast.centroid(i)[c] - x[c]);
      const double mr = v * (ref.centroid(i)[c] - x[c]);
      REQUIRE(std::fabs(mf - mr) <= rel * (v + vunit) * reach);
    }
    INFO("energy " << fast.energy(i) << " vs " << ref.energy(i) << ", volume " << v << ", reach "
                   << reach);
    REQUIRE(std::fabs(fast.energy(i) - ref.energy(i)) <=
            rel * (ref.energy(i) + vunit * reach * reach));
    compared += v > 0 ? 1 : 0;
  }
  REQUIRE(compared > 0);
  REQUIRE(std::fabs(fast.total_volume() - d.volume()) <= 1e-12 * d.volume());
  REQUIRE(std::fabs(ref.total_volume() - d.volume()) <= 1e-12 * d.volume());
  return fast.nb_multi_crossing_cells();
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
  const ClippedVoronoi3 cv = clip(d, dt);
  check_diagram(d, dt, cv, static_cast<std::uint32_t>(100000 * test_scale()), 5);
  // The volume is convex: each face of a cell on a bisector is convex, one loop, in
  // cell_faces() already (boundary cells' faces are built from the surface, whole).
  const ClippedVoronoi3::Polygons joined = cv.cell_boundaries();
  for (const ClippedVoronoi3::Polygons* f : {&cv.cell_faces(), &joined}) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> count;
    std::size_t on_bisectors = 0;
    for (std::size_t k = 0; k < f->site.size(); ++k) {
      REQUIRE(f->across[k] != ClippedVoronoi3::kInterior);
      if (f->across[k] == ClippedVoronoi3::kSurface) continue;
      on_bisectors += cv.is_boundary(f->site[k]) ? 1 : 0;
      INFO("cell " << f->site[k] << ", face on bisector(" << f->site[k] << ", " << f->across[k]
                   << ")");
      REQUIRE(++count[{f->site[k], f->across[k]}] == 1);
    }
    REQUIRE(on_bisectors > 0);
  }
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
  for (std::uint32_t b = 0; b < sphere.surface().nb_triangles(); ++b) {
    for (int k = 0; k < 3; ++k) on_boundary[sphere.surface().triangle_vertex(b, k)] = 1;
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

TEST_CASE("clip3d: sites on the domain's faces to the last bits: Delaunay slivers",
          "[clip][degenerate]") {
  // A CVT snaps sites onto the boundary: on a cube's faces they are coplanar up to
  // rounding, and the Delaunay tets between four such sites are slivers whose floating-
  // point determinant is zero or noise. (The unit cube meshed with 5000 vertices had
  // them, and their Voronoi vertices came out NaN.) Here: a grid on each face of the
  // cube, each site moved off its face by up to 3 ulps, and random inner sites.
  const Domain3 cube(cube_mesh(4));
  std::mt19937_64 rng(29);
  std::uniform_int_distribution<int> ulps(-3, 3);
  std::uniform_real_distribution<double> u(0.1, 3.9);
  const auto moved = [&](double x) {
    for (int k = ulps(rng); k != 0; k += k > 0 ? -1 : 1) {
      x = std::nextafter(x, k > 0 ? 10.0 : -10.0);
    }
    return x;
  };
  std::vector<double> sites;
  for (int axis = 0; axis < 3; ++axis) {
    for (const double side : {0.0, 4.0}) {
      for (int a = 0; a < 8; ++a) {
        for (int b = 0; b < 8; ++b) {
          double p[3];
          p[axis] = moved(side);
          p[(axis + 1) % 3] = 0.25 + 0.5 * a;
          p[(axis + 2) % 3] = 0.25 + 0.5 * b;
          sites.insert(sites.end(), {p[0], p[1], p[2]});
        }
      }
    }
  }
  for (int k = 0; k < 300; ++k) sites.insert(sites.end(), {u(rng), u(rng), u(rng)});
  const auto n = static_cast<std::uint32_t>(sites.size() / 3);
  for (const bool surface_only : {false, true}) {
    INFO((surface_only ? "from the surface" : "from the tets"));
    const Domain3 d = surface_only ? Domain3(cube.surface()) : cube;
    const Delaunay3 dt(sites.data(), n);
    const ClippedVoronoi3 cv = clip(d, dt);
    for (std::uint32_t i = 0; i < n; ++i) {
      INFO("site " << i);
      REQUIRE(std::isfinite(cv.volume(i)));
      REQUIRE(std::isfinite(cv.centroid(i)[0]));
      REQUIRE(std::isfinite(cv.centroid(i)[1]));
      REQUIRE(std::isfinite(cv.centroid(i)[2]));
    }
    check_diagram(d, dt, cv, 20000, 14);
  }
}

TEST_CASE("clip3d: identical results with 1 and 2 threads", "[clip][threads]") {
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
    tbb::global_control c(tbb::global_control::max_allowed_parallelism,
                          voroclip_test::test_threads());
    two.compute(d, dt, o);
  }
  require_same_cells(one, two);
  REQUIRE(one.cell_faces().xyz == two.cell_faces().xyz);
  REQUIRE(one.surface_polygons().xyz == two.surface_polygons().xyz);
  // The default path alone, with the restricted surface's symbolic vertices; sites outside
  // too (cells placed outside spread through their neighbours).
  std::vector<double> more = sites;
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  for (int k = 0; k < 3 * 300; ++k) more.push_back(u(rng) + d.bbox_lo()[k % 3] - 0.05);
  const Delaunay3 dt2(more.data(), static_cast<std::uint32_t>(more.size() / 3));
  voroclip::Clip3Options s;
  s.keep_surface = true;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one.compute(d, dt2, s);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism,
                          voroclip_test::test_threads());
    two.compute(d, dt2, s);
  }
  REQUIRE(std::fabs(one.total_volume() - d.volume()) <= 1e-12 * d.volume());
  require_same_cells(one, two);
  REQUIRE(one.surface_polygons().xyz == two.surface_polygons().xyz);
  REQUIRE(one.surface_polygons().vertices == two.surface_polygons().vertices);
  REQUIRE(one.surface_polygons().triangle == two.surface_polygons().triangle);
}

// The output cells are not zeroed before a compute writes them: a compute on an object
// that already holds a larger result must write every cell, and one that throws must leave
// no stale or unwritten cells behind.
TEST_CASE("clip3d: repeated computes on one object, and a failed one", "[clip]") {
  const Domain3 d(voroclip::read_tet_mesh(kData + "/tetmeshes/bunny.mesh"));
  const std::vector<double> many = sample_volume(d, 4000, 21);
  const std::vector<double> few = sample_volume(d, 1500, 22);
  const Delaunay3 dt_many(many.data(), 4000), dt_few(few.data(), 1500);
  const ClippedVoronoi3 fresh = clip(d, dt_few, false);
  ClippedVoronoi3 cv;
  cv.compute(d, dt_many);
  REQUIRE(cv.nb_sites() == 4000);
  voroclip::Clip3Options bad;
  bad.density.value = -1;
  CHECK_THROWS_AS(cv.compute(d, dt_many, bad), voroclip::Error);
  CHECK(cv.nb_sites() == 0);
  cv.compute(d, dt_many);
  cv.compute(d, dt_few);  // smaller than the result it replaces
  REQUIRE(cv.nb_sites() == 1500);
  for (std::uint32_t i = 0; i < 1500; ++i) {
    INFO("site " << i);
    REQUIRE(cv.volume(i) == fresh.volume(i));
    REQUIRE(cv.mass(i) == fresh.mass(i));
    REQUIRE(cv.energy(i) == fresh.energy(i));
    REQUIRE(cv.surface_area(i) == fresh.surface_area(i));
    REQUIRE(cv.is_boundary(i) == fresh.is_boundary(i));
    for (int c = 0; c < 3; ++c) REQUIRE(cv.centroid(i)[c] == fresh.centroid(i)[c]);
  }
  CHECK(cv.total_volume() == fresh.total_volume());
}

// compute(domain, sites, n) triangulates the sites along a Hilbert curve and reports in
// input order. Against the order's definition (hilbert_sort of the input order),
// against compute(domain, dt) on the sorted copy triangulated as compute() does, presorted
// (bit for bit, after mapping the indices: the same triangulation and the same
// arithmetic), and against compute(domain, dt) on the input order (the same cells up to
// rounding: the perturbation only decides measure zero).
TEST_CASE("clip3d: compute from the sites, in spatial order, reported in input order",
          "[clip][threads]") {
  const Domain3 d(voroclip::read_tet_mesh(kData + "/tetmeshes/bunny.mesh"));
  std::vector<double> sites = sample_volume(d, 3000, 51);
  sites.insert(sites.end(), sites.begin() + 300, sites.begin() + 360);  // 20 duplicates
  std::mt19937_64 rng(52);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  for (int k = 0; k < 3 * 40; ++k) sites.push_back(u(rng) + d.bbox_lo()[k % 3] - 0.05);
  const auto n = static_cast<std::uint32_t>(sites.size() / 3);
  voroclip::Clip3Options o;
  o.keep_surface = true;
  ClippedVoronoi3 cv;
  cv.compute(d, sites.data(), n, o);
  REQUIRE(cv.nb_sites() == n);
  REQUIRE(std::fabs(cv.total_volume() - d.volume()) <= 1e-12 * d.volume());

  // The order: the Hilbert sort of the input order, which keeps duplicates in input order.
  const std::vector<std::uint32_t>& order = cv.site_order();
  std::vector<std::uint32_t> expected(n);
  std::iota(expected.begin(), expected.end(), 0u);
  voroclip::hilbert_sort(sites.data(), 3, expected.data(), expected.data() + n);
  REQUIRE(order == expected);
  std::vector<std::uint32_t> rank(n, n);
  for (std::uint32_t k = 0; k < n; ++k) {
    REQUIRE(order[k] < n);
    REQUIRE(rank[order[k]] == n);
    rank[order[k]] = k;
  }
  for (std::uint32_t i = 100; i < 120; ++i) REQUIRE(rank[i] < rank[i + 2900]);
  REQUIRE(cv.delaunay().nb_points() == n);
  REQUIRE(cv.delaunay().nb_unique_points() == n - 20);

  // The same computation on the sorted copy, by hand.
  std::vector<double> sorted(sites.size());
  for (std::uint32_t k = 0; k < n; ++k) {
    for (int c = 0; c < 3; ++c) sorted[3 * k + c] = sites[3 * order[k] + c];
  }
  voroclip::Delaunay3Options presorted;
  presorted.presorted = true;
  const Delaunay3 dts(sorted.data(), n, presorted);
  ClippedVoronoi3 ref;
  ref.compute(d, dts, o);
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t k = rank[i];
    INFO("site " << i << ", rank " << k);
    REQUIRE(cv.volume(i) == ref.volume(k));
    REQUIRE(cv.energy(i) == ref.energy(k));
    REQUIRE(cv.surface_area(i) == ref.surface_area(k));
    REQUIRE(cv.is_boundary(i) == ref.is_boundary(k));
    for (int c = 0; c < 3; ++c) REQUIRE(cv.centroid(i)[c] == ref.centroid(k)[c]);
  }
  // Totals: sums over the cells in input order.
  double volume = 0, energy = 0, area = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    volume += cv.volume(i);
    energy += cv.energy(i);
    area += cv.surface_area(i);
  }
  REQUIRE(cv.total_volume() == volume);
  REQUIRE(cv.total_energy() == energy);
  REQUIRE(cv.total_surface_area() == area);
  // Restricted surface: cell i's polygons are rank[i]'s, with their sites mapped.
  const ClippedVoronoi3::Polygons& s = cv.surface_polygons();
  const ClippedVoronoi3::Polygons& r = ref.surface_polygons();
  REQUIRE(s.site_begin.size() == n + 1);
  REQUIRE(s.site.size() == r.site.size());
  REQUIRE(s.vertices.size() == r.vertices.size());
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t k = rank[i];
    REQUIRE(s.site_begin[i + 1] - s.site_begin[i] == r.site_begin[k + 1] - r.site_begin[k]);
    for (std::uint32_t a = s.site_begin[i], b = r.site_begin[k]; a < s.site_begin[i + 1];
         ++a, ++b) {
      REQUIRE(s.site[a] == i);
      REQUIRE(s.triangle[a] == r.triangle[b]);
      REQUIRE(s.polygon_begin[a + 1] - s.polygon_begin[a] ==
              r.polygon_begin[b + 1] - r.polygon_begin[b]);
      for (std::uint32_t v = s.polygon_begin[a], w = r.polygon_begin[b]; v < s.polygon_begin[a + 1];
           ++v, ++w) {
        voroclip::ClipVertex3 x = r.vertices[w];
        for (std::uint32_t& e : x.site) {
          if (e != voroclip::ClipVertex3::kNone) e = order[e];
        }
        std::sort(std::begin(x.site), std::end(x.site));  // kNone sorts last
        REQUIRE(s.vertices[v] == x);
        for (int c = 0; c < 3; ++c) REQUIRE(s.xyz[3 * v + c] == r.xyz[3 * w + c]);
      }
    }
  }
  // Cell faces (keep_geometry; inner cells included): the same faces, sites mapped.
  voroclip::Clip3Options g;
  g.keep_geometry = true;
  ClippedVoronoi3 cvg, refg;
  cvg.compute(d, sites.data(), n, g);
  refg.compute(d, dts, g);
  REQUIRE(cvg.cell_faces().xyz == refg.cell_faces().xyz);
  REQUIRE(cvg.cell_faces().piece == refg.cell_faces().piece);
  REQUIRE(cvg.cell_faces().site.size() == refg.cell_faces().site.size());
  for (std::size_t f = 0; f < refg.cell_faces().site.size(); ++f) {
    REQUIRE(cvg.cell_faces().site[f] == order[refg.cell_faces().site[f]]);
    const std::uint32_t across = refg.cell_faces().across[f];
    REQUIRE(cvg.cell_faces().across[f] ==
            (across >= ClippedVoronoi3::kInterior ? across : order[across]));
  }

  // The input order's triangulation: the same cells up to rounding; duplicates empty, the
  // first in input order holding the cell.
  const Delaunay3 dti(sites.data(), n);
  const ClippedVoronoi3 in = clip(d, dti, false);
  const double vunit = d.volume() / (n - 20);
  for (std::uint32_t i = 0; i < n; ++i) {
    INFO("site " << i);
    REQUIRE(cv.is_boundary(i) == in.is_boundary(i));
    REQUIRE(std::fabs(cv.volume(i) - in.volume(i)) <= 1e-12 * vunit);
    if (i >= 3000 && i < 3020) REQUIRE(cv.volume(i) == 0);
  }
  for (std::uint32_t i = 100; i < 120; ++i) REQUIRE(cv.volume(i) > 0);

  // 1 and 2 threads (2: boundary cells whose star the other thread listed traverse it
  // again), and errors.
  ClippedVoronoi3 one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one.compute(d, sites.data(), n, o);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism,
                          voroclip_test::test_threads());
    two.compute(d, sites.data(), n, o);
  }
  require_same_cells(one, two);
  require_same_cells(one, cv);
  REQUIRE(one.surface_polygons().xyz == two.surface_polygons().xyz);
  REQUIRE(one.surface_polygons().vertices == two.surface_polygons().vertices);
  std::vector<double> bad = sites;
  bad[3 * 17 + 1] = NAN;
  CHECK_THROWS_WITH(one.compute(d, bad.data(), n),
                    Catch::Contains("site 17 (from 0, in input order) has a non-finite"));
  CHECK(one.nb_sites() == 0);
  CHECK_THROWS_AS(one.compute(d, sites.data(), 0), voroclip::Error);
}

TEST_CASE("clip3d: density linear per tet", "[clip]") {
  const Domain3 d(voroclip::read_tet_mesh(kData + "/tetmeshes/bunny.mesh"));
  const std::vector<double> sites = sample_volume(d, 3000, 8);
  const Delaunay3 dt(sites.data(), 3000);
  const ClippedVoronoi3 constant = clip(d, dt, false);
  // The constant path takes its inner cells in chunks of 1024 (clip3d.cpp): two here.
  REQUIRE(constant.nb_sites() - constant.nb_boundary_sites() > 1024);
  // rho = 1 at every vertex: every cell clipped tet by tet, the same cells as the
  // unclipped inner cells of the constant path.
  voroclip::Clip3Options ones;
  ones.density = voroclip::Density3::vertex_linear(std::vector<double>(d.nb_vertices(), 1.0));
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
  std::vector<double> values;
  for (std::uint32_t v = 0; v < d.nb_vertices(); ++v) values.push_back(rho(d.vertex(v)));
  lin.density = voroclip::Density3::vertex_linear(values);
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

TEST_CASE("clip3d: cones over the boundary equal the tet-by-tet clipping, cell by cell",
          "[clip][exact]") {
  const Domain3 sphere(voroclip::read_tet_mesh(kData + "/tetmeshes/sphere.mesh"));
  // Random sites, some outside the ball.
  for (const std::uint64_t seed : {21u, 22u}) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1.2, 1.2);
    std::vector<double> sites = sample_volume(sphere, 400, seed);
    for (int k = 0; k < 3 * 60; ++k) sites.push_back(u(rng));
    const Delaunay3 dt(sites.data(), static_cast<std::uint32_t>(sites.size() / 3));
    check_against_tet_clipping(sphere, dt, "random, seed " + std::to_string(seed));
  }
  // Every mesh vertex a site (boundary and interior): bisectors through mesh vertices,
  // edges and facets everywhere.
  {
    const Delaunay3 dt(sphere.coords().data(), sphere.nb_vertices());
    check_against_tet_clipping(sphere, dt, "the mesh vertices");
  }
  // Sites on the boundary facets (centroids) and edges (midpoints), and inside. Three sites
  // on neighbouring facets have a Voronoi edge nearly along the surface, whose crossing is
  // ill-conditioned: 1e-11.
  {
    std::vector<double> sites = sample_volume(sphere, 300, 24);
    for (std::uint32_t b = 0; b < sphere.surface().nb_triangles(); b += 2) {
      // Corners in the tets' facet order (the surface lists them reversed).
      const double* p[3];
      for (int k = 0; k < 3; ++k) {
        p[k] = sphere.vertex(sphere.surface().triangle_vertex(b, k == 0 ? 0 : 3 - k));
      }
      for (int c = 0; c < 3; ++c) sites.push_back((p[0][c] + p[1][c] + p[2][c]) / 3);
      for (int c = 0; c < 3; ++c) sites.push_back((p[0][c] + p[1][c]) / 2);
    }
    const Delaunay3 dt(sites.data(), static_cast<std::uint32_t>(sites.size() / 3));
    check_against_tet_clipping(sphere, dt, "on facets and edges", 1e-11);
  }
  // The cube's corners (Fig. 11), integer grids with duplicates and sites outside, the
  // half-integer grid (bisectors along the mesh's facets).
  {
    const Domain3 cube(cube_mesh(2));
    std::vector<double> corners;
    for (int c = 0; c < 8; ++c)
      corners.insert(corners.end(), {2.0 * (c & 1), 2.0 * ((c >> 1) & 1), 2.0 * (c >> 2)});
    const Delaunay3 dt(corners.data(), 8);
    check_against_tet_clipping(cube, dt, "cube corners");
  }
  {
    const Domain3 cube(cube_mesh(3));
    std::vector<double> grid, half;
    for (int z = -1; z <= 4; ++z) {
      for (int y = -1; y <= 4; ++y) {
        for (int x = -1; x <= 4; ++x) {
          grid.insert(grid.end(), {double(x), double(y), double(z)});
          half.insert(half.end(), {x + 0.5, y + 0.5, z + 0.5});
        }
      }
    }
    grid.insert(grid.end(), grid.begin(), grid.begin() + 24);  // eight duplicates
    const Delaunay3 dtg(grid.data(), static_cast<std::uint32_t>(grid.size() / 3));
    check_against_tet_clipping(cube, dtg, "integer grid");
    const Delaunay3 dth(half.data(), static_cast<std::uint32_t>(half.size() / 3));
    check_against_tet_clipping(cube, dth, "half-integer grid");
  }
  // A real model with thin parts: some Voronoi edges cross the surface twice.
  {
    const Domain3 bunny(voroclip::read_tet_mesh(kData + "/tetmeshes/bunny.mesh"));
    const std::vector<double> sites = sample_volume(bunny, 2000, 23);
    const Delaunay3 dt(sites.data(), 2000);
    CHECK(check_against_tet_clipping(bunny, dt, "bunny") > 0);
  }
}

TEST_CASE("clip3d: Voronoi edges crossing a thin slab twice, as signed segments",
          "[clip][degenerate]") {
  // A slab 6 x 6 x 0.25; sites in its mid-plane, slightly off it, and a few above and below:
  // the Voronoi edges of the mid-plane sites run across the slab, through both faces.
  const double h[3] = {1, 1, 0.125}, lo[3] = {0, 0, 0};
  const Domain3 slab(box_mesh(6, 6, 2, h, lo));
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> u(0.2, 5.8), dz(-0.01, 0.01);
  std::vector<double> sites;
  for (int k = 0; k < 40; ++k) sites.insert(sites.end(), {u(rng), u(rng), 0.125 + dz(rng)});
  for (int k = 0; k < 6; ++k) sites.insert(sites.end(), {u(rng), u(rng), k % 2 ? 3.0 : -3.0});
  const Delaunay3 dt(sites.data(), static_cast<std::uint32_t>(sites.size() / 3));
  const std::uint32_t multi = check_against_tet_clipping(slab, dt, "slab");
  CHECK(multi >= 20);
  // The slab given by its 12 triangles alone: the same cells.
  const Domain3 box(voroclip_test::box_surface({0, 0, 0}, {6, 6, 0.25}));
  CHECK(check_against_tet_clipping(slab, dt, "slab surface", 1e-12, &box) >= 20);
}

TEST_CASE("clip3d: a surface component inside one cell (no Voronoi edge crosses it)",
          "[clip][degenerate]") {
  // Sites: the origin and the corners of [-10, 10]^3. The domain: the cube [-1, 1]^3, wholly
  // in the origin's cell and far from every Voronoi vertex, plus a box [4, 14] x [-3, 3]^2
  // that the cells of the corners (10, +-10, +-10) and the origin's share. The first
  // component gives its cell no crossing to place its Voronoi vertices from.
  const double h1[3] = {1, 1, 1}, lo1[3] = {-1, -1, -1};
  const double h2[3] = {2.5, 1.5, 1.5}, lo2[3] = {4, -3, -3};
  std::vector<double> sites = {0, 0, 0};
  for (int c = 0; c < 8; ++c) {
    sites.insert(sites.end(), {c & 1 ? 10.0 : -10.0, c & 2 ? 10.0 : -10.0, c & 4 ? 10.0 : -10.0});
  }
  const Delaunay3 dt(sites.data(), 9);
  const Domain3 inner(box_mesh(2, 2, 2, h1, lo1));
  ClippedVoronoi3 cv;
  cv.compute(inner, dt);
  REQUIRE(cv.is_boundary(0));
  REQUIRE(cv.nb_boundary_sites() == 1);
  REQUIRE(std::fabs(cv.volume(0) - 8) <= 1e-13);
  REQUIRE(std::fabs(cv.energy(0) - 8.0) <= 1e-13);  // ∫ |x|^2 over [-1, 1]^3 = 8
  for (int c = 0; c < 3; ++c) REQUIRE(std::fabs(cv.centroid(0)[c]) <= 1e-14);
  const Domain3 both(merged(box_mesh(2, 2, 2, h1, lo1), box_mesh(4, 4, 4, h2, lo2)));
  REQUIRE(std::fabs(both.volume() - 8 - 360) <= 1e-12);
  check_against_tet_clipping(both, dt, "two components");
  ClippedVoronoi3 cvb;
  cvb.compute(both, dt);
  // In the box, the origin's cell is x + |y| + |z| <= 15 (bisectors with the corners
  // (10, +-10, +-10)): 288 - 2/3 of it.
  REQUIRE(std::fabs(cvb.volume(0) - (8 + 288 - 2.0 / 3)) <= 1e-12);
}

TEST_CASE("clip3d: a boundary cell with nothing to place its Voronoi vertices from",
          "[clip][degenerate]") {
  // The domain: the cube [-0.1, 0.1]^3 around the site at the origin; 300 other sites in
  // [-1, 1]^3, none within 0.4 of the origin, so the cube lies in the origin's cell (its
  // points are within 0.18 of the origin and beyond 0.22 of every other site). The only
  // boundary cell has no infinite tet and no crossing around it: its chunk, and then the
  // cell alone, cannot place its Voronoi vertices, and the search from the infinite tets
  // does (global_flags).
  std::vector<double> sites = {0, 0, 0};
  std::mt19937_64 rng(91);
  std::uniform_real_distribution<double> u(-1, 1);
  while (sites.size() < 3 * 301) {
    const double p[3] = {u(rng), u(rng), u(rng)};
    if (p[0] * p[0] + p[1] * p[1] + p[2] * p[2] > 0.4 * 0.4) sites.insert(sites.end(), p, p + 3);
  }
  const Delaunay3 dt(sites.data(), 301);
  const double h[3] = {0.1, 0.1, 0.1}, lo[3] = {-0.1, -0.1, -0.1};
  const Domain3 cube(box_mesh(2, 2, 2, h, lo));
  ClippedVoronoi3 cv;
  cv.compute(cube, dt);
  REQUIRE(cv.nb_boundary_sites() == 1);
  REQUIRE(cv.is_boundary(0));
  REQUIRE(std::fabs(cv.volume(0) - 0.008) <= 1e-15);
  REQUIRE(std::fabs(cv.energy(0) - 8e-5) <= 1e-17);  // ∫ |x|^2 over [-0.1, 0.1]^3
  for (int c = 0; c < 3; ++c) REQUIRE(std::fabs(cv.centroid(0)[c]) <= 1e-15);
  for (std::uint32_t i = 1; i < 301; ++i) REQUIRE(cv.volume(i) == 0);
  check_against_tet_clipping(cube, dt, "a cube inside one cell");
}

TEST_CASE("clip3d: restricted surface polygons and their symbolic vertices", "[clip]") {
  const Domain3 d(voroclip::read_tet_mesh(kData + "/tetmeshes/bunny.mesh"));
  const std::vector<double> sites = sample_volume(d, 1500, 41);
  const Delaunay3 dt(sites.data(), 1500);
  voroclip::Clip3Options o;
  o.keep_surface = true;
  ClippedVoronoi3 cv;
  cv.compute(d, dt, o);
  const ClippedVoronoi3::Polygons& s = cv.surface_polygons();
  REQUIRE(s.site_begin.size() == 1501);
  REQUIRE(s.polygon_begin.size() == s.site.size() + 1);
  REQUIRE(s.vertices.size() * 3 == s.xyz.size());
  REQUIRE(cv.cell_faces().site.empty());
  // Boundary triangles: their area, and the polygons of each cover it.
  std::vector<double> tri_area(d.surface().nb_triangles(), 0), poly_area(tri_area.size(), 0);
  const auto area_of = [](const double* p, std::size_t m) {
    double a[3] = {0, 0, 0};
    for (std::size_t k = 1; k + 1 < m; ++k) {
      const double* u = p + 3 * k;
      const double* w = p + 3 * (k + 1);
      const double e[3] = {u[0] - p[0], u[1] - p[1], u[2] - p[2]};
      const double f[3] = {w[0] - p[0], w[1] - p[1], w[2] - p[2]};
      a[0] += e[1] * f[2] - e[2] * f[1];
      a[1] += e[2] * f[0] - e[0] * f[2];
      a[2] += e[0] * f[1] - e[1] * f[0];
    }
    return 0.5 * std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  };
  for (std::uint32_t b = 0; b < d.surface().nb_triangles(); ++b) {
    double p[9];
    for (int k = 0; k < 3; ++k) {
      for (int c = 0; c < 3; ++c) p[3 * k + c] = d.vertex(d.surface().triangle_vertex(b, k))[c];
    }
    tri_area[b] = area_of(p, 3);
  }
  double total = 0;
  for (std::uint32_t i = 0; i < 1500; ++i) {
    INFO("site " << i);
    REQUIRE((s.site_begin[i + 1] > s.site_begin[i]) == cv.is_boundary(i));
    double area = 0;
    for (std::uint32_t p = s.site_begin[i]; p < s.site_begin[i + 1]; ++p) {
      REQUIRE(s.site[p] == i);
      if (p > s.site_begin[i]) REQUIRE(s.triangle[p] > s.triangle[p - 1]);
      const std::uint32_t b = s.triangle[p];
      std::uint32_t tv[3];
      for (int k = 0; k < 3; ++k) tv[k] = d.surface().triangle_vertex(b, k);
      const std::uint32_t m = s.polygon_begin[p + 1] - s.polygon_begin[p];
      REQUIRE(m >= 3);
      const double a = area_of(&s.xyz[3 * std::size_t{s.polygon_begin[p]}], m);
      area += a;
      poly_area[b] += a;
      for (std::uint32_t v = s.polygon_begin[p]; v < s.polygon_begin[p + 1]; ++v) {
        const voroclip::ClipVertex3& x = s.vertices[v];
        const double* xyz = &s.xyz[3 * std::size_t{v}];
        int nm = 0, ns = 0;
        for (int k = 0; k < 3; ++k) {
          if (x.mesh[k] != voroclip::ClipVertex3::kNone) {
            ++nm;
            REQUIRE((x.mesh[k] == tv[0] || x.mesh[k] == tv[1] || x.mesh[k] == tv[2]));
            if (k > 0) REQUIRE(x.mesh[k] > x.mesh[k - 1]);
          }
          if (x.site[k] != voroclip::ClipVertex3::kNone) {
            ++ns;
            REQUIRE(cv.is_boundary(x.site[k]));
            if (k > 0) REQUIRE(x.site[k] > x.site[k - 1]);
          }
        }
        switch (x.kind) {
          case voroclip::ClipVertex3::Kind::kMeshVertex:
            REQUIRE((nm == 1 && ns == 0));
            for (int c = 0; c < 3; ++c) REQUIRE(xyz[c] == d.vertex(x.mesh[0])[c]);
            break;
          case voroclip::ClipVertex3::Kind::kEdgeBisector:
            REQUIRE((nm == 2 && ns == 2));
            break;
          case voroclip::ClipVertex3::Kind::kFacetBisectors:
            REQUIRE((nm == 3 && ns == 3));
            break;
        }
        if (ns > 0) REQUIRE((x.site[0] == i || x.site[1] == i || x.site[2] == i));
        // Equidistant from its sites, up to rounding.
        if (ns >= 2) {
          const auto d2 = [&](std::uint32_t k) {
            const double* q = dt.point(k);
            return (xyz[0] - q[0]) * (xyz[0] - q[0]) + (xyz[1] - q[1]) * (xyz[1] - q[1]) +
                   (xyz[2] - q[2]) * (xyz[2] - q[2]);
          };
          for (int k = 1; k < ns; ++k) {
            REQUIRE(std::fabs(d2(x.site[k]) - d2(x.site[0])) <= 1e-9 * (d2(x.site[0]) + 1e-3));
          }
        }
      }
    }
    REQUIRE(std::fabs(area - cv.surface_area(i)) <= 1e-12 * (area + 1e-12));
    total += area;
  }
  for (std::uint32_t b = 0; b < d.surface().nb_triangles(); ++b) {
    REQUIRE(std::fabs(poly_area[b] - tri_area[b]) <= 1e-10 * tri_area[b]);
  }
  REQUIRE(std::fabs(total - cv.total_surface_area()) <= 1e-12 * total);
  // A point on bisectors has the same coordinates, bit for bit, in every polygon that has
  // it: an edge point in the two cells' polygons of the two triangles on its edge (the
  // surface is closed), a point of a triangle on two bisectors in its three cells' polygons.
  std::map<std::array<std::uint32_t, 7>, std::pair<std::array<double, 3>, int>> seen;
  for (std::size_t v = 0; v < s.vertices.size(); ++v) {
    const voroclip::ClipVertex3& x = s.vertices[v];
    if (x.kind == voroclip::ClipVertex3::Kind::kMeshVertex) continue;
    const std::array<std::uint32_t, 7> key = {static_cast<std::uint32_t>(x.kind),
                                              x.mesh[0],
                                              x.mesh[1],
                                              x.mesh[2],
                                              x.site[0],
                                              x.site[1],
                                              x.site[2]};
    const std::array<double, 3> xyz = {s.xyz[3 * v], s.xyz[3 * v + 1], s.xyz[3 * v + 2]};
    auto it = seen.find(key);
    if (it == seen.end()) {
      seen.emplace(key, std::make_pair(xyz, 1));
    } else {
      REQUIRE(it->second.first == xyz);
      ++it->second.second;
    }
  }
  REQUIRE(!seen.empty());
  for (const auto& [key, value] : seen) {
    const bool edge =
        key[0] == static_cast<std::uint32_t>(voroclip::ClipVertex3::Kind::kEdgeBisector);
    REQUIRE(value.second == (edge ? 4 : 3));
  }
}

namespace {

// A tet mesh of shared/data/tetmeshes and its boundary written as OBJ and read back: the
// same volume given by its surface alone.
struct TwoDomains {
  Domain3 tets, surface;
};
TwoDomains tet_mesh_and_surface(const std::string& name, const voroclip_test::TempDir& dir) {
  const voroclip::TetMeshInput mesh =
      voroclip::read_tet_mesh(kData + "/tetmeshes/" + name + ".mesh");
  const std::string obj = dir.file(name + ".obj");
  voroclip::write_surface(obj, voroclip::tet_mesh_boundary(mesh), voroclip::SurfaceFormat::kObj);
  return {Domain3(mesh), Domain3(voroclip::read_surface(obj))};
}

}  // namespace

TEST_CASE("clip3d from a surface alone: every shared model against the tet-by-tet clipping",
          "[clip][data]") {
  const voroclip_test::TempDir dir("clip3d_surfaces");
  const char* models[] = {"sphere",  "sphere-fine", "bunny", "skull_low_resolution",
                          "elk",     "fandisk",     "homer", "rocker-arm",
                          "gargoyle"};
  for (const char* m : models) {
    const TwoDomains d = tet_mesh_and_surface(m, dir);
    REQUIRE(!d.surface.has_tets());
    REQUIRE(std::fabs(d.surface.volume() - d.tets.tet_volume()) <= 1e-12 * d.tets.tet_volume());
    for (const std::uint32_t n : {1000u, static_cast<std::uint32_t>(10000 * test_scale())}) {
      const std::vector<double> sites = sample_volume(d.tets, n, n + 7);
      const Delaunay3 dt(sites.data(), n);
      check_against_tet_clipping(d.tets, dt, m, 1e-12, &d.surface);
    }
  }
}

TEST_CASE("clip3d from a surface alone: 10^5 sites in sphere-fine, 10^5 probes", "[clip][data]") {
  const voroclip_test::TempDir dir("clip3d_sphere_fine");
  const TwoDomains d = tet_mesh_and_surface("sphere-fine", dir);
  const auto n = static_cast<std::uint32_t>(100000 * test_scale());
  const std::vector<double> sites = sample_volume(d.surface, n, 15);
  const Delaunay3 dt(sites.data(), n);
  const ClippedVoronoi3 cv = clip(d.surface, dt);
  check_diagram(d.surface, dt, cv, n, 15);
  // The same cells from the tet mesh's domain (the same surface), to rounding: the two
  // list each triangle's corners from a different first corner.
  const ClippedVoronoi3 ct = clip(d.tets, dt, false);
  REQUIRE(cv.nb_boundary_sites() == ct.nb_boundary_sites());
  const double vunit = d.surface.volume() / n;
  for (std::uint32_t i = 0; i < n; ++i) {
    REQUIRE(cv.is_boundary(i) == ct.is_boundary(i));
    REQUIRE(std::fabs(cv.volume(i) - ct.volume(i)) <= 1e-12 * (cv.volume(i) + vunit));
  }
}

TEST_CASE("clip3d from a surface alone: cavities, components, a tube, the paper's cases",
          "[clip][degenerate]") {
  using voroclip_test::icosphere;
  std::mt19937_64 rng(61);
  const auto random_sites = [&](const Domain3& d, std::uint32_t n, double margin) {
    std::vector<double> xyz;
    for (std::uint32_t i = 0; i < n; ++i) {
      for (int c = 0; c < 3; ++c) {
        const double lo = d.bbox_lo()[c] - margin, hi = d.bbox_hi()[c] + margin;
        xyz.push_back(std::uniform_real_distribution<double>(lo, hi)(rng));
      }
    }
    return xyz;
  };
  SECTION("a hollow ball (sites in the cavity and outside too)") {
    const Domain3 d(
        voroclip_test::merged(icosphere(3, 2), voroclip_test::reversed(icosphere(2, 1))));
    REQUIRE(d.surface().shells().size() == 2);
    const std::vector<double> sites = random_sites(d, 2000, 0.3);
    const Delaunay3 dt(sites.data(), 2000);
    check_diagram(d, dt, clip(d, dt), 20000, 61);
  }
  SECTION("two disjoint balls, one with few sites near it") {
    const Domain3 d(voroclip_test::merged(icosphere(3, 1), icosphere(2, 0.5, {3, 0, 0})));
    const std::vector<double> sites = random_sites(d, 1000, 0.5);
    const Delaunay3 dt(sites.data(), 1000);
    check_diagram(d, dt, clip(d, dt), 20000, 62);
  }
  SECTION("a tube: the bisector of two sites on its axis cuts an annulus (a face with a hole)") {
    const Domain3 d(voroclip_test::tube_surface(1, 2, -1, 1, 64));
    // Two far sites whose cells miss the tube, so that the four make a tet.
    const std::vector<double> sites = {0, 0, -0.5, 0, 0, 0.5, 50, 0, 0, 0, 50, 0};
    const Delaunay3 dt(sites.data(), 4);
    const ClippedVoronoi3 cv = clip(d, dt);
    check_diagram(d, dt, cv, 20000, 63);
    REQUIRE(std::fabs(cv.volume(0) - d.volume() / 2) <= 1e-13 * d.volume());
    const ClippedVoronoi3::Polygons& f = cv.cell_faces();
    int loops = 0;
    double signed_area = 0;
    for (std::size_t k = 0; k < f.site.size(); ++k) {
      if (f.site[k] != 0 || f.across[k] != 1) continue;
      ++loops;
      // On the plane z = 0, facing inwards (clockwise seen from site 1, at +z).
      for (std::uint32_t v = f.polygon_begin[k]; v < f.polygon_begin[k + 1]; ++v) {
        const std::uint32_t w = v + 1 == f.polygon_begin[k + 1] ? f.polygon_begin[k] : v + 1;
        REQUIRE(std::fabs(f.xyz[3 * std::size_t{v} + 2]) <= 1e-15);
        signed_area += 0.5 * (f.xyz[3 * std::size_t{v}] * f.xyz[3 * std::size_t{w} + 1] -
                              f.xyz[3 * std::size_t{w}] * f.xyz[3 * std::size_t{v} + 1]);
      }
    }
    REQUIRE(loops == 2);  // the outer circle and the hole
    const double ring = 0.5 * 64 * std::sin(2 * 3.14159265358979323846 / 64) * (4 - 1);
    REQUIRE(std::fabs(signed_area + ring) <= 1e-12 * ring);
  }
  SECTION("Fig. 10: the sites are the vertices of sphere.obj") {
    const Domain3 sphere(voroclip::read_surface(kData + "/surfaces/sphere.obj"));
    const std::vector<double>& sites = sphere.coords();
    const auto n = static_cast<std::uint32_t>(sites.size() / 3);
    REQUIRE(n == 642);
    const Delaunay3 dt(sites.data(), n);
    const ClippedVoronoi3 cv = clip(sphere, dt);
    check_diagram(sphere, dt, cv, 20000, 64);
    REQUIRE(cv.nb_boundary_sites() == n);
  }
  SECTION("Fig. 11: the corners of a cube given by its 12 triangles") {
    const Domain3 cube(voroclip_test::box_surface({0, 0, 0}, {2, 2, 2}));
    std::vector<double> corners;
    for (int c = 0; c < 8; ++c)
      corners.insert(corners.end(), {2.0 * (c & 1), 2.0 * ((c >> 1) & 1), 2.0 * (c >> 2)});
    const Delaunay3 dt(corners.data(), 8);
    const ClippedVoronoi3 cv = clip(cube, dt);
    check_diagram(cube, dt, cv, 20000, 65);
    for (std::uint32_t i = 0; i < 8; ++i) {
      REQUIRE(std::fabs(cv.volume(i) - 1.0) < 1e-14);
      REQUIRE(cv.is_boundary(i));
      REQUIRE(std::fabs(cv.surface_area(i) - 3.0) < 1e-13);
    }
  }
  SECTION("integer and half-integer grids in a box of 12 triangles") {
    const Domain3 cube(voroclip_test::box_surface({0, 0, 0}, {4, 4, 4}));
    std::vector<double> grid, half;
    for (int z = -1; z <= 5; ++z) {
      for (int y = -1; y <= 5; ++y) {
        for (int x = -1; x <= 5; ++x) grid.insert(grid.end(), {double(x), double(y), double(z)});
      }
    }
    grid.insert(grid.end(), grid.begin(), grid.begin() + 30);  // ten duplicates
    const Delaunay3 dt(grid.data(), static_cast<std::uint32_t>(grid.size() / 3));
    check_diagram(cube, dt, clip(cube, dt), 20000, 66);
    for (int z = -1; z <= 4; ++z) {
      for (int y = -1; y <= 4; ++y) {
        for (int x = -1; x <= 4; ++x) half.insert(half.end(), {x + 0.5, y + 0.5, z + 0.5});
      }
    }
    const Delaunay3 dth(half.data(), static_cast<std::uint32_t>(half.size() / 3));
    const ClippedVoronoi3 cvh = clip(cube, dth);
    check_diagram(cube, dth, cvh, 20000, 67);
    for (std::uint32_t i = 0; i < cvh.nb_sites(); ++i) {
      const double* p = &half[3 * i];
      const bool inside = p[0] > 0 && p[0] < 4 && p[1] > 0 && p[1] < 4 && p[2] > 0 && p[2] < 4;
      REQUIRE(std::fabs(cvh.volume(i) - (inside ? 1.0 : 0.0)) < 1e-13);
    }
  }
}

TEST_CASE("clip3d from a surface alone: a density given as a function", "[clip]") {
  const Domain3 tets(voroclip::read_tet_mesh(kData + "/tetmeshes/bunny.mesh"));
  const Domain3 surface(voroclip::read_surface(kData + "/surfaces/bunny.obj"));
  const std::vector<double> sites = sample_volume(tets, 3000, 71);
  const Delaunay3 dt(sites.data(), 3000);
  const double* lo = tets.bbox_lo();
  const double* hi = tets.bbox_hi();
  const auto rho = [lo, hi](double x, double y, double z) {
    return 1 + (x - lo[0]) / (hi[0] - lo[0]) + 2 * (y - lo[1]) / (hi[1] - lo[1]) +
           3 * (z - lo[2]) / (hi[2] - lo[2]);
  };
  // Linear: the quadrature is exact, as is the tet-by-tet path's per-piece integration.
  std::vector<double> values;
  for (std::uint32_t v = 0; v < tets.nb_vertices(); ++v) {
    const double* p = tets.vertex(v);
    values.push_back(rho(p[0], p[1], p[2]));
  }
  voroclip::Clip3Options lin, fun;
  lin.density = voroclip::Density3::vertex_linear(values);
  fun.density = voroclip::Density3::function(rho);
  ClippedVoronoi3 ref, cv;
  ref.compute(tets, dt, lin);
  cv.compute(surface, dt, fun);
  REQUIRE(std::fabs(cv.total_mass() - ref.total_mass()) <= 1e-12 * ref.total_mass());
  REQUIRE(std::fabs(cv.total_volume() - surface.volume()) <= 1e-12 * surface.volume());
  const double munit = ref.total_mass() / 3000;
  for (std::uint32_t i = 0; i < 3000; ++i) {
    INFO("site " << i);
    REQUIRE(cv.is_boundary(i) == ref.is_boundary(i));
    REQUIRE(std::fabs(cv.mass(i) - ref.mass(i)) <= 1e-11 * (ref.mass(i) + munit));
    REQUIRE(std::fabs(cv.energy(i) - ref.energy(i)) <= 1e-11 * (ref.energy(i) + 1e-3 * munit));
    for (int c = 0; c < 3; ++c) {
      REQUIRE(std::fabs(cv.centroid(i)[c] - ref.centroid(i)[c]) <= 1e-9);
    }
  }
  // A cubic density on a box: the total mass and first moment in closed form.
  const Domain3 box(voroclip_test::box_surface({0, 0, 0}, {2, 1, 1}));
  voroclip::Clip3Options cubic;
  cubic.density = voroclip::Density3::function(
      [](double x, double y, double z) { return 1 + x * x * x + y * z; });
  std::vector<double> s2(3 * 500);
  std::mt19937_64 rng(72);
  for (std::size_t k = 0; k < s2.size(); ++k) {
    s2[k] = std::uniform_real_distribution<double>(-0.1, k % 3 == 0 ? 2.1 : 1.1)(rng);
  }
  const Delaunay3 db(s2.data(), 500);
  ClippedVoronoi3 cb;
  cb.compute(box, db, cubic);
  // ∫ over [0,2]x[0,1]^2 of 1 + x^3 + yz = 2 + 4 + 2 / 4 = 6.5.
  REQUIRE(std::fabs(cb.total_mass() - 6.5) <= 1e-13 * 6.5);
  double moment_x = 0;
  for (std::uint32_t i = 0; i < 500; ++i) moment_x += cb.mass(i) * cb.centroid(i)[0];
  // ∫ x (1 + x^3 + yz) = 2 + 32 / 5 + 2 / 4 = 8.9.
  REQUIRE(std::fabs(moment_x - 8.9) <= 1e-12 * 8.9);
  // Errors: a density per tet needs tets; tet_clipping too.
  voroclip::Clip3Options bad = lin;
  CHECK_THROWS_WITH(cv.compute(surface, dt, bad), Catch::Contains("needs a domain with a "
                                                                  "tetrahedral mesh"));
  voroclip::Clip3Options tc;
  tc.tet_clipping = true;
  CHECK_THROWS_WITH(cv.compute(surface, dt, tc), Catch::Contains("tet_clipping needs"));
}

TEST_CASE("clip3d from a surface alone: identical with 1 and 2 threads", "[clip][threads]") {
  const Domain3 d(voroclip_test::merged(voroclip::read_surface(kData + "/surfaces/elk.off"),
                                        voroclip_test::box_surface({-5, -5, -5}, {-4, -4, -4})));
  const std::vector<double> sites = sample_volume(d, 4000, 81);
  voroclip::Clip3Options o;
  o.keep_geometry = true;
  o.density = voroclip::Density3::function(
      [](double x, double y, double z) { return 1 / (0.5 + x * x + 0.1 * y * y + z * z); });
  ClippedVoronoi3 one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one.compute(d, sites.data(), 4000, o);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism,
                          voroclip_test::test_threads());
    two.compute(d, sites.data(), 4000, o);
  }
  require_same_cells(one, two);
  for (std::uint32_t i = 0; i < 4000; ++i) REQUIRE(one.mass(i) == two.mass(i));
  REQUIRE(one.cell_faces().xyz == two.cell_faces().xyz);
  REQUIRE(one.cell_faces().across == two.cell_faces().across);
}

// Regression: a site far outside the domain had its cell integrated as cones from the site
// (a site 1e20 away: volume -8768 for the unit sphere) and its bisectors' points built by
// the midpoint formula (x - (p + q) / 2).(q - p), which keeps nothing for sites 1e20 away:
// the bisector of (s, 0.3, 0.1) and (0.3, s, 0.1) (the plane x = y) split the cube wrong.
// The exact answers: one site's cell is the whole cube [-1, 1]^3 (volume 8, centroid 0,
// ∫|x - p|^2 = 8 (|p|^2 + 1), surface area 24); sites mirrored by x <-> y, or by x -> -x,
// split it into halves (volume 4, centroid (1/3, -1/3, 0) or (1/2, 0, 0), area 12). Every
// result is within 1e-12 (relative) of them, measured 2e-16 .. 1e-15.
TEST_CASE("clip3d: sites far outside the domain", "[clip][regression]") {
  voroclip::TetMeshInput m = cube_mesh(2);
  for (double& x : m.xyz) x -= 1;  // [-1, 1]^3, exactly
  const Domain3 cube(m);
  const auto near = [](double a, double b, double scale) {
    return std::fabs(a - b) <= 1e-12 * scale;
  };
  for (const bool tet_clipping : {false, true}) {
    voroclip::Clip3Options o;
    o.tet_clipping = tet_clipping;
    for (const double s : {1e3, 1e6, 1e10, 1e20, 1e100}) {
      INFO("s = " << s << ", tet_clipping " << tet_clipping);
      {
        const double p[3] = {s, 0.3, 0.1};
        ClippedVoronoi3 cv;
        cv.compute(cube, p, 1, o);
        CHECK(near(cv.volume(0), 8, 8));
        for (int k = 0; k < 3; ++k) CHECK(near(cv.centroid(0)[k], 0, 1));
        CHECK(near(cv.energy(0), 8 * (s * s + 0.1 + 1), 8 * (s * s + 1.1)));
        CHECK(near(cv.surface_area(0), 24, 24));
      }
      {
        const double p[6] = {s, 0.3, 0.1, 0.3, s, 0.1};
        ClippedVoronoi3 cv;
        cv.compute(cube, p, 2, o);
        for (std::uint32_t i = 0; i < 2; ++i) {
          CHECK(near(cv.volume(i), 4, 4));
          CHECK(near(cv.centroid(i)[0], i == 0 ? 1.0 / 3 : -1.0 / 3, 1));
          CHECK(near(cv.centroid(i)[1], i == 0 ? -1.0 / 3 : 1.0 / 3, 1));
          CHECK(near(cv.centroid(i)[2], 0, 1));
          CHECK(near(cv.surface_area(i), 12, 12));
        }
      }
      {
        const double p[6] = {s, 0.3, 0.1, -s, 0.3, 0.1};
        ClippedVoronoi3 cv;
        cv.compute(cube, p, 2, o);
        for (std::uint32_t i = 0; i < 2; ++i) {
          CHECK(near(cv.volume(i), 4, 4));
          CHECK(near(cv.centroid(i)[0], i == 0 ? 0.5 : -0.5, 1));
          CHECK(near(cv.centroid(i)[1], 0, 1));
          CHECK(near(cv.centroid(i)[2], 0, 1));
          CHECK(near(cv.surface_area(i), 12, 12));
        }
      }
    }
    // Beyond 2^500 from the domain the energy (~ s^2 V) may overflow: an Error, not inf.
    const double p[3] = {1e200, 0.3, 0.1};
    ClippedVoronoi3 cv;
    CHECK_THROWS_WITH(cv.compute(cube, p, 1, o), Catch::Contains("too far from the domain"));
  }
}
