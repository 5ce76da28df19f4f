// The 3D CVT tet-meshing pipeline (Yan et al. 2011, sec. 5.2; the steps are listed in
// mesh.h): sizing, sampling, unconstrained CVT, snapping of boundary, feature and corner
// sites, constrained CVT, exact extraction, sliver perturbation, output and quality.
//
// Feature sites (step 4). Each feature line is sampled every eighth of the local spacing
// of the sites (the spacing that n sites of density h^-3 have: (integral of h^-3 / n)^(1/3)
// h(x), h the sizing field or 1), and at its end; the site nearest to a sample
// (Delaunay3::nearest_vertex, exact) is the site whose Voronoi cell holds it, so the sites sampled
// are those whose cells the line crosses, in order along it. A site met on several lines goes to
// the line with the most samples in its cell (ties: the lower line). Corners come first: each takes
// the site nearest to it unless that site already went to another corner, in which case a new site
// is added at the corner. Surface sites are then the boundary sites (ClippedVoronoi3::
// is_boundary) left. Every choice is a function of the sites, in index order.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "mesh3d_tags.h"
#include "voroclip/mesh.h"

namespace voroclip {

namespace {

using Kind = SiteConstraint3::Kind;
using Clock = std::chrono::steady_clock;

// The shortest decimal of x.
std::string detail_number(double x) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, r.ptr);
}

double since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

struct Cancelled {};

// Projection onto the boundary surface (closest point, pseudo-normal) or onto a site's
// feature line (closest point, tangent). Const queries: thread-safe.
struct Projection {
  const SurfaceTree* surface = nullptr;
  const FeatureTree* lines = nullptr;
  const std::vector<std::uint32_t>* line_of = nullptr;  // per site (kCurve)
  const PhongSurface* smooth = nullptr;                 // kSurface sites: lifted onto it when set

  void operator()(std::uint32_t site, Kind kind, const double* p, double* q, double* d) const {
    if (kind == Kind::kCurve) {
      const FeatureTree::Closest c = lines->closest(p, (*line_of)[site]);
      std::copy_n(c.point, 3, q);
      std::copy_n(c.tangent, 3, d);
    } else if (smooth) {
      smooth->project(*surface, p, q, d);
    } else {
      const SurfaceTree::Closest c = surface->closest(p);
      std::copy_n(c.point, 3, q);
      std::copy_n(c.normal, 3, d);
    }
  }
};

// Sites on a body-centred cubic lattice (the points a (i, j, k) + o and a (i + 1/2, j + 1/2,
// k + 1/2) + o) strictly inside the domain (exact point location), about n of them: the
// spacing starts at (2 V / n)^(1/3) and is corrected by the count's cube root until the
// count is within 0.5 % of n (at most 6 times). The offset o is a function of the seed.
// The BCC lattice is the best known CVT in space (its cells are truncated octahedra,
// Du & Wang 2005), so only the sites near the boundary have far to go.
std::vector<double> lattice_sites(const Domain3& domain, const TetExtractor3& locator,
                                  std::uint32_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  double offset[3];
  for (double& o : offset) o = static_cast<double>(rng() >> 11) * 0x1p-53;
  const double* lo = domain.bbox_lo();
  const double* hi = domain.bbox_hi();
  double a = std::cbrt(2 * domain.volume() / n);
  std::vector<double> xyz;
  for (int attempt = 0; attempt < 6; ++attempt) {
    xyz.clear();
    std::int64_t first[3], last[3];
    for (int c = 0; c < 3; ++c) {
      first[c] = static_cast<std::int64_t>(std::floor(lo[c] / a - offset[c])) - 1;
      last[c] = static_cast<std::int64_t>(std::ceil(hi[c] / a - offset[c])) + 1;
    }
    for (int shift = 0; shift < 2; ++shift) {
      for (std::int64_t k = first[2]; k <= last[2]; ++k) {
        for (std::int64_t j = first[1]; j <= last[1]; ++j) {
          for (std::int64_t i = first[0]; i <= last[0]; ++i) {
            const std::int64_t ijk[3] = {i, j, k};
            double p[3];
            for (int c = 0; c < 3; ++c) {
              p[c] = a * (static_cast<double>(ijk[c]) + offset[c] + 0.5 * shift);
            }
            if (locator.point_side(p) == Sign::positive) xyz.insert(xyz.end(), p, p + 3);
          }
        }
      }
    }
    const double count = static_cast<double>(xyz.size() / 3);
    if (std::fabs(count - n) <= 0.005 * n) break;
    a *= std::cbrt(std::max(count, 1.0) / n);
  }
  if (xyz.size() < 12) throw Error("mesh3d: the lattice has fewer than 4 points in the domain");
  return xyz;
}

// The integral of f over the volume by the midpoint rule on a grid of 48 cells along the
// longest side of the bounding box, each cell's centre located exactly; slices summed in
// order (the same value for any thread count). For the scale of the sizing field, which
// needs a few digits.
template <class F>
double integrate_over_volume(const Domain3& domain, const F& f) {
  constexpr double kCells = 48;
  const double* lo = domain.bbox_lo();
  const double* hi = domain.bbox_hi();
  const double longest = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  if (!(longest > 0)) return 0;
  const double h = longest / kCells;
  std::uint32_t n[3];
  for (int c = 0; c < 3; ++c) {
    n[c] = std::max<std::uint32_t>(1, static_cast<std::uint32_t>(std::ceil((hi[c] - lo[c]) / h)));
  }
  std::vector<double> slice(n[2], 0);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, n[2], 1), [&](const auto& range) {
    for (std::uint32_t k = range.begin(); k != range.end(); ++k) {
      double sum = 0;
      for (std::uint32_t j = 0; j < n[1]; ++j) {
        for (std::uint32_t i = 0; i < n[0]; ++i) {
          const double p[3] = {lo[0] + (i + 0.5) * h, lo[1] + (j + 0.5) * h, lo[2] + (k + 0.5) * h};
          if (domain.locate(p) == Sign::positive) sum += f(p);
        }
      }
      slice[k] = sum;
    }
  });
  double total = 0;
  for (const double v : slice) total += v;
  return total * h * h * h;
}

