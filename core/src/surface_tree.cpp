// SurfaceTree: closest points on a triangle surface (a bounding-volume hierarchy, bvh.h)
// with pseudo-normals (Baerentzen and Aanaes, "Signed distance computation using the angle
// weighted pseudonormal", IEEE TVCG 2005) at the closest point.
//
// Point-triangle distance: the closest point lies in one of seven regions of the
// triangle's plane — a corner, an edge, the interior — told apart by the signs of dot
// products of the query's offsets with the edge vectors (each region is the set where the
// corresponding Karush-Kuhn-Tucker conditions hold), so that the interior is reached only
// when the projection is inside. Where the triangle has zero area the interior region
// does not exist and the answer is the nearest of its three edges.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "bvh.h"
#include "voroclip/core.h"

namespace voroclip {

namespace {

inline void sub(const double* a, const double* b, double* out) {
  out[0] = a[0] - b[0];
  out[1] = a[1] - b[1];
  out[2] = a[2] - b[2];
}
inline double dot(const double* a, const double* b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
inline void cross(const double* a, const double* b, double* out) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}
inline void normalize(double* v) {
  const double len = std::sqrt(dot(v, v));
  for (int k = 0; k < 3; ++k) v[k] = len > 0 ? v[k] / len : 0.0;
}

// The closest point of segment [a, b] to p, its parameter in [0, 1] and squared distance.
double closest_on_segment(const double* p, const double* a, const double* b, double* out,
                          double& t) {
  double ab[3], ap[3];
  sub(b, a, ab);
  sub(p, a, ap);
  const double len2 = dot(ab, ab);
  t = len2 > 0 ? std::clamp(dot(ap, ab) / len2, 0.0, 1.0) : 0.0;
  for (int k = 0; k < 3; ++k) out[k] = a[k] + t * ab[k];
  double d[3];
  sub(p, out, d);
  return dot(d, d);
}

struct TrianglePoint {
  double point[3];
  double d2;
  SurfaceTree::Feature feature;
  std::uint8_t index;
};

// Edge e of a triangle is opposite corner e: from corner e + 1 to corner e + 2.
TrianglePoint on_edge(const double* p, const double* const c[3], int e) {
  TrianglePoint r{};
  double t = 0;
  const double* a = c[(e + 1) % 3];
  const double* b = c[(e + 2) % 3];
  r.d2 = closest_on_segment(p, a, b, r.point, t);
  if (t <= 0 || t >= 1) {
    const int corner = t <= 0 ? (e + 1) % 3 : (e + 2) % 3;
    for (int k = 0; k < 3; ++k) r.point[k] = c[corner][k];
    r.feature = SurfaceTree::Feature::kVertex;
    r.index = static_cast<std::uint8_t>(corner);
  } else {
    r.feature = SurfaceTree::Feature::kEdge;
    r.index = static_cast<std::uint8_t>(e);
  }
  return r;
}

TrianglePoint corner_point(const double* p, const double* v, int corner) {
  TrianglePoint r{};
  double d[3];
  sub(p, v, d);
  r.d2 = dot(d, d);
  for (int k = 0; k < 3; ++k) r.point[k] = v[k];
  r.feature = SurfaceTree::Feature::kVertex;
  r.index = static_cast<std::uint8_t>(corner);
  return r;
}

TrianglePoint closest_on_triangle(const double* p, const double* a, const double* b,
                                  const double* c) {
  const double* const corners[3] = {a, b, c};
  double ab[3], ac[3], ap[3];
  sub(b, a, ab);
  sub(c, a, ac);
  sub(p, a, ap);
  double n[3];
  cross(ab, ac, n);
  if (dot(n, n) == 0) {
    TrianglePoint best = on_edge(p, corners, 0);
    for (int e = 1; e < 3; ++e) {
      const TrianglePoint r = on_edge(p, corners, e);
      if (r.d2 < best.d2) best = r;
    }
    return best;
  }
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return corner_point(p, a, 0);
  double bp[3];
  sub(p, b, bp);
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return corner_point(p, b, 1);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return on_edge(p, corners, 2);  // edge ab
  double cp[3];
  sub(p, c, cp);
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return corner_point(p, c, 2);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return on_edge(p, corners, 1);  // edge ca
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return on_edge(p, corners, 0);  // edge bc
  const double sum = va + vb + vc;
  if (!(sum > 0)) {
    // Rounding put the point in no region of a nearly flat triangle: its edges decide.
    TrianglePoint best = on_edge(p, corners, 0);
    for (int e = 1; e < 3; ++e) {
      const TrianglePoint r = on_edge(p, corners, e);
      if (r.d2 < best.d2) best = r;
    }
    return best;
  }
  const double v = vb / sum, w = vc / sum;
  TrianglePoint r{};
  for (int k = 0; k < 3; ++k) r.point[k] = a[k] + v * ab[k] + w * ac[k];
  double d[3];
  sub(p, r.point, d);
  r.d2 = dot(d, d);
  r.feature = SurfaceTree::Feature::kFace;
  r.index = 0;
  return r;
}

}  // namespace

SurfaceTree::SurfaceTree(const TriangleSurface& surface) {
  const std::uint32_t nt = surface.nb_triangles();
  const std::uint32_t nv = surface.nb_vertices();
  if (surface.triangles.size() != 3 * std::size_t{nt}) {
    throw Error(surface.source + ": triangle array size is not a multiple of 3");
  }
  for (std::size_t i = 0; i < surface.triangles.size(); ++i) {
    if (surface.triangles[i] >= nv) {
      throw Error(surface.source + ": triangle " + std::to_string(i / 3) + " has vertex " +
                  std::to_string(surface.triangles[i]) + ", the surface has " + std::to_string(nv) +
                  " vertices (numbered from 0)");
    }
    const double* v = &surface.xyz[3 * std::size_t{surface.triangles[i]}];
    if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
      throw Error(surface.source + ": vertex " + std::to_string(surface.triangles[i]) +
                  " (from 0) has a non-finite coordinate");
    }
  }
  triangles_ = surface.triangles;
  face_normal_.assign(3 * std::size_t{nt}, 0.0);
  vertex_normal_.assign(3 * std::size_t{nv}, 0.0);
  edge_normal_.assign(9 * std::size_t{nt}, 0.0);
  if (nt == 0) return;
  const auto vertex = [&](std::uint32_t t, int k) {
    return &surface
                .xyz[3 * std::size_t{triangles_[3 * std::size_t{t} + static_cast<std::size_t>(k)]}];
  };
  // Face normals, then angle-weighted vertex normals.
  for (std::uint32_t t = 0; t < nt; ++t) {
    double u[3], w[3];
    sub(vertex(t, 1), vertex(t, 0), u);
    sub(vertex(t, 2), vertex(t, 0), w);
    double* n = &face_normal_[3 * std::size_t{t}];
    cross(u, w, n);
    normalize(n);
    for (int k = 0; k < 3; ++k) {
      double e1[3], e2[3];
      sub(vertex(t, (k + 1) % 3), vertex(t, k), e1);
      sub(vertex(t, (k + 2) % 3), vertex(t, k), e2);
      double x[3];
      cross(e1, e2, x);
      const double angle = std::atan2(std::sqrt(dot(x, x)), dot(e1, e2));
      double* vn =
          &vertex_normal_[3 * std::size_t{
                                  triangles_[3 * std::size_t{t} + static_cast<std::size_t>(k)]}];
      for (int c = 0; c < 3; ++c) vn[c] += angle * n[c];
    }
  }
  for (std::uint32_t v = 0; v < nv; ++v) normalize(&vertex_normal_[3 * std::size_t{v}]);
  // Edge normals: the sum of the normals of the triangles sharing the edge.
  struct EdgeRef {
    std::uint32_t lo, hi, slot;  // slot = 3 t + e
  };
  std::vector<EdgeRef> edges(3 * std::size_t{nt});
  for (std::uint32_t t = 0; t < nt; ++t) {
    for (std::uint32_t e = 0; e < 3; ++e) {
      const std::uint32_t a = triangles_[3 * std::size_t{t} + (e + 1) % 3];
      const std::uint32_t b = triangles_[3 * std::size_t{t} + (e + 2) % 3];
      edges[3 * std::size_t{t} + e] = {std::min(a, b), std::max(a, b), 3 * t + e};
    }
  }
  std::sort(edges.begin(), edges.end(), [](const EdgeRef& x, const EdgeRef& y) {
    return x.lo != y.lo ? x.lo < y.lo : x.hi != y.hi ? x.hi < y.hi : x.slot < y.slot;
  });
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    double sum[3] = {0, 0, 0};
    for (; j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi; ++j) {
      const double* n = &face_normal_[3 * std::size_t{edges[j].slot / 3}];
      for (int c = 0; c < 3; ++c) sum[c] += n[c];
    }
    normalize(sum);
    for (std::size_t k = i; k < j; ++k) {
      double* en = &edge_normal_[3 * std::size_t{edges[k].slot}];
      for (int c = 0; c < 3; ++c) en[c] = sum[c];
    }
    i = j;
  }
  // The hierarchy, and the corners in leaf order.
  std::vector<double> box(6 * std::size_t{nt});
  for (std::uint32_t t = 0; t < nt; ++t) {
    for (int c = 0; c < 3; ++c) {
      const double x0 = vertex(t, 0)[c], x1 = vertex(t, 1)[c], x2 = vertex(t, 2)[c];
      box[6 * std::size_t{t} + static_cast<std::size_t>(c)] = std::min({x0, x1, x2});
      box[6 * std::size_t{t} + 3 + static_cast<std::size_t>(c)] = std::max({x0, x1, x2});
    }
  }
  detail::build_bvh(box, nt, nodes_, leaf_triangle_, 0);
  leaf_of_.resize(nt);
  corners_.resize(9 * std::size_t{nt});
  for (std::uint32_t i = 0; i < nt; ++i) {
    const std::uint32_t t = leaf_triangle_[i];
    leaf_of_[t] = i;
    for (int k = 0; k < 3; ++k) {
      for (int c = 0; c < 3; ++c) {
        corners_[9 * std::size_t{i} + 3 * static_cast<std::size_t>(k) +
                 static_cast<std::size_t>(c)] = vertex(t, k)[c];
      }
    }
  }
  for (std::uint32_t t = 0; t < nt; ++t) {
    for (int c = 0; c < 3; ++c) {
      const double lo = box[6 * std::size_t{t} + static_cast<std::size_t>(c)];
      const double hi = box[6 * std::size_t{t} + 3 + static_cast<std::size_t>(c)];
      bbox_[c] = t == 0 ? lo : std::min(bbox_[c], lo);
      bbox_[3 + c] = t == 0 ? hi : std::max(bbox_[3 + c], hi);
    }
  }
}

