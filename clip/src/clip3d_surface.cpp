// The restricted surface of the 3D clipped Voronoi diagram (Yan et al. 2011, sec. 4.1),
// triangle by triangle rather than by the paper's global propagation, so that triangles go
// in parallel and the result, concatenated in triangle order, does not depend on the
// thread count. SurfaceRvd (clip3d_surface.h) runs it over chunks of triangles, each thread
// with a Scratch of its own (below) and its Stars (neighbour lists, kept for the cells),
// and leaves a RestrictedSurface for DelaunayCells (clip3d_cells.h).
//
// 1. The cell of every boundary vertex of the mesh (the perturbed nearest site: the
//    descent over Delaunay neighbours decides with bisector_side_vertex3d), in the order of
//    a breadth-first walk over the surface, each from the previous one's cell; a chunk of
//    vertices starts from an exact nearest-site query.
// 2. Per boundary triangle: when its three corners lie in one cell, so does the triangle
//    (cells are convex; under the perturbation the corners are strictly inside); else the
//    cells of its corners, then every cell across a bisector edge of a polygon found, are
//    clipped against the triangle (Sutherland-Hodgman on symbolic vertices: exact). A
//    bisector is skipped without a predicate when the three corners are certainly on the
//    cell's side of it (bisector_value's bound).
// 3. Per polygon of cell c, the divergence theorem's share of ∂(C_c ∩ Ω) that the surface
//    knows (clip3d_cells.cpp has the rest): the cones from p_c over the polygon (outward,
//    as the surface's triangles) and, over each polygon edge on bisector(c, j), the cone
//    over the triangle (foot of p_c on the bisector, edge reversed) — the edge bounds the
//    facet of c on bisector(c, j) inside the volume, which runs through it the other way.
//    A polygon vertex on two bisectors (c, k), (c, l) is where the Voronoi edge of c, k, l
//    crosses the surface; the polygon of the smallest of the three records it.
// 4. Per Voronoi edge, its crossings, each with the direction in which the edge crosses
//    the surface there (voronoi_edge_direction3d): clip3d_cells.cpp turns them into the
//    pieces of the edge inside the volume, whatever their number.
#include "clip3d_surface.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <string>
#include <vector>

