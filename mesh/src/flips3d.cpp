// Flips, smoothing and insertion against the worst tets of a finished tet mesh (step 7c of
// mesh3d): 2-3 flips of interior faces and edge removal of interior edges (3-2, 4-4 and the
// general n-to-2(n-2) flip), moves of interior vertices, and a new interior vertex in the
// cavity of a tet and its neighbours, after Shewchuk, "Two discrete optimization algorithms for the
// topological improvement of tetrahedral meshes" (2002, edge removal by dynamic
// programming over the triangulations of the edge's ring) and Klingner & Shewchuk,
// "Aggressive tetrahedral mesh improvement" (IMR 2007, the greedy worst-first schedule, a
// flip kept only when it raises the smallest quality among the tets it replaces).
//
// The mesh need not be Delaunay before or after. A flip replaces a set of tets by another
// set with the same union (the two tets of an interior face, the ring of an interior edge);
// a move changes only the position of a free vertex inside the mesh (one on its boundary
// stays: Flipper's constructor) or (Flip3Options::on_surface) slides a
// surface vertex on the surface within its patch, an insertion replaces a cavity by the
// star of a new free vertex: the boundary triangles are unchanged (their surface vertices
// at most slide) but for the boundary flips below;
// every new tet is checked exactly (orient3d with the mesh's sign, never zero), so the
// result is a valid tet mesh whenever the input is. The quality is Q1, the smallest
// dihedral angle (tet_shape). For the worst tet first: the best flip that removes it; when
// none gains, the best move of one of its free vertices (a compass search on the smallest
// Q1 of the vertex's tets: steps along the axes and towards the mean of its neighbours,
// halved when none gains); when none gains, an insertion (the cavity: the tet and its
// face neighbours; the new vertex from the tet's centroid, moved by the same search).
// Every operation also keeps the smallest Q4 of the tets it replaces, or kQ4Keep: a constraint
// of the search (a move's candidate position, a triangulation of an edge's ring that breaks
// it ranks below every one that keeps it), not only a check of its result, so that the best
// move that keeps Q4 is found where the best one for Q1 alone would lower it.
// Three passes: against the tets whose Q4 is below Flip3Options::below_q4 (Q4 raised, Q1
// kept), then those below below_deg by min(Q1, kQ4Weight Q4) (Q4 kept), then Q4 again. The Q4
// pass first: on skull_low_resolution at 10,000 vertices the Q1 pass first left a
// cluster of thin tets it could not improve further (min Q1 13.9, Q4 0.27), which the Q4
// pass first raised to 20.1 and 0.40 (session 25).
// Sequential and deterministic: the same result for any thread count.
//
// The pass for the mean (raise_mean3, step 7d of mesh3d) works on every tet, not the worst:
// rounds of flips (2-3, edge removal up to kMeanRing tets) each raising the mesh's mean Q1
// (the new tets' sum of Q1 beats the old ones' by more than the mean times the tets added),
// then of moves of each movable vertex to the best position of a compass search on the sum of
// Q1 over its star. Every operation keeps the smallest Q1 of what it replaces (or kMeanKeepQ1)
// and its smallest Q4 (or kMeanKeepQ4). A surface vertex moves only where its boundary
// triangles are flat within kMeanFlatDeg and the move takes them no farther from the surface
// (their centroids) nor from its old position. At 10,000 vertices (the 8 shared surfaces,
// main 40c072e) the tets with 2 or 3 boundary vertices (a sixth to a third of the tets)
// average 47 to 53 degrees, those with 0 or 1 54 to 58: the moves raise both (session 26).
// The moves of a round go by classes of vertices that share no tet (greedy colouring in vertex
// order): a vertex's search reads only its star, whose other vertices are in other classes,
// so the searches of a class run in parallel and their moves are applied in vertex order,
// the same for any thread count (session 27; before, in vertex order one by one).
// The flips of a round are those of a walk through the tets in order, one after the other;
// the candidates of a block of tets are found in parallel before the walk reaches it and found
// again for a tet that a flip of the block has since touched (a tet with one of its edges
// removed or made): the same flips as finding each tet's when the walk reaches it, but for
// the order of a ring's tets (vertex_tets_ order, which flips at a vertex of the ring change),
// so the last bits of a sum over the ring. The thread count changes nothing of it.
//
// Orientation: the tets here have orient3d(v0, v1, v2, v3) < 0 (right-handed,
// det(v1 - v0, v2 - v0, v3 - v0) > 0: the order extract3d gives).
//
// 2-3 flip of the face (a, b, c) of t = (.., d, ..) shared with u, whose fourth vertex is e:
// the three new tets are t with one of a, b, c replaced by e, each right-handed exactly when
// the segment de crosses the triangle abc inside.
//
// Edge removal of (a, b): the tets around it form a closed ring r_0 .. r_{k-1} (an interior
// edge), ordered so that (a, b, r_0, r_1) is right-handed; each triangle (r_i, r_j, r_m),
// i < j < m, of a triangulation of the ring gives the two tets (r_i, r_j, r_m, b) and
// (r_i, r_m, r_j, a), both right-handed when the flip is valid. The best triangulation
// (max of the min Q1 of its tets) by dynamic programming over the ring's sub-polygons.
//
// Boundary 2-2 flip of the boundary edge (a, b) (Flip3Options::same_patch): the tets around
// it form an open fan r_0 .. r_k from the boundary face (a, b, r_0) to (a, b, r_k); the
// polygon r_0 .. r_k triangulated as a ring is (its base (r_0, r_k) the new boundary edge)
// gives the new tets, and the boundary triangles (a, r_0, r_k), (b, r_k, r_0) replace
// (a, b, r_0), (b, a, r_k). The union changes by the tet (a, b, r_0, r_k), thin where the
// four normals agree within kBoundaryFlipDeg; the caller checks the boundary's shape.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <queue>
#include <string>
#include <utility>
#include <vector>

#include "mesh3d_pipeline.h"
#include "mesh3d_tags.h"
#include "voroclip/mesh.h"
#include "voroclip/predicates.h"

