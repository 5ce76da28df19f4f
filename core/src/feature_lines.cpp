// Sharp feature lines of a triangle surface (extract_feature_lines) and closest points on
// them (FeatureTree): what the 3D meshing pipeline needs to keep crisp edges and corners
// (Yan et al. 2011, sec. 5.2: feature sites move along feature lines, corners are fixed).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "bvh.h"
#include "voroclip/core.h"

namespace voroclip {

namespace {

void unit_normal(const TriangleSurface& s, std::size_t t, double n[3]) {
  const double* a = &s.xyz[3 * std::size_t{s.triangles[3 * t]}];
  const double* b = &s.xyz[3 * std::size_t{s.triangles[3 * t + 1]}];
  const double* c = &s.xyz[3 * std::size_t{s.triangles[3 * t + 2]}];
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  n[0] = u[1] * v[2] - u[2] * v[1];
  n[1] = u[2] * v[0] - u[0] * v[2];
  n[2] = u[0] * v[1] - u[1] * v[0];
  const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (int k = 0; k < 3; ++k) n[k] = len > 0 ? n[k] / len : 0.0;
}

}  // namespace

FeatureLines extract_feature_lines(const TriangleSurface& surface, double feature_angle_deg,
                                   const std::vector<std::int32_t>& triangle_tag) {
  if (!(feature_angle_deg >= 0 && feature_angle_deg <= 180)) {
    throw Error("feature angle " + std::to_string(feature_angle_deg) +
                " degrees: expected a value in [0, 180]");
  }
  const std::size_t nt = surface.nb_triangles();
  if (!triangle_tag.empty() && triangle_tag.size() != nt) {
    throw Error(surface.source + ": " + count_of(triangle_tag.size(), "triangle tag") + " for " +
                count_of(nt, "triangle"));
  }
  const std::uint32_t nv = surface.nb_vertices();
  for (const std::uint32_t v : surface.triangles) {
    if (v >= nv) throw Error(surface.source + ": a triangle has a vertex index out of range");
  }
  // Undirected edges with their triangles, grouped by sorting.
  struct EdgeRef {
    std::uint32_t lo, hi, t;
  };
  std::vector<EdgeRef> refs(3 * nt);
  for (std::size_t t = 0; t < nt; ++t) {
    for (std::size_t e = 0; e < 3; ++e) {
      const std::uint32_t a = surface.triangles[3 * t + (e + 1) % 3];
      const std::uint32_t b = surface.triangles[3 * t + (e + 2) % 3];
      refs[3 * t + e] = {std::min(a, b), std::max(a, b), static_cast<std::uint32_t>(t)};
    }
  }
  std::sort(refs.begin(), refs.end(), [](const EdgeRef& x, const EdgeRef& y) {
    return x.lo != y.lo ? x.lo < y.lo : x.hi != y.hi ? x.hi < y.hi : x.t < y.t;
  });
  const double cos_limit = std::cos(feature_angle_deg * (3.14159265358979323846 / 180.0));
  std::vector<std::uint32_t> feature_edges;  // 2 per edge (lo, hi)
  for (std::size_t i = 0; i < refs.size();) {
    std::size_t j = i;
    while (j < refs.size() && refs[j].lo == refs[i].lo && refs[j].hi == refs[i].hi) ++j;
    bool sharp = j - i != 2;
    if (!sharp && refs[i].lo != refs[i].hi) {
      double n1[3], n2[3];
      unit_normal(surface, refs[i].t, n1);
      unit_normal(surface, refs[i + 1].t, n2);
      const bool both =
          (n1[0] != 0 || n1[1] != 0 || n1[2] != 0) && (n2[0] != 0 || n2[1] != 0 || n2[2] != 0);
      sharp = both && n1[0] * n2[0] + n1[1] * n2[1] + n1[2] * n2[2] < cos_limit;
      if (!triangle_tag.empty() && triangle_tag[refs[i].t] != triangle_tag[refs[i + 1].t]) {
        sharp = true;
      }
    }
    if (refs[i].lo == refs[i].hi) sharp = false;  // an edge of a triangle with a repeated vertex
    if (sharp) {
      feature_edges.push_back(refs[i].lo);
      feature_edges.push_back(refs[i].hi);
    }
    i = j;
  }
  FeatureLines out;
  const std::size_t ne = feature_edges.size() / 2;
  out.nb_feature_edges = static_cast<std::uint32_t>(ne);
  // Incidence lists, each sorted by the other vertex (the edges are sorted by (lo, hi)).
  std::vector<std::uint32_t> begin(std::size_t{nv} + 1, 0);
  for (const std::uint32_t v : feature_edges) ++begin[std::size_t{v} + 1];
  for (std::size_t v = 0; v < nv; ++v) begin[v + 1] += begin[v];
  std::vector<std::uint32_t> incident(2 * ne), fill(begin.begin(), begin.end() - 1);
  for (std::uint32_t e = 0; e < ne; ++e) {
    incident[fill[feature_edges[2 * std::size_t{e}]]++] = e;
    incident[fill[feature_edges[2 * std::size_t{e} + 1]]++] = e;
  }
  const auto other = [&](std::uint32_t e, std::uint32_t v) {
    return feature_edges[2 * std::size_t{e}] == v ? feature_edges[2 * std::size_t{e} + 1]
                                                  : feature_edges[2 * std::size_t{e}];
  };
  for (std::uint32_t v = 0; v < nv; ++v) {
    std::sort(incident.begin() + begin[v], incident.begin() + begin[v + 1],
              [&](std::uint32_t a, std::uint32_t b) { return other(a, v) < other(b, v); });
  }
  const auto degree = [&](std::uint32_t v) { return begin[std::size_t{v} + 1] - begin[v]; };
  for (std::uint32_t v = 0; v < nv; ++v) {
    if (degree(v) != 0 && degree(v) != 2) out.corners.push_back(v);
  }
  std::vector<std::uint8_t> used(ne, 0);
  // Walks from v along edge e until a corner, or back to `stop` (a loop).
  const auto walk = [&](std::uint32_t v, std::uint32_t e, bool loop) {
    const std::uint32_t start = v;
    out.line_vertices.push_back(v);
    for (;;) {
      used[e] = 1;
      v = other(e, v);
      out.line_vertices.push_back(v);
      if (degree(v) != 2 || (loop && v == start)) break;
      const std::uint32_t a = incident[begin[v]], b = incident[begin[v] + 1];
      e = a == e ? b : a;
      if (used[e]) break;
    }
    out.line_begin.push_back(static_cast<std::uint32_t>(out.line_vertices.size()));
    out.line_closed.push_back(loop ? 1 : 0);
  };
  for (const std::uint32_t c : out.corners) {
    for (std::uint32_t k = begin[c]; k < begin[std::size_t{c} + 1]; ++k) {
      if (!used[incident[k]]) walk(c, incident[k], false);
    }
  }
  for (std::uint32_t v = 0; v < nv; ++v) {
    if (degree(v) == 2 && !used[incident[begin[v]]]) walk(v, incident[begin[v]], true);
  }
  return out;
}

FeatureTree::FeatureTree(const TriangleSurface& surface, const FeatureLines& lines) {
  const std::uint32_t nl = lines.nb_lines();
  closed_ = lines.line_closed;
  std::vector<double> box;
  std::vector<std::uint32_t> order;
  for (std::uint32_t l = 0; l < nl; ++l) {
    const std::uint32_t b = lines.line_begin[l], e = lines.line_begin[l + 1];
    if (e < b + 2) throw Error("feature line " + std::to_string(l) + " has fewer than 2 vertices");
    const auto first = static_cast<std::uint32_t>(arclength_.size());
    for (std::uint32_t i = b; i < e; ++i) {
      const std::uint32_t v = lines.line_vertices[i];
      if (v >= surface.nb_vertices()) {
        throw Error("feature line " + std::to_string(l) + ": vertex " + std::to_string(v) +
                    " is out of range (lines and vertices numbered from 0)");
      }
      const double* p = &surface.xyz[3 * std::size_t{v}];
      double s = 0;
      if (i > b) {
        const double* q = &points_[points_.size() - 3];
        s = arclength_.back() +
            std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                      (p[2] - q[2]) * (p[2] - q[2]));
      }
      points_.insert(points_.end(), p, p + 3);
      arclength_.push_back(s);
    }
    point_begin_.push_back(static_cast<std::uint32_t>(arclength_.size()));
    const std::uint32_t nseg = e - b - 1;
    box.assign(6 * std::size_t{nseg}, 0.0);
    for (std::uint32_t i = 0; i < nseg; ++i) {
      const double* p = &points_[3 * (std::size_t{first} + i)];
      for (int c = 0; c < 3; ++c) {
        box[6 * std::size_t{i} + static_cast<std::size_t>(c)] = std::min(p[c], p[c + 3]);
        box[6 * std::size_t{i} + 3 + static_cast<std::size_t>(c)] = std::max(p[c], p[c + 3]);
      }
    }
    const auto offset = static_cast<std::uint32_t>(segments_.size());
    line_node_.push_back(detail::build_bvh(box, nseg, nodes_, order, offset));
    for (const std::uint32_t i : order) segments_.push_back(first + i);
  }
}

