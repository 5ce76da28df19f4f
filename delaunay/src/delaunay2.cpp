// Delaunay2: Bowyer–Watson insertion (Bowyer 1981; Watson 1981) in BRIO order (Amenta,
// Choi & Rote 2003), located by a remembering visibility walk (Devillers, Pion & Teillaud
// 2002) from the last created triangle. Conventions, storage and the conflict test are
// documented once in voroclip/delaunay.h.
//
// One insertion: walk to a triangle in conflict with the new point p (the finite triangle
// whose closure contains p, or an infinite triangle whose hull edge p sees strictly),
// grow the cavity by a search over adjacent triangles in conflict, then replace it by the
// star of p over the cavity boundary. The perturbed triangulation before the insertion is
// the regular triangulation of the points inserted so far, so the cavity is a topological
// disk star-shaped from p; its boundary is one cycle of edges, each starting at a
// distinct vertex, which is how the new triangles find their neighbours (starting_at_).
// The walk terminates: in a regular triangulation the "in front of" relation seen from
// any point is acyclic (Edelsbrunner 1990), so no triangle is visited twice; a step limit
// with a linear scan guards the invariant anyway.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numeric>
#include <sstream>
#include <string>
#include <type_traits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "nearest.h"
#include "spatial_sort.h"
#include "voroclip/core.h"
#include "voroclip/delaunay.h"

namespace voroclip {

namespace {

constexpr int kNext[3] = {1, 2, 0};
constexpr int kPrev[3] = {2, 0, 1};

bool same_point(const double* a, const double* b) { return a[0] == b[0] && a[1] == b[1]; }

// A hint that the cache line at p will be read soon (no effect on results).
inline void prefetch(const void* p) {
#if defined(__GNUC__)
  __builtin_prefetch(p);
#else
  static_cast<void>(p);
#endif
}

// p strictly between a and b, given that the three are collinear and a != b.
bool strictly_between(const double* a, const double* b, const double* p) {
  const int axis = a[0] != b[0] ? 0 : 1;
  const double lo = std::min(a[axis], b[axis]), hi = std::max(a[axis], b[axis]);
  return p[axis] > lo && p[axis] < hi;
}

}  // namespace

Delaunay2::Delaunay2(const double* xy, std::uint32_t n, const Options& options)
    : options_(options) {
  build(xy, n);
}

// ---------------------------------------------------------------------------------------
// Construction

void Delaunay2::build(const double* xy, std::uint32_t n) {
  if (n > kMaxPoints) {
    throw Error("Delaunay2: " + std::to_string(n) + " points exceed the limit of " +
                std::to_string(kMaxPoints));
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    const double* p = xy + 2 * static_cast<std::size_t>(i);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1])) {
      std::ostringstream message;
      message << "Delaunay2: point " << i << " has a non-finite coordinate (" << p[0] << ", "
              << p[1] << ")";
      throw Error(message.str());
    }
  }
  xy_ = xy;
  nb_points_ = n;
  nb_unique_ = 0;
  nb_finite_ = 0;
  clear_triangles();
  vertex_triangle_.clear();
  if (n < 3) {
    throw Error("Delaunay2: at least 3 affinely independent points are needed, got " +
                std::to_string(n) + " point" + (n == 1 ? "" : "s"));
  }
  filter_ = StaticFilter::bounding(xy, n, 2);
  detail::reserve_advised(duplicate_of_, n);
  duplicate_of_.resize(n);
  std::iota(duplicate_of_.begin(), duplicate_of_.end(), 0u);
  input_index_ = detail::brio_order(xy, n, 2);
  relabeled_ = false;
  insert_all();
  // Union-find with the smallest index as root: duplicate_of_[i] <= i, so one ascending
  // pass compresses every path.
  for (std::uint32_t i = 0; i < n; ++i) duplicate_of_[i] = duplicate_of_[duplicate_of_[i]];
  if (relabeled_) {
    // A vertex was inserted before a smaller-index twin: its perturbation used the wrong
    // index. Rebuild from the distinct points (only for some duplicated input).
    input_index_.erase(std::remove_if(input_index_.begin(), input_index_.end(),
                                      [this](std::uint32_t i) { return duplicate_of_[i] != i; }),
                       input_index_.end());
    clear_triangles();
    relabeled_ = false;
    insert_all();
  }
  for (std::uint32_t i = 0; i < n; ++i) nb_unique_ += duplicate_of_[i] == i ? 1u : 0u;
  canonicalize();
  if (!options_.keep_buffers) {
    for (auto* buffer : {&scratch_a_, &starting_at_, &stack_, &cavity_, &free_}) {
      std::vector<std::uint32_t>().swap(*buffer);
    }
    decltype(rec_)().swap(rec_);
    decltype(scratch_c_)().swap(scratch_c_);
    decltype(keys_)().swap(keys_);
    decltype(placed_)().swap(placed_);
    decltype(coords_)().swap(coords_);
    std::vector<BoundaryEdge>().swap(boundary_);
  }
  if (options_.check) {
    std::string defect = check_topology();
    if (defect.empty()) defect = check_delaunay();
    if (!defect.empty()) throw Error("Delaunay2: internal check failed: " + defect);
  }
}

