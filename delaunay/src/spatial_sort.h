// Spatial sort for incremental Delaunay insertion, shared by Delaunay2 and Delaunay3.
//
// brio_order: Biased Randomized Insertion Order (Amenta, Choi & Rote, "Incremental
// constructions con BRIO", SoCG 2003). The points are split into rounds; the last round
// holds about half of the points, the one before it half of the rest, and so on (a
// geometric series), the first round gathering the remainder (at least kBrioMinRound
// points when n allows). Which round a point goes to is a fixed hash of its index
// (splitmix64), so the order is deterministic: no global RNG, no time seed. Rounds, and the
// large cells of the recursion below, are sorted as parallel TBB tasks over disjoint
// ranges, so the result is the same for any number of threads.
// Rounds are inserted smallest first; each one is sorted along a Hilbert curve, and a round
// is reversed when that brings its first point closer to the last point of the round
// before (a reversed Hilbert curve is still one), so the walk from the last inserted point
// stays short across round boundaries.
//
// hilbert_sort: the recursive median-split Hilbert sort (as CGAL's hilbert_sort with the
// median policy, Brönnimann, Devillers et al.): the range is split at the median of the
// current axis (std::nth_element), each half at the median of the next axis, and so on,
// giving 4 (2D) or 8 (3D) cells visited in Hilbert order, each sorted recursively with
// the curve rotated and reflected accordingly. Splitting by count (not by the box middle)
// makes the recursion depth log2(n) whatever the distribution (clusters, duplicates), so
// the cost is O(n log n). Ties are fine: the order is a fixed function of the input.
#pragma once

#include <cstdint>
#include <vector>

namespace voroclip::detail {

// Rounds smaller than this are merged into the first round.
inline constexpr std::uint32_t kBrioMinRound = 64;

// A permutation of [0, n): the insertion order of the n points given as packed
// coordinates (dim = 2 or 3 doubles per point). Coordinates must be finite.
std::vector<std::uint32_t> brio_order(const double* coords, std::uint32_t n, int dim);

// Sorts the point indices [first, last) along a Hilbert curve (one BRIO round).
void hilbert_sort(const double* coords, int dim, std::uint32_t* first, std::uint32_t* last);

}  // namespace voroclip::detail
