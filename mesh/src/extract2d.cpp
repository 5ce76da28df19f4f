// Mesh extraction (Yan et al. 2011, sec. 5.1, last step) and the exact mesh checker.
//
// The paper keeps the primal Delaunay triangles whose circumcenter lies inside the domain.
// The circumcenter of Delaunay triangle (i, k, l) is the Voronoi vertex of the three sites;
// with the symbolic perturbation of the clipping predicates (predicates.h) it is never on
// the domain boundary, and its location is decided exactly by the crossing parity of a
// ray: the half-line of bisector(i, k) where site l is nearer than site i. A domain edge
// [a, b] crosses the bisector iff f_ik(a), f_ik(b) differ in sign (bisector_side_vertex2d,
// never zero), and the crossing is on the ray iff f_il there is positive
// (bisector_side_edge2d, never zero). The same perturbation decides the clipped diagram,
// so a triangle is kept exactly when its Voronoi vertex is a vertex of the clipped cells.
// Shortcut: a non-empty cell that does not meet the boundary lies inside the domain with
// all its Voronoi vertices, so a triangle with such a vertex is kept without the ray.
//
// The rule alone does not make a triangle lie in the domain (a triangle over a small hole
// or across a concave part can have its circumcenter inside), so every kept triangle T is
// then checked exactly: T is in the closed domain iff no domain edge meets the interior of
// T and the interior of T is inside. An edge [a, b] misses the open triangle iff a line
// separates them weakly, and for a segment and a triangle the candidates are the four
// lines of their edges (separating axes of the Minkowski difference): either a and b are
// on the closed outer side of one edge line of T, or the three vertices of T are on one
// closed side of line ab — all orient2d signs. When no edge meets the open triangle, it is
// entirely inside or entirely outside: a vertex strictly inside (exact locate) settles it;
// otherwise the rounded centroid, when it is strictly inside T (exact orient2d), is
// located; a triangle for which neither applies is dropped (never seen on CVT output).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <string>
#include <unordered_map>
#include <vector>

#include "edge_grid2.h"
#include "voroclip/mesh.h"

