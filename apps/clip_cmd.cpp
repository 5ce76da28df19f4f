// voroclip clip2d / cvt2d: the clipped Voronoi diagram of sites in a polygonal domain, and
// its centroidal Voronoi tessellation; pictures (SVG), VTK polygons and JSON out.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
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

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::vector<double> parse_numbers(const std::string& list, std::size_t count,
                                  const std::string& what) {
  std::vector<double> v;
  std::size_t start = 0;
  while (start <= list.size()) {
    const std::size_t comma = std::min(list.find(',', start), list.size());
    v.push_back(parse_finite_double(list.substr(start, comma - start), what));
    start = comma + 1;
  }
  if (v.size() != count) {
    throw UsageError(what + ": expected " + std::to_string(count) +
                     " comma-separated numbers, got '" + list + "'");
  }
  return v;
}

// A ring of the domain picture or of a cell, as an SVG path (y up).
void svg_ring(std::ostream& out, const double* xy, std::size_t count, double x0, double y1,
              double scale) {
  for (std::size_t k = 0; k < count; ++k) {
    out << (k == 0 ? 'M' : 'L') << (xy[2 * k] - x0) * scale << ' ' << (y1 - xy[2 * k + 1]) * scale;
  }
  out << 'Z';
}

// Colour of cell i: a hue from a hash of the index, light; boundary cells warm, inner cool.
std::string cell_colour(std::uint32_t i, bool boundary) {
  std::uint32_t h = i * 2654435761u;
  h ^= h >> 15;
  const int hue = boundary ? static_cast<int>(h % 60) + 10 : static_cast<int>(h % 90) + 170;
  const int light = 72 + static_cast<int>((h >> 8) % 14);
  std::ostringstream s;
  s << "hsl(" << hue << ",60%," << light << "%)";
  return s.str();
}

}  // namespace

Domain2 load_domain(const std::string& spec) { return Domain2(load_rings(spec)); }

PolygonRings load_rings(const std::string& spec) {
  if (spec.rfind("annulus:", 0) == 0) {
    const std::vector<double> v = parse_numbers(spec.substr(8), 3, "annulus:R_IN,R_OUT,SEGMENTS");
    if (!(v[0] > 0 && v[1] > v[0]) || v[2] < 3 || v[2] > 1e7 || v[2] != std::floor(v[2])) {
      throw UsageError("annulus:R_IN,R_OUT,SEGMENTS needs 0 < R_IN < R_OUT and 3 <= SEGMENTS");
    }
    return annulus_rings(v[0], v[1], static_cast<std::uint32_t>(v[2]));
  }
  if (spec.rfind("square-holes:", 0) == 0) {
    const std::vector<double> v = parse_numbers(spec.substr(13), 2, "square-holes:K,FRACTION");
    if (v[0] < 1 || v[0] > 1000 || v[0] != std::floor(v[0]) || !(v[1] > 0 && v[1] < 1)) {
      throw UsageError("square-holes:K,FRACTION needs 1 <= K <= 1000 and 0 < FRACTION < 1");
    }
    return square_with_holes(static_cast<std::uint32_t>(v[0]), v[1]);
  }
  return read_polygon(spec);
}

