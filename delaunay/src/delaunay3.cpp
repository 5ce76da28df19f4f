// Delaunay3: Bowyer–Watson insertion (Bowyer 1981; Watson 1981) in BRIO order (Amenta,
// Choi & Rote 2003), located by a remembering visibility walk (Devillers, Pion & Teillaud
// 2002) from the last created tet; parallel insertion in boxes after HXT (Marot, Pellerin
// & Remacle, IJNME 2019). Storage, numbering, the conflict test, the slot numbering and
// the threading scheme are documented once in voroclip/delaunay.h.
//
// One insertion: walk to a tet in conflict with q, grow the cavity by a breadth-first
// search over adjacent tets in conflict (the cavity array is the queue), then replace it
// by the star of q over the cavity boundary. Each boundary facet (a, b, c), listed as in
// the cavity tet behind it, gives the new tet (q, a, b, c) (q takes the place of the
// vertex opposite the facet, so the orientation is kept), rotated so that kInfinite stays
// vertex 3. Its facet 0 is glued to the tet outside; facets 1, 2, 3 contain q and the
// boundary edges (b, c), (c, a), (a, b): the new tets are glued pairwise by these edges,
// each directed edge of one boundary facet matching the reversed edge of another. Small
// cavities (at most 31 boundary vertices, nearly all of them) give their boundary vertices
// local ids 1..31 (0 is kInfinite) and glue through a 32 x 32 table; larger ones sort their
// edges. The new tets reuse the cavity's slots first, while they are in cache.
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <string>

#include "insphere_det.h"
#include "nearest.h"
#include "spatial_sort.h"
#include "voroclip/core.h"
#include "voroclip/delaunay.h"

namespace voroclip {

namespace {

constexpr std::uint32_t kInCavity = 0x80000000u;  // marks in tets_[8t + 4]
constexpr std::uint32_t kOutside = 0x40000000u;
// Cavities with at most this many boundary facets have at most 31 boundary vertices
// (a triangulated sphere with F facets has F / 2 + 2 vertices): the table path.
constexpr std::size_t kSmallCavity = 58;
constexpr std::uint32_t kTableSide = 32;
// Fresh slots given to a zone per point it inserts (uniform points need about 6.75).
constexpr double kSlotsPerPoint = 6.9;
// Slots per point the sequential rounds before the first zoned one may use (see
// triangulate).
constexpr std::size_t kPrefixSlotsPerPoint = 8;
// A set of points is split into at most this many zones.
constexpr std::size_t kMaxZones = 64;
// Zones of at least this many points that defer most of them turn zoning off.
constexpr std::size_t kLargeZone = 16384;

// The CPU can run detail::insphere_det_avx2.
bool cpu_has_avx2() {
#if defined(VOROCLIP_INSPHERE_DET_AVX2)
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2");
#else
  return false;
#endif
}

bool same_point(const double* a, const double* b) {
  return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
}

// Reserves room for exactly `size` elements (resize() alone may double the capacity).
template <class T, class A>
void reserve_exactly(std::vector<T, A>& v, std::size_t size) {
  if (size > v.capacity()) {
    v.reserve(size);
    if (size * sizeof(T) >= detail::kHugePageAdviceBytes) {
      detail::advise_huge_pages(v.data(), size * sizeof(T));
    }
  }
}

// A hint that the cache line at p will be read soon (no effect on results).
inline void prefetch(const void* p) {
#if defined(__GNUC__)
  __builtin_prefetch(p);
#else
  static_cast<void>(p);
#endif
}

// More than one thread may run this build's tasks (the arena's and the global limit).
bool several_threads() {
  return tbb::this_task_arena::max_concurrency() > 1 &&
         tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism) > 1;
}

// Writes one word in every 4 KiB page of [first, last), in parallel: the kernel zeroes a
// page (or a whole huge page) on its first touch, on the touching thread. Values are left
// arbitrary (every slot is written before it is read).
void touch_pages(std::uint32_t* first, std::uint32_t* last) {
  constexpr std::size_t kPageWords = 4096 / sizeof(std::uint32_t);
  constexpr std::size_t kChunkWords = (std::size_t{1} << 21) / sizeof(std::uint32_t);
  const auto size = static_cast<std::size_t>(last - first);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, (size + kChunkWords - 1) / kChunkWords, 1),
                    [first, size](const tbb::blocked_range<std::size_t>& chunks) {
                      const std::size_t end = std::min(size, chunks.end() * kChunkWords);
                      for (std::size_t i = chunks.begin() * kChunkWords; i < end; i += kPageWords) {
                        first[i] = 0;
                      }
                    });
}

