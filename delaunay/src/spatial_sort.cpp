// Spatial sort: BRIO rounds, each along a Hilbert curve (see spatial_sort.h).
#include "spatial_sort.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>

#include "voroclip/delaunay.h"

namespace voroclip::detail {

namespace {

// A point copied next to its index: the recursion moves these contiguously instead of
// chasing indices into the coordinate array.
template <int D>
struct Item {
  double c[D];
  std::uint32_t index;
  std::uint32_t rank;  // the position before the recursion (in its padding: no extra bytes)
};

// After the recursion over run[0, size): points with equal coordinates back in the order
// of their ranks, each group on the positions it took (nth_element does not keep the
// order of equal elements, and a caller may want the first of a group of duplicates
// first: ClippedVoronoi3 gives a duplicated site's cell to its first copy in input order).
template <int D>
void keep_order_of_duplicates(std::vector<Item<D>>& run, std::vector<std::uint32_t>& by_point,
                              std::vector<std::uint32_t>& places, std::vector<Item<D>>& group) {
  const auto size = static_cast<std::uint32_t>(run.size());
  by_point.resize(size);
  for (std::uint32_t k = 0; k < size; ++k) by_point[k] = k;
  const auto less = [&run](std::uint32_t a, std::uint32_t b) {
    for (int d = 0; d < D; ++d) {
      if (run[a].c[d] != run[b].c[d]) return run[a].c[d] < run[b].c[d];
    }
    return run[a].rank < run[b].rank;
  };
  std::sort(by_point.begin(), by_point.end(), less);
  for (std::uint32_t g = 0; g < size;) {
    std::uint32_t h = g + 1;
    while (h < size && std::equal(run[by_point[g]].c, run[by_point[g]].c + D, run[by_point[h]].c)) {
      ++h;
    }
    if (h - g > 1) {
      places.assign(by_point.begin() + g, by_point.begin() + h);
      std::sort(places.begin(), places.end());
      group.clear();
      for (std::uint32_t k = g; k < h; ++k) group.push_back(run[by_point[k]]);
      for (std::uint32_t k = 0; k < h - g; ++k) run[places[k]] = group[k];
    }
    g = h;
  }
}

// Splits [first, last) at its middle so that the lower half precedes along `axis`, in
// increasing coordinate order when `up`, decreasing otherwise; returns the middle.
template <int D>
Item<D>* split(Item<D>* first, Item<D>* last, int axis, bool up) {
  if (last - first < 2) return first;
  Item<D>* middle = first + (last - first) / 2;
  if (up) {
    std::nth_element(first, middle, last,
                     [axis](const Item<D>& a, const Item<D>& b) { return a.c[axis] < b.c[axis]; });
  } else {
    std::nth_element(first, middle, last,
                     [axis](const Item<D>& a, const Item<D>& b) { return a.c[axis] > b.c[axis]; });
  }
  return middle;
}

// Sub-ranges at least this long are sorted as parallel tasks: they are disjoint, so the
// result does not depend on the number of threads.
constexpr std::ptrdiff_t kParallelGrain = 8192;

// The Hilbert recursion. `x` is the axis split first; bit a of `up` says whether the
// curve runs in increasing direction along axis a in this cell. The child cells are
// visited in Hilbert order with the axis and the direction flips of the curve's
// standard construction (the reflected/rotated sub-curves).
void hilbert_2(Item<2>* first, Item<2>* last, int x, unsigned up) {
  if (last - first <= 1) return;
  const int y = 1 - x;
  const auto is_up = [up](int a) { return ((up >> a) & 1u) != 0; };
  Item<2>* m0 = first;
  Item<2>* m4 = last;
  Item<2>* m2 = split(m0, m4, x, is_up(x));
  Item<2>* m1 = split(m0, m2, y, is_up(y));
  Item<2>* m3 = split(m2, m4, y, !is_up(y));
  const unsigned flip_xy = up ^ 3u;
  if (last - first >= kParallelGrain) {
    tbb::parallel_invoke([=] { hilbert_2(m0, m1, y, up); }, [=] { hilbert_2(m1, m2, x, up); },
                         [=] { hilbert_2(m2, m3, x, up); }, [=] { hilbert_2(m3, m4, y, flip_xy); });
    return;
  }
  hilbert_2(m0, m1, y, up);
  hilbert_2(m1, m2, x, up);
  hilbert_2(m2, m3, x, up);
  hilbert_2(m3, m4, y, flip_xy);
}

void hilbert_3(Item<3>* first, Item<3>* last, int x, unsigned up) {
  if (last - first <= 1) return;
  const int y = (x + 1) % 3, z = (x + 2) % 3;
  const auto is_up = [up](int a) { return ((up >> a) & 1u) != 0; };
  const auto flip = [up](int a, int b) { return up ^ (1u << a) ^ (1u << b); };
  Item<3>* m0 = first;
  Item<3>* m8 = last;
  Item<3>* m4 = split(m0, m8, x, is_up(x));
  Item<3>* m2 = split(m0, m4, y, is_up(y));
  Item<3>* m1 = split(m0, m2, z, is_up(z));
  Item<3>* m3 = split(m2, m4, z, !is_up(z));
  Item<3>* m6 = split(m4, m8, y, !is_up(y));
  Item<3>* m5 = split(m4, m6, z, is_up(z));
  Item<3>* m7 = split(m6, m8, z, !is_up(z));
  if (last - first >= kParallelGrain) {
    tbb::parallel_invoke(
        [=] { hilbert_3(m0, m1, z, up); }, [=] { hilbert_3(m1, m2, y, up); },
        [=] { hilbert_3(m2, m3, y, up); }, [=] { hilbert_3(m3, m4, x, flip(y, z)); },
        [=] { hilbert_3(m4, m5, x, flip(y, z)); }, [=] { hilbert_3(m5, m6, y, flip(x, y)); },
        [=] { hilbert_3(m6, m7, y, flip(x, y)); }, [=] { hilbert_3(m7, m8, z, flip(z, x)); });
    return;
  }
  hilbert_3(m0, m1, z, up);
  hilbert_3(m1, m2, y, up);
  hilbert_3(m2, m3, y, up);
  hilbert_3(m3, m4, x, flip(y, z));
  hilbert_3(m4, m5, x, flip(y, z));
  hilbert_3(m5, m6, y, flip(x, y));
  hilbert_3(m6, m7, y, flip(x, y));
  hilbert_3(m7, m8, z, flip(z, x));
}

// The bits of x (b <= 16 of them) spread out D apart: bit k moves to bit D k. Interleaving
// the D coordinates' spread bits, x[0] the most significant at each level, makes the index.
template <int D>
std::uint64_t spread(std::uint64_t x) {
  if constexpr (D == 2) {
    x = (x | x << 8) & 0x00ff00ffu;
    x = (x | x << 4) & 0x0f0f0f0fu;
    x = (x | x << 2) & 0x33333333u;
    return (x | x << 1) & 0x55555555u;
  } else {
    x = (x | x << 16) & 0x0000ff0000ffull;
    x = (x | x << 8) & 0x00f00f00f00full;
    x = (x | x << 4) & 0x0c30c30c30c3ull;
    return (x | x << 2) & 0x249249249249ull;
  }
}

// Skilling's transform ("Programming the Hilbert curve", AIP Conf. Proc. 707, 2004): the
// cell coordinates x[0..D) of b bits each become the "transposed" Hilbert index, whose
// bits, interleaved from the most significant down (x[0] first), are the index along the
// curve through the 2^(bD) cells.
template <int D>
std::uint64_t hilbert_key(std::uint32_t x[D], int b) {
  // Branch-free: the branches of the textbook loop depend on the coordinate bits and
  // would mispredict about half the time. m is all ones where bit q of x[i] is set.
  for (int level = b - 1; level > 0; --level) {
    const std::uint32_t p = (1u << level) - 1;
    for (int i = 0; i < D; ++i) {
      const std::uint32_t m = 0u - ((x[i] >> level) & 1u);
      const std::uint32_t t = (x[0] ^ x[i]) & p & ~m;  // exchange when the bit is clear
      x[0] ^= (p & m) | t;                             // invert when it is set
      x[i] ^= t;
    }
  }
  for (int i = 1; i < D; ++i) x[i] ^= x[i - 1];  // Gray encode
  std::uint32_t t = 0;
  for (int level = b - 1; level > 0; --level) {
    t ^= ((1u << level) - 1) & (0u - ((x[D - 1] >> level) & 1u));
  }
  for (int i = 0; i < D; ++i) x[i] ^= t;
  std::uint64_t key = 0;
  for (int i = 0; i < D; ++i) key |= spread<D>(x[i]) << (D - 1 - i);
  return key;
}

// The 2D Hilbert index as a finite-state machine, two levels per table look-up: the same
// index as hilbert_key<2> (tested cell by cell), in about a third of the instructions.
// A state is the symmetry of the square that maps the remaining (lower) bits of the cell
// onto the standard curve: bit 2 swaps x and y, bits 1 and 0 flip x and y (flips first).
// One level reads the transformed bits (rx, ry), emits the digit (3 rx) xor ry and
// composes the state with the curve's turn: when ry = 0, swap, after flipping both axes
// when rx = 1.
struct HilbertTable2 {
  std::uint8_t one[8 * 4];   // [state][x bit, y bit]: digit | next state << 2
  std::uint8_t two[8 * 16];  // [state][x 2 bits, y 2 bits]: 4-bit digits | next state << 4
};

constexpr unsigned hilbert_step2(unsigned state, unsigned xb, unsigned yb, unsigned& digit) {
  xb ^= (state >> 1) & 1u;
  yb ^= state & 1u;
  const unsigned rx = (state & 4u) != 0 ? yb : xb;
  const unsigned ry = (state & 4u) != 0 ? xb : yb;
  digit = (3 * rx) ^ ry;
  if (ry == 0) state = (rx == 1 ? state ^ 3u : state) ^ 4u;
  return state;
}

constexpr HilbertTable2 make_hilbert_table2() {
  HilbertTable2 table{};
  for (unsigned state = 0; state < 8; ++state) {
    for (unsigned q = 0; q < 4; ++q) {
      unsigned digit = 0;
      const unsigned next = hilbert_step2(state, q >> 1, q & 1u, digit);
      table.one[4 * state + q] = static_cast<std::uint8_t>(digit | next << 2);
    }
    for (unsigned q = 0; q < 16; ++q) {
      unsigned high = 0, low = 0;
      const unsigned mid = hilbert_step2(state, (q >> 3) & 1u, (q >> 1) & 1u, high);
      const unsigned next = hilbert_step2(mid, (q >> 2) & 1u, q & 1u, low);
      table.two[16 * state + q] = static_cast<std::uint8_t>(high << 2 | low | next << 4);
    }
  }
  return table;
}

constexpr HilbertTable2 kHilbertTable2 = make_hilbert_table2();

inline std::uint64_t hilbert_key2(std::uint32_t x, std::uint32_t y, int b) {
  unsigned state = 0;
  std::uint64_t key = 0;
  int level = b;
  if ((b & 1) != 0) {
    --level;
    const unsigned e = kHilbertTable2.one[((x >> level) & 1u) << 1 | ((y >> level) & 1u)];
    key = e & 3u;
    state = e >> 2;
  }
  while (level > 0) {
    level -= 2;
    const unsigned e =
        kHilbertTable2.two[16 * state + (((x >> level) & 3u) << 2 | ((y >> level) & 3u))];
    key = key << 4 | (e & 15u);
    state = e >> 4;
  }
  return key;
}

// The 3D Hilbert index as a finite-state machine, one level per table look-up: the same
// index as hilbert_key<3> (tested cell by cell). Skilling's transform maps the bits below
// each level by a signed permutation of the axes (the exchanges and inversions it applies
// to all lower bits), and its final xor adds the parity of the Gray-coded last axis over
// the levels above: a state is (permutation, inversion mask, parity), 6 x 8 x 2 of them.
// transformed y[i] = raw[perm[i]] ^ mask bit i; the level's digit is Gray(y) ^ parity.
struct HilbertTable3 {
  std::uint16_t next[96 * 8];  // [state][x y z bits]: digit | next state << 3
};

constexpr int kAxisPermutations[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2},
                                         {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};

constexpr HilbertTable3 make_hilbert_table3() {
  HilbertTable3 table{};
  for (unsigned state = 0; state < 96; ++state) {
    const unsigned parity = state & 1u;
    const unsigned mask = (state >> 1) & 7u;
    const unsigned perm_index = state >> 4;
    for (unsigned raw = 0; raw < 8; ++raw) {
      int perm[3] = {0, 0, 0};
      unsigned inverted[3] = {0, 0, 0}, y[3] = {0, 0, 0};
      for (int i = 0; i < 3; ++i) {
        perm[i] = kAxisPermutations[perm_index][i];
        inverted[i] = (mask >> i) & 1u;
        y[i] = ((raw >> (2 - perm[i])) & 1u) ^ inverted[i];
      }
      // This level's operations on the lower bits, in Skilling's order.
      for (int i = 0; i < 3; ++i) {
        if (y[i] != 0) {
          inverted[0] ^= 1u;
        } else if (i != 0) {
          const int p0 = perm[0];
          perm[0] = perm[i];
          perm[i] = p0;
          const unsigned m0 = inverted[0];
          inverted[0] = inverted[i];
          inverted[i] = m0;
        }
      }
      const unsigned g0 = y[0], g1 = y[1] ^ y[0], g2 = y[2] ^ y[1] ^ y[0];
      const unsigned digit = ((g0 ^ parity) << 2) | ((g1 ^ parity) << 1) | (g2 ^ parity);
      unsigned next_perm = 0;
      for (unsigned k = 0; k < 6; ++k) {
        if (kAxisPermutations[k][0] == perm[0] && kAxisPermutations[k][1] == perm[1]) {
          next_perm = k;
        }
      }
      const unsigned next =
          next_perm << 4 | (inverted[0] | inverted[1] << 1 | inverted[2] << 2) << 1 | (parity ^ g2);
      table.next[8 * state + raw] = static_cast<std::uint16_t>(digit | next << 3);
    }
  }
  return table;
}

constexpr HilbertTable3 kHilbertTable3 = make_hilbert_table3();

inline std::uint64_t hilbert_key3(std::uint32_t x, std::uint32_t y, std::uint32_t z, int b) {
  unsigned state = 0;
  std::uint64_t key = 0;
  for (int level = b - 1; level >= 0; --level) {
    const unsigned raw = ((x >> level) & 1u) << 2 | ((y >> level) & 1u) << 1 | ((z >> level) & 1u);
    const unsigned e = kHilbertTable3.next[8 * state + raw];
    key = key << 3 | (e & 7u);
    state = e >> 3;
  }
  return key;
}

struct Keyed {
  std::uint64_t key;
  std::uint32_t index;
};

// Stable LSD radix sort by key, 8 bits per pass; passes whose digit is constant are skipped.
// Large arrays go in fixed blocks of kRadixBlock elements (so the same result for any
// number of threads): per pass, each block's counts in parallel, then each block scatters
// from its own offsets (bucket by bucket, blocks in order: stable).
constexpr std::size_t kRadixBlock = std::size_t{1} << 16;

void radix_sort(std::vector<Keyed>& a, std::vector<Keyed>& tmp) {
  const std::size_t n = a.size();
  reserve_advised(tmp, n);
  tmp.resize(n);
  const std::size_t nb_blocks = (n + kRadixBlock - 1) / kRadixBlock;
  if (nb_blocks <= 2) {
    std::vector<std::size_t> count(8 * 256, 0);
    for (const Keyed& k : a) {
      for (int d = 0; d < 8; ++d)
        ++count[static_cast<std::size_t>(256 * d) + ((k.key >> (8 * d)) & 255u)];
    }
    for (int d = 0; d < 8; ++d) {
      std::size_t* c = &count[static_cast<std::size_t>(256 * d)];
      if (*std::max_element(c, c + 256) == n) continue;
      std::size_t sum = 0;
      for (int i = 0; i < 256; ++i) {
        const std::size_t x = c[i];
        c[i] = sum;
        sum += x;
      }
      for (const Keyed& k : a) tmp[c[(k.key >> (8 * d)) & 255u]++] = k;
      a.swap(tmp);
    }
    return;
  }
  // Which digits vary: the bits where some key differs from the first.
  const std::uint64_t first = a[0].key;
  std::vector<std::uint64_t> differ(nb_blocks, 0);
  tbb::parallel_for(std::size_t{0}, nb_blocks, [&](std::size_t b) {
    std::uint64_t x = 0;
    for (std::size_t i = b * kRadixBlock; i < std::min(n, (b + 1) * kRadixBlock); ++i) {
      x |= a[i].key ^ first;
    }
    differ[b] = x;
  });
  std::uint64_t varying = 0;
  for (const std::uint64_t x : differ) varying |= x;
  std::vector<std::size_t> offset(nb_blocks * 256);
  for (int d = 0; d < 8; ++d) {
    const int shift = 8 * d;
    if (((varying >> shift) & 255u) == 0) continue;
    tbb::parallel_for(std::size_t{0}, nb_blocks, [&](std::size_t b) {
      std::size_t* c = &offset[b * 256];
      std::fill_n(c, 256, std::size_t{0});
      for (std::size_t i = b * kRadixBlock; i < std::min(n, (b + 1) * kRadixBlock); ++i) {
        ++c[(a[i].key >> shift) & 255u];
      }
    });
    std::size_t sum = 0;
    for (std::size_t bucket = 0; bucket < 256; ++bucket) {
      for (std::size_t b = 0; b < nb_blocks; ++b) {
        const std::size_t x = offset[b * 256 + bucket];
        offset[b * 256 + bucket] = sum;
        sum += x;
      }
    }
    tbb::parallel_for(std::size_t{0}, nb_blocks, [&](std::size_t b) {
      std::size_t* c = &offset[b * 256];
      for (std::size_t i = b * kRadixBlock; i < std::min(n, (b + 1) * kRadixBlock); ++i) {
        tmp[c[(a[i].key >> shift) & 255u]++] = a[i];
      }
    });
    a.swap(tmp);
  }
}

// Equal keys (points in one grid cell) in runs at least this long are ordered by the
// median-split recursion, which adapts to any clustering.
constexpr std::size_t kRefineRun = 16;

// One round: Hilbert keys on a 2^b grid per axis (b <= 16, at least 64 cells per point)
// over the bounding box of the range,
// radix-sorted; ties in runs of kRefineRun or more are refined by the median
// recursion (all points equal, a cluster far smaller than the box, or a box whose extent
// overflows: then every key is 0 and the median recursion sorts everything).
template <int D>
void hilbert_sort_range(const double* coords, std::uint32_t* first, std::uint32_t* last) {
  const std::size_t count = static_cast<std::size_t>(last - first);
  if (count < 2) return;
  // Enough grid cells that few points share one (at least 64 cells per point), at most
  // 2^16 per axis: the key's cost grows with its bits.
  int bits = 1;
  while (bits < 16 && (std::uint64_t{1} << (D * bits)) < 64 * static_cast<std::uint64_t>(count)) {
    ++bits;
  }
  const double cells = static_cast<double>(1u << bits);
  // The box. (A round's indices are increasing: the coordinates are read in order.)
  const auto at = [coords](std::uint32_t index) {
    return coords + static_cast<std::size_t>(D) * index;
  };
  double lo[D], hi[D], scale[D];
  for (int a = 0; a < D; ++a) lo[a] = hi[a] = at(*first)[a];
  for (std::size_t i = 0; i < count; ++i) {
    const double* p = at(first[i]);
    for (int a = 0; a < D; ++a) {
      lo[a] = std::min(lo[a], p[a]);
      hi[a] = std::max(hi[a], p[a]);
    }
  }
  for (int a = 0; a < D; ++a) {
    const double extent = hi[a] - lo[a];
    scale[a] = extent > 0 && std::isfinite(extent) ? cells / extent : 0.0;
    if (!std::isfinite(scale[a])) scale[a] = 0.0;
  }
  int axes[3] = {0, 1, 2};
  if constexpr (D == 3) hilbert_axes3(lo, hi, axes);
  std::vector<Keyed> keyed, tmp;
  reserve_advised(keyed, count);
  keyed.resize(count);
  // Each key is a function of its point alone: parallel and deterministic.
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, count, 16384),
      [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
          const double* p = at(first[i]);
          std::uint32_t x[D];
          for (int a = 0; a < D; ++a) {
            const double t = (p[a] - lo[a]) * scale[a];
            x[a] = t >= 0 ? (t < cells ? static_cast<std::uint32_t>(t) : (1u << bits) - 1) : 0;
          }
          if constexpr (D == 2) {
            keyed[i] = {hilbert_key2(x[0], x[1], bits), first[i]};
          } else {
            keyed[i] = {hilbert_key3(x[axes[0]], x[axes[1]], x[axes[2]], bits), first[i]};
          }
        }
      });
  radix_sort(keyed, tmp);  // stable: equal keys keep the order of [first, last)
  for (std::size_t i = 0; i < count; ++i) first[i] = keyed[i].index;
  std::vector<Item<D>> run, group;
  std::vector<std::uint32_t> by_point, places;
  for (std::size_t i = 0; i < count;) {
    std::size_t j = i + 1;
    while (j < count && keyed[j].key == keyed[i].key) ++j;
    if (j - i >= kRefineRun) {
      run.resize(j - i);
      for (std::size_t k = i; k < j; ++k) {
        std::copy_n(at(keyed[k].index), D, run[k - i].c);
        run[k - i].index = keyed[k].index;
        run[k - i].rank = static_cast<std::uint32_t>(k - i);
      }
      if constexpr (D == 2) {
        hilbert_2(run.data(), run.data() + run.size(), 0, 3u);
      } else {
        hilbert_3(run.data(), run.data() + run.size(), 0, 7u);
      }
      keep_order_of_duplicates(run, by_point, places, group);
      for (std::size_t k = i; k < j; ++k) first[k] = run[k - i].index;
    }
    i = j;
  }
}

