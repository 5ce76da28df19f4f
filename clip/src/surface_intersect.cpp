// Exact self-intersection test of a triangle surface: the first pair of triangles (in index
// order) that meet beyond what they share (surface_intersect.h has the contract).
//
// 1. Candidates: a bounding-volume hierarchy over the triangles' boxes. Each box is the
//    min/max of its exact corner coordinates, each node's box the union of its children's,
//    and boxes are compared with <= on both sides: two closed triangles that meet have
//    overlapping boxes, and no rounding is involved, so the filter never drops a pair that
//    meets. The tree is a linear BVH (Lauterbach et al., "Fast BVH construction on GPUs",
//    2009; Karras, "Maximizing parallelism in the construction of BVHs, octrees, and k-d
//    trees", HPG 2012): the triangles sorted by the Morton code of their box centres (10
//    bits per axis, ties by index), each node split where the highest differing bit of its
//    codes changes, down to leaves of at most kLeafSize. The codes only shape the tree;
//    they decide nothing. The tree is then searched against itself: the pairs within a
//    node are those within each child and those across the two, found by descending both
//    sides while their boxes overlap, so every pair of overlapping boxes is met once.
//
// 2. The pair test, by orient3d and orient2d signs only (filtered exact predicates). Two
//    triangles are closed convex sets; if their intersection S contains a point other than
//    a given common vertex v, it has an extreme point other than v (S is compact, convex,
//    with two points or more), and an extreme point of S lies on an edge of one triangle
//    and in the other. So "S holds a point other than v" is the same as "an edge of one
//    triangle meets the other at a point other than v" (with no common vertex: "an edge
//    meets the other"). The cases, by the vertex indices the triangles share:
//    - none: both planes first (all three corners of one strictly on one side of the
//      other's plane: disjoint), then the six edge-triangle tests;
//    - one, v, in (v, a, b) and (v, c, d): the far edges decide, [a, b] meets (v, c, d)
//      or [c, d] meets (v, a, b). Take an extreme point e != v of S on an edge of (v, a, b),
//      say: on [a, b], done; on (v, a], either e = a, on [a, b], or e is inside the edge
//      and on the boundary of (v, c, d) (were it inside, S would reach along va on both
//      sides of e), so on [c, d], or on (v, c] along the same ray as (v, a], where the
//      nearer of a and c lies in the other triangle. Most pairs stop earlier: a and b
//      strictly on one side of the plane of (v, c, d) (or c, d of (v, a, b)) leave v alone
//      in that plane;
//    - two, the edge (u, v), in (u, v, w) and (u, v, x): in distinct planes the triangles
//      meet on the line uv, where each is the edge uv; in one plane they overlap beyond
//      the edge exactly when w and x are on the same side of it.
//    Edge (p, q) against triangle (r, s, t): with p, q strictly on one side of the plane,
//    no; with one of them off the plane, the segment meets the plane at one point, which
//    is in the closed triangle unless two of orient3d(p, q, r, s), (p, q, s, t),
//    (p, q, t, r) have opposite signs (the orientation of the line pq against each edge;
//    cf. Guigue and Devillers, "Fast and robust triangle-triangle overlap test using
//    orientation predicates", JGT 2003); with both in the plane, in 2D.
//    orient3d first tries a static filter whose bound holds for the root box (the whole
//    surface), then the library's semi-static filter and exact stage.
//    Coplanar tests project onto the coordinate plane dropping one axis, chosen so that the
//    triangle's projection has a non-zero orient2d (checked exactly; the largest component
//    of a floating-point normal only orders the tries): an affine bijection of the plane,
//    so every side and incidence is kept.
//
// 3. Fan certificates skip most pairs with a common vertex (on a clean surface nearly all
//    the candidate pairs: each triangle's box meets those of its neighbours). A vertex v is
//    certified when its incident triangles (v, a_j, b_j) chain into one cycle of ring edges
//    (b_j = a_next, back to the first after all of them), and, projected along the axis of
//    the largest component of their summed normals, all have the same strict orientation
//    (orient2d) and their angles at v cover a fixed direction exactly once (a ray from v,
//    counted half-open by coordinate comparisons): the projected triangles then tile a star
//    around v once. Two of them meet in the projection at v only, or along their common
//    edge; the projection is one-to-one on each triangle, so in space too. The pairs whose
//    common vertex, or one end of whose common edge, is certified are not tested; a fan
//    that fails (folded, non-manifold, open, too large) leaves its pairs to the tests.
//
// 4. The answer is the minimum of (a, b) over the pairs that meet: a reduction that does
//    not depend on the order of the visits, so neither does the answer on the thread
//    count. A shared atomic minimum only skips pairs that cannot be smaller than it.
#include "surface_intersect.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "voroclip/predicates.h"