namespace voroclip::mesh3 {

namespace {

constexpr std::size_t kMaxRing = 8;     // edge removal up to 8 tets around the edge
constexpr double kInvalid = -1;         // the quality of an inverted or flat new tet
constexpr double kBelowFloor = -0.5;    // of a right-handed one below the kept measure's floor
constexpr int kSearchSteps = 48;        // compass search: evaluations of a move, at most
constexpr double kFirstStep = 0.25;     // times the mean edge length of the vertex's tets
constexpr double kLastStep = 1.0 / 64;  // idem, the search stops below
// An operation may lower the smallest Q4 of the tets it replaces only down to this (the
// target of issue 30 is 0.4): raising the smallest angle can make a needle.
constexpr double kQ4Keep = 0.5;
// The Q1 pass raises min(Q1, kQ4Weight Q4) (degrees): Q4 = 0.4 weighs as Q1 = 20 degrees,
// the two targets of issue 30, so that a tet short of either is worked on and no operation
// trades one target for the other. With Q1 alone (and Q4 only kept), elk at 10,000
// vertices ended with min Q4 0.370 and fandisk at 30,000 with 0.231 (session 25).
constexpr double kQ4Weight = 50;
// A boundary flip only where the boundary is nearly flat: the normals of its two old and two
// new boundary triangles within this of each other (degrees). Then the tet (a, b, c, d) the
// flip adds or removes is thin: d off the plane of (a, b, c) by at most sin(5 deg) = 8.7% of
// its distance to the line ab. Measured (session 24,
// 10k vertices): fandisk makes 3 boundary flips with it, its Hausdorff distance
// unchanged (0.652% of the diagonal); around skull's worst tets the candidates' normals spread
// 0.9 to 5.0 deg, or 7 to 20 deg. The worst tets of skull 10k and elk 3k would need 11.1 and
// 9.7 deg, yet with bounds up to 20 deg no boundary flip is kept there (skull's fails the Q4
// keep): they stay.
constexpr double kBoundaryFlipDeg = 5;
constexpr double kPi = 3.14159265358979323846;
// The pass for the mean (raise_mean3): an operation keeps the smallest Q1 of the tets it
// replaces or this, and their smallest Q4 or kMeanKeepQ4 (the targets of issue 30 are 20
// degrees and 0.4; 30 as step 7c's threshold).
constexpr double kMeanKeepQ1 = 30;
constexpr double kMeanKeepQ4 = 0.4;
constexpr double kMeanGain = 0.01;      // degrees, summed over the tets an operation makes
constexpr std::size_t kMeanRing = 4;    // edge removal up to 4 tets around the edge
constexpr double kMeanFirstStep = 0.1;  // times the mean edge length of the vertex's tets
constexpr int kMeanSearchSteps = 28;    // compass search: evaluations of a move, at most
// The mean pass's flips find the candidates of this many tets at a time in parallel.
constexpr std::size_t kMeanBlock = 2048;
// A surface vertex moves only where its boundary triangles' normals are within this of each
// other (Flipper::flat).
constexpr double kMeanFlatDeg = 30;

// Q1 (degrees) and Q4 (into q4) of a tet, as tet_shape has them to rounding but cheaper (one
// acos, no orientation test): the pass for the mean evaluates them for every candidate
// position of every vertex. 0 for a flat tet.
double q1_q4(const double* p0, const double* p1, const double* p2, const double* p3, double& q4) {
  const double* p[4] = {p0, p1, p2, p3};
  double e[6][3];
  for (int k = 0; k < 6; ++k)
    sub3(p[TetShape::kTetEdges[k][1]], p[TetShape::kTetEdges[k][0]], e[k]);
  // Face normals, face k opposite vertex k, all outward or all inward (TetShape's).
  double n[4][3], len[4];
  cross3(e[3], e[4], n[0]);
  cross3(e[2], e[1], n[1]);
  cross3(e[0], e[2], n[2]);
  cross3(e[1], e[0], n[3]);
  for (int f = 0; f < 4; ++f) len[f] = std::sqrt(dot3(n[f], n[f]));
  double bc[3];
  cross3(e[1], e[2], bc);
  const double det = dot3(e[0], bc);
  double sum_l2 = 0;
  for (const auto& v : e) sum_l2 += dot3(v, v);
  q4 = sum_l2 > 0 ? 12 * std::cbrt(det * det / 4) / sum_l2 : 0.0;
  return smallest_dihedral_deg(n, len);
}

// The squared distance from p to the segment ab.
double distance2_to_segment(const double* p, const double* a, const double* b) {
  double ab[3], ap[3];
  sub3(b, a, ab);
  sub3(p, a, ap);
  const double l2 = dot3(ab, ab);
  const double s = l2 > 0 ? std::min(1.0, std::max(0.0, dot3(ap, ab) / l2)) : 0.0;
  double d[3];
  for (int c = 0; c < 3; ++c) d[c] = ap[c] - s * ab[c];
  return dot3(d, d);
}

// The squared distance from p to the triangle abc (its plane's where p projects inside, else
// the nearest edge's).
double distance2_to_triangle(const double* p, const double* a, const double* b, const double* c) {
  double ab[3], ac[3], n[3], ap[3];
  sub3(b, a, ab);
  sub3(c, a, ac);
  cross3(ab, ac, n);
  sub3(p, a, ap);
  const double nn = dot3(n, n);
  if (nn > 0) {
    const double* v[3] = {a, b, c};
    bool inside = true;
    for (int k = 0; k < 3 && inside; ++k) {
      double e[3], w[3], m[3];
      sub3(v[(k + 1) % 3], v[k], e);
      sub3(p, v[k], w);
      cross3(e, w, m);
      inside = dot3(m, n) >= 0;
    }
    if (inside) {
      const double h = dot3(ap, n);
      return h * h / nn;
    }
  }
  return std::min({distance2_to_segment(p, a, b), distance2_to_segment(p, b, c),
                   distance2_to_segment(p, c, a)});
}

// What may move: free_[v].
constexpr std::uint8_t kFixed = 0, kMovable = 1, kOnSurface = 2;
constexpr std::uint32_t kNoVertex = 0xffffffff;

class Flipper {
 public:
  Flipper(std::vector<double>& sites, const std::vector<Kind>& kinds,
          const std::vector<std::uint32_t>& mesh, const Flip3Options& options)
      : sites_(sites), options_(options), vertex_tets_(sites.size() / 3) {
    free_.resize(sites.size() / 3);
    surface_.resize(sites.size() / 3);
    for (std::size_t v = 0; v < free_.size(); ++v) {
      free_[v] = kinds[v] == Kind::kFree                            ? kMovable
                 : kinds[v] == Kind::kSurface && options.on_surface ? kOnSurface
                                                                    : kFixed;
      surface_[v] = kinds[v] == Kind::kSurface ? 1 : 0;
    }
    const std::size_t nt = mesh.size() / 4;
    for (std::size_t t = 0; t < nt; ++t)
      add({mesh[4 * t], mesh[4 * t + 1], mesh[4 * t + 2], mesh[4 * t + 3]});
    // A free vertex on the boundary (a face of its tets on no other tet: the extraction's
    // manifold repair or step 7b can leave one) stays: only an interior vertex's star is a
    // closed ball, inside which the moves' checks (every tet right-handed) keep the mesh
    // embedded. Moved, a boundary vertex takes its boundary triangles with it, which can cut
    // through another part of the boundary (skull_low_resolution at 1,000 vertices, step 7d:
    // "the boundary facet of tet 2789 and the boundary facet of tet 2790 intersect", and the
    // mesh made again with twice the vertices; session 31). No operation makes an interior
    // vertex a boundary one or the reverse (boundary flips keep their four vertices on it).
    std::vector<std::uint32_t> triangles, face_tet;
    boundary_triangles(mesh, triangles, face_tet);
    for (const std::uint32_t w : triangles) {
      if (free_[w] == kMovable) free_[w] = kFixed;
    }
  }

  // The Q4 pass, the Q1 pass, the Q4 pass again (the file's header); at most
  // options_.max_operations in all.
  Flip3Stats run() {
    for (const bool q4 : {true, false, true}) {
      if (q4 && !(options_.below_q4 > 0)) continue;
      q4_mode_ = q4;
      gain_ = q4 ? options_.gain_q4 : options_.gain_deg;
      keep_ = q4 ? options_.below_deg : kQ4Keep;
      for (std::size_t t = 0; t < tets_.size(); ++t) {
        if (alive_[t] == 0) continue;
        const Tet& v = tets_[t];
        const TetShape shape = tet_shape(at(v[0]), at(v[1]), at(v[2]), at(v[3]));
        obj_[t] = measure(shape);
        guard_[t] = q4 ? shape.q1_deg : shape.q4;
      }
      pass(q4 ? options_.below_q4 : options_.below_deg);
    }
    return stats_;
  }

