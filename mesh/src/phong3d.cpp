// The Phong tessellation of a triangle surface (mesh.h, PhongSurface): the smooth surface
// mesh3d projects its surface sites onto (smooth_surface), with exactly planar regions kept
// in their plane.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "mesh3d_pipeline.h"
#include "voroclip/mesh.h"

namespace voroclip {

namespace {

using mesh3::edge_key;

// The planar regions of a triangle surface (see PhongSurface): a vertex is flat when each
// of its edges has two triangles and every triangle around it is in one patch and exactly
// coplanar with the others (orient3d, exact); the triangles around flat vertices seed the
// regions, which grow across edges inside a patch to every exactly coplanar neighbour. Returns one
// region id per triangle (kNoRegion outside) and the unit normal of each region (the normalised sum
// of its triangles' cross products).
constexpr std::uint32_t kNoRegion = 0xffffffffu;

std::uint32_t planar_regions(const TriangleSurface& surface,
                             const std::vector<std::uint32_t>& patch,
                             std::vector<std::uint32_t>& region, std::vector<double>& normals) {
  const std::uint32_t nt = surface.nb_triangles(), nv = surface.nb_vertices();
  const auto corner = [&](std::uint32_t t, int k) {
    const std::uint32_t v = surface.triangles[3 * std::size_t{t} + static_cast<std::size_t>(k)];
    return &surface.xyz[3 * std::size_t{v}];
  };
  const auto coplanar = [&](std::uint32_t t, const double* x) {
    return orient3d(corner(t, 0), corner(t, 1), corner(t, 2), x) == Sign::zero;
  };
  // Triangles around each vertex (CSR).
  std::vector<std::uint32_t> first(std::size_t{nv} + 1, 0), around(3 * std::size_t{nt});
  for (const std::uint32_t v : surface.triangles) ++first[std::size_t{v} + 1];
  for (std::uint32_t v = 0; v < nv; ++v) first[v + 1] += first[v];
  {
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
    for (std::uint32_t t = 0; t < nt; ++t) {
      for (int k = 0; k < 3; ++k) {
        around[fill[surface.triangles[3 * std::size_t{t} + static_cast<std::size_t>(k)]]++] = t;
      }
    }
  }
  // Edge adjacency: the two triangles of an edge used by exactly two.
  struct Side {
    std::uint64_t key;
    std::uint32_t triangle;
    std::uint32_t opposite;  // the triangle's vertex off the edge
  };
  std::vector<Side> sides;
  std::vector<std::uint8_t> open(nv, 0);
  sides.reserve(3 * std::size_t{nt});
  for (std::uint32_t t = 0; t < nt; ++t) {
    const std::uint32_t* tv = &surface.triangles[3 * std::size_t{t}];
    for (int k = 0; k < 3; ++k) {
      sides.push_back({edge_key(tv[(k + 1) % 3], tv[(k + 2) % 3]), t, tv[k]});
    }
  }
  std::sort(sides.begin(), sides.end(), [](const Side& a, const Side& b) {
    return a.key != b.key ? a.key < b.key : a.triangle < b.triangle;
  });
  std::vector<std::uint32_t> adjacent(3 * std::size_t{nt}, kNoRegion);  // (t, slot) pairs
  std::vector<std::uint32_t> nb_adjacent(nt, 0), across(3 * std::size_t{nt});
  for (std::size_t i = 0; i < sides.size();) {
    std::size_t j = i;
    while (j < sides.size() && sides[j].key == sides[i].key) ++j;
    if (j - i != 2) {
      // A vertex of an edge not shared by exactly two triangles is not flat.
      for (std::size_t k = i; k < j; ++k) {
        open[sides[k].key >> 32] = 1;
        open[sides[k].key & 0xffffffffu] = 1;
      }
    } else {
      for (int s = 0; s < 2; ++s) {
        const Side& a = sides[i + static_cast<std::size_t>(s)];
        const Side& b = sides[i + static_cast<std::size_t>(1 - s)];
        const std::size_t slot = 3 * std::size_t{a.triangle} + nb_adjacent[a.triangle]++;
        adjacent[slot] = b.triangle;
        across[slot] = b.opposite;
      }
    }
    i = j;
  }
  region.assign(nt, kNoRegion);
  std::vector<std::uint32_t> seed(nt, kNoRegion);  // a seed's reference triangle (not collinear)
  for (std::uint32_t v = 0; v < nv; ++v) {
    std::uint32_t ref = kNoRegion;
    for (std::uint32_t i = first[v]; i < first[v + 1]; ++i) {
      const std::uint32_t t = around[i];
      if (!collinear3d(corner(t, 0), corner(t, 1), corner(t, 2))) {
        ref = t;
        break;
      }
    }
    if (ref == kNoRegion || open[v] != 0) continue;
    bool flat = true;
    for (std::uint32_t i = first[v]; i < first[v + 1] && flat; ++i) {
      const std::uint32_t t = around[i];
      flat = patch[t] == patch[ref];
      for (int k = 0; k < 3 && flat; ++k) flat = coplanar(ref, corner(t, k));
    }
    if (!flat) continue;
    for (std::uint32_t i = first[v]; i < first[v + 1]; ++i) seed[around[i]] = ref;
  }
  std::uint32_t nb_regions = 0;
  std::vector<std::uint32_t> queue;
  normals.clear();
  for (std::uint32_t t0 = 0; t0 < nt; ++t0) {
    if (seed[t0] == kNoRegion || region[t0] != kNoRegion) continue;
    const std::uint32_t ref = seed[t0];
    region[t0] = nb_regions;
    queue.assign(1, t0);
    double sum[3] = {0, 0, 0};
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const std::uint32_t t = queue[q];
      const double *a = corner(t, 0), *b = corner(t, 1), *c = corner(t, 2);
      const double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
      const double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
      sum[0] += e1[1] * e2[2] - e1[2] * e2[1];
      sum[1] += e1[2] * e2[0] - e1[0] * e2[2];
      sum[2] += e1[0] * e2[1] - e1[1] * e2[0];
      for (std::uint32_t e = 0; e < nb_adjacent[t]; ++e) {
        const std::size_t slot = 3 * std::size_t{t} + e;
        const std::uint32_t n = adjacent[slot];
        if (region[n] != kNoRegion || patch[n] != patch[t] ||
            !coplanar(ref, &surface.xyz[3 * std::size_t{across[slot]}]))
          continue;
        region[n] = nb_regions;
        queue.push_back(n);
      }
    }
    const double len = std::sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
    for (int a = 0; a < 3; ++a) normals.push_back(len > 0 ? sum[a] / len : 0.0);
    ++nb_regions;
  }
  return nb_regions;
}

}  // namespace