template <class T, class A>
std::size_t capacity_bytes(const std::vector<T, A>& v) {
  return v.capacity() * sizeof(T);
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Predicates on the triangulation

// The common case inline (a finite tet, decided by the static filter); the rest in
// in_conflict_rest, out of line so that the hot path needs few registers. kAvx2: the
// determinant by insphere_det_avx2 (a call: it is compiled for AVX2, this code is not).
// v: t's record; pts, pq: the points and q's coordinates (passed by the cavity search,
// which holds them in registers).
template <bool kAvx2>
inline bool Delaunay3::in_conflict(const std::uint32_t* v, std::uint32_t t, std::uint32_t q,
                                   const double* pts, const double* pq) const {
  if (v[3] != kInfinite) {
    // insphere(a, b, c, d, q, filter_)'s first stage, in SSE2 or AVX2 (the same value).
    const double* a = pts + 3 * static_cast<std::size_t>(v[0]);
    const double* b = pts + 3 * static_cast<std::size_t>(v[1]);
    const double* c = pts + 3 * static_cast<std::size_t>(v[2]);
    const double* d = pts + 3 * static_cast<std::size_t>(v[3]);
    double det;
#if defined(VOROCLIP_INSPHERE_DET_AVX2)
    if constexpr (kAvx2) {
      det = detail::insphere_det_avx2(a, b, c, d, pq);
    } else {
      det = detail::insphere_det(a, b, c, d, pq);
    }
#else
    det = detail::insphere_det(a, b, c, d, pq);
#endif
    if (std::fabs(det) > filter_.insphere_bound()) return det > 0;
  }
  return in_conflict_rest(t, q);
}

template <bool kAvx2>
inline bool Delaunay3::in_conflict(std::uint32_t t, std::uint32_t q) const {
  return in_conflict<kAvx2>(&tets_[8 * static_cast<std::size_t>(t)], t, q, pts_, point(q));
}

bool Delaunay3::in_conflict_rest(std::uint32_t t, std::uint32_t q) const {
  const std::uint32_t* v = &tets_[8 * static_cast<std::size_t>(t)];
  const double* pq = point(q);
  if (v[3] != kInfinite) {
    const double* a = point(v[0]);
    const double* b = point(v[1]);
    const double* c = point(v[2]);
    const double* d = point(v[3]);
    Sign r = insphere(a, b, c, d, pq);
    if (r == Sign::zero) {
      r = insphere_sos(a, b, c, d, pq, sos_id(v[0]), sos_id(v[1]), sos_id(v[2]), sos_id(v[3]),
                       sos_id(q));
    }
    return r == Sign::positive;
  }
  // Facet 3 as listed, (v2, v1, v0): the hull facet, the hull's inside on its positive side.
  const double* a = point(v[2]);
  const double* b = point(v[1]);
  const double* c = point(v[0]);
  const Sign o = orient3d(a, b, c, pq, filter_);
  if (o != Sign::zero) return o == Sign::negative;
  // On the hull facet's plane: inside its circumcircle (see the header).
  const std::uint32_t code = v[7] & kCodeMask;
  const std::uint32_t d = tets_[8 * static_cast<std::size_t>(code / 4) + code % 4];
  return insphere_sos(a, b, c, point(d), pq, sos_id(v[2]), sos_id(v[1]), sos_id(v[0]), sos_id(d),
                      sos_id(q)) == Sign::positive;
}

// Visibility walk from t towards p (a point of the construction, inside the filter's box),
// remembering the tet it came from; it terminates in a Delaunay triangulation (Edelsbrunner
// 1990). The facet tested first rotates with the step, which avoids the worst cases of a
// fixed order. Ends in t: a finite tet whose closure holds p, or an infinite tet whose hull
// facet p lies strictly beyond (both in conflict with p). kZoned: only steps into tets whose
// finite vertices are in the zone; returns false, leaving the triangulation untouched,
// when p is beyond a facet of the current tet but every such facet leads out of the zone.
template <bool kZoned>
bool Delaunay3::walk(const Zone& zone, const double* p, std::uint32_t& t) const {
  std::uint32_t current = t;
  if (tets_[8 * static_cast<std::size_t>(current) + 3] == kInfinite) {
    const std::uint32_t code = tets_[8 * static_cast<std::size_t>(current) + 7] & kCodeMask;
    if constexpr (kZoned) {
      if (!zone.inside(point(tets_[8 * static_cast<std::size_t>(code / 4) + code % 4]))) {
        return false;
      }
    }
    current = code / 4;
  }
  std::uint32_t previous = kNoTet;
  const std::size_t limit = 16 * static_cast<std::size_t>(nb_slots_) + 64;
  for (std::size_t step = 0; step < limit; ++step) {
    const std::uint32_t* v = &tets_[8 * static_cast<std::size_t>(current)];
    // The next tet is one of the neighbours: load them while the predicates run.
    for (std::size_t f = 0; f < 4; ++f) {
      prefetch(&tets_[8 * static_cast<std::size_t>((v[4 + f] & kCodeMask) / 4)]);
    }
    // The vertices' differences to p, computed once for the facets tested: orient3d's
    // filter stage on (a, b, c, p) translates to p with these same operations, so `det` is
    // bit for bit its value and the filter's bound holds.
    double dx[4], dy[4], dz[4];
    for (std::size_t k = 0; k < 4; ++k) {
      const double* pk = point(v[k]);
      dx[k] = pk[0] - p[0];
      dy[k] = pk[1] - p[1];
      dz[k] = pk[2] - p[2];
    }
    std::uint32_t next_code = kNoTet;
    bool blocked = false;  // a facet p lies beyond leads out of the zone
    for (std::size_t i = 0; i < 4; ++i) {
      const std::size_t f = (step + i) & 3u;
      const std::uint32_t code = v[4 + f] & kCodeMask;
      if (code / 4 == previous) continue;
      const int* fv = kFacetVertex[f];
      const auto a = static_cast<std::size_t>(fv[0]), b = static_cast<std::size_t>(fv[1]),
                 c = static_cast<std::size_t>(fv[2]);
      const double det = dz[a] * (dx[b] * dy[c] - dx[c] * dy[b]) +
                         dz[b] * (dx[c] * dy[a] - dx[a] * dy[c]) +
                         dz[c] * (dx[a] * dy[b] - dx[b] * dy[a]);
      const bool beyond =
          std::fabs(det) > filter_.orient3d_bound()
              ? det > 0
              : orient3d(point(v[a]), point(v[b]), point(v[c]), p) == Sign::positive;
      if (beyond) {
        if constexpr (kZoned) {
          // Any facet p lies beyond will do (the walk still terminates): take one whose tet
          // is in the zone.
          const std::uint32_t o = tets_[8 * static_cast<std::size_t>(code / 4) + code % 4];
          if (o != kInfinite && !zone.inside(point(o))) {
            blocked = true;
            continue;
          }
        }
        next_code = code;
        break;
      }
    }
    if (next_code == kNoTet) {
      t = current;
      return !blocked;
    }
    const std::uint32_t* n = &tets_[8 * static_cast<std::size_t>(next_code / 4)];
    previous = current;
    current = next_code / 4;
    if (n[3] == kInfinite) {
      t = current;
      return true;
    }
  }
  throw Error("Delaunay3: internal error, the point location walk did not terminate");
}

// The same walk for queries on the finished triangulation: plain predicates (the query may
// lie outside the filter's box).
std::uint32_t Delaunay3::walk_query(const double* p, std::uint32_t t) const {
  if (is_infinite(t)) t = tet_adjacent(t, 3);
  std::uint32_t previous = kNoTet;
  const std::size_t limit = 16 * static_cast<std::size_t>(nb_slots_) + 64;
  for (std::size_t step = 0; step < limit; ++step) {
    std::uint32_t next = kNoTet;
    for (std::size_t i = 0; i < 4 && next == kNoTet; ++i) {
      const int f = static_cast<int>((step + i) & 3u);
      const std::uint32_t n = tet_adjacent(t, f);
      if (n == previous) continue;
      const int* fv = kFacetVertex[f];
      if (orient3d(point(tet_vertex(t, fv[0])), point(tet_vertex(t, fv[1])),
                   point(tet_vertex(t, fv[2])), p) == Sign::positive) {
        next = n;
      }
    }
    if (next == kNoTet) return t;
    previous = t;
    t = next;
    if (is_infinite(t)) return t;
  }
  throw Error("Delaunay3: internal error, the point location walk did not terminate");
}

// ---------------------------------------------------------------------------------------
// Insertion

// Makes at least `slots` slots addressable: within the capacity by steps of 1/16, beyond
// it by reallocating with 1/8 more (resize() alone would double the capacity).
void Delaunay3::grow_slots(std::size_t slots) {
  if (slots > kMaxTets) throw Error("Delaunay3: more than 2^28 tetrahedra; input too large");
  const std::size_t size = tets_.size() / 8;
  if (slots <= size) return;
  const std::size_t capacity = tets_.capacity() / 8;
  if (slots > capacity) {
    reserve_exactly(tets_,
                    8 * std::min<std::size_t>(kMaxTets, std::max(slots, capacity + capacity / 8)));
  }
  tets_.resize(8 * std::min(tets_.capacity() / 8, std::max(slots, size + size / 16 + 64)));
  note_memory();
}

// Makes `count` slots available to the zone (its free list, then its fresh range). A
// sequential insertion grows the array; a zone with a fixed range may run out.
template <bool kZoned>
bool Delaunay3::take_slots(Zone& zone, std::size_t count) {
  const std::size_t available = zone.free.size() + (zone.fresh_end - zone.fresh);
  if (available >= count) return true;
  if constexpr (kZoned) {
    return false;
  } else {
    const std::size_t slots = static_cast<std::size_t>(zone.fresh) + count;
    if (slots > slot_limit_) return false;
    grow_slots(slots);
    zone.fresh_end = static_cast<std::uint32_t>(std::min(tets_.size() / 8, slot_limit_));
    return true;
  }
}

void Delaunay3::unmark_cavity(const Zone& zone) {
  for (const std::uint32_t t : zone.cavity) tets_[8 * static_cast<std::size_t>(t) + 4] &= kCodeMask;
  for (const BoundaryFacet& b : zone.boundary) {
    tets_[8 * static_cast<std::size_t>(b.code / 4) + 4] &= kCodeMask;
  }
}

template <bool kZoned, bool kAvx2>
inline Delaunay3::Inserted Delaunay3::insert(Zone& zone, std::uint32_t q) {
  const double* pq = point(q);
  std::uint32_t start = zone.hint;
  if (!walk<kZoned>(zone, pq, start)) return Inserted::deferred;
  if (tets_[8 * static_cast<std::size_t>(start) + 3] != kInfinite) {
    for (std::size_t k = 0; k < 4; ++k) {
      const std::uint32_t w = tets_[8 * static_cast<std::size_t>(start) + k];
      if (same_point(point(w), pq)) {
        duplicate_internal_[q] = w;
        zone.hint = start;
        return Inserted::duplicate;
      }
    }
  }

  // The cavity: breadth-first from the located tet (in conflict: q lies in it, or
  // strictly beyond its hull facet). Marks: kInCavity on cavity tets, kOutside on tets
  // tested and found outside; both are cleared below.
  std::vector<std::uint32_t>& cavity = zone.cavity;
  std::vector<BoundaryFacet>& boundary = zone.boundary;
  cavity.clear();
  boundary.clear();
  // The records and points through local pointers (reloaded after take_slots, which may
  // move the array): the stores of cavity's end, a std::uint32_t* like tets_'s start, made
  // the compiler reload that after each push, and the stores to local_id_ (bytes, which may
  // alias anything) every array's address after each of them.
  std::uint32_t* tets = tets_.data();
  const double* const pts = pts_;
  // A tet's neighbours are read when it is taken from the queue, a few tets after it entered:
  // their records are prefetched as it enters (they are scattered over the array).
  const auto prefetch_neighbors = [tets](std::uint32_t t) {
    const std::uint32_t* w = &tets[8 * static_cast<std::size_t>(t)];
    for (std::size_t f = 0; f < 4; ++f) {
      prefetch(&tets[8 * static_cast<std::size_t>((w[4 + f] & kCodeMask) / 4)]);
    }
  };
  tets[8 * static_cast<std::size_t>(start) + 4] |= kInCavity;
  prefetch_neighbors(start);
  cavity.push_back(start);
  for (std::size_t i = 0; i < cavity.size(); ++i) {
    const std::uint32_t* w = &tets[8 * static_cast<std::size_t>(cavity[i])];
    for (std::size_t f = 0; f < 4; ++f) {
      const std::uint32_t code = w[4 + f] & kCodeMask;
      const std::uint32_t n = code / 4;
      std::uint32_t* const record = &tets[8 * static_cast<std::size_t>(n)];
      std::uint32_t& marks = record[4];
      if ((marks & kInCavity) != 0) continue;
      if ((marks & kOutside) == 0) {
        // The zone test's vertex (opposite the facet crossed) is read before the conflict
        // test, and the boundary facet's code again from the record: held across the
        // test, the code was spilled to the stack (callgrind: 0.9 % fewer instructions).
        std::uint32_t o = 0;
        if constexpr (kZoned) o = record[code % 4];
        if (in_conflict<kAvx2>(record, n, q, pts, pq)) {
          if constexpr (kZoned) {
            if (o != kInfinite && !zone.inside(pts + 3 * static_cast<std::size_t>(o))) {
              unmark_cavity(zone);
              return Inserted::deferred;
            }
          }
          marks |= kInCavity;
          prefetch_neighbors(n);
          cavity.push_back(n);
          continue;
        }
        marks |= kOutside;
      }
      const int* fv = kFacetVertex[f];
      boundary.push_back({w[4 + f] & kCodeMask, {w[fv[0]], w[fv[1]], w[fv[2]]}});
    }
  }

  // Slots for the new tets: the cavity's, then the zone's free list, then fresh ones.
  const std::size_t nb_new = boundary.size();
  const std::size_t nb_dead = cavity.size();
  if (nb_new > nb_dead && !take_slots<kZoned>(zone, nb_new - nb_dead)) {
    unmark_cavity(zone);
    return Inserted::deferred;
  }
  for (std::size_t i = nb_new; i < nb_dead; ++i) {
    std::uint32_t* w = &tets_[8 * static_cast<std::size_t>(cavity[i])];
    w[0] = kFreeVertex;
    w[4] = 0;
    zone.free.push_back(cavity[i]);
  }
  if (nb_new > nb_dead) {
    // Indexed writes after one resize: push_back's growth path is not inlined.
    cavity.resize(nb_new);
    std::size_t i = nb_dead;
    const std::size_t nb_free = std::min(zone.free.size(), nb_new - nb_dead);
    const std::uint32_t* free_top = zone.free.data() + zone.free.size();
    for (std::size_t k = 0; k < nb_free; ++k)
      cavity[i++] = free_top[-1 - static_cast<std::ptrdiff_t>(k)];
    zone.free.resize(zone.free.size() - nb_free);
    // From a local copy: through zone.fresh the loop stored and reloaded it each time.
    std::uint32_t fresh = zone.fresh;
    for (; i < nb_new; ++i) cavity[i] = fresh++;
    zone.fresh = fresh;
  }

  const bool small = nb_new <= kSmallCavity;
  tets = tets_.data();
  std::uint32_t* const table = zone.edge_map.data();
  std::uint8_t* const local_id = local_id_.data();
  std::uint32_t* const local_vertex = zone.local_vertex.data();
  BoundaryFacet* const facets = boundary.data();
  const std::uint32_t* const slots = cavity.data();
  std::uint32_t nb_local = 1;
  // The local id of a finite vertex (kInfinite has 0; after the rotation below only the
  // third vertex of a facet can be kInfinite). local_id_ is 0 for every vertex between
  // insertions: the ids given here are reset below.
  const auto local = [local_id, local_vertex, &nb_local](std::uint32_t v) -> std::uint32_t {
    const std::uint32_t l = local_id[v];
    if (l != 0) return l;
    local_vertex[nb_local] = v;
    local_id[v] = static_cast<std::uint8_t>(nb_local);
    return nb_local++;
  };
  for (std::size_t i = 0; i < nb_new; ++i) {
    BoundaryFacet& b = facets[i];
    const std::uint32_t nt = slots[i];
    std::uint32_t x = b.v[0], y = b.v[1], z = b.v[2];
    if (x == kInfinite) {  // (y, z, x): an even permutation keeps the orientation
      x = y;
      y = z;
      z = kInfinite;
    } else if (y == kInfinite) {  // (z, x, y)
      y = x;
      x = z;
      z = kInfinite;
    }
    std::uint32_t* w = &tets[8 * static_cast<std::size_t>(nt)];
    w[0] = q;
    w[1] = x;
    w[2] = y;
    w[3] = z;
    w[4] = b.code;
    std::uint32_t* outside = &tets[8 * static_cast<std::size_t>(b.code / 4)];
    outside[4] &= kCodeMask;
    outside[4 + b.code % 4] = (outside[4 + b.code % 4] & ~kCodeMask) | (4 * nt);
    if (small) {
      const std::uint32_t lx = local(x), ly = local(y), lz = z == kInfinite ? 0 : local(z);
      b.v[0] = lx;
      b.v[1] = ly;
      b.v[2] = lz;
      // Table entry (u, v): the facet through q and the directed boundary edge u -> v.
      table[lx * kTableSide + ly] = 4 * nt + 3;
      table[ly * kTableSide + lz] = 4 * nt + 1;
      table[lz * kTableSide + lx] = 4 * nt + 2;
    }
    b.code = 4 * nt;
  }
  if (small) {
    for (const BoundaryFacet* b = facets; b != facets + nb_new; ++b) {
      std::uint32_t* w = &tets[2 * static_cast<std::size_t>(b->code) + 4];
      w[1] = table[b->v[2] * kTableSide + b->v[1]];
      w[2] = table[b->v[0] * kTableSide + b->v[2]];
      w[3] = table[b->v[1] * kTableSide + b->v[0]];
    }
    for (std::uint32_t l = 1; l < nb_local; ++l) local_id[local_vertex[l]] = 0;
  } else {
    glue_large_cavity(zone, q);
  }
  cavity.resize(nb_new);
  zone.hint = cavity.back();
  return Inserted::yes;
}

// Gluing for large cavities: every directed boundary edge (u, v) with the new tet's facet
// through it, sorted; the facet through (v, u) is found by binary search.
void Delaunay3::glue_large_cavity(Zone& zone, std::uint32_t q) {
  std::vector<std::uint64_t>& keys = zone.edges;
  std::vector<std::uint32_t>& codes = zone.edge_codes;
  keys.clear();
  for (const BoundaryFacet& b : zone.boundary) {
    const std::uint32_t* w = &tets_[2 * static_cast<std::size_t>(b.code)];
    const auto key = [](std::uint32_t u, std::uint32_t v) {
      return (static_cast<std::uint64_t>(u) << 32) | v;
    };
    // Facet f of (q, a, b, c) holds the edge opposite: 1 -> (b, c), 2 -> (c, a), 3 -> (a, b).
    keys.push_back(key(w[2], w[3]));
    keys.push_back(key(w[3], w[1]));
    keys.push_back(key(w[1], w[2]));
  }
  // Sort the keys with their facet codes (the code of entry 3i + j is 4 * tet + j + 1).
  codes.resize(keys.size());
  std::iota(codes.begin(), codes.end(), 0u);
  std::sort(codes.begin(), codes.end(),
            [&keys](std::uint32_t i, std::uint32_t j) { return keys[i] < keys[j]; });
  std::vector<std::uint64_t>& sorted = zone.sorted_edges;
  sorted.resize(keys.size());
  for (std::size_t i = 0; i < codes.size(); ++i) sorted[i] = keys[codes[i]];
  for (std::size_t i = 0; i < codes.size(); ++i) {
    const std::uint64_t reversed = (sorted[i] << 32) | (sorted[i] >> 32);
    const auto at = std::lower_bound(sorted.begin(), sorted.end(), reversed);
    if (at == sorted.end() || *at != reversed) {
      throw Error("Delaunay3: internal error, the cavity boundary is not closed (point " +
                  std::to_string(sos_id(q)) + ")");
    }
    const std::uint32_t mine = codes[i];
    const std::uint32_t other = codes[static_cast<std::size_t>(at - sorted.begin())];
    const std::uint32_t my_tet = zone.boundary[mine / 3].code / 4;
    const std::uint32_t other_tet = zone.boundary[other / 3].code / 4;
    tets_[8 * static_cast<std::size_t>(my_tet) + 4 + 1 + mine % 3] = 4 * other_tet + 1 + other % 3;
  }
}

std::uint32_t Delaunay3::initial_tetrahedron() {
  // The first four affinely independent points of the insertion order.
  const auto m = static_cast<std::uint32_t>(input_id_.size());
  std::uint32_t chosen[4];
  std::uint32_t i = 0;
  chosen[0] = 0;
  for (i = 1; i < m && same_point(point(i), point(chosen[0])); ++i) {
  }
  if (i == m)
    throw Error(
        "Delaunay3: all points coincide; need 4 affinely independent points; for the clipped "
        "Voronoi diagram of such sites, ClippedVoronoi3::compute(domain, sites, n) takes them");
  chosen[1] = i;
  for (++i; i < m && collinear3d(point(chosen[0]), point(chosen[1]), point(i)); ++i) {
  }
  if (i == m)
    throw Error(
        "Delaunay3: all points are collinear; need 4 affinely independent points; for the clipped "
        "Voronoi diagram of such sites, ClippedVoronoi3::compute(domain, sites, n) takes them");
  chosen[2] = i;
  Sign o = Sign::zero;
  for (++i; i < m; ++i) {
    o = orient3d(point(chosen[0]), point(chosen[1]), point(chosen[2]), point(i));
    if (o != Sign::zero) break;
  }
  if (i == m)
    throw Error(
        "Delaunay3: all points are coplanar; need 4 affinely independent points; for the clipped "
        "Voronoi diagram of such sites, ClippedVoronoi3::compute(domain, sites, n) takes them");
  chosen[3] = i;
  if (o == Sign::negative) std::swap(chosen[0], chosen[1]);

  // Tet 0 and, on each facet (a, b, c) of it, the infinite tet (b, c, a, inf), whose facet
  // 3 = (a, c, b) lists it reversed. Their facets through the infinite vertex are glued by
  // matching vertex sets.
  grow_slots(5);
  nb_slots_ = 5;
  std::fill_n(tets_.begin(), 40, 0u);
  for (std::size_t k = 0; k < 4; ++k) tets_[k] = chosen[k];
  for (std::uint32_t f = 0; f < 4; ++f) {
    std::uint32_t* v = &tets_[8 * static_cast<std::size_t>(f + 1)];
    v[0] = chosen[kFacetVertex[f][1]];
    v[1] = chosen[kFacetVertex[f][2]];
    v[2] = chosen[kFacetVertex[f][0]];
    v[3] = kInfinite;
    tets_[4 + f] = 4 * (f + 1) + 3;
    v[7] = f;
  }
  for (std::uint32_t t = 1; t < 5; ++t) {
    for (std::uint32_t g = 0; g < 3; ++g) {
      for (std::uint32_t t2 = 1; t2 < 5; ++t2) {
        for (std::uint32_t g2 = 0; g2 < 3 && t2 != t; ++g2) {
          int common = 0;
          for (int x = 0; x < 3; ++x) {
            for (int y = 0; y < 3; ++y) {
              common += tets_[8 * t + static_cast<std::uint32_t>(kFacetVertex[g][x])] ==
                        tets_[8 * t2 + static_cast<std::uint32_t>(kFacetVertex[g2][y])];
            }
          }
          if (common == 3) tets_[8 * t + 4 + g] = 4 * t2 + g2;
        }
      }
    }
  }
  initial_[0] = chosen[0];
  initial_[1] = chosen[1];
  initial_[2] = chosen[2];
  initial_[3] = chosen[3];
  return 0;
}

// The points in order; the deferred ones are appended to zone.deferred. The AVX2
// insphere determinant is bit for bit the SSE2 one, so either choice builds the same
// triangulation. (Measured: compiling all of insert for AVX2, inlined into this loop,
// runs fewer instructions but is slower than this baseline code calling the AVX2
// determinant; see bench/RESULTS.md.)
template <bool kZoned>
void Delaunay3::insert_points(Zone& zone, const std::uint32_t* first, const std::uint32_t* last) {
  if constexpr (kZoned) zone.prepare_inside();
  if (avx2_) {
    for (; first != last; ++first) {
      if (insert<kZoned, true>(zone, *first) == Inserted::deferred) {
        zone.deferred.push_back(*first);
      }
    }
  } else {
    for (; first != last; ++first) {
      if (insert<kZoned, false>(zone, *first) == Inserted::deferred) {
        zone.deferred.push_back(*first);
      }
    }
  }
}

void Delaunay3::insert_sequentially(const std::uint32_t* first, const std::uint32_t* last) {
  stats_.sequential_points += static_cast<std::uint32_t>(last - first);
  insert_points<false>(zones_[0], first, last);
}

// A start tet for the zone: the tet holding one of a few of its points (spread over its
// list), found by a sequential walk, if all its finite vertices lie in the zone. False when none is
// found (then the zone's points are deferred).
bool Delaunay3::start_zone(Zone& zone) {
  constexpr std::size_t kTries = 16;
  std::uint32_t t = zones_[0].hint;
  const std::size_t size = zone.points.size();
  for (std::size_t i = 0; i < size && i < kTries; ++i) {
    walk<false>(zones_[0], point(zone.points[i * size / kTries]), t);
    bool inside = true;
    for (std::size_t k = 0; k < 4 && inside; ++k) {
      const std::uint32_t v = tets_[8 * static_cast<std::size_t>(t) + k];
      inside = v == kInfinite || zone.contains(point(v));
    }
    if (inside) {
      zone.hint = t;
      return true;
    }
  }
  return false;
}

namespace {

// Splits `points` (in insertion order) by count into nb boxes of the given frame, kd-style:
// each split is at a quantile of the longest axis of the points' bounding box, the lower
// part getting floor(nb / 2) / nb of them. Writes each zone's box and its points, in their
// original order.
template <class ZoneT, class PointOf>
void split_zones(const std::vector<std::uint32_t>& points, ZoneT* zones, std::size_t nb,
                 const double* lo, const double* hi, int frame, const PointOf& point_of,
                 std::vector<double>& scratch) {
  const auto coordinates = [&point_of, frame](std::uint32_t p, double* u) {
    ZoneT::frame_coordinates(frame, point_of(p), u);
  };
  if (nb == 1) {
    ZoneT& z = zones[0];
    z.frame = frame;
    z.along_curve = false;
    std::copy_n(lo, 3, z.lo);
    std::copy_n(hi, 3, z.hi);
    z.points = points;
    return;
  }
  double box_lo[3] = {0, 0, 0}, box_hi[3] = {0, 0, 0};
  for (std::size_t i = 0; i < points.size(); ++i) {
    double u[3];
    coordinates(points[i], u);
    for (int a = 0; a < 3; ++a) {
      box_lo[a] = i == 0 ? u[a] : std::min(box_lo[a], u[a]);
      box_hi[a] = i == 0 ? u[a] : std::max(box_hi[a], u[a]);
    }
  }
  int axis = 0;
  for (int a = 1; a < 3; ++a) {
    if (box_hi[a] - box_lo[a] > box_hi[axis] - box_lo[axis]) axis = a;
  }
  const std::size_t nb_low = nb / 2;
  const std::size_t target = points.size() * nb_low / nb;
  double split = box_lo[axis];
  if (target < points.size()) {
    scratch.resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
      double u[3];
      coordinates(points[i], u);
      scratch[i] = u[axis];
    }
    std::nth_element(scratch.begin(), scratch.begin() + static_cast<std::ptrdiff_t>(target),
                     scratch.end());
    split = scratch[target];
  }
  std::vector<std::uint32_t> low, high;
  for (const std::uint32_t p : points) {
    double u[3];
    coordinates(p, u);
    (u[axis] < split ? low : high).push_back(p);
  }
  double low_hi[3] = {hi[0], hi[1], hi[2]}, high_lo[3] = {lo[0], lo[1], lo[2]};
  low_hi[axis] = split;
  high_lo[axis] = split;
  split_zones(low, zones, nb_low, lo, low_hi, frame, point_of, scratch);
  split_zones(high, zones + nb_low, nb - nb_low, high_lo, hi, frame, point_of, scratch);
}

// The number of zones a set of points is split into: a function of its size alone (never
// of the number of threads), so that the construction is the same for any thread count;
// a power of two, so that 2, 4, 8 ... threads share the zones evenly. Two zones from
// two_from points on (a function of per_zone: see the callers).
std::size_t zone_count(std::size_t nb_points, std::size_t per_zone, std::size_t two_from) {
  per_zone = std::max<std::size_t>(per_zone, 1);
  const std::size_t wanted = nb_points / per_zone;
  std::size_t zones = 1;
  while (2 * zones <= wanted && 2 * zones <= kMaxZones) zones *= 2;
  if (zones == 1 && nb_points >= std::max<std::size_t>(two_from, 2)) zones = 2;
  return zones;
}

// Where a BRIO round's first pass takes two zones: from 7/16 per_zone points on (57344 by
// default; the round of 1M / 16 points then runs on two threads), or from 7/256 per_zone
// points on (3584) in a build with no round that large but one of 7/64 per_zone (14336) or
// more, or from 7/1024 per_zone points on (896) in a build whose largest round has 3584 to
// 14335 points; a smaller build is sequential. A build with a round of 57344 keeps its
// smaller ones in the sequential prefix (triangulate), during which the other threads
// split the later rounds into zones and fault in the tet array; zoning rounds 8 and 9 of
// 1M points too was slower on two threads (median of five runs 2.249 s against 2.175 s on
// the 2.0 GHz EPYC host). A mid-size build gets all but its smallest rounds in parallel:
// with 3 10^4 points (rounds of about 15k, 7.5k and 3.7k points in zones) rocker-arm's
// Delaunay phase takes 0.060-0.065 s on two threads instead of 0.074-0.076 s with only the
// 15k round in zones (0.097 s with none); 10^5 uniform points 0.198-0.200 s instead of
// 0.219-0.226 s. The price is the points the zones defer, on one thread: 10^5 points
// 0.331 -> 0.335-0.338 s, rocker-arm's phase 0.098-0.100 -> 0.102-0.105 s. Builds of 10^4
// points (largest round about 5k) were sequential, since zoning their 5k round took their
// one-thread time from 0.029 to 0.031 s; but mesh3d's CVT builds one per evaluation, about
// 75 at 10^4 sites, a quarter of its CPU time on one thread while the other waits. Zoned
// from 896 points (session 33, `voroclip --threads T cvt3d bunny.obj --random N
// --iterations 40 --tolerance 0`, the same energies): on two threads 10^4 sites 1.43 ->
// 1.29-1.30 s, 1.4 10^4 sites 1.82-1.83 -> 1.61-1.64 s (6,000 sites, largest round 3k:
// unchanged); on one thread 10^4 sites 1.85-1.86 -> 1.94 s. A function of the round sizes
// alone.
std::size_t first_pass_two_from(const std::vector<std::uint32_t>& round_starts,
                                std::size_t per_zone) {
  const std::size_t large = (7 * per_zone + 15) / 16;
  const std::size_t mid = (7 * per_zone + 63) / 64;
  std::size_t largest = 0;
  for (std::size_t r = 0; r + 1 < round_starts.size(); ++r) {
    largest = std::max<std::size_t>(largest, round_starts[r + 1] - round_starts[r]);
  }
  if (largest >= large) return large;
  const std::size_t small = (7 * per_zone + 255) / 256;
  if (largest >= mid) return small;
  return largest >= small ? (7 * per_zone + 1023) / 1024 : mid;
}

}  // namespace