void write_clip_svg(std::ostream& out, const Domain2& domain, const std::vector<double>& sites,
                    const ClippedVoronoi2& cv) {
  const double* lo = domain.bbox_lo();
  const double* hi = domain.bbox_hi();
  const double extent = std::max(hi[0] - lo[0], hi[1] - lo[1]);
  const double scale = 1000 / extent;
  const double margin = 10;
  const double w = (hi[0] - lo[0]) * scale, h = (hi[1] - lo[1]) * scale;
  out << std::setprecision(7);
  out << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << w + 2 * margin << "\" height=\""
      << h + 2 * margin << "\" viewBox=\"" << -margin << ' ' << -margin << ' ' << w + 2 * margin
      << ' ' << h + 2 * margin << "\">\n<rect x=\"" << -margin << "\" y=\"" << -margin
      << "\" width=\"" << w + 2 * margin << "\" height=\"" << h + 2 * margin
      << "\" fill=\"white\"/>\n";
  const std::vector<double>& xy = cv.vertex_coords();
  const double stroke = std::max(0.05, std::min(0.8, 40 / std::sqrt(double(cv.nb_sites()) + 1)));
  out << "<g stroke=\"#555\" stroke-width=\"" << stroke << "\" stroke-linejoin=\"round\">\n";
  for (std::uint32_t i = 0; i < cv.nb_sites(); ++i) {
    const std::uint32_t rb = cv.cell_ring_begin(i), re = cv.cell_ring_begin(i + 1);
    if (rb == re) continue;
    out << "<path fill=\"" << cell_colour(i, cv.is_boundary(i)) << "\" d=\"";
    for (std::uint32_t r = rb; r < re; ++r) {
      const std::uint32_t b = cv.ring_vertex_begin(r), e = cv.ring_vertex_begin(r + 1);
      svg_ring(out, &xy[2 * std::size_t{b}], e - b, lo[0], hi[1], scale);
    }
    out << "\"/>\n";
  }
  out << "</g>\n<path fill=\"none\" stroke=\"black\" stroke-width=\"" << 2 * stroke << "\" d=\"";
  for (std::uint32_t r = 0; r < domain.nb_rings(); ++r) {
    svg_ring(out, domain.vertex(domain.ring_begin(r)), domain.ring_end(r) - domain.ring_begin(r),
             lo[0], hi[1], scale);
  }
  out << "\"/>\n<g fill=\"black\">\n";
  const double radius = std::max(0.3, std::min(3.0, 60 / std::sqrt(double(cv.nb_sites()) + 1)));
  for (std::size_t i = 0; i < sites.size() / 2; ++i) {
    out << "<circle cx=\"" << (sites[2 * i] - lo[0]) * scale << "\" cy=\""
        << (hi[1] - sites[2 * i + 1]) * scale << "\" r=\"" << radius << "\"/>\n";
  }
  out << "</g>\n</svg>\n";
}