void Delaunay2::clear_triangles() {
  rec_slots_ = 0;
  free_.clear();
}

// A slot for a new triangle: a recycled one, else the next of rec_ (whose mark is reset:
// rec_ keeps the stamps of the previous build). Inlined: six calls per insertion.
[[gnu::always_inline]] inline std::uint32_t Delaunay2::new_triangle() {
  if (!free_.empty()) {
    const std::uint32_t t = free_.back();
    free_.pop_back();
    return t;
  }
  const std::uint32_t t = rec_slots_++;
  if (8 * static_cast<std::size_t>(rec_slots_) > rec_.size()) {
    rec_.resize(rec_.size() + rec_.size() / 8 + 64);
  }
  rec_[8 * static_cast<std::size_t>(t) + 3] = 0;
  return t;
}

// Inserts the points input_index_[0], input_index_[1], ... (local ids 0, 1, ...).
void Delaunay2::insert_all() {
  const auto m = static_cast<std::uint32_t>(input_index_.size());
  detail::reserve_advised(coords_, 2 * static_cast<std::size_t>(m));
  coords_.resize(2 * static_cast<std::size_t>(m));
  for (std::uint32_t q = 0; q < m; ++q) {
    coords_[2 * static_cast<std::size_t>(q)] = pt(input_index_[q])[0];
    coords_[2 * static_cast<std::size_t>(q) + 1] = pt(input_index_[q])[1];
  }
  starting_at_.resize(static_cast<std::size_t>(m) + 1);
  // About 2m triangles in all (finite and infinite). resize() rather than reserve(): a
  // rebuild on as many points touches nothing here.
  const std::size_t expected = 8 * (2 * static_cast<std::size_t>(m) + 16);
  if (rec_.size() < expected) {
    if (rec_.capacity() < expected) decltype(rec_)().swap(rec_);
    rec_.reserve(expected);
    rec_.resize(expected);
  }

  // The first triangle: a = 0, b the first point different from a, c the first point not
  // collinear with a and b. The points skipped meanwhile are inserted later, in order.
  const double* a = local_pt(0);
  std::uint32_t b = 1;
  while (b < m && same_point(local_pt(b), a)) ++b;
  if (b == m) {
    throw Error("Delaunay2: all " + std::to_string(nb_points_) +
                " points coincide; at least 3 affinely independent points are needed");
  }
  std::uint32_t c = b + 1;
  while (c < m && orient2d(a, local_pt(b), local_pt(c), filter_) == Sign::zero) ++c;
  if (c == m) {
    throw Error("Delaunay2: all " + std::to_string(nb_points_) +
                " points are collinear; at least 3 affinely independent points are needed");
  }
  std::uint32_t v[3] = {0, b, c};
  if (orient2d(a, local_pt(b), local_pt(c), filter_) == Sign::negative) std::swap(v[1], v[2]);
  // The finite triangle and, across each of its edges k, the infinite triangle
  // (v_{k+2}, v_{k+1}, inf); adjacency by matching reversed edges.
  std::uint32_t t[4];
  for (auto& s : t) s = new_triangle();
  for (int i = 0; i < 3; ++i) rec_[8 * t[0] + static_cast<std::uint32_t>(i)] = v[i];
  for (int k = 0; k < 3; ++k) {
    std::uint32_t* w = &rec_[8 * t[k + 1]];
    w[0] = v[kPrev[k]];
    w[1] = v[kNext[k]];
    w[2] = kInfinite;
  }
  for (int i = 0; i < 4; ++i) {
    for (int ki = 0; ki < 3; ++ki) {
      const std::uint32_t* vi = &rec_[8 * t[i]];
      const std::uint32_t p = vi[kNext[ki]], q = vi[kPrev[ki]];
      for (int j = 0; j < 4; ++j) {
        const std::uint32_t* vj = &rec_[8 * t[j]];
        for (int kj = 0; kj < 3; ++kj) {
          if (j != i && vj[kNext[kj]] == q && vj[kPrev[kj]] == p) {
            rec_[8 * t[i] + 4 + static_cast<std::uint32_t>(ki)] =
                3 * t[j] + static_cast<std::uint32_t>(kj);
          }
        }
      }
    }
  }
  hint_ = t[0];
  stamp_ = 0;
  for (std::uint32_t q = 1; q < m; ++q) {
    if (q != b && q != c) insert(q);
  }
}

