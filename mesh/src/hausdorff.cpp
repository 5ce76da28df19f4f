// Sampled two-sided Hausdorff distance between triangle surfaces, as Metro measures it
// (Cignoni, Rocchini, Scopigno 1998): samples at the vertices, along the edges and at the
// centroids of similar sub-triangles ("similar triangles sampling"), each measured exactly
// (in double precision) against the other surface through a SurfaceTree.
//
// Determinism: per-item slots (per vertex, per edge, per triangle) written by parallel
// loops, reduced in item order; a sample's answer does not depend on the hint given to the
// tree. So the result is the same for any thread count.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "voroclip/mesh.h"

namespace voroclip {

namespace {

// The largest distance in an item, where (its sample), and the item's weighted sum.
struct Slot {
  double max = -1;
  double where[3] = {0, 0, 0};
  double weighted = 0;
};

double triangle_area(const double* a, const double* b, const double* c) {
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                       u[0] * v[1] - u[1] * v[0]};
  return 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

// Subdivisions of a length or of sqrt(area) at step h, at least 1, at most 2^12 (a
// triangle then holds 2^24 samples: far past any useful density).
std::uint32_t divisions(double size, double h) {
  if (!(h > 0)) return 1;
  const double n = std::round(size / h);
  return n < 1 ? 1u : n > 4096 ? 4096u : static_cast<std::uint32_t>(n);
}

}  // namespace

OneSidedDistance sampled_distance(const TriangleSurface& from, const SurfaceTree& to,
                                  const HausdorffOptions& options) {
  const std::uint32_t nt = from.nb_triangles();
  const std::uint32_t nv = from.nb_vertices();
  if (nt == 0) throw Error(from.source + ": no triangles to sample");
  if (to.nb_triangles() == 0) throw Error("sampled_distance: the target surface is empty");
  for (const std::uint32_t v : from.triangles) {
    if (v >= nv) throw Error(from.source + ": a triangle has a vertex index out of range");
  }
  const auto vertex = [&](std::uint32_t t, std::size_t k) {
    return &from.xyz[3 * std::size_t{from.triangles[3 * std::size_t{t} + k]}];
  };
  std::vector<double> area(nt);
  double total_area = 0;
  for (std::uint32_t t = 0; t < nt; ++t) {
    area[t] = triangle_area(vertex(t, 0), vertex(t, 1), vertex(t, 2));
    total_area += area[t];
  }
  const double target = std::max(static_cast<double>(options.min_samples),
                                 options.samples_per_triangle * static_cast<double>(nt));
  const double h = total_area > 0 && target > 0 ? std::sqrt(total_area / target) : 0.0;

  // Used vertices and unique edges (as sorted pairs).
  std::vector<std::uint32_t> vertices(from.triangles);
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  std::vector<std::uint64_t> edges;
  edges.reserve(3 * std::size_t{nt});
  for (std::uint32_t t = 0; t < nt; ++t) {
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint64_t a = from.triangles[3 * std::size_t{t} + k];
      const std::uint64_t b = from.triangles[3 * std::size_t{t} + (k + 1) % 3];
      if (a != b) edges.push_back(std::min(a, b) << 32 | std::max(a, b));
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());

  // A block of samples, measured and then reduced into their items' slots in sample
  // order: with options.scale_batch, one call per block scales them (a Python or
  // interpreted function pays its per-call cost, and takes its lock, once per block).
  struct Sample {
    double p[3];
    double distance;  // unscaled
    Slot* slot;
    double weight;  // of a sub-triangle centroid in its slot's mean; < 0: none
  };
  struct Block {
    std::vector<Sample> samples;
    std::vector<double> xyz, scales;
    std::uint32_t hint = SurfaceTree::kNone;
  };
  const auto flush = [&](Block& b) {
    const std::size_t n = b.samples.size();
    if (options.scale_batch) {
      b.xyz.resize(3 * n);
      b.scales.resize(n);
      for (std::size_t k = 0; k < n; ++k) {
        for (int q = 0; q < 3; ++q) b.xyz[3 * k + q] = b.samples[k].p[q];
      }
      options.scale_batch(b.xyz.data(), n, b.scales.data());
    }
    for (std::size_t k = 0; k < n; ++k) {
      const Sample& x = b.samples[k];
      const double d = options.scale_batch ? x.distance / b.scales[k]
                       : options.scale     ? x.distance / options.scale(x.p)
                                           : x.distance;
      Slot& slot = *x.slot;
      if (d > slot.max) {
        slot.max = d;
        for (int q = 0; q < 3; ++q) slot.where[q] = x.p[q];
      }
      if (x.weight >= 0) slot.weighted += x.weight * d;
    }
    b.samples.clear();
  };
  constexpr std::size_t kBlock = 4096;
  const auto measure = [&](const double* p, Block& b, Slot& slot, double weight) {
    const SurfaceTree::Closest c = to.closest(p, b.hint);
    if (c.triangle == SurfaceTree::kNone) {
      throw Error(from.source + ": a squared distance overflows (coordinates too large)");
    }
    b.hint = c.triangle;
    b.samples.push_back({{p[0], p[1], p[2]}, std::sqrt(c.distance2), &slot, weight});
    if (b.samples.size() == kBlock) flush(b);
  };
  std::vector<Slot> vertex_slots(vertices.size()), edge_slots(edges.size()), tri_slots(nt);
  std::vector<std::uint64_t> edge_samples(edges.size(), 0), tri_samples(nt, 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, vertices.size(), 256),
                    [&](const auto& range) {
                      Block b;
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        measure(&from.xyz[3 * std::size_t{vertices[i]}], b, vertex_slots[i], -1);
                      }
                      flush(b);
                    });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, edges.size(), 256), [&](const auto& range) {
    Block b;
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      const double* a = &from.xyz[3 * (edges[i] >> 32)];
      const double* c = &from.xyz[3 * (edges[i] & 0xffffffffu)];
      const double len = std::sqrt((c[0] - a[0]) * (c[0] - a[0]) + (c[1] - a[1]) * (c[1] - a[1]) +
                                   (c[2] - a[2]) * (c[2] - a[2]));
      const std::uint32_t m = divisions(len, h);
      for (std::uint32_t j = 1; j < m; ++j) {
        const double s = static_cast<double>(j) / m;
        const double p[3] = {a[0] + s * (c[0] - a[0]), a[1] + s * (c[1] - a[1]),
                             a[2] + s * (c[2] - a[2])};
        measure(p, b, edge_slots[i], -1);
      }
      edge_samples[i] = m - 1;
    }
    flush(b);
  });
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, nt, 64), [&](const auto& range) {
    Block b;
    for (std::uint32_t t = range.begin(); t != range.end(); ++t) {
      const double* a = vertex(t, 0);
      const double* bv = vertex(t, 1);
      const double* c = vertex(t, 2);
      const std::uint32_t n = divisions(std::sqrt(area[t]), h);
      const double weight = area[t] / (static_cast<double>(n) * n);
      Slot& slot = tri_slots[t];
      // Sub-triangle centroids in barycentric steps of 1/n: the "upward" ones at
      // ((i + 1/3) / n, (j + 1/3) / n), i + j <= n - 1, the "downward" ones at
      // ((i + 2/3) / n, (j + 2/3) / n), i + j <= n - 2, coordinates of b and c.
      for (int pass = 0; pass < 2; ++pass) {
        const double shift = pass == 0 ? 1.0 / 3 : 2.0 / 3;
        const std::uint32_t last = n - 1 - static_cast<std::uint32_t>(pass);
        for (std::uint32_t i = 0; i + static_cast<std::uint32_t>(pass) < n; ++i) {
          for (std::uint32_t j = 0; i + j <= last; ++j) {
            const double u = (i + shift) / n, v = (j + shift) / n, w = 1 - u - v;
            const double p[3] = {w * a[0] + u * bv[0] + v * c[0], w * a[1] + u * bv[1] + v * c[1],
                                 w * a[2] + u * bv[2] + v * c[2]};
            measure(p, b, slot, weight);
          }
        }
      }
      tri_samples[t] = std::uint64_t{n} * n;
    }
    flush(b);
  });
  OneSidedDistance out;
  double weighted = 0, vertex_sum = 0;
  bool found = false;
  const auto take = [&](const Slot& s) {
    if (s.max > out.max || (!found && s.max >= 0)) {
      out.max = s.max;
      for (int k = 0; k < 3; ++k) out.where[k] = s.where[k];
      found = true;
    }
  };
  for (const Slot& s : vertex_slots) {
    take(s);
    vertex_sum += s.max;
  }
  for (const Slot& s : edge_slots) take(s);
  for (const Slot& s : tri_slots) {
    take(s);
    weighted += s.weighted;
  }
  out.nb_samples = vertices.size();
  for (const std::uint64_t n : edge_samples) out.nb_samples += n;
  for (const std::uint64_t n : tri_samples) out.nb_samples += n;
  out.mean =
      total_area > 0 ? weighted / total_area : vertex_sum / static_cast<double>(vertices.size());
  return out;
}

