// libFuzzer target: small site sets through Delaunay2/3 and ClippedVoronoi2/3 (issue 34).
//
// The bytes decode to at most 64 sites in 2D or 3D, from one of three decoders chosen by the
// first byte:
//   grid     coordinates on a 9-step grid over [-0.25, 1.25]: duplicates, collinear and
//            coplanar sets, cocircular / cospherical sets, sites on the domain's boundary;
//   near     a grid point plus a perturbation m * 2^e with e in [-80, -1]: nearly degenerate
//            sets, the predicates' exact stages;
//   wide     sign * m * 2^e with e in [-120, 7]: magnitudes from 1e-36 to 256 around a
//            domain of size 1, far sites and sites packed in a corner.
// Each set is triangulated and its Voronoi diagram clipped to a fixed domain: in 2D the
// unit square with the square hole [0.375, 0.625]^2, in 3D the unit cube. Checked facts
// (a violated one aborts, which libFuzzer reports):
//   - check_topology() and check_delaunay() of the triangulation are empty;
//   - every finite triangle (tet) has an empty circumcircle (sphere): no site strictly
//     inside, by the exact filtered incircle (insphere), brute force over all sites;
//   - nearest_vertex() at probe points is a nearest site (exact compare_distance, brute
//     force), and that site's clipped cell has positive area (volume) when the probe is
//     inside the domain (the cell contains the probe and is full-dimensional there);
//   - the cells' areas (volumes) are >= 0 and sum to the domain's to 1e-9 relative.
// voroclip::Error (fewer than 3 affinely independent sites, ...) is a clean refusal; any
// other exception escapes and is a finding.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "support/surfaces.h"
#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/delaunay.h"
#include "voroclip/predicates.h"

namespace {

using voroclip::Sign;

constexpr std::size_t kMaxSites = 64;

void fail(const char* what, std::size_t detail) {
  std::fprintf(stderr, "fuzz_sites: %s (%zu)\n", what, detail);
  std::abort();
}

// Reads the bytes in order; zero once they run out.
struct Bytes {
  const std::uint8_t* data;
  std::size_t size, pos = 0;
  std::uint8_t next() { return pos < size ? data[pos++] : 0; }
  std::uint64_t next_bits(int bytes) {
    std::uint64_t v = 0;
    for (int i = 0; i < bytes; ++i) v = (v << 8) | next();
    return v;
  }
  std::size_t left() const { return size - pos; }
};

double grid_value(std::uint8_t b) { return -0.25 + 0.1875 * (b % 9); }

// One coordinate, by the decoder `mode` (see the header).
double decode(Bytes& in, int mode) {
  switch (mode) {
    case 0:
      return grid_value(in.next());
    case 1: {
      const double base = grid_value(in.next());
      const std::uint8_t e = in.next();
      const double m = static_cast<double>(in.next_bits(2)) / 65536.0;
      return base + ((e & 0x80) ? -1 : 1) * std::ldexp(m, -1 - (e % 80));
    }
    default: {
      const std::uint8_t e = in.next();
      const double m = 1.0 + static_cast<double>(in.next_bits(6) >> 4) * 0x1p-44;
      return ((e & 0x80) ? -1 : 1) * std::ldexp(m, 7 - (e % 128));
    }
  }
}

std::size_t bytes_per_coordinate(int mode) { return mode == 0 ? 1 : mode == 1 ? 4 : 7; }

voroclip::PolygonRings square_with_hole() {
  voroclip::PolygonRings p;
  p.source = "fuzz square with hole";
  p.xy = {0,     0,     1,     0,     1,     1,     0,     1,       // outer, counter-clockwise
          0.375, 0.375, 0.375, 0.625, 0.625, 0.625, 0.625, 0.375};  // hole, clockwise
  p.ring_begin = {0, 4, 8};
  p.ring_polygon = {0, 0};
  p.ring_line = {0, 0};
  return p;
}

bool inside_square_with_hole(const double* p) {
  const auto in = [](double v, double lo, double hi) { return v > lo && v < hi; };
  return in(p[0], 0, 1) && in(p[1], 0, 1) &&
         !(p[0] >= 0.375 && p[0] <= 0.625 && p[1] >= 0.375 && p[1] <= 0.625);
}

// Probe points: fixed ones inside the domain and a few from the input.
std::vector<double> probes(Bytes& in, int dim) {
  std::vector<double> out;
  const double fixed[4][3] = {{0.1, 0.2, 0.3}, {0.9, 0.3, 0.7}, {0.5, 0.8, 0.5}, {0.3, 0.5, 0.1}};
  for (const auto& f : fixed) out.insert(out.end(), f, f + dim);
  for (int k = 0; k < 3; ++k) {
    for (int c = 0; c < dim; ++c) out.push_back(grid_value(in.next()) + in.next() * 0x1p-10);
  }
  return out;
}

void check_2d(const std::vector<double>& xy, Bytes& in) {
  const auto n = static_cast<std::uint32_t>(xy.size() / 2);
  voroclip::Delaunay2 dt;
  try {
    dt.build(xy.data(), n);
  } catch (const voroclip::Error&) {
    return;
  }
  if (!dt.check_topology().empty()) fail("Delaunay2 topology", 0);
  if (!dt.check_delaunay().empty()) fail("Delaunay2 not Delaunay", 0);
  for (std::uint32_t t = 0; t < dt.nb_triangles(); ++t) {
    const double* a = dt.point(dt.tri_vertex(t, 0));
    const double* b = dt.point(dt.tri_vertex(t, 1));
    const double* c = dt.point(dt.tri_vertex(t, 2));
    if (voroclip::orient2d(a, b, c) != Sign::positive) fail("Delaunay2 triangle not ccw", t);
    for (std::uint32_t i = 0; i < n; ++i) {
      if (voroclip::incircle(a, b, c, xy.data() + 2 * i) == Sign::positive) {
        fail("Delaunay2 circumcircle not empty", t);
      }
    }
  }
  voroclip::ClippedVoronoi2 cv;
  const voroclip::Domain2 domain(square_with_hole());
  try {
    cv.compute(domain, dt);
  } catch (const voroclip::Error&) {
    return;
  }
  if (cv.nb_sites() != n) fail("ClippedVoronoi2 site count", cv.nb_sites());
  double sum = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    // Areas are rounded sums: a sliver cell of true area ~1e-55 may come out as -3e-55
    // (fuzz/seeds/fuzz_sites/sliver_cell_negative_area: sites packed within 1e-26 of a
    // corner). Below -1e-12 of the domain's area it is a defect.
    if (!(cv.area(i) >= -1e-12 * domain.area())) fail("negative or NaN cell area", i);
    sum += cv.area(i);
  }
  if (!(std::fabs(sum - domain.area()) <= 1e-9 * domain.area())) fail("areas do not sum", 0);
  const std::vector<double> p = probes(in, 2);
  for (std::size_t k = 0; k < p.size() / 2; ++k) {
    const double* q = p.data() + 2 * k;
    const std::uint32_t v = dt.nearest_vertex(q[0], q[1]);
    if (v >= n || dt.duplicate_of(v) != v) fail("nearest_vertex not a vertex", k);
    for (std::uint32_t i = 0; i < n; ++i) {
      if (voroclip::compare_distance2d(q, xy.data() + 2 * i, dt.point(v)) == Sign::negative) {
        fail("nearest_vertex not nearest", k);
      }
    }
    if (inside_square_with_hole(q) && !(cv.area(v) > 0)) fail("probe's cell has no area", k);
  }
}