// kLocal: t holds local ids (construction), else input indices (checks). ip is the input
// index of p, for the perturbation. Inlined: the cavity search calls it for every
// neighbour (7% of the build's instructions were the call and its set-up).
template <bool kLocal>
[[gnu::always_inline]] inline bool Delaunay2::in_conflict(std::uint32_t t, const double* p,
                                                          std::uint32_t ip) const {
  const std::uint32_t* v = vertices_of<kLocal>(t);
  const auto point_of = [this](std::uint32_t w) { return kLocal ? local_pt(w) : pt(w); };
  const int kinf = v[0] == kInfinite ? 0 : v[1] == kInfinite ? 1 : v[2] == kInfinite ? 2 : -1;
  if (kinf < 0) {
    const double* a = point_of(v[0]);
    const double* b = point_of(v[1]);
    const double* c = point_of(v[2]);
    Sign s = incircle(a, b, c, p, filter_);
    if (s == Sign::zero) {
      if constexpr (kLocal) {
        s = incircle_sos(a, b, c, p, input_index_[v[0]], input_index_[v[1]], input_index_[v[2]],
                         ip);
      } else {
        s = incircle_sos(a, b, c, p, v[0], v[1], v[2], ip);
      }
    }
    return s == Sign::positive;
  }
  const double* a = point_of(v[kNext[kinf]]);
  const double* b = point_of(v[kPrev[kinf]]);
  const Sign o = orient2d(a, b, p, filter_);
  if (o != Sign::zero) return o == Sign::positive;
  return strictly_between(a, b, p);
}

// kLocal: during construction (local ids, p inside the filter's box); otherwise a query
// on the finished triangulation, with plain predicates since p may lie outside the box.
template <bool kLocal>
std::uint32_t Delaunay2::walk(const double* p, std::uint32_t t) const {
  const auto orient = [this, p](std::uint32_t a, std::uint32_t b) {
    if constexpr (kLocal) {
      return orient2d(local_pt(a), local_pt(b), p, filter_);
    } else {
      return orient2d(pt(a), pt(b), p);
    }
  };
  const std::uint32_t slots = kLocal ? rec_slots_ : nb_slots_;
  const std::size_t limit = static_cast<std::size_t>(slots) + 8;
  std::uint32_t previous = kNone;
  std::uint32_t state = 0x9e3779b9u;  // xorshift32: a fixed sequence of edge choices
  for (std::size_t step = 0; step < limit; ++step) {
    const std::uint32_t* v = vertices_of<kLocal>(t);
    const int kinf = v[0] == kInfinite ? 0 : v[1] == kInfinite ? 1 : v[2] == kInfinite ? 2 : -1;
    if (kinf >= 0) {
      if (orient(v[kNext[kinf]], v[kPrev[kinf]]) == Sign::positive) return t;
      previous = t;
      t = neighbor_of<kLocal>(t, kinf) / 3;
      continue;
    }
    if constexpr (kLocal) {
      // The next triangle is a neighbour: load them while the predicates run.
      for (int k = 0; k < 3; ++k) prefetch(vertices_of<true>(neighbor_of<true>(t, k) / 3));
    }
    state ^= state << 13;
    state ^= state >> 17;
    state ^= state << 5;
    const auto k0 = static_cast<int>(state % 3);
    bool moved = false;
    for (int j = 0; j < 3 && !moved; ++j) {
      const int k = (k0 + j) % 3;
      const std::uint32_t next = neighbor_of<kLocal>(t, k) / 3;
      if (next == previous) continue;
      if (orient(v[kNext[k]], v[kPrev[k]]) == Sign::negative) {
        previous = t;
        t = next;
        moved = true;
      }
    }
    if (!moved) return t;
  }
  // Unreachable in a valid triangulation (see the file comment): scan every triangle.
  for (std::uint32_t s = 0; s < slots; ++s) {
    const std::uint32_t* v = vertices_of<kLocal>(s);
    if (v[0] == kFreeVertex) continue;
    const int kinf = v[0] == kInfinite ? 0 : v[1] == kInfinite ? 1 : v[2] == kInfinite ? 2 : -1;
    if (kinf >= 0) {
      if (orient(v[kNext[kinf]], v[kPrev[kinf]]) == Sign::positive) return s;
    } else if (orient(v[1], v[2]) != Sign::negative && orient(v[2], v[0]) != Sign::negative &&
               orient(v[0], v[1]) != Sign::negative) {
      return s;
    }
  }
  throw Error("Delaunay2: point location failed (corrupted triangulation)");
}

