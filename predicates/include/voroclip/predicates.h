// voroclip/predicates.h — exact geometric predicates.
//
// Every function here returns the exact sign of a polynomial in its double inputs; no
// epsilon is involved anywhere. Three tiers (STYLE.md, "Data and API"):
//
//   orient2d, incircle, orient3d, insphere        exact: an inlined semi-static floating-
//                                                 point filter, then exact arithmetic
//                                                 (Shewchuk expansions) when it cannot decide
//   *_sos(points..., indices...)                  exact and never zero: symbolic
//                                                 perturbation by point index (see below)
//   *_fast                                        plain floating point, NOT exact: for tests
//                                                 and benchmarks only
//
// Sign conventions are those of Shewchuk's predicates.c:
//   orient2d(a,b,c)      > 0  when a, b, c are counter-clockwise
//   incircle(a,b,c,d)    > 0  when d is inside the circle through counter-clockwise a, b, c
//   orient3d(a,b,c,d)    = sign of det[a-d; b-d; c-d]  (> 0 when d is below the plane of
//                              a, b, c, seen counter-clockwise from above)
//   insphere(a,b,c,d,e)  > 0  when e is inside the sphere through a, b, c, d, where
//                              orient3d(a,b,c,d) > 0
// Equivalently, each is the sign of the determinant whose rows are its arguments in order,
// each row (p, 1) for the orientations and (p, |p|^2, 1) for the in-circle/in-sphere tests.
//
// Input range. The result is exact for every finite double input: the filter handles the
// common case; the exact stage uses expansion arithmetic after scaling by a power of two
// when the exponents of the coordinates in one call span a range that expansions can carry
// without underflow or overflow (see predicates/src/exact.h), and a big-integer evaluation
// of the same determinant otherwise (first of all, points that share one coordinate
// exactly, on an axis-aligned line or plane, are zero at once: the determinant has a zero
// column). A NaN or infinite coordinate throws voroclip::Error; no input produces a wrong
// sign.
//
// Symbolic perturbation (*_sos). Point k of a call, with index i_k, is replaced by
//     x_{k,j}(eps) = x_{k,j} + eps^(2^pos(k,j))       for each coordinate j
//     w_k(eps)     = |p_k|^2 + eps^(2^pos(k,w))       for the lifted coordinate
// (Edelsbrunner & Mücke's "simulation of simplicity", 1990), where pos orders the
// perturbations by decreasing size: every lift perturbation is larger than every
// coordinate perturbation; among lifts and among coordinates a smaller point index means a
// larger perturbation; and within one point the last coordinate comes first (z, y, x).
// The sign returned is that of the perturbed determinant for every small enough eps > 0:
// the sign of the first non-zero coefficient of its expansion in eps. The perturbation is
// a fixed function of the point indices, so all four predicates decide on one and the same
// perturbed configuration and are mutually consistent (the lifted coordinate is perturbed
// independently of x, y, z: geometrically a regular triangulation with infinitesimal
// weights, which refines the Delaunay subdivision). Consequences:
//   - the sign is never zero, whatever the input (duplicates, collinear, cospherical...)
//     provided the indices of one call are distinct (equal indices throw voroclip::Error);
//   - for incircle/insphere, when the exact sign is zero the first deciding terms are the
//     orientations of the other points (Devillers & Teillaud 2011): for a non-degenerate
//     triangle/tetrahedron the answer costs one extra orient2d/orient3d at most a few.
// The indices only need to be distinct and fixed per point; typically they are positions
// in the caller's point array.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace voroclip {

enum class Sign : int { negative = -1, zero = 0, positive = 1 };

inline Sign operator-(Sign s) { return static_cast<Sign>(-static_cast<int>(s)); }
inline Sign operator*(Sign a, Sign b) {
  return static_cast<Sign>(static_cast<int>(a) * static_cast<int>(b));
}

namespace detail {

// Semi-static filter. Each predicate computes its determinant det~ in floating point
// (Shewchuk's formulas, translated to the last point) together with a magnitude `scale`,
// and returns sign(det~) when |det~| > bound * scale and lower < scale < upper.
//
// The bound: scripts/filter_bounds.py derives, by forward error analysis with u = 2^-53
// (as Meyer & Pion's FPG does), |det~ - det| <= E M^deg where M bounds every rounded
// coordinate difference: orient2d E = 8u, orient3d 46u, incircle 128u, insphere 1104u.
// The analysis is multilinear in the leaves, so M^deg may be replaced by any product of
// per-leaf bounds matching the terms' shape:
//   orient2d  scale = mx my        (every term is an x difference times a y difference;
//   orient3d  scale = mx my mz      mA = max |A difference| over the points)
//   incircle  scale = L^2          (L = the largest computed lift |p - p_last|^2; every
//   insphere  scale = L^2 sqrt(L)   difference satisfies x^2 <= L / (1-u)^3)
// The stored constants are E times at most (1+u)^12 (the roundings of the lifts, of
// scale and of bound * scale), rounded up to 3 digits; the rounding-up alone leaves
// more than 0.3 % of slack.
// The range (lower, upper) keeps the quantity bounding M^deg within [2^-960, 2^1000]: no
// intermediate overflows (all are below 72 M^deg), and the absolute error of underflowing
// products (<= 2^-1075 each, amplified by at most 72 max(1, M)^3) stays far below the
// constants' slack. NaN and infinities fail the range test or both comparisons, so they
// always reach the exact stage, which rejects them.
inline constexpr double kOrient2dBound = 8.89e-16;
inline constexpr double kOrient3dBound = 5.11e-15;
inline constexpr double kIncircleBound = 1.43e-14;
inline constexpr double kInsphereBound = 1.23e-13;
// compare_distance: E = 20u (2D), 34u (3D) on M^2, with scale = the larger of the two
// computed squared distances (x^2 <= L / (1-u)^3 as for the lifts).
inline constexpr double kCompareDistance2dBound = 2.23e-15;
inline constexpr double kCompareDistance3dBound = 3.78e-15;
inline constexpr double kOrientScaleLower = 0x1p-960, kOrientScaleUpper = 0x1p+1000;
inline constexpr double kIncircleScaleLower = 0x1p-940, kIncircleScaleUpper = 0x1p+980;
inline constexpr double kInsphereScaleLower = 0x1p-950, kInsphereScaleUpper = 0x1p+1000;

// Exact stages (predicates/src/exact.cpp): called when the filter cannot decide.
Sign orient2d_exact(const double* a, const double* b, const double* c);
Sign incircle_exact(const double* a, const double* b, const double* c, const double* d);
Sign orient3d_exact(const double* a, const double* b, const double* c, const double* d);
Sign insphere_exact(const double* a, const double* b, const double* c, const double* d,
                    const double* e);
Sign compare_distance2d_exact(const double* p, const double* q, const double* r);
Sign compare_distance3d_exact(const double* p, const double* q, const double* r);

inline double max_abs(double a, double b) { return std::max(std::fabs(a), std::fabs(b)); }

// Branch-free: the signs of random input are unpredictable, a branch would mispredict.
inline Sign sign_of(double x) { return static_cast<Sign>(int{x > 0} - int{x < 0}); }

}  // namespace detail