namespace {

// Rings of cell i grouped into polygons: each counter-clockwise ring with the clockwise
// rings it contains (grouping for output only; the rings themselves are exact).
std::vector<std::vector<std::uint32_t>> group_rings(const ClippedVoronoi2& cv, std::uint32_t i) {
  const std::vector<double>& xy = cv.vertex_coords();
  const auto signed_area = [&](std::uint32_t r) {
    const std::uint32_t b = cv.ring_vertex_begin(r), e = cv.ring_vertex_begin(r + 1);
    double a = 0;
    for (std::uint32_t k = b; k < e; ++k) {
      const std::uint32_t l = k + 1 == e ? b : k + 1;
      a += (xy[2 * k] - xy[2 * b]) * (xy[2 * l + 1] - xy[2 * b + 1]) -
           (xy[2 * l] - xy[2 * b]) * (xy[2 * k + 1] - xy[2 * b + 1]);
    }
    return a;
  };
  const auto inside = [&](std::uint32_t r, const double* p) {
    const std::uint32_t b = cv.ring_vertex_begin(r), e = cv.ring_vertex_begin(r + 1);
    bool in = false;
    for (std::uint32_t k = b; k < e; ++k) {
      const std::uint32_t l = k + 1 == e ? b : k + 1;
      const double* u = &xy[2 * std::size_t{k}];
      const double* v = &xy[2 * std::size_t{l}];
      if ((u[1] > p[1]) != (v[1] > p[1]) &&
          p[0] < u[0] + (p[1] - u[1]) * (v[0] - u[0]) / (v[1] - u[1])) {
        in = !in;
      }
    }
    return in;
  };
  std::vector<std::vector<std::uint32_t>> polygons;
  std::vector<std::uint32_t> holes;
  for (std::uint32_t r = cv.cell_ring_begin(i); r < cv.cell_ring_begin(i + 1); ++r) {
    if (signed_area(r) > 0) {
      polygons.push_back({r});
    } else {
      holes.push_back(r);
    }
  }
  for (const std::uint32_t h : holes) {
    std::size_t best = 0;
    for (std::size_t p = 0; p < polygons.size(); ++p) {
      if (inside(polygons[p][0], &xy[2 * std::size_t{cv.ring_vertex_begin(h)}])) best = p;
    }
    if (polygons.empty()) {
      polygons.push_back({h});
    } else {
      polygons[best].push_back(h);
    }
  }
  return polygons;
}

void write_clip_json(std::ostream& out, const std::vector<double>& sites, const ClippedVoronoi2& cv,
                     const CellTable& table) {
  const std::vector<double>& xy = cv.vertex_coords();
  nlohmann::json cells = nlohmann::json::array();
  for (std::uint32_t i = 0; i < cv.nb_sites(); ++i) {
    nlohmann::json polygons = nlohmann::json::array();
    for (const auto& group : group_rings(cv, i)) {
      nlohmann::json rings = nlohmann::json::array();
      for (const std::uint32_t r : group) {
        nlohmann::json ring = nlohmann::json::array();
        for (std::uint32_t k = cv.ring_vertex_begin(r); k < cv.ring_vertex_begin(r + 1); ++k) {
          ring.push_back({xy[2 * std::size_t{k}], xy[2 * std::size_t{k} + 1]});
        }
        rings.push_back(std::move(ring));
      }
      polygons.push_back(std::move(rings));
    }
    cells.push_back({{"index", i},
                     {"site", {sites[2 * std::size_t{i}], sites[2 * std::size_t{i} + 1]}},
                     {"area", cv.area(i)},
                     {"mass", cv.mass(i)},
                     {"centroid", {cv.centroid(i)[0], cv.centroid(i)[1]}},
                     {"energy", cv.energy(i)},
                     {"boundary", cv.is_boundary(i)},
                     {"neighbors", table.nb_neighbors[i]},
                     {"polygons", std::move(polygons)}});
  }
  out << nlohmann::json{{"cells", std::move(cells)}}.dump(1) << '\n';
}

// VTK XML unstructured grid: one VTK_POLYGON per ring, with the cell's site index
// ("site_id") and the ring's orientation ("hole": 1 for a clockwise ring).
void write_clip_vtu(std::ostream& out, const ClippedVoronoi2& cv, VtuEncoding encoding) {
  const std::vector<double>& xy = cv.vertex_coords();
  const auto nv = static_cast<std::uint32_t>(cv.vertices().size());
  std::vector<std::uint32_t> indices(nv), ring_begin;
  for (std::uint32_t k = 0; k < nv; ++k) indices[k] = k;
  std::vector<VtuCellTags> tags(2);
  tags[0].name = "site_id";
  tags[1].name = "hole";
  for (std::uint32_t i = 0; i < cv.nb_sites(); ++i) {
    for (std::uint32_t r = cv.cell_ring_begin(i); r < cv.cell_ring_begin(i + 1); ++r) {
      const std::uint32_t b = cv.ring_vertex_begin(r), e = cv.ring_vertex_begin(r + 1);
      if (ring_begin.empty()) ring_begin.push_back(b);
      ring_begin.push_back(e);
      double a = 0;
      for (std::uint32_t k = b; k < e; ++k) {
        const std::uint32_t l = k + 1 == e ? b : k + 1;
        a += (xy[2 * k] - xy[2 * b]) * (xy[2 * l + 1] - xy[2 * b + 1]) -
             (xy[2 * l] - xy[2 * b]) * (xy[2 * k + 1] - xy[2 * b + 1]);
      }
      tags[0].values.push_back(static_cast<std::int32_t>(i));
      tags[1].values.push_back(a < 0 ? 1 : 0);
    }
  }
  if (ring_begin.empty()) ring_begin.push_back(0);
  const std::uint32_t first = ring_begin[0];  // 0: the rings are stored cell by cell
  for (std::uint32_t& r : ring_begin) r -= first;
  const VtuCellBlock rings{indices.data() + first, ring_begin.size() - 1, 0, ring_begin.data()};
  write_vtu(out, xy.data(), nv, 2, {rings}, encoding, {}, tags);
}

// Each coordinate in the shortest decimal that reads back to its bits.
void write_sites(std::ostream& out, const std::vector<double>& sites) {
  for (std::size_t i = 0; i < sites.size() / 2; ++i) {
    out << format_double(sites[2 * i]) << ' ' << format_double(sites[2 * i + 1]) << '\n';
  }
}

void check_output_name(const std::string& path, bool sites_ok) {
  if (path.empty()) return;
  const std::string ext = lower_extension(path);
  if (ext == ".svg" || ext == ".vtu" || ext == ".json" || ext == ".csv") return;
  if (sites_ok && ext == ".txt") return;
  throw UsageError("-o: the output must end in .svg, .vtu, .json or .csv" +
                   std::string(sites_ok ? " (or .txt for the sites)" : "") + ", got '" + path +
                   "'");
}

void check_encoding(const ClipArgs& args) {
  if ((args.binary || args.compress) && lower_extension(args.output) != ".vtu") {
    throw UsageError(no_encoding_message(args.compress ? "--compress" : "--binary",
                                         lower_extension(args.output)));
  }
}

VtuEncoding vtu_encoding(const ClipArgs& args) {
  return args.compress ? VtuEncoding::kZlibBase64
                       : (args.binary ? VtuEncoding::kBase64 : VtuEncoding::kAscii);
}

void check_neighbors_name(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (!path.empty() && ext != ".csv" && ext != ".json") {
    throw UsageError("--neighbors: the table must end in .csv or .json, got '" + path + "'");
  }
}

// -o and --neighbors, together or not at all. The tables need the cells' geometry (the
// diagram computed with keep_geometry).
void write_output(const ClipArgs& args, const Domain2& domain, const std::vector<double>& sites,
                  const ClippedVoronoi2& cv) {
  const std::string ext = lower_extension(args.output);
  NeighborTable neighbors;
  const bool tables = ext == ".csv" || ext == ".json" || !args.neighbors.empty();
  if (tables) neighbors = cell_neighbors(cv);
  std::vector<FileWriter> files;
  if (!args.output.empty()) {
    files.push_back({args.output, [&](std::ostream& out) {
                       if (ext == ".svg") {
                         write_clip_svg(out, domain, sites, cv);
                       } else if (ext == ".vtu") {
                         write_clip_vtu(out, cv, vtu_encoding(args));
                       } else if (ext == ".json") {
                         write_clip_json(out, sites, cv, cell_table(cv, sites.data(), &neighbors));
                       } else if (ext == ".csv") {
                         write_cell_table_csv(out, cell_table(cv, sites.data(), &neighbors));
                       } else {
                         write_sites(out, sites);
                       }
                     }});
  }
  if (!args.neighbors.empty()) {
    files.push_back({args.neighbors, [&](std::ostream& out) {
                       if (lower_extension(args.neighbors) == ".json") {
                         write_neighbor_table_json(out, neighbors);
                       } else {
                         write_neighbor_table_csv(out, neighbors);
                       }
                     }});
  }
  write_files_atomically(files);
}

// Given sites outside the domain or repeated: a warning (an error with --strict); their
// numbers for --stats json.
struct SiteCheck {
  std::size_t outside = 0, repeated = 0;
};

// --random draws with density `draw` (cvt2d: rho^(1/2), a CVT's; uniform when constant).
std::vector<double> load_sites(const ClipArgs& args, const Domain2& domain, SiteCheck& check,
                               Progress& progress, const Density2& draw = {}) {
  if (args.sites.empty() == !args.random_set) {
    throw UsageError("give exactly one of --sites FILE and --random N");
  }
  if (args.random_set && args.random < 1) throw UsageError("--random: needs at least 1 site");
  if (args.random_set) return random_points2(domain, args.random, args.seed, draw);
  std::vector<double> sites = read_points(args.sites, 2);
  std::vector<std::uint32_t> outside;
  for (std::size_t i = 0; i < sites.size() / 2; ++i) {
    if (domain.locate(&sites[2 * i]) == Sign::negative) {
      outside.push_back(static_cast<std::uint32_t>(i));
    }
  }
  const std::vector<std::uint32_t> repeated = repeated_sites(sites, 2);
  report_sites(domain.source(), outside, repeated, args.strict, progress);
  check.outside = outside.size();
  check.repeated = repeated.size();
  return sites;
}

}  // namespace