HausdorffDistance hausdorff_distance(const TriangleSurface& surface,
                                     const TriangleSurface& reference,
                                     const HausdorffOptions& options) {
  if (surface.nb_triangles() == 0) throw Error(surface.source + ": no triangles");
  if (reference.nb_triangles() == 0) throw Error(reference.source + ": no triangles");
  return hausdorff_distance(surface, SurfaceTree(surface), reference, SurfaceTree(reference),
                            options);
}

HausdorffDistance hausdorff_distance(const TriangleSurface& surface,
                                     const SurfaceTree& surface_tree,
                                     const TriangleSurface& reference,
                                     const SurfaceTree& reference_tree,
                                     const HausdorffOptions& options) {
  HausdorffDistance d;
  d.forward = sampled_distance(surface, reference_tree, options);
  d.backward = sampled_distance(reference, surface_tree, options);
  d.max = std::max(d.forward.max, d.backward.max);
  d.mean = std::max(d.forward.mean, d.backward.mean);
  double diag2 = 0;
  for (int k = 0; k < 3; ++k) {
    const double e = reference_tree.bbox_hi()[k] - reference_tree.bbox_lo()[k];
    diag2 += e * e;
  }
  d.diagonal = std::sqrt(diag2);
  return d;
}

}  // namespace voroclip