namespace voroclip::detail {

namespace {

constexpr std::uint32_t kLeafSize = 4;
constexpr std::uint64_t kNoKey = ~std::uint64_t{0};

// ---------------------------------------------------------------------------------------
// 2D (projected) tests. A projected point is two coordinates of a 3D point.

struct P2 {
  double v[2];
};

// The point p without coordinate `drop`, the other two in cyclic order (drop + 1, drop + 2).
inline P2 project(const double* p, int drop) {
  static constexpr int kNext[3] = {1, 2, 0};
  const int i = kNext[drop], j = kNext[i];
  return {{p[i], p[j]}};
}

inline Sign orient2(const P2& a, const P2& b, const P2& c) { return orient2d(a.v, b.v, c.v); }

// The coordinate to drop so that the projection of the non-degenerate triangle (a, b, c)
// has a non-zero area: tried in decreasing order of the floating-point normal's
// components, decided by the exact orient2d.
int projection_axis(const double* a, const double* b, const double* c) {
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double n[3] = {std::fabs(u[1] * w[2] - u[2] * w[1]), std::fabs(u[2] * w[0] - u[0] * w[2]),
                       std::fabs(u[0] * w[1] - u[1] * w[0])};
  std::array<int, 3> order = {0, 1, 2};
  std::sort(order.begin(), order.end(), [&](int x, int y) { return n[x] > n[y]; });
  for (int k = 0; k < 2; ++k) {
    const int d = order[static_cast<std::size_t>(k)];
    if (orient2(project(a, d), project(b, d), project(c, d)) != Sign::zero) return d;
  }
  return order[2];  // a non-degenerate triangle has a non-zero projection somewhere
}

// Closed point-in-triangle, `s` the (non-zero) orientation of (a, b, c).
inline bool in_triangle(const P2& p, const P2& a, const P2& b, const P2& c, Sign s) {
  const Sign s0 = orient2(a, b, p);
  if (s0 == -s) return false;
  const Sign s1 = orient2(b, c, p);
  if (s1 == -s) return false;
  return orient2(c, a, p) != -s;
}

// Lexicographic order of projected points: along a line it is the order along the line.
inline bool lex_less(const P2& a, const P2& b) {
  return a.v[0] < b.v[0] || (a.v[0] == b.v[0] && a.v[1] < b.v[1]);
}

// Closed segments [p, q] and [r, s] (non-empty: p != q, r != s) have a common point.
bool segments_meet(const P2& p, const P2& q, const P2& r, const P2& s) {
  const Sign o1 = orient2(p, q, r), o2 = orient2(p, q, s);
  if (o1 == o2 && o1 != Sign::zero) return false;
  const Sign o3 = orient2(r, s, p), o4 = orient2(r, s, q);
  if (o3 == o4 && o3 != Sign::zero) return false;
  if (o1 != Sign::zero || o2 != Sign::zero) return true;
  // Collinear: the two intervals along the line overlap.
  const P2& pq_lo = lex_less(p, q) ? p : q;
  const P2& pq_hi = lex_less(p, q) ? q : p;
  const P2& rs_lo = lex_less(r, s) ? r : s;
  const P2& rs_hi = lex_less(r, s) ? s : r;
  return !lex_less(pq_hi, rs_lo) && !lex_less(rs_hi, pq_lo);
}

// ---------------------------------------------------------------------------------------
// 3D tests on one surface. Triangles are given by their corners' coordinates.

inline bool opposite_signs_among(Sign x, Sign y, Sign z) {
  const bool pos = x == Sign::positive || y == Sign::positive || z == Sign::positive;
  const bool neg = x == Sign::negative || y == Sign::negative || z == Sign::negative;
  return pos && neg;
}

// Closed segment [p, q] and closed triangle (r, s, t) lying in one plane.
bool coplanar_segment_triangle(const double* p, const double* q, const double* r, const double* s,
                               const double* t) {
  const int d = projection_axis(r, s, t);
  const P2 p2 = project(p, d), q2 = project(q, d);
  const P2 r2 = project(r, d), s2 = project(s, d), t2 = project(t, d);
  const Sign o = orient2(r2, s2, t2);
  return in_triangle(p2, r2, s2, t2, o) || in_triangle(q2, r2, s2, t2, o) ||
         segments_meet(p2, q2, r2, s2) || segments_meet(p2, q2, s2, t2) ||
         segments_meet(p2, q2, t2, r2);
}

// Closed segment [p, q] and closed triangle (r, s, t); op, oq are orient3d(r, s, t, p)
// and orient3d(r, s, t, q). `f` is a static filter valid for every corner of the surface.
bool segment_triangle(const double* p, const double* q, const double* r, const double* s,
                      const double* t, Sign op, Sign oq, const StaticFilter& f) {
  if (op == oq) {
    if (op != Sign::zero) return false;
    return coplanar_segment_triangle(p, q, r, s, t);
  }
  // One point of the segment in the plane: inside when the line pq passes the three edges
  // on one side (or on them).
  return !opposite_signs_among(orient3d(p, q, r, s, f), orient3d(p, q, s, t, f),
                               orient3d(p, q, t, r, f));
}

// Triangles (p0, p1, p2) and (q0, q1, q2) without common vertex have a common point.
bool triangles_meet(const double* const p[3], const double* const q[3], const StaticFilter& f) {
  const Sign sq0 = orient3d(p[0], p[1], p[2], q[0], f);
  const Sign sq1 = orient3d(p[0], p[1], p[2], q[1], f);
  const Sign sq2 = orient3d(p[0], p[1], p[2], q[2], f);
  if (sq0 == sq1 && sq1 == sq2 && sq0 != Sign::zero) return false;
  const Sign sp0 = orient3d(q[0], q[1], q[2], p[0], f);
  const Sign sp1 = orient3d(q[0], q[1], q[2], p[1], f);
  const Sign sp2 = orient3d(q[0], q[1], q[2], p[2], f);
  if (sp0 == sp1 && sp1 == sp2 && sp0 != Sign::zero) return false;
  return segment_triangle(p[0], p[1], q[0], q[1], q[2], sp0, sp1, f) ||
         segment_triangle(p[1], p[2], q[0], q[1], q[2], sp1, sp2, f) ||
         segment_triangle(p[2], p[0], q[0], q[1], q[2], sp2, sp0, f) ||
         segment_triangle(q[0], q[1], p[0], p[1], p[2], sq0, sq1, f) ||
         segment_triangle(q[1], q[2], p[0], p[1], p[2], sq1, sq2, f) ||
         segment_triangle(q[2], q[0], p[0], p[1], p[2], sq2, sq0, f);
}

// Triangles (v, a, b) and (v, c, d), with v their only common vertex, have a common point
// other than v. The far edges decide (see the top of the file): [a, b] meets (v, c, d) or
// [c, d] meets (v, a, b).
bool triangles_meet_beyond_vertex(const double* v, const double* a, const double* b,
                                  const double* c, const double* d, const StaticFilter& f) {
  const Sign oa = orient3d(v, c, d, a, f), ob = orient3d(v, c, d, b, f);
  if (oa == ob && oa != Sign::zero) return false;
  const Sign oc = orient3d(v, a, b, c, f), od = orient3d(v, a, b, d, f);
  if (oc == od && oc != Sign::zero) return false;
  return segment_triangle(a, b, v, c, d, oa, ob, f) || segment_triangle(c, d, v, a, b, oc, od, f);
}

// Triangles (u, v, w) and (u, v, x), sharing the edge uv, have a common point off it.
bool triangles_meet_beyond_edge(const double* u, const double* v, const double* w, const double* x,
                                const StaticFilter& f) {
  if (orient3d(u, v, w, x, f) != Sign::zero) return false;
  const int k = projection_axis(u, v, w);
  const P2 u2 = project(u, k), v2 = project(v, k);
  return orient2(u2, v2, project(w, k)) == orient2(u2, v2, project(x, k));
}

// The lowest set bit of a non-zero mask.
inline int lowest_bit(unsigned mask) {
#if defined(__GNUC__)
  return __builtin_ctz(mask);
#else
  int i = 0;
  while ((mask & 1u) == 0) {
    mask >>= 1;
    ++i;
  }
  return i;
#endif
}

// The pair test on triangles ta, tb (3 vertex indices each) of the surface.
// Vertices with certified[v] != 0 have certified fans (below).
bool pair_meets(const double* xyz, const std::uint8_t* certified, const std::uint32_t* ta,
                const std::uint32_t* tb, const StaticFilter& f) {
  const auto pt = [xyz](std::uint32_t i) { return xyz + 3 * std::size_t{i}; };
  // Bit 3 i + j: ta[i] == tb[j] (without branches: which vertices match is unpredictable).
  unsigned shared = 0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      shared |= static_cast<unsigned>(ta[i] == tb[j]) << (3 * i + j);
    }
  }
  if (shared == 0) {
    const double* const p[3] = {pt(ta[0]), pt(ta[1]), pt(ta[2])};
    const double* const q[3] = {pt(tb[0]), pt(tb[1]), pt(tb[2])};
    return triangles_meet(p, q, f);
  }
  const int first = lowest_bit(shared), ia = first / 3, ib = first % 3;
  shared &= shared - 1;
  if (shared == 0) {
    if (certified[ta[ia]] != 0) return false;
    return triangles_meet_beyond_vertex(pt(ta[ia]), pt(ta[(ia + 1) % 3]), pt(ta[(ia + 2) % 3]),
                                        pt(tb[(ib + 1) % 3]), pt(tb[(ib + 2) % 3]), f);
  }
  // Two common vertices (three cannot occur: no two triangles on one vertex set).
  const int second = lowest_bit(shared), ja = second / 3, jb = second % 3;
  assert(ia != ja && ib != jb);  // no repeated vertex in a triangle
  if (certified[ta[ia]] != 0 || certified[ta[ja]] != 0) return false;
  const int wa = 3 - ia - ja, xb = 3 - ib - jb;
  return triangles_meet_beyond_edge(pt(ta[ia]), pt(ta[ja]), pt(ta[wa]), pt(tb[xb]), f);
}