// The first level of a round's Hilbert curve: a BRIO round comes in the order of the
// Hilbert curve over its bounding box (brio_order), which visits the box's halves,
// quarters and octants about its midpoint one after the other (halves across the longest
// axis, quarters across the two longest, then octants: hilbert_axes3). Two, four or eight
// zones made of those boxes (unbounded on their outer sides) get their points in the
// round's order, already along a Hilbert curve of each zone: no split and no sort, where
// split_zones and a sort per zone took about 0.1 s of the one-thread time at 10^6 uniform
// points. Only when the zones are balanced (every one within 2 % of the mean count: with
// two zones on two threads the larger sets the pace, and 3.7k-15k points of rocker-arm's
// sites split 10 % apart made its two-thread build 4 % slower); otherwise false, nothing
// done (the kd split by count adapts to any distribution). A function of the points alone.
bool Delaunay3::split_along_curve(const std::vector<std::uint32_t>& points, std::size_t nb_zones,
                                  Zone* zones) const {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const int axes = nb_zones == 2 ? 1 : nb_zones == 4 ? 2 : nb_zones == 8 ? 3 : 0;
  if (axes == 0 || points.empty()) return false;
  // The box of the curve: the round's, or under `presorted` the box of all the points.
  double lo[3], hi[3], mid[3];
  if (options_.presorted) {
    std::copy_n(box_lo_, 3, lo);
    std::copy_n(box_hi_, 3, hi);
  } else {
    for (int a = 0; a < 3; ++a) lo[a] = hi[a] = point(points[0])[a];
    for (const std::uint32_t v : points) {
      const double* p = point(v);
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], p[a]);
        hi[a] = std::max(hi[a], p[a]);
      }
    }
  }
  for (int a = 0; a < 3; ++a) mid[a] = lo[a] + 0.5 * (hi[a] - lo[a]);
  int order[3];  // the curve's axes (hilbert_sort's, from the same box)
  detail::hilbert_axes3(lo, hi, order);
  // The zone of each octant (its bits on the curve's axes, order[0] first): the curve's
  // first digit (the octant's rank along the curve) without the unsplit axes' bits, which
  // do not change it. A point's octant is Zone::contains's test, on the same planes.
  std::uint32_t zone_of_octant[8];
  for (std::uint32_t octant = 0; octant < 8; ++octant) {
    const auto digit = static_cast<std::uint32_t>(
        detail::hilbert_index3(octant >> 2 & 1u, octant >> 1 & 1u, octant & 1u, 1));
    zone_of_octant[octant] = digit >> (3 - axes);
  }
  const auto zone_of = [&](const double* p) {
    std::uint32_t octant = 0;
    for (int i = 0; i < axes; ++i) octant |= (p[order[i]] >= mid[order[i]] ? 4u : 0u) >> i;
    return zone_of_octant[octant];
  };
  std::uint32_t count[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  for (const std::uint32_t v : points) ++count[zone_of(point(v))];
  const std::size_t mean = points.size() / nb_zones;
  for (std::size_t k = 0; k < nb_zones; ++k) {
    if (50 * std::size_t{count[k]} < 49 * mean || 50 * std::size_t{count[k]} > 51 * mean) {
      return false;
    }
  }
  // Each zone's box, from one of its octants (the one whose unsplit bits are 0).
  for (std::uint32_t octant = 0; octant < 8; octant += 1u << (3 - axes)) {
    Zone& z = zones[zone_of_octant[octant]];
    z.frame = 0;
    z.along_curve = true;
    for (int a = 0; a < 3; ++a) {
      z.lo[a] = -kInf;
      z.hi[a] = kInf;
    }
    for (int i = 0; i < axes; ++i) {
      (((octant << i) & 4u) != 0 ? z.lo : z.hi)[order[i]] = mid[order[i]];
    }
  }
  for (std::size_t k = 0; k < nb_zones; ++k) {
    zones[k].points.clear();
    zones[k].points.reserve(count[k]);
  }
  for (const std::uint32_t v : points) zones[zone_of(point(v))].points.push_back(v);
#ifndef NDEBUG
  for (std::size_t k = 0; k < nb_zones; ++k) {
    for (const std::uint32_t v : zones[k].points) assert(zones[k].contains(point(v)));
  }
#endif
  return true;
}

