// A uniform grid of bins over a Domain2's bounding box, each listing the domain edges whose
// bounding box meets it: the spatial filter of the 2D mesher's boundary queries. Bins are
// found by a monotone function of a coordinate, and edge boxes are exact (min/max of the
// endpoints), so a box query never misses an edge whose box meets the query box: the grid
// only filters, decisions stay with the caller's exact predicates.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "voroclip/clip.h"

namespace voroclip::mesh2d {

// Squared distance from p to segment [a, b] and the parameter of the closest point.
inline double segment_distance2(const double* p, const double* a, const double* b,
                                double* t_out = nullptr) {
  const double dx = b[0] - a[0], dy = b[1] - a[1];
  const double l2 = dx * dx + dy * dy;
  double t = l2 > 0 ? ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2 : 0;
  t = std::clamp(t, 0.0, 1.0);
  const double qx = a[0] + t * dx - p[0], qy = a[1] + t * dy - p[1];
  if (t_out) *t_out = t;
  return qx * qx + qy * qy;
}

// True when the closed box [lo, hi] meets the segment [a, b] (exact).
inline bool box_meets_segment(const double* lo, const double* hi, const double* a,
                              const double* b) {
  for (int c = 0; c < 2; ++c) {
    if (std::max(a[c], b[c]) < lo[c] || std::min(a[c], b[c]) > hi[c]) return false;
  }
  const double corners[4][2] = {{lo[0], lo[1]}, {hi[0], lo[1]}, {hi[0], hi[1]}, {lo[0], hi[1]}};
  bool pos = false, neg = false;
  for (const auto& q : corners) {
    const Sign s = orient2d(a, b, q);
    if (s == Sign::zero) return true;
    pos = pos || s == Sign::positive;
    neg = neg || s == Sign::negative;
  }
  return pos && neg;
}

class EdgeGrid2 {
 public:
  explicit EdgeGrid2(const Domain2& domain) : domain_(domain) {
    const double* lo = domain.bbox_lo();
    const double* hi = domain.bbox_hi();
    lo_[0] = lo[0];
    lo_[1] = lo[1];
    const double w = std::max(hi[0] - lo[0], 0.0), h = std::max(hi[1] - lo[1], 0.0);
    // About two edges per bin on average, bins roughly square.
    const double cells = std::max(1.0, 0.5 * domain.nb_edges());
    double size = std::sqrt(std::max(w * h, 1e-300) / cells);
    if (!(size > 0) || !std::isfinite(size)) size = std::max(w, h) > 0 ? std::max(w, h) : 1.0;
    size = std::max(size, std::max(w, h) / 4096);
    size_ = size;
    nx_ = static_cast<std::uint32_t>(std::min(4096.0, std::floor(w / size) + 1));
    ny_ = static_cast<std::uint32_t>(std::min(4096.0, std::floor(h / size) + 1));
    begin_.assign(std::size_t{nx_} * ny_ + 1, 0);
    for (int pass = 0; pass < 2; ++pass) {
      for (std::uint32_t e = 0; e < domain.nb_edges(); ++e) {
        std::uint32_t b[4];
        edge_bins(e, b);
        for (std::uint32_t j = b[1]; j <= b[3]; ++j) {
          for (std::uint32_t i = b[0]; i <= b[2]; ++i) {
            const std::size_t c = std::size_t{j} * nx_ + i;
            if (pass == 0) {
              ++begin_[c + 1];
            } else {
              edges_[fill_[c]++] = e;
            }
          }
        }
      }
      if (pass == 0) {
        for (std::size_t c = 0; c + 1 < begin_.size(); ++c) begin_[c + 1] += begin_[c];
        edges_.resize(begin_.back());
        fill_.assign(begin_.begin(), begin_.end() - 1);
      }
    }
    fill_.clear();
    fill_.shrink_to_fit();
  }

  std::uint32_t bin_x(double x) const { return bin(x, lo_[0], nx_); }
  std::uint32_t bin_y(double y) const { return bin(y, lo_[1], ny_); }