SurfaceTree::Closest SurfaceTree::closest(const double* p, std::uint32_t hint) const {
  Closest best;
  if (nodes_.empty()) return best;
  double best2 = std::numeric_limits<double>::infinity();
  std::uint32_t best_leaf = kNone;
  TrianglePoint best_point{};
  const auto consider = [&](std::uint32_t i) {
    const double* c = &corners_[9 * std::size_t{i}];
    const TrianglePoint r = closest_on_triangle(p, c, c + 3, c + 6);
    if (best_leaf == kNone || r.d2 < best2 ||
        (r.d2 == best2 && leaf_triangle_[i] < leaf_triangle_[best_leaf])) {
      best2 = r.d2;
      best_leaf = i;
      best_point = r;
    }
  };
  if (hint < leaf_of_.size()) consider(leaf_of_[hint]);
  detail::nearest_leaves(nodes_, 0, p, best2, [&](std::uint32_t first, std::uint32_t count) {
    for (std::uint32_t i = first; i < first + count; ++i) consider(i);
  });
  if (best_leaf == kNone || !(best2 < std::numeric_limits<double>::infinity())) return best;
  const std::uint32_t t = leaf_triangle_[best_leaf];
  for (int k = 0; k < 3; ++k) best.point[k] = best_point.point[k];
  best.distance2 = best_point.d2;
  best.triangle = t;
  best.feature = best_point.feature;
  best.index = best_point.index;
  const double* n = &face_normal_[3 * std::size_t{t}];
  if (best.feature == Feature::kEdge) {
    n = &edge_normal_[9 * std::size_t{t} + 3 * std::size_t{best.index}];
  } else if (best.feature == Feature::kVertex) {
    n = &vertex_normal_[3 * std::size_t{triangles_[3 * std::size_t{t} + best.index]}];
  }
  for (int k = 0; k < 3; ++k) best.normal[k] = n[k];
  return best;
}

}  // namespace voroclip