void run_clip2d(const ClipArgs& args, const GlobalOptions& options) {
  check_output_name(args.output, false);
  check_encoding(args);
  check_neighbors_name(args.neighbors);
  check_outputs({{"-o", args.output}, {"--neighbors", args.neighbors}});
  Progress progress(options);
  progress.phase("reading");
  const Domain2 domain = load_domain(args.domain);
  SiteCheck site_check;
  const std::vector<double> sites = load_sites(args, domain, site_check, progress);
  const auto n = static_cast<std::uint32_t>(sites.size() / 2);
  ClippedVoronoi2 cv;
  Clip2Options o;
  o.keep_geometry = !args.output.empty() || !args.neighbors.empty();
  progress.phase("Delaunay and clipping");
  const auto t0 = std::chrono::steady_clock::now();
  cv.compute(domain, sites.data(), n, o);
  const double t_delaunay = cv.seconds_delaunay();
  const double t_clip = seconds_since(t0) - t_delaunay;
  if (o.keep_geometry) {
    progress.phase("writing");
    write_output(args, domain, sites, cv);
  }
  progress.done();
  if (options.stats_json) {
    print_stats(
        nlohmann::json{{"sites", n},
                       {"unique_sites", cv.delaunay().nb_unique_points() - cv.nb_auxiliary_sites()},
                       {"sites_outside", site_check.outside},
                       {"duplicate_sites", site_check.repeated},
                       {"boundary_sites", cv.nb_boundary_sites()},
                       {"domain_area", domain.area()},
                       {"cells_area_sum", cv.total_area()},
                       {"energy", cv.total_energy()},
                       {"seconds", t_delaunay + t_clip},
                       {"delaunay_seconds", t_delaunay},
                       {"clip_seconds", t_clip}},
        options);
  }
  if (std::ostream* out = human_stream(options)) {
    *out << "Clipped Voronoi diagram: " << count_of(n, "site") << " ("
         << count_of(cv.nb_boundary_sites(), "boundary cell") << ") in " << domain.source() << ", "
         << count_of(domain.nb_rings(), "ring") << "; cells' area "
         << format_double(cv.total_area()) << " (domain " << format_double(domain.area())
         << "); Delaunay " << format_double(t_delaunay) << " s, clipping " << format_double(t_clip)
         << " s\n";
    if (!args.output.empty()) *out << "Written to " << args.output << '\n';
    if (!args.neighbors.empty()) *out << "Neighbour pairs written to " << args.neighbors << '\n';
  }
}