// ---------------------------------------------------------------------------------------
// Floating-point evaluation shared by the filters and the *_fast variants: the rounded
// determinant (Shewchuk's formulas, translated to the last point) and M, the largest
// absolute rounded coordinate difference. The filter constants above are derived for
// exactly these operation trees; change one and re-run scripts/filter_bounds.py.

namespace detail {

struct Approx {
  double det;
  double scale;
};

inline Approx orient2d_approx(const double* a, const double* b, const double* c) {
#if defined(__SSE2__)
  // Differences, absolute values and per-axis maxima two lanes at a time (see orient3d).
  const __m128d cxy = _mm_loadu_pd(c);
  const __m128d axy = _mm_sub_pd(_mm_loadu_pd(a), cxy);
  const __m128d bxy = _mm_sub_pd(_mm_loadu_pd(b), cxy);
  const double adx = _mm_cvtsd_f64(axy), ady = _mm_cvtsd_f64(_mm_unpackhi_pd(axy, axy));
  const double bdx = _mm_cvtsd_f64(bxy), bdy = _mm_cvtsd_f64(_mm_unpackhi_pd(bxy, bxy));
  const __m128d abs_mask = _mm_castsi128_pd(_mm_set1_epi64x(0x7fffffffffffffffLL));
  const __m128d mxy = _mm_max_pd(_mm_and_pd(axy, abs_mask), _mm_and_pd(bxy, abs_mask));
  const double mx = _mm_cvtsd_f64(mxy), my = _mm_cvtsd_f64(_mm_unpackhi_pd(mxy, mxy));
#else
  const double adx = a[0] - c[0], bdx = b[0] - c[0];
  const double ady = a[1] - c[1], bdy = b[1] - c[1];
  const double mx = max_abs(adx, bdx), my = max_abs(ady, bdy);
#endif
  return {adx * bdy - ady * bdx, mx * my};
}

inline Approx orient3d_approx(const double* a, const double* b, const double* c, const double* d) {
#if defined(__SSE2__)
  // The x and y differences, their absolute values and per-axis maxima two lanes at a
  // time: the same IEEE operations as the scalar code below, in fewer instructions (this
  // predicate has the most differences per product, so the filter's share is largest).
  const __m128d dxy = _mm_loadu_pd(d);
  const __m128d axy = _mm_sub_pd(_mm_loadu_pd(a), dxy);
  const __m128d bxy = _mm_sub_pd(_mm_loadu_pd(b), dxy);
  const __m128d cxy = _mm_sub_pd(_mm_loadu_pd(c), dxy);
  const double adx = _mm_cvtsd_f64(axy), ady = _mm_cvtsd_f64(_mm_unpackhi_pd(axy, axy));
  const double bdx = _mm_cvtsd_f64(bxy), bdy = _mm_cvtsd_f64(_mm_unpackhi_pd(bxy, bxy));
  const double cdx = _mm_cvtsd_f64(cxy), cdy = _mm_cvtsd_f64(_mm_unpackhi_pd(cxy, cxy));
  const __m128d abs_mask = _mm_castsi128_pd(_mm_set1_epi64x(0x7fffffffffffffffLL));
  const __m128d mxy = _mm_max_pd(_mm_max_pd(_mm_and_pd(axy, abs_mask), _mm_and_pd(bxy, abs_mask)),
                                 _mm_and_pd(cxy, abs_mask));
  const double mx = _mm_cvtsd_f64(mxy), my = _mm_cvtsd_f64(_mm_unpackhi_pd(mxy, mxy));
#else
  const double adx = a[0] - d[0], bdx = b[0] - d[0], cdx = c[0] - d[0];
  const double ady = a[1] - d[1], bdy = b[1] - d[1], cdy = c[1] - d[1];
  const double mx = std::max(max_abs(adx, bdx), std::fabs(cdx));
  const double my = std::max(max_abs(ady, bdy), std::fabs(cdy));
#endif
  const double adz = a[2] - d[2], bdz = b[2] - d[2], cdz = c[2] - d[2];
  const double det =
      adz * (bdx * cdy - cdx * bdy) + bdz * (cdx * ady - adx * cdy) + cdz * (adx * bdy - bdx * ady);
  const double mz = std::max(max_abs(adz, bdz), std::fabs(cdz));
  return {det, mx * my * mz};
}

inline Approx incircle_approx(const double* a, const double* b, const double* c, const double* d) {
  const double adx = a[0] - d[0], bdx = b[0] - d[0], cdx = c[0] - d[0];
  const double ady = a[1] - d[1], bdy = b[1] - d[1], cdy = c[1] - d[1];
  const double alift = adx * adx + ady * ady;
  const double blift = bdx * bdx + bdy * bdy;
  const double clift = cdx * cdx + cdy * cdy;
  const double det = alift * (bdx * cdy - cdx * bdy) + blift * (cdx * ady - adx * cdy) +
                     clift * (adx * bdy - bdx * ady);
  const double lift = std::max(std::max(alift, blift), clift);
  return {det, lift * lift};
}

inline Approx insphere_approx(const double* a, const double* b, const double* c, const double* d,
                              const double* e) {
  const double aex = a[0] - e[0], bex = b[0] - e[0], cex = c[0] - e[0], dex = d[0] - e[0];
  const double aey = a[1] - e[1], bey = b[1] - e[1], cey = c[1] - e[1], dey = d[1] - e[1];
  const double aez = a[2] - e[2], bez = b[2] - e[2], cez = c[2] - e[2], dez = d[2] - e[2];
  const double ab = aex * bey - bex * aey, bc = bex * cey - cex * bey;
  const double cd = cex * dey - dex * cey, da = dex * aey - aex * dey;
  const double ac = aex * cey - cex * aey, bd = bex * dey - dex * bey;
  const double abc = aez * bc - bez * ac + cez * ab;
  const double bcd = bez * cd - cez * bd + dez * bc;
  const double cda = cez * da + dez * ac + aez * cd;
  const double dab = dez * ab + aez * bd + bez * da;
  const double alift = aex * aex + aey * aey + aez * aez;
  const double blift = bex * bex + bey * bey + bez * bez;
  const double clift = cex * cex + cey * cey + cez * cez;
  const double dlift = dex * dex + dey * dey + dez * dez;
  const double det = (dlift * abc - clift * dab) + (blift * cda - alift * bcd);
  const double lift = std::max(std::max(alift, blift), std::max(clift, dlift));
  return {det, lift * lift * std::sqrt(lift)};
}

template <int D>
inline Approx compare_distance_approx(const double* p, const double* q, const double* r) {
  double lq = 0, lr = 0;
  for (int j = 0; j < D; ++j) {
    const double dq = q[j] - p[j], dr = r[j] - p[j];
    lq += dq * dq;
    lr += dr * dr;
  }
  return {lq - lr, std::max(lq, lr)};
}

// +1 / -1 when the filter is certain, 0 when the exact stage must decide. The test is a
// well-predicted branch (the filter almost always decides); the sign is then read from
// the sign bit (det != 0 there), since the signs of random input are unpredictable.
inline int decided_sign(double det) { return 1 - 2 * static_cast<int>(std::signbit(det)); }

// lower < x < upper for x >= 0 (or NaN) and 0 < lower < upper, in one unsigned comparison:
// non-negative doubles are ordered like their bit patterns, NaNs and +inf lie above upper.
inline bool in_open_range(double x, double lower, double upper) {
  std::uint64_t bx, bl, bu;
  std::memcpy(&bx, &x, sizeof bx);
  std::memcpy(&bl, &lower, sizeof bl);
  std::memcpy(&bu, &upper, sizeof bu);
  return bx - bl - 1 < bu - bl - 1;
}

inline int filter_decision(const Approx& r, double bound, double lower, double upper) {
  if (in_open_range(r.scale, lower, upper) && std::fabs(r.det) > bound * r.scale) {
    return decided_sign(r.det);
  }
  return 0;
}

inline int compare_distance2d_filter(const double* p, const double* q, const double* r) {
  return filter_decision(compare_distance_approx<2>(p, q, r), kCompareDistance2dBound,
                         kOrientScaleLower, kOrientScaleUpper);
}
inline int compare_distance3d_filter(const double* p, const double* q, const double* r) {
  return filter_decision(compare_distance_approx<3>(p, q, r), kCompareDistance3dBound,
                         kOrientScaleLower, kOrientScaleUpper);
}

// The filter of each predicate: its decision, or 0 when the exact stage must decide.
//
// orient2d needs no range test: its two products are each at most scale = mx my, so
// underflow adds at most 2 * 2^-1075 of absolute error, covered by the slack 2^-1000; and
// when scale is finite a product cannot overflow, while an overflowing difference of two
// products is far larger than the error, so a resulting infinity has the right sign.
// Non-finite input makes scale or det infinite or NaN, and the test false.
inline int orient2d_filter(const double* a, const double* b, const double* c) {
  constexpr double kUnderflowSlack = 0x1p-1000;
  const Approx r = orient2d_approx(a, b, c);
  if (std::fabs(r.det) > kOrient2dBound * r.scale + kUnderflowSlack) return decided_sign(r.det);
  return 0;
}
inline int orient3d_filter(const double* a, const double* b, const double* c, const double* d) {
  return filter_decision(orient3d_approx(a, b, c, d), kOrient3dBound, kOrientScaleLower,
                         kOrientScaleUpper);
}
inline int incircle_filter(const double* a, const double* b, const double* c, const double* d) {
  return filter_decision(incircle_approx(a, b, c, d), kIncircleBound, kIncircleScaleLower,
                         kIncircleScaleUpper);
}
inline int insphere_filter(const double* a, const double* b, const double* c, const double* d,
                           const double* e) {
  return filter_decision(insphere_approx(a, b, c, d, e), kInsphereBound, kInsphereScaleLower,
                         kInsphereScaleUpper);
}

}  // namespace detail

