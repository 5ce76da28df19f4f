// The 2D mesher's sizing field (sizing2d.h): the cone envelope over feature samples and its
// two-level tabulation.
#include "sizing2d.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace voroclip::mesh2d {

namespace {

std::uint32_t clamp_index(double t, std::uint32_t n) {
  if (!(t > 0)) return 0;
  if (t >= static_cast<double>(n - 1)) return n - 1;
  return static_cast<std::uint32_t>(t);
}

}  // namespace

ConeEnvelope::ConeEnvelope(std::vector<FeatureSample> samples, double gradation, const double* lo,
                           const double* hi)
    : g_(gradation) {
  lo_[0] = lo[0];
  lo_[1] = lo[1];
  const double w = hi[0] - lo[0], h = hi[1] - lo[1];
  const double bins = std::max(1.0, static_cast<double>(samples.size()) / 4);
  size_ = std::sqrt(std::max(w * h, 1e-300) / bins);
  size_ = std::max({size_, w / 2048, h / 2048});
  if (!(size_ > 0) || !std::isfinite(size_)) size_ = 1;
  nx_ = static_cast<std::uint32_t>(std::min(2048.0, std::floor(w / size_) + 1));
  ny_ = static_cast<std::uint32_t>(std::min(2048.0, std::floor(h / size_) + 1));
  const std::size_t nb = std::size_t{nx_} * ny_;
  std::vector<std::uint32_t> bin_of(samples.size());
  begin_.assign(nb + 1, 0);
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const std::uint32_t i = clamp_index(std::floor((samples[k].x - lo_[0]) / size_), nx_);
    const std::uint32_t j = clamp_index(std::floor((samples[k].y - lo_[1]) / size_), ny_);
    bin_of[k] = j * nx_ + i;
    ++begin_[bin_of[k] + 1];
  }
  for (std::size_t b = 0; b < nb; ++b) begin_[b + 1] += begin_[b];
  samples_.resize(samples.size());
  std::vector<std::uint32_t> fill(begin_.begin(), begin_.end() - 1);
  bin_min_s_.assign(nb, std::numeric_limits<double>::infinity());
  min_s_ = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < samples.size(); ++k) {
    samples_[fill[bin_of[k]]++] = samples[k];
    bin_min_s_[bin_of[k]] = std::min(bin_min_s_[bin_of[k]], samples[k].s);
    min_s_ = std::min(min_s_, samples[k].s);
  }
}

double ConeEnvelope::value(double x, double y, double cap) const {
  double best = cap;
  if (samples_.empty()) return best;
  const auto ci = static_cast<std::int64_t>(clamp_index(std::floor((x - lo_[0]) / size_), nx_));
  const auto cj = static_cast<std::int64_t>(clamp_index(std::floor((y - lo_[1]) / size_), ny_));
  const std::int64_t rmax = std::max<std::int64_t>(nx_, ny_);
  for (std::int64_t r = 0; r <= rmax; ++r) {
    // Every bin of ring r is at least (r - 1) bins away from (x, y) (x may lie outside the
    // clamped bin's box, which only makes the bound smaller than the true distance).
    if (r > 1 && min_s_ + g_ * static_cast<double>(r - 1) * size_ >= best) break;
    for (std::int64_t j = cj - r; j <= cj + r; ++j) {
      if (j < 0 || j >= ny_) continue;
      const bool full_row = j == cj - r || j == cj + r;
      for (std::int64_t i = ci - r; i <= ci + r; i += full_row ? 1 : 2 * r) {
        if (i >= 0 && i < nx_) {
          const std::size_t b = static_cast<std::size_t>(j) * nx_ + static_cast<std::size_t>(i);
          if (bin_min_s_[b] < best) {
            const double bx0 = lo_[0] + static_cast<double>(i) * size_;
            const double by0 = lo_[1] + static_cast<double>(j) * size_;
            const double dx = std::max({bx0 - x, x - (bx0 + size_), 0.0});
            const double dy = std::max({by0 - y, y - (by0 + size_), 0.0});
            if (bin_min_s_[b] + g_ * std::sqrt(dx * dx + dy * dy) < best) {
              for (std::uint32_t k = begin_[b]; k < begin_[b + 1]; ++k) {
                const FeatureSample& s = samples_[k];
                const double v = s.s + g_ * std::hypot(x - s.x, y - s.y);
                best = std::min(best, v);
              }
            }
          }
        }
        if (r == 0) break;
      }
    }
  }
  return best;
}

