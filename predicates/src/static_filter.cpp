// StaticFilter: box-based constant error bounds (see voroclip/predicates.h).
#include <algorithm>
#include <cmath>
#include <string>

#include "voroclip/core.h"
#include "voroclip/predicates.h"

namespace voroclip {

namespace {

bool within(double x, double lo, double hi) { return x >= lo && x <= hi; }

}  // namespace

StaticFilter::StaticFilter(const double* lo, const double* hi, int dimension) {
  if (dimension != 2 && dimension != 3) {
    throw Error("StaticFilter: dimension must be 2 or 3, got " + std::to_string(dimension));
  }
  double extent[3] = {0, 0, 0};
  for (int j = 0; j < dimension; ++j) {
    if (!std::isfinite(lo[j]) || !std::isfinite(hi[j]) || !(lo[j] <= hi[j])) {
      throw Error("StaticFilter: the box must be finite with lo <= hi on every axis");
    }
    extent[j] = hi[j] - lo[j];  // rounded: bounds every rounded difference of the box
  }
  const double x = extent[0], y = extent[1], z = extent[2];
  const double m = std::max(std::max(x, y), z);
  constexpr double kLo = 0x1p-300, kHi = 0x1p+300;
  if (within(x, kLo, kHi) && within(y, kLo, kHi)) {
    orient2d_ = detail::kOrient2dBound * x * y;
    if (dimension == 3 && within(z, kLo, kHi)) orient3d_ = detail::kOrient3dBound * x * y * z;
  }
  if (dimension == 2 && within(x, 0x1p-200, 0x1p+200) && within(y, 0x1p-200, 0x1p+200)) {
    incircle_ = detail::kIncircleBound * (m * m) * (m * m);
  }
  if (dimension == 3 && within(x, 0x1p-150, 0x1p+150) && within(y, 0x1p-150, 0x1p+150) &&
      within(z, 0x1p-150, 0x1p+150)) {
    insphere_ = detail::kInsphereBound * (m * m) * (m * m) * m;
  }
}

StaticFilter StaticFilter::bounding(const double* coords, std::size_t n, int dimension) {
  if (n == 0) return StaticFilter();
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  const auto dim = static_cast<std::size_t>(dimension);
  for (std::size_t j = 0; j < dim && j < 3; ++j) lo[j] = hi[j] = coords[j];
  for (std::size_t i = 1; i < n; ++i) {
    for (std::size_t j = 0; j < dim && j < 3; ++j) {
      lo[j] = std::min(lo[j], coords[i * dim + j]);
      hi[j] = std::max(hi[j], coords[i * dim + j]);
    }
  }
  return StaticFilter(lo, hi, dimension);
}

}  // namespace voroclip