void Delaunay2::insert(std::uint32_t q) {
  const double* p = local_pt(q);
  const std::uint32_t ip = input_index_[q];
  const std::uint32_t start = walk<true>(p, hint_);
  const std::uint32_t* sv = vertices_of<true>(start);
  if (sv[0] != kInfinite && sv[1] != kInfinite && sv[2] != kInfinite) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t w = sv[k];
      if (!same_point(local_pt(w), p)) continue;
      std::uint32_t root = input_index_[w];
      while (duplicate_of_[root] != root) root = duplicate_of_[root];
      if (ip < root) {
        duplicate_of_[root] = ip;
        relabeled_ = true;
      } else {
        duplicate_of_[ip] = root;
      }
      return;
    }
  }
  // A triangle's neighbours are read when it is taken from the stack: their records are
  // prefetched as it enters (they are scattered over the array).
  const auto prefetch_neighbors = [this](std::uint32_t t) {
    for (int k = 0; k < 3; ++k) prefetch(vertices_of<true>(neighbor_of<true>(t, k) / 3));
  };
  stamp_ += 2;  // stamp_: in the cavity; stamp_ + 1: tested, not in conflict
  const std::uint32_t rejected = stamp_ + 1;
  stack_.clear();
  cavity_.clear();
  boundary_.clear();
  rec_[8 * static_cast<std::size_t>(start) + 3] = stamp_;
  prefetch_neighbors(start);
  stack_.push_back(start);
  while (!stack_.empty()) {
    const std::uint32_t c = stack_.back();
    stack_.pop_back();
    cavity_.push_back(c);
    const std::uint32_t* v = vertices_of<true>(c);
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t code = v[4 + k];
      const std::uint32_t nt = code / 3;
      std::uint32_t& mark = rec_[8 * static_cast<std::size_t>(nt) + 3];
      if (mark == stamp_) continue;
      if (mark != rejected && in_conflict<true>(nt, p, ip)) {
        mark = stamp_;
        prefetch_neighbors(nt);
        stack_.push_back(nt);
        continue;
      }
      mark = rejected;
      boundary_.push_back({v[kNext[k]], v[kPrev[k]], code});
    }
  }
  for (const std::uint32_t c : cavity_) free_.push_back(c);
  const auto infinite_slot_index = static_cast<std::size_t>(input_index_.size());
  const auto slot_of = [infinite_slot_index](std::uint32_t v) {
    return v == kInfinite ? infinite_slot_index : static_cast<std::size_t>(v);
  };
  // The star of p: (p, u, w) for each boundary edge (u, w), its edge 0 glued to the
  // triangle outside; edge 1 (w, p) is edge 2 of the new triangle starting at w.
  stack_.clear();
  for (const BoundaryEdge& e : boundary_) {
    const std::uint32_t t = new_triangle();
    std::uint32_t* v = &rec_[8 * static_cast<std::size_t>(t)];
    v[0] = q;
    v[1] = e.u;
    v[2] = e.w;
    v[4] = e.outside;
    rec_[8 * static_cast<std::size_t>(e.outside / 3) + 4 + e.outside % 3] = 3 * t;
    starting_at_[slot_of(e.u)] = t;
    stack_.push_back(t);
  }
  for (const std::uint32_t t : stack_) {
    std::uint32_t* v = &rec_[8 * static_cast<std::size_t>(t)];
    const std::uint32_t next = starting_at_[slot_of(v[2])];
    v[5] = 3 * next + 2;
    rec_[8 * static_cast<std::size_t>(next) + 6] = 3 * t + 1;
  }
  hint_ = stack_.back();
}

