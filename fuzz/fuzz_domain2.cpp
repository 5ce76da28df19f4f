// libFuzzer target: the 2D domain validator (Domain2's constructor) on rings of a valid
// structure (1 to 4 rings of 3 to 8 points, JSON-like polygons or .poly-like nesting with
// hole markers) with fuzzed coordinates (fuzz_coords.h). Any voroclip::Error is a verdict;
// a crash, a sanitizer report, another exception or a hang is a finding.
#include <fuzzer/FuzzedDataProvider.h>

#include "fuzz_common.h"
#include "fuzz_coords.h"
#include "voroclip/clip.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider fdp(data, size);
  voroclip::PolygonRings rings;
  rings.source = "fuzz";
  const bool nesting = fdp.ConsumeBool();  // .poly: roles from nesting; else JSON polygons
  const int nb_rings = fdp.ConsumeIntegralInRange<int>(1, 4);
  voroclip::fuzz::CoordSource coord(fdp);
  rings.ring_begin.push_back(0);
  std::int32_t polygon = 0;
  for (int r = 0; r < nb_rings; ++r) {
    const int n = fdp.ConsumeIntegralInRange<int>(3, 8);
    for (int k = 0; k < n; ++k) {
      rings.xy.push_back(coord.next());
      rings.xy.push_back(coord.next());
    }
    rings.ring_begin.push_back(static_cast<std::uint32_t>(rings.xy.size() / 2));
    if (!nesting && r > 0 && fdp.ConsumeBool()) ++polygon;  // a new polygon, else a hole
    rings.ring_polygon.push_back(nesting ? -1 : polygon);
    rings.ring_line.push_back(static_cast<std::uint32_t>(r + 1));
  }
  if (nesting) {
    const int nb_holes = fdp.ConsumeIntegralInRange<int>(0, 2);
    for (int h = 0; h < nb_holes; ++h) {
      rings.hole_points.push_back(coord.next());
      rings.hole_points.push_back(coord.next());
      rings.hole_line.push_back(static_cast<std::uint32_t>(nb_rings + h + 1));
    }
  }
  voroclip::fuzz::expect_only_error([&] {
    const voroclip::Domain2 domain(rings);
    if (domain.nb_rings() == 0 || domain.nb_rings() > static_cast<std::uint32_t>(nb_rings) ||
        domain.nb_vertices() < 3 * domain.nb_rings()) {
      voroclip::fuzz::finding("a validated domain with impossible ring or vertex counts");
    }
  });
  return 0;
}