// Feature lines cut at the vertices where they turn by more than angle_deg (the angle
// between consecutive segments), which become corners: where a crease folds back on
// itself two feature edges meet, yet the point is a corner of the shape.
FeatureLines split_at_turns(const TriangleSurface& s, const FeatureLines& lines, double angle_deg) {
  const double cos_limit = std::cos(angle_deg * (3.14159265358979323846 / 180));
  const auto turns = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    double u[3], v[3];
    for (int k = 0; k < 3; ++k) {
      u[k] = s.xyz[3 * std::size_t{b} + static_cast<std::size_t>(k)] -
             s.xyz[3 * std::size_t{a} + static_cast<std::size_t>(k)];
      v[k] = s.xyz[3 * std::size_t{c} + static_cast<std::size_t>(k)] -
             s.xyz[3 * std::size_t{b} + static_cast<std::size_t>(k)];
    }
    const double uv = u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    const double uu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
    const double vv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    return uv < cos_limit * std::sqrt(uu * vv);
  };
  FeatureLines out;
  out.corners = lines.corners;
  out.nb_feature_edges = lines.nb_feature_edges;
  const auto emit = [&](const std::vector<std::uint32_t>& vs, bool closed) {
    out.line_vertices.insert(out.line_vertices.end(), vs.begin(), vs.end());
    out.line_begin.push_back(static_cast<std::uint32_t>(out.line_vertices.size()));
    out.line_closed.push_back(closed ? 1 : 0);
  };
  std::vector<std::uint32_t> vs, piece;
  for (std::uint32_t l = 0; l < lines.nb_lines(); ++l) {
    vs.assign(lines.line_vertices.begin() + lines.line_begin[l],
              lines.line_vertices.begin() + lines.line_begin[l + 1]);
    const bool closed = lines.line_closed[l] != 0;
    const std::size_t m = vs.size();
    std::vector<std::size_t> cuts;  // positions of turning vertices
    for (std::size_t i = 0; i < m; ++i) {
      if (closed ? i + 1 == m : (i == 0 || i + 1 == m)) continue;
      const std::uint32_t prev = closed && i == 0 ? vs[m - 2] : vs[i - (i > 0 ? 1 : 0)];
      if (turns(prev, vs[i], vs[i + 1])) cuts.push_back(i);
    }
    if (cuts.empty()) {
      emit(vs, closed);
      continue;
    }
    for (const std::size_t c : cuts) out.corners.push_back(vs[c]);
    if (closed) {
      // Start at the first cut: an open line from cut to cut, all the way round.
      std::vector<std::uint32_t> ring(vs.begin(), vs.end() - 1);
      std::rotate(ring.begin(), ring.begin() + static_cast<std::ptrdiff_t>(cuts[0]), ring.end());
      ring.push_back(ring.front());
      for (std::size_t& c : cuts) c = (c + (m - 1) - cuts[0]) % (m - 1);
      cuts.push_back(m - 1);
      vs = ring;
    } else {
      cuts.push_back(m - 1);
      cuts.insert(cuts.begin(), 0);
    }
    for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
      if (cuts[k + 1] <= cuts[k]) continue;
      piece.assign(vs.begin() + static_cast<std::ptrdiff_t>(cuts[k]),
                   vs.begin() + static_cast<std::ptrdiff_t>(cuts[k + 1]) + 1);
      emit(piece, false);
    }
  }
  std::sort(out.corners.begin(), out.corners.end());
  out.corners.erase(std::unique(out.corners.begin(), out.corners.end()), out.corners.end());
  return out;
}

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
  return a < b ? std::uint64_t{a} << 32 | b : std::uint64_t{b} << 32 | a;
}

// The feature lines at least as long as `ratio` times the local spacing of the sites at
// their middle vertex, and the corners that end them: shorter creases (noise of a coarse
// surface, details below the resolution) are treated as smooth surface.
// A line with an edge of `keep` (sorted edge keys: the borders of tagged patches) is kept
// whatever its length.
template <class Spacing>
FeatureLines drop_short_lines(const TriangleSurface& s, const FeatureLines& lines, double ratio,
                              const Spacing& spacing, const std::vector<std::uint64_t>& keep) {
  FeatureLines out;
  out.nb_feature_edges = 0;
  for (std::uint32_t l = 0; l < lines.nb_lines(); ++l) {
    const std::uint32_t b = lines.line_begin[l], e = lines.line_begin[l + 1];
    double length = 0;
    bool kept = false;
    for (std::uint32_t i = b; i + 1 < e; ++i) {
      kept =
          kept || std::binary_search(keep.begin(), keep.end(),
                                     edge_key(lines.line_vertices[i], lines.line_vertices[i + 1]));
      const double* p = &s.xyz[3 * std::size_t{lines.line_vertices[i]}];
      const double* q = &s.xyz[3 * std::size_t{lines.line_vertices[i + 1]}];
      length += std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                          (p[2] - q[2]) * (p[2] - q[2]));
    }
    const double* middle = &s.xyz[3 * std::size_t{lines.line_vertices[b + (e - b) / 2]}];
    if (!kept && length < ratio * spacing(middle)) continue;
    out.line_vertices.insert(out.line_vertices.end(), lines.line_vertices.begin() + b,
                             lines.line_vertices.begin() + e);
    out.line_begin.push_back(static_cast<std::uint32_t>(out.line_vertices.size()));
    out.line_closed.push_back(lines.line_closed[l]);
    out.nb_feature_edges += e - b - 1;
    if (lines.line_closed[l] == 0) {
      out.corners.push_back(lines.line_vertices[b]);
      out.corners.push_back(lines.line_vertices[e - 1]);
    }
  }
  std::sort(out.corners.begin(), out.corners.end());
  out.corners.erase(std::unique(out.corners.begin(), out.corners.end()), out.corners.end());
  return out;
}

