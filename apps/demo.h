// The `voroclip demo` command: the exact predicate kernel on two bundled examples.
//
// 1. The "classroom example" of Kettner, Mehlhorn, Pion, Schirra and Yap, "Classroom
//    examples of robustness problems in geometric computations", CGTA 40(1), 2008, sec. 3:
//    orient2d(p, q, r) for q = (12, 12), r = (24, 24) and the 256 x 256 points
//    p = (0.5 + i*u, 0.5 + j*u), u = 2^-53 (consecutive doubles above 0.5). All of them are
//    within a few ulps of the line y = x; the exact determinant is 12 (p.y - p.x), so the
//    exact sign is known in closed form and the demo checks every exact answer against it.
// 2. Symbolic perturbation on the corners of the unit cube: all eight are cospherical, so
//    insphere is exactly zero for every 5-tuple and insphere_sos must decide.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <vector>

#include "voroclip/predicates.h"

namespace voroclip::cli {

struct SignCounts {
  std::size_t positive = 0;
  std::size_t zero = 0;
  std::size_t negative = 0;
  void add(Sign s);
};

struct ClassroomResult {
  static constexpr std::size_t kGrid = 256;
  // Signs of point (i, j) at [j * kGrid + i].
  std::vector<Sign> naive;
  std::vector<Sign> exact;
  SignCounts naive_counts;
  SignCounts exact_counts;
  std::size_t naive_wrong = 0;
  // The wrong naive signs split by kind: zero for a point off the line, non-zero for a point
  // on it, and the opposite sign.
  std::size_t naive_false_zero = 0;
  std::size_t naive_false_nonzero = 0;
  std::size_t naive_flipped = 0;
};

struct CubeTest {
  std::uint32_t corner;  // the fifth point; corner k is (k & 1, (k >> 1) & 1, (k >> 2) & 1)
  Sign exact;
  Sign sos;
};

struct CubeResult {
  std::array<std::uint32_t, 4> tetrahedron;  // corners in positive orient3d order
  std::vector<CubeTest> tests;
  SignCounts sos_counts;
};

/// Evaluates both predicates on the whole grid in parallel (one slot per point, so the
/// result does not depend on the number of threads) and checks every exact sign against
/// the closed form; throws voroclip::Error if one disagrees.
ClassroomResult run_classroom_example();

/// Throws voroclip::Error if an exact insphere on the cube is not zero.
CubeResult run_cube_example();

/// A two-panel SVG picture (naive | exact) of the classroom example's signs.
void write_classroom_svg(const ClassroomResult& result, std::ostream& out);

}  // namespace voroclip::cli
