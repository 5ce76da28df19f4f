// voroclip/delaunay.h — Delaunay triangulations (the module's one public header).
//
// Delaunay2: the 2D Delaunay triangulation by Bowyer–Watson insertion (Bowyer 1981,
// Watson 1981) in BRIO order over a Hilbert curve (Amenta, Choi & Rote 2003), with exact
// predicates and symbolic perturbation, on flat 32-bit arrays.
//
// Storage (24 bytes per triangle slot, about 2 slots per point):
//   tri_vertices_[3t + k]   vertex k of triangle t: an input point index, or kInfinite
//   tri_neighbors_[3t + k]  3t' + k': the triangle t' across the edge opposite vertex k,
//                           and the local index k' of the vertex of t' opposite that edge
// The construction works on one 32-byte record per triangle instead (vertices, the cavity
// search's stamp, neighbour codes: one cache line for two triangles), which the
// renumbering below converts to these arrays. The stamp is compared with a counter that
// only grows, so it is never cleared between insertions. The convex hull is closed by infinite
// triangles, each made of one hull edge and the infinite vertex kInfinite, so every edge has two
// triangles (a triangulated sphere). Slots freed while inserting go to a free list and are reused
// first.
//
// Local numbering (the one convention; everything else refers to it):
//
//            v2                  Vertices counter-clockwise: orient2d(v0, v1, v2) > 0.
//           /  \                 Edge k is opposite vertex k, with endpoints listed as
//     e1   /    \   e0           kEdgeVertex[k] = (v_{k+1}, v_{k+2}) (indices mod 3), so
//         /      \               the triangle's inside is on the left of v_{k+1} -> v_{k+2}
//       v0 ------ v1             and orient2d(v_{k+1}, v_{k+2}, p) < 0 means p is beyond
//            e2                  edge k. The neighbour across edge k lists it reversed.
//
// An infinite triangle (a, b, kInfinite) (in any rotation) is ordered as if kInfinite were
// a point far beyond its hull edge: the triangulation's inside is on the RIGHT of a -> b,
// orient2d(a, b, p) > 0 means p is strictly outside the hull across that edge.
//
// Conflict (the Bowyer–Watson cavity of a new point p with input index ip):
//   finite triangle (a, b, c)       incircle_sos(a, b, c, p, ia, ib, ic, ip) > 0
//   infinite triangle, hull edge    orient2d(a, b, p) > 0 (strictly outside), or
//   (a, b) as listed in it          orient2d(a, b, p) == 0 and p strictly between a and b
// The perturbation makes the result the regular triangulation of the points with
// infinitesimal weights given by their indices: a refinement of the Delaunay subdivision
// that is unique, so it does not depend on the insertion order. The rule for infinite
// triangles is the limit of the lifting (as in CGAL): points exactly on the hull between
// two hull vertices become hull vertices on a straight hull edge, and no triangle of zero
// area is ever created. With n' distinct points, b of them on the hull boundary, there are
// exactly 2n' - b - 2 finite triangles and b infinite ones.
//
// Canonical output. After each build the triangles are renumbered in an order that is a
// function of the input alone, not of the insertion history (the insertion order is itself
// a fixed function of the input: detail::brio_order). Finite triangles occupy
// [0, nb_triangles()), sorted by (r0, r1) where r0 is the largest insertion rank (position
// in the BRIO order) among the triangle's vertices and r1 the rank of the vertex following
// that one counter-clockwise, so that triangles numbered close together are close in
// space; each is rotated to start at its smallest input index. Infinite triangles follow,
// rotated to (a, b, kInfinite), in hull order (the next one starts at b) from the one whose
// a has the smallest input index. There are no free slots after a build;
// vertex_triangle(v) is the smallest-numbered finite triangle incident to v. (Keeping the
// construction's slot order instead saves 0.03 s of a 1M-point build but made the
// clipping that reads the triangles in this order 35% slower.)
//
// Duplicates. Points with exactly equal coordinates are detected while inserting; only the
// one with the smallest index becomes a vertex. duplicate_of(i) gives that index. (When a
// smaller-index twin arrives after its vertex was inserted, the triangulation is rebuilt
// from the distinct points so that the perturbation sees the vertex's final index.)
//
// Points. The construction works on a copy of the coordinates in insertion order (for
// memory locality), but the finished triangulation reads the caller's array: the array
// passed to the constructor or build() must stay alive and unchanged while the
// triangulation is used (until the next build()).
//
// Threads. The spatial sort and the renumbering use TBB parallel loops over disjoint
// ranges. With several threads, a large BRIO round (Options::zoned_round) is split into
// strips across the longest axis of its box, at quantiles of its points, and each strip's
// points are inserted by their own task in the round's order: a task only touches
// triangles having an edge with both endpoints in its strip, which no other task can
// touch (two edges of a triangle share a vertex), so the tasks need no locks. A point
// whose walk or cavity would reach a triangle with a vertex outside the strip is deferred,
// leaving the triangulation untouched; the deferred points are inserted sequentially after
// the round (a round whose strips defer more than half of its points, as points on a
// circle do, ends the strips for the rest of the build). Each task takes new slots from
// its own range and stamps from its own range of values. The triangulation is unique
// (the perturbation), and the renumbering below does not depend on the insertion
// history, so the result is identical for any thread count and any number of strips.
//
// Speed (bench/bench_delaunay2, bench/compare/compare_delaunay2; bench/RESULTS.md): 1M
// uniform points in 0.50-0.62 s for a first build on two threads (0.47-0.51 s for a
// rebuild, 0.81-0.87 s on one thread) on the project's 2-core "AMD EPYC" VM, where CGAL's
// Delaunay_triangulation_2 took 0.89-0.97 s in the same runs: 0.54-0.64x (one thread
// 0.83-0.97x). A 1000 x 1000 integer grid takes 1.3 times as long, 1M points on a circle
// 2.4 times.
#pragma once

#include <cassert>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include "voroclip/predicates.h"