namespace voroclip {

namespace clip3 {

namespace {

constexpr std::uint32_t kTriangleChunk = 128;
constexpr std::size_t kSums = 7;  // per polygon (SurfaceRvd::Chunk::sums)

}  // namespace

// A vertex of a boundary triangle clipped by cell c: tag 0..2, corner `tag` of the triangle;
// 3..5, the triangle edge opposite corner tag - 3 ∩ bisector(c, k); 6, the triangle's plane
// ∩ bisector(c, k) ∩ bisector(c, l), k < l.
// fk, fl: while the triangle is clipped by cell c, the rows of CornerValues of the
// bisectors (c, k) and (c, l); fm: the row of FacetMinors of a point inside (tag 6).
struct TriVertex {
  std::int8_t tag;
  std::uint32_t k, l;
  std::uint32_t fk, fl, fm;
};

// F = |y - p_c|^2 - |y - p_j|^2 at the three corners of a triangle (bisector_value), each
// within err of the exact value.
struct CornerValues {
  double f[3], err[3];
};

// A point of the triangle's plane on bisectors (c, k) and (c, l), from their CornerValues:
// the 2 x 2 minors m[p] of the rows F_k, F_l (columns q, r after p), each within err[p], and
// the sign of D = m[0] + m[1] + m[2] when decided (0 otherwise; facet_minors).
struct FacetMinors {
  double m[3], err[3];
  int sign_d;
};

// A convex polygon in a boundary triangle: vertex k is v[k], and the edge from v[k] to
// v[k + 1] lies on plane e[k] (a facet of the triangle's tet, i.e. a triangle edge, or a
// bisector of the cell).
// The arrays only grow (reset), so that a polygon's vertices are written without a
// capacity check: the first n entries are the polygon.
struct TriPoly {
  std::vector<TriVertex> v;
  std::vector<Plane> e;
  std::size_t n = 0;
  // Empty, with room for `cap` vertices.
  void reset(std::size_t cap) {
    if (v.size() < cap) {
      v.resize(cap);
      e.resize(cap);
    }
    n = 0;
  }
  void push(const TriVertex& x, Plane edge) {
    v[n] = x;
    e[n] = edge;
    ++n;
  }
  std::size_t size() const { return n; }
};

// The same F = |v - p_c|^2 - |v - p_j|^2 as 2 r.e - |e|^2 with r = v - p_c and e = p_j - p_c
// rounded once each (r shared by every neighbour of c, e by every point): the products and
// sums add at most gamma_5 (2 sum |r_k e_k| + |e|^2) and the last subtraction u |F|, with
// 2 |r_k e_k| <= r_k^2 + e_k^2, so |computed - F| <= gamma_7 (|r|^2 + 2 |e|^2) / (1 - gamma_3)
// with rr, ee the computed squared norms: bound 1e-15 (rr + 2 ee) (> 7.2 u), plus 1e-300
// for underflow. Returns F (rounded) and sets `bound`.
inline double bisector_value(const double* r, double rr, const double* e, double ee,
                             double& bound) {
  bound = 1e-15 * (rr + 2 * ee) + 1e-300;
  return 2 * ((r[0] * e[0] + r[1] * e[1]) + r[2] * e[2]) - ee;
}

namespace {

// A point X of triangle edge (a, b) on bisector(c, k): F_k affine along the edge, so
//   F_j(X) = N / D,  N = F_k(a) F_j(b) - F_k(b) F_j(a),  D = F_k(a) - F_k(b)
// (the contract of bisector_side_edge3d, with F for f: they differ by eps terms only, which
// matter only when N or D is zero). With each value F~ within err of F,
//   |F~_k F~_j - F_k F_j| <= |F~_k| e_j + e_k |F~_j| + e_k e_j,
// the two products and the difference round within 2.0001 u (|F~_k(a) F~_j(b)| +
// |F~_k(b) F~_j(a)|), and the bound itself is rounded up by a factor 1 + 1e-14. Values are
// used only in [1e-150, 1e150] (errors) and below 1e150 (values): no product overflows,
// and one that underflows errs by less than the 1e-300 added (the products of two errors
// are >= 1e-300). Returns the sign of F_j(X) when that decides it, else 0.
inline int edge_point_side(const CornerValues& k, const CornerValues& j, int a, int b) {
  const double ka = k.f[a], kb = k.f[b], ja = j.f[a], jb = j.f[b];
  const double eka = k.err[a], ekb = k.err[b], eja = j.err[a], ejb = j.err[b];
  const double lo = std::min(std::min(eka, ekb), std::min(eja, ejb));
  const double hi = std::max(std::max(std::fabs(ka) + eka, std::fabs(kb) + ekb),
                             std::max(std::fabs(ja) + eja, std::fabs(jb) + ejb));
  if (!(lo >= 1e-150 && hi <= 1e150)) return 0;
  const double p1 = ka * jb, p2 = kb * ja;
  const double n = p1 - p2, d = ka - kb;
  const double bn = ((std::fabs(ka) * ejb + eka * std::fabs(jb) + eka * ejb) +
                     (std::fabs(kb) * eja + ekb * std::fabs(ja) + ekb * eja) +
                     2.0001 * 0x1p-53 * (std::fabs(p1) + std::fabs(p2)) + 1e-300) *
                    (1 + 1e-14);
  const double bd = (eka + ekb + 0x1p-53 * std::fabs(d)) * (1 + 1e-14);
  if (!(std::fabs(n) > bn && std::fabs(d) > bd)) return 0;
  return (n > 0) == (d > 0) ? 1 : -1;
}

// A point X of the triangle's plane on bisectors (c, k) and (c, l): with barycentric
// coordinates from F_k(X) = F_l(X) = 0 (F affine), F_j(X) = N / D, N = det[F_j; F_k; F_l],
// D = det[1; F_k; F_l] (rows: the values at the corners; the contract of
// bisector_side_facet3d). Expanding along the first row, N = sum_p F_j[p] m_p and
// D = sum_p m_p with the minors m_p = F_k[q] F_l[r] - F_k[r] F_l[q] ((p, q, r) cyclic).
// A minor of values within e of the exact ones errs by at most
//   |k_q| e + e |l_r| + e e + |k_r| e + e |l_q| + e e
// plus 2.0001 u (|k_q l_r| + |k_r l_q|) of rounding (every bound is a sum of non-negative
// terms, so its own rounding is relative); a dot product sum_p a_p m_p of values
// within e_a, e_m errs by sum_p (|a_p| e_m + e_a |m_p| + e_a e_m) plus 3.0001 u
// sum_p |a_p m_p|. Bounds are rounded up by 1 + 1e-14. Values are used only with errors in
// [1e-100, 1e100] and magnitudes below 1e100, so no product overflows, and the 1e-300 added
// covers those that underflow (products of errors stay above 1e-200).
FacetMinors facet_minors(const CornerValues& k, const CornerValues& l) {
  FacetMinors fm{};
  double lo = 1e300, hi = 0;
  for (const CornerValues* r : {&k, &l}) {
    for (int p = 0; p < 3; ++p) {
      lo = std::min(lo, r->err[p]);
      hi = std::max(hi, std::fabs(r->f[p]) + r->err[p]);
    }
  }
  if (!(lo >= 1e-100 && hi <= 1e100)) {
    fm.sign_d = 0;
    fm.err[0] = fm.err[1] = fm.err[2] = std::numeric_limits<double>::infinity();
    return fm;
  }
  double sum_err = 0, sum_abs = 0;
  for (int p = 0; p < 3; ++p) {
    const int q = (p + 1) % 3, r = (p + 2) % 3;
    const double a = k.f[q] * l.f[r], b = k.f[r] * l.f[q];
    fm.m[p] = a - b;
    const double spread =
        (std::fabs(k.f[q]) * l.err[r] + k.err[q] * std::fabs(l.f[r]) + k.err[q] * l.err[r]) +
        (std::fabs(k.f[r]) * l.err[q] + k.err[r] * std::fabs(l.f[q]) + k.err[r] * l.err[q]);
    fm.err[p] = (spread + 2.0001 * 0x1p-53 * (std::fabs(a) + std::fabs(b)) + 1e-300) * (1 + 1e-14);
    sum_err += fm.err[p];
    sum_abs += std::fabs(fm.m[p]);
  }
  const double d = (fm.m[0] + fm.m[1]) + fm.m[2];
  const double bd = (sum_err + 3.0001 * 0x1p-53 * sum_abs + 1e-300) * (1 + 1e-14);
  fm.sign_d = std::fabs(d) > bd ? (d > 0 ? 1 : -1) : 0;
  return fm;
}

// The sign of F_j at the facet point of `fm` when decided, else 0 (see facet_minors).
inline int facet_point_side(const FacetMinors& fm, const CornerValues& j) {
  if (fm.sign_d == 0) return 0;
  double lo = 1e300, hi = 0;
  for (int p = 0; p < 3; ++p) {
    lo = std::min(lo, j.err[p]);
    hi = std::max(hi, std::fabs(j.f[p]) + j.err[p]);
  }
  if (!(lo >= 1e-100 && hi <= 1e100)) return 0;
  const double t0 = j.f[0] * fm.m[0], t1 = j.f[1] * fm.m[1], t2 = j.f[2] * fm.m[2];
  const double n = (t0 + t1) + t2;
  double spread = 0;
  for (int p = 0; p < 3; ++p) {
    spread += std::fabs(j.f[p]) * fm.err[p] + j.err[p] * std::fabs(fm.m[p]) + j.err[p] * fm.err[p];
  }
  const double bn =
      (spread + 3.0001 * 0x1p-53 * ((std::fabs(t0) + std::fabs(t1)) + std::fabs(t2)) + 1e-300) *
      (1 + 1e-14);
  if (!(std::fabs(n) > bn)) return 0;
  return (n > 0) == (fm.sign_d > 0) ? 1 : -1;
}

// The ends of the triangle edge opposite corner k.
constexpr int kEdgeEnd[3][2] = {{1, 2}, {2, 0}, {0, 1}};

}  // namespace

// A point of a triangle on bisectors met while it is clipped (a vertex of the polygons of
// two or three cells): tag, sorted sites (kNone past the tag's count), coordinates.
struct TriPoint {
  std::int8_t tag;
  std::uint32_t s[3];
  double x[3];
};

// One thread's scratch of the pass.
struct SurfaceRvd::Scratch {
  TriPoly a, b;  // the polygon being clipped, and the next one (swapped)
  // Per polygon vertex, beyond the bisector.
  std::vector<std::uint8_t> beyond;
  // clip_triangle: the neighbours past the filters, and their corner values.
  std::vector<std::uint32_t> candidates;
  std::vector<CornerValues> candidate_values;
  // While the triangle is clipped by a cell: the rows of TriVertex::fk, fl and fm.
  std::vector<CornerValues> corner_values;
  std::vector<FacetMinors> facet_minors;
  // The cells met by the current triangle.
  std::vector<std::uint32_t> cells;
  // Per domain vertex: its cell, when stamp is the current chunk's (+ 1); the last cell met
  // (a hint).
  struct Corners {
    std::vector<std::uint32_t> cell, stamp;
    std::uint32_t last = kNone;
  } corners;
  std::vector<double> xyz, rel;  // a polygon's vertices, absolute and relative to its site
  // The points of the current triangle on bisectors met so far.
  std::vector<TriPoint> tri_points;
};

// A crossing of a Voronoi edge with the surface: Delaunay triangle (s[0] < s[1] < s[2]), the
// boundary triangle, the point.
struct Crossing {
  std::uint32_t s[3], tri;
  double x[3];
};

// Per chunk of triangles, its polygons in triangle order.
struct SurfaceRvd::Chunk {
  std::vector<std::uint32_t> cell, tri;
  std::vector<double> sums;  // per polygon: volume, moment (3), energy, area, mass
  std::vector<std::uint32_t> begin{0};
  std::vector<ClipVertex3> verts;  // keep_surface
  std::vector<double> xyz;         // keep_surface
  // keep_surface: per polygon vertex, the site across the edge from it (kNone: an edge on
  // the triangle's boundary).
  std::vector<std::uint32_t> across;
  std::vector<Crossing> crossings;
  // A callback density: per polygon, its cones' density-weighted moments, summed by the
  // thread's DensityBatch over the whole chunk (one batch for all its polygons, not one
  // per polygon: a Python callable pays its call once per batch) and copied into `sums`
  // when the chunk is done (finish_weighted). A deque: the batch holds pointers to them.
  std::deque<Moments> weighted;
};

// The cell of point p (perturbed): descent from c. If p is not in cell c, a Delaunay
// neighbour k has f_ck(p) > 0, and the power distance decreases at each step. The
// neighbours are tried nearest first (largest F in floating point); one certainly farther
// than c needs no predicate.
std::uint32_t SurfaceRvd::descend(const double* p, std::uint32_t c, Stars& stars) const {
  for (;;) {
    const NeighborList nb = stars.neighbors(ctx_, c);
    const double* pc = ctx_.site(c);
    const double r[3] = {p[0] - pc[0], p[1] - pc[1], p[2] - pc[2]};
    const double rr = (r[0] * r[0] + r[1] * r[1]) + r[2] * r[2];
    // The neighbour nearest to p in floating point first; the others not certainly
    // farther than c only when it is not nearer (rare).
    std::uint32_t best = kNone;
    double best_f = 0;
    for (std::uint32_t q = 0; q < nb.count; ++q) {
      double bound;
      const double f = bisector_value(r, rr, nb.geo[q].e, nb.geo[q].ee, bound);
      if (f < -bound) continue;
      if (best == kNone || f > best_f) {
        best = q;
        best_f = f;
      }
    }
    if (best == kNone) return c;
    std::uint32_t next = kNone;
    if (bisector_side_vertex3d(pc, ctx_.site(nb.id[best]), p, c, nb.id[best]) == Sign::positive) {
      next = nb.id[best];
    } else {
      for (std::uint32_t q = 0; q < nb.count && next == kNone; ++q) {
        double bound;
        const double f = bisector_value(r, rr, nb.geo[q].e, nb.geo[q].ee, bound);
        if (q == best || f < -bound) continue;
        if (bisector_side_vertex3d(pc, ctx_.site(nb.id[q]), p, c, nb.id[q]) == Sign::positive) {
          next = nb.id[q];
        }
      }
    }
    if (next == kNone) return c;
    c = next;
  }
}

Sign SurfaceRvd::tri_side(const Tri& tri, const TriVertex& v, std::uint32_t c,
                          std::uint32_t j) const {
  if (v.tag < 3) return bisector_side_vertex3d(ctx_.site(c), ctx_.site(j), tri.x[v.tag], c, j);
  if (v.tag < 6) {
    const int o = v.tag - 3;
    return bisector_side_edge3d(ctx_.site(c), ctx_.site(v.k), ctx_.site(j), tri.x[(o + 1) % 3],
                                tri.x[(o + 2) % 3], c, v.k, j);
  }
  return bisector_side_facet3d(ctx_.site(c), ctx_.site(v.k), ctx_.site(v.l), ctx_.site(j), tri.x[0],
                               tri.x[1], tri.x[2], c, v.k, v.l, j);
}

void SurfaceRvd::tri_coords(const Tri& tri, const TriVertex& v, std::uint32_t c, double* x) const {
  if (v.tag < 3) {
    for (int q = 0; q < 3; ++q) x[q] = tri.x[v.tag][q];
  } else if (v.tag < 6) {
    const int o = v.tag - 3;
    const std::uint32_t a = tri.mv[kEdgeEnd[o][0]], b = tri.mv[kEdgeEnd[o][1]];
    ctx_.edge_point(std::min(a, b), std::max(a, b), std::min(c, v.k), std::max(c, v.k), x);
  } else {
    std::uint32_t mesh[3] = {tri.mv[0], tri.mv[1], tri.mv[2]}, sites[3] = {c, v.k, v.l};
    small_sort(mesh, 3);
    small_sort(sites, 3);
    ctx_.facet_point(mesh, sites, x);
  }
}

ClipVertex3 SurfaceRvd::tri_symbolic(const Tri& tri, const TriVertex& v, std::uint32_t c) const {
  ClipVertex3 x{};
  std::uint32_t mesh[3] = {tri.mv[0], tri.mv[1], tri.mv[2]}, sites[3] = {c, v.k, v.l};
  int nm = 3, ns = 3;
  if (v.tag < 3) {
    x.kind = ClipVertex3::Kind::kMeshVertex;
    mesh[0] = tri.mv[v.tag];
    nm = 1;
    ns = 0;
  } else if (v.tag < 6) {
    x.kind = ClipVertex3::Kind::kEdgeBisector;
    const int o = v.tag - 3;
    mesh[0] = tri.mv[(o + 1) % 3];
    mesh[1] = tri.mv[(o + 2) % 3];
    nm = 2;
    ns = 2;
  } else {
    x.kind = ClipVertex3::Kind::kFacetBisectors;
  }
  small_sort(mesh, nm);
  small_sort(sites, ns);
  for (int k = 0; k < 3; ++k) {
    x.mesh[k] = k < nm ? mesh[k] : ClipVertex3::kNone;
    x.site[k] = k < ns ? sites[k] : ClipVertex3::kNone;
  }
  return x;
}

// The polygon of a triangle in cell c: integrals, crossings, geometry (see the top).
void SurfaceRvd::emit_polygon(const Tri& tri, std::uint32_t c, const TriPoly& p, Scratch& s,
                              Chunk& chunk) const {
  const std::size_t m = p.size();
  // The cones' apex: the site, or for a far one the domain's centre (Clip3Context::far).
  if (ctx_.far(c)) ctx_.check_far_site(c);
  const double* pc = ctx_.apex(c);
  if (s.xyz.size() < 3 * m) {
    s.xyz.resize(3 * m);
    s.rel.resize(4 * m);
  }
  // rel: per vertex y = x - p_c (the apex) and |y|^2.
  for (std::size_t k = 0; k < m; ++k) {
    const TriVertex& v = p.v[k];
    double* xk = &s.xyz[3 * k];
    if (v.tag < 3) {
      for (int q = 0; q < 3; ++q) xk[q] = tri.x[v.tag][q];
    } else {
      std::uint32_t ids[3] = {c, v.k, v.tag == 6 ? v.l : kNone};
      small_sort(ids, 3);
      bool found = false;
      for (const TriPoint& tp : s.tri_points) {
        if (tp.tag == v.tag && tp.s[0] == ids[0] && tp.s[1] == ids[1] && tp.s[2] == ids[2]) {
          for (int q = 0; q < 3; ++q) xk[q] = tp.x[q];
          found = true;
          break;
        }
      }
      if (!found) {
        tri_coords(tri, v, c, xk);
        // Field by field into the new entry: a temporary's mixed-width stores copied by
        // 16-byte loads stalled on store forwarding (perf annotate).
        TriPoint& tp = s.tri_points.emplace_back();
        tp.tag = v.tag;
        for (int q = 0; q < 3; ++q) {
          tp.s[q] = ids[q];
          tp.x[q] = xk[q];
        }
      }
    }
    double* y = &s.rel[4 * k];
    for (int q = 0; q < 3; ++q) y[q] = s.xyz[3 * k + q] - pc[q];
    y[3] = (y[0] * y[0] + y[1] * y[1]) + y[2] * y[2];
  }
  const auto x = [&](std::size_t k) { return &s.rel[4 * (k == m ? 0 : k)]; };
  // Cones from p_c (add_cone's formulas) with det = 6 V accumulated, and, with
  // s = a + b + c, the moment sum det s = 24 M and the energy sum
  // det (|s|^2 + |a|^2 + |b|^2 + |c|^2) = 120 E (|a|^2 + |b|^2 + |c|^2 + a.b + a.c + b.c
  // is half the bracket).
  // Fan from o = y_0 over the polygon (outward, as its triangle): det(o, u, w) = o . (a x d)
  // for a = u - o, d = w - o, whose cross product also sums to twice the area vector.
  double vol6 = 0, mom24[3] = {0, 0, 0}, en120 = 0, area[3] = {0, 0, 0};
  const double* o = x(0);
  for (std::size_t k = 1; k + 1 < m; ++k) {
    const double* u = x(k);
    const double* w = x(k + 1);
    const double a[3] = {u[0] - o[0], u[1] - o[1], u[2] - o[2]};
    const double d[3] = {w[0] - o[0], w[1] - o[1], w[2] - o[2]};
    const double nv[3] = {a[1] * d[2] - a[2] * d[1], a[2] * d[0] - a[0] * d[2],
                          a[0] * d[1] - a[1] * d[0]};
    for (int q = 0; q < 3; ++q) area[q] += nv[q];
    const double det = (o[0] * nv[0] + o[1] * nv[1]) + o[2] * nv[2];
    const double sv[3] = {(o[0] + u[0]) + w[0], (o[1] + u[1]) + w[1], (o[2] + u[2]) + w[2]};
    vol6 += det;
    for (int q = 0; q < 3; ++q) mom24[q] += det * sv[q];
    en120 += det * (((sv[0] * sv[0] + sv[1] * sv[1]) + sv[2] * sv[2]) + ((o[3] + u[3]) + w[3]));
  }
  // Over each edge u -> w on bisector(c, j), the cone over (h, w, u), h the foot (the facet
  // runs through the edge the other way): there h . u = h . w = |h|^2, so the bracket is
  // 2 (3 |h|^2 + |u|^2 + |w|^2 + u . w) (add_edge_piece).
  for (std::size_t k = 0; k < m; ++k) {
    if (is_facet(p.e[k])) continue;
    double h[3];
    ctx_.foot(c, static_cast<std::uint32_t>(p.e[k]), h);
    const double* u = x(k);
    const double* w = x(k + 1);
    const double nv[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                          u[0] * w[1] - u[1] * w[0]};
    const double det = -((h[0] * nv[0] + h[1] * nv[1]) + h[2] * nv[2]);
    const double hh3 = 3 * ((h[0] * h[0] + h[1] * h[1]) + h[2] * h[2]);
    const double q2 = hh3 + ((u[3] + w[3]) + ((u[0] * w[0] + u[1] * w[1]) + u[2] * w[2]));
    vol6 += det;
    for (int q = 0; q < 3; ++q) mom24[q] += det * ((h[q] + u[q]) + w[q]);
    en120 += 2 * det * q2;
  }
  Moments r;
  r.volume = vol6 * (1.0 / 6);
  for (int q = 0; q < 3; ++q) r.moment[q] = mom24[q] * (1.0 / 24);
  r.energy = en120 * (1.0 / 120);
  if (ctx_.callback_density) {
    // The same cones, weighted by the density (the volume stays the closed form's), into
    // the polygon's entry of chunk.weighted, which finish_weighted copies over the mass,
    // moment and energy once the chunk's batch is flushed. Each entry takes only its own
    // cones, in this order, and rho depends only on a point's bits: the same sums as a
    // flush per polygon.
    Moments& wm = chunk.weighted.emplace_back();
    DensityBatch& batch = thread_density_batch();
    for (std::size_t k = 1; k + 1 < m; ++k) batch.add(pc, o, x(k), x(k + 1), wm);
    for (std::size_t k = 0; k < m; ++k) {
      if (is_facet(p.e[k])) continue;
      double h[3];
      ctx_.foot(c, static_cast<std::uint32_t>(p.e[k]), h);
      batch.add(pc, h, x(k + 1), x(k), wm);
    }
  }
  for (std::size_t k = 0; k < m; ++k) {
    const TriVertex& v = p.v[k];
    if (v.tag != 6 || c > v.k) continue;
    Crossing cr{};
    cr.s[0] = c;
    cr.s[1] = v.k;
    cr.s[2] = v.l;
    cr.tri = tri.b;
    for (int q = 0; q < 3; ++q) cr.x[q] = s.xyz[3 * k + q];
    chunk.crossings.push_back(cr);
  }
  chunk.cell.push_back(c);
  chunk.tri.push_back(tri.b);
  // Written in place (a local array copied by 16-byte loads stalled on store forwarding).
  const std::size_t at = chunk.sums.size();
  chunk.sums.resize(at + kSums);
  double* sums = chunk.sums.data() + at;
  sums[0] = r.volume;
  for (int q = 0; q < 3; ++q) sums[1 + q] = r.moment[q];
  sums[4] = r.energy;
  sums[5] = 0.5 * std::sqrt(area[0] * area[0] + area[1] * area[1] + area[2] * area[2]);
  sums[6] = r.mass;
  if (ctx_.keep_surface) {
    for (std::size_t k = 0; k < m; ++k) {
      chunk.verts.push_back(tri_symbolic(tri, p.v[k], c));
      for (int q = 0; q < 3; ++q) chunk.xyz.push_back(s.xyz[3 * k + q]);
      chunk.across.push_back(is_facet(p.e[k]) ? kNone : static_cast<std::uint32_t>(p.e[k]));
    }
    chunk.begin.push_back(static_cast<std::uint32_t>(chunk.verts.size()));
  }
}

void SurfaceRvd::finish_weighted(Chunk& chunk) const {
  thread_density_batch().flush();
  for (std::size_t p = 0; p < chunk.weighted.size(); ++p) {
    const Moments& wm = chunk.weighted[p];
    double* sums = chunk.sums.data() + kSums * p;
    for (int q = 0; q < 3; ++q) sums[1 + q] = wm.moment[q];
    sums[4] = wm.energy;
    sums[6] = wm.mass;
  }
  chunk.weighted.clear();
  chunk.weighted.shrink_to_fit();
}

void SurfaceRvd::clip_triangle(std::uint32_t b, std::uint32_t stamp, Stars& stars, Scratch& s,
                               Chunk& chunk) const {
  // The edge from corner k to k + 1 lies on "facet" k + 2 (the plane label of the triangle
  // edge opposite corner k + 2: facet_plane(f) with f the opposite corner).
  Tri tri{};
  tri.b = b;
  // The cells of the corners that earlier triangles of this chunk found (kNone: unknown).
  if (s.corners.cell.size() != ctx_.surface.nb_vertices()) {
    s.corners.cell.assign(ctx_.surface.nb_vertices(), kNone);
    s.corners.stamp.assign(ctx_.surface.nb_vertices(), 0);
  }
  std::uint32_t corner[3];
  for (int k = 0; k < 3; ++k) {
    tri.mv[k] = ctx_.surface.triangle_vertex(b, k);
    tri.x[k] = ctx_.surface.vertex(tri.mv[k]);
    corner[k] = s.corners.stamp[tri.mv[k]] == stamp ? s.corners.cell[tri.mv[k]] : kNone;
  }
  if (corner[0] == kNone && corner[1] == kNone && corner[2] == kNone) {
    // From the last cell this thread met (nearby: the order follows the surface), or an
    // exact nearest-site query; the descent's result does not depend on where it starts.
    const std::uint32_t hint =
        s.corners.last != kNone ? s.corners.last : ctx_.dt.nearest_vertex(tri.x[0]);
    corner[0] = descend(tri.x[0], hint, stars);
  }
  const auto init = [&](TriPoly& p) {
    p.reset(3);
    for (int k = 0; k < 3; ++k) {
      p.push(TriVertex{static_cast<std::int8_t>(k), kNone, kNone, kNone, kNone, kNone},
             facet_plane((k + 2) % 3));
    }
  };
  init(s.a);
  if (corner[0] == corner[1] && corner[1] == corner[2]) {
    emit_polygon(tri, corner[0], s.a, s, chunk);
    s.corners.last = corner[0];
    return;
  }
  const auto record_corners = [&](std::uint32_t c, const TriPoly& p) {
    for (std::size_t k = 0; k < p.size(); ++k) {
      const TriVertex& v = p.v[k];
      if (v.tag < 3) {
        s.corners.cell[tri.mv[v.tag]] = c;
        s.corners.stamp[tri.mv[v.tag]] = stamp;
      }
    }
  };
  // A ball around the triangle: centre g, radius R (the farthest corner).
  double g[3], radius = 0;
  for (int q = 0; q < 3; ++q) g[q] = (tri.x[0][q] + tri.x[1][q] + tri.x[2][q]) / 3;
  for (int k = 0; k < 3; ++k) {
    const double d[3] = {tri.x[k][0] - g[0], tri.x[k][1] - g[1], tri.x[k][2] - g[2]};
    radius = std::max(radius, (d[0] * d[0] + d[1] * d[1]) + d[2] * d[2]);
  }
  radius = std::sqrt(radius) * (1 + 1e-14);  // above the true distance despite rounding
  s.cells.clear();
  s.tri_points.clear();
  for (const std::uint32_t c : corner) {
    if (c != kNone && std::find(s.cells.begin(), s.cells.end(), c) == s.cells.end()) {
      s.cells.push_back(c);
    }
  }
  for (std::size_t q = 0; q < s.cells.size(); ++q) {
    const std::uint32_t c = s.cells[q];
    const double* pc = ctx_.site(c);
    const double rg[3] = {g[0] - pc[0], g[1] - pc[1], g[2] - pc[2]};
    const double rrg = (rg[0] * rg[0] + rg[1] * rg[1]) + rg[2] * rg[2];
    double r[3][3], rr[3];
    for (int k = 0; k < 3; ++k) {
      for (int h = 0; h < 3; ++h) r[k][h] = tri.x[k][h] - pc[h];
      rr[k] = (r[k][0] * r[k][0] + r[k][1] * r[k][1]) + r[k][2] * r[k][2];
    }
    init(s.a);
    const NeighborList nb = stars.neighbors(ctx_, c);
    s.corner_values.clear();
    s.facet_minors.clear();
    // bisector_value's bound at g is near + ee_err: each term rounded, the sum stays above
    // the proven 7.2 u (|r|^2 + 2 |e|^2) with room for the roundings of the test below.
    const double near = 1e-15 * rrg + 1e-300;
    bool empty = false;
    // F = |y - p_c|^2 - |y - p_j|^2 is affine: F(y) <= F(g) + 2 R |p_j - p_c| on the ball;
    // below zero there, the bisector misses the triangle. The neighbours that pass, listed
    // without branching (whether one passes is hard to predict).
    if (s.candidates.size() < nb.count) s.candidates.resize(nb.count);
    std::uint32_t* cand = s.candidates.data();
    std::uint32_t nb_cand = 0;
    for (std::uint32_t h = 0; h < nb.count; ++h) {
      const NbrGeo& ng = nb.geo[h];
      const double fg = 2 * ((rg[0] * ng.e[0] + rg[1] * ng.e[1]) + rg[2] * ng.e[2]) - ng.ee;
      cand[nb_cand] = h;
      nb_cand += (fg + radius * ng.reach < -(near + ng.ee_err)) ? 0 : 1;
    }
    // Then those with a corner not certainly nearer c, with their corner values (the list
    // compacted in place, again without branching).
    if (s.candidate_values.size() < nb_cand) s.candidate_values.resize(nb_cand);
    CornerValues* cand_fj = s.candidate_values.data();
    std::uint32_t nb_kept = 0;
    for (std::uint32_t z = 0; z < nb_cand; ++z) {
      const std::uint32_t h = cand[z];
      const NbrGeo& ng = nb.geo[h];
      CornerValues& fj = cand_fj[nb_kept];
      bool all_nearer = true;
      for (int k = 0; k < 3; ++k) {
        fj.f[k] = bisector_value(r[k], rr[k], ng.e, ng.ee, fj.err[k]);
        all_nearer = all_nearer & (fj.f[k] < -fj.err[k]);
      }
      cand[nb_kept] = h;
      nb_kept += all_nearer ? 0 : 1;
    }
    for (std::uint32_t z = 0; z < nb_kept; ++z) {
      const std::uint32_t h = cand[z];
      // The corners: -1 certainly nearer c, +1 certainly nearer j, 0 undecided.
      const CornerValues& fj = cand_fj[z];
      int corner_side[3];
      for (int k = 0; k < 3; ++k) {
        corner_side[k] = fj.f[k] < -fj.err[k] ? -1 : (fj.f[k] > fj.err[k] ? 1 : 0);
      }
      const std::uint32_t j = nb.id[h];
      // Sutherland-Hodgman on symbolic vertices. A corner's side, and that of a point of a
      // triangle edge whose ends agree, comes from the filter when it decided (F is affine).
      const TriPoly& in = s.a;
      const std::size_t m = in.size();
      if (s.beyond.size() < m) s.beyond.resize(m);
      bool any_beyond = false, any_kept = false;
      for (std::size_t k = 0; k < m; ++k) {
        const TriVertex& x = in.v[k];
        int known = 0;
        if (x.tag < 3) {
          known = corner_side[x.tag];
        } else if (x.tag < 6) {
          const int ea = kEdgeEnd[x.tag - 3][0], eb = kEdgeEnd[x.tag - 3][1];
          known = corner_side[ea] == corner_side[eb]
                      ? corner_side[ea]
                      : edge_point_side(s.corner_values[x.fk], fj, ea, eb);
        } else {
          known = facet_point_side(s.facet_minors[x.fm], fj);
        }
        const bool o = known != 0 ? known > 0 : tri_side(tri, in.v[k], c, j) == Sign::positive;
        s.beyond[k] = o ? 1 : 0;
        any_beyond = any_beyond || o;
        any_kept = any_kept || !o;
      }
      if (!any_beyond) continue;
      if (!any_kept) {
        empty = true;
        break;
      }
      // The crossing of edge k (plane e[k]) with bisector(c, j). The corner values of j
      // join the table; those of a bisector edge's site come from the vertex it starts at.
      const auto row = static_cast<std::uint32_t>(s.corner_values.size());
      s.corner_values.push_back(fj);
      TriPoly& res = s.b;
      res.reset(m + 1);  // a convex polygon cut by a line
      for (std::size_t k = 0; k < m; ++k) {
        const std::size_t kn = k + 1 == m ? 0 : k + 1;
        if (!s.beyond[k]) res.push(in.v[k], in.e[k]);
        if (s.beyond[k] != s.beyond[kn]) {
          TriVertex x{6, j, kNone, row, kNone, kNone};
          const Plane e = in.e[k];
          if (is_facet(e)) {
            x.tag = static_cast<std::int8_t>(3 + facet_of(e));
          } else {
            // The edge from v[k] lies on bisector(c, e): v[k] is on it, and carries its row.
            const TriVertex& from = in.v[k];
            const auto ke = static_cast<std::uint32_t>(e);
            const std::uint32_t row_e = from.k == ke ? from.fk : from.fl;
            x.k = std::min(j, ke);
            x.l = std::max(j, ke);
            x.fk = x.k == j ? row : row_e;
            x.fl = x.k == j ? row_e : row;
            x.fm = static_cast<std::uint32_t>(s.facet_minors.size());
            s.facet_minors.push_back(facet_minors(s.corner_values[x.fk], s.corner_values[x.fl]));
          }
          res.push(x, s.beyond[k] ? e : static_cast<Plane>(j));
        }
      }
      std::swap(s.a, s.b);
    }
    if (empty) continue;  // (a corner's cell, or a cell across an edge, is never empty)
    emit_polygon(tri, c, s.a, s, chunk);
    record_corners(c, s.a);
    s.corners.last = c;
    for (std::size_t h = 0; h < s.a.size(); ++h) {
      const Plane e = s.a.e[h];
      if (is_facet(e)) continue;
      const auto k = static_cast<std::uint32_t>(e);
      if (std::find(s.cells.begin(), s.cells.end(), k) == s.cells.end()) s.cells.push_back(k);
    }
  }
}

const EdgeCrossings* RestrictedSurface::find_crossings(std::uint32_t a, std::uint32_t b,
                                                       std::uint32_t c) const {
  std::uint32_t s[3] = {a, b, c};
  small_sort(s, 3);
  for (std::uint32_t e = crossing_begin[s[0]]; e < crossing_begin[s[0] + std::size_t{1}]; ++e) {
    const EdgeCrossings& x = crossings[e];
    if (x.s[1] == s[1] && x.s[2] == s[2]) return &x;
  }
  return nullptr;
}

RestrictedSurface SurfaceRvd::compute(tbb::enumerable_thread_specific<Stars>& stars,
                                      ClippedVoronoi3::Polygons* polygons) const {
  const std::uint32_t n = ctx_.n;
  RestrictedSurface rs;
  tbb::enumerable_thread_specific<Scratch> scratch;
  // Triangles in depth-first order over the surface, in chunks: a triangle takes the
  // cells of its corners from the polygons of the chunk's triangles before it (exact facts,
  // so the order changes nothing but the work).
  const std::uint32_t nb = ctx_.surface.nb_triangles();
  const std::vector<std::uint32_t>& order = ctx_.surface.order();
  const std::uint32_t nb_chunks = (nb + kTriangleChunk - 1) / kTriangleChunk;
  std::vector<Chunk> chunks(nb_chunks);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, nb_chunks, 1), [&](const auto& range) {
    if (!ctx_.running()) return;
    Stars& w = stars.local();
    Scratch& s = scratch.local();
    for (std::uint32_t k = range.begin(); k != range.end(); ++k) {
      const std::uint32_t end = std::min(nb, (k + 1) * kTriangleChunk);
      if (ctx_.callback_density) thread_density_batch().begin(*ctx_.callback_density);
      for (std::uint32_t h = k * kTriangleChunk; h < end; ++h) {
        // In this order the triangles are scattered over the surface's arrays: the corners'
        // indices eight triangles ahead, their coordinates three ahead.
        if (h + 8 < nb) {
          __builtin_prefetch(ctx_.surface.triangle(order[h + 8]));
        }
        if (h + 3 < nb) {
          const std::uint32_t* v = ctx_.surface.triangle(order[h + 3]);
          for (int q = 0; q < 3; ++q) __builtin_prefetch(ctx_.surface.vertex(v[q]));
        }
        clip_triangle(order[h], k + 1, w, s, chunks[k]);
      }
      if (ctx_.callback_density) finish_weighted(chunks[k]);
      ctx_.chunk_done(end - k * kTriangleChunk);
    }
  });
  if (ctx_.poll) ctx_.poll->check();

