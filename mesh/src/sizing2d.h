// The sizing field of the 2D mesher (mesh.h, step 1): a target edge length
//     h(x) = min(u(x), f(x)),   f(x) = min_j (s_j + g |x - x_j|),
// with u the uniform part (a constant H, or c rho(x)^(-1/4) for a user density) and f the
// feature part, the lower envelope of cones of slope g (the gradation) over feature
// samples (x_j, s_j) of the boundary.
//
// Evaluation. f is g-Lipschitz, so it is tabulated on a two-level grid: coarse cells of
// side about the cap (the largest size that matters); a coarse cell where f cannot be
// below the cap (f(centre) - g * half-diagonal >= cap) is constant, the others carry a
// sub-grid of nodes with spacing about the smallest f in the cell, interpolated
// bilinearly. Node values are exact envelope values (binned cone search), so the
// interpolant is within g * spacing of f. Queries are a pure function of (x, y): the same
// value from any thread.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "voroclip/clip.h"

namespace voroclip::mesh2d {

struct FeatureSample {
  double x, y, s;
};

// The exact envelope f over bins of samples (used to build the grid, and for estimates).
class ConeEnvelope {
 public:
  ConeEnvelope() = default;
  ConeEnvelope(std::vector<FeatureSample> samples, double gradation, const double* lo,
               const double* hi);
  // min(cap, f(x, y)), exact up to rounding.
  double value(double x, double y, double cap) const;
  bool empty() const { return samples_.empty(); }
  double min_size() const { return min_s_; }
  double gradation() const { return g_; }

 private:
  std::vector<FeatureSample> samples_;  // sorted by bin
  std::vector<std::uint32_t> begin_;    // per bin
  std::vector<double> bin_min_s_;
  double g_ = 1, lo_[2] = {0, 0}, size_ = 1, min_s_ = 0;
  std::uint32_t nx_ = 1, ny_ = 1;
};

class SizingField2 {
 public:
  SizingField2() = default;
  // Tabulates min(cap, f) over the box [lo, hi] (queries outside clamp to it).
  void build(const ConeEnvelope& envelope, double cap, const double* lo, const double* hi);
  // min(cap, f(x, y)) by interpolation.
  double feature(double x, double y) const;
  double cap() const { return cap_; }
  // Nodes of the cells that have them (uniform cells' included, not stored).
  std::uint64_t nb_nodes() const { return nb_nodes_; }
  // The largest node spacing of the cells with nodes (0 when there are none): the
  // interpolant is within gradation * sqrt(2) * spacing of the envelope.
  double max_spacing() const;

  // Coarse-cell data for sampling: cell c spans [x0 + i C, x0 + (i + 1) C) x [...] with
  // c = j nx + i.
  std::uint32_t nb_cells() const { return nx_ * ny_; }
  void cell_box(std::uint32_t c, double* lo, double* hi) const;
  // The smallest value of the tabulated field in cell c (the minimum of a bilinear
  // interpolant is at a node).
  double cell_min(std::uint32_t c) const { return cells_[c].min; }
  // Mean of feature()^-2 over cell c (node average; exact for constant cells).
  double cell_mean_inverse_square(std::uint32_t c) const { return cells_[c].mean_inv2; }

  // A square [x, x + side] x [y, y + side] and the smallest value of feature() on it.
  struct BoundedSquare {
    double x, y, side, min;
  };
  // Appends squares tiling cell c, each with the smallest value of the interpolant on it:
  // the cell itself when it is constant, else its node squares, each split into four while
  // its largest corner value exceeds `ratio` times its smallest (at most `max_depth`
  // times). A bilinear patch, and each square of it, takes its extremes at its corners, so
  // the smallest corner value is the minimum up to the rounding of the evaluation. For a
  // rejection sampler's envelope where cell_min() is far below most of the cell.
  void cell_squares(std::uint32_t c, double ratio, int max_depth,
                    std::vector<BoundedSquare>* out) const;

 private:
  struct Cell {
    std::uint32_t first = 0;  // first node; res == 0: constant cell (value cap)
    std::uint32_t res = 0;    // nodes per side - 1
    double min = 0, mean_inv2 = 0;
  };
  std::vector<Cell> cells_;
  // Per cell: 1 when its nodes are all the cap (f >= cap + reach at its centre, yet
  // (cap + reach) - reach < cap by rounding gave it nodes); they are not stored, and every
  // query gives what they would, in the same operations (two squares of side 1e-4 at
  // (0, 0) and (1, 1) had 4M such cells, 196M nodes: 1.6 GB and 25 s of envelope queries;
  // side 1e-8, 37.7 billion nodes).
  std::vector<std::uint8_t> uniform_;
  std::vector<double> nodes_;
  std::uint64_t nb_nodes_ = 0;
  double lo_[2] = {0, 0}, size_ = 1, cap_ = 1;
  std::uint32_t nx_ = 1, ny_ = 1;
};

}  // namespace voroclip::mesh2d