namespace voroclip {

// ---------------------------------------------------------------------------------------
// Spatial sorting (delaunay/src/spatial_sort.cpp), for callers that want their points, and
// so their memory accesses, in the order of a space-filling curve (as the triangulations'
// insertion orders and the 3D clipped diagram's cells are).

// Sorts the point indices [first, last) along a Hilbert curve over the bounding box of
// those points (packed coordinates, dim = 2 or 3 doubles each): the order of each BRIO
// round, and of the points for Delaunay3Options::presorted. Parallel; a fixed function of
// the coordinates and of the order of [first, last), which points with equal coordinates
// keep among themselves.
void hilbert_sort(const double* coords, int dim, std::uint32_t* first, std::uint32_t* last);

// The smallest index of a point (packed coordinates, dim = 2 or 3 doubles each) with a
// non-finite coordinate, or n if there is none; then lo and hi (dim values each) receive
// the points' bounding box. Parallel over fixed blocks: the same answer for any number of
// threads.
std::uint32_t finite_bounding_box(const double* coords, std::uint32_t n, int dim, double* lo,
                                  double* hi);

namespace detail {

// Asks the kernel to back the whole 2 MiB pages inside [p, p + bytes) with transparent
// huge pages when they are first touched (Linux madvise(MADV_HUGEPAGE); no effect
// elsewhere, on pages already touched, or when the system disables it). For the large
// arrays of one build: one page fault per 2 MiB instead of per 4 KiB. Never changes results.
void advise_huge_pages(void* p, std::size_t bytes) noexcept;

// While one lives with enabled == false, advise_huge_pages() does nothing on the thread that
// made it (restored when it goes). Delaunay3::build() on one thread uses it: its page faults
// are then on the critical path, and fresh huge pages measured slower to fault in than 4 KiB
// pages on the 2-core VM (1M points, one thread: 2.35-2.59 s advised, 2.19-2.26 s not); on
// several threads the other thread faults the pages in ahead of the zones, and the huge
// pages spare the cells' traversals TLB misses (bench/RESULTS.md).
class HugePageAdvice {
 public:
  explicit HugePageAdvice(bool enabled) noexcept;
  ~HugePageAdvice();
  HugePageAdvice(const HugePageAdvice&) = delete;
  HugePageAdvice& operator=(const HugePageAdvice&) = delete;

 private:
  bool previous_;
};

// Arrays at least this large get advise_huge_pages() when allocated.
inline constexpr std::size_t kHugePageAdviceBytes = std::size_t{4} << 20;

// Gives v room for n elements, advised for huge pages when large. The contents are lost
// when it has to grow: for arrays rewritten completely by the caller.
template <class Vector>
void reserve_advised(Vector& v, std::size_t n) {
  if (v.capacity() >= n) return;
  Vector().swap(v);
  v.reserve(n);
  const std::size_t bytes = n * sizeof(typename Vector::value_type);
  if (bytes >= kHugePageAdviceBytes) advise_huge_pages(v.data(), bytes);
}

// An allocator whose vector elements are left uninitialized by resize(): for arrays whose
// every element is written before it is read, so that growing them touches no memory.
// Large blocks are advised for huge pages.
template <class T>
struct UninitializedAllocator : std::allocator<T> {
  using value_type = T;
  template <class U>
  struct rebind {
    using other = UninitializedAllocator<U>;
  };
  UninitializedAllocator() = default;
  template <class U>
  explicit UninitializedAllocator(const UninitializedAllocator<U>&) {}
  T* allocate(std::size_t n) {
    T* p = std::allocator<T>::allocate(n);
    if (n * sizeof(T) >= kHugePageAdviceBytes) advise_huge_pages(p, n * sizeof(T));
    return p;
  }
  template <class U>
  void construct(U* p) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

}  // namespace detail

struct Delaunay2Options {
  // Run check_topology() and check_delaunay() at the end of every build and throw
  // voroclip::Error if either finds a defect (slow: for debugging and the CLI's --check).
  bool check = false;
  // Keep the construction buffers (point copy, sort keys, renumbering arrays) between
  // builds, so that a rebuild allocates nothing: about 180 bytes per point in all. With
  // false they are freed at the end of each build, leaving about 60 bytes per point (the
  // triangle arrays, 24 bytes per triangle, and the per-point maps).
  bool keep_buffers = true;
  // Parallel insertion (see "Threads" above): a BRIO round of at least this many points is
  // split into strips inserted by concurrent tasks, when more than one thread is available
  // or `zones` asks for it. The triangulation never depends on it.
  std::uint32_t zoned_round = 32768;
  // The number of strips of a zoned round: 0 for the number of threads TBB may use (at
  // most 8; a single thread inserts everything sequentially), else that many (2 to 64)
  // whatever the thread count (tests).
  std::uint32_t zones = 0;
};

class Delaunay2 {
 public:
  using Options = Delaunay2Options;

  static constexpr std::uint32_t kInfinite = 0xffffffffu;
  static constexpr std::uint32_t kNone = 0xffffffffu;
  // Inputs above this size would overflow the 32-bit encodings 3t + k.
  static constexpr std::uint32_t kMaxPoints = 1u << 29;
  // kEdgeVertex[k]: the local indices of the endpoints of edge k (see the diagram).
  static constexpr int kEdgeVertex[3][2] = {{1, 2}, {2, 0}, {0, 1}};

  Delaunay2() = default;
  explicit Delaunay2(const Options& options) : options_(options) {}
  // Triangulates the n points given as packed x y. Throws voroclip::Error for a
  // non-finite coordinate (naming the point) or fewer than 3 affinely independent points.
  Delaunay2(const double* xy, std::uint32_t n, const Options& options = {});

  // (Re)builds on new points, reusing every buffer (CVT rebuilds at each iteration).
  void build(const double* xy, std::uint32_t n);

