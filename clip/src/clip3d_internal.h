// Internals of the 3D clipped Voronoi diagram (clip3d.cpp describes the algorithm): the
// shared state of one compute() and the helpers of its three source files,
//   clip3d_kernel.cpp   exact symbolic clipping of a tet (or a triangle) by a cell, and the
//                       tet-by-tet integration of a cell (sec. 4.2: the reference path);
//   clip3d_surface.cpp  the restricted surface, triangle by triangle;
//   clip3d_cells.cpp    inner and boundary cells from the Delaunay triangulation.
#pragma once

#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <type_traits>
#include <utility>
#include <vector>

#include "voroclip/clip.h"

namespace voroclip {

namespace clip3 {

constexpr std::uint32_t kNone = 0xffffffffu;

// A plane of a clip: facet f (0..3) of the current tet is -(f + 1); the bisector of the
// cell's site and site k is k.
using Plane = std::int32_t;
inline bool is_facet(Plane p) { return p < 0; }
inline int facet_of(Plane p) { return -p - 1; }
inline Plane facet_plane(int f) { return -(f + 1); }

// A vertex of a clip: the three planes that define it (any order).
struct PVertex {
  Plane p[3];
};

// A convex polyhedron (several faces) or polygon (one face). Face k lies on plane
// face_plane[k] and has the vertices face_verts[face_begin[k] .. face_begin[k + 1]).
// Faces are oriented consistently (adjacent faces run through a shared edge in opposite
// directions): the tet's facets as in Domain3::kTetFacetVertex.
struct Poly {
  std::vector<PVertex> verts;
  std::vector<Plane> face_plane;
  std::vector<std::uint32_t> face_begin{0};
  std::vector<std::uint32_t> face_verts;

