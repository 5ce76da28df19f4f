// Density2: the density of the 2D cell integrals (see clip.h).
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "voroclip/clip.h"

namespace voroclip {

Density2 Density2::constant(double rho) {
  if (!(rho > 0) || !std::isfinite(rho)) {
    throw Error("density: a constant density must be finite and positive, not " +
                std::to_string(rho));
  }
  Density2 d;
  d.kind = Kind::kConstant;
  d.value = rho;
  return d;
}

Density2 Density2::function(std::function<double(double, double)> rho) {
  if (!rho) throw Error("density: empty callback");
  Density2 d;
  d.kind = Kind::kCallback;
  d.callback = std::move(rho);
  return d;
}

Density2 Density2::linear_grid(std::uint32_t nx, std::uint32_t ny, const double lo[2],
                               const double hi[2], std::vector<double> values) {
  if (nx < 2 || ny < 2) throw Error("density grid: needs at least 2 x 2 nodes");
  if (values.size() != std::size_t{nx} * ny) {
    throw Error("density grid: expected " + std::to_string(std::size_t{nx} * ny) + " values, got " +
                std::to_string(values.size()));
  }
  if (!(lo[0] < hi[0]) || !(lo[1] < hi[1]) || !std::isfinite(lo[0]) || !std::isfinite(lo[1]) ||
      !std::isfinite(hi[0]) || !std::isfinite(hi[1])) {
    throw Error("density grid: the box must be finite with lo < hi");
  }
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (!(values[k] >= 0) || !std::isfinite(values[k])) {
      throw Error("density grid: value " + std::to_string(k) +
                  " is negative or not finite: " + std::to_string(values[k]));
    }
  }
  Density2 d;
  d.kind = Kind::kGrid;
  d.nx = nx;
  d.ny = ny;
  d.lo[0] = lo[0];
  d.lo[1] = lo[1];
  d.hi[0] = hi[0];
  d.hi[1] = hi[1];
  d.grid = std::move(values);
  return d;
}

double Density2::operator()(double x, double y) const {
  switch (kind) {
    case Kind::kConstant:
      return value;
    case Kind::kCallback:
      return callback(x, y);
    case Kind::kGrid:
      break;
  }
  // Grid coordinates, clamped to the grid; square (i, j) split along the diagonal from
  // node (i, j) to node (i + 1, j + 1): the lower triangle has u >= v, the upper u < v.
  const double gx = (x - lo[0]) / (hi[0] - lo[0]) * (nx - 1);
  const double gy = (y - lo[1]) / (hi[1] - lo[1]) * (ny - 1);
  const double cx = std::clamp(gx, 0.0, static_cast<double>(nx - 1));
  const double cy = std::clamp(gy, 0.0, static_cast<double>(ny - 1));
  const std::uint32_t i = std::min(static_cast<std::uint32_t>(cx), nx - 2);
  const std::uint32_t j = std::min(static_cast<std::uint32_t>(cy), ny - 2);
  const double u = cx - i, v = cy - j;
  const auto at = [&](std::uint32_t a, std::uint32_t b) { return grid[std::size_t{b} * nx + a]; };
  const double f00 = at(i, j), f11 = at(i + 1, j + 1);
  if (u >= v) return f00 + u * (at(i + 1, j) - f00) + v * (f11 - at(i + 1, j));
  return f00 + v * (at(i, j + 1) - f00) + u * (f11 - at(i, j + 1));
}

}  // namespace voroclip