// ---------------------------------------------------------------------------------------
// Exact predicates (filtered).

inline Sign orient2d(const double* a, const double* b, const double* c) {
  const int s = detail::orient2d_filter(a, b, c);
  return s != 0 ? static_cast<Sign>(s) : detail::orient2d_exact(a, b, c);
}

inline Sign orient3d(const double* a, const double* b, const double* c, const double* d) {
  const int s = detail::orient3d_filter(a, b, c, d);
  return s != 0 ? static_cast<Sign>(s) : detail::orient3d_exact(a, b, c, d);
}

inline Sign incircle(const double* a, const double* b, const double* c, const double* d) {
  const int s = detail::incircle_filter(a, b, c, d);
  return s != 0 ? static_cast<Sign>(s) : detail::incircle_exact(a, b, c, d);
}

inline Sign insphere(const double* a, const double* b, const double* c, const double* d,
                     const double* e) {
  const int s = detail::insphere_filter(a, b, c, d, e);
  return s != 0 ? static_cast<Sign>(s) : detail::insphere_exact(a, b, c, d, e);
}

// Three points of 3D space exactly on one line (or coincident): every axis-aligned
// projection of the triangle has zero area. Exact.
inline bool collinear3d(const double* a, const double* b, const double* c) {
  const double ayz[2] = {a[1], a[2]}, byz[2] = {b[1], b[2]}, cyz[2] = {c[1], c[2]};
  const double azx[2] = {a[2], a[0]}, bzx[2] = {b[2], b[0]}, czx[2] = {c[2], c[0]};
  return orient2d(a, b, c) == Sign::zero && orient2d(ayz, byz, cyz) == Sign::zero &&
         orient2d(azx, bzx, czx) == Sign::zero;
}