  // ---- Points and vertices
  std::uint32_t nb_points() const { return nb_points_; }
  // Distinct points = vertices of the triangulation (input indices i with duplicate_of(i) == i).
  std::uint32_t nb_unique_points() const { return nb_unique_; }
  std::uint32_t nb_vertices() const { return nb_unique_; }
  // The smallest input index with the same coordinates as point i (i for a vertex).
  std::uint32_t duplicate_of(std::uint32_t i) const;
  const double* point(std::uint32_t v) const;

  // ---- Triangles. Finite ones are [0, nb_triangles()), infinite ones follow.
  std::uint32_t nb_triangles() const { return nb_finite_; }
  std::uint32_t nb_triangle_slots() const { return nb_slots_; }
  bool is_infinite(std::uint32_t t) const;
  std::uint32_t tri_vertex(std::uint32_t t, int k) const;
  // The triangle across edge k of t, and the local index of that edge in it.
  std::uint32_t tri_adjacent(std::uint32_t t, int k) const;
  int tri_adjacent_edge(std::uint32_t t, int k) const;
  // The raw encoding 3t' + k' (see above).
  std::uint32_t tri_neighbor_code(std::uint32_t t, int k) const;
  const std::vector<std::uint32_t>& tri_vertices() const { return tri_vertices_; }
  const std::vector<std::uint32_t>& tri_neighbors() const { return tri_neighbors_; }
  // The local index of vertex v in t; asserts that v is one.
  int local_index(std::uint32_t t, std::uint32_t v) const;

  // ---- Around a vertex (v must be a vertex: duplicate_of(v) == v)
  // The smallest-numbered finite triangle incident to v (kNone for duplicates).
  std::uint32_t vertex_triangle(std::uint32_t v) const;
  // The finite triangles incident to v in counter-clockwise order: for a hull vertex, the
  // whole fan from the hull edge leaving v to the one entering it; for an inner vertex,
  // the full cycle starting at vertex_triangle(v). `out` is cleared first.
  void triangles_around_vertex(std::uint32_t v, std::vector<std::uint32_t>& out) const;
  // The Delaunay neighbours of v (the sites whose Voronoi cells share an edge with v's),
  // counter-clockwise, in the same rotation as triangles_around_vertex.
  void vertex_neighbors(std::uint32_t v, std::vector<std::uint32_t>& out) const;
  bool is_hull_vertex(std::uint32_t v) const;

  // ---- Hull, counter-clockwise (inside on the left), starting at its smallest vertex.
  std::vector<std::uint32_t> hull_vertices() const;
  // Pairs (u, w) flattened: edge i is (out[2i], out[2i + 1]).
  std::vector<std::uint32_t> hull_edges() const;

  // ---- Geometry (floating point, not exact: for output and clipping)
  // The circumcenter of finite triangle t (circumcenter2d of predicates.h: within
  // kConstructionLimit of the triangle's size however flat it is, a few ulps when the
  // floating-point formula cannot guarantee that).
  void circumcenter(std::uint32_t t, double* out) const;

  // ---- Queries (exact orientation tests; the query point need not be an input point)
  // A finite triangle containing (x, y) in its closure, or an infinite triangle whose hull
  // edge has (x, y) strictly outside. `hint`: a triangle to start the walk from.
  std::uint32_t locate(double x, double y, std::uint32_t hint = kNone) const;
  // The vertex nearest to (x, y), decided exactly (compare_distance2d); among equidistant
  // nearest vertices the smallest index. Locate, then greedy descent over Delaunay
  // neighbours (which reaches the nearest site in a Delaunay triangulation).
  std::uint32_t nearest_vertex(double x, double y, std::uint32_t hint = kNone) const;

  // ---- Exact checks, called by the tests on every result. Each returns an empty string
  // when valid, else a description of the first defect found.
  // Adjacency symmetric and consistent with the vertices, every finite triangle strictly
  // counter-clockwise (exact orient2d), one umbrella per vertex, incident triangles
  // valid, canonical layout, Euler count (finite + infinite = 2 nb_vertices - 2).
  std::string check_topology() const;
  // For every edge, the vertex opposite across it is not in conflict with the triangle
  // (the same exact conflict test as the construction, with the perturbation): locally
  // Delaunay everywhere, hence globally.
  std::string check_delaunay() const;

  // How the last build inserted its points (counts of insertion attempts; see "Threads").
  struct Stats {
    std::uint32_t zoned_passes = 0;     // rounds split into strips
    std::uint32_t zoned_points = 0;     // points attempted in a strip
    std::uint32_t deferred_points = 0;  // of those, deferred to the sequential insertion
  };
  const Stats& stats() const { return stats_; }

 private:
  static constexpr std::uint32_t kFreeVertex = 0xfffffffeu;