  // Polygons per triangle (each triangle's are consecutive in its chunk), then per cell in
  // triangle order.
  std::vector<std::uint32_t> tri_chunk(nb), tri_first(nb), tri_count(nb, 0);
  std::vector<std::uint32_t> count(std::size_t{n} + 1, 0);
  std::size_t nb_polygons = 0;
  for (std::uint32_t h = 0; h < nb_chunks; ++h) {
    const Chunk& ch = chunks[h];
    for (std::size_t p = 0; p < ch.cell.size(); ++p) {
      const std::uint32_t b = ch.tri[p];
      if (tri_count[b]++ == 0) {
        tri_chunk[b] = h;
        tri_first[b] = static_cast<std::uint32_t>(p);
      }
      ++count[ch.cell[p] + std::size_t{1}];
    }
    nb_polygons += ch.cell.size();
  }
  for (std::uint32_t i = 0; i < n; ++i) count[i + 1] += count[i];
  rs.is_boundary.assign(n, 0);
  rs.boundary_slot.assign(n, kNone);
  rs.boundary_cells.clear();
  for (std::uint32_t i = 0; i < n; ++i) {
    if (count[i + 1] > count[i]) {
      rs.is_boundary[i] = 1;
      rs.boundary_slot[i] = static_cast<std::uint32_t>(rs.boundary_cells.size());
      rs.boundary_cells.push_back(i);
    }
  }
  // Polygon p of chunk h goes to position pos (cell-major); sums per cell in that order.
  std::vector<std::uint32_t> cursor(count.begin(), count.end() - 1);
  std::vector<std::uint32_t> where_chunk(nb_polygons), where_index(nb_polygons);
  rs.cell_tris.resize(nb_polygons);
  for (std::uint32_t b = 0; b < nb; ++b) {
    const Chunk& ch = chunks[tri_chunk[b]];
    for (std::uint32_t p = tri_first[b]; p < tri_first[b] + tri_count[b]; ++p) {
      const std::uint32_t pos = cursor[ch.cell[p]]++;
      where_chunk[pos] = tri_chunk[b];
      where_index[pos] = p;
      rs.cell_tris[pos] = b;
    }
  }
  rs.cell_tri_begin.assign(rs.boundary_cells.size() + 1, 0);
  for (std::size_t q = 0; q < rs.boundary_cells.size(); ++q) {
    rs.cell_tri_begin[q + 1] = count[rs.boundary_cells[q] + std::size_t{1}];
  }
  rs.surface_area.assign(n, 0);
  rs.surface_moments.assign(rs.boundary_cells.size(), Moments{});
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, rs.boundary_cells.size(), 256), [&](const auto& range) {
        for (std::size_t q = range.begin(); q != range.end(); ++q) {
          Moments& r = rs.surface_moments[q];
          double area = 0;
          for (std::uint32_t pos = rs.cell_tri_begin[q]; pos < rs.cell_tri_begin[q + 1]; ++pos) {
            const double* v = &chunks[where_chunk[pos]].sums[kSums * std::size_t{where_index[pos]}];
            r.volume += v[0];
            for (int c = 0; c < 3; ++c) r.moment[c] += v[1 + c];
            r.energy += v[4];
            area += v[5];
            r.mass += v[6];
          }
          rs.surface_area[rs.boundary_cells[q]] = area;
        }
      });
  if (ctx_.keep_surface && polygons) {
    ClippedVoronoi3::Polygons& sp = *polygons;
    sp.site_begin.assign(count.begin(), count.end());
    sp.site.resize(nb_polygons);
    sp.triangle.resize(nb_polygons);
    sp.polygon_begin.assign(1, 0);
    rs.surface_across.clear();
    for (std::size_t pos = 0; pos < nb_polygons; ++pos) {
      const Chunk& ch = chunks[where_chunk[pos]];
      const std::uint32_t p = where_index[pos];
      sp.site[pos] = ch.cell[p];
      sp.triangle[pos] = ch.tri[p];
      sp.vertices.insert(sp.vertices.end(), ch.verts.begin() + ch.begin[p],
                         ch.verts.begin() + ch.begin[p + 1]);
      rs.surface_across.insert(rs.surface_across.end(), ch.across.begin() + ch.begin[p],
                               ch.across.begin() + ch.begin[p + 1]);
      sp.xyz.insert(sp.xyz.end(), ch.xyz.begin() + 3 * std::size_t{ch.begin[p]},
                    ch.xyz.begin() + 3 * std::size_t{ch.begin[p + 1]});
      sp.polygon_begin.push_back(static_cast<std::uint32_t>(sp.vertices.size()));
    }
  }

  // Crossings per Voronoi edge.
  std::vector<Crossing> all;
  for (const Chunk& ch : chunks) all.insert(all.end(), ch.crossings.begin(), ch.crossings.end());
  // The keys are distinct (a Voronoi edge meets a triangle's plane once, and the cell of
  // the smallest site has one polygon in the triangle): any sort gives the same order.
  tbb::parallel_sort(all.begin(), all.end(), [](const Crossing& x, const Crossing& y) {
    if (x.s[0] != y.s[0]) return x.s[0] < y.s[0];
    if (x.s[1] != y.s[1]) return x.s[1] < y.s[1];
    if (x.s[2] != y.s[2]) return x.s[2] < y.s[2];
    return x.tri < y.tri;
  });
  std::vector<std::uint32_t> group_begin;
  for (std::size_t k = 0; k < all.size(); ++k) {
    if (k == 0 || all[k].s[0] != all[k - 1].s[0] || all[k].s[1] != all[k - 1].s[1] ||
        all[k].s[2] != all[k - 1].s[2]) {
      group_begin.push_back(static_cast<std::uint32_t>(k));
    }
  }
  group_begin.push_back(static_cast<std::uint32_t>(all.size()));
  rs.crossings.resize(group_begin.size() - 1);
  // The points of the edges crossed several times go to multi_crossings, in group order.
  std::vector<std::uint32_t> multi_first(rs.crossings.size(), kNone);
  std::uint32_t nb_multi = 0;
  for (std::size_t g = 0; g < rs.crossings.size(); ++g) {
    const std::uint32_t nb_in_group = group_begin[g + 1] - group_begin[g];
    if (nb_in_group < 2) continue;
    multi_first[g] = nb_multi;
    nb_multi += nb_in_group;
  }
  rs.multi_crossings.resize(nb_multi);
  // The direction of a crossing: sigma, the sign of n . N for the outward normal N of the
  // triangle crossed (Surface3's orientation).
  const auto direction = [&](const Crossing& c) -> std::int8_t {
    const std::uint32_t* v = ctx_.surface.triangle(c.tri);
    const Sign d = voronoi_edge_direction3d(ctx_.site(c.s[0]), ctx_.site(c.s[1]), ctx_.site(c.s[2]),
                                            ctx_.surface.vertex(v[0]), ctx_.surface.vertex(v[1]),
                                            ctx_.surface.vertex(v[2]));
    if (d == Sign::zero) {
      throw Error("clip3d: internal error: the Voronoi edge of sites " + std::to_string(c.s[0]) +
                  ", " + std::to_string(c.s[1]) + ", " + std::to_string(c.s[2]) +
                  " crosses boundary triangle " + std::to_string(c.tri) + " along its plane");
    }
    return d == Sign::positive ? 1 : -1;
  };
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rs.crossings.size(), 1024),
                    [&](const auto& range) {
                      for (std::size_t g = range.begin(); g != range.end(); ++g) {
                        const Crossing& first = all[group_begin[g]];
                        EdgeCrossings& x = rs.crossings[g];
                        x = EdgeCrossings{};
                        for (int q = 0; q < 3; ++q) {
                          x.s[q] = first.s[q];
                          x.x[q] = first.x[q];
                        }
                        x.count = group_begin[g + 1] - group_begin[g];
                        x.first = multi_first[g];
                        if (x.count == 1) {
                          x.sigma = direction(first);
                          continue;
                        }
                        for (std::uint32_t k = 0; k < x.count; ++k) {
                          const Crossing& c = all[group_begin[g] + k];
                          CrossingPoint& point = rs.multi_crossings[x.first + k];
                          for (int q = 0; q < 3; ++q) point.x[q] = c.x[q];
                          point.sigma = direction(c);
                        }
                      }
                    });
  rs.multi_crossed.assign(n, 0);
  for (const EdgeCrossings& x : rs.crossings) {
    if (x.count == 1) continue;
    for (const std::uint32_t c : x.s) rs.multi_crossed[c] = 1;
  }
  rs.crossing_begin.assign(std::size_t{n} + 1, 0);
  for (const EdgeCrossings& x : rs.crossings) ++rs.crossing_begin[x.s[0] + std::size_t{1}];
  for (std::uint32_t i = 0; i < n; ++i) rs.crossing_begin[i + 1] += rs.crossing_begin[i];
  return rs;
}

}  // namespace clip3

}  // namespace voroclip