  void clear() {
    verts.clear();
    face_plane.clear();
    face_begin.assign(1, 0);
    face_verts.clear();
  }
  std::uint32_t nb_faces() const { return static_cast<std::uint32_t>(face_plane.size()); }
  bool empty() const { return face_plane.empty(); }
};

// A vertex of a boundary triangle clipped by cell c: tag 0..2, corner `tag` of the triangle;
// 3..5, the triangle edge opposite corner tag - 3 ∩ bisector(c, k); 6, the triangle's plane
// ∩ bisector(c, k) ∩ bisector(c, l), k < l.
// fk, fl: while the triangle is clipped by cell c, the rows of CornerValues of the
// bisectors (c, k) and (c, l); fm: the row of FacetMinors of a point inside (tag 6)
// (clip3d_surface.cpp).
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
// the sign of D = m[0] + m[1] + m[2] when decided (0 otherwise; clip3d_surface.cpp).
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

// Insertion sort of a few ids (std::sort on tiny arrays trips -Warray-bounds in GCC 12).
template <class T>
void small_sort(T* a, int n) {
  for (int k = 1; k < n; ++k) {
    for (int q = k; q > 0 && a[q - 1] > a[q]; --q) std::swap(a[q - 1], a[q]);
  }
}

// Four ids sorted by a network of min/max (no branch: the order of a tet's vertices is
// unpredictable); the same result as small_sort.
inline void sort4(std::uint32_t* a) {
  const auto exchange = [a](int i, int j) {
    const std::uint32_t lo = std::min(a[i], a[j]), hi = std::max(a[i], a[j]);
    a[i] = lo;
    a[j] = hi;
  };
  exchange(0, 1);
  exchange(2, 3);
  exchange(0, 2);
  exchange(1, 3);
  exchange(1, 2);
}

// The plane shared by vertices u and w (adjacent along an edge) other than `face`.
Plane other_common_plane(const PVertex& u, const PVertex& w, Plane face);

// Integrals over a region relative to a site x: volume, mass (only with a linear density),
// energy ∫rho |y - x|^2 (rho = 1 for the constant density: the caller scales), first
// moment ∫rho (y - x).
struct Moments {
  double volume = 0, mass = 0, energy = 0, moment[3] = {0, 0, 0};
  void add(const Moments& o) {
    volume += o.volume;
    mass += o.mass;
    energy += o.energy;
    for (int c = 0; c < 3; ++c) moment[c] += o.moment[c];
  }
};

// The signed tet (x, x + a, x + b, x + c) for vectors relative to x: volume
// det(a, b, c) / 6, positive when the triangle (a, b, c) is counter-clockwise seen from
// outside (its right-hand normal points away from x). Centroid (a + b + c) / 4 and
// ∫|y - x|^2 = V / 10 (|a|^2 + |b|^2 + |c|^2 + a.b + a.c + b.c).
inline void add_cone(const double* a, const double* b, const double* c, Moments& r) {
  const double det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                     a[2] * (b[0] * c[1] - b[1] * c[0]);
  const double vol = det / 6;
  r.volume += vol;
  for (int k = 0; k < 3; ++k) r.moment[k] += vol * (a[k] + b[k] + c[k]) / 4;
  r.energy +=
      vol / 10 *
      ((a[0] * a[0] + a[1] * a[1] + a[2] * a[2]) + (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]) +
       (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) + (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) +
       (a[0] * c[0] + a[1] * c[1] + a[2] * c[2]) + (b[0] * c[0] + b[1] * c[1] + b[2] * c[2]));
}

// The integrals of a density rho over the signed tet (x, x + a, x + b, x + c) (vectors
// relative to x, sign as add_cone): r.volume += det / 6, r.mass += ∫rho, r.moment +=
// ∫rho (y - x), r.energy += ∫rho |y - x|^2, by Walkington's 14-point rule of degree 5
// (positive weights; "Quadrature on simplices of arbitrary dimension", 2000): two orbits
// of 4 points (a, a, a, 1 - 3a) and one of 6 points (b, b, 1/2 - b, 1/2 - b) in barycentric
// coordinates. Exact for polynomials of degree <= 5, so for rho of degree <= 3 (the
// energy's integrand is rho |y - x|^2); tests/clip/test_clip3d.cpp checks it on monomials.
struct TetRule {
  double l[3];  // barycentric coordinates of the points x + a, x + b, x + c
  double w;     // weight, the 14 summing to 1
};
inline constexpr TetRule kTetRule[14] = {
    {{0.31088591926330060980, 0.31088591926330060980, 0.31088591926330060980},
     0.11268792571801585080},
    {{0.06734224221009817060, 0.31088591926330060980, 0.31088591926330060980},
     0.11268792571801585080},
    {{0.31088591926330060980, 0.06734224221009817060, 0.31088591926330060980},
     0.11268792571801585080},
    {{0.31088591926330060980, 0.31088591926330060980, 0.06734224221009817060},
     0.11268792571801585080},
    {{0.092735250310891226402, 0.092735250310891226402, 0.092735250310891226402},
     0.073493043116361949544},
    {{0.72179424906732632079, 0.092735250310891226402, 0.092735250310891226402},
     0.073493043116361949544},
    {{0.092735250310891226402, 0.72179424906732632079, 0.092735250310891226402},
     0.073493043116361949544},
    {{0.092735250310891226402, 0.092735250310891226402, 0.72179424906732632079},
     0.073493043116361949544},
    {{0.045503704125649649492, 0.045503704125649649492, 0.45449629587435035051},
     0.042546020777081466438},
    {{0.045503704125649649492, 0.45449629587435035051, 0.045503704125649649492},
     0.042546020777081466438},
    {{0.45449629587435035051, 0.045503704125649649492, 0.045503704125649649492},
     0.042546020777081466438},
    {{0.045503704125649649492, 0.45449629587435035051, 0.45449629587435035051},
     0.042546020777081466438},
    {{0.45449629587435035051, 0.045503704125649649492, 0.45449629587435035051},
     0.042546020777081466438},
    {{0.45449629587435035051, 0.45449629587435035051, 0.045503704125649649492},
     0.042546020777081466438},
};

inline void add_tet_weighted(const Density3& rho, const double* x, const double* a, const double* b,
                             const double* c, Moments& r) {
  const double det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                     a[2] * (b[0] * c[1] - b[1] * c[0]);
  r.volume += det / 6;
  double m = 0, mom[3] = {0, 0, 0}, e = 0;
  for (const TetRule& q : kTetRule) {
    double y[3];
    for (int k = 0; k < 3; ++k) y[k] = (q.l[0] * a[k] + q.l[1] * b[k]) + q.l[2] * c[k];
    const double f = q.w * rho.callback(x[0] + y[0], x[1] + y[1], x[2] + y[2]);
    m += f;
    for (int k = 0; k < 3; ++k) mom[k] += f * y[k];
    e += f * ((y[0] * y[0] + y[1] * y[1]) + y[2] * y[2]);
  }
  const double v = det / 6;
  r.mass += v * m;
  for (int k = 0; k < 3; ++k) r.moment[k] += v * mom[k];
  r.energy += v * e;
}

// A point relative to a site: y = (x - p_i) and |y|^2.
struct Rel {
  double y[3], yy;
};
inline Rel rel(const double* x, const double* pi) {
  Rel r;
  for (int k = 0; k < 3; ++k) r.y[k] = x[k] - pi[k];
  r.yy = (r.y[0] * r.y[0] + r.y[1] * r.y[1]) + r.y[2] * r.y[2];
  return r;
}

// Sums over the Voronoi edge pieces of a cell, scaled: volume 6 V, first moment 24 M,
// energy 60 E (see add_edge_piece).
struct PieceSums {
  double v = 0, m[3] = {0, 0, 0}, e = 0;
  void add_to(Moments& r) const {
    r.volume += v * (1.0 / 6);
    for (int k = 0; k < 3; ++k) r.moment[k] += m[k] * (1.0 / 24);
    r.energy += e * (1.0 / 60);
  }
};

// The foot of bisector(i, j) seen from p_i: h = (p_j - p_i) / 2 and hh3 = 3 |h|^2. Every
// point y of the bisector has h . y = |h|^2 (add_edge_piece).
struct Foot {
  double y[3], hh3;
};
inline Foot foot(const double* pj, const double* pi) {
  Foot f;
  for (int k = 0; k < 3; ++k) f.y[k] = 0.5 * (pj[k] - pi[k]);
  f.hh3 = 3 * ((f.y[0] * f.y[0] + f.y[1] * f.y[1]) + f.y[2] * f.y[2]);
  return f;
}

// The feet of a cell's neighbours, direct-mapped by site id (a neighbour is in about six
// star tets of the cell; a slot holds the last site mapped to it). Per cell, on the stack.
class FootCache {
 public:
  static constexpr std::uint32_t kSlots = 64;
  FootCache() {
    for (std::uint32_t& s : site_) s = kNone;
  }
  // The foot of site v (at pv) seen from pi.
  const Foot& get(std::uint32_t v, const double* pv, const double* pi) {
    const std::uint32_t slot = v & (kSlots - 1);
    if (site_[slot] != v) {
      site_[slot] = v;
      foot_[slot] = foot(pv, pi);
    }
    return foot_[slot];
  }