  const double* pt(std::uint32_t v) const { return xy_ + 2 * static_cast<std::size_t>(v); }
  // During construction the triangles hold local vertex ids: ranks in the insertion order,
  // whose coordinates are copied to coords_ in that order (so that consecutive insertions
  // touch nearby memory); input_index_ maps them back. canonicalize() converts to input
  // indices.
  const double* local_pt(std::uint32_t v) const {
    return coords_.data() + 2 * static_cast<std::size_t>(v);
  }
  int infinite_slot(std::uint32_t t) const {
    const std::uint32_t* v = &tri_vertices_[3 * static_cast<std::size_t>(t)];
    return v[0] == kInfinite ? 0 : v[1] == kInfinite ? 1 : v[2] == kInfinite ? 2 : -1;
  }
  // A triangle's vertices and neighbour codes: in rec_ during construction (kLocal), in
  // the final arrays after it.
  template <bool kLocal>
  const std::uint32_t* vertices_of(std::uint32_t t) const {
    if constexpr (kLocal) {
      return &rec_[8 * static_cast<std::size_t>(t)];
    } else {
      return &tri_vertices_[3 * static_cast<std::size_t>(t)];
    }
  }
  template <bool kLocal>
  std::uint32_t neighbor_of(std::uint32_t t, int k) const {
    if constexpr (kLocal) {
      return rec_[8 * static_cast<std::size_t>(t) + 4 + static_cast<std::size_t>(k)];
    } else {
      return tri_neighbors_[3 * static_cast<std::size_t>(t) + static_cast<std::size_t>(k)];
    }
  }
  // Per-insertion and per-build scratch, reused.
  struct BoundaryEdge {
    std::uint32_t u, w;     // the edge, counter-clockwise as seen from the new point
    std::uint32_t outside;  // code 3t' + k' of the triangle beyond it
  };
  // The state of one inserting task: the sequential insertion's (everywhere), or one strip
  // of a zoned round, lo <= p[axis] < hi (bounds may be infinite).
  struct Zone {
    int axis = 0;
    double lo = 0, hi = 0;
    bool inside(const double* p) const { return p[axis] >= lo && p[axis] < hi; }
    std::vector<std::uint32_t> points, deferred;  // local ids, in insertion order
    // Runs of points (see insert_in_strips): where each begins in `points`, and its start.
    std::vector<std::uint32_t> run_start, run_hint;
    std::vector<std::uint32_t> stack, cavity, free;
    std::vector<BoundaryEdge> boundary;
    std::uint32_t hint = 0;   // a live triangle to walk from (all its finite vertices inside)
    std::uint32_t stamp = 0;  // the last stamp used (each insertion takes two)
    std::uint32_t fresh = 0, fresh_end = 0;  // unused slots [fresh, fresh_end) (strips)
    std::size_t infinite_slot = 0;           // starting_at_'s entry for the infinite vertex
    bool relabeled = false;                  // see build()
    bool started = false;                    // hint is valid
  };
  template <bool kLocal>
  bool in_conflict(std::uint32_t t, const double* p, std::uint32_t ip) const;
  // kLocal: construction (zone: the strip to stay in, or null); false: a query.
  template <bool kLocal>
  std::uint32_t walk(const double* p, std::uint32_t t, const Zone* zone = nullptr) const;
  template <bool kZoned>
  std::uint32_t new_triangle(Zone& zone);
  void clear_triangles();
  void insert_all(const std::vector<std::uint32_t>* round_starts);
  template <bool kZoned>
  bool insert(Zone& zone, std::uint32_t q);
  void insert_sequentially(const std::uint32_t* first, const std::uint32_t* last);
  std::uint32_t zone_count(std::uint32_t round_size) const;
  void insert_in_strips(std::uint32_t first, std::uint32_t last, std::uint32_t nb_zones,
                        std::uint32_t skip_b, std::uint32_t skip_c);
  void canonicalize();
  std::uint32_t next_ccw(std::uint32_t t, std::uint32_t v) const;

  Options options_;
  const double* xy_ = nullptr;
  std::uint32_t nb_points_ = 0;
  std::uint32_t nb_unique_ = 0;
  std::uint32_t nb_finite_ = 0;
  StaticFilter filter_;

