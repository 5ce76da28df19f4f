// The range of double precision in the CVT (cvt2d.cpp, cvt3d.cpp): gradient norms that
// neither overflow nor underflow, and the checks that the start of an optimisation is
// representable at all.
//
// With coordinates of size L, a site's gradient 2 m (x - c) grows as L^(d+1) and the
// energy as L^(d+2) (d = 2, 3). The squared norm of the gradient left double precision
// (2^-1022 .. 2^1024) from L ~ 2^+-100 in 3D (the gradient in variables scaled by 1/L: L^5,
// squared L^10; the sphere scaled by 1e32 or 1e-35) and 2^+-170 in 2D (L^6), long before
// the energy does (L^5: 2^+-204; L^4: 2^+-255). A norm that overflowed to inf or underflowed
// to 0 made the run "converged" at iteration 0 (inf <= tolerance * inf, 0 <= tolerance * 0).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "voroclip/core.h"

namespace voroclip::cvt_detail {

// True when every component's square, and the sum of the squares, stay normal and finite
// (|g_i| within [2^-400, 2^400]): the plain Euclidean norm is then computed as it always
// was, and its bits are kept.
inline bool norm_in_range(double max_abs) {
  return max_abs == 0 || (max_abs >= 0x1p-400 && max_abs <= 0x1p400);
}

// The power of two 2^-ilogb(max_abs) that brings the largest component to [1, 2); scaling
// by it is exact, and so is the square root of a sum scaled by its square (an even power):
// the norm computed through it is the plain one, bit for bit, where both are representable.
inline int norm_exponent(double max_abs) { return std::ilogb(max_abs); }

// |g|, without overflow or underflow of the squares (Eigen's norm(), same summation order).
inline double euclidean_norm(const Eigen::VectorXd& g) {
  if (g.size() == 0) return 0;
  const double max_abs = g.cwiseAbs().maxCoeff();
  if (!std::isfinite(max_abs) || norm_in_range(max_abs)) return g.norm();
  const int k = norm_exponent(max_abs);
  return std::ldexp((g * std::ldexp(1.0, -k)).norm(), k);
}

// The sum of the squares of the values that for_each(visit) visits, as sum * 4^k (*exponent =
// k): the plain sum (k = 0, its bits kept) when the largest is within range (norm_in_range),
// else the sum of the values scaled by 2^-k, the largest then in [1, 2).
template <class ForEach>
double sum_of_squares(const ForEach& for_each, int* exponent) {
  double max_abs = 0;
  for_each([&](double t) { max_abs = std::max(max_abs, std::fabs(t)); });
  *exponent = std::isfinite(max_abs) && !norm_in_range(max_abs) ? norm_exponent(max_abs) : 0;
  const double f = std::ldexp(1.0, -*exponent);
  double s = 0;
  for_each([&](double t) { s += (t * f) * (t * f); });
  return s;
}

// "2.3e+32": a short number for messages.
inline std::string short_number(double x) {
  if (std::isnan(x)) return "NaN";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

// What to do when the model does not fit double precision: rescale it by a power of two
// (exact) to a size of about 1. `size` is the bounding box's diagonal.
inline std::string rescale_advice(double size) {
  std::string advice = "rescale the model";
  if (std::isfinite(size) && size > 0) {
    advice += " (e.g. multiply its coordinates and the sites by 2^" +
              std::to_string(-std::ilogb(size)) + ", which is exact, for a size of about 1)";
  }
  return advice + " and scale the resulting sites back";
}

// Throws Error when a quantity of the start of an optimisation is not representable: 0,
// subnormal, not finite (`allow_zero`: 0 is a value, as a gradient at a stationary start).
// `where` is "cvt3d: bunny.obj (0.2 across)", `power` the power of the model's size the
// quantity grows as, `size` the bounding box's diagonal.
inline void check_representable(const std::string& where, double size, const std::string& quantity,
                                double value, int power, bool allow_zero = false) {
  const double tiny = std::numeric_limits<double>::min();
  if (std::isfinite(value) && (value >= tiny || (allow_zero && value == 0))) return;
  const bool large = !std::isfinite(value);
  throw Error(where + ": " + quantity + " is " + short_number(value) +
              " in double precision (it grows as the size to the power " + std::to_string(power) +
              "): the coordinates are too " + (large ? "large" : "small") +
              " for a CVT in double precision; " + rescale_advice(size));
}

// "cvt3d: bunny.obj (0.2 across)": the start of the messages above.
inline std::string model_name(const char* what, const std::string& source, double size) {
  return std::string(what) + ": " + (source.empty() ? "the domain" : source) + " (" +
         short_number(size) + " across)";
}

}  // namespace voroclip::cvt_detail