// ---------------------------------------------------------------------------------------
// Fan certificates (step 3 at the top of the file).

// The vertex v (index) with its incident triangles `fan` (indices into `triangles`).
bool certify_fan(const double* xyz, const std::uint32_t* triangles, std::uint32_t v,
                 const std::uint32_t* fan, std::uint32_t k) {
  constexpr std::uint32_t kMaxFan = 32;  // larger fans are left to the pair tests
  if (k < 3 || k > kMaxFan) return false;
  // Ring edge j: (a[j], b[j]), the triangle (v, a[j], b[j]) rotated to start at v.
  std::uint32_t a[kMaxFan], b[kMaxFan];
  double normal[3] = {0, 0, 0};
  const auto pt = [xyz](std::uint32_t i) { return xyz + 3 * std::size_t{i}; };
  for (std::uint32_t j = 0; j < k; ++j) {
    const std::uint32_t* t = triangles + 3 * std::size_t{fan[j]};
    const int r = t[0] == v ? 0 : t[1] == v ? 1 : 2;
    a[j] = t[(r + 1) % 3];
    b[j] = t[(r + 2) % 3];
    const double* p = pt(v);
    const double* q = pt(a[j]);
    const double* w = pt(b[j]);
    const double u0 = q[0] - p[0], u1 = q[1] - p[1], u2 = q[2] - p[2];
    const double w0 = w[0] - p[0], w1 = w[1] - p[1], w2 = w[2] - p[2];
    normal[0] += u1 * w2 - u2 * w1;
    normal[1] += u2 * w0 - u0 * w2;
    normal[2] += u0 * w1 - u1 * w0;
  }
  // One cycle through all k ring edges: following b[j] = a[next] from edge 0 comes back to
  // it after exactly k steps, not before (so the k steps visit k distinct edges). A ring
  // vertex twice in the cycle would turn the angles below around v more than once.
  std::uint32_t cur = 0;
  for (std::uint32_t step = 1; step <= k; ++step) {
    std::uint32_t next = 0;
    while (next < k && a[next] != b[cur]) ++next;
    if (next == k || (next == 0) != (step == k)) return false;
    cur = next;
  }
  // The projection dropping the normal's largest component (a heuristic; the checks below
  // are exact). Every projected triangle has the same strict orientation...
  int drop = 0;
  for (int j = 1; j < 3; ++j) {
    if (std::fabs(normal[j]) > std::fabs(normal[drop])) drop = j;
  }
  const P2 v2 = project(pt(v), drop);
  Sign side = Sign::zero;
  std::uint32_t winding = 0;
  for (std::uint32_t j = 0; j < k; ++j) {
    const P2 a2 = project(pt(a[j]), drop), b2 = project(pt(b[j]), drop);
    const Sign s = orient2(v2, a2, b2);
    if (s == Sign::zero || (side != Sign::zero && s != side)) return false;
    side = s;
    // ... and the direction +x from v lies in exactly one of their angles at v, counted
    // half-open, [a, b) counter-clockwise (an angle below pi: the two comparisons are the
    // signs of cross(a - v, +x) >= 0 and cross(+x, b - v) > 0).
    const P2& from = s == Sign::positive ? a2 : b2;
    const P2& to = s == Sign::positive ? b2 : a2;
    if (from.v[1] <= v2.v[1] && to.v[1] > v2.v[1]) ++winding;
  }
  return winding == 1;
}