  std::vector<std::uint32_t> tri_vertices_;
  std::vector<std::uint32_t> tri_neighbors_;
  std::uint32_t nb_slots_ = 0;
  // Construction: one 32-byte record per slot, two per cache line:
  //   rec_[8t + k] vertex k (local id), rec_[8t + 3] the cavity search's stamp,
  //   rec_[8t + 4 + k] neighbour code 3t' + k', rec_[8t + 7] unused.
  // Slots [0, rec_slots_) are in use; free ones have rec_[8t] == kFreeVertex.
  std::vector<std::uint32_t, detail::UninitializedAllocator<std::uint32_t>> rec_;
  std::uint32_t rec_slots_ = 0;
  std::vector<std::uint32_t> vertex_triangle_;
  std::vector<std::uint32_t> duplicate_of_;
  Zone seq_;                 // the sequential insertion (its free list: the free slots)
  std::vector<Zone> zones_;  // the strips of a zoned round
  Stats stats_;
  bool zoning_off_ = false;  // a zoned round deferred most of its points
  // The new triangle per boundary start vertex (local id; the infinite vertex: one entry
  // per zone, after them).
  std::vector<std::uint32_t> starting_at_;
  // Arrays written in full before they are read: left uninitialized when they grow.
  template <class T>
  using Uninitialized = std::vector<T, detail::UninitializedAllocator<T>>;
  Uninitialized<double> coords_;
  std::vector<std::uint32_t> input_index_;
  std::vector<std::uint32_t> scratch_a_;
  Uninitialized<std::uint32_t> scratch_c_;
  Uninitialized<std::uint64_t> keys_, placed_;
  std::vector<std::uint8_t> shift_;
};

inline std::uint32_t Delaunay2::duplicate_of(std::uint32_t i) const {
  assert(i < nb_points_);
  return duplicate_of_[i];
}
inline const double* Delaunay2::point(std::uint32_t v) const {
  assert(v < nb_points_);
  return pt(v);
}
inline bool Delaunay2::is_infinite(std::uint32_t t) const {
  assert(t < nb_triangle_slots());
  return infinite_slot(t) >= 0;
}
inline std::uint32_t Delaunay2::tri_vertex(std::uint32_t t, int k) const {
  assert(t < nb_triangle_slots() && k >= 0 && k < 3);
  return tri_vertices_[3 * static_cast<std::size_t>(t) + static_cast<std::size_t>(k)];
}
inline std::uint32_t Delaunay2::tri_neighbor_code(std::uint32_t t, int k) const {
  assert(t < nb_triangle_slots() && k >= 0 && k < 3);
  return tri_neighbors_[3 * static_cast<std::size_t>(t) + static_cast<std::size_t>(k)];
}
inline std::uint32_t Delaunay2::tri_adjacent(std::uint32_t t, int k) const {
  return tri_neighbor_code(t, k) / 3;
}
inline int Delaunay2::tri_adjacent_edge(std::uint32_t t, int k) const {
  return static_cast<int>(tri_neighbor_code(t, k) % 3);
}
inline int Delaunay2::local_index(std::uint32_t t, std::uint32_t v) const {
  const std::uint32_t* w = &tri_vertices_[3 * static_cast<std::size_t>(t)];
  const int k = w[0] == v ? 0 : w[1] == v ? 1 : 2;
  assert(w[k] == v);
  return k;
}
inline std::uint32_t Delaunay2::vertex_triangle(std::uint32_t v) const {
  assert(v < nb_points_);
  return vertex_triangle_[v];
}

namespace detail {

// The box of one of Delaunay3's zones (see "Threads" below): the points whose coordinates
// in `frame` lie in [lo, hi), half-open on every axis; bounds may be infinite. Frame 0 is
// (x, y, z), frame 1 (x + y, y + z, z + x) (floating point: a zone need only be a function
// of the coordinates, so that zones are disjoint).
struct ZoneBox {
  int frame = 0;
  double lo[3], hi[3];
  static void frame_coordinates(int frame, const double* p, double* u) {
    if (frame == 0) {
      u[0] = p[0];
      u[1] = p[1];
      u[2] = p[2];
    } else {
      u[0] = p[0] + p[1];
      u[1] = p[1] + p[2];
      u[2] = p[2] + p[0];
    }
  }
  bool contains(const double* p) const {
    double u[3];
    frame_coordinates(frame, p, u);
    return u[0] >= lo[0] && u[0] < hi[0] && u[1] >= lo[1] && u[1] < hi[1] && u[2] >= lo[2] &&
           u[2] < hi[2];
  }
  // contains() for the zoned insertion, which tests about 18 vertices per point: a box of
  // frame 0 bounded on one axis only (a half of a round: two zones) compares that one
  // coordinate, the same answer for finite coordinates (the other bounds are infinite).
  // slab_axis is set from the box by prepare_inside(), after the box and before the tests.
  int slab_axis = -1;
  void prepare_inside() {
    slab_axis = -1;
    if (frame != 0) return;
    int bounded = 0, axis = 0;
    for (int a = 0; a < 3; ++a) {
      if (std::isinf(lo[a]) && std::isinf(hi[a])) continue;
      ++bounded;
      axis = a;
    }
    if (bounded <= 1) slab_axis = axis;
  }
  bool inside(const double* p) const {
    if (slab_axis >= 0) {
      const double x = p[slab_axis];
      return x >= lo[slab_axis] && x < hi[slab_axis];
    }
    return contains(p);
  }
};

}  // namespace detail

// ---------------------------------------------------------------------------------------
// Delaunay3: the 3D Delaunay triangulation by Bowyer–Watson insertion (Bowyer 1981,
// Watson 1981) in BRIO order (Amenta, Choi & Rote 2003), with exact predicates and
// symbolic perturbation, on one flat array; parallel insertion with TBB.
//
// Storage (32 bytes per tetrahedron slot, one cache line holds two):
//   tets_[8t + k]       vertex k of tet t (k < 4): a point index, or kInfinite
//   tets_[8t + 4 + f]   4t' + f': the tet t' across facet f (the facet opposite vertex f)
//                       and the local index f' of that facet in t'
// The two top bits of tets_[8t + 4] are the cavity search's marks ("in the cavity",
// "tested, outside"), clear outside an insertion; neighbour codes use the low 30 bits,
// which caps a triangulation at 2^28 tets. A recycled slot has tets_[8t] == kFreeVertex.
// The hull is closed by infinite tets: each holds one hull facet and kInfinite, always as
// its vertex 3 (so is_infinite(t) is tet_vertex(t, 3) == kInfinite).
//
// Local numbering. A finite tet (p0, p1, p2, p3) is positive: orient3d(p0, p1, p2, p3) > 0.
// Facet f is opposite vertex f, its vertices listed as kFacetVertex[f]:
//
//            p3                 facet 0: (p1, p2, p3)
//           /|\                 facet 1: (p0, p3, p2)
//          / | \                facet 2: (p3, p0, p1)
//         /  |  \               facet 3: (p2, p1, p0)
//       p0 --+-- p2
//          \ | /                With this order, orient3d(facet, q) < 0 for q on the side
//           \|/                 of the opposite vertex (the tet's inside) and > 0 beyond
//            p1                 the facet. The neighbour lists the shared facet reversed.
//
// Conflict (the Bowyer–Watson cavity of a new point q):
//   finite tet     insphere_sos(p0, p1, p2, p3, q) > 0 (indices = input indices).
//   infinite tet   with hull facet (a, b, c) = facet 3 as listed in it (inside of the hull
//                  on the positive side): orient3d(a, b, c, q) < 0, q strictly outside; or
//                  q on the facet's plane and inside the facet's circumcircle, decided with
//                  the same perturbation: insphere_sos(a, b, c, d, q) > 0 where d is the
//                  fourth vertex of the finite tet behind the facet. (Any sphere through
//                  a, b, c meets the plane in their circumcircle; the sign of the
//                  perturbed terms does not depend on d, whose own term is orient3d(a, b,
//                  c, q) = 0.) The infinite vertex is thus the limit of the lifting, as in
//                  CGAL and Geogram: coplanar points on the hull are triangulated within
//                  the hull facet, and no tet of zero volume is ever created.
// The perturbation makes the result the regular triangulation of the points with
// infinitesimal weights given by their indices: unique, whatever the insertion order.
//
// Duplicates. Points with exactly equal coordinates are detected while inserting; only the
// one with the smallest index becomes a vertex, duplicate_of(i) gives that index.
//
// Points. The construction works on a copy of the coordinates in insertion order (for
// memory locality), but the finished triangulation reads the caller's array: it must stay
// alive and unchanged while the triangulation is used (until the next build()).
//
// Threads. A BRIO round of at least 7/16 * points_per_zone points (Options; in a build with
// no round that large, 7/256 if a round reaches 7/64, else none) is split into zones, each
// inserted by its own TBB task along a Hilbert curve of its box: 2, 4 or 8 zones are the
// halves, quarters or octants of the round's box that its own Hilbert curve visits one
// after the other, taken in the round's order, when they hold about equal numbers of
// points (Stats::curve_zoned_passes); otherwise, and for more zones, a kd bisection by
// count along the longest axis, each zone sorted along the curve of its box. A task only
// touches tets having a facet whose finite vertices all lie in its zone, which no other
// task can touch (two facets of a tet share an edge), so the tasks need no locks: a point
// whose walk or cavity would reach a vertex outside the zone is deferred, leaving the
// triangulation untouched.
// The deferred points get a second pass with zones in a skew frame (boxes in (x + y, y + z, z + x),
// whose faces cross the first pass's), and what remains is inserted sequentially. Zones of many
// points that defer most of them (points on a sphere: their tets cross the ball) turn zoning off
// for the rest of the build. This is HXT's scheme (Marot, Pellerin & Remacle, "One
// machine, one minute, three billion tetrahedra", IJNME 2019) with boxes instead of Hilbert
// ranges as zones. Each zone owns a range of fresh slots and a share of the free ones. The
// number of zones, their boxes, their slots and their points depend on the input alone,
// never on the number of threads, and a zone's work depends on its own tets only: every
// array of the result (tet slots, neighbour codes, vertex_tet, duplicate_of) is identical
// to the last bit for any number of threads, without a renumbering pass. While the rounds
// before the first zoned one are inserted sequentially, the other threads compute the
// later rounds' first-pass zones ahead and fault in the pages of the tet array the zones
// will fill; those rounds use at most 8 slots per point (a point needing more is deferred
// to their end, Stats::limited_points), so that no slot is touched by both. (A renumbering
// into a sorted order was measured at 0.35 s for 1M points with a second 32-byte-per-tet
// array, or 1.3 s permuted in place.)
//
// Instruction sets. The library is built for portable x86-64 (SSE2). The insphere
// determinant of the conflict test also has a four-lane AVX2 version, which build() uses
// when the CPU has AVX2, except on AMD Zen 1, where it is slower (Options::insphere_simd,
// Stats::avx2). Both perform the same IEEE operations (no FMA, no contraction), so the
// result is the same to the last bit.
//
// Speed (bench/bench_delaunay3, bench/compare/compare_delaunay3; bench/RESULTS.md): 1M
// uniform points in about 2.0-2.1 s of CPU time on one thread, 0.51 of CGAL's
// Delaunay_triangulation_3 in the same run, about 1.15-1.2 s on two threads (a 2.6 GHz
// Xeon); 3.4 s, 0.48-0.49 of CGAL, and 1.9-2.5 s on two threads on a 2.0 GHz Zen 1 EPYC
// (the host's speed varies, its second core's most). 10^5 points on that EPYC: 0.32 s
// (0.47 of CGAL) on one thread, 0.20-0.23 s on two. 35 bytes per tet at the end, 39 at the
// peak.
//
// Slots after a build. Slots [0, nb_tet_slots()) all hold live tets, finite and infinite
// mixed (free slots left by the construction are filled with the last live records).
// vertex_tet(v) is the smallest-numbered finite tet incident to v.
//
struct Delaunay3Options {
  // Run check_topology() and check_delaunay() at the end of every build and throw
  // voroclip::Error if either finds a defect (slow: for debugging and the CLI's --check).
  bool check = false;
  // Parallel insertion: a BRIO round of n points is split into as many zones as the largest
  // power of two <= n / points_per_zone (at most 64), but two from 7/16 * points_per_zone on
  // (in a build with no round that large, from 7/256 * points_per_zone if a round reaches
  // 7/64 of it, else from 7/1024 * points_per_zone if a round reaches 7/256 of it, else
  // never; a smaller round is inserted sequentially), the points it defers
  // into zones of points_per_zone / 32 (two from 7/4 of that on). Fewer points per zone give
  // more parallelism and more points deferred at zone boundaries. The tet set never depends
  // on it; the slot numbering does (but never on the number of threads). The default makes
  // every zoned round of 1M uniform points two zones, the fastest on two cores (3-5 %
  // faster than 32768, which splits the last rounds into 8 and 4 zones: bench/RESULTS.md);
  // with more cores, a smaller value gives more zones to share.
  std::uint32_t points_per_zone = 131072;
  // Which code computes the conflict test's insphere determinant: the same operations
  // either way, so the same triangulation to the last bit; only the speed differs.
  enum class InsphereSimd : std::uint8_t {
    // AVX2 on x86-64 CPUs that have it (checked at run time) and where it pays: not on
    // AMD Zen 1 ("znver1"), which splits 256-bit operations into two 128-bit halves and
    // runs the lane permutations in several micro-ops (there SSE2 was 1-2.5 % faster on
    // one thread, and no different on two; bench/RESULTS.md).
    // Delaunay3::automatic_uses_avx2() tells the choice.
    automatic,
    sse2,  // always the SSE2 code
    avx2,  // AVX2 whenever the CPU has it
  };
  InsphereSimd insphere_simd = InsphereSimd::automatic;
  // The points come in a spatial order already, as hilbert_sort leaves them: each
  // BRIO round keeps their order instead of being sorted along its own curve, and the
  // zones along the curve take the halves, quarters and octants of the points' bounding
  // box (the box of that sort). For a caller that sorts its points anyway
  // (ClippedVoronoi3::compute numbers its sites so). The tet set never depends on it; the
  // slot numbering does. Any order is correct, only slower when it is not spatial.
  bool presorted = false;
};

class Delaunay3 {
 public:
  using Options = Delaunay3Options;