// Renumbers the triangles in the canonical order described in the header, drops free
// slots, converts local ids to input indices and recomputes vertex_triangle_.
// Linear time but for the sort of each bucket (a counting sort by largest rank leaves in
// bucket r the few triangles whose last inserted vertex is r). The key is the largest rank
// because a triangle is created by the insertion of that vertex: the new order follows the
// insertion order, along the Hilbert curve, which keeps the renumbering cache-friendly.
// The parallel loops work on disjoint ranges and write per-item results only, so the
// outcome does not depend on the number of threads.
void Delaunay2::canonicalize() {
  const std::uint32_t slots = rec_slots_;
  const std::size_t m = input_index_.size();
  const auto kinf_of = [](const std::uint32_t* v) {
    return v[0] == kInfinite ? 0 : v[1] == kInfinite ? 1 : v[2] == kInfinite ? 2 : -1;
  };
  // Per slot: keys[t] = (largest rank r0 << 32) | rank of the vertex after it
  // counter-clockwise, for a finite triangle (below kHullKey: ranks are below 2^31);
  // kHullKey | a, for an infinite triangle (a, b, inf), a its first vertex's input index;
  // kNoKey for a free slot. packed[t] = rotation: new vertex j is old vertex
  // (j + rotation) mod 3, so that a finite triangle starts at its smallest input index and
  // an infinite one ends with kInfinite. The new index is or-ed in as (index << 2) below.
  constexpr std::uint64_t kNoKey = ~std::uint64_t{0};
  constexpr std::uint64_t kHullKey = std::uint64_t{1} << 63;
  static_assert(kMaxPoints <= (1u << 31), "ranks must leave the top bit of a key clear");
  auto& keys = keys_;
  detail::reserve_advised(keys, slots);
  keys.resize(slots);
  auto& packed = scratch_c_;
  detail::reserve_advised(packed, slots);
  packed.resize(slots);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, slots, 16384),
                    [&](const tbb::blocked_range<std::uint32_t>& range) {
                      for (std::uint32_t t = range.begin(); t != range.end(); ++t) {
                        const std::uint32_t* v = vertices_of<true>(t);
                        keys[t] = kNoKey;
                        if (v[0] == kFreeVertex) continue;
                        const int kinf = kinf_of(v);
                        if (kinf >= 0) {
                          packed[t] = static_cast<std::uint32_t>(kNext[kinf]);
                          keys[t] = kHullKey | input_index_[v[kNext[kinf]]];
                          continue;
                        }
                        const std::uint32_t i0 = input_index_[v[0]], i1 = input_index_[v[1]],
                                            i2 = input_index_[v[2]];
                        packed[t] = i0 < i1 ? (i0 < i2 ? 0u : 2u) : (i1 < i2 ? 1u : 2u);
                        const int r = v[0] > v[1] ? (v[0] > v[2] ? 0 : 2) : (v[1] > v[2] ? 1 : 2);
                        keys[t] = (static_cast<std::uint64_t>(v[r]) << 32) | v[kNext[r]];
                      }
                    });
  // Counting sort of the finite triangles by r0; bucket_end[r] ends bucket r.
  std::vector<std::uint32_t>& bucket_end = scratch_a_;
  bucket_end.assign(m + 1, 0);
  // The same pass finds the infinite triangle whose first vertex has the smallest index.
  std::uint32_t first_hull = kNone;
  std::uint64_t first_hull_key = kNoKey;
  for (std::uint32_t t = 0; t < slots; ++t) {
    const std::uint64_t key = keys[t];
    if (key < kHullKey) {
      ++bucket_end[(key >> 32) + 1];
    } else if (key < first_hull_key) {
      first_hull_key = key;
      first_hull = t;
    }
  }
  for (std::size_t r = 1; r <= m; ++r) bucket_end[r] += bucket_end[r - 1];
  const std::uint32_t nb_finite = bucket_end[m];
  // placed_[i] = (r1 << 32) | slot, by bucket (bucket_end[r] moves from the start to the
  // end of bucket r).
  detail::reserve_advised(placed_, nb_finite);
  placed_.resize(nb_finite);
  for (std::uint32_t t = 0; t < slots; ++t) {
    const std::uint64_t key = keys[t];
    if (key < kHullKey) placed_[bucket_end[key >> 32]++] = (key << 32) | t;
  }
  // Each bucket (about two triangles) by r1: insertion sort.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, m, 16384),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t r = range.begin(); r != range.end(); ++r) {
                        const std::uint32_t begin = r == 0 ? 0 : bucket_end[r - 1];
                        for (std::uint32_t i = begin + 1; i < bucket_end[r]; ++i) {
                          const std::uint64_t x = placed_[i];
                          std::uint32_t j = i;
                          for (; j > begin && placed_[j - 1] > x; --j) placed_[j] = placed_[j - 1];
                          placed_[j] = x;
                        }
                      }
                    });
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, nb_finite, 16384),
                    [&](const tbb::blocked_range<std::uint32_t>& range) {
                      for (std::uint32_t i = range.begin(); i != range.end(); ++i) {
                        packed[placed_[i] & 0xffffffffu] |= i << 2;
                      }
                    });
  // Infinite triangles (a, b, inf) follow in hull order, the next one starting at b, from
  // the one whose a has the smallest input index (so hull_vertices() starts there).
  std::uint32_t total = nb_finite;
  std::vector<std::uint32_t>& hull = stack_;
  hull.clear();
  {
    std::uint32_t t = first_hull;
    do {
      hull.push_back(t);
      packed[t] |= total++ << 2;
      t = neighbor_of<true>(t, static_cast<int>(packed[t] & 3u)) / 3;  // across (b, inf)
    } while (t != first_hull);
  }
  // The new arrays, in new order (sequential writes): each slot rotated, with input
  // indices and new neighbour codes.
  detail::reserve_advised(tri_vertices_, 3 * static_cast<std::size_t>(total));
  detail::reserve_advised(tri_neighbors_, 3 * static_cast<std::size_t>(total));
  tri_vertices_.resize(3 * static_cast<std::size_t>(total));
  tri_neighbors_.resize(3 * static_cast<std::size_t>(total));
  // kFinite: t has no infinite vertex. (x mod 3 for x < 6 by table: no division.)
  constexpr std::uint32_t kMod3[6] = {0, 1, 2, 0, 1, 2};
  const auto write = [&](std::uint32_t i, std::uint32_t t, auto finite) {
    constexpr bool kFinite = decltype(finite)::value;
    const std::uint32_t* v = vertices_of<true>(t);
    const std::uint32_t s = packed[t] & 3u;
    std::uint32_t* out_vertices = &tri_vertices_[3 * static_cast<std::size_t>(i)];
    std::uint32_t* out_neighbors = &tri_neighbors_[3 * static_cast<std::size_t>(i)];
    for (std::uint32_t j = 0; j < 3; ++j) {
      const std::uint32_t k = kMod3[j + s];
      const std::uint32_t code = v[4 + k];
      const std::uint32_t nt = code / 3;
      const std::uint32_t other = packed[nt];
      out_neighbors[j] = 3 * (other >> 2) + kMod3[code - 3 * nt + 3 - (other & 3u)];
      if constexpr (kFinite) {
        out_vertices[j] = input_index_[v[k]];
      } else {
        out_vertices[j] = v[k] == kInfinite ? kInfinite : input_index_[v[k]];
      }
    }
  };
  tbb::parallel_for(
      tbb::blocked_range<std::uint32_t>(0, nb_finite, 16384),
      [&](const tbb::blocked_range<std::uint32_t>& range) {
        // The slots of consecutive triangles are scattered over rec_:
        // their records are fetched kAhead triangles early.
        constexpr std::uint32_t kAhead = 16;
        for (std::uint32_t i = range.begin(); i != range.end(); ++i) {
          if (i + kAhead < nb_finite) {
            prefetch(
                vertices_of<true>(static_cast<std::uint32_t>(placed_[i + kAhead] & 0xffffffffu)));
          }
          write(i, static_cast<std::uint32_t>(placed_[i] & 0xffffffffu), std::true_type{});
        }
      });
  for (const std::uint32_t t : hull) write(packed[t] >> 2, t, std::false_type{});
  // The smallest finite triangle of each vertex: the last write of a descending pass.
  detail::reserve_advised(vertex_triangle_, nb_points_);
  vertex_triangle_.assign(nb_points_, kNone);
  for (std::uint32_t i = nb_finite; i-- > 0;) {
    const std::uint32_t* v = &tri_vertices_[3 * static_cast<std::size_t>(i)];
    vertex_triangle_[v[0]] = i;
    vertex_triangle_[v[1]] = i;
    vertex_triangle_[v[2]] = i;
  }
  nb_slots_ = total;
  free_.clear();
  stamp_ = 0;
  hint_ = 0;
  nb_finite_ = nb_finite;
}