PhongSurface::PhongSurface(const TriangleSurface& surface,
                           const std::vector<std::uint32_t>& triangle_patch,
                           const std::vector<std::uint8_t>& pinned, double shape)
    : shape_(shape) {
  const std::uint32_t nt = surface.nb_triangles();
  if (!triangle_patch.empty() && triangle_patch.size() != nt) {
    throw Error("PhongSurface: " + std::to_string(triangle_patch.size()) + " patch ids for " +
                std::to_string(nt) + " triangles of " + surface.source);
  }
  if (!pinned.empty() && pinned.size() != surface.nb_vertices()) {
    throw Error("PhongSurface: " + std::to_string(pinned.size()) + " pinned flags for " +
                std::to_string(surface.nb_vertices()) + " vertices of " + surface.source);
  }
  if (!(shape >= 0 && shape <= 1)) {
    throw Error("PhongSurface: shape factor " + std::to_string(shape) + "; expected [0, 1]");
  }
  const auto patch_of = [&](std::uint32_t t) {
    return triangle_patch.empty() ? 0u : triangle_patch[t];
  };
  corners_.resize(9 * std::size_t{nt});
  face_normal_.assign(3 * std::size_t{nt}, 0.0);
  corner_normal_.assign(9 * std::size_t{nt}, 0.0);
  corner_shape_.assign(3 * std::size_t{nt}, shape);
  // One slot per (vertex, patch) met at a corner: the angle-weighted sum of face normals.
  std::vector<std::uint64_t> keys(3 * std::size_t{nt});
  for (std::uint32_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = surface.triangles[3 * std::size_t{t} + static_cast<std::size_t>(k)];
      if (v >= surface.nb_vertices()) {
        throw Error("PhongSurface: triangle " + std::to_string(t) + " of " + surface.source +
                    " has vertex " + std::to_string(v) + " out of range");
      }
      std::copy_n(&surface.xyz[3 * std::size_t{v}], 3,
                  &corners_[9 * std::size_t{t} + 3 * static_cast<std::size_t>(k)]);
      keys[3 * std::size_t{t} + static_cast<std::size_t>(k)] = std::uint64_t{v} << 32 | patch_of(t);
      if (!pinned.empty() && pinned[v] != 0) {
        corner_shape_[3 * std::size_t{t} + static_cast<std::size_t>(k)] = 0;
      }
    }
  }
  std::vector<std::uint64_t> slots = keys;
  std::sort(slots.begin(), slots.end());
  slots.erase(std::unique(slots.begin(), slots.end()), slots.end());
  std::vector<double> sum(3 * slots.size(), 0.0);
  std::vector<std::uint32_t> slot_of(keys.size());
  for (std::size_t i = 0; i < keys.size(); ++i) {
    slot_of[i] = static_cast<std::uint32_t>(std::lower_bound(slots.begin(), slots.end(), keys[i]) -
                                            slots.begin());
  }
  for (std::uint32_t t = 0; t < nt; ++t) {
    const double* c = &corners_[9 * std::size_t{t}];
    double e1[3], e2[3], n[3];
    for (int a = 0; a < 3; ++a) {
      e1[a] = c[3 + a] - c[a];
      e2[a] = c[6 + a] - c[a];
    }
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(len > 0) || !std::isfinite(len)) continue;
    double* fn = &face_normal_[3 * std::size_t{t}];
    for (int a = 0; a < 3; ++a) fn[a] = n[a] / len;
    for (int k = 0; k < 3; ++k) {
      const double* p = c + 3 * k;
      const double* q = c + 3 * ((k + 1) % 3);
      const double* r = c + 3 * ((k + 2) % 3);
      double u[3], w[3], x[3];
      for (int a = 0; a < 3; ++a) {
        u[a] = q[a] - p[a];
        w[a] = r[a] - p[a];
      }
      x[0] = u[1] * w[2] - u[2] * w[1];
      x[1] = u[2] * w[0] - u[0] * w[2];
      x[2] = u[0] * w[1] - u[1] * w[0];
      const double angle = std::atan2(std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]),
                                      u[0] * w[0] + u[1] * w[1] + u[2] * w[2]);
      double* sl = &sum[3 * std::size_t{slot_of[3 * std::size_t{t} + static_cast<std::size_t>(k)]}];
      for (int a = 0; a < 3; ++a) sl[a] += angle * fn[a];
    }
  }
  // Planar regions keep their plane: every corner of a region's triangle, and every corner
  // at a vertex whose slot meets exactly one region, takes the region's normal.
  std::vector<std::uint32_t> patch(nt), region;
  for (std::uint32_t t = 0; t < nt; ++t) patch[t] = patch_of(t);
  std::vector<double> region_normal;
  planar_regions(surface, patch, region, region_normal);
  constexpr std::uint32_t kSeveral = kNoRegion - 1;
  std::vector<std::uint32_t> slot_region(slots.size(), kNoRegion);
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const std::uint32_t r = region[i / 3];
    std::uint32_t& sr = slot_region[slot_of[i]];
    if (r != kNoRegion) sr = sr == kNoRegion || sr == r ? r : kSeveral;
  }
  for (std::size_t i = 0; i < keys.size(); ++i) {
    std::uint32_t r = region[i / 3];
    if (r == kNoRegion && slot_region[slot_of[i]] != kSeveral) r = slot_region[slot_of[i]];
    const double* sl =
        r != kNoRegion ? &region_normal[3 * std::size_t{r}] : &sum[3 * std::size_t{slot_of[i]}];
    const double len = std::sqrt(sl[0] * sl[0] + sl[1] * sl[1] + sl[2] * sl[2]);
    if (!(len > 0)) continue;
    for (int a = 0; a < 3; ++a) corner_normal_[3 * i + static_cast<std::size_t>(a)] = sl[a] / len;
  }
}

