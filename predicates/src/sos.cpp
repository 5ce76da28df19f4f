// Symbolic perturbation ("simulation of simplicity", Edelsbrunner & Mücke, ACM TOG 9(1),
// 1990) for the four predicates, in one place. The scheme is documented in
// voroclip/predicates.h; this file implements it generically.
//
// The k x k matrix of a call has one row per point, ordered by rank (rank 0 = smallest
// index), and columns
//     0 .. d-1   coordinates x, y[, z]
//     d          lifted coordinate w = |p|^2      (incircle, insphere only)
//     k-1        the constant 1
// Entry (r, c) of a coordinate or lift column is perturbed by eps^(2^pos(r, c)), with
//     lifted:     pos(r, w) = r,        pos(r, j) = k + d*r + (d-1-j)
//     orient:                           pos(r, j) = d*r + (d-1-j)
// so that lifts dominate coordinates, smaller indices dominate larger ones, and z comes
// before y before x. The perturbed determinant is a polynomial in eps whose terms are the
// partial matchings S of rows to perturbed columns (a perturbed entry from each matched
// row); the exponent of S is sum over S of 2^pos, so terms are ordered by the bitmask
// `mask(S)`, all distinct. The coefficient of S is, by the generalised Laplace expansion,
//     (-1)^(sum rows(S) + sum cols(S)) * sgn(S) * det(M without the rows and columns of S)
// where sgn(S) is the parity of S's columns listed in row order. A table of all S sorted
// by mask (500 for insphere) is built once; a call walks it until a coefficient is
// non-zero. The walk always ends: the last matchings leave only the constant column, a
// 1x1 minor equal to 1.
//
// Minors without the lift column are orientation determinants of the points projected
// on the kept coordinates (exact orient3d / orient2d / comparisons). Minors with it occur
// only once every lift-only term vanished (all points of an incircle call collinear, all
// of an insphere call coplanar); they are evaluated with big integers, exact for all
// finite inputs.

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "bigint.h"
#include "voroclip/core.h"
#include "voroclip/predicates.h"