  // Worst first (by the current measure), the tets below `below`, while operations are
  // left (options_.max_operations in all).
  void pass(double below) {
    using Entry = std::pair<double, std::uint32_t>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
    for (std::uint32_t t = 0; t < obj_.size(); ++t) {
      if (alive_[t] != 0 && obj_[t] < below) queue.emplace(obj_[t], t);
    }
    while (!queue.empty() &&
           stats_.flips + stats_.moves + stats_.insertions < options_.max_operations) {
      const std::uint32_t t = queue.top().second;
      queue.pop();
      if (alive_[t] == 0) continue;
      const std::size_t first_new = tets_.size();
      if (!improve(t)) continue;
      for (std::size_t s = first_new; s < tets_.size(); ++s) {
        if (obj_[s] < below) queue.emplace(obj_[s], static_cast<std::uint32_t>(s));
      }
    }
  }

  // The pass for the mean Q1 (raise_mean3): `rounds` rounds of flips then moves, each raising
  // the mean Q1 of the mesh (a flip) or the sum of Q1 over a vertex's star (a move) by more
  // than kMeanGain, keeping the smallest Q1 of the tets it replaces or kMeanKeepQ1, and their
  // smallest Q4 or kMeanKeepQ4. A round that changes nothing ends the pass.
  Mean3Stats raise_mean(std::uint32_t rounds) {
    mean_mode_ = true;
    q4_mode_ = false;
    keep_ = kMeanKeepQ4;
    Mean3Stats stats;
    total_ = 0;
    count_ = 0;
    for (std::size_t t = 0; t < tets_.size(); ++t) {
      if (alive_[t] == 0) continue;
      const Tet& v = tets_[t];
      obj_[t] = q1_q4(at(v[0]), at(v[1]), at(v[2]), at(v[3]), guard_[t]);
      total_ += obj_[t];
      ++count_;
    }
    stats.mean_before = count_ > 0 ? total_ / static_cast<double>(count_) : 0;
    for (std::uint32_t round = 0; round < rounds; ++round) {
      const std::uint32_t flips = mean_flips(), moves = mean_moves();
      stats.flips += flips;
      stats.moves += moves;
      ++stats.rounds;
      if (flips + moves == 0) break;
    }
    double sum = 0;
    std::size_t nb = 0;
    for (std::size_t t = 0; t < tets_.size(); ++t) {
      if (alive_[t] != 0) {
        sum += obj_[t];
        ++nb;
      }
    }
    stats.mean_after = nb > 0 ? sum / static_cast<double>(nb) : 0;
    return stats;
  }

  // The live tets, in the order of their creation.
  std::vector<std::uint32_t> tets() const {
    std::vector<std::uint32_t> out;
    for (std::size_t t = 0; t < tets_.size(); ++t) {
      if (alive_[t] != 0) out.insert(out.end(), tets_[t].begin(), tets_[t].end());
    }
    return out;
  }

 private:
  using Tet = std::array<std::uint32_t, 4>;

  const double* at(std::uint32_t v) const { return &sites_[3 * std::size_t{v}]; }
  double* at(std::uint32_t v) { return &sites_[3 * std::size_t{v}]; }

  // Q1 of a tet given right-handed, kInvalid when it is not right-handed (exact), kBelowFloor
  // when its guarded measure is below `floor` (floor_ by default: set_floor()).
  double quality(const Tet& v) const { return quality(v, floor_); }
  double quality(const Tet& v, double floor) const {
    if (mean_mode_) return mean_quality(v, kNoVertex, nullptr, floor);
    if (orient3d(at(v[0]), at(v[1]), at(v[2]), at(v[3])) != Sign::negative) return kInvalid;
    const TetShape shape = tet_shape(at(v[0]), at(v[1]), at(v[2]), at(v[3]));
    if ((q4_mode_ ? shape.q1_deg : shape.q4) < floor) return kBelowFloor;
    return measure(shape);
  }
  // The floor of the kept measure for an operation replacing old_tets: their smallest, or
  // keep_ when that is lower (floor_of), and set as floor_ (set_floor).
  double floor_of(const std::vector<std::uint32_t>& old_tets) const {
    double floor = keep_;
    for (const std::uint32_t o : old_tets) floor = std::min(floor, guard_[o]);
    return floor;
  }
  void set_floor(const std::vector<std::uint32_t>& old_tets) const { floor_ = floor_of(old_tets); }

  // The measure the current pass raises: Q4, or min(Q1, kQ4Weight Q4).
  double measure(const TetShape& shape) const {
    if (mean_mode_) return shape.q1_deg;
    return q4_mode_ ? shape.q4 : std::min(shape.q1_deg, kQ4Weight * shape.q4);
  }
  void add(const Tet& v) {
    const auto t = static_cast<std::uint32_t>(tets_.size());
    tets_.push_back(v);
    if (mean_mode_) {
      double q4 = 0;
      obj_.push_back(q1_q4(at(v[0]), at(v[1]), at(v[2]), at(v[3]), q4));
      guard_.push_back(q4);
    } else {
      const TetShape shape = tet_shape(at(v[0]), at(v[1]), at(v[2]), at(v[3]));
      obj_.push_back(measure(shape));
      guard_.push_back(q4_mode_ ? shape.q1_deg : shape.q4);
    }
    alive_.push_back(1);
    for (const std::uint32_t x : v) vertex_tets_[x].push_back(t);
  }
  // Whether `new_tets` (vertex x at p when x is given) keep the smallest Q4 of `old_tets`,
  // or kQ4Keep.
  bool keeps_q4(const std::vector<std::uint32_t>& old_tets, const std::vector<Tet>& new_tets,
                std::uint32_t x = kNoVertex, const double* p = nullptr) {
    double before = keep_;
    for (const std::uint32_t o : old_tets) before = std::min(before, guard_[o]);
    std::array<double, 3> keep{};
    if (x != kNoVertex) {
      std::copy(at(x), at(x) + 3, keep.begin());
      std::copy(p, p + 3, at(x));
    }
    double after = std::numeric_limits<double>::infinity();
    for (const Tet& w : new_tets) {
      const TetShape shape = tet_shape(at(w[0]), at(w[1]), at(w[2]), at(w[3]));
      after = std::min(after, q4_mode_ ? shape.q1_deg : shape.q4);
    }
    if (x != kNoVertex) std::copy(keep.begin(), keep.end(), at(x));
    return after >= before;
  }
  void remove(std::uint32_t t) {
    alive_[t] = 0;
    for (const std::uint32_t x : tets_[t]) {
      auto& list = vertex_tets_[x];
      list.erase(std::find(list.begin(), list.end(), t));
    }
  }

  static bool has(const Tet& v, std::uint32_t x) {
    return v[0] == x || v[1] == x || v[2] == x || v[3] == x;
  }