// Per vertex, 1 when its fan is certified.
std::vector<std::uint8_t> certify_fans(const std::vector<double>& xyz,
                                       const std::vector<std::uint32_t>& triangles) {
  const auto nv = static_cast<std::uint32_t>(xyz.size() / 3);
  std::vector<std::uint32_t> begin(std::size_t{nv} + 1, 0), fan(triangles.size());
  for (const std::uint32_t v : triangles) ++begin[v + 1];
  for (std::uint32_t v = 0; v < nv; ++v) begin[v + 1] += begin[v];
  std::vector<std::uint32_t> fill(begin.begin(), begin.end() - 1);
  for (std::size_t c = 0; c < triangles.size(); ++c) {
    fan[fill[triangles[c]]++] = static_cast<std::uint32_t>(c / 3);
  }
  std::vector<std::uint8_t> certified(nv, 0);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, nv, 4096), [&](const auto& range) {
    for (std::uint32_t v = range.begin(); v != range.end(); ++v) {
      certified[v] =
          certify_fan(xyz.data(), triangles.data(), v, &fan[begin[v]], begin[v + 1] - begin[v]) ? 1
                                                                                                : 0;
    }
  });
  return certified;
}

// ---------------------------------------------------------------------------------------
// Bounding-volume hierarchy.