void PhongSurface::lift(std::uint32_t t, const double* x, double* q, double* normal) const {
  const double* c = &corners_[9 * std::size_t{t}];
  const double* fn = &face_normal_[3 * std::size_t{t}];
  std::copy_n(x, 3, q);
  std::copy_n(fn, 3, normal);
  // Barycentric coordinates from the sub-triangles (x - p_k differences: at x = p_k the two
  // sub-triangles that have x and p_k as corners are exactly zero).
  double d[3][3];
  for (int k = 0; k < 3; ++k) {
    for (int a = 0; a < 3; ++a) d[k][a] = c[3 * k + a] - x[a];
  }
  double u[3], total = 0;
  for (int k = 0; k < 3; ++k) {
    const double* e = d[(k + 1) % 3];
    const double* f = d[(k + 2) % 3];
    u[k] = (e[1] * f[2] - e[2] * f[1]) * fn[0] + (e[2] * f[0] - e[0] * f[2]) * fn[1] +
           (e[0] * f[1] - e[1] * f[0]) * fn[2];
    total += u[k];
  }
  if (!(total > 0)) return;  // degenerate triangle: flat
  double shift[3] = {0, 0, 0}, m[3] = {0, 0, 0};
  for (int k = 0; k < 3; ++k) {
    const double w = std::max(u[k], 0.0) / total;
    const double* nk = corner_normal(t, k);
    const double h = corner_shape_[3 * std::size_t{t} + static_cast<std::size_t>(k)] * w *
                     (d[k][0] * nk[0] + d[k][1] * nk[1] + d[k][2] * nk[2]);
    for (int a = 0; a < 3; ++a) {
      shift[a] += h * nk[a];
      m[a] += w * nk[a];
    }
  }
  for (int a = 0; a < 3; ++a) q[a] = x[a] + shift[a];
  const double len = std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
  if (len > 0) {
    for (int a = 0; a < 3; ++a) normal[a] = m[a] / len;
  }
}

void PhongSurface::project(const SurfaceTree& tree, const double* p, double* q,
                           double* normal) const {
  const SurfaceTree::Closest c = tree.closest(p);
  if (c.triangle == SurfaceTree::kNone) {
    std::copy_n(c.point, 3, q);
    std::copy_n(c.normal, 3, normal);
    return;
  }
  lift(c.triangle, c.point, q, normal);
  if (normal[0] == 0 && normal[1] == 0 && normal[2] == 0) std::copy_n(c.normal, 3, normal);
}

}  // namespace voroclip
