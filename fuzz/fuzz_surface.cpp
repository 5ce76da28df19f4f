// libFuzzer target: triangle surface files through read_surface(std::istream&, name). The
// format is recognised from the bytes as a user's file would be named: "ply" first: .ply;
// a first word ending in "OFF": .off; "solid" first, or the size of a binary STL: .stl;
// anything else: .obj.
#include <cctype>
#include <cstring>
#include <sstream>
#include <string>

#include "fuzz_common.h"

namespace {

const char* surface_name(const std::string& s) {
  if (s.rfind("ply", 0) == 0) return "fuzz.ply";
  std::size_t i = 0;
  while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
  std::size_t j = i;
  while (j < s.size() && !std::isspace(static_cast<unsigned char>(s[j]))) ++j;
  const std::string first = s.substr(i, j - i);
  if (first.size() >= 3 && first.compare(first.size() - 3, 3, "OFF") == 0) return "fuzz.off";
  if (first.rfind("solid", 0) == 0) return "fuzz.stl";
  if (s.size() >= 84) {
    std::uint32_t n = 0;
    std::memcpy(&n, s.data() + 80, 4);  // little endian hosts only, as the CI machine
    if (s.size() == 84 + 50 * std::uint64_t{n}) return "fuzz.stl";
  }
  return "fuzz.obj";
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text = voroclip::fuzz::bytes(data, size);
  voroclip::fuzz::expect_only_error([&] {
    std::istringstream in(text);
    const voroclip::TriangleSurface s = voroclip::read_surface(in, surface_name(text));
    // What read_surface promises: at least one triangle, indices in range, finite
    // coordinates, one line and one face number per triangle.
    if (s.xyz.size() % 3 != 0 || s.triangles.size() % 3 != 0 || s.triangles.empty() ||
        s.triangle_line.size() != s.nb_triangles() || s.triangle_face.size() != s.nb_triangles()) {
      voroclip::fuzz::finding("surface arrays of inconsistent sizes");
    }
    for (const std::uint32_t v : s.triangles) {
      if (v >= s.nb_vertices()) voroclip::fuzz::finding("a vertex index out of range");
    }
    for (const double x : s.xyz) {
      if (!std::isfinite(x)) voroclip::fuzz::finding("a coordinate that is not finite");
    }
  });
  return 0;
}