std::vector<std::uint64_t> sorted_feature_edges(const FeatureLines& lines) {
  std::vector<std::uint64_t> features;
  for (std::uint32_t l = 0; l < lines.nb_lines(); ++l) {
    for (std::uint32_t i = lines.line_begin[l]; i + 1 < lines.line_begin[l + 1]; ++i) {
      features.push_back(edge_key(lines.line_vertices[i], lines.line_vertices[i + 1]));
    }
  }
  std::sort(features.begin(), features.end());
  return features;
}

// The patch of each boundary triangle: the triangles grouped by a flood fill across the
// edges that are not feature edges, numbered in the order of their first triangle.
std::vector<std::uint32_t> triangle_patches(const Domain3& domain, const FeatureLines& lines) {
  const std::vector<std::uint64_t> features = sorted_feature_edges(lines);
  const std::uint32_t nb = domain.surface().nb_triangles();
  std::vector<std::uint32_t> patch(nb, SurfaceTree::kNone), queue;
  std::uint32_t nb_patches = 0;
  for (std::uint32_t b0 = 0; b0 < nb; ++b0) {
    if (patch[b0] != SurfaceTree::kNone) continue;
    patch[b0] = nb_patches;
    queue.assign(1, b0);
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const std::uint32_t b = queue[q];
      for (int e = 0; e < 3; ++e) {
        const std::uint32_t a = domain.surface().adjacent(b, e);
        const std::uint64_t key = edge_key(domain.surface().triangle_vertex(b, (e + 1) % 3),
                                           domain.surface().triangle_vertex(b, (e + 2) % 3));
        if (patch[a] != SurfaceTree::kNone ||
            std::binary_search(features.begin(), features.end(), key))
          continue;
        patch[a] = nb_patches;
        queue.push_back(a);
      }
    }
    ++nb_patches;
  }
  return patch;
}

// The surface patches of the sites (SurfacePatches), `patch` the patch of each boundary
// triangle: a surface site is on the patch of the triangle it projects onto, a feature site
// on the patches beside the segment it projects onto, a corner on the patches around its
// vertex.
SurfacePatches site_patches(const Domain3& domain, const FeatureLines& lines,
                            const SurfaceTree& surface, const FeatureTree& line_tree,
                            const std::vector<double>& sites, const std::vector<Kind>& kinds,
                            const std::vector<std::uint32_t>& line_of,
                            const std::vector<std::uint32_t>& corner_vertex,
                            const std::vector<std::uint32_t>& patch) {
  const std::vector<std::uint64_t> features = sorted_feature_edges(lines);
  const auto is_feature = [&](std::uint64_t k) {
    return std::binary_search(features.begin(), features.end(), k);
  };
  const std::uint32_t nb = domain.surface().nb_triangles();
  const auto edge_of = [&](std::uint32_t b, int e) {
    return edge_key(domain.surface().triangle_vertex(b, (e + 1) % 3),
                    domain.surface().triangle_vertex(b, (e + 2) % 3));
  };
  // (feature edge, patch) and (corner vertex, patch) pairs.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> edge_patch, vertex_patch;
  std::vector<std::uint32_t> corner_mark(domain.nb_vertices(), 0);
  for (const std::uint32_t v : corner_vertex) {
    if (v != SurfaceTree::kNone) corner_mark[v] = 1;
  }
  for (std::uint32_t b = 0; b < nb; ++b) {
    for (int e = 0; e < 3; ++e) {
      if (is_feature(edge_of(b, e))) edge_patch.emplace_back(edge_of(b, e), patch[b]);
      const std::uint32_t v = domain.surface().triangle_vertex(b, e);
      if (corner_mark[v] != 0) vertex_patch.emplace_back(v, patch[b]);
    }
  }
  std::sort(edge_patch.begin(), edge_patch.end());
  edge_patch.erase(std::unique(edge_patch.begin(), edge_patch.end()), edge_patch.end());
  std::sort(vertex_patch.begin(), vertex_patch.end());
  vertex_patch.erase(std::unique(vertex_patch.begin(), vertex_patch.end()), vertex_patch.end());
  const auto append_all = [](auto& pairs, auto key, std::vector<std::uint32_t>& out) {
    auto it = std::lower_bound(pairs.begin(), pairs.end(),
                               std::make_pair(std::uint64_t{key}, std::uint32_t{0}));
    for (; it != pairs.end() && it->first == key; ++it) out.push_back(it->second);
  };
  SurfacePatches sp;
  const auto n = static_cast<std::uint32_t>(kinds.size());
  sp.begin.reserve(std::size_t{n} + 1);
  sp.begin.push_back(0);
  for (std::uint32_t s = 0; s < n; ++s) {
    const double* p = &sites[3 * std::size_t{s}];
    if (kinds[s] == Kind::kSurface) {
      sp.patches.push_back(patch[surface.closest(p).triangle]);
    } else if (kinds[s] == Kind::kCurve) {
      const std::uint32_t l = line_of[s];
      const FeatureTree::Closest c = line_tree.closest(p, l);
      const std::uint32_t i = lines.line_begin[l] + c.segment;
      append_all(edge_patch, edge_key(lines.line_vertices[i], lines.line_vertices[i + 1]),
                 sp.patches);
    } else if (kinds[s] == Kind::kFixed && corner_vertex[s] != SurfaceTree::kNone) {
      append_all(vertex_patch, std::uint64_t{corner_vertex[s]}, sp.patches);
    }
    sp.begin.push_back(static_cast<std::uint32_t>(sp.patches.size()));
  }
  return sp;
}

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

