// Signed arbitrary-precision integers, just enough to evaluate a predicate's determinant
// exactly when expansion arithmetic cannot (coordinates of one call whose exponents span
// more than the double range allows the products to carry; see exact.h). Slow on purpose
// of simplicity: it runs only for such inputs and for the rare symbolic-perturbation
// minors that involve the lifted coordinate.
#pragma once

#include <cstdint>
#include <vector>

namespace voroclip::detail {

class BigInt {
 public:
  BigInt() = default;
  // The integer x * 2^-shift, where x is a finite double that is an integer multiple of
  // 2^shift (checked by the caller: shift <= the exponent of x's lowest set bit).
  static BigInt from_scaled_double(double x, int shift);

  int sign() const { return mag_.empty() ? 0 : (negative_ ? -1 : 1); }
  // The value as m * 2^exponent, m a double of at most 64 significant bits' magnitude
  // (2^63 <= |m| < 2^64 for a value of that size or more), within an ulp of m (its top 64
  // bits, rounded to a double): for quotients of huge or tiny values that no double holds.
  double approx(int& exponent) const;

  friend BigInt operator+(const BigInt& a, const BigInt& b);
  friend BigInt operator-(const BigInt& a, const BigInt& b);
  friend BigInt operator*(const BigInt& a, const BigInt& b);

 private:
  bool negative_ = false;
  std::vector<std::uint32_t> mag_;  // little-endian base 2^32, no leading zero limbs

  static BigInt add_signed(const BigInt& a, const BigInt& b, bool negate_b);
  void trim();
};

// A finite non-zero double as +/- mantissa * 2^exponent with an odd mantissa (< 2^53).
struct DecodedDouble {
  std::uint64_t mantissa;
  int exponent;
};
DecodedDouble decode_double(double x);

// The exponent of the lowest set bit of a finite non-zero double: x is an odd integer
// times 2^lowest_bit_exponent(x).
int lowest_bit_exponent(double x);

// floor(log2(|x|)) for a finite non-zero double.
int highest_bit_exponent(double x);

}  // namespace voroclip::detail