void SizingField2::build(const ConeEnvelope& envelope, double cap, const double* lo,
                         const double* hi) {
  cap_ = cap;
  lo_[0] = lo[0];
  lo_[1] = lo[1];
  const double w = hi[0] - lo[0], h = hi[1] - lo[1];
  // Coarse cells of side the cap, at least 16 x 16 of them over the box and at most
  // about 4M.
  size_ = std::min(cap, std::sqrt(std::max(w * h, 0.0) / 256));
  size_ = std::max({size_, std::sqrt(std::max(w * h, 0.0) / 4e6), w / 8192, h / 8192});
  if (!(size_ > 0) || !std::isfinite(size_)) size_ = 1;
  nx_ = static_cast<std::uint32_t>(std::min(8192.0, std::floor(w / size_) + 1));
  ny_ = static_cast<std::uint32_t>(std::min(8192.0, std::floor(h / size_) + 1));
  cells_.assign(std::size_t{nx_} * ny_, Cell{});
  uniform_.assign(cells_.size(), 0);
  const double half_diagonal = size_ * std::sqrt(0.5);
  // Pass 1: which cells need nodes, and how many.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells_.size()),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t c = range.begin(); c != range.end(); ++c) {
                        Cell& cell = cells_[c];
                        cell.min = cap;
                        cell.mean_inv2 = 1 / (cap * cap);
                        if (envelope.empty()) continue;
                        const double x = lo_[0] + (static_cast<double>(c % nx_) + 0.5) * size_;
                        const double y = lo_[1] + (static_cast<double>(c / nx_) + 0.5) * size_;
                        const double reach = envelope.gradation() * half_diagonal;
                        const double v = envelope.value(x, y, cap + reach);
                        if (v - reach >= cap) continue;
                        // No sample below cap + reach (v is that cap): f >= cap on the
                        // cell (up to the rounding of the cone values), every node would
                        // be the cap, and the test above failed by rounding alone
                        // ((cap + reach) - reach < cap, about one cell in two).
                        uniform_[c] = !(v < cap + reach);
                        const double low = std::max(v - reach, envelope.min_size());
                        const double res = std::ceil(size_ / std::max(low, 1e-300));
                        cell.res = static_cast<std::uint32_t>(std::clamp(res, 1.0, 96.0));
                      }
                    });
  std::uint64_t total = 0;
  nb_nodes_ = 0;
  for (std::size_t c = 0; c < cells_.size(); ++c) {
    Cell& cell = cells_[c];
    if (cell.res == 0) continue;
    const std::uint64_t count = std::uint64_t{cell.res + 1} * (cell.res + 1);
    nb_nodes_ += count;
    if (uniform_[c]) continue;
    cell.first = static_cast<std::uint32_t>(total);
    total += count;
  }
  nodes_.assign(total, cap);
  // The mean of 1 / cap^2 over the (res + 1)^2 nodes of a uniform cell, summed as pass 2
  // sums a cell's nodes (the same bits), once per resolution.
  std::vector<double> uniform_mean(97, 0.0);
  for (std::size_t c = 0; c < cells_.size(); ++c) {
    const std::uint32_t res = cells_[c].res;
    if (!uniform_[c] || uniform_mean[res] != 0) continue;
    double inv2 = 0;
    for (std::uint64_t k = 0; k < std::uint64_t{res + 1} * (res + 1); ++k) inv2 += 1 / (cap * cap);
    uniform_mean[res] = inv2 / ((res + 1.0) * (res + 1.0));
  }
  // Pass 2: node values.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells_.size()),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t c = range.begin(); c != range.end(); ++c) {
                        Cell& cell = cells_[c];
                        if (cell.res == 0) continue;
                        if (uniform_[c]) {
                          cell.min = cap;
                          cell.mean_inv2 = uniform_mean[cell.res];
                          continue;
                        }
                        const double x0 = lo_[0] + static_cast<double>(c % nx_) * size_;
                        const double y0 = lo_[1] + static_cast<double>(c / nx_) * size_;
                        const double step = size_ / cell.res;
                        double mn = cap, inv2 = 0;
                        for (std::uint32_t b = 0; b <= cell.res; ++b) {
                          for (std::uint32_t a = 0; a <= cell.res; ++a) {
                            const double v = envelope.value(x0 + a * step, y0 + b * step, cap);
                            nodes_[cell.first + b * (cell.res + 1) + a] = v;
                            mn = std::min(mn, v);
                            inv2 += 1 / (v * v);
                          }
                        }
                        cell.min = mn;
                        cell.mean_inv2 = inv2 / ((cell.res + 1.0) * (cell.res + 1.0));
                      }
                    });
}