namespace voroclip {

namespace {

// True when segment [a, b] meets the interior of the counter-clockwise triangle t[0..2].
bool segment_meets_open_triangle(const double* a, const double* b, const double* const t[3]) {
  for (int e = 0; e < 3; ++e) {
    const double* u = t[e];
    const double* v = t[(e + 1) % 3];
    if (orient2d(u, v, a) != Sign::positive && orient2d(u, v, b) != Sign::positive) return false;
  }
  const Sign s0 = orient2d(a, b, t[0]), s1 = orient2d(a, b, t[1]), s2 = orient2d(a, b, t[2]);
  const bool any_pos = s0 == Sign::positive || s1 == Sign::positive || s2 == Sign::positive;
  const bool any_neg = s0 == Sign::negative || s1 == Sign::negative || s2 == Sign::negative;
  return any_pos && any_neg;
}

// True when the open triangles t and u (counter-clockwise) meet.
bool open_triangles_meet(const double* const t[3], const double* const u[3]) {
  for (int pass = 0; pass < 2; ++pass) {
    const double* const* p = pass == 0 ? t : u;
    const double* const* q = pass == 0 ? u : t;
    for (int e = 0; e < 3; ++e) {
      if (orient2d(p[e], p[(e + 1) % 3], q[0]) != Sign::positive &&
          orient2d(p[e], p[(e + 1) % 3], q[1]) != Sign::positive &&
          orient2d(p[e], p[(e + 1) % 3], q[2]) != Sign::positive) {
        return false;
      }
    }
  }
  return true;
}

enum class Containment : std::uint8_t { kInside, kCrossed, kOutside, kUndecided };

// Whether the closed triangle t (counter-clockwise, non-degenerate) lies in the closed
// domain. `vertex_location`: exact locate of each vertex (POSITIVE inside).
Containment triangle_containment(const Domain2& domain, const mesh2d::EdgeGrid2& grid,
                                 const double* const t[3], const Sign location[3]) {
  double lo[2] = {std::min({t[0][0], t[1][0], t[2][0]}), std::min({t[0][1], t[1][1], t[2][1]})};
  double hi[2] = {std::max({t[0][0], t[1][0], t[2][0]}), std::max({t[0][1], t[1][1], t[2][1]})};
  bool crossed = false;
  grid.for_each_in_box(lo, hi, [&](std::uint32_t e) {
    if (crossed) return;
    if (segment_meets_open_triangle(domain.vertex(e), domain.vertex(domain.next(e)), t)) {
      crossed = true;
    }
  });
  if (crossed) return Containment::kCrossed;
  for (int k = 0; k < 3; ++k) {
    if (location[k] == Sign::positive) return Containment::kInside;
    if (location[k] == Sign::negative) return Containment::kOutside;
  }
  const double c[2] = {(t[0][0] + t[1][0] + t[2][0]) / 3, (t[0][1] + t[1][1] + t[2][1]) / 3};
  for (int e = 0; e < 3; ++e) {
    if (orient2d(t[e], t[(e + 1) % 3], c) != Sign::positive) return Containment::kUndecided;
  }
  const Sign s = domain.locate(c);
  return s == Sign::positive ? Containment::kInside : Containment::kOutside;
}

}  // namespace

Sign circumcenter_location2(const Domain2& domain, const Delaunay2& dt, std::uint32_t triangle) {
  const std::uint32_t i = dt.tri_vertex(triangle, 0);
  const std::uint32_t k = dt.tri_vertex(triangle, 1);
  const std::uint32_t l = dt.tri_vertex(triangle, 2);
  const double* pi = dt.point(i);
  const double* pk = dt.point(k);
  const double* pl = dt.point(l);
  bool inside = false;
  for (std::uint32_t r = 0; r < domain.nb_rings(); ++r) {
    const std::uint32_t begin = domain.ring_begin(r), end = domain.ring_end(r);
    const Sign first = bisector_side_vertex2d(pi, pk, domain.vertex(begin), i, k);
    Sign sa = first;
    for (std::uint32_t v = begin; v < end; ++v) {
      const std::uint32_t w = v + 1 == end ? begin : v + 1;
      const Sign sb = w == begin ? first : bisector_side_vertex2d(pi, pk, domain.vertex(w), i, k);
      if (sa != sb && bisector_side_edge2d(pi, pk, pl, domain.vertex(v), domain.vertex(w), i, k,
                                           l) == Sign::positive) {
        inside = !inside;
      }
      sa = sb;
    }
  }
  return inside ? Sign::positive : Sign::negative;
}

Mesh2 extract_mesh2(const Domain2& domain, const std::vector<double>& sites,
                    const std::vector<Mesh2::VertexKind>& kinds,
                    const std::vector<std::uint32_t>& site_domain,
                    const std::vector<std::uint32_t>& site_edge, Extract2Stats* stats,
                    bool keep_gaps) {
  if (sites.size() % 2 != 0) throw Error("extract_mesh2: the site array has an odd length");
  const auto n = static_cast<std::uint32_t>(sites.size() / 2);
  if ((!kinds.empty() && kinds.size() != n) || (!site_domain.empty() && site_domain.size() != n) ||
      (!site_edge.empty() && site_edge.size() != n)) {
    throw Error("extract_mesh2: per-site arrays must have one entry per site (" +
                std::to_string(n) + ")");
  }
  const Delaunay2 dt(sites.data(), n);
  ClippedVoronoi2 cv;
  cv.compute(domain, dt);
  const mesh2d::EdgeGrid2 grid(domain);

  std::vector<Sign> location(n, Sign::zero);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, n),
                    [&](const tbb::blocked_range<std::uint32_t>& range) {
                      for (std::uint32_t v = range.begin(); v != range.end(); ++v) {
                        if (dt.duplicate_of(v) == v) location[v] = domain.locate(dt.point(v));
                      }
                    });
  // Per triangle: 0 circumcenter outside, 1 kept, 2 not contained, 3 circumcenter outside
  // but contained (a gap in the mesh).
  const std::uint32_t nt = dt.nb_triangles();
  std::vector<std::uint8_t> verdict(nt, 0);
  tbb::parallel_for(
      tbb::blocked_range<std::uint32_t>(0, nt),
      [&](const tbb::blocked_range<std::uint32_t>& range) {
        for (std::uint32_t t = range.begin(); t != range.end(); ++t) {
          std::uint32_t v[3];
          bool inner = false;
          for (int k = 0; k < 3; ++k) {
            v[k] = dt.tri_vertex(t, k);
            inner = inner || (!cv.is_boundary(v[k]) && cv.area(v[k]) > 0);
          }
          const bool in = inner || circumcenter_location2(domain, dt, t) == Sign::positive;
          const double* p[3] = {dt.point(v[0]), dt.point(v[1]), dt.point(v[2])};
          const Sign loc[3] = {location[v[0]], location[v[1]], location[v[2]]};
          const bool contained = triangle_containment(domain, grid, p, loc) == Containment::kInside;
          verdict[t] = in ? (contained ? 1 : 2) : (contained ? 3 : 0);
          if (keep_gaps && verdict[t] == 3) verdict[t] = 1;
        }
      });

  Mesh2 mesh;
  Extract2Stats st;
  st.nb_delaunay = nt;
  // Vertices numbered in site order, triangles in Delaunay order.
  std::vector<std::uint32_t> index(n, Mesh2::kNone);
  for (std::uint32_t t = 0; t < nt; ++t) {
    if (verdict[t] == 0 || verdict[t] == 3) ++st.nb_circumcenter_outside;
    if (verdict[t] == 2) ++st.dropped_outside;
    if (verdict[t] == 3) {
      for (int k = 0; k < 3; ++k) st.gap_triangles.push_back(dt.tri_vertex(t, k));
    }
    if (verdict[t] != 1) continue;
    for (int k = 0; k < 3; ++k) index[dt.tri_vertex(t, k)] = 0;
  }
  std::uint32_t used = 0;
  for (std::uint32_t v = 0; v < n; ++v) {
    if (index[v] == Mesh2::kNone) continue;
    index[v] = used++;
    mesh.xy.push_back(sites[2 * std::size_t{v}]);
    mesh.xy.push_back(sites[2 * std::size_t{v} + 1]);
    mesh.vertex_kind.push_back(kinds.empty() ? Mesh2::VertexKind::kInterior : kinds[v]);
    mesh.vertex_domain.push_back(site_domain.empty() ? Mesh2::kNone : site_domain[v]);
    mesh.vertex_edge.push_back(site_edge.empty() ? Mesh2::kNone : site_edge[v]);
    mesh.vertex_site.push_back(v);
  }
  for (std::uint32_t t = 0; t < nt; ++t) {
    if (verdict[t] != 1) continue;
    for (int k = 0; k < 3; ++k) mesh.triangles.push_back(index[dt.tri_vertex(t, k)]);
  }
  st.removed_vertices = n - used;
  if (stats) *stats = std::move(st);
  return mesh;
}