FeatureTree::Closest FeatureTree::closest_on(const double* p, std::uint32_t line,
                                             double best2) const {
  Closest best;
  best.distance2 = best2;
  std::uint32_t best_seg = SurfaceTree::kNone;
  detail::nearest_leaves(nodes_, line_node_[line], p, best2,
                         [&](std::uint32_t first, std::uint32_t count) {
                           for (std::uint32_t i = first; i < first + count; ++i) {
                             const std::uint32_t g = segments_[i];
                             const double* a = &points_[3 * std::size_t{g}];
                             const double* b = a + 3;
                             double ab[3], ap[3];
                             for (int k = 0; k < 3; ++k) {
                               ab[k] = b[k] - a[k];
                               ap[k] = p[k] - a[k];
                             }
                             const double len2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
                             const double dt = ap[0] * ab[0] + ap[1] * ab[1] + ap[2] * ab[2];
                             const double t = len2 > 0 ? std::clamp(dt / len2, 0.0, 1.0) : 0.0;
                             double q[3], d2 = 0;
                             for (int k = 0; k < 3; ++k) {
                               q[k] = a[k] + t * ab[k];
                               d2 += (p[k] - q[k]) * (p[k] - q[k]);
                             }
                             if (d2 < best2 || (d2 == best2 && g < best_seg)) {
                               best2 = d2;
                               best_seg = g;
                               best.distance2 = d2;
                               best.t = t;
                               for (int k = 0; k < 3; ++k) best.point[k] = q[k];
                               const double len = std::sqrt(len2);
                               for (int k = 0; k < 3; ++k)
                                 best.tangent[k] = len > 0 ? ab[k] / len : 0.0;
                             }
                           }
                         });
  if (best_seg != SurfaceTree::kNone) {
    best.line = line;
    best.segment = best_seg - point_begin_[line];
    best.arclength =
        arclength_[best_seg] + best.t * (arclength_[best_seg + 1] - arclength_[best_seg]);
  }
  return best;
}