// Inserts `points` (ranks in insertion order) by nb_zones tasks, each in its zone; a
// second pass, with zones in the skew frame, takes the points the first deferred, and the
// rest is inserted sequentially. See "Threads" in the header.
// Splits `points` into the boxes of zones[0, nb_zones) in `frame`, each zone's points along
// the Hilbert curve of its box (the round's curve leaves and re-enters a box: consecutive
// points of a zone would be far apart there). A function of the points alone: the first
// pass's zones of a round can be computed ahead (triangulate).
void Delaunay3::split_into_zones(const std::vector<std::uint32_t>& points, std::size_t nb_zones,
                                 int frame, Zone* zones) const {
  if (frame == 0 && split_along_curve(points, nb_zones, zones)) return;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const double everywhere_lo[3] = {-kInf, -kInf, -kInf}, everywhere_hi[3] = {kInf, kInf, kInf};
  std::vector<double> scratch;
  split_zones(
      points, zones, nb_zones, everywhere_lo, everywhere_hi, frame,
      [this](std::uint32_t v) { return point(v); }, scratch);
  tbb::parallel_for(std::size_t{0}, nb_zones, [this, zones](std::size_t k) {
    std::vector<std::uint32_t>& p = zones[k].points;
    hilbert_sort(sorted_xyz_.data(), 3, p.data(), p.data() + p.size());
  });
}