const char* mesh3_phase_name(Mesh3Phase phase) {
  switch (phase) {
    case Mesh3Phase::kSizing:
      return "sizing";
    case Mesh3Phase::kSampling:
      return "sampling";
    case Mesh3Phase::kUnconstrained:
      return "unconstrained";
    case Mesh3Phase::kSnapping:
      return "snapping";
    case Mesh3Phase::kConstrained:
      return "constrained";
    case Mesh3Phase::kTopology:
      return "topology";
    case Mesh3Phase::kExtraction:
      return "extraction";
    case Mesh3Phase::kSlivers:
      return "slivers";
    case Mesh3Phase::kQuality:
      return "quality";
  }
  return "?";
}

TriangleSurface boundary_surface(const Domain3& domain) {
  TriangleSurface s;
  s.source = domain.source() + " (boundary)";
  s.xyz = domain.coords();
  s.triangles.reserve(3 * std::size_t{domain.surface().nb_triangles()});
  s.triangles = domain.surface().triangles();
  s.triangle_line.assign(domain.surface().nb_triangles(), 0);
  return s;
}

Mesh3Result mesh3d(const Domain3& domain, const Mesh3Options& options) {
  if (options.edge_length != 0) {
    // An absolute size: the vertex count it takes, then the run with that count.
    if (!(options.edge_length > 0) || !std::isfinite(options.edge_length)) {
      throw Error("mesh3d: edge length " + std::to_string(options.edge_length) +
                  "; expected a positive number");
    }
    if (options.adaptive)
      throw Error("mesh3d: an absolute edge length and adaptive sizing exclude each other");
    if (domain.surface().nb_triangles() == 0) throw Error("mesh3d: the domain has no boundary");
    const Density3& rho = options.density;
    double integral = domain.volume();
    if (!rho.is_constant()) {
      if (rho.kind != Density3::Kind::kCallback || !rho.callback) {
        throw Error(
            "mesh3d: the density must be a function (a density linear per tet is not supported "
            "here)");
      }
      integral = integrate_over_volume(domain, [&rho](const double* p) {
        return std::pow(rho.callback(p[0], p[1], p[2]), 0.6);
      });
    }
    const double h = options.edge_length;
    const double n = std::round(kMesh3VerticesPerEdgeVolume * integral / (h * h * h));
    if (!(n <= 2e9)) {
      throw Error("mesh3d: the edge length asks for " + std::to_string(n) +
                  " vertices; at most 2e9");
    }
    Mesh3Options o = options;
    o.edge_length = 0;
    o.nb_vertices = static_cast<std::uint32_t>(std::max(4.0, n));
    return mesh3d(domain, o);
  }
  const Clock::time_point t_start = Clock::now();
  if (options.nb_vertices < 4) {
    throw Error("mesh3d: " + std::to_string(options.nb_vertices) + " vertices; need at least 4");
  }
  if (!(options.feature_angle_deg >= 0 && options.feature_angle_deg <= 180)) {
    throw Error("mesh3d: feature angle " + std::to_string(options.feature_angle_deg) +
                " degrees; expected a value in [0, 180]");
  }
  if (!(options.smooth_shape >= 0 && options.smooth_shape <= 1)) {
    throw Error("mesh3d: smooth_shape " + std::to_string(options.smooth_shape) +
                "; expected a value in [0, 1]");
  }
  if (domain.surface().nb_triangles() == 0) throw Error("mesh3d: the domain has no boundary");
  Mesh3Result result;
  Mesh3Phase phase = Mesh3Phase::kSizing;
  Clock::time_point t_phase = t_start;
  // false when the caller asks to stop.
  const auto notify = [&](Mesh3Progress p) {
    p.phase = phase;
    p.seconds = since(t_start);
    return !options.progress || options.progress(p);
  };
  const auto report = [&](const Mesh3Progress& p) {
    if (!notify(p)) throw Cancelled{};
  };
  const auto next_phase = [&](Mesh3Phase next) {
    result.seconds[static_cast<int>(phase)] += since(t_phase);
    t_phase = Clock::now();
    phase = next;
    report({});
  };
  const auto cvt_progress = [&](const CvtProgress& c) {
    Mesh3Progress p;
    p.iteration = c.iteration;
    p.energy = c.energy;
    p.gradient_norm = c.gradient_norm;
    return notify(p);
  };

  try {
    report({});
    // 1. Sizing.
    Clip3Options clip;
    // The local spacing of the sites is about spacing_scale * h(x) (h = 1 when uniform):
    // with n sites of density h^-3 in the volume, spacing_scale^3 = (integral of h^-3) / n.
    std::unique_ptr<SizingField3> field;
    double integral = domain.volume();
    const Density3& user_density = options.density;
    const bool graded = options.adaptive || !user_density.is_constant();
    if (!user_density.is_constant()) {
      if (options.adaptive) throw Error("mesh3d: a density and adaptive sizing exclude each other");
      if (user_density.kind != Density3::Kind::kCallback || !user_density.callback) {
        throw Error(
            "mesh3d: the density must be a function (a density linear per tet is not "
            "supported here)");
      }
      // rho = h^-5 and n sites of density h^-3: h = rho^(-1/5), h^-3 = rho^(3/5).
      clip.density = user_density;
      integral = integrate_over_volume(domain, [&user_density](const double* p) {
        return std::pow(user_density.callback(p[0], p[1], p[2]), 0.6);
      });
    } else if (options.adaptive) {
      field = std::make_unique<SizingField3>(domain, options.sizing);
      const SizingField3* h = field.get();
      clip.density = Density3::function([h](double x, double y, double z) {
        const double p[3] = {x, y, z};
        const double s = h->size(p);
        return 1 / (s * s * s * s * s);
      });
      integral = integrate_over_volume(domain, [h](const double* p) {
        const double s = h->size(p);
        return 1 / (s * s * s);
      });
    }
    const auto local_spacing = [&](const double* x) {
      const double scale = std::cbrt(integral / options.nb_vertices);
      if (!user_density.is_constant()) {
        return scale * std::pow(user_density.callback(x[0], x[1], x[2]), -0.2);
      }
      return field ? scale * field->size(x) : scale;
    };
    const TriangleSurface surface = boundary_surface(domain);
    const SurfaceTree surface_tree(surface);
    // The input's triangle tags (a tet mesh file's boundary triangles): the borders of
    // their patches are feature lines too, kept however short or flat, so that every
    // boundary triangle of the mesh lies in one patch and carries its tag.
    const std::vector<std::int32_t>& input_tags = domain.boundary_refs();
    std::vector<std::uint64_t> tag_borders;
    for (std::uint32_t b = 0; b < domain.surface().nb_triangles() && !input_tags.empty(); ++b) {
      for (int e = 0; e < 3; ++e) {
        const std::uint32_t a = domain.surface().adjacent(b, e);
        if (a > b && input_tags[a] != input_tags[b]) {
          tag_borders.push_back(edge_key(domain.surface().triangle_vertex(b, (e + 1) % 3),
                                         domain.surface().triangle_vertex(b, (e + 2) % 3)));
        }
      }
    }
    std::sort(tag_borders.begin(), tag_borders.end());
    FeatureLines lines;
    if (options.features || !tag_borders.empty()) {
      // Without features, only the tags' borders (no edge is sharper than 180 degrees).
      const double angle = options.features ? options.feature_angle_deg : 180.0;
      lines = drop_short_lines(
          surface,
          split_at_turns(surface, extract_feature_lines(surface, angle, input_tags), angle),
          options.min_feature_length, local_spacing, tag_borders);
    }
    const FeatureTree line_tree(surface, lines);
    const std::vector<std::uint32_t> triangle_patch = triangle_patches(domain, lines);
    // The smooth surface's patches are bounded by every edge sharper than feature_angle_deg,
    // and pinned there, kept feature line or not: a crease too short to keep (or
    // features = false) is not rounded by the interpolant, which would bulge the large flat
    // triangles beside it.
    std::unique_ptr<PhongSurface> smooth;
    if (options.smooth_surface) {
      const FeatureLines sharp =
          extract_feature_lines(surface, options.feature_angle_deg, input_tags);
      std::vector<std::uint8_t> pinned(surface.nb_vertices(), 0);
      for (const std::uint32_t v : sharp.line_vertices) pinned[v] = 1;
      for (const std::uint32_t v : sharp.corners) pinned[v] = 1;
      smooth = std::make_unique<PhongSurface>(surface, triangle_patches(domain, sharp), pinned,
                                              options.smooth_shape);
    }
    result.nb_feature_lines = lines.nb_lines();
    result.nb_feature_corners = static_cast<std::uint32_t>(lines.corners.size());

    // 2. Sampling.
    next_phase(Mesh3Phase::kSampling);
    const TetExtractor3 extractor(domain);
    std::vector<double> sites =
        options.sampling == Mesh3Sampling::kLattice && !graded
            ? lattice_sites(domain, extractor, options.nb_vertices, options.seed)
            : random_points3(
                  domain, options.nb_vertices, options.seed,
                  user_density.is_constant()
                      ? clip.density
                      : Density3::function([&user_density](double x, double y, double z) {
                          return std::pow(user_density.callback(x, y, z), 0.6);
                        }));

    // 3. Unconstrained CVT.
    next_phase(Mesh3Phase::kUnconstrained);
    Cvt3Options cvt;
    cvt.method = CvtMethod::kLbfgs;
    cvt.max_iterations = options.unconstrained_iterations;
    cvt.gradient_tolerance = options.gradient_tolerance;
    cvt.clip = clip;
    cvt.progress = cvt_progress;
    std::vector<std::uint8_t> boundary;  // per site, from the CVT's last diagram
    cvt.boundary_sites = &boundary;
    result.unconstrained = optimize_cvt3(domain, sites, cvt);
    if (result.unconstrained.cancelled) throw Cancelled{};

    // 4. Classification and snapping.
    next_phase(Mesh3Phase::kSnapping);
    auto n = static_cast<std::uint32_t>(sites.size() / 3);
    std::vector<Kind> kinds(n, Kind::kFree);
    std::vector<std::uint32_t> line_of(n, SurfaceTree::kNone);
    std::vector<std::uint32_t> corner_vertex(n, SurfaceTree::kNone);  // kFixed: its corner
    {
      const Delaunay3 dt(sites.data(), n);
      // Corners. (The sites move only after the last query: dt reads them.)
      std::vector<double> added;
      std::vector<std::uint32_t> added_corner;
      for (const std::uint32_t c : lines.corners) {
        const double* p = domain.vertex(c);
        const std::uint32_t s = dt.nearest_vertex(p);
        if (kinds[s] != Kind::kFixed) {
          kinds[s] = Kind::kFixed;
          corner_vertex[s] = c;
        } else {
          added.insert(added.end(), p, p + 3);
          added_corner.push_back(c);
        }
      }
      // Feature lines: the sites whose cells hold points along them.
      if (lines.nb_lines() > 0) {
        // Samples every eighth of the local spacing along each line, and its end.
        std::vector<std::uint64_t> claims;  // (site, line) per sample
        std::uint32_t hint = Delaunay3::kNoTet;
        for (std::uint32_t l = 0; l < lines.nb_lines(); ++l) {
          const double length = line_tree.length(l);
          double arclength = 0;
          for (bool last = false; !last;) {
            last = arclength >= length;
            double x[3];
            line_tree.eval(l, std::min(arclength, length), x);
            const std::uint32_t s = dt.nearest_vertex(x, hint);
            hint = dt.vertex_tet(s);
            if (kinds[s] != Kind::kFixed) claims.push_back(std::uint64_t{s} << 32 | l);
            arclength += 0.125 * local_spacing(x);
          }
        }
        std::sort(claims.begin(), claims.end());
        for (std::size_t i = 0; i < claims.size();) {
          const auto s = static_cast<std::uint32_t>(claims[i] >> 32);
          std::uint32_t best_line = 0, best_count = 0;
          std::size_t j = i;
          while (j < claims.size() && (claims[j] >> 32) == s) {
            std::size_t k = j;
            while (k < claims.size() && claims[k] == claims[j]) ++k;
            if (k - j > best_count) {
              best_count = static_cast<std::uint32_t>(k - j);
              best_line = static_cast<std::uint32_t>(claims[j] & 0xffffffffu);
            }
            j = k;
          }
          kinds[s] = Kind::kCurve;
          line_of[s] = best_line;
          i = j;
        }
      }
      for (std::uint32_t s = 0; s < n; ++s) {
        if (kinds[s] == Kind::kFree && boundary[s] != 0) kinds[s] = Kind::kSurface;
      }
      for (std::uint32_t v = 0; v < n; ++v) {
        if (corner_vertex[v] != SurfaceTree::kNone) {
          std::copy_n(domain.vertex(corner_vertex[v]), 3, &sites[3 * std::size_t{v}]);
        }
      }
      // Corners without a site of their own get a new one.
      sites.insert(sites.end(), added.begin(), added.end());
      const auto extra = static_cast<std::uint32_t>(added.size() / 3);
      kinds.insert(kinds.end(), extra, Kind::kFixed);
      line_of.insert(line_of.end(), extra, SurfaceTree::kNone);
      corner_vertex.insert(corner_vertex.end(), added_corner.begin(), added_corner.end());
      n += extra;
    }
    const Projection project{&surface_tree, &line_tree, &line_of, smooth.get()};
    for (std::uint32_t s = 0; s < n; ++s) {
      if (kinds[s] == Kind::kSurface || kinds[s] == Kind::kCurve) {
        double q[3], d[3];
        project(s, kinds[s], &sites[3 * std::size_t{s}], q, d);
        std::copy_n(q, 3, &sites[3 * std::size_t{s}]);
      }
      result.nb_boundary_sites += kinds[s] == Kind::kSurface ? 1 : 0;
      result.nb_feature_sites += kinds[s] == Kind::kCurve ? 1 : 0;
      result.nb_corner_sites += kinds[s] == Kind::kFixed ? 1 : 0;
    }
    result.nb_sites = n;

    // 5. Constrained CVT, in up to three stages (two thirds of the iterations, then the
    // rest, then a few more): after a stage, free sites whose cells now reach the boundary
    // (the boundary layer settles after the snapping) are snapped to the surface too, or
    // they would become boundary vertices inside the volume.
    next_phase(Mesh3Phase::kConstrained);
    cvt.project = project;
    // Free sites whose cells reach the boundary in the CVT's last diagram go onto the
    // surface (they would become boundary vertices inside the volume); their number.
    const auto snap_boundary_free_sites = [&]() {
      std::uint32_t snapped = 0;
      for (std::uint32_t v = 0; v < n; ++v) {
        if (kinds[v] != Kind::kFree || boundary[v] == 0) continue;
        kinds[v] = Kind::kSurface;
        double q[3], d[3];
        project(v, kinds[v], &sites[3 * std::size_t{v}], q, d);
        std::copy_n(q, 3, &sites[3 * std::size_t{v}]);
        ++snapped;
      }
      result.nb_boundary_sites += snapped;
      return snapped;
    };
    const std::uint32_t total = options.constrained_iterations;
    const std::uint32_t stages[3] = {total - total / 3, std::max<std::uint32_t>(total / 3, 1), 5};
    for (int stage = 0; stage < 3; ++stage) {
      cvt.max_iterations = stages[stage];
      cvt.constraints = kinds;
      const CvtResult r = optimize_cvt3(domain, sites, cvt);
      if (r.cancelled) throw Cancelled{};
      if (stage == 0) {
        result.constrained = r;
      } else {
        result.constrained.iterations += r.iterations;
        result.constrained.evaluations += r.evaluations;
        result.constrained.energy = r.energy;
        result.constrained.gradient_norm = r.gradient_norm;
        result.constrained.seconds += r.seconds;
        result.constrained.converged = r.converged;
      }
      if (stage == 2) break;
      if (snap_boundary_free_sites() == 0) break;
    }

    // 5b. Topology: sites where the restricted Voronoi diagram lacks the closed-ball
    // property (closed_ball_defects), round after round with no CVT in between (the
    // farthest-point refinement, which converges), then a short constrained CVT to spread
    // them, checked again; the last state without defects is the one meshed (a CVT that
    // breaks the property is undone when more rounds cannot repair it).
    next_phase(Mesh3Phase::kTopology);
    {
      Clip3Options with_surface = clip;
      with_surface.keep_surface = true;
      cvt.max_iterations = options.topology_iterations;
      std::vector<double> first_points;  // where the first round found defects
      // Edges where the normals differ by more than 90 degrees (closed_ball_defects).
      std::vector<std::uint64_t> knife_edges;
      {
        const FeatureLines knives = extract_feature_lines(surface, 90.0);
        for (std::uint32_t l = 0; l < knives.nb_lines(); ++l) {
          for (std::uint32_t i = knives.line_begin[l]; i + 1 < knives.line_begin[l + 1]; ++i) {
            knife_edges.push_back(edge_key(knives.line_vertices[i], knives.line_vertices[i + 1]));
          }
        }
        std::sort(knife_edges.begin(), knife_edges.end());
        knife_edges.erase(std::unique(knife_edges.begin(), knife_edges.end()), knife_edges.end());
      }
      struct State {
        std::vector<double> sites;
        std::vector<Kind> kinds;
        std::vector<std::uint32_t> line_of, corner_vertex;
        std::uint32_t n = 0, nb_topology_sites = 0, nb_boundary_sites = 0;
      };
      // The state with the fewest defects so far (the latest one without any): refinement
      // near a sharp crease can feed itself (a site near a crease of dihedral angle below
      // 90 degrees has a cell reaching across it, which the next site splits), so after
      // max_topology_stall rounds without a better state the loop stops and meshes that one;
      // check_mesh3_shape then decides whether the output is right.
      State best;
      std::uint32_t best_defects = std::numeric_limits<std::uint32_t>::max(), stall = 0;
      bool inserted_since_cvt = false;
      std::uint32_t cycles = 0;
      for (std::uint32_t round = 0;; ++round) {
        ClippedVoronoi3 cv;
        cv.compute(domain, sites.data(), n, with_surface);
        const ClosedBallDefects defects = closed_ball_defects(cv, sites.data(), knife_edges);
        const auto nb_defects = static_cast<std::uint32_t>(defects.cells.size());
        if (round == 0) first_points = defects.points;
        Mesh3Progress p;
        p.iteration = round;
        p.topology_round = true;
        p.defects = nb_defects;
        p.added_sites = result.nb_topology_sites;
        report(p);
        if (nb_defects < best_defects || nb_defects == 0) {
          best = {sites,
                  kinds,
                  line_of,
                  corner_vertex,
                  n,
                  result.nb_topology_sites,
                  result.nb_boundary_sites};
          best_defects = nb_defects;
          stall = 0;
        } else if (++stall == options.max_topology_stall) {
          break;
        }
        if (nb_defects == 0) {
          if (!inserted_since_cvt || options.topology_iterations == 0 ||
              cycles == options.topology_cycles) {
            break;
          }
          // Spread the sites just added: a short constrained CVT; free sites whose cells
          // now reach the surface go onto it (as after step 5).
          cvt.constraints = kinds;
          const CvtResult r = optimize_cvt3(domain, sites, cvt);
          if (r.cancelled) throw Cancelled{};
          snap_boundary_free_sites();
          ++cycles;
          inserted_since_cvt = false;
          continue;
        }
        if (round == options.max_topology_rounds) break;
        // A site at each bad cell's farthest point, each point once (two bad cells can
        // share it), projected onto the surface.
        std::vector<std::array<double, 3>> points;
        for (std::size_t k = 0; k < defects.cells.size(); ++k) {
          points.push_back(
              {defects.points[3 * k], defects.points[3 * k + 1], defects.points[3 * k + 2]});
        }
        std::sort(points.begin(), points.end());
        points.erase(std::unique(points.begin(), points.end()), points.end());
        for (const std::array<double, 3>& x : points) {
          double q[3], d[3];
          project(n, Kind::kSurface, x.data(), q, d);
          sites.insert(sites.end(), q, q + 3);
          kinds.push_back(Kind::kSurface);
          line_of.push_back(SurfaceTree::kNone);
          corner_vertex.push_back(SurfaceTree::kNone);
          ++n;
          ++result.nb_topology_sites;
          ++result.nb_boundary_sites;
        }
        result.topology_rounds = round + 1;
        inserted_since_cvt = true;
      }
      sites = std::move(best.sites);
      kinds = std::move(best.kinds);
      line_of = std::move(best.line_of);
      corner_vertex = std::move(best.corner_vertex);
      n = best.n;
      result.nb_topology_sites = best.nb_topology_sites;
      result.nb_boundary_sites = best.nb_boundary_sites;
      result.topology_defects_left = best_defects;
      result.nb_sites = n;
      if (options.vertex_count == Mesh3Options::VertexCount::kExact &&
          result.nb_topology_sites > 0) {
        throw Error("mesh3d: " + std::to_string(options.nb_vertices) +
                    " vertices do not resolve the surface of " + domain.source() +
                    ": the restricted Voronoi cells of the sites near (" +
                    detail_number(first_points[0]) + ", " + detail_number(first_points[1]) + ", " +
                    detail_number(first_points[2]) + ") and " +
                    std::to_string(first_points.size() / 3 - 1) +
                    " other places are not disks meeting along single arcs; about " +
                    std::to_string(options.nb_vertices + result.nb_topology_sites) +
                    " vertices would (or let mesh3d add the sites it needs)");
      }
    }

    // 6. Extraction; 7. slivers (the perturbation extracts as it goes and returns the
    // final mesh).
    next_phase(Mesh3Phase::kExtraction);
    std::vector<std::uint32_t> tets;
    const SurfacePatches patches = site_patches(domain, lines, surface_tree, line_tree, sites,
                                                kinds, line_of, corner_vertex, triangle_patch);
    // The caller's extraction settings (options.perturbation.extraction), with the surface
    // patches of these sites.
    Extract3Options eo = options.perturbation.extraction;
    eo.surface = &patches;
    if (options.perturb) {
      next_phase(Mesh3Phase::kSlivers);
      Perturb3Options po = options.perturbation;
      po.extraction = eo;
      const auto user = po.progress;
      po.progress = [&](std::uint32_t round, std::uint32_t slivers, double worst) {
        Mesh3Progress p;
        p.iteration = round;
        p.slivers = slivers;
        p.min_dihedral_deg = worst;
        return notify(p) && (!user || user(round, slivers, worst));
      };
      // A surface site moves within its own patch: across a feature line its patch (the
      // crease rule of the extraction) would be stale, and the line could be cut. A
      // candidate that projects onto another patch stays where the site is (the wave's moves
      // are written after its candidates are scored, so sites[s] is the current position).
      const SiteProjector3 on_own_patch = [&](std::uint32_t s, Kind k, const double* p, double* q,
                                              double* d) {
        project(s, k, p, q, d);
        if (k != Kind::kSurface || patches.begin[s] == patches.begin[s + 1]) return;
        if (triangle_patch[surface_tree.closest(q).triangle] != patches.patches[patches.begin[s]])
          project(s, k, &sites[3 * std::size_t{s}], q, d);
      };
      result.perturbation =
          perturb_slivers3(extractor, sites, kinds, on_own_patch, po, &tets, &result.extraction);
      if (result.perturbation.cancelled) throw Cancelled{};
    } else {
      const Delaunay3 dt(sites.data(), n);
      tets = extractor.extract(dt, eo, &result.extraction);
    }

    // 8. Output: the used sites, renumbered in site order.
    next_phase(Mesh3Phase::kQuality);
    std::vector<std::uint32_t> index(n, SurfaceTree::kNone);
    for (const std::uint32_t v : tets) index[v] = 0;
    std::uint32_t nv = 0;
    for (std::uint32_t s = 0; s < n; ++s) {
      if (index[s] == SurfaceTree::kNone) {
        ++result.nb_dropped_sites;
        continue;
      }
      index[s] = nv++;
      result.xyz.insert(result.xyz.end(), &sites[3 * std::size_t{s}],
                        &sites[3 * std::size_t{s}] + 3);
      result.kinds.push_back(kinds[s] == Kind::kSurface ? Mesh3VertexKind::kSurface
                             : kinds[s] == Kind::kCurve ? Mesh3VertexKind::kFeature
                             : kinds[s] == Kind::kFixed ? Mesh3VertexKind::kCorner
                                                        : Mesh3VertexKind::kInterior);
    }
    result.tets.resize(tets.size());
    for (std::size_t i = 0; i < tets.size(); ++i) result.tets[i] = index[tets[i]];

    // Boundary triangles and tags: patches (the input's triangle tags, else the patches
    // between feature lines, from 1) and regions (the input's tet tags, else one per volume
    // component).
    {
      std::vector<std::uint32_t> face_tet;
      mesh3::boundary_triangles(result.tets, result.boundary_triangles, face_tet);
      const std::size_t nb = face_tet.size();
      std::vector<std::uint32_t> closest(nb);
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nb, 256), [&](const auto& range) {
        for (std::size_t b = range.begin(); b != range.end(); ++b) {
          double c[3] = {0, 0, 0};
          for (int k = 0; k < 3; ++k) {
            const double* p =
                &result
                     .xyz[3 * std::size_t{
                                  result.boundary_triangles[3 * b + static_cast<std::size_t>(k)]}];
            for (int q = 0; q < 3; ++q) c[q] += p[q] / 3;
          }
          closest[b] = surface_tree.closest(c).triangle;
        }
      });
      std::vector<std::uint32_t> vertex_patch_begin{0}, vertex_patch;
      for (std::uint32_t s = 0; s < n; ++s) {
        if (index[s] == SurfaceTree::kNone) continue;
        vertex_patch.insert(vertex_patch.end(), patches.patches.begin() + patches.begin[s],
                            patches.patches.begin() + patches.begin[std::size_t{s} + 1]);
        vertex_patch_begin.push_back(static_cast<std::uint32_t>(vertex_patch.size()));
      }
      const std::uint32_t nb_patches =
          triangle_patch.empty()
              ? 0
              : 1 + *std::max_element(triangle_patch.begin(), triangle_patch.end());
      std::vector<std::int32_t> patch_tag(nb_patches, 0);
      for (std::uint32_t p = 0; p < nb_patches; ++p)
        patch_tag[p] = static_cast<std::int32_t>(p + 1);
      if (!input_tags.empty()) {
        for (std::size_t t = triangle_patch.size(); t-- > 0;)
          patch_tag[triangle_patch[t]] = input_tags[t];
      }
      result.boundary_tags = mesh3::patch_tags(result.boundary_triangles, vertex_patch_begin,
                                               vertex_patch, patch_tag, triangle_patch, closest);
      result.tet_tags = mesh3::region_tags(domain, result.xyz, result.tets, face_tet, closest);
      result.tag_names = domain.tag_names();
      // Triangles grouped by patch tag (stable: (tet, facet) order within a patch), so that
      // a file has one block per patch rather than one per run of the tet order.
      std::vector<std::uint32_t> order(result.boundary_tags.size());
      std::iota(order.begin(), order.end(), 0u);
      std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
        return result.boundary_tags[a] < result.boundary_tags[b];
      });
      std::vector<std::uint32_t> triangles(result.boundary_triangles.size());
      std::vector<std::int32_t> tags(order.size());
      for (std::size_t i = 0; i < order.size(); ++i) {
        std::copy_n(&result.boundary_triangles[3 * std::size_t{order[i]}], 3, &triangles[3 * i]);
        tags[i] = result.boundary_tags[order[i]];
      }
      result.boundary_triangles = std::move(triangles);
      result.boundary_tags = std::move(tags);
    }
    result.quality = tet_quality(result.xyz.data(), nv, result.tets.data(), result.nb_tets());
    result.shape_problem = check_mesh3_shape(domain, result.xyz, result.tets);
    result.seconds[static_cast<int>(phase)] += since(t_phase);
  } catch (const Cancelled&) {
    result.cancelled = true;
    result.xyz.clear();
    result.kinds.clear();
    result.tets.clear();
  }
  result.total_seconds = since(t_start);
  return result;
}

}  // namespace voroclip