// sign(|p - q|^2 - |p - r|^2): negative when q is strictly closer to p than r, positive
// when r is, zero when p is equidistant (on the bisector of q and r). Exact, filtered.
inline Sign compare_distance2d(const double* p, const double* q, const double* r) {
  const int s = detail::compare_distance2d_filter(p, q, r);
  return s != 0 ? static_cast<Sign>(s) : detail::compare_distance2d_exact(p, q, r);
}
inline Sign compare_distance3d(const double* p, const double* q, const double* r) {
  const int s = detail::compare_distance3d_filter(p, q, r);
  return s != 0 ? static_cast<Sign>(s) : detail::compare_distance3d_exact(p, q, r);
}

// ---------------------------------------------------------------------------------------
// Static filter: for points known to lie in an axis-aligned box (typically the bounding
// box of the point set a triangulation is built from), the error bounds above become
// constants computed once: with X, Y, Z the box's rounded extents, every rounded
// coordinate difference of a call satisfies |fl(p - q)| <= X (rounding is monotone), so
//   orient2d |error| <= E X Y,   orient3d E X Y Z,   incircle E M^4,   insphere E M^5
// with M = max(X, Y[, Z]) and E the constants above (which carry the rounding of these
// products). A call then costs the plain determinant and one comparison; when the static
// bound cannot decide, the semi-static filter and then the exact stage do, so results are
// identical to the plain overloads. The bounds are enabled only while the extents keep
// every product far from underflow and overflow (orient: each extent in [2^-300, 2^300];
// incircle M in [2^-200, 2^200]; insphere M in [2^-150, 2^150]); otherwise, or for a
// default-constructed filter, every call takes the semi-static path.
// Precondition: every point passed with the filter lies inside its box; a point outside
// can make the static bound too small.
class StaticFilter {
 public:
  StaticFilter() = default;
  // The box [lo, hi] of `dimension` (2 or 3) coordinates.
  StaticFilter(const double* lo, const double* hi, int dimension);
  // The bounding box of n points stored as packed coordinates (x y [z] per point).
  static StaticFilter bounding(const double* coords, std::size_t n, int dimension);

  double orient2d_bound() const { return orient2d_; }
  double orient3d_bound() const { return orient3d_; }
  double incircle_bound() const { return incircle_; }
  double insphere_bound() const { return insphere_; }

 private:
  // +inf: |det| > inf is never true, so a disabled bound defers every call.
  static constexpr double kDisabled = std::numeric_limits<double>::infinity();
  double orient2d_ = kDisabled, orient3d_ = kDisabled;
  double incircle_ = kDisabled, insphere_ = kDisabled;
};

inline Sign orient2d(const double* a, const double* b, const double* c, const StaticFilter& f) {
  const double det = detail::orient2d_approx(a, b, c).det;
  if (std::fabs(det) > f.orient2d_bound()) return static_cast<Sign>(detail::decided_sign(det));
  return orient2d(a, b, c);
}

inline Sign orient3d(const double* a, const double* b, const double* c, const double* d,
                     const StaticFilter& f) {
  const double det = detail::orient3d_approx(a, b, c, d).det;
  if (std::fabs(det) > f.orient3d_bound()) return static_cast<Sign>(detail::decided_sign(det));
  return orient3d(a, b, c, d);
}

inline Sign incircle(const double* a, const double* b, const double* c, const double* d,
                     const StaticFilter& f) {
  const double det = detail::incircle_approx(a, b, c, d).det;
  if (std::fabs(det) > f.incircle_bound()) return static_cast<Sign>(detail::decided_sign(det));
  return incircle(a, b, c, d);
}