 private:
  std::uint32_t site_[kSlots];
  Foot foot_[kSlots];
};

// A piece [P, Q] of the Voronoi edge dual to Delaunay triangle (i, j, k), P -> Q running
// counter-clockwise around p_j - p_i (so clockwise around p_k - p_i), with u = P - p_i,
// w = Q - p_i (Rel: with their squared norms) and the feet hj, hk of bisectors (i, j) and
// (i, k). It bounds the facets of cell i on those bisectors: its share of the cones from
// p_i over them is
//   cone(hj, u, w) - cone(hk, u, w)
// (add_cone, outward: the facet on bisector(i, j) is counter-clockwise around its outward
// normal p_j - p_i). With a = h . (u x w), s = u + w, q = |u|^2 + |w|^2 + u . w, a cone has
// volume a / 6, moment a (h + s) / 24 and energy a (|h|^2 + h . s + q) / 60, where
// h . s = 2 |h|^2 since u and w lie on the bisector (the piece lies on both): energy
// a (3 |h|^2 + q) / 60.
inline void add_edge_piece(const Foot& hj, const Foot& hk, const Rel& u, const Rel& w,
                           PieceSums& r) {
  const double a0 = u.y[0], a1 = u.y[1], a2 = u.y[2];
  const double b0 = w.y[0], b1 = w.y[1], b2 = w.y[2];
  const double c0 = a1 * b2 - a2 * b1, c1 = a2 * b0 - a0 * b2, c2 = a0 * b1 - a1 * b0;
  const double s0 = a0 + b0, s1 = a1 + b1, s2 = a2 + b2;
  const double q = (u.yy + w.yy) + ((a0 * b0 + a1 * b1) + a2 * b2);
  const double j0 = hj.y[0], j1 = hj.y[1], j2 = hj.y[2];
  const double k0 = hk.y[0], k1 = hk.y[1], k2 = hk.y[2];
  const double aj = (j0 * c0 + j1 * c1) + j2 * c2;
  const double ak = (k0 * c0 + k1 * c1) + k2 * c2;
  const double d = aj - ak;
  r.v += d;
  r.m[0] += (aj * j0 - ak * k0) + d * s0;
  r.m[1] += (aj * j1 - ak * k1) + d * s1;
  r.m[2] += (aj * j2 - ak * k2) + d * s2;
  r.e += (aj * hj.hh3 - ak * hk.hh3) + d * q;
}

// True when |v - p_c|^2 < |v - p_j|^2 certainly: v is strictly on c's side of
// bisector(c, j), whatever the perturbation (which only breaks exact ties). Floating-point
// filter: with a = v - p_c, b = v - p_j rounded (relative error u = 2^-53 each), the sums of
// squares A, B carry a relative error below gamma_5 (three products, two sums of
// non-negative terms) and A - B one more rounding, so |(A - B) - F| <= gamma_6 (A + B) /
// (1 - gamma_5) < 6.01 u (A + B) for the exact F = |v - p_c|^2 - |v - p_j|^2; the bound is
// taken as 8 u (A + B) (its own rounding included). Underflow: each product that underflows
// errs by at most 2^-1074, covered by the 1e-300 term. Overflow and NaN make the
// comparison fail (infinite bound, NaN value): the caller then asks the exact predicate.
inline bool certainly_nearer(const double* v, const double* pc, const double* pj) {
  const double a0 = v[0] - pc[0], a1 = v[1] - pc[1], a2 = v[2] - pc[2];
  const double b0 = v[0] - pj[0], b1 = v[1] - pj[1], b2 = v[2] - pj[2];
  const double A = (a0 * a0 + a1 * a1) + a2 * a2;
  const double B = (b0 * b0 + b1 * b1) + b2 * b2;
  return A - B < -(8.9e-16 * (A + B) + 1e-300);
}

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

// Circumcentres of the Delaunay tets one thread's cells have met, direct-mapped by tet
// slot. Cells go in Hilbert order of their sites, so a tet's four cells mostly come close
// together and its circumcentre is computed about once, from sites the cells read anyway:
// this replaced a pass over all tets into a 24-byte-per-tet array (156 MB at 10^6 sites)
// whose random reads of the sites cost more than the cells themselves.
class CircumcentreCache {
 public:
  struct Entry {
    std::uint32_t tet;
    double x[3];
  };
  static constexpr std::uint32_t kSlots = std::uint32_t{1} << 15;  // 1 MB
  // The entry for tet t (its x is valid when entry.tet == t).
  Entry& entry(std::uint32_t t) { return entries_[t & (kSlots - 1)]; }
  void prefetch(std::uint32_t t) const { __builtin_prefetch(&entries_[t & (kSlots - 1)]); }

