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
#include <cassert>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numeric>
#include <sstream>
#include <string>
#include <type_traits>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "nearest.h"
#include "spatial_sort.h"
#include "voroclip/core.h"
#include "voroclip/delaunay.h"

namespace voroclip {

namespace {

constexpr int kNext[3] = {1, 2, 0};
constexpr int kPrev[3] = {2, 0, 1};
// The most strips a round is split into (Options::zones).
constexpr std::uint32_t kMaxZones = 64;

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
  double lo[2], hi[2];
  const std::uint32_t bad = finite_bounding_box(xy, n, 2, lo, hi);
  if (bad < n) {
    const double* p = xy + 2 * static_cast<std::size_t>(bad);
    std::ostringstream message;
    message << "Delaunay2: point " << bad << " has a non-finite coordinate (" << p[0] << ", "
            << p[1] << ")";
    throw Error(message.str());
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
  filter_ = StaticFilter(lo, hi, 2);
  stats_ = Stats();
  detail::reserve_advised(duplicate_of_, n);
  duplicate_of_.resize(n);
  std::iota(duplicate_of_.begin(), duplicate_of_.end(), 0u);
  std::vector<std::uint32_t> round_starts;
  input_index_ = detail::brio_order(xy, n, 2, &round_starts);
  seq_.relabeled = false;
  insert_all(&round_starts);
  // Union-find with the smallest index as root: duplicate_of_[i] <= i, so one ascending
  // pass compresses every path.
  for (std::uint32_t i = 0; i < n; ++i) duplicate_of_[i] = duplicate_of_[duplicate_of_[i]];
  if (seq_.relabeled) {
    // A vertex was inserted before a smaller-index twin: its perturbation used the wrong
    // index. Rebuild from the distinct points (only for some duplicated input), in one
    // sequence (the rounds' bounds moved).
    input_index_.erase(std::remove_if(input_index_.begin(), input_index_.end(),
                                      [this](std::uint32_t i) { return duplicate_of_[i] != i; }),
                       input_index_.end());
    clear_triangles();
    seq_.relabeled = false;
    insert_all(nullptr);
  }
  for (std::uint32_t i = 0; i < n; ++i) nb_unique_ += duplicate_of_[i] == i ? 1u : 0u;
  canonicalize();
  if (!options_.keep_buffers) {
    for (auto* buffer : {&scratch_a_, &starting_at_}) std::vector<std::uint32_t>().swap(*buffer);
    seq_ = Zone();
    decltype(zones_)().swap(zones_);
    decltype(rec_)().swap(rec_);
    decltype(scratch_c_)().swap(scratch_c_);
    decltype(keys_)().swap(keys_);
    decltype(placed_)().swap(placed_);
    decltype(coords_)().swap(coords_);
  }
  if (options_.check) {
    std::string defect = check_topology();
    if (defect.empty()) defect = check_delaunay();
    if (!defect.empty()) throw Error("Delaunay2: internal check failed: " + defect);
  }
}

void Delaunay2::clear_triangles() {
  rec_slots_ = 0;
  seq_.free.clear();
}

// A slot for a new triangle: a recycled one, else a fresh one (whose mark is reset: rec_
// keeps the stamps of the previous build): the next of rec_, or for a strip the next of
// its range (which has room for all its points: insert_in_strips). Inlined: six calls per
// insertion.
template <bool kZoned>
[[gnu::always_inline]] inline std::uint32_t Delaunay2::new_triangle(Zone& zone) {
  if (!zone.free.empty()) {
    const std::uint32_t t = zone.free.back();
    zone.free.pop_back();
    return t;
  }
  std::uint32_t t;
  if constexpr (kZoned) {
    t = zone.fresh++;
  } else {
    t = rec_slots_++;
    if (8 * static_cast<std::size_t>(rec_slots_) > rec_.size()) {
      rec_.resize(rec_.size() + rec_.size() / 8 + 64);
    }
  }
  rec_[8 * static_cast<std::size_t>(t) + 3] = 0;
  return t;
}

// Inserts the points input_index_[0], input_index_[1], ... (local ids 0, 1, ...), round
// by round (round_starts: see detail::brio_order; null: all in one sequence).
void Delaunay2::insert_all(const std::vector<std::uint32_t>* round_starts) {
  const auto m = static_cast<std::uint32_t>(input_index_.size());
  detail::reserve_advised(coords_, 2 * static_cast<std::size_t>(m));
  coords_.resize(2 * static_cast<std::size_t>(m));
  for (std::uint32_t q = 0; q < m; ++q) {
    coords_[2 * static_cast<std::size_t>(q)] = pt(input_index_[q])[0];
    coords_[2 * static_cast<std::size_t>(q) + 1] = pt(input_index_[q])[1];
  }
  starting_at_.resize(static_cast<std::size_t>(m) + 1 + kMaxZones);
  seq_.infinite_slot = m;
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
  for (auto& s : t) s = new_triangle<false>(seq_);
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
  seq_.hint = t[0];
  seq_.stamp = 0;
  zoning_off_ = false;
  const std::uint32_t nb_rounds =
      round_starts == nullptr ? 1 : static_cast<std::uint32_t>(round_starts->size() - 1);
  for (std::uint32_t r = 0; r < nb_rounds; ++r) {
    const std::uint32_t first = round_starts == nullptr ? 0 : (*round_starts)[r];
    const std::uint32_t last = round_starts == nullptr ? m : (*round_starts)[r + 1];
    const std::uint32_t nb_zones = round_starts == nullptr ? 1 : zone_count(last - first);
    if (nb_zones > 1) {
      insert_in_strips(first, last, nb_zones, b, c);
      continue;
    }
    for (std::uint32_t q = std::max(first, 1u); q < last; ++q) {
      if (q != b && q != c) insert<false>(seq_, q);
    }
  }
}

// The number of strips for a round of `round_size` points (Options::zoned_round, zones).
std::uint32_t Delaunay2::zone_count(std::uint32_t round_size) const {
  if (zoning_off_ || round_size < std::max(options_.zoned_round, 2u)) return 1;
  if (options_.zones != 0) return std::min(options_.zones, kMaxZones);
  const std::size_t threads = std::min<std::size_t>(
      static_cast<std::size_t>(tbb::this_task_arena::max_concurrency()),
      tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
  return static_cast<std::uint32_t>(std::min<std::size_t>(threads, 8));
}

void Delaunay2::insert_sequentially(const std::uint32_t* first, const std::uint32_t* last) {
  for (; first != last; ++first) insert<false>(seq_, *first);
}

// Inserts the local ids [first, last) but 0, b and c (the first triangle's) in nb_zones
// strips (see "Threads" in the header), then the points they defer, sequentially.
void Delaunay2::insert_in_strips(std::uint32_t first, std::uint32_t last, std::uint32_t nb_zones,
                                 std::uint32_t skip_b, std::uint32_t skip_c) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // Across the longest axis of the round's box, at quantiles of a sample of its points
  // (every 16th: the strips need only be about equal).
  double lo[2] = {kInf, kInf}, hi[2] = {-kInf, -kInf};
  for (std::uint32_t q = first; q < last; ++q) {
    const double* p = local_pt(q);
    for (int a = 0; a < 2; ++a) {
      lo[a] = std::min(lo[a], p[a]);
      hi[a] = std::max(hi[a], p[a]);
    }
  }
  const int axis = hi[0] - lo[0] >= hi[1] - lo[1] ? 0 : 1;
  std::vector<double> sample;
  sample.reserve((last - first) / 16 + 1);
  for (std::uint32_t q = first; q < last; q += 16) sample.push_back(local_pt(q)[axis]);
  std::vector<double> split(nb_zones - 1);
  for (std::uint32_t k = 1; k < nb_zones; ++k) {
    const auto at = static_cast<std::ptrdiff_t>(sample.size() * k / nb_zones);
    std::nth_element(sample.begin(), sample.begin() + at, sample.end());
    split[k - 1] = sample[static_cast<std::size_t>(at)];  // (ascending in k)
  }
  if (zones_.size() < nb_zones) zones_.resize(nb_zones);
  for (std::uint32_t k = 0; k < nb_zones; ++k) {
    Zone& z = zones_[k];
    z.axis = axis;
    z.lo = k == 0 ? -kInf : split[k - 1];
    z.hi = k + 1 == nb_zones ? kInf : split[k];
    z.points.clear();
    z.run_start.clear();
    z.run_hint.clear();
    z.deferred.clear();
    z.relabeled = false;
    z.infinite_slot = input_index_.size() + 1 + k;
  }
  // A strip's points come in the round's order, along its Hilbert curve, which may leave
  // the strip and come back far away: each such return (more than kGap points of other
  // strips in between) starts a run, whose first point gets a start triangle below.
  constexpr std::uint32_t kGap = 64;
  for (std::uint32_t q = std::max(first, 1u); q < last; ++q) {
    if (q == skip_b || q == skip_c) continue;
    const double x = local_pt(q)[axis];
    Zone& z = zones_[static_cast<std::size_t>(std::upper_bound(split.begin(), split.end(), x) -
                                              split.begin())];
    if (z.points.empty() || q - z.points.back() > kGap) {
      z.run_start.push_back(static_cast<std::uint32_t>(z.points.size()));
    }
    z.points.push_back(q);
  }
  // Stamps: each insertion attempt takes two, from the zone's own range. Slots: each
  // insertion makes two more triangles than its cavity frees (whose slots it reuses
  // first), so two fresh slots per point suffice (the construction's estimate of 2m
  // slots in all still holds).
  std::uint32_t stamp = seq_.stamp;
  std::size_t slots = rec_slots_;
  for (std::uint32_t k = 0; k < nb_zones; ++k) {
    Zone& z = zones_[k];
    z.stamp = stamp;
    stamp += 2 * static_cast<std::uint32_t>(z.points.size());
    z.fresh = static_cast<std::uint32_t>(slots);
    slots += 2 * z.points.size();
    z.fresh_end = static_cast<std::uint32_t>(slots);
  }
  if (8 * slots > rec_.size()) rec_.resize(8 * slots + rec_.size() / 8);
  rec_slots_ = static_cast<std::uint32_t>(slots);  // the walks' step limit reads it
  // A start for each run: the triangle holding one of its first points (the 1st, 2nd,
  // 4th, 8th, ...: a run begins where the curve enters the strip, on its boundary), found
  // by a sequential walk, whose finite vertices are all in the strip. run_start then
  // becomes that point's position (the points before it go on from the strip's last
  // triangle, if any), or kNone when there is none. It is still a triangle all in the
  // strip when the point's turn comes: only the strip's own insertions may change it, and
  // each reuses the slots of its cavity, which are all in the strip.
  for (std::uint32_t k = 0; k < nb_zones; ++k) {
    Zone& z = zones_[k];
    for (std::size_t r = 0; r < z.run_start.size(); ++r) {
      const std::uint32_t end = r + 1 < z.run_start.size()
                                    ? z.run_start[r + 1]
                                    : static_cast<std::uint32_t>(z.points.size());
      const std::uint32_t begin = z.run_start[r];
      z.run_start[r] = kNone;
      z.run_hint.push_back(kNone);
      for (std::uint32_t step = 1, i = begin; i < end; i = begin + step, step *= 2) {
        const std::uint32_t t = walk<true>(local_pt(z.points[i]), seq_.hint);
        seq_.hint = t;
        const std::uint32_t* v = vertices_of<true>(t);
        if (std::all_of(v, v + 3, [&z, this](std::uint32_t w) {
              return w == kInfinite || z.inside(local_pt(w));
            })) {
          z.run_start[r] = i;
          z.run_hint[r] = t;
          break;
        }
      }
    }
  }
  tbb::parallel_for(
      tbb::blocked_range<std::uint32_t>(0, nb_zones, 1),
      [this](const tbb::blocked_range<std::uint32_t>& range) {
        for (std::uint32_t k = range.begin(); k != range.end(); ++k) {
          Zone& z = zones_[k];
          z.started = false;
          std::size_t run = 0;
          for (std::size_t i = 0; i < z.points.size(); ++i) {
            while (run < z.run_start.size() && z.run_start[run] == kNone) ++run;
            if (run < z.run_start.size() && z.run_start[run] == i) {
              z.hint = z.run_hint[run++];
              z.started = true;
            }
            if (!z.started || !insert<true>(z, z.points[i])) z.deferred.push_back(z.points[i]);
          }
        }
      },
      tbb::simple_partitioner());
  // Unused slots become free ones of the sequential insertion.
  std::vector<std::uint32_t> deferred;
  for (std::uint32_t k = 0; k < nb_zones; ++k) {
    Zone& z = zones_[k];
    for (std::uint32_t t = z.fresh; t < z.fresh_end; ++t) {
      rec_[8 * static_cast<std::size_t>(t)] = kFreeVertex;
      rec_[8 * static_cast<std::size_t>(t) + 3] = 0;
      seq_.free.push_back(t);
    }
    // (Each insertion reuses every slot its cavity frees: a strip's free list ends empty.)
    assert(z.free.empty());
    if (z.started) seq_.hint = z.hint;
    seq_.relabeled = seq_.relabeled || z.relabeled;
    deferred.insert(deferred.end(), z.deferred.begin(), z.deferred.end());
    stats_.zoned_points += static_cast<std::uint32_t>(z.points.size());
  }
  seq_.stamp = stamp;
  ++stats_.zoned_passes;
  stats_.deferred_points += static_cast<std::uint32_t>(deferred.size());
  // Strips that deferred most of their points: cavities span them (points on a circle:
  // their triangles cross the disk). The rest of the build is sequential.
  if (2 * deferred.size() > last - first) zoning_off_ = true;
  std::sort(deferred.begin(), deferred.end());  // back to insertion order
  insert_sequentially(deferred.data(), deferred.data() + deferred.size());
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
// With a zone (construction only), t has all its finite vertices in the zone and so has
// every triangle the walk enters: a step across an edge is allowed only when the vertex
// beyond it is in the zone. kNone when p lies beyond edges of a triangle that all lead
// out of the zone (or after the step limit, since other tasks may be inserting).
template <bool kLocal>
std::uint32_t Delaunay2::walk(const double* p, std::uint32_t t, const Zone* zone) const {
  const auto orient = [this, p](std::uint32_t a, std::uint32_t b) {
    if constexpr (kLocal) {
      return orient2d(local_pt(a), local_pt(b), p, filter_);
    } else {
      return orient2d(pt(a), pt(b), p);
    }
  };
  // Whether the triangle across code 3t' + k' (which shares an edge in the zone) is all in it.
  const auto reaches = [this, zone](std::uint32_t code) {
    if (!kLocal || zone == nullptr) return true;
    const std::uint32_t o = vertices_of<kLocal>(code / 3)[code % 3];
    return o == kInfinite || zone->inside(local_pt(o));
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
      const std::uint32_t code = neighbor_of<kLocal>(t, kinf);
      if (!reaches(code)) return kNone;
      previous = t;
      t = code / 3;
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
    bool moved = false, blocked = false;
    for (int j = 0; j < 3 && !moved; ++j) {
      const int k = (k0 + j) % 3;
      const std::uint32_t code = neighbor_of<kLocal>(t, k);
      const std::uint32_t next = code / 3;
      if (next == previous) continue;
      if (orient(v[kNext[k]], v[kPrev[k]]) == Sign::negative) {
        if (!reaches(code)) {
          blocked = true;
          continue;
        }
        previous = t;
        t = next;
        moved = true;
      }
    }
    if (!moved) return blocked ? kNone : t;
  }
  if (kLocal && zone != nullptr) return kNone;
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

// Inserts local id q; false (the triangulation untouched) when a strip's walk or cavity
// would leave it.
template <bool kZoned>
bool Delaunay2::insert(Zone& zone, std::uint32_t q) {
  const double* p = local_pt(q);
  const std::uint32_t ip = input_index_[q];
  const std::uint32_t start = walk<true>(p, zone.hint, kZoned ? &zone : nullptr);
  if (kZoned && start == kNone) return false;
  const std::uint32_t* sv = vertices_of<true>(start);
  if (sv[0] != kInfinite && sv[1] != kInfinite && sv[2] != kInfinite) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t w = sv[k];
      if (!same_point(local_pt(w), p)) continue;
      std::uint32_t root = input_index_[w];
      while (duplicate_of_[root] != root) root = duplicate_of_[root];
      if (ip < root) {
        duplicate_of_[root] = ip;
        zone.relabeled = true;
      } else {
        duplicate_of_[ip] = root;
      }
      return true;
    }
  }
  // A triangle's neighbours are read when it is taken from the stack: their records are
  // prefetched as it enters (they are scattered over the array).
  const auto prefetch_neighbors = [this](std::uint32_t t) {
    for (int k = 0; k < 3; ++k) prefetch(vertices_of<true>(neighbor_of<true>(t, k) / 3));
  };
  zone.stamp += 2;  // stamp: in the cavity; stamp + 1: tested, not in conflict
  const std::uint32_t stamp = zone.stamp;
  const std::uint32_t rejected = stamp + 1;
  std::vector<std::uint32_t>& stack = zone.stack;
  std::vector<std::uint32_t>& cavity = zone.cavity;
  std::vector<BoundaryEdge>& boundary = zone.boundary;
  stack.clear();
  cavity.clear();
  boundary.clear();
  rec_[8 * static_cast<std::size_t>(start) + 3] = stamp;
  prefetch_neighbors(start);
  stack.push_back(start);
  while (!stack.empty()) {
    const std::uint32_t c = stack.back();
    stack.pop_back();
    cavity.push_back(c);
    const std::uint32_t* v = vertices_of<true>(c);
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t code = v[4 + k];
      const std::uint32_t nt = code / 3;
      if constexpr (kZoned) {
        // A triangle with a vertex outside the strip: its mark may be another task's.
        const std::uint32_t o = rec_[8 * static_cast<std::size_t>(nt) + (code - 3 * nt)];
        if (o != kInfinite && !zone.inside(local_pt(o))) {
          if (in_conflict<true>(nt, p, ip)) return false;
          boundary.push_back({v[kNext[k]], v[kPrev[k]], code});
          continue;
        }
      }
      std::uint32_t& mark = rec_[8 * static_cast<std::size_t>(nt) + 3];
      if (mark == stamp) continue;
      if (mark != rejected && in_conflict<true>(nt, p, ip)) {
        mark = stamp;
        prefetch_neighbors(nt);
        stack.push_back(nt);
        continue;
      }
      mark = rejected;
      boundary.push_back({v[kNext[k]], v[kPrev[k]], code});
    }
  }
  // A strip's range holds two fresh slots per point (insert_in_strips) and each insertion
  // takes two more than its cavity frees: room for every point.
  assert(!kZoned ||
         zone.free.size() + cavity.size() + (zone.fresh_end - zone.fresh) >= boundary.size());
  for (const std::uint32_t c : cavity) zone.free.push_back(c);
  const std::size_t infinite_slot = zone.infinite_slot;
  const auto slot_of = [infinite_slot](std::uint32_t v) {
    return v == kInfinite ? infinite_slot : static_cast<std::size_t>(v);
  };
  // The star of p: (p, u, w) for each boundary edge (u, w), its edge 0 glued to the
  // triangle outside; edge 1 (w, p) is edge 2 of the new triangle starting at w.
  stack.clear();
  for (const BoundaryEdge& e : boundary) {
    const std::uint32_t t = new_triangle<kZoned>(zone);
    std::uint32_t* v = &rec_[8 * static_cast<std::size_t>(t)];
    v[0] = q;
    v[1] = e.u;
    v[2] = e.w;
    v[4] = e.outside;
    rec_[8 * static_cast<std::size_t>(e.outside / 3) + 4 + e.outside % 3] = 3 * t;
    starting_at_[slot_of(e.u)] = t;
    stack.push_back(t);
  }
  for (const std::uint32_t t : stack) {
    std::uint32_t* v = &rec_[8 * static_cast<std::size_t>(t)];
    const std::uint32_t next = starting_at_[slot_of(v[2])];
    v[5] = 3 * next + 2;
    rec_[8 * static_cast<std::size_t>(next) + 6] = 3 * t + 1;
  }
  zone.hint = stack.back();
  return true;
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
  std::vector<std::uint32_t>& hull = seq_.stack;
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
  seq_.free.clear();
  seq_.stamp = 0;
  seq_.hint = 0;
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
  // Accurate however flat the triangle (predicates.h): the plain formula's determinant is
  // rounding noise for sites 3e-48 apart among others 1e-28 from them, and the Voronoi
  // vertex came out NaN (tests/clip/fuzz_regressions/clip2d_nan_voronoi_vertex.xy).
  circumcenter2d(a, b, c, out);
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