void Delaunay3::insert_in_parallel(std::vector<std::uint32_t>& points, std::size_t nb_zones,
                                   std::vector<Zone>* plan) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const double everywhere_lo[3] = {-kInf, -kInf, -kInf}, everywhere_hi[3] = {kInf, kInf, kInf};
  for (int frame = 0; frame < 2 && nb_zones > 1; ++frame) {
    if (zones_.size() < nb_zones) zones_.resize(nb_zones);
    Zone& first = zones_[0];
    for (std::size_t k = 1; k < nb_zones; ++k) {
      zones_[k].edge_map.resize(kTableSide * kTableSide);
      zones_[k].local_vertex.assign(kTableSide, kInfinite);  // local id 0 is kInfinite
    }
    // zones_[0] is also the sequential zone: keep its free list and hint aside.
    std::vector<std::uint32_t> free_slots;
    free_slots.swap(first.free);
    const std::uint32_t hint = first.hint;
    const bool planned = frame == 0 && plan != nullptr && plan->size() == nb_zones;
    if (planned) {
      for (std::size_t k = 0; k < nb_zones; ++k) {
        Zone& z = zones_[k];
        Zone& from = (*plan)[k];
        z.frame = from.frame;
        z.along_curve = from.along_curve;
        std::copy_n(from.lo, 3, z.lo);
        std::copy_n(from.hi, 3, z.hi);
        z.points.swap(from.points);
      }
    } else {
      split_into_zones(points, nb_zones, frame, zones_.data());
    }
    // Slots: each zone needs about kSlotsPerPoint per point. It gets a share of the free
    // slots proportional to that, then a fresh range after the used slots for the rest
    // (shrunk to the array's capacity when that is nearly enough: growing copies the
    // array; a zone that runs out defers its remaining points).
    std::vector<std::size_t> need(nb_zones);
    std::size_t total_need = 0;
    for (std::size_t k = 0; k < nb_zones; ++k) {
      need[k] =
          static_cast<std::size_t>(kSlotsPerPoint * static_cast<double>(zones_[k].points.size())) +
          64;
      total_need += need[k];
    }
    std::size_t wanted = 0, dealt = 0, cumulative = 0;
    for (std::size_t k = 0; k < nb_zones; ++k) {
      Zone& z = zones_[k];
      cumulative += need[k];
      const std::size_t until = free_slots.size() * cumulative / total_need;
      z.free.assign(free_slots.begin() + static_cast<std::ptrdiff_t>(dealt),
                    free_slots.begin() + static_cast<std::ptrdiff_t>(until));
      need[k] -= std::min(need[k], until - dealt);
      dealt = until;
      wanted += need[k];
    }
    free_slots.clear();
    const std::size_t capacity = tets_.capacity() / 8;
    const std::size_t room = capacity - std::min<std::size_t>(capacity, nb_slots_);
    double scale = 1.0;
    if (room >= wanted / 2 && room < wanted) {
      scale = static_cast<double>(room) / static_cast<double>(wanted);
    } else if (room < wanted) {
      grow_slots(nb_slots_ + wanted);
    }
    std::size_t next = nb_slots_;
    for (std::size_t k = 0; k < nb_zones; ++k) {
      Zone& z = zones_[k];
      z.deferred.clear();
      z.fresh = static_cast<std::uint32_t>(next);
      next += static_cast<std::size_t>(scale * static_cast<double>(need[k]));
      next = std::min(next, tets_.capacity() / 8);
      z.fresh_end = static_cast<std::uint32_t>(next);
    }
    grow_slots(next);
    const auto end_slots = static_cast<std::uint32_t>(next);
    first.hint = hint;
    std::vector<char> started(nb_zones, 0);
    for (std::size_t k = 0; k < nb_zones; ++k) started[k] = start_zone(zones_[k]) ? 1 : 0;
    nb_slots_ = end_slots;  // the walks' step limit reads it
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, nb_zones, 1),
        [this, &started](const tbb::blocked_range<std::size_t>& range) {
          for (std::size_t k = range.begin(); k != range.end(); ++k) {
            Zone& z = zones_[k];
            if (started[k] == 0) {
              z.deferred = z.points;
              continue;
            }
            insert_points<true>(z, z.points.data(), z.points.data() + z.points.size());
          }
        },
        tbb::simple_partitioner());
    // Unused fresh slots become free; all free slots go back to the sequential zone.
    std::vector<std::uint32_t> deferred;
    for (std::size_t k = 0; k < nb_zones; ++k) {
      Zone& z = zones_[k];
      for (std::uint32_t t = z.fresh; t < z.fresh_end; ++t) {
        tets_[8 * static_cast<std::size_t>(t)] = kFreeVertex;
        tets_[8 * static_cast<std::size_t>(t) + 4] = 0;
        free_slots.push_back(t);
      }
      free_slots.insert(free_slots.end(), z.free.begin(), z.free.end());
      deferred.insert(deferred.end(), z.deferred.begin(), z.deferred.end());
    }
    ++stats_.zoned_passes;
    if (zones_[0].along_curve) ++stats_.curve_zoned_passes;
    stats_.zoned_points += static_cast<std::uint32_t>(points.size());
    stats_.deferred_points += static_cast<std::uint32_t>(deferred.size());
    // A live tet to continue from: the hint of the last zone that started.
    for (std::size_t k = 0; k < nb_zones; ++k) {
      if (started[k] != 0) first.hint = zones_[k].hint;
    }
    first.free.swap(free_slots);
    first.fresh = end_slots;
    first.fresh_end = end_slots;
    first.frame = 0;
    first.along_curve = false;
    std::copy_n(everywhere_lo, 3, first.lo);
    std::copy_n(everywhere_hi, 3, first.hi);
    // Zones of many points that deferred most of them: cavities span the zones (points on
    // a sphere: their tets cross the ball). Zones only waste work then: the rest of the
    // build is sequential. (Uniform points defer under 10% from zones this large.)
    if (frame == 0 && 2 * deferred.size() > points.size() &&
        points.size() >= kLargeZone * nb_zones) {
      zoning_off_ = true;
    }
    std::sort(deferred.begin(), deferred.end());  // back to insertion order
    points.swap(deferred);
    // The points deferred lie near the first pass's zone boundaries, which the skew frame's
    // boundaries cross: fewer points per zone suffice.
    const std::size_t second = options_.points_per_zone / 32;
    nb_zones = zoning_off_ ? 1 : zone_count(points.size(), second, (7 * second + 3) / 4);
  }
  insert_sequentially(points.data(), points.data() + points.size());
}