void run_cvt2d(const ClipArgs& args, const GlobalOptions& options) {
  check_output_name(args.output, true);
  check_encoding(args);
  check_neighbors_name(args.neighbors);
  check_outputs({{"-o", args.output}, {"--neighbors", args.neighbors}});
  if (args.method != "lbfgs" && args.method != "lloyd") {
    throw UsageError("--method: expected lbfgs or lloyd, got '" + args.method + "'");
  }
  if (!(args.tolerance >= 0) || !std::isfinite(args.tolerance)) {
    throw UsageError("--tolerance: expected a finite number >= 0");
  }
  Progress progress(options);
  progress.phase("reading");
  const Domain2 domain = load_domain(args.domain);
  Cvt2Options o;
  o.method = args.method == "lloyd" ? CvtMethod::kLloyd : CvtMethod::kLbfgs;
  o.max_iterations = args.iterations;
  o.gradient_tolerance = args.tolerance;
  o.density = make_density2(args.density, domain);
  // A CVT of density rho has about rho^(d/(d+2)) sites per unit area: --random starts there.
  Density2 draw;
  if (!o.density.is_constant()) {
    const Density2 rho = o.density;
    draw = Density2::function([rho](double x, double y) { return std::sqrt(rho(x, y)); });
  }
  SiteCheck site_check;
  std::vector<double> sites = load_sites(args, domain, site_check, progress, draw);
  const auto n = static_cast<std::uint32_t>(sites.size() / 2);
  std::ostream* human = human_stream(options);
  progress.phase("CVT (" + args.method + ")", args.iterations);
  o.progress = [&](const CvtProgress& p) {
    progress.iteration(p.iteration, p.energy, p.gradient_norm);
    return true;
  };
  const Cvt2Result r = optimize_cvt2(domain, sites, o);
  if (!args.output.empty() || !args.neighbors.empty()) {
    progress.phase("writing");
    ClippedVoronoi2 cv;
    Clip2Options co;
    co.keep_geometry = true;
    co.density = o.density;
    cv.compute(domain, sites.data(), n, co);
    write_output(args, domain, sites, cv);
  }
  progress.done();
  if (options.stats_json) {
    print_stats(nlohmann::json{{"sites", n},
                               {"method", args.method},
                               {"sites_outside", site_check.outside},
                               {"duplicate_sites", site_check.repeated},
                               {"iterations", r.iterations},
                               {"evaluations", r.evaluations},
                               {"energy", r.energy},
                               {"gradient_norm", r.gradient_norm},
                               {"initial_gradient_norm", r.initial_gradient_norm},
                               {"converged", r.converged},
                               {"stop", cvt_stop_name(r.stop)},
                               {"density", args.density.describe()},
                               {"seconds", r.seconds}},
                options);
  }
  if (human) {
    *human << "CVT (" << args.method << "): " << count_of(r.iterations, "iteration") << ", "
           << count_of(r.evaluations, "diagram") << ", energy " << std::setprecision(12) << r.energy
           << ", |g|/|g0| " << std::setprecision(3)
           << (r.initial_gradient_norm > 0 ? r.gradient_norm / r.initial_gradient_norm : 0)
           << "; stopped: " << cvt_stop_name(r.stop) << ", " << r.seconds << " s\n";
    if (!args.output.empty()) *human << "Written to " << args.output << '\n';
    if (!args.neighbors.empty()) *human << "Neighbour pairs written to " << args.neighbors << '\n';
  }
}

}  // namespace voroclip::cli
