// Expansion arithmetic; see expansion.h for the representation and the references.
#include "expansion.h"

#include <algorithm>

namespace voroclip::expansion {

namespace {

// Merges e and (+/-)f by increasing magnitude and accumulates with Two-Sum, emitting the
// non-zero round-off terms: Shewchuk's Fast-Expansion-Sum (Thm 13) with zero elimination.
template <bool kNegateF>
int merge_sum(const double* e, int ne, const double* f, int nf, double* h) {
  int i = 0, j = 0, nh = 0;
  auto next = [&]() -> double {
    if (j >= nf || (i < ne && std::fabs(e[i]) < std::fabs(f[j]))) return e[i++];
    return kNegateF ? -f[j++] : f[j++];
  };
  if (ne + nf == 0) return 0;
  double q = next();
  while (i < ne || j < nf) {
    double s, err;
    two_sum(q, next(), s, err);
    if (err != 0) h[nh++] = err;
    q = s;
  }
  if (q != 0) h[nh++] = q;
  return nh;
}

}  // namespace

int expansion_sum(const double* e, int ne, const double* f, int nf, double* h) {
  return merge_sum<false>(e, ne, f, nf, h);
}

int expansion_diff(const double* e, int ne, const double* f, int nf, double* h) {
  return merge_sum<true>(e, ne, f, nf, h);
}

int scale_expansion(const double* e, int ne, double b, double* h) {
  if (ne == 0 || b == 0) return 0;
  int nh = 0;
  double q, hh;
  two_product(e[0], b, q, hh);
  if (hh != 0) h[nh++] = hh;
  for (int i = 1; i < ne; ++i) {
    double p1, p0, sum;
    two_product(e[i], b, p1, p0);
    two_sum(q, p0, sum, hh);
    if (hh != 0) h[nh++] = hh;
    fast_two_sum(p1, sum, q, hh);
    if (hh != 0) h[nh++] = hh;
  }
  if (q != 0) h[nh++] = q;
  return nh;
}

int expansion_product(const double* e, int ne, const double* f, int nf, double* h,
                      double* scratch) {
  if (ne == 0 || nf == 0) return 0;
  double* acc = h;
  double* other = scratch;
  double* term = scratch + 2 * ne * nf;
  int n = scale_expansion(e, ne, f[0], acc);
  for (int j = 1; j < nf; ++j) {
    const int nt = scale_expansion(e, ne, f[j], term);
    n = expansion_sum(acc, n, term, nt, other);
    std::swap(acc, other);
  }
  if (acc != h) std::copy(acc, acc + n, h);
  return n;
}

int compress(double* e, int ne) {
  if (ne == 0) return 0;
  // Top-down pass: accumulate from the largest component, keeping the partial sums that
  // left a round-off (they go to the top of the array, above what is still unread).
  int bottom = ne - 1;
  double q = e[bottom];
  for (int i = ne - 2; i >= 0; --i) {
    double sum, small;
    fast_two_sum(q, e[i], sum, small);
    if (small != 0) {
      e[bottom--] = sum;
      q = small;
    } else {
      q = sum;
    }
  }
  // Bottom-up pass over the kept partial sums; writes stay below the read position.
  int top = 0;
  for (int i = bottom + 1; i < ne; ++i) {
    double sum, small;
    fast_two_sum(e[i], q, sum, small);
    if (small != 0) e[top++] = small;
    q = sum;
  }
  e[top++] = q;
  return top;
}

}  // namespace voroclip::expansion