 private:
  std::vector<Entry> entries_ = std::vector<Entry>(kSlots, Entry{kNone, {0, 0, 0}});
};

// Tets around a vertex of the triangulation, breadth first through the facets that contain
// it, from vertex_tet (the order is a function of the triangulation: deterministic).
// mark[t] >= first iff t is in the current star, at position mark[t] - first; each
// traversal starts where the previous one ended, so no clearing is needed (until the
// counter nears 2^32).
struct Star {
  std::vector<std::uint32_t> tets;
  std::vector<std::uint32_t> mark;
  std::uint32_t first = 1, next = 1;
  bool contains(std::uint32_t t) const { return mark[t] >= first; }
  std::uint32_t pos(std::uint32_t t) const { return mark[t] - first; }
  // Makes mark one entry per tet slot, cleared, when it is not (or the counter nears 2^32).
  void reset_if_needed(std::uint32_t slots) {
    if (mark.size() == slots && next <= 0xf0000000u) return;
    mark.assign(slots, 0);
    next = 1;
  }
};

// Local numbering of the Voronoi edges around a tet's vertex: for vertex li of a positive
// tet (Delaunay3) and a facet f != li, kFaceOther[li][f] = {lj, lk}, the other two vertices
// of facet f, so that (li, lj, lk, f) is an even permutation of (0, 1, 2, 3). Then the
// Voronoi edge dual to that facet, from this tet's circumcentre to the next tet's across
// f, runs counter-clockwise around p_lj - p_li (clip3d_cells.cpp).
extern const std::int8_t kFaceOther[4][4][2];

}  // namespace clip3

// The state of one ClippedVoronoi3::compute().
struct Clip3Impl {
  using Moments = clip3::Moments;
  using Plane = clip3::Plane;
  using PVertex = clip3::PVertex;
  using Poly = clip3::Poly;
  using TriPoly = clip3::TriPoly;
  using Star = clip3::Star;

