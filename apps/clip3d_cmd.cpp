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
#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/cvt.h"
#include "voroclip/delaunay.h"

namespace voroclip::cli {

namespace {

bool has_suffix(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

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
void write_surface_obj(std::ostream& out, const ClippedVoronoi3& cv) {
  const ClippedVoronoi3::Polygons& s = cv.surface_polygons();
  out << std::setprecision(17) << "# voroclip clip3d: restricted Voronoi diagram on the "
      << "boundary surface, coloured by cell\n";
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
// the other side, -1 for the domain's surface).
void write_cells_vtu(std::ostream& out, const ClippedVoronoi3& cv) {
  const ClippedVoronoi3::Polygons f = cv.cell_boundaries();
  const std::size_t nf = f.site.size();
  const std::size_t nv = f.polygon_begin.back();
  out << std::setprecision(17);
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" "
         "byte_order=\"LittleEndian\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\""
      << nv << "\" NumberOfCells=\"" << nf << "\">\n<Points>\n<DataArray type=\"Float64\" "
      << "NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (std::size_t k = 0; k < nf; ++k) {
    const double* c = cv.centroid(f.site[k]);
    for (std::uint32_t v = f.polygon_begin[k]; v < f.polygon_begin[k + 1]; ++v) {
      for (int q = 0; q < 3; ++q)
        out << c[q] + 0.9 * (f.xyz[3 * std::size_t{v} + static_cast<std::size_t>(q)] - c[q])
            << (q < 2 ? ' ' : '\n');
    }
  }
  out << "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" "
         "format=\"ascii\">\n";
  for (std::size_t v = 0; v < nv; ++v) out << v << '\n';
  out << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (std::size_t k = 0; k < nf; ++k) out << f.polygon_begin[k + 1] << '\n';
  out << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (std::size_t k = 0; k < nf; ++k) out << "7\n";
  out << "</DataArray>\n</Cells>\n<CellData Scalars=\"site_id\">\n<DataArray type=\"UInt32\" "
         "Name=\"site_id\" format=\"ascii\">\n";
  for (std::size_t k = 0; k < nf; ++k) out << f.site[k] << '\n';
  out << "</DataArray>\n<DataArray type=\"Int64\" Name=\"across\" format=\"ascii\">\n";
  for (std::size_t k = 0; k < nf; ++k) {
    if (f.across[k] == ClippedVoronoi3::kSurface) {
      out << "-1\n";
    } else {
      out << f.across[k] << '\n';
    }
  }
  out << "</DataArray>\n</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
}

void write_cells_json(std::ostream& out, const std::vector<double>& sites,
                      const ClippedVoronoi3& cv) {
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
                     {"boundary", cv.is_boundary(i)}});
  }
  out << nlohmann::json{{"cells", std::move(cells)}}.dump(1) << '\n';
}

}  // namespace

void write_cells3_file(const std::string& path, const std::vector<double>& sites,
                       const ClippedVoronoi3& cv) {
  write_file_atomically(path, [&](std::ostream& out) {
    if (has_suffix(path, ".obj")) {
      write_surface_obj(out, cv);
    } else if (has_suffix(path, ".vtu")) {
      write_cells_vtu(out, cv);
    } else {
      write_cells_json(out, sites, cv);
    }
  });
}

void run_clip3d(const ClipArgs& args, const GlobalOptions& options) {
  if (!args.output.empty() && !has_suffix(args.output, ".vtu") &&
      !has_suffix(args.output, ".obj") && !has_suffix(args.output, ".json")) {
    throw UsageError(
        "-o: the output must end in .vtu (cell faces), .obj (restricted "
        "surface) or .json (per cell), got '" +
        args.output + "'");
  }
  check_output_path(args.output);
  if (args.sites.empty() == !args.random_set) {
    throw UsageError("give exactly one of --sites FILE and --random N");
  }
  if (args.random_set && args.random < 4) throw UsageError("--random: needs at least 4 sites");
  const Domain3 domain = load_domain3(args.domain, args.reorient, options);
  const std::vector<double> sites =
      args.random_set ? random_points3(domain, args.random, args.seed) : read_points(args.sites, 3);
  const auto n = static_cast<std::uint32_t>(sites.size() / 3);
  ClippedVoronoi3 cv;
  Clip3Options o;
  o.keep_surface = has_suffix(args.output, ".obj");
  o.keep_geometry = has_suffix(args.output, ".vtu");
  // The Delaunay triangulation is built by compute(), of the sites in spatial order.
  const auto t0 = std::chrono::steady_clock::now();
  cv.compute(domain, sites.data(), n, o);
  const double t_total =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double t_delaunay = cv.seconds_delaunay();
  if (!args.output.empty()) write_cells3_file(args.output, sites, cv);
  if (options.stats_json) {
    std::cout << nlohmann::json{{"tets", domain.nb_tets()},
                                {"boundary_triangles", domain.surface().nb_triangles()},
                                {"shells", domain.surface().shells().size()},
                                {"sites", n},
                                {"unique_sites", cv.delaunay().nb_unique_points()},
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
                                  {"total", t_total}}}}
                     .dump()
              << '\n';
  }
  if (std::ostream* out = human_stream(options)) {
    *out << "Clipped Voronoi diagram: " << n << " sites (" << cv.nb_boundary_sites()
         << " boundary cells) in " << domain.source() << " ("
         << (domain.has_tets() ? std::to_string(domain.nb_tets()) + " tets, " : std::string())
         << domain.surface().nb_triangles() << " boundary triangles); cells' volume "
         << format_double(cv.total_volume()) << " (domain " << format_double(domain.volume())
         << "); Delaunay " << format_double(t_delaunay) << " s, surface "
         << format_double(cv.seconds_surface()) << " s, boundary cells "
         << format_double(cv.seconds_boundary_cells()) << " s, inner cells "
         << format_double(cv.seconds_inner_cells()) << " s\n";
    if (!args.output.empty()) *out << "Written to " << args.output << '\n';
  }
}

}  // namespace voroclip::cli
