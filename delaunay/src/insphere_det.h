// The floating-point insphere determinant of the static filter, two lanes at a time.
//
// insphere_det(a, b, c, d, e) is bit for bit detail::insphere_approx(a, b, c, d, e).det
// (voroclip/predicates.h): every product, sum and difference of that expression is the
// same IEEE operation on the same operands, the SSE2 lanes only pairing independent ones,
// so the error bound proven for it (scripts/filter_bounds.py) holds unchanged. With
// -ffp-contract=off no operation is fused. About 60 instructions instead of 105 for the
// scalar expression; Delaunay3 calls it about 43 times per inserted point.
//
// Pairing (lane 0, lane 1), with aex = a.x - e.x etc.:
//   (ab, cd), (bc, da), (ac, bd)      2x2 minors of the xy differences
//   (abc, bcd), (cda, dab)            the 3x3 minors, each as written in insphere_approx
//   (alift, blift), (clift, dlift)    squared distances to e
//   det = (dlift abc - clift dab) + (blift cda - alift bcd)
#pragma once

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define VOROCLIP_INSPHERE_DET_AVX2 1
#endif

#include "voroclip/predicates.h"

namespace voroclip::detail {

inline double insphere_det(const double* a, const double* b, const double* c, const double* d,
                           const double* e) {
#if defined(__SSE2__)
  const __m128d exy = _mm_loadu_pd(e);
  const __m128d ae = _mm_sub_pd(_mm_loadu_pd(a), exy);  // (aex, aey)
  const __m128d be = _mm_sub_pd(_mm_loadu_pd(b), exy);
  const __m128d ce = _mm_sub_pd(_mm_loadu_pd(c), exy);
  const __m128d de = _mm_sub_pd(_mm_loadu_pd(d), exy);
  const __m128d ez = _mm_set1_pd(e[2]);
  const __m128d z_ab = _mm_sub_pd(_mm_set_pd(b[2], a[2]), ez);  // (aez, bez)
  const __m128d z_cd = _mm_sub_pd(_mm_set_pd(d[2], c[2]), ez);  // (cez, dez)

  const __m128d x_ab = _mm_unpacklo_pd(ae, be);  // (aex, bex)
  const __m128d y_ab = _mm_unpackhi_pd(ae, be);  // (aey, bey)
  const __m128d x_cd = _mm_unpacklo_pd(ce, de);  // (cex, dex)
  const __m128d y_cd = _mm_unpackhi_pd(ce, de);  // (cey, dey)
  const __m128d x_ac = _mm_unpacklo_pd(ae, ce);  // (aex, cex)
  const __m128d y_ac = _mm_unpackhi_pd(ae, ce);  // (aey, cey)
  const __m128d x_bd = _mm_unpacklo_pd(be, de);  // (bex, dex)
  const __m128d y_bd = _mm_unpackhi_pd(be, de);  // (bey, dey)
  const __m128d x_ca = _mm_unpacklo_pd(ce, ae);  // (cex, aex)
  const __m128d y_ca = _mm_unpackhi_pd(ce, ae);  // (cey, aey)
  // ab = aex bey - bex aey, cd = cex dey - dex cey
  const __m128d ab_cd = _mm_sub_pd(_mm_mul_pd(x_ac, y_bd), _mm_mul_pd(x_bd, y_ac));
  // bc = bex cey - cex bey, da = dex aey - aex dey
  const __m128d bc_da = _mm_sub_pd(_mm_mul_pd(x_bd, y_ca), _mm_mul_pd(x_ca, y_bd));
  // ac = aex cey - cex aey, bd = bex dey - dex bey
  const __m128d ac_bd = _mm_sub_pd(_mm_mul_pd(x_ab, y_cd), _mm_mul_pd(x_cd, y_ab));

  // abc = aez bc - bez ac + cez ab, bcd = bez cd - cez bd + dez bc
  const __m128d bc_cd = _mm_shuffle_pd(bc_da, ab_cd, 2);  // (bc, cd)
  const __m128d z_bc = _mm_shuffle_pd(z_ab, z_cd, 1);     // (bez, cez)
  const __m128d ab_bc = _mm_unpacklo_pd(ab_cd, bc_da);    // (ab, bc)
  const __m128d abc_bcd = _mm_add_pd(_mm_sub_pd(_mm_mul_pd(z_ab, bc_cd), _mm_mul_pd(z_bc, ac_bd)),
                                     _mm_mul_pd(z_cd, ab_bc));
  // cda = cez da + dez ac + aez cd, dab = dez ab + aez bd + bez da
  const __m128d da_ab = _mm_shuffle_pd(bc_da, ab_cd, 1);  // (da, ab)
  const __m128d z_da = _mm_shuffle_pd(z_cd, z_ab, 1);     // (dez, aez)
  const __m128d cd_da = _mm_unpackhi_pd(ab_cd, bc_da);    // (cd, da)
  const __m128d cda_dab = _mm_add_pd(_mm_add_pd(_mm_mul_pd(z_cd, da_ab), _mm_mul_pd(z_da, ac_bd)),
                                     _mm_mul_pd(z_ab, cd_da));

  // alift = aex aex + aey aey + aez aez, ...
  const __m128d lift_ab = _mm_add_pd(_mm_add_pd(_mm_mul_pd(x_ab, x_ab), _mm_mul_pd(y_ab, y_ab)),
                                     _mm_mul_pd(z_ab, z_ab));
  const __m128d lift_cd = _mm_add_pd(_mm_add_pd(_mm_mul_pd(x_cd, x_cd), _mm_mul_pd(y_cd, y_cd)),
                                     _mm_mul_pd(z_cd, z_cd));

  // (dlift abc - clift dab, blift cda - alift bcd), then the sum of the two lanes.
  const __m128d lift_db = _mm_shuffle_pd(lift_cd, lift_ab, 3);  // (dlift, blift)
  const __m128d abc_cda = _mm_unpacklo_pd(abc_bcd, cda_dab);    // (abc, cda)
  const __m128d lift_ca = _mm_unpacklo_pd(lift_cd, lift_ab);    // (clift, alift)
  const __m128d dab_bcd = _mm_shuffle_pd(cda_dab, abc_bcd, 3);  // (dab, bcd)
  const __m128d halves = _mm_sub_pd(_mm_mul_pd(lift_db, abc_cda), _mm_mul_pd(lift_ca, dab_bcd));
  return _mm_cvtsd_f64(halves) + _mm_cvtsd_f64(_mm_unpackhi_pd(halves, halves));
#else
  return insphere_approx(a, b, c, d, e).det;
#endif
}

#if defined(VOROCLIP_INSPHERE_DET_AVX2)
// The same determinant, four lanes at a time, for code compiled with AVX2 (the caller checks
// the CPU). Again bit for bit insphere_approx's value: lanes pair independent operations,
// and a difference x - y z is computed as x + y (-z) where -z comes exactly from a
// reversed 2x2 minor (round to nearest is symmetric, so the result is the same double).
// Lanes (a, c, b, d): X = (aex, cex, bex, dex), likewise Y, Z.
//   M1  = X Y[p] - X[p] Y, p = (2, 3, 1, 0):   (ab, cd, bc, da)
//   M2  = X[s] Y - X Y[s], s = (1, 0, 3, 2):   (-ac, ac, -bd, bd)
//   R   = (Z M1[p] + Z[p] M2) + Z[s] M1:       (abc, cda, bcd, dab)
//   L   = (X X + Y Y) + Z Z:                   (alift, clift, blift, dlift)
//   L[(3, 2, 0, 1)] R = (dlift abc, blift cda, alift bcd, clift dab), then
//   det = (dlift abc - clift dab) + (blift cda - alift bcd).
__attribute__((target("avx2"))) inline double insphere_det_avx2(const double* a, const double* b,
                                                                const double* c, const double* d,
                                                                const double* e) {
  const __m256d exy = _mm256_broadcast_pd(reinterpret_cast<const __m128d*>(e));
  const __m256d ab_xy = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(a)),
                                             _mm_loadu_pd(b), 1);  // (ax, ay, bx, by)
  const __m256d cd_xy = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(c)),
                                             _mm_loadu_pd(d), 1);  // (cx, cy, dx, dy)
  const __m256d ab_e = _mm256_sub_pd(ab_xy, exy);
  const __m256d cd_e = _mm256_sub_pd(cd_xy, exy);
  const __m256d x = _mm256_unpacklo_pd(ab_e, cd_e);  // (aex, cex, bex, dex)
  const __m256d y = _mm256_unpackhi_pd(ab_e, cd_e);  // (aey, cey, bey, dey)
  const __m128d ac_z = _mm_loadh_pd(_mm_load_sd(a + 2), c + 2);
  const __m128d bd_z = _mm_loadh_pd(_mm_load_sd(b + 2), d + 2);
  const __m256d z = _mm256_sub_pd(_mm256_insertf128_pd(_mm256_castpd128_pd256(ac_z), bd_z, 1),
                                  _mm256_broadcast_sd(e + 2));

  constexpr int kP = 2 | (3 << 2) | (1 << 4) | (0 << 6);  // lane i takes lane p[i]
  constexpr int kS = 0x5;                                 // swap within each 128-bit half
  const __m256d x_p = _mm256_permute4x64_pd(x, kP);
  const __m256d y_p = _mm256_permute4x64_pd(y, kP);
  const __m256d m1 = _mm256_sub_pd(_mm256_mul_pd(x, y_p), _mm256_mul_pd(x_p, y));
  const __m256d x_s = _mm256_permute_pd(x, kS);
  const __m256d y_s = _mm256_permute_pd(y, kS);
  const __m256d m2 = _mm256_sub_pd(_mm256_mul_pd(x_s, y), _mm256_mul_pd(x, y_s));
  const __m256d r = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(z, _mm256_permute4x64_pd(m1, kP)),
                                                _mm256_mul_pd(_mm256_permute4x64_pd(z, kP), m2)),
                                  _mm256_mul_pd(_mm256_permute_pd(z, kS), m1));
  const __m256d lift =
      _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(x, x), _mm256_mul_pd(y, y)), _mm256_mul_pd(z, z));
  constexpr int kLift = 3 | (2 << 2) | (0 << 4) | (1 << 6);
  const __m256d terms = _mm256_mul_pd(_mm256_permute4x64_pd(lift, kLift), r);
  const __m128d low = _mm256_castpd256_pd128(terms);  // (dl abc, bl cda)
  const __m128d high =
      _mm256_castpd256_pd128(_mm256_permute4x64_pd(terms, 3 | (2 << 2)));  // (cl dab, al bcd)
  const __m128d halves = _mm_sub_pd(low, high);
  return _mm_cvtsd_f64(_mm_add_sd(halves, _mm_unpackhi_pd(halves, halves)));
}
#endif

}  // namespace voroclip::detail