  // The surface drives everything; the domain's tets only the tet-by-tet clipping
  // (tet_clipping, a density linear per tet).
  const Domain3& domain;
  const Surface3& surface;
  const Delaunay3& dt;
  const Clip3Options& options;
  ClippedVoronoi3& out;
  Clip3Impl(const Domain3& d, const Delaunay3& t, const Clip3Options& o, ClippedVoronoi3& r)
      : domain(d), surface(d.surface()), dt(t), options(o), out(r) {}

  std::uint32_t n = 0;
  // A non-constant density: the cells' integrals are weighted (Moments::mass).
  bool weighted = false;
  // A density linear per tet: every cell is clipped tet by tet.
  bool linear_density = false;
  // A density given as a function: quadrature on the cells' cone decompositions.
  const Density3* callback_density = nullptr;
  bool keep_surface = false;
  // Where cell i goes in the output (compute(domain, sites, n)), or nullptr: cell i.
  const std::uint32_t* input_index = nullptr;

  const double* site(std::uint32_t i) const { return dt.point(i); }
  // (After a build an infinite tet has kInfinite as its vertex 3: Delaunay3.)
  bool infinite(std::uint32_t t) const { return dt.is_infinite(t); }

  // ---- Exact clipping kernel (clip3d_kernel.cpp).
  struct Scratch {
    Poly a, b;
    std::vector<std::int8_t> sides;
    std::vector<std::uint64_t> edge_keys;
    std::vector<std::uint32_t> edge_new;
    std::vector<std::uint32_t> chain_next;
    std::vector<std::uint32_t> remap;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> cut_edges;
    std::vector<std::uint32_t> nbrs;
    std::vector<double> xyz;
    std::vector<std::uint32_t> stamp;  // per domain tet: the last cell (+ 1) that queued it
    std::vector<std::uint32_t> queue;
  };
  // Exact side of a vertex of a clip in tet t of cell i with respect to bisector(i, j):
  // POSITIVE when on j's side (clipped away).
  Sign side(const PVertex& v, std::uint32_t t, std::uint32_t i, std::uint32_t j) const;
  // Coordinates of a vertex, from its sorted global ids (bit-identical in every cell).
  void coords(const PVertex& v, std::uint32_t t, std::uint32_t i, double* x) const;
  // Mesh edge (ma, mb) ∩ bisector(s0, s1), and the plane of triangle mesh[0..2] ∩
  // bisectors (s0, s1), (s0, s2), from sorted ids (the same bits wherever they are met).
  void edge_point(std::uint32_t ma, std::uint32_t mb, std::uint32_t s0, std::uint32_t s1,
                  double* x) const;
  void facet_point(const std::uint32_t* mesh, const std::uint32_t* sites, double* x) const;
  // The Voronoi vertex (circumcentre) of sites[0..3], sorted: the same bits for the cells
  // (through circumcentre() below) and the tet-by-tet clipping.
  void voronoi_point(const std::uint32_t* sites, double* x) const;
  // The circumcentre of finite tet t with vertices v[0..3] (as stored), through the cache:
  // voronoi_point's bits.
  const double* circumcentre(std::uint32_t t, const std::uint32_t* v,
                             clip3::CircumcentreCache& cache) const {
    clip3::CircumcentreCache::Entry& e = cache.entry(t);
    if (e.tet != t) {
      std::uint32_t sorted[4] = {v[0], v[1], v[2], v[3]};
      clip3::sort4(sorted);
      voronoi_point(sorted, e.x);
      e.tet = t;
    }
    return e.x;
  }
  static void init_tet(Poly& p, int only_facet);
  bool clip(const Poly& in, Poly& res, std::uint32_t t, std::uint32_t i, std::uint32_t j,
            Scratch& s) const;
  void clip_by_cell(std::uint32_t t, int only_facet, std::uint32_t i,
                    const std::vector<std::uint32_t>& nbrs, Scratch& s) const;
  // The output of a cell clipped tet by tet.
  struct CellOut : Moments {
    std::uint64_t pairs = 0;
    std::vector<std::uint32_t> face_begin{0};
    std::vector<std::uint32_t> face_piece;
    std::vector<std::uint32_t> face_across;  // as ClippedVoronoi3::Polygons::across
    std::vector<double> face_xyz;
  };
  void clip_cell(std::uint32_t c, const std::uint32_t* seeds, std::size_t nb_seeds, Scratch& s,
                 CellOut& res,
                 std::vector<std::pair<std::uint32_t, std::uint32_t>>* seeds_out) const;
  static void add_tet(const double* o, const double* a, const double* b, const double* d,
                      Moments& res);
  void add_tet_linear(std::uint32_t t, const double* o, const double* a, const double* b,
                      const double* d, Moments& res) const;
  double density_at(std::uint32_t t, const double* x) const;