std::string check_mesh2(const Domain2& domain, const Mesh2& mesh) {
  const std::uint32_t nv = mesh.nb_vertices(), nt = mesh.nb_triangles();
  if (mesh.triangles.size() != 3 * std::size_t{nt})
    return "the triangle array is not 3 per triangle";
  const auto tri_name = [](std::uint32_t t) { return "triangle " + std::to_string(t); };
  std::vector<std::uint8_t> used(nv, 0);
  for (std::uint32_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = mesh.triangles[3 * std::size_t{t} + k];
      if (v >= nv) return tri_name(t) + ": vertex index " + std::to_string(v) + " out of range";
      used[v] = 1;
    }
  }
  for (std::uint32_t v = 0; v < nv; ++v) {
    if (!used[v]) return "vertex " + std::to_string(v) + " is used by no triangle";
  }
  const auto point = [&](std::uint32_t t, int k) {
    return &mesh.xy[2 * std::size_t{mesh.triangles[3 * std::size_t{t} + k]}];
  };
  for (std::uint32_t t = 0; t < nt; ++t) {
    if (orient2d(point(t, 0), point(t, 1), point(t, 2)) != Sign::positive) {
      return tri_name(t) + " is not counter-clockwise with non-zero area";
    }
  }
  // Edges: each directed edge at most once (so an edge has at most two triangles, with
  // opposite orientations).
  std::unordered_map<std::uint64_t, std::uint32_t> directed;
  directed.reserve(3 * std::size_t{nt});
  for (std::uint32_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t a = mesh.triangles[3 * std::size_t{t} + k];
      const std::uint64_t b = mesh.triangles[3 * std::size_t{t} + (k + 1) % 3];
      if (!directed.emplace(a << 32 | b, t).second) {
        return tri_name(t) + " repeats the directed edge " + std::to_string(a) + " -> " +
               std::to_string(b) + " of " + tri_name(directed[a << 32 | b]);
      }
    }
  }
  // Containment, exact.
  const mesh2d::EdgeGrid2 grid(domain);
  std::vector<Sign> location(nv);
  for (std::uint32_t v = 0; v < nv; ++v) location[v] = domain.locate(&mesh.xy[2 * std::size_t{v}]);
  for (std::uint32_t t = 0; t < nt; ++t) {
    const double* p[3] = {point(t, 0), point(t, 1), point(t, 2)};
    const Sign loc[3] = {location[mesh.triangles[3 * std::size_t{t}]],
                         location[mesh.triangles[3 * std::size_t{t} + 1]],
                         location[mesh.triangles[3 * std::size_t{t} + 2]]};
    switch (triangle_containment(domain, grid, p, loc)) {
      case Containment::kInside:
        break;
      case Containment::kCrossed:
        return tri_name(t) + " is crossed by a domain edge";
      case Containment::kOutside:
        return tri_name(t) + " lies outside the domain";
      case Containment::kUndecided:
        return tri_name(t) +
               ": containment undecided (all vertices on the boundary, centroid "
               "not strictly inside)";
    }
  }
  // Triangles pairwise interior-disjoint: bins of triangles by their boxes.
  double lo[2] = {domain.bbox_lo()[0], domain.bbox_lo()[1]};
  double hi[2] = {domain.bbox_hi()[0], domain.bbox_hi()[1]};
  const std::uint32_t side =
      std::max<std::uint32_t>(1, static_cast<std::uint32_t>(std::sqrt(double(nt)) / 2));
  const double wx = (hi[0] - lo[0]) / side, wy = (hi[1] - lo[1]) / side;
  const auto bin = [&](double x, double x0, double w) {
    const double f = std::floor((x - x0) / w);
    return f <= 0 ? 0u : f >= side - 1 ? side - 1 : static_cast<std::uint32_t>(f);
  };
  std::vector<std::vector<std::uint32_t>> bins(std::size_t{side} * side);
  std::vector<std::uint32_t> box(4 * std::size_t{nt});
  for (std::uint32_t t = 0; t < nt; ++t) {
    const double* p[3] = {point(t, 0), point(t, 1), point(t, 2)};
    std::uint32_t* b = &box[4 * std::size_t{t}];
    b[0] = bin(std::min({p[0][0], p[1][0], p[2][0]}), lo[0], wx);
    b[1] = bin(std::min({p[0][1], p[1][1], p[2][1]}), lo[1], wy);
    b[2] = bin(std::max({p[0][0], p[1][0], p[2][0]}), lo[0], wx);
    b[3] = bin(std::max({p[0][1], p[1][1], p[2][1]}), lo[1], wy);
    for (std::uint32_t j = b[1]; j <= b[3]; ++j) {
      for (std::uint32_t i = b[0]; i <= b[2]; ++i) bins[std::size_t{j} * side + i].push_back(t);
    }
  }
  for (std::size_t c = 0; c < bins.size(); ++c) {
    const std::vector<std::uint32_t>& list = bins[c];
    for (std::size_t x = 0; x < list.size(); ++x) {
      for (std::size_t y = x + 1; y < list.size(); ++y) {
        const std::uint32_t t = list[x], u = list[y];
        // Test each pair once: in the first bin shared by both boxes.
        const std::uint32_t* bt = &box[4 * std::size_t{t}];
        const std::uint32_t* bu = &box[4 * std::size_t{u}];
        const std::uint32_t i0 = std::max(bt[0], bu[0]), j0 = std::max(bt[1], bu[1]);
        if (std::size_t{j0} * side + i0 != c) continue;
        const double* p[3] = {point(t, 0), point(t, 1), point(t, 2)};
        const double* q[3] = {point(u, 0), point(u, 1), point(u, 2)};
        if (open_triangles_meet(p, q)) return tri_name(t) + " overlaps " + tri_name(u);
      }
    }
  }
  return "";
}

}  // namespace voroclip
