// voroclip clip3d: the Voronoi diagram of sites clipped to a volume given by its closed
// surface or a tet mesh; every cell's faces (VTK), the restricted surface (OBJ, coloured by
// cell) and per-cell JSON out.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli.h"
#include "progress.h"
#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/cvt.h"
#include "voroclip/delaunay.h"

namespace voroclip::cli {

namespace {

// A colour per cell for the OBJ materials: a hue from a hash of the index.
void cell_rgb(std::uint32_t i, double* rgb) {
  std::uint32_t h = i * 2654435761u;
  h ^= h >> 15;
  const double hue = (h % 360) / 60.0;
  const double x = 1 - std::fabs(std::fmod(hue, 2.0) - 1);
  const double c = 0.75, m = 0.2;
  double r = 0, g = 0, b = 0;
  switch (static_cast<int>(hue)) {
    case 0:
      r = c;
      g = c * x;
      break;
    case 1:
      r = c * x;
      g = c;
      break;
    case 2:
      g = c;
      b = c * x;
      break;
    case 3:
      g = c * x;
      b = c;
      break;
    case 4:
      r = c * x;
      b = c;
      break;
    default:
      r = c;
      b = c * x;
      break;
  }
  rgb[0] = r + m;
  rgb[1] = g + m;
  rgb[2] = b + m;
}

// The restricted surface as OBJ polygons with per-vertex colours (x y z r g b, the
// colour extension read by MeshLab and Blender), one colour per cell.
void write_surface_obj(std::ostream& out, const ClippedVoronoi3& cv, const std::string& command) {
  const ClippedVoronoi3::Polygons& s = cv.surface_polygons();
  out << std::setprecision(17) << "# voroclip " << command
      << ": restricted Voronoi diagram on the boundary surface, coloured by cell\n";
  for (std::size_t p = 0; p + 1 < s.polygon_begin.size(); ++p) {
    double rgb[3];
    cell_rgb(s.site[p], rgb);
    for (std::uint32_t v = s.polygon_begin[p]; v < s.polygon_begin[p + 1]; ++v) {
      out << "v " << s.xyz[3 * v] << ' ' << s.xyz[3 * v + 1] << ' ' << s.xyz[3 * v + 2] << ' '
          << std::setprecision(3) << rgb[0] << ' ' << rgb[1] << ' ' << rgb[2]
          << std::setprecision(17) << '\n';
    }
  }
  for (std::size_t p = 0; p + 1 < s.polygon_begin.size(); ++p) {
    out << 'f';
    for (std::uint32_t v = s.polygon_begin[p]; v < s.polygon_begin[p + 1]; ++v) out << ' ' << v + 1;
    out << '\n';
  }
}

// Every cell's boundary (cell_boundaries()) as VTK XML polygons, each shrunk towards its
// cell's centroid by 10 % so that cells stand apart, with site_id and across (the site on
// the other side, -1 for the domain's surface). The polygons face out of their cell
// (counter-clockwise seen from outside, as viewers light them and as the restricted
// surface's OBJ is): cell_boundaries() lists them the other way round.
void write_cells_vtu(std::ostream& out, const ClippedVoronoi3& cv, VtuEncoding encoding) {
  const ClippedVoronoi3::Polygons f = cv.cell_boundaries();
  const std::size_t nf = f.site.size();
  const std::size_t nv = f.polygon_begin.back();
  std::vector<double> xyz(3 * nv);
  std::vector<std::uint32_t> indices(nv);
  std::vector<VtuCellTags> tags(2);
  tags[0].name = "site_id";
  tags[1].name = "across";
  for (std::size_t k = 0; k < nf; ++k) {
    const double* c = cv.centroid(f.site[k]);
    for (std::uint32_t v = f.polygon_begin[k]; v < f.polygon_begin[k + 1]; ++v) {
      indices[v] = f.polygon_begin[k] + f.polygon_begin[k + 1] - 1 - v;
      for (std::size_t q = 0; q < 3; ++q) {
        xyz[3 * std::size_t{v} + q] = c[q] + 0.9 * (f.xyz[3 * std::size_t{v} + q] - c[q]);
      }
    }
    tags[0].values.push_back(static_cast<std::int32_t>(f.site[k]));
    tags[1].values.push_back(
        f.across[k] == ClippedVoronoi3::kSurface ? -1 : static_cast<std::int32_t>(f.across[k]));
  }
  const VtuCellBlock faces{indices.data(), nf, 0, f.polygon_begin.data()};
  write_vtu(out, xyz.data(), static_cast<std::uint32_t>(nv), 3, {faces}, encoding, {}, tags);
}

void write_cells_json(std::ostream& out, const std::vector<double>& sites,
                      const ClippedVoronoi3& cv, const CellTable& table) {
  nlohmann::json cells = nlohmann::json::array();
  for (std::uint32_t i = 0; i < cv.nb_sites(); ++i) {
    const double* c = cv.centroid(i);
    cells.push_back({{"index", i},
                     {"site", {sites[3 * i], sites[3 * i + 1], sites[3 * i + 2]}},
                     {"volume", cv.volume(i)},
                     {"mass", cv.mass(i)},
                     {"centroid", {c[0], c[1], c[2]}},
                     {"energy", cv.energy(i)},
                     {"surface_area", cv.surface_area(i)},
                     {"boundary", cv.is_boundary(i)},
                     {"neighbors", table.nb_neighbors[i]}});
  }
  out << nlohmann::json{{"cells", std::move(cells)}}.dump(1) << '\n';
}

}  // namespace

FileWriter cells3_file(const std::string& path, const std::string& command,
                       const std::vector<double>& sites, const ClippedVoronoi3& cv,
                       VtuEncoding encoding, const NeighborTable* neighbors) {
  const std::string ext = lower_extension(path);
  return {path, [ext, command, &sites, &cv, encoding, neighbors](std::ostream& out) {
            if (ext == ".obj") {
              write_surface_obj(out, cv, command);
            } else if (ext == ".vtu") {
              write_cells_vtu(out, cv, encoding);
            } else {
              NeighborTable local;
              if (!neighbors) local = cell_neighbors(cv);
              const CellTable table = cell_table(cv, sites.data(), neighbors ? neighbors : &local);
              if (ext == ".csv") {
                write_cell_table_csv(out, table);
              } else {
                write_cells_json(out, sites, cv, table);
              }
            }
          }};
}

void run_clip3d(const ClipArgs& args, const GlobalOptions& options) {
  const std::string ext = lower_extension(args.output);
  if (!args.output.empty() && ext != ".vtu" && ext != ".obj" && ext != ".json" && ext != ".csv") {
    throw UsageError(
        "-o: the output must end in .vtu (cell faces), .obj (restricted "
        "surface), .json or .csv (per cell), got '" +
        args.output + "'");
  }
  const std::string neighbors_ext = lower_extension(args.neighbors);
  if (!args.neighbors.empty() && neighbors_ext != ".csv" && neighbors_ext != ".json") {
    throw UsageError("--neighbors: the table must end in .csv or .json, got '" + args.neighbors +
                     "'");
  }
  if ((args.binary || args.compress) && ext != ".vtu") {
    throw UsageError(no_encoding_message(args.compress ? "--compress" : "--binary", ext));
  }
  check_outputs({{"-o", args.output}, {"--neighbors", args.neighbors}});
  if (args.sites.empty() == !args.random_set) {
    throw UsageError("give exactly one of --sites FILE and --random N");
  }
  if (args.random_set && args.random < 1) throw UsageError("--random: needs at least 1 site");
  Progress progress(options);
  progress.phase("reading");
  const Domain3 domain = load_domain3(args.domain, args.reorient, options);
  const std::vector<double> sites =
      args.random_set ? random_points3(domain, args.random, args.seed) : read_points(args.sites, 3);
  const auto n = static_cast<std::uint32_t>(sites.size() / 3);
  std::vector<std::uint32_t> outside, repeated;
  if (!args.random_set) {
    for (std::uint32_t i = 0; i < n; ++i) {
      if (domain.locate(&sites[3 * std::size_t{i}]) == Sign::negative) outside.push_back(i);
    }
    repeated = repeated_sites(sites, 3);
    report_sites(domain.source(), outside, repeated, args.strict, progress);
  }
  ClippedVoronoi3 cv;
  Clip3Options o;
  const bool tables = ext == ".json" || ext == ".csv" || !args.neighbors.empty();
  o.keep_surface = ext == ".obj";
  o.keep_geometry = ext == ".vtu" || tables;
  // The Delaunay triangulation is built by compute(), of the sites in spatial order. Its
  // phases (ClipProgress, on this thread) become the printer's: a long one shows life.
  progress.phase("Delaunay and clipping");
  const char* last_phase = "";
  o.progress = [&](const ClipProgress& p) {
    if (std::string(p.phase) != last_phase) {
      last_phase = p.phase;
      progress.phase(std::string("clipping: ") + p.phase);
    }
    return true;
  };
  const auto t0 = std::chrono::steady_clock::now();
  cv.compute(domain, sites.data(), n, o);
  const double t_total =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double t_delaunay = cv.seconds_delaunay();
  if (!args.output.empty() || tables) progress.phase("writing");
  NeighborTable neighbors;
  if (tables) neighbors = cell_neighbors(cv);
  // -o and --neighbors appear together or not at all.
  std::vector<FileWriter> files;
  if (!args.output.empty()) {
    files.push_back(cells3_file(args.output, "clip3d", sites, cv,
                                args.compress ? VtuEncoding::kZlibBase64
                                : args.binary ? VtuEncoding::kBase64
                                              : VtuEncoding::kAscii,
                                tables ? &neighbors : nullptr));
  }
  if (!args.neighbors.empty()) {
    files.push_back({args.neighbors, [&](std::ostream& out) {
                       if (neighbors_ext == ".json") {
                         write_neighbor_table_json(out, neighbors);
                       } else {
                         write_neighbor_table_csv(out, neighbors);
                       }
                     }});
  }
  write_files_atomically(files);
  progress.done();
  if (options.stats_json) {
    print_stats(
        nlohmann::json{{"tets", domain.nb_tets()},
                       {"boundary_triangles", domain.surface().nb_triangles()},
                       {"shells", domain.surface().shells().size()},
                       {"sites", n},
                       {"unique_sites", cv.delaunay().nb_unique_points() - cv.nb_auxiliary_sites()},
                       {"sites_outside", outside.size()},
                       {"duplicate_sites", repeated.size()},
                       {"boundary_sites", cv.nb_boundary_sites()},
                       {"domain_volume", domain.volume()},
                       {"cells_volume_sum", cv.total_volume()},
                       {"surface_area_sum", cv.total_surface_area()},
                       {"clipped_pairs", cv.nb_clipped_pairs()},
                       {"multi_crossing_cells", cv.nb_multi_crossing_cells()},
                       {"seconds",
                        {{"delaunay", t_delaunay},
                         {"surface_rvd", cv.seconds_surface()},
                         {"boundary_cells", cv.seconds_boundary_cells()},
                         {"inner_cells", cv.seconds_inner_cells()},
                         {"total", t_total}}}},
        options);
  }
  if (std::ostream* out = human_stream(options)) {
    *out << "Clipped Voronoi diagram: " << count_of(n, "site") << " ("
         << count_of(cv.nb_boundary_sites(), "boundary cell") << ") in " << domain.source() << " ("
         << (domain.has_tets() ? count_of(domain.nb_tets(), "tet") + ", " : std::string())
         << count_of(domain.surface().nb_triangles(), "boundary triangle") << "); cells' volume "
         << format_double(cv.total_volume()) << " (domain " << format_double(domain.volume())
         << "); Delaunay " << format_double(t_delaunay) << " s, surface "
         << format_double(cv.seconds_surface()) << " s, boundary cells "
         << format_double(cv.seconds_boundary_cells()) << " s, inner cells "
         << format_double(cv.seconds_inner_cells()) << " s\n";
    if (!args.output.empty()) *out << "Written to " << args.output << '\n';
    if (!args.neighbors.empty()) *out << "Neighbour pairs written to " << args.neighbors << '\n';
  }
}

}  // namespace voroclip::cli