  // A Voronoi edge crossing the surface: Delaunay triangle (s[0] < s[1] < s[2]), the
  // boundary triangle, the point.
  struct Crossing {
    std::uint32_t s[3], tri;
    double x[3];
  };
  // The crossings of one Voronoi edge: how many, the point when there is one, and sigma,
  // the sign of n . N with n = (p_s1 - p_s0) x (p_s2 - p_s0) and N the outward normal of
  // the boundary triangle crossed (voronoi_edge_direction3d): the edge, oriented along n,
  // leaves the volume there when sigma > 0.
  struct EdgeCrossings {
    std::uint32_t s[3], count;
    double x[3];
    std::int8_t sigma;
    // count >= 2: the crossings are multi_crossings[first, first + count), in triangle order.
    std::uint32_t first;
  };
  // One crossing of a Voronoi edge crossed several times: the point and sigma (as above).
  struct CrossingPoint {
    double x[3];
    std::int8_t sigma;
  };
  // A neighbour j of site c: e = p_j - p_c, ee = |e|^2 (rounded), reach = 2 |e| (1 + 1e-14)
  // (above the exact 2 |e| despite rounding), ee_err = 2e-15 ee (bisector_value's bound,
  // less its |r|^2 term).
  struct NbrGeo {
    double e[3], ee, reach, ee_err;
  };
  // ---- Per-thread scratch of the whole compute.
  struct ThreadScratch {
    Star star;
    // Delaunay neighbours of a site (in star order), computed once per thread: the list of
    // site c is nbr_pool[nbr_offset[c] + 2 ..], its length at nbr_pool[nbr_offset[c]];
    // nbr_geo[k] is the NbrGeo of nbr_pool[k] relative to c. The star traversed to find
    // them is kept for boundary_cell: star_pool[o + 1 ..], its length at star_pool[o], for
    // o = nbr_pool[nbr_offset[c] + 1].
    std::vector<std::uint32_t> nbr_offset, nbr_pool, site_mark, star_pool;
    std::vector<NbrGeo> nbr_geo;
    std::uint32_t site_gen = 0;
    TriPoly a, b;
    // Per polygon vertex, beyond the bisector (boundary cells: per star facet, its
    // crossings looked up).
    std::vector<std::uint8_t> beyond;
    // clip_triangle: the neighbours past the filters, and their corner values.
    std::vector<std::uint32_t> candidates;
    std::vector<clip3::CornerValues> candidate_values;
    // Per domain vertex: its cell, when corner_stamp is the current chunk's (+ 1).
    std::vector<std::uint32_t> corner_cell, corner_stamp;
    std::uint32_t last_cell = clip3::kNone;  // the last cell met (a hint)
    std::vector<clip3::CornerValues> corner_values;
    std::vector<clip3::FacetMinors> facet_minors;
    // The cells met by the current triangle (a cell clipped tet by tet: its seed tets).
    std::vector<std::uint32_t> cells;
    std::vector<double> xyz, rel;  // a polygon's vertices, absolute and relative to its site
    // The points of the current triangle on bisectors met so far (each is a vertex of the
    // polygons of two or three cells): tag, sorted sites (kNone past the tag's count),
    // coordinates.
    struct TriPoint {
      std::int8_t tag;
      std::uint32_t s[3];
      double x[3];
    };
    std::vector<TriPoint> tri_points;
    std::vector<std::int8_t> flag;
    std::vector<std::uint32_t> queue;
    clip3::CircumcentreCache circ;
    std::vector<clip3::Rel> cu;  // per star tet: its circumcentre relative to the site
    // inner_chunk: per site, its position in the chunk + 1 (0: not in it); per tet of the
    // chunk, its circumcentre and that relative to each chunk vertex; per cell, its sums
    // and its moments.
    std::vector<std::uint32_t> chunk_slot;
    std::vector<std::array<double, 3>> chunk_c;
    std::vector<clip3::Rel> chunk_rel;
    std::vector<clip3::PieceSums> chunk_sums;
    std::vector<clip3::Moments> chunk_moments;  // (weighted)
    std::vector<clip3::Moments> chunk_out;
    std::vector<const EdgeCrossings*> fx;  // per star tet and facet: its crossings
    std::vector<std::pair<std::uint32_t, std::int8_t>> first_layer;
    Scratch clip;
    std::vector<std::uint8_t> edge_done;  // voronoi_facets: per star tet and vertex
  };
  // Fills s.tets with the tets around v, finite and infinite.
  void star(std::uint32_t v, Star& s) const;
  // The same star in s.star: from s's pool when neighbors() traversed it on this thread
  // (the marks set again), else traversed.
  void pooled_star(std::uint32_t v, ThreadScratch& s) const;
  // The Delaunay neighbours of site c (ids, and geometry relative to c), valid until the
  // next call.
  struct NeighborList {
    const std::uint32_t* id;
    const NbrGeo* geo;
    std::uint32_t count;
  };
  NeighborList neighbors(std::uint32_t c, ThreadScratch& s) const;

