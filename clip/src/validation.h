// What the validations of the 3D domains share (domain3.cpp: tet meshes; surface3.cpp:
// closed surfaces): numbers in messages, the first error of a pass, keys bucketed by their
// smallest vertex, compensated sums.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "voroclip/core.h"

namespace voroclip::detail {

// The shortest decimal that reads back as x.
inline std::string number(double x) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof(buf), x);
  return std::string(buf, r.ptr);
}

// "(x, y, z)".
inline std::string point(const double* p) {
  return "(" + number(p[0]) + ", " + number(p[1]) + ", " + number(p[2]) + ")";
}

// The first error found by a pass, keeping the one about the smallest key, so that the
// message does not depend on the order of the work (or the thread count).
struct FirstError {
  std::uint64_t key = ~std::uint64_t{0};
  std::string message;

  bool wants(std::uint64_t k) const { return k < key; }
  void set(std::uint64_t k, std::string m) {
    key = k;
    message = std::move(m);
  }
  void raise() const {
    if (!message.empty()) throw Error(message);
  }
};

// Sorts three indices; returns the parity of the permutation applied (1: odd).
inline std::uint32_t sort3(std::uint32_t& a, std::uint32_t& b, std::uint32_t& c) {
  std::uint32_t parity = 0;
  if (a > b) std::swap(a, b), parity ^= 1u;
  if (b > c) std::swap(b, c), parity ^= 1u;
  if (a > b) std::swap(a, b), parity ^= 1u;
  return parity;
}

// A facet or an edge keyed by its other vertices (hi0, hi1) in the bucket of its smallest
// one; code says where it came from (4 t + f, 3 t + e), parity how it was listed.
struct Keyed {
  std::uint32_t hi0, hi1, code, parity;
};

// Counting sort into buckets (stable in the order of `keys`), then each bucket sorted by
// (hi0, hi1, code) in parallel: the order is unique, whatever the thread count. Returns the
// bucket offsets (nb_buckets + 1); `keys` is reordered in place.
inline std::vector<std::uint32_t> bucket_sort(std::vector<Keyed>& keys,
                                              const std::vector<std::uint32_t>& bucket,
                                              std::uint32_t nb_buckets) {
  std::vector<std::uint32_t> begin(static_cast<std::size_t>(nb_buckets) + 1, 0);
  for (const std::uint32_t b : bucket) ++begin[b + 1];
  for (std::size_t i = 0; i < nb_buckets; ++i) begin[i + 1] += begin[i];
  std::vector<Keyed> sorted(keys.size());
  std::vector<std::uint32_t> pos(begin.begin(), begin.end() - 1);
  for (std::size_t i = 0; i < keys.size(); ++i) sorted[pos[bucket[i]]++] = keys[i];
  keys.swap(sorted);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, nb_buckets, 1024), [&](const auto& r) {
    for (std::uint32_t a = r.begin(); a != r.end(); ++a) {
      std::sort(keys.begin() + begin[a], keys.begin() + begin[a + 1],
                [](const Keyed& x, const Keyed& y) {
                  if (x.hi0 != y.hi0) return x.hi0 < y.hi0;
                  if (x.hi1 != y.hi1) return x.hi1 < y.hi1;
                  return x.code < y.code;
                });
    }
  });
  return begin;
}

// Neumaier's compensated sum, in the order given.
class CompensatedSum {
 public:
  void add(double x) {
    const double t = sum_ + x;
    comp_ += std::fabs(sum_) >= std::fabs(x) ? (sum_ - t) + x : (x - t) + sum_;
    sum_ = t;
  }
  double value() const { return sum_ + comp_; }

 private:
  double sum_ = 0, comp_ = 0;
};

inline double compensated_sum(const std::vector<double>& v) {
  CompensatedSum s;
  for (const double x : v) s.add(x);
  return s.value();
}

}  // namespace voroclip::detail