  static constexpr std::uint32_t kInfinite = 0xffffffffu;
  static constexpr std::uint32_t kNoTet = 0xffffffffu;

  // kFacetVertex[f][i]: local index of the i-th vertex of facet f (see the diagram above).
  static constexpr int kFacetVertex[4][3] = {{1, 2, 3}, {0, 3, 2}, {3, 0, 1}, {2, 1, 0}};

  Delaunay3() = default;
  explicit Delaunay3(const Options& options) : options_(options) {}
  // Triangulates n points given as packed x y z. The array is referenced, not copied: it
  // must outlive the triangulation (or the next build()).
  Delaunay3(const double* xyz, std::uint32_t n, const Options& options = {}) : options_(options) {
    build(xyz, n);
  }

  // (Re)builds on new points, reusing the tet array (CVT rebuilds each iteration).
  // Throws voroclip::Error for non-finite coordinates or fewer than 4 affinely
  // independent points.
  void build(const double* xyz, std::uint32_t n);
  // The options of the next build() (the current triangulation is left as it is).
  const Options& options() const { return options_; }
  void set_options(const Options& options) { options_ = options; }

  std::uint32_t nb_points() const { return nb_points_; }
  std::uint32_t nb_unique_points() const { return nb_unique_; }
  // The smallest input index with the same coordinates as point i (i itself if unique).
  std::uint32_t duplicate_of(std::uint32_t i) const {
    assert(i < nb_points_);
    return duplicate_of_[i];
  }
  // Point v (x y z): after a build, input point v (during construction, internal ids).
  const double* point(std::uint32_t v) const { return pts_ + 3 * static_cast<std::size_t>(v); }