  // ---- Restricted surface (clip3d_surface.cpp).
  std::vector<EdgeCrossings> crossings;        // sorted by s
  std::vector<CrossingPoint> multi_crossings;  // of the edges crossed several times
  std::vector<std::uint32_t> crossing_begin;   // per site a: crossings with s[0] == a
  // The crossings of the Voronoi edge of sites a, b, c (any order; nullptr: none).
  const EdgeCrossings* find_crossings(std::uint32_t a, std::uint32_t b, std::uint32_t c) const;
  std::vector<std::uint8_t> is_boundary;  // per site
  // Per site: 1 when a Voronoi edge of its cell crosses the surface several times.
  std::vector<std::uint8_t> multi_crossed;
  std::vector<std::uint32_t> boundary_cells;  // sorted
  std::vector<std::uint32_t> boundary_slot;   // per site: index in boundary_cells
  // Per boundary cell: its restricted polygons' triangles, in triangle order (CSR).
  std::vector<std::uint32_t> cell_tri_begin, cell_tris;
  std::vector<Moments> surface_moments;  // per boundary cell: the polygons' cones
  // keep_surface: per vertex of out.surface_ (before to_input_indices), the site across the
  // polygon edge from it (kNone: an edge on the triangle's boundary).
  std::vector<std::uint32_t> surface_across;
  std::vector<double> surface_area;  // per site
  std::uint32_t descend(const double* p, std::uint32_t c, ThreadScratch& s) const;
  struct SurfaceChunk;
  // A boundary triangle: its index, corners (domain vertices, in the triangle's order).
  struct Tri {
    std::uint32_t b, mv[3];
    const double* x[3];
  };
  Sign tri_side(const Tri& tri, const clip3::TriVertex& v, std::uint32_t c, std::uint32_t j) const;
  void tri_coords(const Tri& tri, const clip3::TriVertex& v, std::uint32_t c, double* x) const;
  ClipVertex3 tri_symbolic(const Tri& tri, const clip3::TriVertex& v, std::uint32_t c) const;
  // Triangle b as the `stamp`-th chunk sees it (ThreadScratch::corner_cell).
  void clip_triangle(std::uint32_t b, std::uint32_t stamp, ThreadScratch& s,
                     SurfaceChunk& chunk) const;
  void emit_polygon(const Tri& tri, std::uint32_t c, const TriPoly& p, ThreadScratch& s,
                    SurfaceChunk& chunk) const;
  void surface_pass(tbb::enumerable_thread_specific<ThreadScratch>& ts);