// Inserts every point (rank) but the initial tet's, round by round: rounds large enough
// in parallel zones, the others sequentially.
void Delaunay3::triangulate(const std::vector<std::uint32_t>& round_starts) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (zones_.empty()) zones_.resize(1);
  {
    Zone& seq = zones_[0];
    seq.frame = 0;
    std::fill_n(seq.lo, 3, -kInf);
    std::fill_n(seq.hi, 3, kInf);
    seq.edge_map.resize(kTableSide * kTableSide);
    seq.local_vertex.assign(kTableSide, kInfinite);  // local id 0 is kInfinite
    seq.free.clear();
    seq.deferred.clear();
    nb_slots_ = 0;
    seq.hint = initial_tetrahedron();
    seq.fresh = nb_slots_;
    seq.fresh_end = static_cast<std::uint32_t>(tets_.size() / 8);
  }
  // The ranks of BRIO round r, without the first tet's vertices (read only: the planning
  // tasks call it concurrently, each with its own `out`).
  const auto round_points = [this, &round_starts](std::size_t r, std::vector<std::uint32_t>& out) {
    out.clear();
    for (std::uint32_t q = round_starts[r]; q < round_starts[r + 1]; ++q) {
      if (q != initial_[0] && q != initial_[1] && q != initial_[2] && q != initial_[3]) {
        out.push_back(q);
      }
    }
  };
  std::vector<std::uint32_t> points;
  zoning_off_ = false;
  zone_plans_.clear();
  const std::size_t nb_rounds = round_starts.size() - 1;
  std::size_t r = 0;
  // The sequential rounds before the first zoned one (the "prefix") leave the other threads
  // idle. Meanwhile they split the later rounds into their first pass's zones (a function
  // of the points alone) and fault in the pages of the tet array the zones will fill (the
  // kernel zeroes a page on the thread that first touches it; on a VM whose host reclaims
  // freed memory, about 0.4 GB/s). The prefix is confined to the slots below slot_limit_ (a
  // point that needs more is deferred to after the prefix), so that no slot is touched by
  // both; the limit depends on the input alone and the pages' contents on nothing, so the
  // result is the same for any number of threads.
  const std::size_t per_zone = options_.points_per_zone;
  const std::size_t two_from = first_pass_two_from(round_starts, per_zone);
  std::size_t first_zoned = 0;
  while (first_zoned < nb_rounds &&
         zone_count(round_starts[first_zoned + 1] - round_starts[first_zoned], per_zone,
                    two_from) == 1) {
    ++first_zoned;
  }
  if (first_zoned < nb_rounds) {
    const std::size_t size = tets_.size() / 8;
    slot_limit_ =
        std::min(size, kPrefixSlotsPerPoint * std::size_t{round_starts[first_zoned]} + 64);
    std::uint32_t* const base = tets_.data();
    const bool prefault = several_threads();
    zones_[0].fresh_end =
        static_cast<std::uint32_t>(std::min<std::size_t>(zones_[0].fresh_end, slot_limit_));
    tbb::parallel_invoke(
        [this, &round_points, &points, first_zoned, &r] {
          for (; r < first_zoned; ++r) {
            round_points(r, points);
            insert_sequentially(points.data(), points.data() + points.size());
            nb_slots_ = std::max(nb_slots_, zones_[0].fresh);
          }
        },
        [base, size, prefault, this, &round_points, first_zoned, nb_rounds, per_zone, two_from] {
          zone_plans_.resize(nb_rounds);
          tbb::parallel_for(first_zoned, nb_rounds, [&](std::size_t pr) {
            std::vector<std::uint32_t> planned;
            round_points(pr, planned);
            const std::size_t nb_zones = zone_count(planned.size(), per_zone, two_from);
            if (nb_zones == 1) return;
            zone_plans_[pr].resize(nb_zones);
            split_into_zones(planned, nb_zones, 0, zone_plans_[pr].data());
          });
          if (prefault) touch_pages(base + 8 * slot_limit_, base + 8 * size);
        });
    slot_limit_ = kMaxTets;
    std::vector<std::uint32_t> deferred;
    deferred.swap(zones_[0].deferred);
    stats_.limited_points = static_cast<std::uint32_t>(deferred.size());
    insert_sequentially(deferred.data(), deferred.data() + deferred.size());
    nb_slots_ = std::max(nb_slots_, zones_[0].fresh);
  }
  for (; r < nb_rounds; ++r) {
    round_points(r, points);
    const std::size_t nb_zones = zoning_off_ ? 1 : zone_count(points.size(), per_zone, two_from);
    if (nb_zones > 1) {
      nb_slots_ = zones_[0].fresh;
      insert_in_parallel(points, nb_zones, r < zone_plans_.size() ? &zone_plans_[r] : nullptr);
      if (r < zone_plans_.size()) std::vector<Zone>().swap(zone_plans_[r]);
    } else {
      insert_sequentially(points.data(), points.data() + points.size());
    }
    nb_slots_ = std::max(nb_slots_, zones_[0].fresh);
  }
  zone_plans_.clear();
}

// AVX2 where the CPU has it, but not on AMD Zen 1 (family 17h, "znver1"): 256-bit
// operations run there as two 128-bit halves and vpermpd as several micro-ops. On a
// 2.0 GHz EPYC of that kind the inlined SSE2 determinant was faster on one thread in 15 of
// 15 alternated pairs (1.3-2.5 % at 10^5 and 10^6 points); on two threads the order of the
// runs, not the code, decided 13 of 16 pairs (bench/RESULTS.md).
bool Delaunay3::automatic_uses_avx2() {
#if defined(VOROCLIP_INSPHERE_DET_AVX2)
  return cpu_has_avx2() && !__builtin_cpu_is("znver1");
#else
  return false;
#endif
}

void Delaunay3::note_memory() { peak_bytes_ = std::max(peak_bytes_, memory_bytes()); }