inline Sign insphere(const double* a, const double* b, const double* c, const double* d,
                     const double* e, const StaticFilter& f) {
  const double det = detail::insphere_approx(a, b, c, d, e).det;
  if (std::fabs(det) > f.insphere_bound()) return static_cast<Sign>(detail::decided_sign(det));
  return insphere(a, b, c, d, e);
}

// ---------------------------------------------------------------------------------------
// Symbolically perturbed predicates: exact, never zero (see the header comment). The
// index arguments identify the points; they must be distinct within a call.

Sign orient2d_sos(const double* a, const double* b, const double* c, std::uint32_t ia,
                  std::uint32_t ib, std::uint32_t ic);
Sign incircle_sos(const double* a, const double* b, const double* c, const double* d,
                  std::uint32_t ia, std::uint32_t ib, std::uint32_t ic, std::uint32_t id);
Sign orient3d_sos(const double* a, const double* b, const double* c, const double* d,
                  std::uint32_t ia, std::uint32_t ib, std::uint32_t ic, std::uint32_t id);
Sign insphere_sos(const double* a, const double* b, const double* c, const double* d,
                  const double* e, std::uint32_t ia, std::uint32_t ib, std::uint32_t ic,
                  std::uint32_t id, std::uint32_t ie);

// ---------------------------------------------------------------------------------------
// The orientation of a closed triangle surface (Surface3 validation, clip/).
//
//   surface_volume_sign(xyz, triangles, n)
//       the exact sign of the sum over the n triangles (a, b, c) (3 indices each into xyz,
//       x y z per vertex) of det(a, b, c) = a . (b x c): six times the volume enclosed by a
//       closed surface, signed (POSITIVE when the triangles' right-hand normals point out
//       of the volume). For a closed surface the sum equals that of det(a - o, b - o, c - o)
//       for any o: a floating-point sum from the first vertex with a proven bound
//       (predicates/src/volume.cpp), then big integers when it cannot decide. Throws Error
//       for a non-finite coordinate. ZERO only when the exact sum is zero.
Sign surface_volume_sign(const double* xyz, const std::uint32_t* triangles, std::size_t n);

// ---------------------------------------------------------------------------------------
// Voronoi clipping predicates in 2D (clip/, DESIGN.md "Clipping predicates on symbolic
// vertices"). Sites p_i carry the lift perturbation of the *_sos predicates above, so the
// Voronoi diagram they decide on is the power diagram dual to the triangulation that
// incircle_sos builds: site i has the power distance
//     pi_i(x) = |x - p_i|^2 + eps_i,     eps_i > 0 infinitesimal, eps_i >> eps_j when i < j,
// and the signed bisector function is f_ij(x) = pi_i(x) - pi_j(x): x is on site i's side of
// bisector(i, j) when f_ij(x) < 0. Between exactly equidistant sites the perturbation gives
// x to the site with the LARGER index (its eps is smaller). Domain points (polygon
// vertices) are not perturbed. Each function returns the sign of f_ij at a symbolic
// vertex, exactly, and never ZERO when its preconditions hold:
//
//   bisector_side_vertex2d     x = a, a polygon vertex:  sign f_ij(a).
//   bisector_side_edge2d       x = q, where segment [a, b] crosses bisector(i, k):
//                              f_ik(a) and f_ik(b) must have opposite (perturbed) signs.
//                              sign f_ij(q) = sign(f_ik(a) f_ij(b) - f_ij(a) f_ik(b))
//                                             * sign(f_ik(a) - f_ik(b)).
//                              i, j, k distinct. (Only f_ik(a) != f_ik(b) is checked: the
//                              result is then f_ij at the crossing of LINE ab.)
//   bisector_side_voronoi2d    x = the Voronoi vertex of sites (i, k, l) (a triangle of
//                              their Delaunay triangulation, so not collinear; any
//                              order): sign f_ij(x), i, j, k, l distinct. Equivalent to
//                              incircle_sos(i, k, l, j) * orient2d(i, k, l) (j inside the
//                              circle through i, k, l means pi_j(x) < pi_i(x)). When
//                              (i, k, l) is a triangle of the triangulation built with
//                              incircle_sos (Delaunay2), NEGATIVE for every other site j.
//
// Ordering of crossings along one bisector (for walking a cell's boundary):
//   compare_on_bisector2d      q1 = [a1, b1] ∩ bisector(i, k), q2 = [a2, b2] ∩ bisector(i,
//                              k), each segment crossing it as above. Returns the sign of
//                              d . (q2 - q1) with d = rot90(p_k - p_i) = (p_i.y - p_k.y,
//                              p_k.x - p_i.x): the direction of travel along the boundary
//                              of cell i counter-clockwise (cell i on the left). POSITIVE
//                              when q2 comes after q1. ZERO only when the two crossings
//                              coincide for every eps (the segments meet on the bisector:
//                              never for two distinct edges of a valid domain).
// Violated preconditions (equal indices, collinear i, k, l, a segment with f_ik(a) ==
// f_ik(b)) and NaN or infinite coordinates throw voroclip::Error. Like the other
// predicates these are exact for every finite input; the filters (predicates/src/
// bisector2d.h) decide random input in about 10 ns (bench/bench_predicates.cpp).
Sign bisector_side_vertex2d(const double* pi, const double* pj, const double* a, std::uint32_t i,
                            std::uint32_t j);
Sign bisector_side_edge2d(const double* pi, const double* pk, const double* pj, const double* a,
                          const double* b, std::uint32_t i, std::uint32_t k, std::uint32_t j);
Sign bisector_side_voronoi2d(const double* pi, const double* pk, const double* pl, const double* pj,
                             std::uint32_t i, std::uint32_t k, std::uint32_t l, std::uint32_t j);
Sign compare_on_bisector2d(const double* pi, const double* pk, const double* a1, const double* b1,
                           const double* a2, const double* b2, std::uint32_t i, std::uint32_t k);

