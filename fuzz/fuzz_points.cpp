// libFuzzer target: point files (JSON or text) through read_points(std::istream&, name,
// dimension), read as 2D and as 3D points.
#include <cmath>
#include <sstream>
#include <string>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text = voroclip::fuzz::bytes(data, size);
  for (const int dimension : {2, 3}) {
    voroclip::fuzz::expect_only_error([&] {
      std::istringstream in(text);
      const std::vector<double> p = voroclip::read_points(in, "fuzz.txt", dimension);
      if (p.size() % static_cast<std::size_t>(dimension) != 0) {
        voroclip::fuzz::finding("a partial point");
      }
      for (const double x : p) {
        if (!std::isfinite(x)) voroclip::fuzz::finding("a coordinate that is not finite");
      }
    });
  }
  return 0;
}