  // Slots: after a build every slot below nb_tet_slots() holds a live tet, finite or
  // infinite (skip these with is_infinite(t)); is_free(t) is true only during a build.
  std::uint32_t nb_tet_slots() const { return nb_slots_; }
  std::uint32_t nb_finite_tets() const { return nb_finite_tets_; }
  bool is_free(std::uint32_t t) const { return word(t, 0) == kFreeVertex; }
  bool is_infinite(std::uint32_t t) const { return word(t, 3) == kInfinite; }
  std::uint32_t tet_vertex(std::uint32_t t, int k) const {
    assert(k >= 0 && k < 4);
    return word(t, static_cast<std::uint32_t>(k));
  }
  std::uint32_t tet_adjacent(std::uint32_t t, int f) const { return neighbor_code(t, f) / 4; }
  int tet_adjacent_facet(std::uint32_t t, int f) const {
    return static_cast<int>(neighbor_code(t, f) & 3u);
  }
  // The raw encoding 4t' + f' (see above).
  std::uint32_t neighbor_code(std::uint32_t t, int f) const {
    assert(f >= 0 && f < 4);
    return word(t, 4 + static_cast<std::uint32_t>(f)) & kCodeMask;
  }
  // A hint that tet t's record will be read soon (one cache line; no effect on results).
  void prefetch_tet(std::uint32_t t) const {
    assert(t < nb_slots_);
#if defined(__GNUC__)
    __builtin_prefetch(tets_.data() + 8 * static_cast<std::size_t>(t));
#endif
  }
  // The smallest-numbered finite tet incident to vertex v (kNoTet for duplicates).
  std::uint32_t vertex_tet(std::uint32_t v) const {
    assert(v < nb_points_);
    return vertex_tet_[v];
  }

  // The finite tets incident to vertex v, and its Delaunay neighbours (the sites of the
  // adjacent Voronoi cells), appended to `out` (cleared first), sorted.
  void vertex_tets(std::uint32_t v, std::vector<std::uint32_t>& out) const;
  void vertex_neighbors(std::uint32_t v, std::vector<std::uint32_t>& out) const;
  // Hull vertices (finite vertices of infinite tets), sorted.
  std::vector<std::uint32_t> hull_vertices() const;
  // A tet containing p: a finite tet whose closed interior holds p, or, for p outside the
  // convex hull, an infinite tet whose hull facet p lies strictly beyond. Exact (plain
  // orient3d); walks from `hint` when it is a valid tet. Throws for a non-finite p.
  std::uint32_t locate(const double* p, std::uint32_t hint = kNoTet) const;
  // The vertex nearest to p, decided exactly (compare_distance3d); among equidistant
  // nearest vertices the smallest index. Greedy descent on the Delaunay graph from a
  // vertex of locate(p, hint).
  std::uint32_t nearest_vertex(const double* p, std::uint32_t hint = kNoTet) const;
  // Circumcenter of finite tet t, in floating point (not exact; for output and clipping).
  void circumcenter(std::uint32_t t, double* out) const;

  // Bytes held by the triangulation's arrays (capacities), for memory reports.
  std::size_t memory_bytes() const;
  // The largest memory_bytes() reached during the last build, the construction's copies
  // and scratch arrays included (not the spatial sort's temporaries, freed before the tet
  // array is first allocated; a rebuild keeps the tet array while they exist).
  std::size_t peak_memory_bytes() const { return peak_bytes_; }
  // How the last build inserted its points (all counts of insertion attempts).
  struct Stats {
    std::uint32_t zoned_passes = 0;        // parallel passes (each over several zones)
    std::uint32_t curve_zoned_passes = 0;  // of those, zones along the round's Hilbert curve
    std::uint32_t zoned_points = 0;        // points attempted in a zone
    std::uint32_t deferred_points = 0;     // of those, deferred (the cavity left the zone)
    std::uint32_t sequential_points = 0;   // points inserted sequentially
    std::uint32_t limited_points = 0;      // of those, deferred by the slot limit (Threads)
    bool avx2 = false;                     // AVX2 insphere determinant (Options::insphere_simd)
  };
  const Stats& stats() const { return stats_; }
  // Whether Options::InsphereSimd::automatic uses the AVX2 determinant on this CPU.
  static bool automatic_uses_avx2();

  // Exact checks, used by the tests on every result. Return an empty string when valid,
  // else a description of the first defect found. check_topology also verifies the
  // layout after a build (no free slot, kInfinite as vertex 3, vertex_tet minimal).
  std::string check_topology() const;
  std::string check_delaunay() const;

 private:
  static constexpr std::uint32_t kFreeVertex = 0xfffffffeu;
  static constexpr std::uint32_t kCodeMask = 0x3fffffffu;
  static constexpr std::uint32_t kMaxTets = 1u << 28;

