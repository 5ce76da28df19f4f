// libFuzzer target: polygon files through read_polygon(std::istream&, name): JSON when the
// first non-blank byte is '[' or '{', Triangle's .poly otherwise.
#include <cctype>
#include <cmath>
#include <sstream>
#include <string>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text = voroclip::fuzz::bytes(data, size);
  std::size_t i = 0;
  while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
  const bool json = i < text.size() && (text[i] == '[' || text[i] == '{');
  voroclip::fuzz::expect_only_error([&] {
    std::istringstream in(text);
    const voroclip::PolygonRings r = voroclip::read_polygon(in, json ? "fuzz.json" : "fuzz.poly");
    // What read_polygon promises: rings that cover the points, in order; finite values.
    const std::uint32_t nr = r.nb_rings();
    if (r.xy.size() % 2 != 0 || r.ring_begin.empty() || r.ring_begin.front() != 0 ||
        r.ring_begin.back() != r.xy.size() / 2 || r.ring_polygon.size() != nr ||
        r.ring_line.size() != nr) {
      voroclip::fuzz::finding("ring arrays of inconsistent sizes");
    }
    for (std::uint32_t k = 0; k < nr; ++k) {
      if (r.ring_begin[k] > r.ring_begin[k + 1]) voroclip::fuzz::finding("ring offsets decrease");
    }
    for (const double x : r.xy) {
      if (!std::isfinite(x)) voroclip::fuzz::finding("a coordinate that is not finite");
    }
  });
  return 0;
}