  // Calls f(e) once for every edge whose bounding box may meet [lo, hi] (a superset).
  template <class F>
  void for_each_in_box(const double* lo, const double* hi, F&& f) const {
    const std::uint32_t i0 = bin_x(lo[0]), i1 = bin_x(hi[0]);
    const std::uint32_t j0 = bin_y(lo[1]), j1 = bin_y(hi[1]);
    for (std::uint32_t j = j0; j <= j1; ++j) {
      for (std::uint32_t i = i0; i <= i1; ++i) {
        const std::size_t c = std::size_t{j} * nx_ + i;
        for (std::uint32_t k = begin_[c]; k < begin_[c + 1]; ++k) {
          const std::uint32_t e = edges_[k];
          // Report e only from the first bin of its overlap with the query range.
          std::uint32_t b[4];
          edge_bins(e, b);
          if (i == std::max(i0, b[0]) && j == std::max(j0, b[1])) f(e);
        }
      }
    }
  }

  // The edge e minimising dist2(e), a squared distance from p that is at least the
  // squared distance from p to edge e (+infinity to skip e), ties to the smaller index;
  // returns false when every edge is skipped.
  template <class Dist2>
  bool nearest(const double* p, Dist2&& dist2, std::uint32_t* edge, double* best_d2) const {
    const double inf = std::numeric_limits<double>::infinity();
    double best = inf;
    std::uint32_t best_e = 0;
    const auto ci = static_cast<std::int64_t>(bin_x(p[0]));
    const auto cj = static_cast<std::int64_t>(bin_y(p[1]));
    // Bins of ring r >= 1 are at least (r - 1) bins plus p's distance to the border of
    // its own bin away (zero when p lies outside the grid and was clamped).
    const double fx = (p[0] - lo_[0]) / size_ - static_cast<double>(ci);
    const double fy = (p[1] - lo_[1]) / size_ - static_cast<double>(cj);
    const double margin = std::max(0.0, std::min({fx, 1 - fx, fy, 1 - fy, 1.0})) * size_;
    const std::int64_t rmax = std::max<std::int64_t>(nx_, ny_);
    for (std::int64_t r = 0; r <= rmax; ++r) {
      if (r > 0) {
        const double bound = margin + static_cast<double>(r - 1) * size_;
        if (bound > 0 && bound * bound > best) break;
      }
      for (std::int64_t j = cj - r; j <= cj + r; ++j) {
        if (j < 0 || j >= ny_) continue;
        const bool full_row = j == cj - r || j == cj + r;
        for (std::int64_t i = ci - r; i <= ci + r; i += full_row ? 1 : 2 * r) {
          if (i >= 0 && i < nx_) {
            const std::size_t c = static_cast<std::size_t>(j) * nx_ + static_cast<std::size_t>(i);
            for (std::uint32_t k = begin_[c]; k < begin_[c + 1]; ++k) {
              const std::uint32_t e = edges_[k];
              const double d2 = dist2(e);
              if (d2 < best || (d2 == best && d2 < inf && e < best_e)) {
                best = d2;
                best_e = e;
              }
            }
          }
          if (r == 0) break;
        }
      }
    }
    if (best == inf) return false;
    *edge = best_e;
    *best_d2 = best;
    return true;
  }

 private:
  static std::uint32_t clamp_bin(double t, std::uint32_t n) {
    if (!(t > 0)) return 0;
    if (t >= static_cast<double>(n - 1)) return n - 1;
    return static_cast<std::uint32_t>(t);
  }
  std::uint32_t bin(double x, double lo, std::uint32_t n) const {
    return clamp_bin(std::floor((x - lo) / size_), n);
  }
  void edge_bins(std::uint32_t e, std::uint32_t b[4]) const {
    const double* p = domain_.vertex(e);
    const double* q = domain_.vertex(domain_.next(e));
    b[0] = bin_x(std::min(p[0], q[0]));
    b[1] = bin_y(std::min(p[1], q[1]));
    b[2] = bin_x(std::max(p[0], q[0]));
    b[3] = bin_y(std::max(p[1], q[1]));
  }

  const Domain2& domain_;
  double lo_[2] = {0, 0};
  double size_ = 1;
  std::uint32_t nx_ = 1, ny_ = 1;
  std::vector<std::uint32_t> begin_, edges_, fill_;
};

}  // namespace voroclip::mesh2d