struct Box {
  double lo[3], hi[3];
};

inline bool boxes_overlap(const Box& x, const Box& y) {
  return x.lo[0] <= y.hi[0] && y.lo[0] <= x.hi[0] && x.lo[1] <= y.hi[1] && y.lo[1] <= x.hi[1] &&
         x.lo[2] <= y.hi[2] && y.lo[2] <= x.hi[2];
}

inline void grow(Box& x, const Box& y) {
  for (int j = 0; j < 3; ++j) {
    x.lo[j] = std::min(x.lo[j], y.lo[j]);
    x.hi[j] = std::max(x.hi[j], y.hi[j]);
  }
}

// Node layout: depth first, an inner node's first child follows it, `right` is the index
// of its second child (0 for a leaf). The node covers positions [begin, end) of the leaf
// order.
struct Node {
  Box box;
  std::uint32_t begin, end, right;
};

// Spreads the 10 low bits of x to every third bit.
inline std::uint32_t spread_bits(std::uint32_t x) {
  x &= 0x3ffu;
  x = (x | (x << 16)) & 0x30000ffu;
  x = (x | (x << 8)) & 0x300f00fu;
  x = (x | (x << 4)) & 0x30c30c3u;
  x = (x | (x << 2)) & 0x9249249u;
  return x;
}

