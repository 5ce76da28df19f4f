// Polynomials in the symbolic perturbations eps_x of up to five sites ("slots"), with exact
// rational coefficients: the oracle side of the bisector predicate tests
// (test_bisector2d.cpp, test_bisector3d.cpp). The sign of a polynomial is that of its
// dominant monomial when the eps are positive infinitesimals with eps_x >> eps_y for index
// x < y (every power of eps_y is negligible against eps_x): the monomial whose exponent of
// the smallest eps is the smallest, then the next smallest, and so on. sign() also reports
// the total degree of that monomial.
#pragma once

#include <gmpxx.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <map>
#include <utility>

namespace voroclip::test {

using Q = mpq_class;

class EpsPoly {
 public:
  static constexpr int kSlots = 5;
  using Exponents = std::array<int, kSlots>;

  EpsPoly() = default;
  EpsPoly(const Q& c) {  // NOLINT: implicit, constants mix freely with polynomials
    if (sgn(c) != 0) terms_[Exponents{}] = c;
  }
  static EpsPoly eps(int slot) {
    EpsPoly p;
    Exponents e{};
    e[static_cast<std::size_t>(slot)] = 1;
    p.terms_[e] = 1;
    return p;
  }

  friend EpsPoly operator+(const EpsPoly& a, const EpsPoly& b) { return a.combine(b, 1); }
  friend EpsPoly operator-(const EpsPoly& a, const EpsPoly& b) { return a.combine(b, -1); }
  friend EpsPoly operator*(const EpsPoly& a, const EpsPoly& b) {
    EpsPoly r;
    for (const auto& [ea, ca] : a.terms_) {
      for (const auto& [eb, cb] : b.terms_) {
        Exponents e{};
        for (std::size_t s = 0; s < kSlots; ++s) e[s] = ea[s] + eb[s];
        r.terms_[e] += ca * cb;
      }
    }
    r.prune();
    return r;
  }

  Q constant() const {
    const auto it = terms_.find(Exponents{});
    return it == terms_.end() ? Q(0) : it->second;
  }
  // The coefficient of eps_slot (degree 1).
  Q linear(int slot) const {
    Exponents e{};
    e[static_cast<std::size_t>(slot)] = 1;
    const auto it = terms_.find(e);
    return it == terms_.end() ? Q(0) : it->second;
  }
  bool is_constant() const {
    return terms_.empty() || (terms_.size() == 1 && terms_.begin()->first == Exponents{});
  }

  // The sign as the eps tend to 0 (index[s]: the site index of slot s; n slots in use),
  // and the total degree of the deciding monomial (-1 for the zero polynomial).
  int sign(const std::array<std::uint32_t, kSlots>& index, int n, int& degree) const {
    // Slots by increasing index = decreasing eps (insertion sort: n <= 5).
    int by_rank[kSlots] = {0, 1, 2, 3, 4};
    const auto index_of = [&](int slot) { return index[static_cast<std::size_t>(slot)]; };
    for (int r = 1; r < n; ++r) {
      for (int q = r; q > 0 && index_of(by_rank[q]) < index_of(by_rank[q - 1]); --q) {
        std::swap(by_rank[q], by_rank[q - 1]);
      }
    }
    // Exponents of the smallest eps first: the dominant monomial has the smallest key.
    const auto key = [&](const Exponents& e) {
      std::array<int, kSlots> k{};
      for (int r = 0; r < n; ++r) {
        k[static_cast<std::size_t>(r)] = e[static_cast<std::size_t>(by_rank[n - 1 - r])];
      }
      return k;
    };
    const std::pair<const Exponents, Q>* best = nullptr;
    for (const auto& t : terms_) {
      if (best == nullptr || key(t.first) < key(best->first)) best = &t;
    }
    if (best == nullptr) {
      degree = -1;
      return 0;
    }
    degree = 0;
    for (const int x : best->first) degree += x;
    return sgn(best->second);
  }

 private:
  EpsPoly combine(const EpsPoly& b, int s) const {
    EpsPoly r = *this;
    for (const auto& [e, c] : b.terms_) {
      if (s > 0) {
        r.terms_[e] += c;
      } else {
        r.terms_[e] -= c;
      }
    }
    r.prune();
    return r;
  }
  void prune() {
    for (auto it = terms_.begin(); it != terms_.end();) {
      it = sgn(it->second) == 0 ? terms_.erase(it) : std::next(it);
    }
  }

  std::map<Exponents, Q> terms_;
};

}  // namespace voroclip::test
