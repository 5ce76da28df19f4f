// libFuzzer target: the surface validator (Surface3's constructor) on a triangle soup of
// a valid structure with fuzzed coordinates and indices: an octahedron, two octahedra (a
// second shell of fuzzed scale and orientation: disjoint, nested or crossing), or a random
// soup of 4 to 16 triangles on 4 to 10 vertices; then some vertices moved and some
// corners re-pointed, all from the fuzzer's bytes (coordinates: fuzz_coords.h).
#include <fuzzer/FuzzedDataProvider.h>

#include <algorithm>
#include <utility>

#include "fuzz_common.h"
#include "fuzz_coords.h"
#include "voroclip/clip.h"

namespace {

// The octahedron with vertices +-e_i, faces outward.
constexpr double kOctaXyz[18] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
constexpr std::uint32_t kOctaTri[24] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4,
                                        2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};

void add_octahedron(voroclip::TriangleSurface& s, double scale, double shift, bool reversed) {
  const auto base = static_cast<std::uint32_t>(s.nb_vertices());
  for (const double x : kOctaXyz) s.xyz.push_back(scale * x + shift);
  for (std::size_t t = 0; t < 8; ++t) {
    std::uint32_t c[3] = {kOctaTri[3 * t], kOctaTri[3 * t + 1], kOctaTri[3 * t + 2]};
    if (reversed) std::swap(c[1], c[2]);
    for (const std::uint32_t v : c) s.triangles.push_back(base + v);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider fdp(data, size);
  voroclip::TriangleSurface s;
  s.source = "fuzz";
  voroclip::fuzz::CoordSource coord(fdp);
  switch (fdp.ConsumeIntegralInRange<int>(0, 2)) {
    case 0:
      add_octahedron(s, 1, 0, false);
      break;
    case 1: {
      add_octahedron(s, 1, 0, false);
      const double scale = fdp.ConsumeIntegralInRange<int>(1, 8) / 4.0;
      const double shift = fdp.ConsumeIntegralInRange<int>(-4, 4) / 2.0;
      add_octahedron(s, scale, shift, fdp.ConsumeBool());
      break;
    }
    default: {
      const int nv = fdp.ConsumeIntegralInRange<int>(4, 10);
      const int nt = fdp.ConsumeIntegralInRange<int>(4, 16);
      for (int k = 0; k < 3 * nv; ++k) s.xyz.push_back(coord.next());
      for (int k = 0; k < 3 * nt; ++k) {
        s.triangles.push_back(fdp.ConsumeIntegralInRange<std::uint32_t>(0, nv - 1));
      }
      break;
    }
  }
  // Moves: vertex v to fuzzed coordinates.
  const int moves = fdp.ConsumeIntegralInRange<int>(0, 4);
  for (int m = 0; m < moves; ++m) {
    const auto v = fdp.ConsumeIntegralInRange<std::uint32_t>(0, s.nb_vertices() - 1);
    for (int k = 0; k < 3; ++k) s.xyz[3 * v + k] = coord.next();
  }
  // Re-pointed corners: a corner to any vertex, or one past the last (out of range).
  const int repoints = fdp.ConsumeIntegralInRange<int>(0, 2);
  for (int m = 0; m < repoints; ++m) {
    const auto c = fdp.ConsumeIntegralInRange<std::size_t>(0, s.triangles.size() - 1);
    s.triangles[c] = fdp.ConsumeIntegralInRange<std::uint32_t>(0, s.nb_vertices());
  }
  voroclip::Surface3Options options;
  options.reorient = fdp.ConsumeBool();
  voroclip::fuzz::expect_only_error([&] {
    const voroclip::Surface3 surface(s, options);
    std::uint64_t in_shells = 0;
    for (const auto& shell : surface.shells()) in_shells += shell.nb_triangles;
    if (in_shells != s.nb_triangles()) {
      voroclip::fuzz::finding("the shells of a validated surface do not hold every triangle");
    }
  });
  return 0;
}