FeatureTree::Closest FeatureTree::closest(const double* p, std::uint32_t line) const {
  if (line >= nb_lines()) throw Error("feature line " + std::to_string(line) + " does not exist");
  return closest_on(p, line, std::numeric_limits<double>::infinity());
}

FeatureTree::Closest FeatureTree::closest(const double* p) const {
  Closest best;
  best.distance2 = std::numeric_limits<double>::infinity();
  for (std::uint32_t l = 0; l < nb_lines(); ++l) {
    const Node& root = nodes_[line_node_[l]];
    if (detail::box_distance2(root.lo, root.hi, p) >= best.distance2) continue;
    const Closest c = closest_on(p, l, best.distance2);
    // Strictly closer only: on a tie the lower line, visited first, stays.
    if (c.line != SurfaceTree::kNone && c.distance2 < best.distance2) best = c;
  }
  return best;
}

void FeatureTree::eval(std::uint32_t line, double s, double* xyz, double* tangent) const {
  if (line >= nb_lines()) throw Error("feature line " + std::to_string(line) + " does not exist");
  const std::uint32_t b = point_begin_[line], e = point_begin_[line + 1];
  const double len = arclength_[e - 1];
  if (closed(line) && len > 0) {
    s = std::fmod(s, len);
    if (s < 0) s += len;
  } else {
    s = std::clamp(s, 0.0, len);
  }
  // The segment [i, i + 1] with arclength_[i] <= s, the last one for s == len.
  const auto it = std::upper_bound(arclength_.begin() + b, arclength_.begin() + e, s);
  std::uint32_t i = static_cast<std::uint32_t>(it - arclength_.begin());
  i = std::clamp<std::uint32_t>(i == 0 ? 0 : i - 1, b, e - 2);
  const double* p = &points_[3 * std::size_t{i}];
  const double seg = arclength_[i + 1] - arclength_[i];
  const double t = seg > 0 ? std::clamp((s - arclength_[i]) / seg, 0.0, 1.0) : 0.0;
  for (int k = 0; k < 3; ++k) xyz[k] = p[k] + t * (p[k + 3] - p[k]);
  if (tangent != nullptr) {
    for (int k = 0; k < 3; ++k) tangent[k] = seg > 0 ? (p[k + 3] - p[k]) / seg : 0.0;
  }
}

}  // namespace voroclip
