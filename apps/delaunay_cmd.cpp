// voroclip delaunay2d / delaunay3d: triangulate a point file or random points, optionally
// check the result exactly, write it as VTK, report statistics.
#include <sys/resource.h>

#include <chrono>
#include <cstdint>
#include <iostream>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "cli.h"
#include "progress.h"
#include "voroclip/core.h"
#include "voroclip/delaunay.h"

namespace voroclip::cli {

namespace {

// Uniform in [0, 1)^dimension from a 64-bit Mersenne twister: the same points on every
// platform (std::uniform_real_distribution is not specified bit for bit).
std::vector<double> random_points(std::uint32_t n, std::uint64_t seed, int dimension) {
  std::mt19937_64 rng(seed);
  std::vector<double> out(static_cast<std::size_t>(n) * static_cast<std::size_t>(dimension));
  for (double& x : out) x = static_cast<double>(rng() >> 11) * 0x1p-53;
  return out;
}

std::uint64_t peak_rss_bytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<std::uint64_t>(usage.ru_maxrss) * 1024u;  // Linux: kilobytes
}

struct Result {
  std::uint32_t unique = 0;
  std::size_t hull_vertices = 0;
  std::vector<std::uint32_t> cells;  // finite simplices, flat
  std::string check;                 // first defect, empty when valid
};

Result triangulate_2d(const std::vector<double>& xy, bool check) {
  const auto n = static_cast<std::uint32_t>(xy.size() / 2);
  const Delaunay2 dt(xy.data(), n);
  Result r;
  r.unique = dt.nb_unique_points();
  r.hull_vertices = dt.hull_vertices().size();
  for (std::uint32_t t = 0; t < dt.nb_triangles(); ++t) {
    for (int k = 0; k < 3; ++k) r.cells.push_back(dt.tri_vertex(t, k));
  }
  if (check) {
    r.check = dt.check_topology();
    if (r.check.empty()) r.check = dt.check_delaunay();
  }
  return r;
}

Result triangulate_3d(const std::vector<double>& xyz, bool check) {
  const auto n = static_cast<std::uint32_t>(xyz.size() / 3);
  const Delaunay3 dt(xyz.data(), n);
  Result r;
  r.unique = dt.nb_unique_points();
  r.hull_vertices = dt.hull_vertices().size();
  r.cells.reserve(4 * static_cast<std::size_t>(dt.nb_finite_tets()));
  for (std::uint32_t t = 0; t < dt.nb_tet_slots(); ++t) {
    if (dt.is_free(t) || dt.is_infinite(t)) continue;
    // Delaunay3's tets have orient3d(p0, p1, p2, p3) > 0, i.e. det(p1 - p0, p2 - p0, p3 - p0)
    // < 0; VTK's (and mesh3d's) have det > 0: p0 and p1 swapped.
    r.cells.push_back(dt.tet_vertex(t, 1));
    r.cells.push_back(dt.tet_vertex(t, 0));
    r.cells.push_back(dt.tet_vertex(t, 2));
    r.cells.push_back(dt.tet_vertex(t, 3));
  }
  if (check) {
    r.check = dt.check_topology();
    if (r.check.empty()) r.check = dt.check_delaunay();
  }
  return r;
}

}  // namespace

void run_delaunay(const DelaunayArgs& args, const GlobalOptions& options) {
  const int dim = args.dimension;
  if (args.input.empty() == !args.random_set) {
    throw UsageError("give exactly one of INPUT and --random N");
  }
  if (!args.output.empty() &&
      (args.output.size() < 4 || args.output.compare(args.output.size() - 4, 4, ".vtk") != 0)) {
    throw UsageError("-o: only legacy VTK output (.vtk) is supported, got '" + args.output + "'");
  }
  check_output_path(args.output);
  Progress progress(options);
  progress.phase("reading");
  const std::vector<double> points =
      args.random_set ? random_points(args.random, args.seed, dim) : read_points(args.input, dim);
  const auto n = static_cast<std::uint32_t>(points.size() / static_cast<std::size_t>(dim));
  // Where the points come from, for messages (the library's name its triangulation class).
  const std::string source =
      args.random_set ? "--random " + std::to_string(args.random) : args.input;
  if (n < static_cast<std::uint32_t>(dim) + 1) {
    throw Error(source + ": " + count_of(n, "point") + "; delaunay" + std::to_string(dim) +
                "d needs at least " + std::to_string(dim + 1) + " points, not all on a line" +
                (dim == 3 ? " or in a plane" : ""));
  }

  progress.phase("Delaunay");
  const auto start = std::chrono::steady_clock::now();
  Result r;
  try {
    r = dim == 2 ? triangulate_2d(points, false) : triangulate_3d(points, false);
  } catch (const Error& e) {
    std::string what = e.what();
    for (const std::string prefix : {"Delaunay2: ", "Delaunay3: "}) {
      if (what.rfind(prefix, 0) == 0) what.erase(0, prefix.size());
    }
    throw Error(source + ": " + what);
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (args.check) {
    progress.phase("exact check");
    r = dim == 2 ? triangulate_2d(points, true) : triangulate_3d(points, true);
    if (!r.check.empty()) throw Error("the exact check failed: " + r.check);
  }
  const std::size_t per_cell = static_cast<std::size_t>(dim) + 1;
  const std::size_t nb_cells = r.cells.size() / per_cell;
  if (!args.output.empty()) {
    progress.phase("writing " + args.output);
    write_file_atomically(args.output, [&](std::ostream& out) {
      write_vtk(out, "voroclip delaunay" + std::to_string(dim) + "d", points.data(), n, dim,
                r.cells, dim + 1);
    });
  }
  progress.done();
  const char* cells_key = dim == 2 ? "triangles" : "tetrahedra";
  if (options.stats_json) {
    nlohmann::json stats = {
        {"points", n},         {"unique_points", r.unique}, {"hull_vertices", r.hull_vertices},
        {cells_key, nb_cells}, {"seconds", seconds},        {"peak_rss_bytes", peak_rss_bytes()}};
    if (args.check) stats["check"] = "passed";
    print_stats(stats, options);
  }
  if (std::ostream* out = human_stream(options)) {
    *out << "Delaunay " << dim << "D: " << count_of(n, "point") << " (" << r.unique
         << " distinct), " << nb_cells << ' ' << cells_key << ", "
         << count_of(r.hull_vertices, "hull vertex", "hull vertices") << ", "
         << format_double(seconds) << " s\n";
    if (args.check) *out << "Exact checks (topology, orientation, local Delaunay): passed\n";
    if (!args.output.empty()) *out << "Written to " << args.output << '\n';
  }
}

}  // namespace voroclip::cli
