// Uses the installed library through its public headers only; check_install.cmake compares
// the output with the known exact answers.
#include <iostream>

#include "voroclip/core.h"
#include "voroclip/predicates.h"

namespace {

const char* name(voroclip::Sign s) {
  return s == voroclip::Sign::positive ? "positive"
                                       : (s == voroclip::Sign::negative ? "negative" : "zero");
}

}  // namespace

int main() {
  using voroclip::Sign;
  // Points of the classroom example of Kettner et al. (CGTA 2008): 0.5 + 2^-53 is the
  // double right after 0.5; naive floating point gets the first two wrong.
  const double u = 0x1p-53;
  const double q[2] = {12, 12}, r[2] = {24, 24};
  const double on_line[2] = {0.5 + u, 0.5 + u};
  const double below[2] = {0.5 + u, 0.5};
  const double a[2] = {0, 0}, b[2] = {1, 0}, c[2] = {0, 1};
  const double centre[2] = {0.5, 0.5}, opposite[2] = {1, 1};
  const double cube[5][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};

  std::cout << "voroclip " << voroclip::version() << "\n"
            << "orient2d ccw: " << name(voroclip::orient2d(a, b, c)) << "\n"
            << "orient2d classroom point on the line: " << name(voroclip::orient2d(on_line, q, r))
            << "\n"
            << "orient2d classroom point off the line: " << name(voroclip::orient2d(below, q, r))
            << "\n"
            << "incircle inside: " << name(voroclip::incircle(a, b, c, centre)) << "\n"
            << "incircle cocircular: " << name(voroclip::incircle(a, b, c, opposite)) << "\n"
            << "orient3d: " << name(voroclip::orient3d(cube[0], cube[1], cube[2], cube[3])) << "\n"
            << "insphere cospherical: "
            << name(voroclip::insphere(cube[0], cube[1], cube[2], cube[3], cube[4])) << "\n";
  const Sign sos =
      voroclip::insphere_sos(cube[0], cube[1], cube[2], cube[3], cube[4], 0, 1, 2, 3, 4);
  std::cout << "insphere_sos cospherical: " << (sos == Sign::zero ? "zero" : "nonzero") << "\n";
  return 0;
}