  // Per-task insertion state: a box of space (the zone; unbounded when inserting
  // sequentially), scratch reused between insertions, the slots it may fill.
  struct BoundaryFacet {
    std::uint32_t code;  // 4t + f of the tet outside the cavity and its facet on the boundary
    std::uint32_t v[3];  // the facet as listed in the cavity tet behind it (kFacetVertex)
  };
  // A zone: its box (detail::ZoneBox) and the state of the task inserting in it.
  struct Zone : detail::ZoneBox {
    bool along_curve = false;  // a half, quarter or octant of the round's box (split_along_curve)
    std::uint32_t hint = kNoTet;
    std::vector<std::uint32_t> cavity;
    std::vector<BoundaryFacet> boundary;
    std::vector<std::uint32_t> free;          // recycled slots this zone may reuse
    std::uint32_t fresh = 0, fresh_end = 0;   // never used slots [fresh, fresh_end)
    std::vector<std::uint32_t> edge_map;      // 32 x 32 small-cavity gluing table
    std::vector<std::uint32_t> local_vertex;  // local id -> vertex, for edge_map
    std::vector<std::uint64_t> edges;         // large-cavity gluing: directed edges,
    std::vector<std::uint32_t> edge_codes;    // their order by key,
    std::vector<std::uint64_t> sorted_edges;  // and the keys sorted
    std::vector<std::uint32_t> points;        // points to insert in this zone
    std::vector<std::uint32_t> deferred;      // points whose cavity left the box
  };
  enum class Inserted { yes, duplicate, deferred };

  std::uint32_t word(std::uint32_t t, std::uint32_t k) const {
    assert(t < nb_slots_);
    return tets_[8 * static_cast<std::size_t>(t) + k];
  }
  // The index symbolic perturbation uses for vertex v: always the input index.
  std::uint32_t sos_id(std::uint32_t v) const { return sos_ids_ ? sos_ids_[v] : v; }
  template <bool kAvx2>
  bool in_conflict(std::uint32_t t, std::uint32_t q) const;
  template <bool kAvx2>
  bool in_conflict(const std::uint32_t* v, std::uint32_t t, std::uint32_t q, const double* pts,
                   const double* pq) const;
  [[gnu::noinline]] bool in_conflict_rest(std::uint32_t t, std::uint32_t q) const;
  template <bool kZoned>
  bool walk(const Zone& zone, const double* p, std::uint32_t& t) const;
  std::uint32_t walk_query(const double* p, std::uint32_t t) const;
  template <bool kZoned, bool kAvx2>
  Inserted insert(Zone& zone, std::uint32_t q);
  template <bool kZoned>
  bool take_slots(Zone& zone, std::size_t count);
  void glue_large_cavity(Zone& zone, std::uint32_t q);
  void unmark_cavity(const Zone& zone);
  template <bool kZoned>
  void insert_points(Zone& zone, const std::uint32_t* first, const std::uint32_t* last);
  void insert_sequentially(const std::uint32_t* first, const std::uint32_t* last);
  void split_into_zones(const std::vector<std::uint32_t>& points, std::size_t nb_zones, int frame,
                        Zone* zones) const;
  bool split_along_curve(const std::vector<std::uint32_t>& points, std::size_t nb_zones,
                         Zone* zones) const;
  void insert_in_parallel(std::vector<std::uint32_t>& points, std::size_t nb_zones,
                          std::vector<Zone>* plan);
  bool start_zone(Zone& zone);
  void grow_slots(std::size_t slots);
  std::uint32_t initial_tetrahedron();
  void triangulate(const std::vector<std::uint32_t>& round_starts);
  void finish();
  void note_memory();
  void vertex_star(std::uint32_t v, std::vector<std::uint32_t>& star) const;
  std::uint32_t any_tet() const;

  Options options_;
  const double* xyz_ = nullptr;
  // During construction vertices are numbered in insertion order (rank) and their
  // coordinates copied in that order (sorted_xyz_), so that the points of neighbouring
  // tets are neighbours in memory; input_id_ maps ranks back. build() ends by renumbering
  // to input indices; from then on pts_ = xyz_ and sos_ids_ = nullptr.
  const double* pts_ = nullptr;
  const std::uint32_t* sos_ids_ = nullptr;
  std::vector<double> sorted_xyz_;
  std::vector<std::uint32_t> input_id_;
  std::uint32_t nb_points_ = 0;
  std::uint32_t nb_unique_ = 0;
  std::uint32_t nb_finite_tets_ = 0;
  std::uint32_t nb_slots_ = 0;
  StaticFilter filter_;
  double box_lo_[3] = {0, 0, 0}, box_hi_[3] = {0, 0, 0};  // the points' bounding box
  std::size_t peak_bytes_ = 0;
  Stats stats_;

  // Grows without initializing (every slot is written before it is read): the pages are
  // touched, and faulted in, by the tasks that fill them.
  std::vector<std::uint32_t, detail::UninitializedAllocator<std::uint32_t>> tets_;
  std::vector<std::uint32_t> vertex_tet_;
  std::vector<std::uint32_t> duplicate_of_;
  std::vector<std::uint32_t> duplicate_internal_;  // during construction, by rank
  std::vector<std::uint8_t> local_id_;             // per rank: gluing ids, 0 between insertions
  std::vector<Zone> zones_;                        // zones_[0] inserts sequentially
  std::vector<std::vector<Zone>> zone_plans_;      // per round: its first pass's zones, ahead
  std::uint32_t initial_[4] = {0, 0, 0, 0};        // ranks of the first tet's vertices
  bool zoning_off_ = false;  // a zoned pass deferred most of its points: no more zones
  // Sequential insertion uses no slot at or above it (a point that would is deferred).
  std::size_t slot_limit_ = kMaxTets;
  bool avx2_ = false;  // this build uses insphere_det_avx2
};

}  // namespace voroclip