  // The best flip among those that remove t (its four faces, its six edges), applied when
  // its new tets' smallest Q1 beats the replaced tets' by gain_deg. Whether one was (else a move,
  // else an insertion).
  bool improve(std::uint32_t t) {
    double best = -std::numeric_limits<double>::infinity();
    std::vector<std::uint32_t> best_old;
    std::vector<Tet> best_new;
    std::vector<std::uint32_t> old_tets;
    std::vector<Tet> new_tets;
    const Tet v = tets_[t];
    for (int f = 0; f < 4 && options_.flip; ++f) {
      if (face_flip(t, f, old_tets, new_tets))
        consider(old_tets, new_tets, best, best_old, best_new);
    }
    bool best_on_boundary = false;  // whether the best flip is a boundary flip
    for (const auto& e : TetShape::kTetEdges) {
      if (!options_.flip) break;
      if (edge_removal(t, v[e[0]], v[e[1]], old_tets, new_tets)) {
        if (consider(old_tets, new_tets, best, best_old, best_new)) best_on_boundary = false;
      } else if (boundary_flip(v[e[0]], v[e[1]], old_tets, new_tets)) {
        if (consider(old_tets, new_tets, best, best_old, best_new)) best_on_boundary = true;
      }
    }
    if (!best_new.empty()) {
      for (const std::uint32_t o : best_old) remove(o);
      for (const Tet& n : best_new) add(n);
      ++stats_.flips;
      stats_.boundary_flips += best_on_boundary;
      return true;
    }
    if (options_.smooth) {
      // The best move of a free vertex of t.
      double best_move = -std::numeric_limits<double>::infinity();
      std::uint32_t moved = 0;
      std::array<double, 3> to{};
      for (const std::uint32_t x : v) {
        if (free_[x] == kFixed) continue;
        const std::vector<std::uint32_t> star = vertex_tets_[x];
        std::vector<Tet> around;
        for (const std::uint32_t s : star) around.push_back(tets_[s]);
        double before = std::numeric_limits<double>::infinity();
        for (const std::uint32_t s : star) before = std::min(before, obj_[s]);
        std::array<double, 3> p = {at(x)[0], at(x)[1], at(x)[2]};
        set_floor(star);
        const double after = search(x, around, p);
        if (after > before + gain_ && after > best_move && keeps_q4(star, around, x, p.data())) {
          best_move = after;
          moved = x;
          to = p;
        }
      }
      if (best_move > 0) {
        const std::vector<std::uint32_t> star = vertex_tets_[moved];
        std::copy(to.begin(), to.end(), at(moved));
        for (const std::uint32_t s : star) {
          const Tet w = tets_[s];
          remove(s);
          add(w);
        }
        ++stats_.moves;
        return true;
      }
    }
    return options_.insert && insert(t);
  }

  // The mean pass's flips: for each live tet in order, the best of its face flips and edge
  // removals (rings of at most kMeanRing tets) that raises the mesh's mean Q1, applied. Their
  // number. The candidates of a block of kMeanBlock tets are found in parallel on the mesh as
  // it is before the block (mean_candidates); the walk through the block takes a tet's as
  // found when no flip of the block has since removed or made a tet with an edge of it (its
  // candidates only have tets with one of its edges), else finds them again: the flips are
  // those of the walk alone, one tet after the other.
  std::uint32_t mean_flips() {
    std::uint32_t applied = 0;
    std::vector<std::uint32_t> old_tets;
    std::vector<Tet> new_tets;
    std::vector<MeanCandidates> found;
    MeanCandidates again;
    std::vector<std::uint64_t> changed;  // the edges of the tets the block's flips removed or made
    const std::size_t end = tets_.size();
    for (std::size_t first = 0; first < end; first += kMeanBlock) {
      const std::size_t last = std::min(end, first + kMeanBlock);
      found.resize(last - first);
      tbb::parallel_for(tbb::blocked_range<std::size_t>(first, last, 256),
                        [&](const tbb::blocked_range<std::size_t>& range) {
                          std::vector<std::uint32_t> o;  // scratch of this range
                          std::vector<Tet> n;
                          for (std::size_t s = range.begin(); s != range.end(); ++s) {
                            if (alive_[s] != 0)
                              mean_candidates(static_cast<std::uint32_t>(s), o, n,
                                              found[s - first]);
                          }
                        });
      changed.clear();
      for (std::size_t s = first; s < last; ++s) {
        const auto t = static_cast<std::uint32_t>(s);
        if (alive_[t] == 0) continue;
        const MeanCandidates* c = &found[s - first];
        if (!changed.empty() && touches(tets_[t], changed)) {
          mean_candidates(t, old_tets, new_tets, again);
          c = &again;
        }
        // The gain: the new tets' sum of Q1 less the old ones', less the mean per tet added.
        double best = kMeanGain;
        int which = -1;
        const double mean = count_ > 0 ? total_ / static_cast<double>(count_) : 0;
        for (std::size_t i = 0; i < c->size; ++i) {
          const MeanCandidate& m = c->list[i];
          const double gain = m.new_sum - m.old_sum - mean * m.added;
          if (gain > best) {
            best = gain;
            which = m.which;
          }
        }
        if (which < 0) continue;
        mean_candidate(t, which, old_tets, new_tets);
        for (const std::uint32_t o : old_tets) {
          add_edges(tets_[o], changed);
          total_ -= obj_[o];
          remove(o);
        }
        for (const Tet& n : new_tets) {
          add_edges(n, changed);
          add(n);
          total_ += obj_.back();
        }
        std::sort(changed.begin(), changed.end());
        changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
        count_ += new_tets.size();
        count_ -= old_tets.size();
        ++applied;
      }
    }
    return applied;
  }

  // A candidate flip of the mean pass for tet t: which (face flip 0 to 3, the removal of edge
  // which - 4 of TetShape::kTetEdges) and its sums of Q1 (gain: new_sum - old_sum - the mean
  // times added).
  struct MeanCandidate {
    int which = 0;
    double old_sum = 0, new_sum = 0, added = 0;
  };
  struct MeanCandidates {
    std::array<MeanCandidate, 10> list;
    std::size_t size = 0;
  };

  // The flip `which` (MeanCandidate) of t into old_tets and new_tets; false when it is none.
  bool mean_candidate(std::uint32_t t, int which, std::vector<std::uint32_t>& old_tets,
                      std::vector<Tet>& new_tets) const {
    if (which < 4) return face_flip(t, which, old_tets, new_tets);
    const Tet& v = tets_[t];
    const auto& e = TetShape::kTetEdges[static_cast<std::size_t>(which - 4)];
    tets_around(v[e[0]], v[e[1]], old_tets);
    if (old_tets.size() > kMeanRing) return false;
    return edge_removal(t, v[e[0]], v[e[1]], old_tets, new_tets);
  }

  // The candidate flips of t (its face flips, then its edge removals with rings of at most
  // kMeanRing tets) whose new tets are right-handed and keep the smallest Q1 of the old ones or
  // kMeanKeepQ1 and their smallest Q4 or kMeanKeepQ4, in that order, into out. Reads the mesh
  // only (old_tets and new_tets are the caller's scratch).
  void mean_candidates(std::uint32_t t, std::vector<std::uint32_t>& old_tets,
                       std::vector<Tet>& new_tets, MeanCandidates& out) const {
    out.size = 0;
    for (int which = 0; which < 10; ++which) {
      if (!mean_candidate(t, which, old_tets, new_tets)) continue;
      const double floor = floor_of(old_tets);  // Q4
      MeanCandidate m;
      m.which = which;
      double old_min = kMeanKeepQ1;
      for (const std::uint32_t o : old_tets) {
        m.old_sum += obj_[o];
        old_min = std::min(old_min, obj_[o]);
      }
      bool kept = true;
      for (const Tet& n : new_tets) {
        const double q = quality(n, floor);
        if (q < old_min) {
          kept = false;
          break;
        }
        m.new_sum += q;
      }
      if (!kept) continue;
      m.added = static_cast<double>(new_tets.size()) - static_cast<double>(old_tets.size());
      out.list[out.size++] = m;
    }
  }