// ---------------------------------------------------------------------------------------
// Queries

std::uint32_t Delaunay2::next_ccw(std::uint32_t t, std::uint32_t v) const {
  return tri_adjacent(t, kNext[local_index(t, v)]);
}

void Delaunay2::triangles_around_vertex(std::uint32_t v, std::vector<std::uint32_t>& out) const {
  out.clear();
  const std::uint32_t t0 = vertex_triangle(v);
  assert(t0 != kNone);
  std::uint32_t t = t0;
  do {
    if (is_infinite(t)) break;
    t = next_ccw(t, v);
  } while (t != t0);
  if (!is_infinite(t)) {
    do {
      out.push_back(t);
      t = next_ccw(t, v);
    } while (t != t0);
    return;
  }
  while (is_infinite(t)) t = next_ccw(t, v);
  while (!is_infinite(t)) {
    out.push_back(t);
    t = next_ccw(t, v);
  }
}

void Delaunay2::vertex_neighbors(std::uint32_t v, std::vector<std::uint32_t>& out) const {
  triangles_around_vertex(v, out);
  if (out.empty()) return;
  const std::uint32_t last = out.back();
  for (std::uint32_t& t : out) t = tri_vertex(t, kNext[local_index(t, v)]);
  if (is_hull_vertex(v)) out.push_back(tri_vertex(last, kPrev[local_index(last, v)]));
}