double SizingField2::feature(double x, double y) const {
  const double tx = (x - lo_[0]) / size_, ty = (y - lo_[1]) / size_;
  const std::uint32_t i = clamp_index(std::floor(tx), nx_);
  const std::uint32_t j = clamp_index(std::floor(ty), ny_);
  const Cell& cell = cells_[std::size_t{j} * nx_ + i];
  if (cell.res == 0) return cap_;
  const double u = std::clamp(tx - i, 0.0, 1.0) * cell.res;
  const double v = std::clamp(ty - j, 0.0, 1.0) * cell.res;
  const std::uint32_t a = std::min(static_cast<std::uint32_t>(u), cell.res - 1);
  const std::uint32_t b = std::min(static_cast<std::uint32_t>(v), cell.res - 1);
  const double fu = u - a, fv = v - b;
  if (uniform_[std::size_t{j} * nx_ + i]) {
    // The interpolant of nodes that are all the cap, in the same operations.
    const double c = cap_;
    return (1 - fv) * ((1 - fu) * c + fu * c) + fv * ((1 - fu) * c + fu * c);
  }
  const double* n = &nodes_[cell.first + b * (cell.res + 1) + a];
  const double* m = n + cell.res + 1;
  return (1 - fv) * ((1 - fu) * n[0] + fu * n[1]) + fv * ((1 - fu) * m[0] + fu * m[1]);
}

double SizingField2::max_spacing() const {
  double m = 0;
  for (const Cell& c : cells_) {
    if (c.res > 0) m = std::max(m, size_ / c.res);
  }
  return m;
}

void SizingField2::cell_squares(std::uint32_t c, double ratio, int max_depth,
                                std::vector<BoundedSquare>* out) const {
  double lo[2], hi[2];
  cell_box(c, lo, hi);
  const Cell& cell = cells_[c];
  if (cell.res == 0) {
    out->push_back({lo[0], lo[1], size_, cap_});
    return;
  }
  const double step = size_ / cell.res;
  // A uniform cell's nodes, all the cap.
  std::vector<double> caps;
  if (uniform_[c]) caps.assign(std::size_t{cell.res + 1} * (cell.res + 1), cap_);
  const double* base = uniform_[c] ? caps.data() : &nodes_[cell.first];
  // A square of a node patch: its lower left corner (u, v) in the patch's unit square, its
  // side, its depth.
  struct Part {
    double u, v, side;
    int depth;
  };
  std::vector<Part> stack;
  for (std::uint32_t b = 0; b < cell.res; ++b) {
    for (std::uint32_t a = 0; a < cell.res; ++a) {
      const double* n = base + b * (cell.res + 1) + a;
      const double* m = n + cell.res + 1;
      // feature()'s interpolant on this patch.
      const auto value = [&](double fu, double fv) {
        return (1 - fv) * ((1 - fu) * n[0] + fu * n[1]) + fv * ((1 - fu) * m[0] + fu * m[1]);
      };
      const double x0 = lo[0] + a * step, y0 = lo[1] + b * step;
      stack.push_back({0, 0, 1, 0});
      while (!stack.empty()) {
        const Part q = stack.back();
        stack.pop_back();
        const double corner[4] = {value(q.u, q.v), value(q.u + q.side, q.v),
                                  value(q.u, q.v + q.side), value(q.u + q.side, q.v + q.side)};
        const double mn = std::min({corner[0], corner[1], corner[2], corner[3]});
        const double mx = std::max({corner[0], corner[1], corner[2], corner[3]});
        if (mx > ratio * mn && q.depth < max_depth) {
          const double h = 0.5 * q.side;
          // Pushed in reverse so that the squares come out in (v, u) order.
          stack.push_back({q.u + h, q.v + h, h, q.depth + 1});
          stack.push_back({q.u, q.v + h, h, q.depth + 1});
          stack.push_back({q.u + h, q.v, h, q.depth + 1});
          stack.push_back({q.u, q.v, h, q.depth + 1});
          continue;
        }
        out->push_back({x0 + q.u * step, y0 + q.v * step, q.side * step, mn});
      }
    }
  }
}

void SizingField2::cell_box(std::uint32_t c, double* lo, double* hi) const {
  lo[0] = lo_[0] + static_cast<double>(c % nx_) * size_;
  lo[1] = lo_[1] + static_cast<double>(c / nx_) * size_;
  hi[0] = lo[0] + size_;
  hi[1] = lo[1] + size_;
}

}  // namespace voroclip::mesh2d