// splitmix64 (Steele, Lea & Flood 2014): a fixed, well-mixed hash of the index.
std::uint64_t mix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

int trailing_ones(std::uint64_t x) {
  int k = 0;
  while ((x & 1u) != 0 && k < 64) {
    x >>= 1;
    ++k;
  }
  return k;
}

double squared_distance(const double* coords, int dim, std::uint32_t a, std::uint32_t b) {
  const double* p = coords + static_cast<std::size_t>(dim) * a;
  const double* q = coords + static_cast<std::size_t>(dim) * b;
  double s = 0;
  for (int k = 0; k < dim; ++k) s += (p[k] - q[k]) * (p[k] - q[k]);
  return s;
}

}  // namespace

std::uint64_t hilbert_index2(std::uint32_t x, std::uint32_t y, int bits) {
  return hilbert_key2(x, y, bits);
}

std::uint64_t hilbert_index2_skilling(std::uint32_t x, std::uint32_t y, int bits) {
  std::uint32_t cell[2] = {x, y};
  return hilbert_key<2>(cell, bits);
}

std::uint64_t hilbert_index3(std::uint32_t x, std::uint32_t y, std::uint32_t z, int bits) {
  return hilbert_key3(x, y, z, bits);
}

std::uint64_t hilbert_index3_skilling(std::uint32_t x, std::uint32_t y, std::uint32_t z, int bits) {
  std::uint32_t cell[3] = {x, y, z};
  return hilbert_key<3>(cell, bits);
}

