// Internals of the 3D clipped Voronoi diagram (clip3d.cpp describes the algorithm; its
// run() orchestrates): what the units share. A compute() is three units, each with its own
// per-thread scratch, over a read-only Clip3Context:
//   clip3d_surface.h/.cpp   SurfaceRvd: the restricted surface, triangle by triangle
//                           (sec. 4.1), into a RestrictedSurface that the cells read;
//   clip3d_cells.h/.cpp     DelaunayCells: inner and boundary cells from the Delaunay
//                           triangulation, placed inside or outside the volume (sec. 4),
//                           and their faces for export (clip3d_faces.cpp);
//   clip3d_kernel.h/.cpp    ConvexCell: exact symbolic clipping of a tet (or a triangle) by
//                           a cell, and the tet-by-tet integration of a cell (sec. 4.2, the
//                           reference path), usable on its own.
// Here and in clip3d_context.cpp: the context (the coordinates of symbolic vertices that
// every unit computes alike, the stars of the triangulation), Stars (one thread's
// traversals and neighbour lists, which the surface pass and the cells share), and the
// integrals the units add up (Moments, add_tet_weighted).
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <utility>
#include <vector>

#include "clip_poll.h"
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
// ∫rho (y - x), r.energy += ∫rho |y - x|^2, under Density3::Rule::kDegree5 by Walkington's 14-point
// rule of degree 5 (positive weights; "Quadrature on simplices of arbitrary dimension", 2000): two
// orbits of 4 points (a, a, a, 1 - 3a) and one of 6 points (b, b, 1/2 - b, 1/2 - b) in barycentric
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

// The degree-5 rule's 14 points x + y of the tet (x; x + a, x + b, x + c), y in kTetRule's
// order; add_tet_degree5 the integrals from rho's values f[0..13] there.
inline void degree5_points(const double* x, const double* a, const double* b, const double* c,
                           double* p) {
  for (const TetRule& q : kTetRule) {
    for (int k = 0; k < 3; ++k) {
      const double y = (q.l[0] * a[k] + q.l[1] * b[k]) + q.l[2] * c[k];
      p[k] = x[k] + y;
    }
    p += 3;
  }
}
inline void add_tet_degree5(const double* f, const double* a, const double* b, const double* c,
                            Moments& r) {
  const double det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                     a[2] * (b[0] * c[1] - b[1] * c[0]);
  r.volume += det / 6;
  double m = 0, mom[3] = {0, 0, 0}, e = 0;
  for (int n = 0; n < 14; ++n) {
    const TetRule& q = kTetRule[n];
    double y[3];
    for (int k = 0; k < 3; ++k) y[k] = (q.l[0] * a[k] + q.l[1] * b[k]) + q.l[2] * c[k];
    const double w = q.w * f[n];
    m += w;
    for (int k = 0; k < 3; ++k) mom[k] += w * y[k];
    e += w * ((y[0] * y[0] + y[1] * y[1]) + y[2] * y[2]);
  }
  const double v = det / 6;
  r.mass += v * m;
  for (int k = 0; k < 3; ++k) r.moment[k] += v * mom[k];
  r.energy += v * e;
}