bool Delaunay2::is_hull_vertex(std::uint32_t v) const {
  const std::uint32_t t0 = vertex_triangle(v);
  assert(t0 != kNone);
  std::uint32_t t = t0;
  do {
    if (is_infinite(t)) return true;
    t = next_ccw(t, v);
  } while (t != t0);
  return false;
}

std::vector<std::uint32_t> Delaunay2::hull_vertices() const {
  std::vector<std::uint32_t> out;
  const std::uint32_t h = nb_triangle_slots() - nb_finite_;
  if (h == 0) return out;
  out.reserve(h);
  // Infinite triangles are (a, b, inf) sorted by a; the hull edge leaving a is (a, a')
  // where (a', a, inf) is the infinite triangle across edge 1 of the previous one.
  std::uint32_t t = tri_adjacent(nb_finite_, 1);
  for (std::uint32_t i = 0; i < h; ++i) {
    out.push_back(tri_vertex(t, 1));
    t = tri_adjacent(t, 1);
  }
  return out;
}

std::vector<std::uint32_t> Delaunay2::hull_edges() const {
  const std::vector<std::uint32_t> hull = hull_vertices();
  std::vector<std::uint32_t> out;
  out.reserve(2 * hull.size());
  for (std::size_t i = 0; i < hull.size(); ++i) {
    out.push_back(hull[i]);
    out.push_back(hull[(i + 1) % hull.size()]);
  }
  return out;
}

void Delaunay2::circumcenter(std::uint32_t t, double* out) const {
  assert(t < nb_finite_);
  const double* a = pt(tri_vertex(t, 0));
  const double* b = pt(tri_vertex(t, 1));
  const double* c = pt(tri_vertex(t, 2));
  const double bx = b[0] - a[0], by = b[1] - a[1];
  const double cx = c[0] - a[0], cy = c[1] - a[1];
  const double d = 2 * (bx * cy - by * cx);
  const double b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
  out[0] = a[0] + (cy * b2 - by * c2) / d;
  out[1] = a[1] + (bx * c2 - cx * b2) / d;
}

std::uint32_t Delaunay2::locate(double x, double y, std::uint32_t hint) const {
  if (nb_triangle_slots() == 0) return kNone;
  const double p[2] = {x, y};
  if (!std::isfinite(x) || !std::isfinite(y)) {
    throw Error("Delaunay2::locate: non-finite query point");
  }
  return walk<false>(p, hint < nb_triangle_slots() ? hint : 0);
}

std::uint32_t Delaunay2::nearest_vertex(double x, double y, std::uint32_t hint) const {
  const std::uint32_t t = locate(x, y, hint);
  if (t == kNone) return kNone;
  const double p[2] = {x, y};
  std::uint32_t v = tri_vertex(t, 0);
  if (v == kInfinite) v = tri_vertex(t, 1);
  return detail::nearest_on_delaunay_graph(
      v, [this](std::uint32_t w, std::vector<std::uint32_t>& out) { vertex_neighbors(w, out); },
      [this, &p](std::uint32_t w, std::uint32_t u) { return compare_distance2d(p, pt(w), pt(u)); });
}

// ---------------------------------------------------------------------------------------
// Checks