void hilbert_axes3(const double* lo, const double* hi, int axes[3]) {
  const double extent[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
  axes[0] = 0;
  axes[1] = 1;
  axes[2] = 2;
  // Insertion sort of three by decreasing extent, stable (ties keep the index order).
  for (int i = 1; i < 3; ++i) {
    for (int k = i; k > 0 && extent[axes[k]] > extent[axes[k - 1]]; --k) {
      std::swap(axes[k], axes[k - 1]);
    }
  }
}

std::vector<std::uint32_t> brio_order(const double* coords, std::uint32_t n, int dim,
                                      std::vector<std::uint32_t>* round_starts, bool presorted) {
  std::vector<std::uint32_t> order;
  reserve_advised(order, n);
  order.resize(n);
  if (round_starts != nullptr) round_starts->assign(1, n);
  if (n == 0) return order;
  // Level 0 is the last round (about n/2 points), level L the one before (n/2^(L+1)), up to
  // max_level which takes everything deeper (about n/2^max_level >= kBrioMinRound points).
  int max_level = 0;
  while ((static_cast<std::uint64_t>(n) >> (max_level + 1)) >= kBrioMinRound) ++max_level;
  // Counting sort by round (round r = max_level - level), stable in the index: the levels
  // and the counts of fixed blocks of indices in parallel (the same result for any number
  // of threads), then each block's points scattered from its own offsets.
  const auto nb_levels = static_cast<std::size_t>(max_level) + 1;
  std::vector<std::uint8_t> round_of(n);
  constexpr std::uint32_t kBlock = 65536;
  const std::uint32_t nb_blocks = n / kBlock + (n % kBlock != 0 ? 1 : 0);
  std::vector<std::uint32_t> offset(std::size_t{nb_blocks} * nb_levels, 0);
  tbb::parallel_for(std::uint32_t{0}, nb_blocks, [&](std::uint32_t b) {
    std::uint32_t* count = &offset[std::size_t{b} * nb_levels];
    const auto end = static_cast<std::uint32_t>(std::min<std::uint64_t>(n, (b + 1ull) * kBlock));
    for (std::uint32_t i = b * kBlock; i < end; ++i) {
      const auto r =
          static_cast<std::size_t>(max_level - std::min(trailing_ones(mix(i)), max_level));
      round_of[i] = static_cast<std::uint8_t>(r);
      ++count[r];
    }
  });
  std::vector<std::uint32_t> start(nb_levels + 1, 0);
  for (std::size_t r = 0; r < nb_levels; ++r) {
    std::uint32_t at = start[r];
    for (std::uint32_t b = 0; b < nb_blocks; ++b) {
      const std::uint32_t here = offset[std::size_t{b} * nb_levels + r];
      offset[std::size_t{b} * nb_levels + r] = at;
      at += here;
    }
    start[r + 1] = at;
  }
  tbb::parallel_for(std::uint32_t{0}, nb_blocks, [&](std::uint32_t b) {
    std::uint32_t* fill = &offset[std::size_t{b} * nb_levels];
    const auto end = static_cast<std::uint32_t>(std::min<std::uint64_t>(n, (b + 1ull) * kBlock));
    for (std::uint32_t i = b * kBlock; i < end; ++i) {
      order[fill[round_of[i]]++] = i;
    }
  });
  // The rounds are disjoint: sort them concurrently, then chain them in order.
  const std::size_t nb_rounds = start.size() - 1;
  if (!presorted) {
    tbb::parallel_for(std::size_t{0}, nb_rounds, [&](std::size_t r) {
      std::uint32_t* first = order.data() + start[r];
      std::uint32_t* last = order.data() + start[r + 1];
      if (dim == 2) {
        hilbert_sort_range<2>(coords, first, last);
      } else {
        hilbert_sort_range<3>(coords, first, last);
      }
    });
  }
  // Start each round at the end nearer to where the previous one ended.
  for (std::size_t r = 1; r < nb_rounds; ++r) {
    std::uint32_t* first = order.data() + start[r];
    std::uint32_t* last = order.data() + start[r + 1];
    if (first == last || start[r] == 0) continue;
    const std::uint32_t previous = order[start[r] - 1];
    if (squared_distance(coords, dim, previous, *(last - 1)) <
        squared_distance(coords, dim, previous, *first)) {
      std::reverse(first, last);
    }
  }
  if (round_starts != nullptr) round_starts->assign(start.begin(), start.end());
  return order;
}

}  // namespace voroclip::detail

