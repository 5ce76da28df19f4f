#include "bigint.h"

#include <algorithm>
#include <cstring>

namespace voroclip::detail {

DecodedDouble decode_double(double x) {
  std::uint64_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  const int biased = static_cast<int>((bits >> 52) & 0x7ff);
  std::uint64_t m = bits & ((std::uint64_t{1} << 52) - 1);
  int e = -1074;
  if (biased != 0) {
    m |= std::uint64_t{1} << 52;
    e = biased - 1075;
  }
  const int tz = __builtin_ctzll(m);
  return {m >> tz, e + tz};
}

namespace {

int compare_magnitude(const std::vector<std::uint32_t>& a, const std::vector<std::uint32_t>& b) {
  if (a.size() != b.size()) return a.size() < b.size() ? -1 : 1;
  for (std::size_t i = a.size(); i-- > 0;) {
    if (a[i] != b[i]) return a[i] < b[i] ? -1 : 1;
  }
  return 0;
}

}  // namespace

int lowest_bit_exponent(double x) { return decode_double(x).exponent; }

int highest_bit_exponent(double x) {
  const DecodedDouble d = decode_double(x);
  return d.exponent + 63 - __builtin_clzll(d.mantissa);
}

BigInt BigInt::from_scaled_double(double x, int shift) {
  BigInt r;
  if (x == 0) return r;
  const DecodedDouble d = decode_double(x);
  const int s = d.exponent - shift;  // >= 0 by contract
  const std::size_t limb = static_cast<std::size_t>(s / 32);
  const int bit = s % 32;
  r.mag_.assign(limb + 3, 0);
  const unsigned __int128 v = static_cast<unsigned __int128>(d.mantissa) << bit;
  r.mag_[limb] = static_cast<std::uint32_t>(v);
  r.mag_[limb + 1] = static_cast<std::uint32_t>(v >> 32);
  r.mag_[limb + 2] = static_cast<std::uint32_t>(v >> 64);
  r.negative_ = x < 0;
  r.trim();
  return r;
}

double BigInt::approx(int& exponent) const {
  exponent = 0;
  if (mag_.empty()) return 0;
  // The top (up to) three limbs, shifted so that the highest set bit is bit 63 of `top`;
  // the bits below are dropped (a relative error below 2^-63, then the rounding to a
  // double).
  const std::size_t n = mag_.size();
  unsigned __int128 window = 0;
  const std::size_t take = n < 3 ? n : 3;
  for (std::size_t k = 0; k < take; ++k) window = (window << 32) | mag_[n - 1 - k];
  int width = 0;  // bits in window
  for (unsigned __int128 w = window; w != 0; w >>= 1) ++width;
  const int drop = width > 64 ? width - 64 : 0;
  const auto top = static_cast<std::uint64_t>(window >> drop);
  exponent = static_cast<int>(32 * (n - take)) + drop;
  const double m = static_cast<double>(top);
  return negative_ ? -m : m;
}

void BigInt::trim() {
  while (!mag_.empty() && mag_.back() == 0) mag_.pop_back();
  if (mag_.empty()) negative_ = false;
}

BigInt BigInt::add_signed(const BigInt& a, const BigInt& b, bool negate_b) {
  const bool b_negative = negate_b ? !b.negative_ && !b.mag_.empty() : b.negative_;
  BigInt r;
  if (a.negative_ == b_negative) {
    const auto& big = a.mag_.size() >= b.mag_.size() ? a.mag_ : b.mag_;
    const auto& small = a.mag_.size() >= b.mag_.size() ? b.mag_ : a.mag_;
    r.mag_.resize(big.size() + 1);
    std::uint64_t carry = 0;
    for (std::size_t i = 0; i < big.size(); ++i) {
      carry += std::uint64_t{big[i]} + (i < small.size() ? small[i] : 0u);
      r.mag_[i] = static_cast<std::uint32_t>(carry);
      carry >>= 32;
    }
    r.mag_[big.size()] = static_cast<std::uint32_t>(carry);
    r.negative_ = a.negative_;
  } else {
    const int c = compare_magnitude(a.mag_, b.mag_);
    if (c == 0) return r;
    const auto& big = c > 0 ? a.mag_ : b.mag_;
    const auto& small = c > 0 ? b.mag_ : a.mag_;
    r.mag_.resize(big.size());
    std::int64_t borrow = 0;
    for (std::size_t i = 0; i < big.size(); ++i) {
      std::int64_t d = std::int64_t{big[i]} - (i < small.size() ? small[i] : 0u) - borrow;
      borrow = d < 0 ? 1 : 0;
      if (d < 0) d += std::int64_t{1} << 32;
      r.mag_[i] = static_cast<std::uint32_t>(d);
    }
    r.negative_ = c > 0 ? a.negative_ : b_negative;
  }
  r.trim();
  return r;
}

BigInt operator+(const BigInt& a, const BigInt& b) { return BigInt::add_signed(a, b, false); }
BigInt operator-(const BigInt& a, const BigInt& b) { return BigInt::add_signed(a, b, true); }

BigInt operator*(const BigInt& a, const BigInt& b) {
  BigInt r;
  if (a.mag_.empty() || b.mag_.empty()) return r;
  r.mag_.assign(a.mag_.size() + b.mag_.size(), 0);
  for (std::size_t i = 0; i < a.mag_.size(); ++i) {
    std::uint64_t carry = 0;
    for (std::size_t j = 0; j < b.mag_.size(); ++j) {
      carry += std::uint64_t{a.mag_[i]} * b.mag_[j] + r.mag_[i + j];
      r.mag_[i + j] = static_cast<std::uint32_t>(carry);
      carry >>= 32;
    }
    r.mag_[i + b.mag_.size()] = static_cast<std::uint32_t>(carry);
  }
  r.negative_ = a.negative_ != b.negative_;
  r.trim();
  return r;
}

}  // namespace voroclip::detail