void Delaunay3::build(const double* xyz, std::uint32_t n) {
  const std::uint32_t bad = finite_bounding_box(xyz, n, 3, box_lo_, box_hi_);
  if (bad < n) {
    const double* p = xyz + 3 * static_cast<std::size_t>(bad);
    std::ostringstream message;
    message << "Delaunay3: point " << bad << " has a non-finite coordinate (" << p[0] << ", "
            << p[1] << ", " << p[2] << ")";
    throw Error(message.str());
  }
  nb_slots_ = 0;
  nb_finite_tets_ = 0;
  nb_unique_ = 0;
  vertex_tet_.clear();
  const detail::HugePageAdvice advice(several_threads());  // (see HugePageAdvice)
  if (n < 4) {
    throw Error("Delaunay3: " + std::to_string(n) + " points; need 4 affinely independent points");
  }
  xyz_ = xyz;
  nb_points_ = n;
  using Simd = Options::InsphereSimd;
  avx2_ = options_.insphere_simd == Simd::avx2
              ? cpu_has_avx2()
              : options_.insphere_simd == Simd::automatic && automatic_uses_avx2();
  peak_bytes_ = 0;
  stats_ = {};
  stats_.avx2 = avx2_;
  filter_ = StaticFilter(box_lo_, box_hi_, 3);
  duplicate_of_.resize(n);
  std::iota(duplicate_of_.begin(), duplicate_of_.end(), 0u);

  std::vector<std::uint32_t> round_starts;
  input_id_ = detail::brio_order(xyz, n, 3, &round_starts, options_.presorted);
  for (int pass = 0; pass < 2; ++pass) {
    if (pass == 1) {
      // Duplicates whose smallest index was not the one inserted first: build again
      // without them, so that every vertex carries the smallest index of its group (the
      // index its symbolic perturbation uses).
      std::vector<std::uint32_t> group_min(n, kInfinite);
      bool relabel = false;
      for (std::uint32_t i = 0; i < n; ++i) {
        const std::uint32_t v = duplicate_of_[i];
        group_min[v] = std::min(group_min[v], i);
        relabel = relabel || group_min[v] < v;
      }
      if (!relabel) break;
      for (std::uint32_t i = 0; i < n; ++i) duplicate_of_[i] = group_min[duplicate_of_[i]];
      std::vector<std::uint32_t> kept;
      kept.reserve(n);
      std::vector<std::uint32_t> starts(1, 0);
      for (std::size_t r = 0; r + 1 < round_starts.size(); ++r) {
        for (std::uint32_t k = round_starts[r]; k < round_starts[r + 1]; ++k) {
          if (duplicate_of_[input_id_[k]] == input_id_[k]) kept.push_back(input_id_[k]);
        }
        starts.push_back(static_cast<std::uint32_t>(kept.size()));
      }
      input_id_.swap(kept);
      round_starts.swap(starts);
    }
    // Internal numbering: rank in the insertion order.
    const auto m = static_cast<std::uint32_t>(input_id_.size());
    reserve_exactly(sorted_xyz_, 3 * static_cast<std::size_t>(m));
    sorted_xyz_.resize(3 * static_cast<std::size_t>(m));
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, m, 16384),
                      [this, xyz](const tbb::blocked_range<std::uint32_t>& range) {
                        for (std::uint32_t v = range.begin(); v != range.end(); ++v) {
                          std::copy_n(xyz + 3 * static_cast<std::size_t>(input_id_[v]), 3,
                                      &sorted_xyz_[3 * static_cast<std::size_t>(v)]);
                        }
                      });
    pts_ = sorted_xyz_.data();
    sos_ids_ = input_id_.data();
    duplicate_internal_.resize(m);
    std::iota(duplicate_internal_.begin(), duplicate_internal_.end(), 0u);
    reserve_exactly(local_id_, m);
    local_id_.assign(m, 0);
    // Uniform random points give about 6.75 tets per point.
    const std::size_t expected = static_cast<std::size_t>(6.8 * static_cast<double>(m)) + 64;
    if (tets_.capacity() < 8 * expected) {
      decltype(tets_)().swap(tets_);
      reserve_exactly(tets_, 8 * expected);
    }
    tets_.resize(8 * expected);
    triangulate(round_starts);
    for (std::uint32_t v = 0; v < m; ++v) {
      duplicate_of_[input_id_[v]] = input_id_[duplicate_internal_[v]];
    }
  }
  for (std::uint32_t i = 0; i < n; ++i) nb_unique_ += duplicate_of_[i] == i ? 1u : 0u;
  note_memory();
  // The construction's copies are not needed any more: free them before renumbering, so
  // that the renumbering's arrays do not add to the peak.
  std::vector<double>().swap(sorted_xyz_);
  std::vector<std::uint32_t>().swap(duplicate_internal_);
  std::vector<std::uint8_t>().swap(local_id_);
  finish();
  note_memory();
  if (options_.check) {
    std::string defect = check_topology();
    if (defect.empty()) defect = check_delaunay();
    if (!defect.empty()) throw Error("Delaunay3: internal check failed: " + defect);
  }
}

// ---------------------------------------------------------------------------------------
// After the construction: the free slots are filled with the last live records (so that
// every slot below nb_tet_slots() is live), ranks become input indices, vertex_tet_ is
// the smallest finite tet of each vertex. All of it depends on the triangulation's arrays
// only, which the construction makes the same for any number of threads.
void Delaunay3::finish() {
  std::vector<std::uint32_t>& free = zones_[0].free;
  std::sort(free.begin(), free.end());
  const auto live = static_cast<std::uint32_t>(nb_slots_ - free.size());
  std::uint32_t mover = nb_slots_;
  for (const std::uint32_t hole : free) {
    if (hole >= live) break;
    do {
      --mover;
    } while (tets_[8 * static_cast<std::size_t>(mover)] == kFreeVertex);
    std::uint32_t* to = &tets_[8 * static_cast<std::size_t>(hole)];
    std::copy_n(&tets_[8 * static_cast<std::size_t>(mover)], 8, to);
    for (std::uint32_t f = 0; f < 4; ++f) {
      const std::uint32_t code = to[4 + f] & kCodeMask;
      std::uint32_t& back = tets_[8 * static_cast<std::size_t>(code / 4) + 4 + code % 4];
      back = (back & ~kCodeMask) | (4 * hole + f);
    }
  }
  nb_slots_ = live;
  tets_.resize(8 * static_cast<std::size_t>(live));
  // Slots [first, last) downwards, ranks to input indices on the way: at_rank[r] ends as
  // the smallest finite tet of the range incident to rank r. Returns the number of finite
  // tets in the range. Indexed by rank, the writes follow the insertion order (nearby slots
  // hold nearby ranks); indexed by input index, after the renumbering, they scatter. At
  // 10^6 uniform points on one thread, renumbering then scanning by input index took
  // 0.052 + 0.105 s; this loop and the scatter to input indices take about 0.08 s.
  const auto scan = [this](std::uint32_t first, std::uint32_t last, std::uint32_t* at_rank) {
    std::uint32_t nb_finite = 0;
    for (std::uint32_t t = last; t-- > first;) {
      std::uint32_t* w = &tets_[8 * static_cast<std::size_t>(t)];
      if (w[3] == kInfinite) {
        for (std::size_t k = 0; k < 3; ++k) w[k] = input_id_[w[k]];
        continue;
      }
      ++nb_finite;
      for (std::size_t k = 0; k < 4; ++k) {
        at_rank[w[k]] = t;
        w[k] = input_id_[w[k]];
      }
    }
    return nb_finite;
  };
  const auto m = static_cast<std::uint32_t>(input_id_.size());
  std::vector<std::uint32_t> at_rank(m, kNoTet);
  vertex_tet_.assign(nb_points_, kNoTet);
  if (several_threads()) {
    // The two halves concurrently, the upper one into a second array; a vertex's smallest
    // tet is in the lower half if it has one there: the same result as one pass.
    std::vector<std::uint32_t> upper(m, kNoTet);
    peak_bytes_ = std::max(peak_bytes_, memory_bytes() + capacity_bytes(at_rank) +
                                            capacity_bytes(upper));  // (the scratch arrays too)
    const std::uint32_t half = live / 2;
    std::uint32_t nb_lower = 0, nb_upper = 0;
    tbb::parallel_invoke([&] { nb_lower = scan(0, half, at_rank.data()); },
                         [&] { nb_upper = scan(half, live, upper.data()); });
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, m, 65536),
                      [this, &at_rank, &upper](const tbb::blocked_range<std::uint32_t>& range) {
                        for (std::uint32_t r = range.begin(); r != range.end(); ++r) {
                          vertex_tet_[input_id_[r]] = at_rank[r] != kNoTet ? at_rank[r] : upper[r];
                        }
                      });
    nb_finite_tets_ = nb_lower + nb_upper;
  } else {
    peak_bytes_ = std::max(peak_bytes_, memory_bytes() + capacity_bytes(at_rank));
    nb_finite_tets_ = scan(0, live, at_rank.data());
    for (std::uint32_t r = 0; r < m; ++r) vertex_tet_[input_id_[r]] = at_rank[r];
  }
  pts_ = xyz_;
  sos_ids_ = nullptr;
}

// ---------------------------------------------------------------------------------------
// Queries

std::uint32_t Delaunay3::any_tet() const {
  if (nb_slots_ == 0) {
    throw Error("Delaunay3: the triangulation is empty (build() has not succeeded)");
  }
  return 0;
}

std::uint32_t Delaunay3::locate(const double* p, std::uint32_t hint) const {
  if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
    throw Error("Delaunay3: the query point has a non-finite coordinate");
  }
  if (hint == kNoTet || hint >= nb_slots_ || is_free(hint)) hint = any_tet();
  return walk_query(p, hint);
}

std::uint32_t Delaunay3::nearest_vertex(const double* p, std::uint32_t hint) const {
  const std::uint32_t t = locate(p, hint);
  const std::uint32_t v = tet_vertex(t, 0);  // never kInfinite, which is vertex 3
  return detail::nearest_on_delaunay_graph(
      v, [this](std::uint32_t w, std::vector<std::uint32_t>& out) { vertex_neighbors(w, out); },
      [this, p](std::uint32_t w, std::uint32_t u) {
        return compare_distance3d(p, point(w), point(u));
      });
}