  // ---- Cells from the triangulation (clip3d_cells.cpp).
  std::vector<std::int8_t> status;  // per site: 1 inside, 0 outside, -1 not decided
  // The parts inside the volume of the Voronoi edge dual to facet f of tet t (vertices
  // tv[0..3]): from its circumcentre u (inside when in1) to the circumcentre w of the tet
  // across f (nullptr when infinite; inside when in2), with the edge's crossings x
  // (nullptr: none). Calls piece(a, b) for signed segments [a, b] whose sum is the inside
  // part: with crossings q_k, each entering (+1) or leaving (-1) the volume as the edge runs
  // from u to w, it is [u, w] if in1, plus [q_k, w] for an entering and [w, q_k] for a
  // leaving crossing; towards infinity, [q_k, u] or [u, q_k] (the segments' integrals are
  // additive along the line, so no order of the crossings is needed).
  template <class Piece>
  void inside_pieces(const std::uint32_t* tv, int f, const double* u, bool in1, const double* w,
                     bool in2, const EdgeCrossings* x, Piece&& piece) const;
  // inside_pieces for an edge crossed twice or more (out of line: rare): the segments, each
  // to be counted `times` times (negative: reversed).
  struct SignedSegment {
    const double* a;
    const double* b;
    int times;
  };
  void multi_crossing_segments(const std::uint32_t* tv, int f, const double* u, bool in1,
                               const double* w, bool in2, const EdgeCrossings& x,
                               std::vector<SignedSegment>& segments) const;
  // Cell i's (site px) share of the segment [a, b] of the Voronoi edge of sites i, vj, vk
  // (kFaceOther order: pj, pk): add_edge_piece, or the same cones weighted by the density.
  template <bool kWeighted>
  using PieceAcc = std::conditional_t<kWeighted, Moments, clip3::PieceSums>;
  template <bool kWeighted>
  void add_piece(const double* px, const double* pj, const double* pk, const clip3::Rel& u,
                 const clip3::Rel& w, PieceAcc<kWeighted>& acc) const {
    if constexpr (kWeighted) {
      const clip3::Foot hj = clip3::foot(pj, px), hk = clip3::foot(pk, px);
      clip3::add_tet_weighted(*callback_density, px, hj.y, u.y, w.y, acc);
      clip3::add_tet_weighted(*callback_density, px, hk.y, w.y, u.y, acc);
    } else {
      clip3::add_edge_piece(clip3::foot(pj, px), clip3::foot(pk, px), u, w, acc);
    }
  }
  // A segment of the boundary of a cell's face on bisector(cell, across), for export.
  struct Segment {
    std::uint32_t across;
    double a[3], b[3];
  };
  // Boundary cell i: its Voronoi vertices placed inside or outside the volume (from its
  // own crossings, or from `global_flag` when given) and, unless it is clipped tet by tet,
  // its integrals added to r. Appends (site, 0/1) for the non-boundary sites of its star.
  // False when no Voronoi vertex of its star could be placed from its own crossings.
  // With `segments`, also the boundary segments of its faces on bisectors: each Voronoi
  // edge part, counter-clockwise around p_j - p_i for the face on bisector(i, j).
  bool boundary_cell(std::uint32_t i, const std::int8_t* global_flag, ThreadScratch& s, Moments& r,
                     std::vector<Segment>* segments = nullptr) const;
  // A chunk's start: a new range of marks in s.star, and s.chunk_slot[c] = k + 1 for
  // c = cells[k] (the chunk functions clear it). Returns s.chunk_slot's data.
  std::uint32_t* start_chunk(const std::uint32_t* cells, std::uint32_t count,
                             ThreadScratch& s) const;
  // The boundary cells cells[0, count) (consecutive in Hilbert order, none clipped tet by
  // tet for its integrals) at once: result[k] (holding cells[k]'s surface share) gets the
  // rest. False when a Voronoi vertex could not be placed (then nothing is changed).
  template <bool kWeighted>
  bool boundary_chunk(const std::uint32_t* cells, std::uint32_t count, ThreadScratch& s,
                      Moments* result) const;
  // The inner cells cells[0, count) (consecutive in Hilbert order) at once: result[k] for
  // cells[k] (clip3d_cells.cpp).
  template <bool kWeighted>
  void inner_chunk(const std::uint32_t* cells, std::uint32_t count, ThreadScratch& s,
                   Moments* result) const;
  // The Voronoi facets of inner cell c (keep_geometry), appended to res as one piece
  // (numbered `piece`), facing inwards (clip3d_cells.cpp).
  void voronoi_facets(std::uint32_t c, std::uint32_t piece, ThreadScratch& s, CellOut& res) const;
  // The faces of boundary cell i from the surface (keep_geometry), appended to res as one
  // piece: its restricted polygons and, per bisector, the loops that bound its face there,
  // all facing inwards. `flag`: the global flags (global_flags).
  void boundary_faces(std::uint32_t i, std::uint32_t piece, const std::int8_t* flag,
                      ThreadScratch& s, std::vector<Segment>& segments, CellOut& res) const;
  // Inside (1) / outside (0) for every Voronoi vertex (tet slot), by a breadth-first
  // search from the infinite tets, flipping with the parity of the crossings.
  void global_flags(std::vector<std::int8_t>& flag) const;
  void decide_status(const std::vector<std::pair<std::uint32_t, std::int8_t>>& first_layer,
                     ThreadScratch& s);

  void run();
};

}  // namespace voroclip