std::string Delaunay2::check_topology() const {
  std::ostringstream err;
  const std::uint32_t slots = nb_triangle_slots();
  if (tri_vertices_.size() != 3 * static_cast<std::size_t>(slots) ||
      tri_neighbors_.size() != 3 * static_cast<std::size_t>(slots)) {
    return "array sizes disagree";
  }
  for (std::uint32_t t = 0; t < slots; ++t) {
    const std::uint32_t* v = &tri_vertices_[3 * static_cast<std::size_t>(t)];
    int nb_inf = 0;
    for (int k = 0; k < 3; ++k) {
      if (v[k] == kInfinite) {
        ++nb_inf;
      } else if (v[k] >= nb_points_ || duplicate_of_[v[k]] != v[k]) {
        err << "triangle " << t << " has vertex " << v[k] << " which is not a vertex";
        return err.str();
      }
    }
    if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) {
      err << "triangle " << t << " repeats a vertex";
      return err.str();
    }
    if ((t < nb_finite_) != (nb_inf == 0) || nb_inf > 1) {
      err << "triangle " << t << " has " << nb_inf
          << " infinite vertices (finite triangles are [0, " << nb_finite_ << "))";
      return err.str();
    }
    if (nb_inf == 0 && orient2d(pt(v[0]), pt(v[1]), pt(v[2])) != Sign::positive) {
      err << "finite triangle " << t << " (" << v[0] << ", " << v[1] << ", " << v[2]
          << ") is not strictly counter-clockwise";
      return err.str();
    }
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t code =
          tri_neighbors_[3 * static_cast<std::size_t>(t) + static_cast<std::size_t>(k)];
      const std::uint32_t nt = code / 3;
      const auto nk = static_cast<int>(code % 3);
      if (nt >= slots || tri_neighbors_[code] != 3 * t + static_cast<std::uint32_t>(k)) {
        err << "adjacency of triangle " << t << " edge " << k << " is not symmetric";
        return err.str();
      }
      const std::uint32_t* w = &tri_vertices_[3 * static_cast<std::size_t>(nt)];
      if (w[kNext[nk]] != v[kPrev[k]] || w[kPrev[nk]] != v[kNext[k]]) {
        err << "triangles " << t << " and " << nt << " do not share edge " << k << " reversed";
        return err.str();
      }
    }
  }
  // One umbrella per vertex: the turns around every vertex (from its incident triangle)
  // and around the infinite vertex add up to one per triangle corner.
  std::size_t corners = 0;
  std::uint32_t nb_vertices = 0;
  for (std::uint32_t v = 0; v < nb_points_; ++v) {
    const std::uint32_t t0 = vertex_triangle_[v];
    if (duplicate_of_[v] != v) {
      if (t0 != kNone) {
        err << "duplicate point " << v << " has an incident triangle";
        return err.str();
      }
      continue;
    }
    ++nb_vertices;
    if (t0 >= nb_finite_) {
      err << "vertex " << v << " has no valid incident finite triangle";
      return err.str();
    }
    const std::uint32_t* w = &tri_vertices_[3 * static_cast<std::size_t>(t0)];
    if (w[0] != v && w[1] != v && w[2] != v) {
      err << "vertex_triangle(" << v << ") = " << t0 << " does not contain it";
      return err.str();
    }
    std::uint32_t t = t0;
    std::size_t turns = 0;
    do {
      t = next_ccw(t, v);
      if (++turns > slots) {
        err << "the triangles around vertex " << v << " do not close";
        return err.str();
      }
    } while (t != t0);
    corners += turns;
  }
  if (nb_vertices != nb_unique_) return "nb_unique_points() disagrees with duplicate_of()";
  if (slots > nb_finite_) {
    std::uint32_t t = nb_finite_;
    do {
      t = next_ccw(t, kInfinite);
      ++corners;
      if (corners > 3 * static_cast<std::size_t>(slots)) return "the hull does not close";
    } while (t != nb_finite_);
  }
  if (corners != 3 * static_cast<std::size_t>(slots)) {
    err << "the vertex umbrellas cover " << corners << " corners, expected " << 3 * slots;
    return err.str();
  }
  if (slots != 2 * static_cast<std::size_t>(nb_vertices) - 2) {
    err << "Euler: " << slots << " triangles (finite + infinite) for " << nb_vertices
        << " vertices, expected " << 2 * static_cast<std::size_t>(nb_vertices) - 2;
    return err.str();
  }
  return {};
}

std::string Delaunay2::check_delaunay() const {
  const std::uint32_t slots = nb_triangle_slots();
  for (std::uint32_t t = 0; t < slots; ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t code =
          tri_neighbors_[3 * static_cast<std::size_t>(t) + static_cast<std::size_t>(k)];
      const std::uint32_t q = tri_vertices_[code];
      if (q == kInfinite) continue;
      if (in_conflict<false>(t, pt(q), q)) {
        std::ostringstream err;
        err << "vertex " << q << " is in conflict with its neighbouring triangle " << t << " ("
            << tri_vertex(t, 0) << ", " << tri_vertex(t, 1) << ", " << tri_vertex(t, 2) << ")";
        return err.str();
      }
    }
  }
  return {};
}

}  // namespace voroclip