void check_3d(const std::vector<double>& xyz, Bytes& in) {
  const auto n = static_cast<std::uint32_t>(xyz.size() / 3);
  voroclip::Delaunay3 dt;
  try {
    dt.build(xyz.data(), n);
  } catch (const voroclip::Error&) {
    return;
  }
  if (!dt.check_topology().empty()) fail("Delaunay3 topology", 0);
  if (!dt.check_delaunay().empty()) fail("Delaunay3 not Delaunay", 0);
  for (std::uint32_t t = 0; t < dt.nb_tet_slots(); ++t) {
    if (dt.is_infinite(t)) continue;
    const double* a = dt.point(dt.tet_vertex(t, 0));
    const double* b = dt.point(dt.tet_vertex(t, 1));
    const double* c = dt.point(dt.tet_vertex(t, 2));
    const double* d = dt.point(dt.tet_vertex(t, 3));
    if (voroclip::orient3d(a, b, c, d) != Sign::positive) fail("Delaunay3 tet not positive", t);
    for (std::uint32_t i = 0; i < n; ++i) {
      if (voroclip::insphere(a, b, c, d, xyz.data() + 3 * i) == Sign::positive) {
        fail("Delaunay3 circumsphere not empty", t);
      }
    }
  }
  static const voroclip::Domain3 cube(voroclip_test::box_surface({0, 0, 0}, {1, 1, 1}));
  voroclip::ClippedVoronoi3 cv;
  try {
    cv.compute(cube, dt);
  } catch (const voroclip::Error&) {
    return;
  }
  if (cv.nb_sites() != n) fail("ClippedVoronoi3 site count", cv.nb_sites());
  double sum = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (!(cv.volume(i) >= -1e-12)) fail("negative or NaN cell volume", i);  // as in 2D
    sum += cv.volume(i);
  }
  if (!(std::fabs(sum - 1.0) <= 1e-9)) fail("volumes do not sum", 0);
  const std::vector<double> p = probes(in, 3);
  for (std::size_t k = 0; k < p.size() / 3; ++k) {
    const double* q = p.data() + 3 * k;
    const std::uint32_t v = dt.nearest_vertex(q);
    if (v >= n || dt.duplicate_of(v) != v) fail("nearest_vertex not a vertex", k);
    for (std::uint32_t i = 0; i < n; ++i) {
      if (voroclip::compare_distance3d(q, xyz.data() + 3 * i, dt.point(v)) == Sign::negative) {
        fail("nearest_vertex not nearest", k);
      }
    }
    const bool inside = q[0] > 0 && q[0] < 1 && q[1] > 0 && q[1] < 1 && q[2] > 0 && q[2] < 1;
    if (inside && !(cv.volume(v) > 0)) fail("probe's cell has no volume", k);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Bytes in{data, size};
  const std::uint8_t head = in.next();
  const int dim = (head & 1) ? 3 : 2;
  const int mode = (head >> 1) % 3;
  // The sites take what the bytes allow (at most 64); what is left after them feeds the probes.
  const std::size_t per_site = static_cast<std::size_t>(dim) * bytes_per_coordinate(mode);
  const std::size_t n = std::min(kMaxSites, in.left() / per_site);
  std::vector<double> coords;
  coords.reserve(n * static_cast<std::size_t>(dim));
  for (std::size_t i = 0; i < n * static_cast<std::size_t>(dim); ++i) {
    coords.push_back(decode(in, mode));
  }
  if (dim == 2) {
    check_2d(coords, in);
  } else {
    check_3d(coords, in);
  }
  return 0;
}