// ---------------------------------------------------------------------------------------
// Plain floating-point determinants (the same formulas as the filters, no guarantee).
// For tests and benchmarks only: they can and do return wrong signs near degeneracy.

inline Sign orient2d_fast(const double* a, const double* b, const double* c) {
  return detail::sign_of(detail::orient2d_approx(a, b, c).det);
}
inline Sign orient3d_fast(const double* a, const double* b, const double* c, const double* d) {
  return detail::sign_of(detail::orient3d_approx(a, b, c, d).det);
}
inline Sign incircle_fast(const double* a, const double* b, const double* c, const double* d) {
  return detail::sign_of(detail::incircle_approx(a, b, c, d).det);
}
inline Sign insphere_fast(const double* a, const double* b, const double* c, const double* d,
                          const double* e) {
  return detail::sign_of(detail::insphere_approx(a, b, c, d, e).det);
}

// ---------------------------------------------------------------------------------------
// Voronoi clipping predicates in 3D (clip/, issue 5): the same perturbed power distance as
// the 2D ones above, pi_i(x) = |x - p_i|^2 + eps_i (the lift perturbation of
// insphere_sos), f_ij = pi_i - pi_j = F_ij + eps_i - eps_j with F_ij(x) = |x - p_i|^2 -
// |x - p_j|^2, x on site i's side of bisector(i, j) when f_ij(x) < 0. Each returns the
// exact sign of f_ij at a symbolic vertex, never ZERO when its preconditions hold (i, j, k,
// l, m distinct):
//
//   bisector_side_vertex3d     x = a, a mesh vertex: sign f_ij(a) (an exact tie F_ij(a) = 0
//                              gives POSITIVE when i < j: x goes to the larger index).
//   bisector_side_edge3d       x = [a, b] ∩ bisector(i, k) (f_ik(a), f_ik(b) of opposite
//                              perturbed signs): sign(f_ik(a) f_ij(b) - f_ij(a) f_ik(b))
//                              * sign(f_ik(a) - f_ik(b)), as in 2D. (Only F_ik(a) !=
//                              F_ik(b) is checked: the result is then f_ij at the crossing
//                              of LINE ab.)
//   bisector_side_facet3d      x = the point of the plane of triangle (a, b, c) on
//                              bisectors (i, k) and (i, l) (the two lines they cut in the
//                              plane must cross: denominator below non-zero). With the
//                              3 x 3 matrices of values at a, b, c (columns; 1 a row of ones)
//                                 N = det[f_ij; f_ik; f_il],   D = det[1; f_ik; f_il],
//                              sign f_ij(x) = sign(N) * sign(D). D = det[1; F_ik; F_il] does
//                              not depend on eps; N is linear in the eps:
//                              N = N0 + e_ij det[1; F_ik; F_il] + e_ik det[F_ij; 1; F_il]
//                                  + e_il det[F_ij; F_ik; 1],  e_xy = eps_x - eps_y,
//                              N0 = det[F_ij; F_ik; F_il]. The eps_j coefficient is -D, so
//                              the result is never zero. It depends neither on the order
//                              of a, b, c nor on the roles of i, k, l (x is where
//                              pi_i = pi_k = pi_l).
//   bisector_side_voronoi3d    x = the Voronoi vertex of sites (i, k, l, m) (a tet of their
//                              Delaunay triangulation, not coplanar; any order): sign
//                              f_ij(x) = insphere_sos(i, k, l, m, j) * orient3d(i, k, l, m)
//                              (j inside the sphere: the vertex is nearer j, POSITIVE).
//                              When (i, k, l, m) is a tet of the triangulation built with
//                              insphere_sos (Delaunay3), NEGATIVE for every other site j
//                              except a duplicate of one of them: for p_j == p_v the
//                              perturbation gives every point to the larger of j and v,
//                              while Delaunay3 keeps the smaller (duplicate_of).
//   voronoi_edge_direction3d   the direction in which the Voronoi edge of sites i, k, l (the
//                              dual of Delaunay triangle (i, k, l)), oriented along
//                              n = (p_k - p_i) x (p_l - p_i), crosses the plane of triangle
//                              (a, b, c): sign(n . ((b - a) x (c - a))), POSITIVE when it
//                              goes the way of the triangle's right-hand normal. It is the
//                              sign of D above (D = 4 n . ((b - a) x (c - a))), so it has
//                              no perturbation and is never ZERO at a point that
//                              bisector_side_facet3d accepts; ZERO when the edge is parallel
//                              to the plane or a triangle is degenerate.
// Violated preconditions (equal indices; a segment with F_ik(a) == F_ik(b); D == 0, i.e. a
// degenerate triangle, sites i, k, l collinear, or the plane parallel to the line of the
// two bisectors; coplanar i, k, l, m) and NaN or infinite coordinates throw voroclip::Error.
// Exact for every finite input; the filters (predicates/src/bisector3d.h) decide random
// input in about 11 ns (edge) and 19 ns (facet) (bench/bench_predicates.cpp).
Sign bisector_side_vertex3d(const double* pi, const double* pj, const double* a, std::uint32_t i,
                            std::uint32_t j);
Sign bisector_side_edge3d(const double* pi, const double* pk, const double* pj, const double* a,
                          const double* b, std::uint32_t i, std::uint32_t k, std::uint32_t j);
Sign bisector_side_facet3d(const double* pi, const double* pk, const double* pl, const double* pj,
                           const double* a, const double* b, const double* c, std::uint32_t i,
                           std::uint32_t k, std::uint32_t l, std::uint32_t j);