void Delaunay3::vertex_star(std::uint32_t v, std::vector<std::uint32_t>& star) const {
  // Breadth-first over the tets around v (finite and infinite), through the facets that
  // contain v. Stars are small (about 27 tets for uniform points): a linear search for
  // visited tets beats any set.
  star.clear();
  const std::uint32_t start = vertex_tet_[v];
  if (start == kNoTet) return;
  star.push_back(start);
  for (std::size_t i = 0; i < star.size(); ++i) {
    const std::uint32_t t = star[i];
    for (int f = 0; f < 4; ++f) {
      if (tet_vertex(t, f) == v) continue;  // the facet opposite v does not contain v
      const std::uint32_t n = tet_adjacent(t, f);
      if (std::find(star.begin(), star.end(), n) == star.end()) star.push_back(n);
    }
  }
}

void Delaunay3::vertex_tets(std::uint32_t v, std::vector<std::uint32_t>& out) const {
  vertex_star(v, out);
  out.erase(
      std::remove_if(out.begin(), out.end(), [this](std::uint32_t t) { return is_infinite(t); }),
      out.end());
  std::sort(out.begin(), out.end());
}

void Delaunay3::vertex_neighbors(std::uint32_t v, std::vector<std::uint32_t>& out) const {
  std::vector<std::uint32_t> star;
  vertex_star(v, star);
  out.clear();
  for (const std::uint32_t t : star) {
    for (int k = 0; k < 4; ++k) {
      const std::uint32_t w = tet_vertex(t, k);
      if (w != v && w != kInfinite) out.push_back(w);
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

std::vector<std::uint32_t> Delaunay3::hull_vertices() const {
  std::vector<std::uint32_t> out;
  for (std::uint32_t t = 0; t < nb_slots_; ++t) {
    if (!is_infinite(t)) continue;
    for (int k = 0; k < 3; ++k) out.push_back(tet_vertex(t, k));
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

void Delaunay3::circumcenter(std::uint32_t t, double* out) const {
  // Center = a + (|b'|^2 (c' x d') + |c'|^2 (d' x b') + |d'|^2 (b' x c')) / (2 det), with
  // b' = b - a etc.: floating point, for output and clipping only.
  const double* a = point(tet_vertex(t, 0));
  double b[3], c[3], d[3];
  for (int j = 0; j < 3; ++j) {
    b[j] = point(tet_vertex(t, 1))[j] - a[j];
    c[j] = point(tet_vertex(t, 2))[j] - a[j];
    d[j] = point(tet_vertex(t, 3))[j] - a[j];
  }
  const auto cross = [](const double* x, const double* y, double* r) {
    r[0] = x[1] * y[2] - x[2] * y[1];
    r[1] = x[2] * y[0] - x[0] * y[2];
    r[2] = x[0] * y[1] - x[1] * y[0];
  };
  double cd[3], db[3], bc[3];
  cross(c, d, cd);
  cross(d, b, db);
  cross(b, c, bc);
  const double bb = b[0] * b[0] + b[1] * b[1] + b[2] * b[2];
  const double cc = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
  const double dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
  const double det = b[0] * cd[0] + b[1] * cd[1] + b[2] * cd[2];
  for (int j = 0; j < 3; ++j) out[j] = a[j] + (bb * cd[j] + cc * db[j] + dd * bc[j]) / (2 * det);
}

std::size_t Delaunay3::memory_bytes() const {
  std::size_t bytes = capacity_bytes(tets_) + capacity_bytes(vertex_tet_) +
                      capacity_bytes(duplicate_of_) + capacity_bytes(duplicate_internal_) +
                      capacity_bytes(sorted_xyz_) + capacity_bytes(input_id_) +
                      capacity_bytes(local_id_);
  for (const std::vector<Zone>& plan : zone_plans_) {
    for (const Zone& z : plan) bytes += capacity_bytes(z.points);
  }
  for (const Zone& z : zones_) {
    bytes += capacity_bytes(z.cavity) + capacity_bytes(z.boundary) + capacity_bytes(z.free) +
             capacity_bytes(z.edge_map) + capacity_bytes(z.local_vertex) + capacity_bytes(z.edges) +
             capacity_bytes(z.edge_codes) + capacity_bytes(z.sorted_edges) +
             capacity_bytes(z.points) + capacity_bytes(z.deferred);
  }
  return bytes;
}

// ---------------------------------------------------------------------------------------
// Checks

std::string Delaunay3::check_topology() const {
  std::ostringstream err;
  if (tets_.size() < 8 * static_cast<std::size_t>(nb_slots_)) return "the tet array is too short";
  std::uint32_t facet_a[3], facet_b[3];
  std::uint32_t nb_finite = 0;
  for (std::uint32_t t = 0; t < nb_slots_; ++t) {
    if (is_free(t)) {
      err << "slot " << t << " is free after a build";
      return err.str();
    }
    for (int k = 0; k < 4; ++k) {
      const std::uint32_t v = tet_vertex(t, k);
      if (v == kInfinite) {
        if (k != 3) {
          err << "tet " << t << " has the infinite vertex in position " << k;
          return err.str();
        }
      } else if (v >= nb_points_ || duplicate_of_[v] != v) {
        err << "tet " << t << " has vertex " << v << " which is not a vertex";
        return err.str();
      }
      for (int j = 0; j < k; ++j) {
        if (tet_vertex(t, j) == v) {
          err << "tet " << t << " repeats vertex " << v;
          return err.str();
        }
      }
    }
    nb_finite += is_infinite(t) ? 0 : 1;
    if (!is_infinite(t) &&
        orient3d(point(tet_vertex(t, 0)), point(tet_vertex(t, 1)), point(tet_vertex(t, 2)),
                 point(tet_vertex(t, 3))) != Sign::positive) {
      err << "finite tet " << t << " is not positively oriented";
      return err.str();
    }
    for (int f = 0; f < 4; ++f) {
      const std::uint32_t n = tet_adjacent(t, f);
      const int g = tet_adjacent_facet(t, f);
      if ((tets_[8 * static_cast<std::size_t>(t) + 4] & ~kCodeMask) != 0) {
        err << "tet " << t << " carries a cavity mark";
        return err.str();
      }
      if (n >= nb_slots_) {
        err << "tet " << t << " facet " << f << ": bad neighbour " << n;
        return err.str();
      }
      if (tet_adjacent(n, g) != t || tet_adjacent_facet(n, g) != f) {
        err << "tet " << t << " facet " << f << ": not symmetric";
        return err.str();
      }
      // The shared facet, listed reversed by the neighbour: (a, b, c) vs a rotation of
      // (a, c, b).
      for (int i = 0; i < 3; ++i) {
        facet_a[i] = tet_vertex(t, kFacetVertex[f][i]);
        facet_b[i] = tet_vertex(n, kFacetVertex[g][2 - i]);
      }
      bool match = false;
      for (int r = 0; r < 3 && !match; ++r) {
        std::rotate(facet_b, facet_b + 1, facet_b + 3);
        match = std::equal(facet_a, facet_a + 3, facet_b);
      }
      if (!match) {
        err << "tet " << t << " facet " << f
            << ": the neighbour does not list the same facet reversed";
        return err.str();
      }
    }
  }
  if (nb_finite != nb_finite_tets_) {
    err << nb_finite << " finite tets, nb_finite_tets() = " << nb_finite_tets_;
    return err.str();
  }
  std::vector<std::uint32_t> first(nb_points_, kNoTet);
  for (std::uint32_t t = nb_slots_; t-- > 0;) {
    if (is_infinite(t)) continue;
    for (int k = 0; k < 4; ++k) first[tet_vertex(t, k)] = t;
  }
  std::uint32_t nb_vertices = 0;
  for (std::uint32_t v = 0; v < nb_points_; ++v) {
    if (duplicate_of_[v] != v) {
      if (vertex_tet_[v] != kNoTet) {
        err << "duplicate point " << v << " is a vertex";
        return err.str();
      }
      continue;
    }
    ++nb_vertices;
    if (vertex_tet_[v] != first[v] || first[v] == kNoTet) {
      err << "vertex_tet(" << v << ") = " << vertex_tet_[v]
          << ", not the smallest finite tet incident to it (" << first[v] << ")";
      return err.str();
    }
  }
  if (nb_vertices != nb_unique_) return "nb_unique_points() disagrees with duplicate_of()";
  return {};
}

std::string Delaunay3::check_delaunay() const {
  for (std::uint32_t t = 0; t < nb_slots_; ++t) {
    for (int f = 0; f < 4; ++f) {
      const std::uint32_t n = tet_adjacent(t, f);
      const std::uint32_t opposite = tet_vertex(n, tet_adjacent_facet(t, f));
      if (opposite == kInfinite) continue;  // checked from the infinite tet's side
      if (in_conflict<false>(t, opposite)) {
        return "tet " + std::to_string(t) + " is in conflict with vertex " +
               std::to_string(opposite) + " of its neighbour " + std::to_string(n);
      }
    }
  }
  return {};
}

}  // namespace voroclip
