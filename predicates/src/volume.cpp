// The exact sign of the volume enclosed by a closed triangle surface (predicates.h,
// surface_volume_sign): the orientation test of Surface3's shells.
//
// Filter. With o the first vertex and the rounded differences a~ = fl(a - o) (each within
// u = 2^-53 relative of the exact one), a triangle's determinant det(a~, b~, c~) evaluated
// as a . (b x c) takes each of its six monomials through at most five roundings, so it is
// within gamma_5 P of det(a~, b~, c~), P the sum of the monomials' magnitudes; and
// det(a~, b~, c~) is within gamma_3 (1 + gamma_3) P of the exact det(a - o, b - o, c - o)
// (each monomial is a product of three factors with relative errors below u). Per
// triangle: within 8.01 u P. The determinants are summed with Neumaier's compensated sum,
// within 2 u |S| + 2 n u^2 sum |det~| of their exact sum, and the P~ in floating point
// (non-negative terms: relative error below (n + 5) u). Hence the exact sum S has the
// sign of the computed S~ when
//   |S~| > 10 u sum P~ + 3 u |S~|
// for any n below 10^12 (the slack covers the rounding of the bound itself). Underflow and
// overflow: the filter runs only when every non-zero difference lies in [2^-300, 2^300].
// For a closed surface sum det(a - o, b - o, c - o) = sum det(a, b, c) for every o (the
// terms with o cancel in pairs across the edges), so when the filter fails the exact
// stage evaluates sum det(a, b, c) on the raw coordinates in big integers, on the common
// binary grid of all of them (exact for every finite input; slow, and needed only for
// surfaces of volume zero or within rounding of it).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "bigint.h"
#include "voroclip/core.h"
#include "voroclip/predicates.h"

namespace voroclip {

namespace {

constexpr double kU = 0x1p-53;
constexpr double kLow = 0x1p-300, kHigh = 0x1p300;

// A compensated (Neumaier) sum.
struct Sum {
  double s = 0, c = 0;
  void add(double x) {
    const double t = s + x;
    c += std::fabs(s) >= std::fabs(x) ? (s - t) + x : (x - t) + s;
    s = t;
  }
  double value() const { return s + c; }
};

bool in_range(double d) {
  const double a = std::fabs(d);
  return a == 0 || (a >= kLow && a <= kHigh);
}

}  // namespace

Sign surface_volume_sign(const double* xyz, const std::uint32_t* triangles, std::size_t n) {
  if (n == 0) return Sign::zero;
  const auto at = [&](std::size_t t, int k) {
    return xyz + 3 * std::size_t{triangles[3 * t + static_cast<std::size_t>(k)]};
  };
  for (std::size_t t = 0; t < n; ++t) {
    for (int k = 0; k < 3; ++k) {
      const double* p = at(t, k);
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
        throw Error("surface_volume_sign: a vertex of triangle " + std::to_string(t) +
                    " has a non-finite coordinate");
      }
    }
  }
  const double* o = at(0, 0);
  Sum total;
  double magnitude = 0;
  bool filtered = true;
  for (std::size_t t = 0; t < n && filtered; ++t) {
    double d[3][3];
    for (int k = 0; k < 3; ++k) {
      const double* p = at(t, k);
      for (int c = 0; c < 3; ++c) {
        d[k][c] = p[c] - o[c];
        filtered = filtered && in_range(d[k][c]);
      }
    }
    const double* a = d[0];
    const double* b = d[1];
    const double* c = d[2];
    const double bc0 = b[1] * c[2] - b[2] * c[1];
    const double bc1 = b[2] * c[0] - b[0] * c[2];
    const double bc2 = b[0] * c[1] - b[1] * c[0];
    total.add((a[0] * bc0 + a[1] * bc1) + a[2] * bc2);
    magnitude += std::fabs(a[0]) * (std::fabs(b[1] * c[2]) + std::fabs(b[2] * c[1])) +
                 std::fabs(a[1]) * (std::fabs(b[2] * c[0]) + std::fabs(b[0] * c[2])) +
                 std::fabs(a[2]) * (std::fabs(b[0] * c[1]) + std::fabs(b[1] * c[0]));
  }
  if (filtered) {
    const double s = total.value();
    if (std::fabs(s) > 10 * kU * magnitude + 3 * kU * std::fabs(s)) {
      return s > 0 ? Sign::positive : Sign::negative;
    }
  }
  // Exact: big integers on the common grid of every coordinate used.
  bool any = false;
  int grid = 0;
  for (std::size_t t = 0; t < n; ++t) {
    for (int k = 0; k < 3; ++k) {
      const double* p = at(t, k);
      for (int c = 0; c < 3; ++c) {
        if (p[c] == 0) continue;
        const int e = detail::lowest_bit_exponent(p[c]);
        grid = any ? std::min(grid, e) : e;
        any = true;
      }
    }
  }
  if (!any) return Sign::zero;
  using detail::BigInt;
  BigInt sum;
  for (std::size_t t = 0; t < n; ++t) {
    BigInt v[3][3];
    for (int k = 0; k < 3; ++k) {
      for (int c = 0; c < 3; ++c) v[k][c] = BigInt::from_scaled_double(at(t, k)[c], grid);
    }
    const BigInt bc0 = v[1][1] * v[2][2] - v[1][2] * v[2][1];
    const BigInt bc1 = v[1][2] * v[2][0] - v[1][0] * v[2][2];
    const BigInt bc2 = v[1][0] * v[2][1] - v[1][1] * v[2][0];
    sum = sum + (v[0][0] * bc0 + v[0][1] * bc1 + v[0][2] * bc2);
  }
  return static_cast<Sign>(sum.sign());
}

}  // namespace voroclip