class Hierarchy {
 public:
  Hierarchy(const double* xyz, const std::uint32_t* triangles, std::uint32_t n) {
    std::vector<Box> box(n);
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, n, 4096), [&](const auto& range) {
      for (std::uint32_t t = range.begin(); t != range.end(); ++t) {
        const double* p = xyz + 3 * std::size_t{triangles[3 * std::size_t{t}]};
        Box& b = box[t];
        for (int j = 0; j < 3; ++j) b.lo[j] = b.hi[j] = p[j];
        for (std::size_t k = 1; k < 3; ++k) {
          const double* q = xyz + 3 * std::size_t{triangles[3 * std::size_t{t} + k]};
          for (int j = 0; j < 3; ++j) {
            b.lo[j] = std::min(b.lo[j], q[j]);
            b.hi[j] = std::max(b.hi[j], q[j]);
          }
        }
      }
    });
    // Half-extents and offsets (halved before subtracting, so nothing overflows), mapped
    // to 10 bits per axis on one scale (cubic cells).
    Box all = box[0];
    for (std::uint32_t t = 1; t < n; ++t) grow(all, box[t]);
    double extent = 0;
    for (int j = 0; j < 3; ++j) extent = std::max(extent, 0.5 * all.hi[j] - 0.5 * all.lo[j]);
    std::vector<std::uint32_t> code(n);
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, n, 4096), [&](const auto& range) {
      for (std::uint32_t t = range.begin(); t != range.end(); ++t) {
        std::uint32_t c = 0;
        for (int j = 0; j < 3; ++j) {
          // The box centre's offset from the low corner, halved: in [0, extent].
          const double h = 0.5 * (0.5 * box[t].lo[j] - 0.5 * all.lo[j]) +
                           0.5 * (0.5 * box[t].hi[j] - 0.5 * all.lo[j]);
          const double q = extent > 0 ? 1023.0 * std::min(h / extent, 1.0) : 0.0;
          c |= spread_bits(static_cast<std::uint32_t>(q)) << j;
        }
        code[t] = c;
      }
    });
    sort_by_code(code);
    codes_.resize(n);
    leaf_box_.resize(n);
    corners_.resize(3 * std::size_t{n});
    for (std::uint32_t k = 0; k < n; ++k) {
      const std::uint32_t t = order_[k];
      codes_[k] = code[t];
      leaf_box_[k] = box[t];
      std::copy_n(triangles + 3 * std::size_t{t}, 3, &corners_[3 * std::size_t{k}]);
    }
    nodes_.reserve(2 * (std::size_t{n} / 2 + 1));
    build(0, n);
    codes_ = {};
  }

  std::uint32_t triangle(std::uint32_t k) const { return order_[k]; }
  const Node& node(std::uint32_t i) const { return nodes_[i]; }
  const Box& box(std::uint32_t k) const { return leaf_box_[k]; }
  const std::uint32_t* corners(std::uint32_t k) const { return &corners_[3 * std::size_t{k}]; }

 private:
  // order_ = the triangles sorted by code, ties by index: a stable radix sort, 3 passes
  // of 10 bits.
  void sort_by_code(const std::vector<std::uint32_t>& code) {
    const auto n = static_cast<std::uint32_t>(code.size());
    std::vector<std::uint32_t> from(n), to(n);
    for (std::uint32_t t = 0; t < n; ++t) from[t] = t;
    for (int shift = 0; shift < 30; shift += 10) {
      std::vector<std::uint32_t> start(1025, 0);
      for (std::uint32_t t = 0; t < n; ++t) ++start[((code[t] >> shift) & 0x3ffu) + 1];
      for (std::size_t d = 1; d <= 1024; ++d) start[d] += start[d - 1];
      for (std::uint32_t t : from) to[start[(code[t] >> shift) & 0x3ffu]++] = t;
      from.swap(to);
    }
    order_ = std::move(from);
  }

  // Node over positions [begin, end): split where the highest bit that differs between
  // the codes of its ends changes (an octree-like cell split), at the median when all the
  // codes are equal; a leaf at kLeafSize or fewer.
  std::uint32_t build(std::uint32_t begin, std::uint32_t end) {
    const auto index = static_cast<std::uint32_t>(nodes_.size());
    nodes_.push_back({leaf_box_[begin], begin, end, 0});
    if (end - begin <= kLeafSize) {
      for (std::uint32_t k = begin + 1; k < end; ++k) grow(nodes_[index].box, leaf_box_[k]);
      return index;
    }
    std::uint32_t mid = begin + (end - begin) / 2;
    const std::uint32_t differ = codes_[begin] ^ codes_[end - 1];
    if (differ != 0) {
      std::uint32_t bit = 1u << 31;
      while ((differ & bit) == 0) bit >>= 1;
      mid = static_cast<std::uint32_t>(
          std::partition_point(codes_.begin() + begin, codes_.begin() + end,
                               [bit](std::uint32_t c) { return (c & bit) == 0; }) -
          codes_.begin());
    }
    build(begin, mid);
    const std::uint32_t right = build(mid, end);
    Box b = nodes_[index + 1].box;
    grow(b, nodes_[right].box);
    nodes_[index].box = b;
    nodes_[index].right = right;
    return index;
  }

  std::vector<std::uint32_t> order_;    // position -> triangle
  std::vector<std::uint32_t> codes_;    // per position, during the construction
  std::vector<Box> leaf_box_;           // per position
  std::vector<std::uint32_t> corners_;  // per position, the triangle's 3 vertices
  std::vector<Node> nodes_;
};