// The P2 (quadratic Lagrange) nodal rule on a tet: nodes 0..3 its vertices, 4..9 the
// midpoints of its edges (01, 02, 03, 12, 13, 23), basis N_i = l_i (2 l_i - 1) and
// N_ij = 4 l_i l_j in the barycentric coordinates l. With rho_h the interpolant of rho at
// the nodes, the weights below are, over the tet's volume V, the integrals of N_n, of
// N_n l_k and of N_n l_k l_l (k, l = 1..3): from the integral of a monomial,
// ∫ l^b = 6 V b! / (|b| + 3)!. Then for vertex 0 at the site and vertices 1..3 at the
// site + a, b, c: ∫rho_h = V sum r_n W0_n, ∫rho_h y = V sum_k v_k (sum r_n W1_nk),
// ∫rho_h |y|^2 = V sum_kl (v_k . v_l) (sum r_n W2_nkl): exact when rho is a polynomial of
// degree <= 2 (then rho_h = rho), in particular when it is constant or linear.
struct P2Weights {
  double w0[10];
  double w1[10][3];  // k = 1..3
  double w2[10][6];  // (k, l) = (1,1) (2,2) (3,3) (1,2) (1,3) (2,3)
};
namespace p2detail {
constexpr double factorial(int n) { return n <= 1 ? 1.0 : n * factorial(n - 1); }
// ∫ l^e / V for exponents e[0..3].
constexpr double monomial(const int* e) {
  double num = 6;
  int deg = 0;
  for (int k = 0; k < 4; ++k) {
    num *= factorial(e[k]);
    deg += e[k];
  }
  return num / factorial(deg + 3);
}
// ∫ N_n l_k l_l / V (k or l = -1: absent).
constexpr double integral(int n, int k, int l) {
  constexpr int kEdge[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  int e[4] = {0, 0, 0, 0};
  if (k >= 0) ++e[k];
  if (l >= 0) ++e[l];
  if (n < 4) {
    int e2[4] = {e[0], e[1], e[2], e[3]}, e1[4] = {e[0], e[1], e[2], e[3]};
    e2[n] += 2;
    e1[n] += 1;
    return 2 * monomial(e2) - monomial(e1);
  }
  ++e[kEdge[n - 4][0]];
  ++e[kEdge[n - 4][1]];
  return 4 * monomial(e);
}
constexpr P2Weights make_weights() {
  constexpr int kPair[6][2] = {{1, 1}, {2, 2}, {3, 3}, {1, 2}, {1, 3}, {2, 3}};
  P2Weights w{};
  for (int n = 0; n < 10; ++n) {
    w.w0[n] = integral(n, -1, -1);
    for (int k = 0; k < 3; ++k) w.w1[n][k] = integral(n, k + 1, -1);
    for (int p = 0; p < 6; ++p) w.w2[n][p] = integral(n, kPair[p][0], kPair[p][1]);
  }
  return w;
}
}  // namespace p2detail
inline constexpr P2Weights kP2Weights = p2detail::make_weights();

// The same integrals under Density3::Rule::kQuadratic: rho replaced by its P2 interpolant
// (P2Weights): 10 values of rho per tet, most of them shared with the cell's other cones
// (DensityBatch, DelaunayCells::add_piece_numbered), where the degree-5 rule calls rho 14
// times per tet. Exact for rho of degree <= 2. A node is x + v for a vertex v and
// x + (v + v') / 2 for a midpoint (v = 0 at x). add_tet_p2: the integrals from the values
// f[0..9] at the nodes. P2Weights' sums in closed form: kP2Weights' entries are integers
// over 120 (w0), 720 (w1) and 5040 (w2), -6 at a vertex and 24 at an edge for w0, and
// with the sums sv (vertices), se (edges) and e_k (the 3 edges at vertex k),
//   sum_n f_n w1_nk = (2 (se + e_k) - (sv - f_k)) / 60,
//   sum_n f_n w2_nkk = (4 se + 8 e_k - 3 sv + 6 f_k) / 420,
//   sum_n f_n w2_nkl = (4 (se + e_k + e_l + f_kl) - 3 sv + f_k + f_l) / 840 (k != l),
// 50 operations instead of 200 (tests/clip/test_density3.cpp checks them against the
// table).
inline void add_tet_p2(const double* f, const double* a, const double* b, const double* c,
                       Moments& r) {
  const double det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                     a[2] * (b[0] * c[1] - b[1] * c[0]);
  const double v = det / 6;
  r.volume += v;
  // Nodes: 0..3 the vertices x, x + a, x + b, x + c; 4..9 the edges 01 02 03 12 13 23.
  const double sv = (f[0] + f[1]) + (f[2] + f[3]);
  const double se = ((f[4] + f[5]) + (f[6] + f[7])) + (f[8] + f[9]);
  const double e1 = (f[4] + f[7]) + f[8], e2 = (f[5] + f[7]) + f[9], e3 = (f[6] + f[8]) + f[9];
  const double m = (24 * se - 6 * sv) * (1.0 / 120);
  const double s1 = (2 * (se + e1) - (sv - f[1])) * (1.0 / 60);
  const double s2 = (2 * (se + e2) - (sv - f[2])) * (1.0 / 60);
  const double s3 = (2 * (se + e3) - (sv - f[3])) * (1.0 / 60);
  const double base = 4 * se - 3 * sv;
  const double t11 = (base + 8 * e1 + 6 * f[1]) * (1.0 / 420);
  const double t22 = (base + 8 * e2 + 6 * f[2]) * (1.0 / 420);
  const double t33 = (base + 8 * e3 + 6 * f[3]) * (1.0 / 420);
  const double t12 = (base + 4 * ((e1 + e2) + f[7]) + (f[1] + f[2])) * (1.0 / 840);
  const double t13 = (base + 4 * ((e1 + e3) + f[8]) + (f[1] + f[3])) * (1.0 / 840);
  const double t23 = (base + 4 * ((e2 + e3) + f[9]) + (f[2] + f[3])) * (1.0 / 840);
  const auto dot = [](const double* u, const double* w) {
    return (u[0] * w[0] + u[1] * w[1]) + u[2] * w[2];
  };
  r.mass += v * m;
  for (int q = 0; q < 3; ++q) r.moment[q] += v * ((s1 * a[q] + s2 * b[q]) + s3 * c[q]);
  const double e = (t11 * dot(a, a) + t22 * dot(b, b)) + t33 * dot(c, c) +
                   2 * ((t12 * dot(a, b) + t13 * dot(a, c)) + t23 * dot(b, c));
  r.energy += v * e;
}

// The P2 rule's 10 nodes of the tet (x; x + a, x + b, x + c), in P2Weights' order: the
// vertices x, x + a, x + b, x + c, then x + v / 2 and x + (v + w) / 2 for the edges. A
// node is computed from the same operands in every cone that has it (the vertices of a
// cell's cones are the site and points relative to it), so the same bits.
inline void p2_nodes(const double* x, const double* a, const double* b, const double* c,
                     double* p) {
  const double* v[3] = {a, b, c};
  for (int k = 0; k < 3; ++k) p[k] = x[k];
  for (int n = 0; n < 3; ++n) {
    for (int k = 0; k < 3; ++k) p[3 * (1 + n) + k] = x[k] + v[n][k];
    for (int k = 0; k < 3; ++k) p[3 * (4 + n) + k] = x[k] + 0.5 * v[n][k];
  }
  constexpr int kPair[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  for (int e = 0; e < 3; ++e) {
    const double* u = v[kPair[e][0]];
    const double* w = v[kPair[e][1]];
    for (int k = 0; k < 3; ++k) p[3 * (7 + e) + k] = x[k] + 0.5 * (u[k] + w[k]);
  }
}

// The cones of a callback density (Density3::Kind::kCallback), integrated in batches: a
// unit records the cones of its cells (add: the tet and the Moments it adds to, alive
// until flush), and flush() computes the cones' quadrature points (Density3::rule: P2
// nodes or the degree-5 points), evaluates rho once per distinct point (kQuadratic: a
// cell's cones share most of their nodes) in one call of Density3::batch when the density
// has one (an interpreted formula pays its per-call cost once per batch), and adds each
// cone's integrals to its Moments in the order recorded (add flushes every kMaxTets cones;
// the unit flushes before it reads its Moments). The values of rho depend only on
// a point's bits, so the sums are those of evaluating cone by cone, for any batch.
// One per thread (thread_density_batch); a unit calls begin before recording (a unit left
// by an exception leaves stale cones behind).
//
// Numbered nodes (kQuadratic only; begin(rho, true)): the unit numbers the P2 nodes itself
// from what defines them (the inner cells: DelaunayCells::add_piece_numbered) instead of
// flush finding equal points by their bits through the table, and integrates its cones
// itself: node() gives a new node its position (from 0 at begin), evaluate_staged()
// evaluates the nodes pushed since its last call (the unit calls it when staged_full(),
// then integrates the cones whose nodes are all evaluated), values() holds rho at the
// nodes. A NodeRef-like record of the unit stays valid while epoch() is unchanged (begin
// starts a new one).
class DensityBatch {
 public:
  // Starts recording cones of rho (dropping any left by an exception); `numbered`: the
  // caller numbers the nodes (rho.rule is kQuadratic).
  void begin(const Density3& rho, bool numbered = false) {
    rho_ = &rho;
    numbered_ = numbered;
    tets_.clear();
    points_.clear();
    index_.clear();
    values_.clear();
    staged_ = 0;
    new_epoch();
  }
  void add(const double* x, const double* a, const double* b, const double* c, Moments& r) {
    Tet t;
    for (int k = 0; k < 3; ++k) {
      t.x[k] = x[k];
      t.a[k] = a[k];
      t.b[k] = b[k];
      t.c[k] = c[k];
    }
    t.r = &r;
    tets_.push_back(t);
    if (tets_.size() == kMaxTets) flush();
  }
  // Numbered nodes: the batch's generation (a record of another generation is stale).
  std::uint64_t epoch() const { return epoch_; }
  // The position of a new node, its 3 coordinates written by make(double*).
  template <class Make>
  std::uint32_t node(Make&& make) {
    if (staged_ == kStageRoom) evaluate_staged();  // (the caller did not: still right)
    make(stage_ + 3 * staged_);
    return static_cast<std::uint32_t>(values_.size() + staged_++);
  }
  bool staged_full() const { return staged_ >= kStage; }
  // rho at the nodes pushed since the last call (Density3::batch when it has one).
  void evaluate_staged();
  const double* values() const { return values_.data(); }
  // Evaluates and adds the recorded cones, then clears (a new epoch).
  void flush();

 private:
  // Cones per batch: the points' buffers stay in the caches (~10^4 points).
  static constexpr std::size_t kMaxTets = 1024;
  // Numbered nodes evaluated at a time (staged_full), and the room for them (a piece pushes
  // 14 at most before the caller checks).
  static constexpr std::size_t kStage = 1024, kStageRoom = kStage + 64;
  // The distinct-node table: direct-mapped, a slot keeps the last node hashed to it.
  static constexpr std::size_t kSlots = 4096;
  struct Tet {
    double x[3], a[3], b[3], c[3];
    Moments* r;
  };
  void new_epoch() {
    ++epoch_;  // 64 bits: never wraps (a record of an old batch is never taken for new)
  }
  const Density3* rho_ = nullptr;
  bool numbered_ = false;
  std::uint64_t epoch_ = 1;
  std::vector<Tet> tets_;
  // The points (3 coordinates each) and rho there (numbered: rho at the nodes evaluated).
  std::vector<double> points_, values_;
  std::vector<std::uint32_t> index_;  // per cone, its points' positions in values_
  double stage_[3 * kStageRoom];      // numbered: the nodes not yet evaluated
  std::size_t staged_ = 0;
  // Per slot, the position in points_ of the last node hashed to it. Never cleared: an
  // entry counts only when it is within points_ and its bits are the node's.
  std::vector<std::uint32_t> table_ = std::vector<std::uint32_t>(kSlots, 0);
};

// The calling thread's DensityBatch.
DensityBatch& thread_density_batch();

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

// The state one compute() shares with its units, read-only while it runs. The surface
// drives everything; the domain's tets only the tet-by-tet clipping (tet_clipping, a
// density linear per tet). Units keep a copy (a few references and flags), so that their
// hot loops reach the triangulation as directly as through their own members.
struct Clip3Context {
  Clip3Context(const Domain3& d, const Delaunay3& t, const Clip3Options& o,
               detail::ClipPoll* p = nullptr);

  const Domain3& domain;
  const Surface3& surface;
  const Delaunay3& dt;
  const Clip3Options& options;
  std::uint32_t n;  // sites (the triangulation's points)
  // A non-constant density: the cells' integrals are weighted (Moments::mass).
  bool weighted;
  // A density linear per tet: every cell is clipped tet by tet.
  bool linear_density;
  // A density given as a function: quadrature on the cells' cone decompositions.
  const Density3* callback_density;
  // The restricted surface polygons are kept (keep_surface or keep_geometry).
  bool keep_surface;
  // Progress and cancel (clip_poll.h): chunks of the parallel loops report to it; null
  // when none.
  detail::ClipPoll* poll;
  bool running() const { return !poll || poll->running(); }
  void chunk_done(std::uint64_t count) const {
    if (poll) poll->chunk(count);
  }

  const double* site(std::uint32_t i) const { return dt.point(i); }
  // Sites far outside the domain: outside its bounding box grown by its largest extent on
  // every side (near_lo, near_hi). A far site's cell, when it meets the domain, is
  // integrated from apex(i) = the box's centre instead of from the site (the cones from a
  // site 1e20 away cancel to nothing: a volume of -8768 for the unit sphere), and the
  // points on its bisectors are constructed exactly (edge_point, facet_point,
  // voronoi_point). Other sites keep the site as apex and every bit of their results.
  // any_far: some site is far (else none of this is looked at).
  bool any_far = false;
  double near_lo[3] = {0, 0, 0}, near_hi[3] = {0, 0, 0}, centre[3] = {0, 0, 0};
  bool far(std::uint32_t i) const {
    if (!any_far) return false;
    const double* p = site(i);
    return !(p[0] >= near_lo[0] && p[0] <= near_hi[0] && p[1] >= near_lo[1] && p[1] <= near_hi[1] &&
             p[2] >= near_lo[2] && p[2] <= near_hi[2]);
  }
  const double* apex(std::uint32_t i) const { return far(i) ? centre : site(i); }
  // The foot of apex(i) on bisector(i, j), relative to apex(i): (p_j - p_i) / 2 for a site
  // that is not far (its bits as before); else -F e / (2 |e|^2), e = p_j - p_i, with
  // F = |a - p_i|^2 - |a - p_j|^2 at the apex a computed exactly (bisector_value3d_exact).
  // Every point y of the bisector (relative to the apex) has h . y = |h|^2.
  void foot(std::uint32_t i, std::uint32_t j, double* h) const;
  // Throws Error when far site i is too far for the cell integrals in double precision
  // (a coordinate offset from the domain's centre above kMaxFarOffset).
  void check_far_site(std::uint32_t i) const;
  // (After a build an infinite tet has kInfinite as its vertex 3: Delaunay3.)
  bool infinite(std::uint32_t t) const { return dt.is_infinite(t); }
  // Fills s.tets with the tets around v, finite and infinite.
  void star(std::uint32_t v, Star& s) const;
  // Mesh edge (ma, mb) ∩ bisector(s0, s1), and the plane of triangle mesh[0..2] ∩
  // bisectors (s0, s1), (s0, s2), from sorted ids (the same bits wherever they are met).
  void edge_point(std::uint32_t ma, std::uint32_t mb, std::uint32_t s0, std::uint32_t s1,
                  double* x) const;
  void facet_point(const std::uint32_t* mesh, const std::uint32_t* sites, double* x) const;
  // The Voronoi vertex (circumcentre) of sites[0..3], sorted: the same bits for the cells
  // (DelaunayCells::circumcentre) and the tet-by-tet clipping; accurate to a few ulps
  // however flat the tet (circumcenter3d).
  void voronoi_point(const std::uint32_t* sites, double* x) const;
};

// A neighbour j of site c: e = p_j - p_c, ee = |e|^2 (rounded), reach = 2 |e| (1 + 1e-14)
// (above the exact 2 |e| despite rounding), ee_err = 2e-15 ee (bisector_value's bound,
// less its |r|^2 term; clip3d_surface.cpp).
struct NbrGeo {
  double e[3], ee, reach, ee_err;
};

// The Delaunay neighbours of a site: ids, and geometry relative to the site.
struct NeighborList {
  const std::uint32_t* id;
  const NbrGeo* geo;
  std::uint32_t count;
};

// One thread's traversals of the Delaunay triangulation, shared by the surface pass and
// the cells (each thread has its own: tbb::enumerable_thread_specific). A single Star's
// tet marks serve every traversal of the thread, each in a new range of marks (Star): the
// stars of sites, and the tets of a chunk of cells (new_range), so that a thread carries
// one mark per tet slot. The neighbours of a site are computed once per thread: the list
// of site c is nbr_pool_[nbr_offset_[c] + 2 ..], its length at nbr_pool_[nbr_offset_[c]];
// nbr_geo_[k] is the NbrGeo of nbr_pool_[k] relative to c. The star traversed to find them
// is kept for pooled_star: star_pool_[o + 1 ..], its length at star_pool_[o], for
// o = nbr_pool_[nbr_offset_[c] + 1].
class Stars {
 public:
  // The star of v, traversed (Clip3Context::star); valid until the next call.
  const Star& star(const Clip3Context& ctx, std::uint32_t v) {
    ctx.star(v, star_);
    return star_;
  }
  // The same star, from the pool when neighbors() traversed it on this thread (the marks
  // set again), else traversed.
  const Star& pooled_star(const Clip3Context& ctx, std::uint32_t v);
  // The Delaunay neighbours of site c, valid until the next call.
  NeighborList neighbors(const Clip3Context& ctx, std::uint32_t c);
  // The Star with a new, empty range of marks, for a traversal of the caller's own: it
  // marks t with first + (position), fills tets as it likes and sets next past its range.
  Star& new_range(const Clip3Context& ctx) {
    star_.reset_if_needed(ctx.dt.nb_tet_slots());
    star_.first = star_.next;
    return star_;
  }

 private:
  Star star_;
  std::vector<std::uint32_t> nbr_offset_, nbr_pool_, star_pool_;
  std::vector<NbrGeo> nbr_geo_;
  std::vector<std::uint32_t> site_mark_;  // per site: the last generation that listed it
  std::uint32_t site_gen_ = 0;
};

// The output of a cell clipped tet by tet (ConvexCell::clip_cell), or of a chunk of cells'
// faces (DelaunayCells::voronoi_facets, boundary_faces): integrals, (cell, tet) pairs
// clipped, and with keep_geometry the faces, each in a numbered piece.
struct CellOut : Moments {
  std::uint64_t pairs = 0;
  std::vector<std::uint32_t> face_begin{0};
  std::vector<std::uint32_t> face_piece;
  std::vector<std::uint32_t> face_across;  // as ClippedVoronoi3::Polygons::across
  std::vector<double> face_xyz;
};

}  // namespace clip3

}  // namespace voroclip
