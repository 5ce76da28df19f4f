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
// hilbert_sort: each point gets its index along the Hilbert curve through a 2^b x 2^b
// (x 2^b) grid over the bounding box of the range (b <= 16, the smallest giving at least
// 64 cells per point), computed with Skilling's transform
// ("Programming the Hilbert curve", 2004), and the range is radix-sorted by it: O(n).
// Points sharing a grid cell in runs of 16 or more (clusters far smaller than the box, all
// points equal, or extents that overflow) are then ordered by the recursive median-split
// Hilbert sort (as CGAL's hilbert_sort with the median policy: split at the median of one
// axis, each half at the median of the next, ..., visiting the 4 or 8 cells in Hilbert
// order with the sub-curves rotated and reflected), which adapts to any distribution;
// splitting by count keeps its depth at log2(n), so the whole sort is O(n log n) at worst.
// On a 2^k grid spanning its box both orders are exactly the Hilbert curve. The order is
// a fixed function of the coordinates and of the order of [first, last), and points with
// equal coordinates keep their order of [first, last) among themselves.
#pragma once

#include <cstdint>
#include <vector>

#include "voroclip/delaunay.h"  // hilbert_sort, finite_bounding_box

namespace voroclip::detail {

// Rounds smaller than this are merged into the first round.
inline constexpr std::uint32_t kBrioMinRound = 64;

// A permutation of [0, n): the insertion order of the n points given as packed
// coordinates (dim = 2 or 3 doubles per point). Coordinates must be finite. With
// `round_starts`, it receives the position in the order where each round begins, followed
// by n (so round r is [round_starts[r], round_starts[r + 1])).
// With `presorted`, the points are taken to be in a spatial order already (as
// hilbert_sort leaves them): each round keeps their order (a subsequence of a curve is a
// curve through the subset), reversed as above, instead of being sorted again.
std::vector<std::uint32_t> brio_order(const double* coords, std::uint32_t n, int dim,
                                      std::vector<std::uint32_t>* round_starts = nullptr,
                                      bool presorted = false);

// The index of cell (x, y) (coordinates below 2^bits, 1 <= bits <= 16) along the Hilbert
// curve through the 2^bits x 2^bits grid used by the 2D sort (a table-driven state
// machine), and the same index by Skilling's transform, which it equals; the same for cell
// (x, y, z) of the 3D sort's grid.
std::uint64_t hilbert_index2(std::uint32_t x, std::uint32_t y, int bits);
std::uint64_t hilbert_index2_skilling(std::uint32_t x, std::uint32_t y, int bits);
std::uint64_t hilbert_index3(std::uint32_t x, std::uint32_t y, std::uint32_t z, int bits);
std::uint64_t hilbert_index3_skilling(std::uint32_t x, std::uint32_t y, std::uint32_t z, int bits);

// The axes of a 3D box (lo, hi) by decreasing extent, ties by index: the 3D curve over the
// box takes its coordinates in this order (hilbert_index3's x is axes[0]), so that its
// first level splits the longest axis first (the halves, then quarters and octants that
// Delaunay3's zones may take have the smallest interfaces).
void hilbert_axes3(const double* lo, const double* hi, int axes[3]);

}  // namespace voroclip::detail