namespace voroclip {

namespace {

using detail::BigInt;

constexpr int kMaxPoints = 5;

struct Shape {
  int k;        // points = rows = columns
  int d;        // dimension
  bool lifted;  // has the w column
};

struct Term {
  std::uint64_t mask;
  std::uint8_t rows_kept;  // bit r set: row of rank r is in the minor
  std::uint8_t cols_kept;  // bit c set: column c is in the minor
  std::int8_t sign;        // Laplace sign of the coefficient
};

int position(const Shape& s, int rank, int col) {
  if (s.lifted && col == s.d) return rank;
  const int base = s.lifted ? s.k : 0;
  return base + s.d * rank + (s.d - 1 - col);
}

// Appends the term of the matching col_of_row (entry r: the column matched to row r, or -1).
void add_term(const Shape& s, const std::array<int, kMaxPoints>& col_of_row,
              std::vector<Term>& terms) {
  Term t{0, 0, 0, 1};
  unsigned used_cols = 0;
  int parity = 0;
  for (int r = 0; r < s.k; ++r) {
    const int c = col_of_row[static_cast<std::size_t>(r)];
    if (c < 0) {
      t.rows_kept = static_cast<std::uint8_t>(t.rows_kept | (1u << r));
      continue;
    }
    t.mask |= std::uint64_t{1} << position(s, r, c);
    parity += r + c;
    // Inversions of the columns listed in row order (unmatched rows hold -1: never count).
    for (int r2 = 0; r2 < r; ++r2) {
      parity += col_of_row[static_cast<std::size_t>(r2)] > c ? 1 : 0;
    }
    used_cols |= 1u << c;
  }
  if (used_cols == 0) return;  // the unperturbed determinant itself
  t.cols_kept = static_cast<std::uint8_t>(((1u << s.k) - 1) & ~used_cols);
  t.sign = static_cast<std::int8_t>(parity % 2 == 0 ? 1 : -1);
  terms.push_back(t);
}

std::vector<Term> build_terms(const Shape& s) {
  // Enumerates every matching as a number in base (k) : digit r is 0 for "row r not in
  // S" or 1 + the column matched to row r; matchings reusing a column are skipped.
  const int perturbed_cols = s.k - 1;
  int count = 1;
  for (int r = 0; r < s.k; ++r) count *= perturbed_cols + 1;
  std::vector<Term> terms;
  for (int code = 0; code < count; ++code) {
    std::array<int, kMaxPoints> col_of_row{};
    col_of_row.fill(-1);
    unsigned used = 0;
    bool valid = true;
    int rest = code;
    for (std::size_t r = 0; r < static_cast<std::size_t>(s.k); ++r) {
      const int digit = rest % (perturbed_cols + 1);
      rest /= perturbed_cols + 1;
      if (digit == 0) continue;
      const int c = digit - 1;
      valid = valid && !(used & (1u << c));
      used |= 1u << c;
      col_of_row[r] = c;
    }
    if (valid) add_term(s, col_of_row, terms);
  }
  std::sort(terms.begin(), terms.end(),
            [](const Term& a, const Term& b) { return a.mask < b.mask; });
  return terms;
}

// Orders the points of a call by index (distinct, checked by the caller): by_rank[r] is
// the point of rank r. Returns the parity of the permutation (+1 / -1), which is the
// parity of its number of inversions. Branch-free rank counting: k <= 5.
int sort_by_index(int k, const double* const* pts, const std::uint32_t* idx,
                  const double** by_rank) {
  int rank[kMaxPoints] = {};
  int inversions = 0;
  for (int i = 0; i < k; ++i) {
    for (int j = i + 1; j < k; ++j) {
      const int greater = int{idx[i] > idx[j]};
      inversions += greater;
      rank[i] += greater;
      rank[j] += 1 - greater;
    }
  }
  for (int i = 0; i < k; ++i) by_rank[rank[i]] = pts[i];
  return 1 - 2 * (inversions & 1);
}

// Determinant of a small square matrix of big integers (Laplace along the first row).
BigInt big_det(const std::vector<BigInt>& m, int n) {
  if (n == 1) return m[0];
  BigInt sum;
  std::vector<BigInt> minor(static_cast<std::size_t>((n - 1) * (n - 1)));
  for (int c = 0; c < n; ++c) {
    std::size_t at = 0;
    for (int r = 1; r < n; ++r) {
      for (int cc = 0; cc < n; ++cc) {
        if (cc != c) minor[at++] = m[static_cast<std::size_t>(r * n + cc)];
      }
    }
    const BigInt term = m[static_cast<std::size_t>(c)] * big_det(minor, n - 1);
    sum = (c % 2 == 0) ? sum + term : sum - term;
  }
  return sum;
}

// Sign of the minor with rows `rows` (points, in rank order) and the kept columns of a
// lifted matrix including the w column: big integers on the points' common binary grid.
int lifted_minor_sign(const Shape& s, const double* const* rows, int m, const int* cols,
                      int ncols_non_one) {
  int grid = 0;
  bool any = false;
  for (int r = 0; r < m; ++r) {
    for (int j = 0; j < s.d; ++j) {
      if (rows[r][j] == 0) continue;
      const int lo = detail::lowest_bit_exponent(rows[r][j]);
      grid = any ? std::min(grid, lo) : lo;
      any = true;
    }
  }
  // Integer coordinates X = x / 2^grid; the w column becomes sum X^2 = w / 2^(2 grid).
  // Scaling a column by a positive factor keeps the sign of the determinant.
  std::vector<BigInt> value(static_cast<std::size_t>(m * ncols_non_one));
  for (int r = 0; r < m; ++r) {
    for (int c = 0; c < ncols_non_one; ++c) {
      BigInt v;
      if (cols[c] == s.d) {
        for (int j = 0; j < s.d; ++j) {
          const BigInt x = BigInt::from_scaled_double(rows[r][j], grid);
          v = v + x * x;
        }
      } else {
        v = BigInt::from_scaled_double(rows[r][cols[c]], grid);
      }
      value[static_cast<std::size_t>(r * ncols_non_one + c)] = v;
    }
  }
  // Subtract the last row: with the constant column, det = det of the (m-1)^2 differences.
  // (The minor is square: m rows, the constant column and m - 1 = ncols_non_one others.)
  const int n = ncols_non_one;
  std::vector<BigInt> diff(static_cast<std::size_t>(n * n));
  for (int r = 0; r < n; ++r) {
    for (int c = 0; c < n; ++c) {
      diff[static_cast<std::size_t>(r * n + c)] =
          value[static_cast<std::size_t>(r * n + c)] - value[static_cast<std::size_t>(n * n + c)];
    }
  }
  return big_det(diff, n).sign();
}

// Sign of det(M[rows_kept, cols_kept]) for the sorted points.
int minor_sign(const Shape& s, const double* const* by_rank, const Term& t) {
  const double* rows[kMaxPoints];
  int m = 0;
  for (int r = 0; r < s.k; ++r) {
    if (t.rows_kept & (1u << r)) rows[m++] = by_rank[r];
  }
  int cols[kMaxPoints];
  int nc = 0;  // kept columns other than the constant one
  bool has_lift = false;
  for (int c = 0; c < s.k - 1; ++c) {
    if (t.cols_kept & (1u << c)) {
      cols[nc++] = c;
      has_lift = has_lift || (s.lifted && c == s.d);
    }
  }
  if (has_lift) return lifted_minor_sign(s, rows, m, cols, nc);
  // Orientation of the points projected on the kept coordinates: det of rows (p, 1).
  switch (nc) {
    case 0:
      return 1;
    case 1: {
      const double a = rows[0][cols[0]], b = rows[1][cols[0]];
      return a > b ? 1 : (a < b ? -1 : 0);
    }
    case 2: {
      const double p[3][2] = {{rows[0][cols[0]], rows[0][cols[1]]},
                              {rows[1][cols[0]], rows[1][cols[1]]},
                              {rows[2][cols[0]], rows[2][cols[1]]}};
      return static_cast<int>(orient2d(p[0], p[1], p[2]));
    }
    default:
      return static_cast<int>(orient3d(rows[0], rows[1], rows[2], rows[3]));
  }
}

const std::vector<Term>& terms_for(const Shape& s) {
  static const std::vector<Term> orient2d_terms = build_terms({3, 2, false});
  static const std::vector<Term> orient3d_terms = build_terms({4, 3, false});
  static const std::vector<Term> incircle_terms = build_terms({4, 2, true});
  static const std::vector<Term> insphere_terms = build_terms({5, 3, true});
  if (!s.lifted) return s.d == 2 ? orient2d_terms : orient3d_terms;
  return s.d == 2 ? incircle_terms : insphere_terms;
}

// The perturbed sign, given that the unperturbed determinant is zero.
Sign perturbed_sign(const char* name, const Shape& s, const double* const* pts,
                    const std::uint32_t* idx) {
  const double* by_rank[kMaxPoints];
  const int parity = sort_by_index(s.k, pts, idx, by_rank);
  for (const Term& t : terms_for(s)) {
    const int minor = minor_sign(s, by_rank, t);
    if (minor != 0) return static_cast<Sign>(parity * t.sign * minor);
  }
  throw Error(std::string(name) + ": internal error, symbolic perturbation found no term");
}

void check_distinct(const char* name, int k, const std::uint32_t* idx) {
  for (int i = 0; i < k; ++i) {
    for (int j = i + 1; j < k; ++j) {
      if (idx[i] == idx[j]) {
        throw Error(std::string(name) + ": point indices must be distinct (index " +
                    std::to_string(idx[i]) + " appears twice)");
      }
    }
  }
}

}  // namespace

Sign orient2d_sos(const double* a, const double* b, const double* c, std::uint32_t ia,
                  std::uint32_t ib, std::uint32_t ic) {
  const std::uint32_t idx[] = {ia, ib, ic};
  check_distinct("orient2d_sos", 3, idx);
  const Sign s = orient2d(a, b, c);
  if (s != Sign::zero) return s;
  const double* pts[] = {a, b, c};
  return perturbed_sign("orient2d_sos", {3, 2, false}, pts, idx);
}

Sign orient3d_sos(const double* a, const double* b, const double* c, const double* d,
                  std::uint32_t ia, std::uint32_t ib, std::uint32_t ic, std::uint32_t id) {
  const std::uint32_t idx[] = {ia, ib, ic, id};
  check_distinct("orient3d_sos", 4, idx);
  const Sign s = orient3d(a, b, c, d);
  if (s != Sign::zero) return s;
  const double* pts[] = {a, b, c, d};
  return perturbed_sign("orient3d_sos", {4, 3, false}, pts, idx);
}

Sign incircle_sos(const double* a, const double* b, const double* c, const double* d,
                  std::uint32_t ia, std::uint32_t ib, std::uint32_t ic, std::uint32_t id) {
  const std::uint32_t idx[] = {ia, ib, ic, id};
  check_distinct("incircle_sos", 4, idx);
  const Sign s = incircle(a, b, c, d);
  if (s != Sign::zero) return s;
  const double* pts[] = {a, b, c, d};
  return perturbed_sign("incircle_sos", {4, 2, true}, pts, idx);
}

Sign insphere_sos(const double* a, const double* b, const double* c, const double* d,
                  const double* e, std::uint32_t ia, std::uint32_t ib, std::uint32_t ic,
                  std::uint32_t id, std::uint32_t ie) {
  const std::uint32_t idx[] = {ia, ib, ic, id, ie};
  check_distinct("insphere_sos", 5, idx);
  const Sign s = insphere(a, b, c, d, e);
  if (s != Sign::zero) return s;
  const double* pts[] = {a, b, c, d, e};
  return perturbed_sign("insphere_sos", {5, 3, true}, pts, idx);
}

}  // namespace voroclip