  // The six edges of w (edge_key) appended to edges.
  static void add_edges(const Tet& w, std::vector<std::uint64_t>& edges) {
    for (const auto& e : TetShape::kTetEdges) edges.push_back(edge_key(w[e[0]], w[e[1]]));
  }
  // Whether an edge of w is in `edges` (sorted).
  static bool touches(const Tet& w, const std::vector<std::uint64_t>& edges) {
    for (const auto& e : TetShape::kTetEdges) {
      if (std::binary_search(edges.begin(), edges.end(), edge_key(w[e[0]], w[e[1]]))) return true;
    }
    return false;
  }

  // The mean pass's moves: each movable vertex to the position found by a compass search on
  // the sum of its star's Q1 (every tet right-handed, the star's smallest Q1 kept or
  // kMeanKeepQ1, its smallest Q4 or kMeanKeepQ4), class by class of move_classes(): the
  // vertices of a class share no tet, so each one's search reads a star that no other move of
  // the class changes; the searches of a class run in parallel and their moves are applied in
  // vertex order, the same for any thread count. Their number.
  std::uint32_t mean_moves() {
    std::uint32_t applied = 0;
    std::vector<MeanMove> found;
    for (const std::vector<std::uint32_t>& members : move_classes()) {
      found.assign(members.size(), MeanMove{});
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, members.size(), 8),
                        [&](const tbb::blocked_range<std::size_t>& range) {
                          std::vector<Tet> around, triangles;  // scratch of this range
                          for (std::size_t i = range.begin(); i != range.end(); ++i)
                            found[i] = mean_move(members[i], around, triangles);
                        });
      for (std::size_t i = 0; i < members.size(); ++i) {
        if (!found[i].moves) continue;
        const std::uint32_t x = members[i];
        std::copy(found[i].to.begin(), found[i].to.end(), at(x));
        const std::vector<std::uint32_t> star = vertex_tets_[x];
        for (const std::uint32_t s : star) {
          const Tet w = tets_[s];
          total_ -= obj_[s];
          remove(s);
          add(w);
          total_ += obj_.back();
        }
        ++applied;
      }
    }
    return applied;
  }

  // The movable vertices (free_, with tets) in classes of which no two share a tet: greedy in
  // vertex order, each vertex into the first class none of its neighbours is in. Each class
  // in vertex order.
  std::vector<std::vector<std::uint32_t>> move_classes() const {
    std::vector<std::uint32_t> class_of(free_.size(), kNoVertex);
    std::vector<std::vector<std::uint32_t>> classes;
    std::vector<std::uint8_t> taken;
    for (std::uint32_t x = 0; x < free_.size(); ++x) {
      if (free_[x] == kFixed || vertex_tets_[x].empty()) continue;
      taken.assign(classes.size(), 0);
      for (const std::uint32_t s : vertex_tets_[x]) {
        for (const std::uint32_t y : tets_[s]) {
          if (class_of[y] != kNoVertex) taken[class_of[y]] = 1;
        }
      }
      const auto c = static_cast<std::uint32_t>(
          std::find(taken.begin(), taken.end(), std::uint8_t{0}) - taken.begin());
      if (c == classes.size()) classes.emplace_back();
      classes[c].push_back(x);
      class_of[x] = c;
    }
    return classes;
  }

  // Where the mean pass moves vertex x (mean_moves()): the compass search on the sum of its
  // star's Q1; a surface vertex only where its boundary triangles are flat (flat()) and no
  // farther from the surface than before (boundary_sag()). Reads the mesh only (around and
  // triangles are the caller's scratch), so the vertices of a class search in parallel.
  struct MeanMove {
    bool moves = false;
    std::array<double, 3> to{};
  };
  MeanMove mean_move(std::uint32_t x, std::vector<Tet>& around, std::vector<Tet>& triangles) const {
    MeanMove m;
    const std::vector<std::uint32_t>& star = vertex_tets_[x];
    around.clear();
    double before = 0, lowest = kMeanKeepQ1, floor = keep_;
    for (const std::uint32_t s : star) {
      around.push_back(tets_[s]);
      before += obj_[s];
      lowest = std::min(lowest, obj_[s]);
      floor = std::min(floor, guard_[s]);
    }
    if (free_[x] == kOnSurface) {
      fan(x, around, triangles);
      if (!flat(triangles)) return m;
    }
    std::array<double, 3> p = {at(x)[0], at(x)[1], at(x)[2]};
    const double after =
        compass(x, around, kMeanFirstStep, kMeanSearchSteps, true, before, p,
                [&](const double* y, double) { return star_sum(x, around, y, lowest, floor); });
    if (!(after > before + kMeanGain)) return m;
    if (free_[x] == kOnSurface) {
      // The boundary triangles at x no farther from the surface (their centroids) than
      // before, at most: the surface moves keep the boundary's distance to the input.
      const double sag = boundary_sag(x, at(x), triangles, nullptr);
      const double moved = boundary_sag(x, p.data(), triangles, at(x));
      if (!(moved <= sag)) return m;
    }
    m.moves = true;
    m.to = p;
    return m;
  }

  // The boundary triangles at x, `around` x's star: the faces of its tets with x that no other
  // tet of the star has, each (a, b, c, d) with d the tet's vertex opposite it and (a, b, c)
  // turning alike for every face of a right-handed tet (so their normals agree on a flat fan).
  void fan(std::uint32_t x, const std::vector<Tet>& around, std::vector<Tet>& out) const {
    out.clear();
    for (std::size_t i = 0; i < around.size(); ++i) {
      for (int f = 0; f < 4; ++f) {
        const std::uint32_t a = around[i][(f + 1) % 4], b = around[i][(f + 2) % 4],
                            c = around[i][(f + 3) % 4];
        if (a != x && b != x && c != x) continue;
        bool inner = false;
        for (std::size_t j = 0; j < around.size() && !inner; ++j) {
          inner = j != i && has(around[j], a) && has(around[j], b) && has(around[j], c);
        }
        if (inner) continue;
        // (f + 1, f + 2, f + 3) turns the other way for odd f.
        if (f % 2 == 0) {
          out.push_back({a, b, c, around[i][static_cast<std::size_t>(f)]});
        } else {
          out.push_back({b, a, c, around[i][static_cast<std::size_t>(f)]});
        }
      }
    }
  }

  // Whether the boundary triangles `fan` (fan()) are within kMeanFlatDeg of each other (their
  // normals), where the mean pass moves a surface vertex: on a curved part of the surface a
  // vertex sliding away from a bump cuts it off (homer and elk at 10,000 vertices: the
  // Hausdorff distance 1.08 to 1.18% and 1.10 to 1.16% of the diagonal with all surface
  // vertices moving).
  bool flat(const std::vector<Tet>& triangles) const {
    std::vector<std::array<double, 3>> normals;
    for (const Tet& t : triangles) {
      double u[3], v[3], n[3];
      sub3(at(t[1]), at(t[0]), u);
      sub3(at(t[2]), at(t[0]), v);
      cross3(u, v, n);
      const double l = std::sqrt(dot3(n, n));
      if (!(l > 0)) return false;
      normals.push_back({n[0] / l, n[1] / l, n[2] / l});
    }
    const double bound = std::cos(kMeanFlatDeg * kPi / 180);
    for (std::size_t i = 0; i < normals.size(); ++i) {
      for (std::size_t j = i + 1; j < normals.size(); ++j) {
        if (!(dot3(normals[i].data(), normals[j].data()) >= bound)) return false;
      }
    }
    return true;
  }

