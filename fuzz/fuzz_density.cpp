// libFuzzer targets for the density / sizing files of the command line (issue 35's
// --density-file and --sizing-file; issue 34): one source, three targets, the format chosen
// at compile time by FUZZ_DENSITY_FORMAT:
//   0  fuzz_density_sol  Medit .sol (SolAtVertices) on a cube's tet mesh of 8 vertices
//   1  fuzz_density_vtu  .vtu with a PointData array (a tet mesh and its values)
//   2  fuzz_density_vtk  legacy VTK STRUCTURED_POINTS grid, read as a 3D and a 2D density
// The readers live in apps/density_options.cpp (compiled into the target, as the CLI uses
// them) and read files: the bytes go to a file of this process, whose extension selects
// the reader, then make_density3 / make_density2 read it as --density-file and as
// --sizing-file. A density that is built is evaluated at a few points
// inside and outside its data (the interpolants on fuzzed meshes and grids). voroclip::Error
// and the command line's UsageError are clean refusals; anything else escapes (a finding),
// as do crashes, sanitizer reports, leaks and allocations over -malloc_limit_mb.
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "cli.h"
#include "density_options.h"
#include "voroclip/clip.h"
#include "voroclip/core.h"

#ifndef FUZZ_DENSITY_FORMAT
#error "FUZZ_DENSITY_FORMAT: 0 (.sol), 1 (.vtu) or 2 (.vtk)"
#endif

namespace {

// [0, 1]^3 as 6 Kuhn tets on its 8 corners (vertex i = x + 2y + 4z): the domain of a .sol.
voroclip::TetMeshInput cube_mesh() {
  voroclip::TetMeshInput m;
  m.source = "cube";
  for (int i = 0; i < 8; ++i) {
    m.xyz.insert(m.xyz.end(), {double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)});
  }
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (const auto& p : perms) {
    int c[3] = {0, 0, 0};
    std::uint32_t tet[4] = {0, 0, 0, 0};
    for (int s = 0; s < 3; ++s) {
      ++c[p[s]];
      tet[s + 1] = static_cast<std::uint32_t>(c[0] + 2 * c[1] + 4 * c[2]);
    }
    m.tets.insert(m.tets.end(), tet, tet + 4);
    m.tet_line.push_back(0);
  }
  return m;
}

const char* extension() {
  switch (FUZZ_DENSITY_FORMAT) {
    case 0:
      return ".sol";
    case 1:
      return ".vtu";
    default:
      return ".vtk";
  }
}

// The file of this process (libFuzzer's -fork / -jobs run several).
const std::string& file_path() {
  static const std::string path = [] {
    const char* dir = std::getenv("TMPDIR");
    return std::string(dir && *dir ? dir : "/tmp") + "/voroclip_fuzz_density." +
           std::to_string(::getpid()) + extension();
  }();
  static const bool removed_at_exit = std::atexit([] { std::remove(path.c_str()); }) == 0;
  (void)removed_at_exit;
  return path;
}

const double kProbes[][3] = {{0.25, 0.5, 0.75}, {0.9, 0.1, 0.3}, {-3, 0.5, 0.5}, {0.5, 7, -2}};

void check_value(double v) {
  // A built density is finite and not negative where it is evaluated (its values were
  // checked when read; interpolants of positive values stay positive; a sizing's h^-(d+2)
  // may underflow to 0).
  if (!(v >= 0) || !std::isfinite(v)) {
    std::fprintf(stderr, "fuzz_density: density value %g\n", v);
    std::abort();
  }
}

void run(bool sizing) {
  static const voroclip::Domain3 cube{cube_mesh()};
  voroclip::cli::DensityArgs args;
  (sizing ? args.sizing_file : args.density_file) = file_path();
  try {
    const voroclip::Density3 rho = voroclip::cli::make_density3(args, cube, true);
    for (const auto& p : kProbes) check_value(rho(p[0], p[1], p[2]));
  } catch (const voroclip::Error&) {
  } catch (const voroclip::cli::UsageError&) {
  }
  if (FUZZ_DENSITY_FORMAT == 2) {
    static const voroclip::Domain2 square = [] {
      voroclip::PolygonRings p;
      p.source = "square";
      p.xy = {0, 0, 1, 0, 1, 1, 0, 1};
      p.ring_begin = {0, 4};
      p.ring_polygon = {0};
      p.ring_line = {0};
      return voroclip::Domain2(p);
    }();
    try {
      const voroclip::Density2 rho = voroclip::cli::make_density2(args, square);
      for (const auto& p : kProbes) check_value(rho(p[0], p[1]));
    } catch (const voroclip::Error&) {
    } catch (const voroclip::cli::UsageError&) {
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  {
    std::ofstream out(file_path(), std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    if (!out) {
      std::fprintf(stderr, "fuzz_density: cannot write %s\n", file_path().c_str());
      std::abort();
    }
  }
  run(false);
  run(true);
  return 0;
}