namespace voroclip {

void hilbert_sort(const double* coords, int dim, std::uint32_t* first, std::uint32_t* last) {
  if (dim == 2) {
    detail::hilbert_sort_range<2>(coords, first, last);
  } else {
    detail::hilbert_sort_range<3>(coords, first, last);
  }
}

std::uint32_t finite_bounding_box(const double* coords, std::uint32_t n, int dim, double* lo,
                                  double* hi) {
  struct Block {
    std::uint32_t bad;
    double lo[3], hi[3];
  };
  constexpr std::uint32_t kBlock = 65536;
  const std::uint32_t nb_blocks = n / kBlock + (n % kBlock != 0 ? 1 : 0);
  const auto d = static_cast<std::size_t>(dim);
  std::vector<Block> blocks(nb_blocks);
  tbb::parallel_for(std::uint32_t{0}, nb_blocks, [&](std::uint32_t b) {
    Block& k = blocks[b];
    const auto end = static_cast<std::uint32_t>(std::min<std::uint64_t>(n, (b + 1ull) * kBlock));
    k.bad = n;
    for (std::size_t a = 0; a < d; ++a)
      k.lo[a] = k.hi[a] = coords[d * (std::size_t{b} * kBlock) + a];
    for (std::uint32_t i = b * kBlock; i < end; ++i) {
      const double* p = coords + d * i;
      bool finite = true;
      for (std::size_t a = 0; a < d; ++a) {
        finite = finite && std::isfinite(p[a]);
        k.lo[a] = std::min(k.lo[a], p[a]);
        k.hi[a] = std::max(k.hi[a], p[a]);
      }
      if (!finite) {
        k.bad = i;
        return;
      }
    }
  });
  for (std::size_t a = 0; a < d && n > 0; ++a) lo[a] = hi[a] = coords[a];
  for (const Block& k : blocks) {
    if (k.bad != n) return k.bad;
    for (std::size_t a = 0; a < d; ++a) {
      lo[a] = std::min(lo[a], k.lo[a]);
      hi[a] = std::max(hi[a], k.hi[a]);
    }
  }
  return n;
}

}  // namespace voroclip