  // The largest distance from the surface (on_surface's projection) of the centroids of the
  // boundary triangles `triangles` at x, with x at p; with `from`, at least the distance from
  // that point to the nearest of them.
  double boundary_sag(std::uint32_t x, const double* p, const std::vector<Tet>& triangles,
                      const double* from) const {
    double sag = 0, nearest = std::numeric_limits<double>::infinity();
    for (const Tet& t : triangles) {
      const double* c[3];
      for (int k = 0; k < 3; ++k)
        c[k] = t[static_cast<std::size_t>(k)] == x ? p : at(t[static_cast<std::size_t>(k)]);
      double g[3], q[3];
      for (int k = 0; k < 3; ++k) g[k] = (c[0][k] + c[1][k] + c[2][k]) / 3;
      options_.on_surface(x, g, q);
      double d[3];
      sub3(q, g, d);
      sag = std::max(sag, dot3(d, d));
      if (from) nearest = std::min(nearest, distance2_to_triangle(from, c[0], c[1], c[2]));
    }
    return std::sqrt(
        from && nearest < std::numeric_limits<double>::infinity() ? std::max(sag, nearest) : sag);
  }

  // The mean pass's Q1 of w with vertex x at p (x = kNoVertex: w as it is): kInvalid when it
  // is not right-handed (exact), kBelowFloor when its Q4 is below `floor`. Reads the mesh only.
  double mean_quality(const Tet& w, std::uint32_t x, const double* p, double floor) const {
    const double* c[4];
    for (std::size_t k = 0; k < 4; ++k) c[k] = w[k] == x ? p : at(w[k]);
    if (orient3d(c[0], c[1], c[2], c[3]) != Sign::negative) return kInvalid;
    double q4 = 0;
    const double q1 = q1_q4(c[0], c[1], c[2], c[3], q4);
    return q4 < floor ? kBelowFloor : q1;
  }

  // The sum of Q1 over `around` with vertex x at p; -infinity when a tet is not right-handed,
  // below the Q4 floor `floor` or below `lowest` in Q1.
  double star_sum(std::uint32_t x, const std::vector<Tet>& around, const double* p, double lowest,
                  double floor) const {
    double sum = 0;
    for (const Tet& w : around) {
      const double r = mean_quality(w, x, p, floor);
      if (r < lowest) return -std::numeric_limits<double>::infinity();
      sum += r;
    }
    return sum;
  }

