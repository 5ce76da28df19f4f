// The 3D sizing field: lfs at the boundary vertices from the poles of their Voronoi
// diagram, spread as the largest g-Lipschitz function below it over a grid (mesh.h).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "voroclip/delaunay.h"
#include "voroclip/mesh.h"

namespace voroclip {

namespace {

constexpr std::uint32_t kNone = 0xffffffffu;

double dist(const double* a, const double* b) {
  const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

// Points in a regular grid of buckets, each bucket with the smallest weight of its points,
// for minimising weight(s) + g |x - p_s| over the points (a branch and bound).
class BucketGrid {
 public:
  template <class Weight>
  BucketGrid(const std::vector<double>& xyz, std::uint32_t m, Weight weight) {
    for (int c = 0; c < 3; ++c) {
      lo_[c] = std::numeric_limits<double>::infinity();
      double hi = -lo_[c];
      for (std::uint32_t s = 0; s < m; ++s) {
        lo_[c] = std::min(lo_[c], xyz[3 * std::size_t{s} + std::size_t(c)]);
        hi = std::max(hi, xyz[3 * std::size_t{s} + std::size_t(c)]);
      }
      extent_[c] = hi - lo_[c];
    }
    const double longest = std::max({extent_[0], extent_[1], extent_[2]});
    // About 4 points per bucket.
    const double per_side = std::max(1.0, std::cbrt(m / 4.0));
    cell_ = longest > 0 ? longest / per_side : 1;
    for (int c = 0; c < 3; ++c) {
      n_[c] = std::max<std::uint32_t>(1, static_cast<std::uint32_t>(extent_[c] / cell_) + 1);
    }
    const std::size_t nb = std::size_t{n_[0]} * n_[1] * n_[2];
    begin_.assign(nb + 1, 0);
    min_weight_.assign(nb, std::numeric_limits<double>::infinity());
    std::vector<std::uint32_t> bucket_of(m);
    for (std::uint32_t s = 0; s < m; ++s) {
      bucket_of[s] = bucket(&xyz[3 * std::size_t{s}]);
      ++begin_[bucket_of[s] + 1];
      min_weight_[bucket_of[s]] = std::min(min_weight_[bucket_of[s]], weight(s));
    }
    for (std::size_t b = 0; b < nb; ++b) begin_[b + 1] += begin_[b];
    points_.resize(m);
    std::vector<std::uint32_t> fill(begin_.begin(), begin_.end() - 1);
    for (std::uint32_t s = 0; s < m; ++s) points_[fill[bucket_of[s]]++] = s;
    min_all_ = *std::min_element(min_weight_.begin(), min_weight_.end());
  }

  // Calls visit(s) for every point of every bucket that may hold a point with
  // weight(s) + g |x - p_s| < bound (bound: read again after each visit, which may
  // lower it).
  template <class Visit>
  void search(const double* x, double g, Visit visit, const double& bound) const {
    const double radius = (bound - min_all_) / g;
    std::uint32_t lo[3], hi[3];
    for (int c = 0; c < 3; ++c) {
      lo[c] = clamp_index(c, (x[c] - radius - lo_[c]) / cell_);
      hi[c] = clamp_index(c, (x[c] + radius - lo_[c]) / cell_);
    }
    for (std::uint32_t k = lo[2]; k <= hi[2]; ++k) {
      for (std::uint32_t j = lo[1]; j <= hi[1]; ++j) {
        for (std::uint32_t i = lo[0]; i <= hi[0]; ++i) {
          const std::size_t b = (std::size_t{k} * n_[1] + j) * n_[0] + i;
          if (begin_[b] == begin_[b + 1]) continue;
          // Distance from x to the bucket's box.
          const std::uint32_t idx[3] = {i, j, k};
          double d2 = 0;
          for (int c = 0; c < 3; ++c) {
            const double b0 = lo_[c] + cell_ * idx[c], b1 = b0 + cell_;
            const double e = x[c] < b0 ? b0 - x[c] : x[c] > b1 ? x[c] - b1 : 0;
            d2 += e * e;
          }
          if (min_weight_[b] + g * std::sqrt(d2) >= bound) continue;
          for (std::uint32_t q = begin_[b]; q < begin_[b + 1]; ++q) visit(points_[q]);
        }
      }
    }
  }

 private:
  std::uint32_t clamp_index(int c, double t) const {
    if (!(t > 0)) return 0;
    return std::min<std::uint32_t>(n_[c] - 1,
                                   t >= n_[c] ? n_[c] - 1 : static_cast<std::uint32_t>(t));
  }
  std::uint32_t bucket(const double* p) const {
    std::uint32_t idx[3];
    for (int c = 0; c < 3; ++c) idx[c] = clamp_index(c, (p[c] - lo_[c]) / cell_);
    return static_cast<std::uint32_t>((std::size_t{idx[2]} * n_[1] + idx[1]) * n_[0] + idx[0]);
  }

  double lo_[3], extent_[3], cell_ = 1, min_all_ = 0;
  std::uint32_t n_[3] = {1, 1, 1};
  std::vector<std::uint32_t> begin_, points_;
  std::vector<double> min_weight_;
};

// The pole distances (lfs estimates) of a domain's boundary vertices.
struct PoleDistances {
  std::vector<double> lfs;              // per domain vertex (0 off the boundary)
  std::vector<std::uint32_t> boundary;  // the boundary vertices, in the order of their first use
  std::vector<double> xyz;              // and their positions
  double max = 0;  // the largest, at most the bounding box's diagonal (none exceeds it)
};

void check_sizing(const Domain3& domain, const Sizing3Options& options) {
  if (domain.surface().nb_triangles() == 0) {
    throw Error("sizing: the domain " + domain.source() + " has no boundary triangles");
  }
  if (!(options.gradation > 0) || !(options.max_ratio >= 1) || options.resolution < 2 ||
      options.resolution > 1024) {
    throw Error("sizing: gradation must be > 0, max_ratio >= 1 and resolution within [2, 1024]");
  }
}

PoleDistances pole_distances(const Domain3& domain) {
  const Surface3& surface = domain.surface();
  // Boundary vertices (local numbering) and their area-weighted outward normals (the
  // surface's triangles face outward: Surface3).
  const std::uint32_t nv = domain.nb_vertices();
  std::vector<std::uint32_t> local(nv, kNone);
  std::vector<std::uint32_t> global;
  std::vector<double> normal;
  for (std::uint32_t b = 0; b < surface.nb_triangles(); ++b) {
    const double* p[3];
    for (int k = 0; k < 3; ++k) p[k] = surface.vertex(surface.triangle_vertex(b, k));
    const double u[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
    const double w[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
    const double outward[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                               u[0] * w[1] - u[1] * w[0]};
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = surface.triangle_vertex(b, k);
      if (local[v] == kNone) {
        local[v] = static_cast<std::uint32_t>(global.size());
        global.push_back(v);
        normal.insert(normal.end(), {0.0, 0.0, 0.0});
      }
      for (int c = 0; c < 3; ++c) normal[3 * std::size_t{local[v]} + std::size_t(c)] += outward[c];
    }
  }
  const auto m = static_cast<std::uint32_t>(global.size());
  std::vector<double> xyz(3 * std::size_t{m});
  for (std::uint32_t k = 0; k < m; ++k) {
    std::copy_n(domain.vertex(global[k]), 3, &xyz[3 * std::size_t{k}]);
  }

  // Poles: per boundary vertex the farthest Voronoi vertex on each side of the surface;
  // lfs = the distance to the nearer of its poles (the pole distance, Amenta & Bern).
  const Delaunay3 dt(xyz.data(), m);
  const auto in_box = [&](const double* c) {
    for (int a = 0; a < 3; ++a) {
      if (!(c[a] >= domain.bbox_lo()[a] && c[a] <= domain.bbox_hi()[a])) return false;
    }
    return true;
  };
  std::vector<std::uint8_t> on_hull(m, 0);
  for (const std::uint32_t v : dt.hull_vertices()) on_hull[v] = 1;
  PoleDistances out;
  std::vector<double>& lfs = out.lfs;
  lfs.assign(nv, 0);
  double lfs_max = 0;
  std::vector<std::uint32_t> tets;
  for (std::uint32_t k = 0; k < m; ++k) {
    const double* v = &xyz[3 * std::size_t{k}];
    const double* n = &normal[3 * std::size_t{k}];
    double best[2] = {-1, -1};  // squared distances of the poles: inner, outer
    dt.vertex_tets(k, tets);
    for (const std::uint32_t t : tets) {
      double c[3];
      dt.circumcenter(t, c);
      if (!std::isfinite(c[0]) || !std::isfinite(c[1]) || !std::isfinite(c[2])) continue;
      const double d[3] = {c[0] - v[0], c[1] - v[1], c[2] - v[2]};
      const int side = d[0] * n[0] + d[1] * n[1] + d[2] * n[2] < 0 ? 0 : 1;
      // An inner pole lies in the domain, hence in its bounding box: a circumcentre outside
      // it is that of a nearly flat tet (cospherical samples), computed with a large error.
      if (side == 0 && !in_box(c)) continue;
      best[side] = std::max(best[side], d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    }
    if (on_hull[k]) best[1] = -1;  // the outer pole is at infinity
    double d = std::numeric_limits<double>::infinity();
    for (const double b2 : best) {
      if (b2 >= 0) d = std::min(d, std::sqrt(b2));
    }
    lfs[global[k]] = d;
    if (std::isfinite(d)) lfs_max = std::max(lfs_max, d);
  }
  const double diag = dist(domain.bbox_lo(), domain.bbox_hi());
  // No pole at all (a flat sampling): a uniform field. No lfs exceeds the diagonal.
  lfs_max = lfs_max > 0 ? std::min(lfs_max, diag) : diag;
  for (const std::uint32_t v : global) lfs[v] = std::min(lfs[v], lfs_max);
  out.max = lfs_max;
  out.boundary = std::move(global);
  out.xyz = std::move(xyz);
  return out;
}

}  // namespace

SizingField3::SizingField3(const Domain3& domain, const Sizing3Options& options)
    : SizingField3(domain, options, {}) {}

SizingField3::SizingField3(const Domain3& domain, const Sizing3Options& options,
                           const std::vector<std::uint8_t>& skip) {
  check_sizing(domain, options);
  PoleDistances poles = pole_distances(domain);
  // The seeds of the field: the boundary vertices not skipped.
  std::vector<double> xyz, seed_lfs;
  for (std::size_t k = 0; k < poles.boundary.size(); ++k) {
    const std::uint32_t v = poles.boundary[k];
    if (v < skip.size() && skip[v] != 0) continue;
    xyz.insert(xyz.end(), &poles.xyz[3 * k], &poles.xyz[3 * k] + 3);
    seed_lfs.push_back(poles.lfs[v]);
  }
  lfs_ = std::move(poles.lfs);
  h_min_ = poles.max / options.max_ratio;
  spread(domain, xyz, seed_lfs, options);
}

SizingField3::SizingField3(const Domain3& domain, const std::vector<const Domain3*>& parts,
                           const Sizing3Options& options,
                           const std::vector<std::vector<std::uint8_t>>& skips) {
  if (parts.empty()) throw Error("sizing: no part of the domain " + domain.source());
  for (const Domain3* part : parts) {
    check_sizing(*part, options);
    if (part->nb_vertices() != domain.nb_vertices()) {
      throw Error("sizing: the part " + part->source() + " has " +
                  std::to_string(part->nb_vertices()) + " vertices, the domain " +
                  std::to_string(domain.nb_vertices()) + ": a part is on the domain's vertices");
    }
  }
  lfs_.assign(domain.nb_vertices(), 0);
  double largest = 0;
  std::vector<double> xyz, seed_lfs;
  const std::vector<std::uint8_t> none;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const PoleDistances poles = pole_distances(*parts[i]);
    largest = std::max(largest, poles.max);
    const std::vector<std::uint8_t>& skip = i < skips.size() ? skips[i] : none;
    for (std::size_t k = 0; k < poles.boundary.size(); ++k) {
      const std::uint32_t v = poles.boundary[k];
      lfs_[v] = lfs_[v] == 0 ? poles.lfs[v] : std::min(lfs_[v], poles.lfs[v]);
      if (v < skip.size() && skip[v] != 0) continue;
      xyz.insert(xyz.end(), &poles.xyz[3 * k], &poles.xyz[3 * k] + 3);
      seed_lfs.push_back(poles.lfs[v]);
    }
  }
  h_min_ = largest / options.max_ratio;
  spread(domain, xyz, seed_lfs, options);
}

// The field on a grid over the domain's bounding box: the smallest seed_lfs[s] + g |x - s|
// over the seeds s (xyz), at least h_min_; the diagonal everywhere without seeds.
void SizingField3::spread(const Domain3& domain, const std::vector<double>& xyz,
                          const std::vector<double>& seed_lfs, const Sizing3Options& options) {
  const auto seeds = static_cast<std::uint32_t>(seed_lfs.size());
  const double diag = dist(domain.bbox_lo(), domain.bbox_hi());
  // The grid and the minimising boundary vertex of each node.
  const double* lo = domain.bbox_lo();
  const double* hi = domain.bbox_hi();
  const double longest = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  spacing_ = longest > 0 ? longest / (options.resolution - 1) : 1;
  for (int c = 0; c < 3; ++c) {
    lo_[c] = lo[c];
    n_[c] = static_cast<std::uint32_t>(std::ceil((hi[c] - lo[c]) / spacing_)) + 1;
    n_[c] = std::clamp<std::uint32_t>(n_[c], 2, options.resolution);
  }
  const std::size_t nodes = std::size_t{n_[0]} * n_[1] * n_[2];
  std::vector<std::uint32_t> source(nodes, kNone);
  h_.assign(nodes, std::numeric_limits<double>::infinity());
  const double g = options.gradation;
  const auto node_point = [&](std::uint32_t i, std::uint32_t j, std::uint32_t k, double* x) {
    x[0] = lo_[0] + spacing_ * i;
    x[1] = lo_[1] + spacing_ * j;
    x[2] = lo_[2] + spacing_ * k;
  };
  const auto index = [&](std::uint32_t i, std::uint32_t j, std::uint32_t k) {
    return (std::size_t{k} * n_[1] + j) * n_[0] + i;
  };
  const auto offer = [&](std::size_t node, const double* x, std::uint32_t s) {
    const double value = seed_lfs[s] + g * dist(x, &xyz[3 * std::size_t{s}]);
    if (value < h_[node]) {
      h_[node] = value;
      source[node] = s;
      return true;
    }
    return false;
  };
  // Seeds: each boundary vertex offers itself to the 8 nodes of its grid cell.
  if (seeds == 0) {
    // Nothing to seed the field (every boundary vertex skipped): the diagonal, which no
    // lfs exceeds, everywhere.
    h_.assign(nodes, diag);
    return;
  }
  for (std::uint32_t s = 0; s < seeds; ++s) {
    std::uint32_t base[3];
    for (int c = 0; c < 3; ++c) {
      const double t = (xyz[3 * std::size_t{s} + std::size_t(c)] - lo_[c]) / spacing_;
      base[c] = std::min<std::uint32_t>(static_cast<std::uint32_t>(std::max(0.0, t)), n_[c] - 2);
    }
    for (int corner = 0; corner < 8; ++corner) {
      const std::uint32_t i = base[0] + (corner & 1), j = base[1] + ((corner >> 1) & 1),
                          k = base[2] + ((corner >> 2) & 1);
      double x[3];
      node_point(i, j, k, x);
      offer(index(i, j, k), x, s);
    }
  }
  // Propagation: forward and backward raster sweeps over the 26 neighbours, each node
  // trying its neighbours' minimisers, until a pair of sweeps changes nothing. This gives
  // an upper bound close to the minimum (the minimiser of a node is almost always one of
  // its neighbours'); a bounded search then makes it exact.
  for (int pass = 0; pass < 16; ++pass) {
    bool changed = false;
    for (int dir = 0; dir < 2; ++dir) {
      for (std::uint32_t kk = 0; kk < n_[2]; ++kk) {
        const std::uint32_t k = dir == 0 ? kk : n_[2] - 1 - kk;
        for (std::uint32_t jj = 0; jj < n_[1]; ++jj) {
          const std::uint32_t j = dir == 0 ? jj : n_[1] - 1 - jj;
          for (std::uint32_t ii = 0; ii < n_[0]; ++ii) {
            const std::uint32_t i = dir == 0 ? ii : n_[0] - 1 - ii;
            const std::size_t node = index(i, j, k);
            double x[3];
            node_point(i, j, k, x);
            for (int dk = -1; dk <= 1; ++dk) {
              for (int dj = -1; dj <= 1; ++dj) {
                for (int di = -1; di <= 1; ++di) {
                  const auto ni = static_cast<std::int64_t>(i) + di;
                  const auto nj = static_cast<std::int64_t>(j) + dj;
                  const auto nk = static_cast<std::int64_t>(k) + dk;
                  if (ni < 0 || nj < 0 || nk < 0 || ni >= n_[0] || nj >= n_[1] || nk >= n_[2]) {
                    continue;
                  }
                  const std::uint32_t s =
                      source[index(static_cast<std::uint32_t>(ni), static_cast<std::uint32_t>(nj),
                                   static_cast<std::uint32_t>(nk))];
                  if (s != kNone && s != source[node] && offer(node, x, s)) changed = true;
                }
              }
            }
          }
        }
      }
    }
    if (!changed) break;
  }
  // Exact minimum: boundary vertices in buckets, each with its smallest lfs; a bucket at
  // distance r from x cannot beat the current value h when min lfs + g r >= h.
  BucketGrid buckets(xyz, seeds, [&](std::uint32_t s) { return seed_lfs[s]; });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nodes, 512), [&](const auto& range) {
    for (std::size_t node = range.begin(); node != range.end(); ++node) {
      const auto i = static_cast<std::uint32_t>(node % n_[0]);
      const auto j = static_cast<std::uint32_t>((node / n_[0]) % n_[1]);
      const auto k = static_cast<std::uint32_t>(node / (std::size_t{n_[0]} * n_[1]));
      double x[3];
      node_point(i, j, k, x);
      buckets.search(
          x, g, [&](std::uint32_t s) { offer(node, x, s); }, h_[node]);
    }
  });
  for (double& h : h_) h = std::max(h, h_min_);
}

double SizingField3::size(const double* p) const {
  double t[3];
  std::uint32_t base[3];
  for (int c = 0; c < 3; ++c) {
    const double u = std::clamp((p[c] - lo_[c]) / spacing_, 0.0, double(n_[c] - 1));
    base[c] = std::min<std::uint32_t>(static_cast<std::uint32_t>(u), n_[c] - 2);
    t[c] = u - base[c];
  }
  double value = 0;
  for (int corner = 0; corner < 8; ++corner) {
    const int b[3] = {corner & 1, (corner >> 1) & 1, (corner >> 2) & 1};
    double w = 1;
    for (int c = 0; c < 3; ++c) w *= b[c] ? t[c] : 1 - t[c];
    const std::size_t node =
        (std::size_t{base[2] + std::uint32_t(b[2])} * n_[1] + base[1] + std::uint32_t(b[1])) *
            n_[0] +
        base[0] + std::uint32_t(b[0]);
    value += w * h_[node];
  }
  return value;
}

std::vector<double> SizingField3::vertex_density(const Domain3& domain) const {
  std::vector<double> rho(domain.nb_vertices());
  for (std::uint32_t v = 0; v < domain.nb_vertices(); ++v) {
    const double h = size(domain.vertex(v));
    rho[v] = 1 / (h * h * h * h * h);
  }
  return rho;
}

}  // namespace voroclip