// The smaller of `key` and the atomic's value is stored.
inline void atomic_min(std::atomic<std::uint64_t>& a, std::uint64_t key) {
  std::uint64_t cur = a.load(std::memory_order_relaxed);
  while (key < cur && !a.compare_exchange_weak(cur, key, std::memory_order_relaxed)) {
  }
}

// The search over pairs of overlapping boxes: the hierarchy against itself. self(N)
// visits the pairs within node N: those within each child, then those across the two
// children, cross(L, R), which descends into the larger side while the boxes overlap. Every
// pair of positions is reached from their lowest common ancestor only, so once. Large
// nodes fork into parallel tasks.
class PairSearch {
 public:
  PairSearch(const Hierarchy& tree, const double* xyz, const std::uint8_t* certified)
      : tree_(tree),
        xyz_(xyz),
        certified_(certified),
        filter_(tree.node(0).box.lo, tree.node(0).box.hi, 3) {}

  void run() { self(0); }
  std::uint64_t best() const { return best_.load(); }

 private:
  static constexpr std::uint32_t kTaskSize = 2048;  // fork below nodes this large

  static std::uint32_t size(const Node& n) { return n.end - n.begin; }

  void self(std::uint32_t i) {
    const Node& n = tree_.node(i);
    if (n.right == 0) {
      for (std::uint32_t k = n.begin; k < n.end; ++k) {
        for (std::uint32_t k2 = k + 1; k2 < n.end; ++k2) {
          if (boxes_overlap(tree_.box(k), tree_.box(k2))) test(k, k2);
        }
      }
      return;
    }
    const std::uint32_t left = i + 1, right = n.right;
    const bool overlap = boxes_overlap(tree_.node(left).box, tree_.node(right).box);
    if (size(n) >= kTaskSize) {
      tbb::parallel_invoke([&] { self(left); }, [&] { self(right); },
                           [&] {
                             if (overlap) cross(left, right);
                           });
    } else {
      self(left);
      self(right);
      if (overlap) cross(left, right);
    }
  }