  // The compass search for vertex x of `around` (all containing x) from p, where `score` is
  // `best`: steps along the axes and towards the mean of its neighbours (that direction first
  // with towards_first, else last), from first_step times the mean edge length, halved when
  // none gains, down to kLastStep, at most `evaluations` scores (a surface vertex's trial
  // points projected by on_surface); the best position found into p, its score returned.
  // score(y, b) is the score at y when that beats b, else any value at most b: a position
  // that does not beat the best so far is dropped, so its score need not be finished.
  template <class Score>
  double compass(std::uint32_t x, const std::vector<Tet>& around, double first_step,
                 int evaluations, bool towards_first, double best, std::array<double, 3>& p,
                 const Score& score) const {
    double length = 0, mean[3] = {0, 0, 0};
    std::uint32_t nb = 0;
    for (const Tet& w : around) {
      for (const std::uint32_t y : w) {
        if (y == x) continue;
        double l2 = 0;
        for (int c = 0; c < 3; ++c) {
          l2 += (at(y)[c] - p[c]) * (at(y)[c] - p[c]);
          mean[c] += at(y)[c];
        }
        length += std::sqrt(l2);
        ++nb;
      }
    }
    if (nb == 0) return best;
    length /= nb;
    double step = first_step * length;
    for (int evaluation = 0; evaluation < evaluations && step > kLastStep * length;) {
      double towards[3], norm2 = 0;
      for (int c = 0; c < 3; ++c) {
        towards[c] = mean[c] / nb - p[c];
        norm2 += towards[c] * towards[c];
      }
      const double scale = norm2 > 0 ? 1 / std::sqrt(norm2) : 0;
      // The six axes, and the direction towards the neighbours' mean first or last.
      const double axes[6][3] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                 {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
      const int along = towards_first ? 0 : 6;
      double directions[7][3];
      for (int k = 0, axis = 0; k < 7; ++k) {
        for (int c = 0; c < 3; ++c) {
          directions[k][c] = k == along ? towards[c] * scale : axes[axis][c];
        }
        if (k != along) ++axis;
      }
      std::array<double, 3> next = p;
      bool gained = false;
      for (const auto& d : directions) {
        double y[3] = {p[0] + step * d[0], p[1] + step * d[1], p[2] + step * d[2]};
        if (free_[x] == kOnSurface) {
          double z[3];
          if (!options_.on_surface(x, y, z)) continue;
          std::copy(z, z + 3, y);
        }
        const double q = score(y, best);
        ++evaluation;
        if (q > best) {
          best = q;
          next = {y[0], y[1], y[2]};
          gained = true;
        }
      }
      if (gained) {
        p = next;
      } else {
        step /= 2;
      }
    }
    return best;
  }

  // The smallest Q1 of `around` with vertex x at p; once it is at most `stop`, any value at
  // most `stop` (the compass search drops such a position).
  double star_quality(std::uint32_t x, const std::vector<Tet>& around, const double* p,
                      double stop = -std::numeric_limits<double>::infinity()) {
    double* q = at(x);
    const std::array<double, 3> keep = {q[0], q[1], q[2]};
    std::copy(p, p + 3, q);
    double worst = std::numeric_limits<double>::infinity();
    for (const Tet& w : around) {
      worst = std::min(worst, quality(w));
      if (worst == kInvalid || worst <= stop) break;
    }
    std::copy(keep.begin(), keep.end(), q);
    return worst;
  }

  // The compass search for vertex x of `around` (all containing x), from p: the best position
  // found into p, its smallest Q1 returned (kInvalid for an empty `around`).
  double search(std::uint32_t x, const std::vector<Tet>& around, std::array<double, 3>& p) {
    if (around.empty()) return kInvalid;
    return compass(x, around, kFirstStep, kSearchSteps, false, star_quality(x, around, p.data()), p,
                   [&](const double* y, double best) { return star_quality(x, around, y, best); });
  }

  // A new free vertex in the cavity of t and its face neighbours, when the star of its best
  // position found beats the cavity's smallest Q1 by gain_deg. Whether it was inserted.
  bool insert(std::uint32_t t) {
    std::vector<std::uint32_t> cavity = {t};
    std::vector<std::uint32_t> old_tets;
    std::vector<Tet> new_tets;
    for (int f = 0; f < 4; ++f) {
      if (face_flip(t, f, old_tets, new_tets)) cavity.push_back(old_tets[1]);
    }
    // The cavity's faces: each face of a cavity tet not shared with another, as that tet
    // with the opposite vertex to be replaced by the new vertex.
    const auto x = static_cast<std::uint32_t>(sites_.size() / 3);
    std::vector<Tet> star;
    for (const std::uint32_t c : cavity) {
      for (int f = 0; f < 4; ++f) {
        const Tet& w = tets_[c];
        const std::uint32_t a = w[(f + 1) % 4], b = w[(f + 2) % 4], d = w[(f + 3) % 4];
        bool inner = false;
        for (const std::uint32_t o : cavity) {
          inner = inner || (o != c && has(tets_[o], a) && has(tets_[o], b) && has(tets_[o], d));
        }
        if (inner) continue;
        Tet n = w;
        n[static_cast<std::size_t>(f)] = x;
        star.push_back(n);
      }
    }
    // Every vertex of the cavity on one of its faces: none would be left out of the mesh.
    for (const std::uint32_t c : cavity) {
      for (const std::uint32_t y : tets_[c]) {
        bool on_face = false;
        for (const Tet& n : star) on_face = on_face || has(n, y);
        if (!on_face) return false;
      }
    }
    double before = std::numeric_limits<double>::infinity();
    for (const std::uint32_t c : cavity) before = std::min(before, obj_[c]);
    std::array<double, 3> p{};
    for (const std::uint32_t y : tets_[t]) {
      for (int c = 0; c < 3; ++c) p[c] += at(y)[c] / 4;
    }
    // x exists (a free vertex) while its position is searched; taken back when rejected.
    sites_.insert(sites_.end(), p.begin(), p.end());
    free_.push_back(kMovable);
    set_floor(cavity);
    const double after = search(x, star, p);
    if (!(after > before + gain_) || !keeps_q4(cavity, star, x, p.data())) {
      sites_.resize(3 * std::size_t{x});
      free_.pop_back();
      return false;
    }
    std::copy(p.begin(), p.end(), at(x));
    vertex_tets_.emplace_back();
    surface_.push_back(0);
    for (const std::uint32_t c : cavity) remove(c);
    for (const Tet& n : star) add(n);
    ++stats_.insertions;
    return true;
  }

  // Keeps (old, new) as the best flip so far when its gain is larger than gain_deg and its
  // new minimum larger than the best's. Whether it was kept.
  bool consider(const std::vector<std::uint32_t>& old_tets, const std::vector<Tet>& new_tets,
                double& best, std::vector<std::uint32_t>& best_old, std::vector<Tet>& best_new) {
    double before = std::numeric_limits<double>::infinity();
    for (const std::uint32_t o : old_tets) before = std::min(before, obj_[o]);
    set_floor(old_tets);
    double after = std::numeric_limits<double>::infinity();
    for (const Tet& n : new_tets) after = std::min(after, quality(n));
    if (after > before + gain_ && after > best && keeps_q4(old_tets, new_tets)) {
      best = after;
      best_old = old_tets;
      best_new = new_tets;
      return true;
    }
    return false;
  }

  // The 2-3 flip of t's face opposite its vertex f, when that face is interior and the
  // flip valid.
  bool face_flip(std::uint32_t t, int f, std::vector<std::uint32_t>& old_tets,
                 std::vector<Tet>& new_tets) const {
    const Tet& v = tets_[t];
    const std::uint32_t a = v[(f + 1) % 4], b = v[(f + 2) % 4], c = v[(f + 3) % 4];
    std::uint32_t u = t;
    for (const std::uint32_t s : vertex_tets_[a]) {
      if (s != t && has(tets_[s], b) && has(tets_[s], c)) {
        u = s;
        break;
      }
    }
    if (u == t) return false;  // a boundary face
    std::uint32_t e = a;
    for (const std::uint32_t x : tets_[u]) {
      if (x != a && x != b && x != c) e = x;
    }
    old_tets.assign({t, u});
    new_tets.clear();
    for (int k = 0; k < 4; ++k) {
      if (k == f) continue;
      Tet n = v;
      n[static_cast<std::size_t>(k)] = e;
      new_tets.push_back(n);
    }
    return true;
  }

  // Each tet of old_tets (all around the edge (a, b)) as its other two vertices (p, q) with
  // (a, b, p, q) right-handed (an even permutation of the tet).
  using Pairs = std::array<std::array<std::uint32_t, 2>, kMaxRing>;
  void pairs_around(std::uint32_t a, std::uint32_t b, const std::vector<std::uint32_t>& old_tets,
                    Pairs& pair) const {
    const std::size_t k = old_tets.size();
    for (std::size_t i = 0; i < k; ++i) {
      const Tet& w = tets_[old_tets[i]];
      std::uint32_t other[2], n_other = 0;
      int ia = 0, ib = 0;
      for (int j = 0; j < 4; ++j) {
        if (w[static_cast<std::size_t>(j)] == a) {
          ia = j;
        } else if (w[static_cast<std::size_t>(j)] == b) {
          ib = j;
        } else {
          other[n_other++] = static_cast<std::uint32_t>(j);
        }
      }
      // (ia, ib, other0, other1) as a permutation of (0, 1, 2, 3): its parity.
      const int perm[4] = {ia, ib, static_cast<int>(other[0]), static_cast<int>(other[1])};
      int inversions = 0;
      for (int x = 0; x < 4; ++x) {
        for (int y = x + 1; y < 4; ++y) inversions += perm[x] > perm[y];
      }
      pair[i] = {w[other[0]], w[other[1]]};
      if (inversions % 2 != 0) std::swap(pair[i][0], pair[i][1]);
    }
  }

  // The tets with the edge (a, b), into old_tets.
  void tets_around(std::uint32_t a, std::uint32_t b, std::vector<std::uint32_t>& old_tets) const {
    old_tets.clear();
    for (const std::uint32_t s : vertex_tets_[a]) {
      if (has(tets_[s], b)) old_tets.push_back(s);
    }
  }

  // The vertices r_0 .. r_k of the k pairs chained from pair[start] (each pair's first vertex
  // the previous pair's second), into ring; false when they do not chain. Around an interior
  // edge the chain closes (r_k = r_0); around a boundary edge it is an open fan.
  using Ring = std::array<std::uint32_t, kMaxRing + 1>;
  static bool chain(const Pairs& pair, std::size_t k, std::size_t start, Ring& ring) {
    std::array<std::uint8_t, kMaxRing> used{};
    ring[0] = pair[start][0];
    ring[1] = pair[start][1];
    used[start] = 1;
    for (std::size_t i = 2; i <= k; ++i) {
      std::size_t next = k;
      for (std::size_t j = 0; j < k; ++j) {
        if (used[j] == 0 && pair[j][0] == ring[i - 1]) next = j;
      }
      if (next == k) return false;
      used[next] = 1;
      ring[i] = pair[next][1];
    }
    return true;
  }

  // The removal of the edge (a, b) of t, by the best triangulation of its ring, when the
  // edge is interior, its ring has at most kMaxRing tets and some triangulation is valid.
  bool edge_removal(std::uint32_t t, std::uint32_t a, std::uint32_t b,
                    std::vector<std::uint32_t>& old_tets, std::vector<Tet>& new_tets) const {
    tets_around(a, b, old_tets);
    const std::size_t k = old_tets.size();
    if (k < 3 || k > kMaxRing) return false;
    // The ring, chained from t's pair.
    Pairs pair{};
    pairs_around(a, b, old_tets, pair);
    std::size_t start = 0;
    while (old_tets[start] != t) ++start;
    Ring ring{};
    // An open chain: a boundary edge (or not a manifold one).
    if (!chain(pair, k, start, ring) || ring[k] != ring[0]) return false;
    return triangulate(ring.data(), k, a, b, floor_of(old_tets), new_tets);
  }

  // The best triangulation of the polygon r_0 .. r_{n-1} (the ring of the edge (a, b), or
  // its open fan with the new edge (r_0, r_{n-1})): each of its triangles (r_i, r_m, r_j),
  // i < m < j, as the tets (r_i, r_m, r_j, b) and (r_i, r_j, r_m, a), into new_tets; false
  // when none has only right-handed tets.
  bool triangulate(const std::uint32_t* ring, std::size_t n, std::uint32_t a, std::uint32_t b,
                   double floor, std::vector<Tet>& new_tets) const {
    // best[i][j]: the best min Q1 over the triangulations of the sub-polygon r_i .. r_j,
    // apex[i][j] the apex of its edge (r_i, r_j) in that triangulation.
    double best[kMaxRing + 1][kMaxRing + 1];
    std::size_t apex[kMaxRing + 1][kMaxRing + 1];
    const auto triangle = [&](std::size_t i, std::size_t j, std::size_t m) {
      return std::min(quality({ring[i], ring[j], ring[m], b}, floor),
                      quality({ring[i], ring[m], ring[j], a}, floor));
    };
    for (std::size_t i = 0; i + 1 < n; ++i)
      best[i][i + 1] = std::numeric_limits<double>::infinity();
    for (std::size_t len = 2; len < n; ++len) {
      for (std::size_t i = 0; i + len < n; ++i) {
        const std::size_t j = i + len;
        best[i][j] = kInvalid;
        apex[i][j] = i + 1;
        for (std::size_t m = i + 1; m < j; ++m) {
          const double q = std::min({best[i][m], best[m][j], triangle(i, m, j)});
          if (q > best[i][j]) {
            best[i][j] = q;
            apex[i][j] = m;
          }
        }
      }
    }
    if (!(best[0][n - 1] > 0)) return false;
    new_tets.clear();
    std::vector<std::pair<std::size_t, std::size_t>> stack = {{0, n - 1}};
    while (!stack.empty()) {
      const auto [i, j] = stack.back();
      stack.pop_back();
      if (j - i < 2) continue;
      const std::size_t m = apex[i][j];
      new_tets.push_back({ring[i], ring[m], ring[j], b});
      new_tets.push_back({ring[i], ring[j], ring[m], a});
      stack.emplace_back(i, m);
      stack.emplace_back(m, j);
    }
    return true;
  }

  // The boundary 2-2 flip of the edge (a, b) of t: its tets an open fan r_0 .. r_k (k from 2
  // to kMaxRing; (a, b, r_i, r_{i+1}) right-handed), its boundary triangles (a, b, r_0) and
  // (a, b, r_k) replaced by (a, r_0, r_k) and (b, r_k, r_0), the fan by the best
  // triangulation of the polygon r_0 .. r_k; when options_.same_patch(a, b, r_0, r_k), a or
  // b is a surface vertex, (r_0, r_k) is no edge of the mesh, the four triangles' normals
  // are within kBoundaryFlipDeg of each other and every new tet is right-handed.
  bool boundary_flip(std::uint32_t a, std::uint32_t b, std::vector<std::uint32_t>& old_tets,
                     std::vector<Tet>& new_tets) const {
    if (!options_.same_patch) return false;
    if (!surface_[a] && !surface_[b]) return false;
    tets_around(a, b, old_tets);
    const std::size_t k = old_tets.size();
    if (k < 2 || k > kMaxRing) return false;
    Pairs pair{};
    pairs_around(a, b, old_tets, pair);
    // The fan starts at the pair whose first vertex is no pair's second.
    std::size_t start = k;
    for (std::size_t i = 0; i < k; ++i) {
      bool second = false;
      for (std::size_t j = 0; j < k; ++j) second = second || pair[j][1] == pair[i][0];
      if (!second) {
        if (start != k) return false;
        start = i;
      }
    }
    if (start == k) return false;  // a closed ring: an interior edge
    Ring ring{};
    if (!chain(pair, k, start, ring)) return false;  // not one fan
    const std::uint32_t c = ring[0], d = ring[k];
    if (c == d) return false;
    for (const std::uint32_t s : vertex_tets_[c]) {
      if (has(tets_[s], d)) return false;  // (c, d) an edge: the boundary would not be a manifold
    }
    if (!options_.same_patch(a, b, c, d)) return false;
    // The outward normals: old (a, b, c), (b, a, d), new (a, c, d), (b, d, c).
    const auto normal = [&](std::uint32_t x, std::uint32_t y, std::uint32_t z) {
      std::array<double, 3> u{}, v{};
      for (int i = 0; i < 3; ++i) {
        u[i] = at(y)[i] - at(x)[i];
        v[i] = at(z)[i] - at(x)[i];
      }
      return std::array<double, 3>{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                                   u[0] * v[1] - u[1] * v[0]};
    };
    const std::array<std::array<double, 3>, 4> normals = {normal(a, c, b), normal(b, d, a),
                                                          normal(a, c, d), normal(b, d, c)};
    const double cos_bound = std::cos(kBoundaryFlipDeg * kPi / 180);
    for (std::size_t i = 0; i < 4; ++i) {
      for (std::size_t j = i + 1; j < 4; ++j) {
        const auto& n = normals[i];
        const auto& m = normals[j];
        const double dot = n[0] * m[0] + n[1] * m[1] + n[2] * m[2];
        const double nn = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        const double mm = std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
        if (!(nn > 0 && mm > 0 && dot >= cos_bound * nn * mm)) return false;
      }
    }
    return triangulate(ring.data(), k + 1, a, b, floor_of(old_tets), new_tets);
  }

  std::vector<double>& sites_;
  const Flip3Options& options_;
  Flip3Stats stats_;
  std::vector<std::vector<std::uint32_t>> vertex_tets_;
  std::vector<std::uint8_t> free_;
  std::vector<std::uint8_t> surface_;  // whether a vertex is a surface vertex (kSurface)
  std::vector<Tet> tets_;
  // Per tet: the measure operations raise (measure()) and the one they keep (Q4 in the Q1
  // pass, Q1 in the Q4 passes).
  std::vector<double> obj_, guard_;
  bool q4_mode_ = false;
  // raise_mean(): the measure is Q1 and the kept one Q4 (q4_mode_ false).
  bool mean_mode_ = false;
  // raise_mean(): the sum of the live tets' Q1 and their number.
  double total_ = 0;
  std::size_t count_ = 0;
  // While an operation is evaluated: the least value of the kept measure (Q4 in the Q1
  // pass, Q1 in the Q4 pass) its new tets may have (set_floor); quality() ranks a tet below
  // it as kBelowFloor.
  mutable double floor_ = 0;
  double gain_ = options_.gain_deg, keep_ = kQ4Keep;
  std::vector<std::uint8_t> alive_;
};

}  // namespace

Mean3Stats raise_mean3(
    std::vector<double>& sites, const std::vector<Kind>& kinds, std::vector<std::uint32_t>& tets,
    std::uint32_t rounds,
    const std::function<bool(std::uint32_t, const double*, double*)>& on_surface) {
  if (kinds.size() != sites.size() / 3) {
    throw Error("raise_mean3: " + std::to_string(kinds.size()) + " constraints for " +
                std::to_string(sites.size() / 3) + " sites");
  }
  Flip3Options options;
  options.on_surface = on_surface;
  Flipper flipper(sites, kinds, tets, options);
  const Mean3Stats stats = flipper.raise_mean(rounds);
  if (stats.flips + stats.moves > 0) tets = flipper.tets();
  return stats;
}

Flip3Stats flip_slivers3(std::vector<double>& sites, const std::vector<Kind>& kinds,
                         std::vector<std::uint32_t>& tets, const Flip3Options& options) {
  Flipper flipper(sites, kinds, tets, options);
  const Flip3Stats stats = flipper.run();
  if (stats.flips + stats.moves + stats.insertions > 0) tets = flipper.tets();
  return stats;
}

}  // namespace voroclip::mesh3