Sign bisector_side_voronoi3d(const double* pi, const double* pk, const double* pl, const double* pm,
                             const double* pj, std::uint32_t i, std::uint32_t k, std::uint32_t l,
                             std::uint32_t m, std::uint32_t j);
Sign voronoi_edge_direction3d(const double* pi, const double* pk, const double* pl, const double* a,
                              const double* b, const double* c);

// ---------------------------------------------------------------------------------------
// Circumcenters of tetrahedra (3D mesh extraction, issue 6; predicates/src/circumcenter3d.h
// has the derivation and the filter's error bound).
//
//   orient3d_circumcenter(a, b, c, p0, p1, p2, p3)
//       the exact sign of orient3d(a, b, c, x), x the circumcenter of p0, p1, p2, p3 (the
//       point equidistant from the four): on which side of the plane of triangle (a, b, c)
//       x lies, with orient3d's convention, ZERO when x is on the plane. The four points
//       must not be coplanar (then x does not exist: throws voroclip::Error); NaN or
//       infinite coordinates throw too. Exact for every finite input: a filter with a
//       proven bound (about 25 ns on random input), then exact arithmetic (degree 6).
//   orient2d_circumcenter(axis, a, b, p0, p1, p2, p3)
//       the exact sign of the axis component of (b - a) x (x - a), x the circumcenter: with
//       (i, j) = ((axis + 1) % 3, (axis + 2) % 3), orient2d((a_i, a_j), (b_i, b_j),
//       (x_i, x_j)) of the projections along the axis (x on the right of b - a is
//       NEGATIVE; for axis 1 the plane's coordinates are (z, x)). ZERO when the projection
//       of x is on the line through those of a and b (in particular when a and b project
//       to one point). axis is 0, 1 or 2 (else throws); coplanar points and non-finite
//       coordinates throw as above. Exact for every finite input: a filter with a proven
//       bound (about 25 ns), then exact arithmetic (degree 5).
//   circumcenter3d_enclosure(p0, p1, p2, p3, center, halfwidth)
//       the circumcenter in floating point (center, 3 values) and a proven bound on its
//       error: |x_k - center_k| <= halfwidth_k for the exact circumcenter x. Returns false
//       (and no bound) when the tetrahedron is too close to flat for the bound (its volume
//       not certainly non-zero in floating point), the differences to p0 lie outside
//       [2^-150, 2^150], or a value is not finite.
Sign orient3d_circumcenter(const double* a, const double* b, const double* c, const double* p0,
                           const double* p1, const double* p2, const double* p3);
Sign orient2d_circumcenter(int axis, const double* a, const double* b, const double* p0,
                           const double* p1, const double* p2, const double* p3);
namespace detail {
// circumcenter3d's bounds (predicates/src/circumcenter3d.h derives them): |D~ - D| <=
// kCircumcenterDetBound D1 D2 D3 and |Nv~_x - Nv_x| <= kCircumcenterNumBound D1 D2 D3 (D1 +
// D2 + D3) for L-infinity norms Dk of the differences in [kCircumcenterLower,
// kCircumcenterUpper]; the floating-point result is used when its error is below
// kCircumcenterLimit times D1 + D2 + D3.
inline constexpr double kCircumcenterDetBound = 5.33e-15;  // 48 mu
inline constexpr double kCircumcenterNumBound = 8.00e-15;  // 72 mu
inline constexpr double kCircumcenterLower = 0x1p-150, kCircumcenterUpper = 0x1p+150;
inline constexpr double kCircumcenterLimit = 0x1p-36;

// The floating-point path of circumcenter3d, inline (the Voronoi vertices of a clipped
// diagram are its hot loop): true with the centre when its bound allows. Evaluated in
// exactly the order the bound was derived for (circumcenter_approx in circumcenter3d.h).
inline bool circumcenter3d_fast(const double* p0, const double* p1, const double* p2,
                                const double* p3, double* center) {
  const double ax = p1[0] - p0[0], ay = p1[1] - p0[1], az = p1[2] - p0[2];
  const double bx = p2[0] - p0[0], by = p2[1] - p0[1], bz = p2[2] - p0[2];
  const double cx = p3[0] - p0[0], cy = p3[1] - p0[1], cz = p3[2] - p0[2];
  const double n1 = std::max(std::max(std::fabs(ax), std::fabs(ay)), std::fabs(az));
  const double n2 = std::max(std::max(std::fabs(bx), std::fabs(by)), std::fabs(bz));
  const double n3 = std::max(std::max(std::fabs(cx), std::fabs(cy)), std::fabs(cz));
  // (d2 x d3), (d3 x d1), (d1 x d2), |dk|^2.
  const double c23x = by * cz - bz * cy, c23y = bz * cx - bx * cz, c23z = bx * cy - by * cx;
  const double c31x = cy * az - cz * ay, c31y = cz * ax - cx * az, c31z = cx * ay - cy * ax;
  const double c12x = ay * bz - az * by, c12y = az * bx - ax * bz, c12z = ax * by - ay * bx;
  const double l1 = (ax * ax + ay * ay) + az * az;
  const double l2 = (bx * bx + by * by) + bz * bz;
  const double l3 = (cx * cx + cy * cy) + cz * cz;
  const double nvx = (l1 * c23x + l2 * c31x) + l3 * c12x;
  const double nvy = (l1 * c23y + l2 * c31y) + l3 * c12y;
  const double nvz = (l1 * c23z + l2 * c31z) + l3 * c12z;
  const double det = (ax * c23x + ay * c23y) + az * c23z;
  const double pd = (n1 * n2) * n3, ps = (n1 + n2) + n3;
  // In range. (A NaN coordinate can hide from std::max, but makes q NaN below.)
  if (!(std::min(std::min(n1, n2), n3) >= kCircumcenterLower &&
        std::max(std::max(n1, n2), n3) <= kCircumcenterUpper)) {
    return false;
  }
  // Each coordinate of Nv~ / (2 D~) is within (eN + |Nv~_x| eD / |D~|) / (2 delta) of the
  // exact one (delta = |D~| - eD > 0): below the limit for all three when eN |D~| +
  // max |Nv~_x| eD <= 2 delta |D~| limit (its own roundings covered by 1 + 2^-40).
  const double e_det = kCircumcenterDetBound * pd, e_num = kCircumcenterNumBound * (pd * ps);
  const double abs_det = std::fabs(det), delta = abs_det - e_det;
  const double nv_max = std::max(std::max(std::fabs(nvx), std::fabs(nvy)), std::fabs(nvz));
  if (!(delta > 0 && (e_num * abs_det + nv_max * e_det) * (1 + 0x1p-40) <=
                         2 * delta * abs_det * (kCircumcenterLimit * ps))) {
    return false;
  }
  const double det2 = det + det;
  const double qx = nvx / det2, qy = nvy / det2, qz = nvz / det2;
  if (!(std::isfinite(qx) && std::isfinite(qy) && std::isfinite(qz))) return false;
  center[0] = p0[0] + qx;
  center[1] = p0[1] + qy;
  center[2] = p0[2] + qz;
  return true;
}

// Nv and D exactly, each rounded, then divided (circumcenter3d.cpp).
void circumcenter3d_exact(const double* p0, const double* p1, const double* p2, const double* p3,
                          double* center);
}  // namespace detail