  // Nodes i and j, whose boxes overlap.
  void cross(std::uint32_t i, std::uint32_t j) {
    const Node& a = tree_.node(i);
    const Node& b = tree_.node(j);
    if (a.right == 0 && b.right == 0) {
      for (std::uint32_t k = a.begin; k < a.end; ++k) {
        const Box& bk = tree_.box(k);
        if (!boxes_overlap(bk, b.box)) continue;
        for (std::uint32_t k2 = b.begin; k2 < b.end; ++k2) {
          if (boxes_overlap(bk, tree_.box(k2))) test(k, k2);
        }
      }
      return;
    }
    // Split the larger node (a leaf is never split).
    const bool split_a = b.right == 0 || (a.right != 0 && size(a) >= size(b));
    const std::uint32_t c0 = split_a ? i + 1 : j + 1, c1 = split_a ? a.right : b.right;
    const std::uint32_t other = split_a ? j : i;
    const Box& ob = tree_.node(other).box;
    const bool overlap0 = boxes_overlap(tree_.node(c0).box, ob);
    const bool overlap1 = boxes_overlap(tree_.node(c1).box, ob);
    if (overlap0 && overlap1 && size(a) + size(b) >= kTaskSize) {
      tbb::parallel_invoke([&] { cross(c0, other); }, [&] { cross(c1, other); });
    } else {
      if (overlap0) cross(c0, other);
      if (overlap1) cross(c1, other);
    }
  }

  // Positions k and k2 (distinct): their triangles' pair, unless it cannot be smaller
  // than the best so far.
  void test(std::uint32_t k, std::uint32_t k2) {
    const std::uint32_t t = tree_.triangle(k), u = tree_.triangle(k2);
    const std::uint64_t key = (std::uint64_t{std::min(t, u)} << 32) | std::max(t, u);
    if (key >= best_.load(std::memory_order_relaxed)) return;
    if (pair_meets(xyz_, certified_, tree_.corners(k), tree_.corners(k2), filter_)) {
      atomic_min(best_, key);
    }
  }

  const Hierarchy& tree_;
  const double* xyz_;
  const std::uint8_t* certified_;
  // The orient3d bound for points in the root box, which holds every corner.
  const StaticFilter filter_;
  // The smallest key (a << 32 | b) of a pair found so far; pairs with a larger key are
  // skipped, so the final value is the minimum over all pairs that meet.
  std::atomic<std::uint64_t> best_{kNoKey};
};

}  // namespace

TrianglePair first_intersecting_pair(const std::vector<double>& xyz,
                                     const std::vector<std::uint32_t>& triangles) {
  const auto n = static_cast<std::uint32_t>(triangles.size() / 3);
  TrianglePair out;
  if (n < 2) return out;
  const std::vector<std::uint8_t> certified = certify_fans(xyz, triangles);
  const Hierarchy tree(xyz.data(), triangles.data(), n);
  PairSearch search(tree, xyz.data(), certified.data());
  search.run();
  const std::uint64_t key = search.best();
  if (key != kNoKey) {
    out.a = static_cast<std::uint32_t>(key >> 32);
    out.b = static_cast<std::uint32_t>(key & 0xffffffffu);
  }
  return out;
}

}  // namespace voroclip::detail