// The circumcentre of p0..p3 (not coplanar), accurately: the floating-point formula
// p0 + Nv / (2 D) (circumcenter3d.h) when its proven error bound is below 2^-36 of the
// tet's size (the sum of the L-infinity distances to p0) in every coordinate, else Nv and
// D in exact arithmetic, each rounded, then divided (a few ulps of the exact offset from
// p0). So a nearly flat tet (a sliver of nearly cospherical points, whose floating-point D
// is all rounding error, or zero) still gets a finite, accurate centre. Throws Error for
// coplanar points or non-finite coordinates. (When the coordinates' exponents are too far
// apart for expansions, the floating-point formula is used.)
inline void circumcenter3d(const double* p0, const double* p1, const double* p2, const double* p3,
                           double* center) {
  if (!detail::circumcenter3d_fast(p0, p1, p2, p3, center)) {
    detail::circumcenter3d_exact(p0, p1, p2, p3, center);
  }
}
bool circumcenter3d_enclosure(const double* p0, const double* p1, const double* p2,
                              const double* p3, double* center, double* halfwidth);

// ---------------------------------------------------------------------------------------
// Constructions of the clipped diagrams' vertices (predicates/src/constructions.cpp has the
// derivations and the filters' error bounds). Coordinates only (no decision depends on
// them), but accurate however degenerate the input: a floating-point formula when its
// proven error bound is below kConstructionLimit of the input's size, else the exact
// numerator and denominator, each rounded, then divided (a few ulps of the exact offset
// from the first point). A plain floating-point formula is not enough: for the Voronoi
// vertex of three sites of which two are 3e-48 apart its determinant is rounding noise
// (a NaN vertex, fuzz_sites' clip2d_nan_voronoi_vertex); the point where a boundary facet
// meets bisector(p0, p1) and bisector(p0, p2) for p1, p2 3e-14 apart, two planes at an
// angle of 3e-14, came out 1.3e-3 away from the exact one (the negative cell volume of
// fuzz_sites' clip3d_near_coincident_facet_point).
//
//   circumcenter2d(a, b, c, center)
//       the circumcentre of the triangle a, b, c (center: 2 values). Throws Error for
//       collinear points or non-finite coordinates.
//   plane_bisectors_point3d(a, b, c, p0, p1, p2, x)
//       the point x of the plane through a, b, c on bisector(p0, p1) and on bisector(p0,
//       p2) (equidistant from p0, p1, p2). Returns false, x unchanged, when that point is
//       not unique (the plane and the bisectors do not meet in one point, exactly) or a
//       coordinate is not finite.
inline constexpr double kConstructionLimit = 0x1p-40;
void circumcenter2d(const double* a, const double* b, const double* c, double* center);
bool plane_bisectors_point3d(const double* a, const double* b, const double* c, const double* p0,
                             const double* p1, const double* p2, double* x);

// The same points with an absolute accuracy (a few ulps of the point itself, not of its
// offset from the first site), always by the exact stage (numerator N + 2 D origin): for
// sites far from the point, such as sites 1e20 away whose Voronoi vertex lies in a unit
// domain, where origin + N / (2 D) rounds away all of the point's bits. Slower; the clipped
// diagrams use them only for sites far outside the domain.
void circumcenter2d_absolute(const double* a, const double* b, const double* c, double* center);
void circumcenter3d_absolute(const double* p0, const double* p1, const double* p2, const double* p3,
                             double* center);
bool plane_bisectors_point3d_absolute(const double* a, const double* b, const double* c,
                                      const double* p0, const double* p1, const double* p2,
                                      double* x);
// |x - p|^2 - |x - q|^2 computed exactly, then rounded (relative error a few ulps), however
// far p and q are from x: in floating point 2 (x - (p + q) / 2).(q - p) keeps nothing of it
// when |p + q| / 2 is 1e19 times the distance from x to the bisector. Overflow gives inf.
// Throws Error for non-finite coordinates.
double bisector_value2d_exact(const double* x, const double* p, const double* q);
double bisector_value3d_exact(const double* x, const double* p, const double* q);

}  // namespace voroclip
