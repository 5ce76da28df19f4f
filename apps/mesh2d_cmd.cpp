// voroclip mesh2d: CVT triangle mesh of a polygonal domain (voroclip/mesh.h), its quality
// report, and the mesh written as an SVG picture, VTK .vtu, Medit .mesh or Gmsh .msh.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli.h"
#include "voroclip/core.h"
#include "voroclip/mesh.h"

namespace voroclip::cli {

namespace {

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// Per triangle: its smallest angle in degrees.
std::vector<double> min_angles(const Mesh2& mesh) {
  std::vector<double> out(mesh.nb_triangles());
  for (std::uint32_t t = 0; t < mesh.nb_triangles(); ++t) {
    double mn = 180;
    for (int k = 0; k < 3; ++k) {
      const double* a = &mesh.xy[2 * std::size_t{mesh.triangles[3 * std::size_t{t} + k]}];
      const double* b = &mesh.xy[2 * std::size_t{mesh.triangles[3 * std::size_t{t} + (k + 1) % 3]}];
      const double* c = &mesh.xy[2 * std::size_t{mesh.triangles[3 * std::size_t{t} + (k + 2) % 3]}];
      const double ux = b[0] - a[0], uy = b[1] - a[1], vx = c[0] - a[0], vy = c[1] - a[1];
      mn = std::min(mn, std::atan2(std::fabs(ux * vy - uy * vx), ux * vx + uy * vy) * 180 / M_PI);
    }
    out[t] = mn;
  }
  return out;
}

int vertex_ref(Mesh2::VertexKind k) {
  return k == Mesh2::VertexKind::kInterior ? 0 : k == Mesh2::VertexKind::kBoundary ? 1 : 2;
}

void write_mesh_vtu(std::ostream& out, const Mesh2& mesh) {
  const std::vector<double> angles = min_angles(mesh);
  out << std::setprecision(17);
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" "
         "byte_order=\"LittleEndian\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\""
      << mesh.nb_vertices() << "\" NumberOfCells=\"" << mesh.nb_triangles()
      << "\">\n<PointData Scalars=\"kind\">\n<DataArray type=\"UInt8\" Name=\"kind\" "
         "format=\"ascii\">\n";
  for (const Mesh2::VertexKind k : mesh.vertex_kind) out << vertex_ref(k) << '\n';
  out << "</DataArray>\n</PointData>\n<CellData Scalars=\"min_angle\">\n<DataArray "
         "type=\"Float64\" Name=\"min_angle\" format=\"ascii\">\n";
  for (const double a : angles) out << a << '\n';
  out << "</DataArray>\n</CellData>\n<Points>\n<DataArray type=\"Float64\" "
         "NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (std::uint32_t v = 0; v < mesh.nb_vertices(); ++v) {
    out << mesh.xy[2 * v] << ' ' << mesh.xy[2 * v + 1] << " 0\n";
  }
  out << "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" "
         "format=\"ascii\">\n";
  for (std::uint32_t t = 0; t < mesh.nb_triangles(); ++t) {
    out << mesh.triangles[3 * t] << ' ' << mesh.triangles[3 * t + 1] << ' '
        << mesh.triangles[3 * t + 2] << '\n';
  }
  out << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (std::uint32_t t = 0; t < mesh.nb_triangles(); ++t) out << 3 * (t + 1) << '\n';
  out << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (std::uint32_t t = 0; t < mesh.nb_triangles(); ++t) out << "5\n";
  out << "</DataArray>\n</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
}

// The mesh's boundary edges (edges of one triangle), in triangle order.
std::vector<std::uint32_t> boundary_edges(const Mesh2& mesh) {
  std::vector<std::uint64_t> directed;
  for (std::uint32_t t = 0; t < mesh.nb_triangles(); ++t) {
    for (int k = 0; k < 3; ++k) {
      directed.push_back(std::uint64_t{mesh.triangles[3 * t + k]} << 32 |
                         mesh.triangles[3 * t + (k + 1) % 3]);
    }
  }
  std::vector<std::uint64_t> sorted = directed;
  std::sort(sorted.begin(), sorted.end());
  std::vector<std::uint32_t> edges;
  for (const std::uint64_t e : directed) {
    const std::uint64_t reverse = (e & 0xffffffffu) << 32 | e >> 32;
    if (!std::binary_search(sorted.begin(), sorted.end(), reverse)) {
      edges.push_back(static_cast<std::uint32_t>(e >> 32));
      edges.push_back(static_cast<std::uint32_t>(e & 0xffffffffu));
    }
  }
  return edges;
}

// Medit: vertices with reference 0 interior, 1 sliding, 2 fixed; the boundary edges.
void write_mesh_medit(std::ostream& out, const Mesh2& mesh) {
  out << std::setprecision(17);
  out << "MeshVersionFormatted 2\n\nDimension 2\n\nVertices\n" << mesh.nb_vertices() << '\n';
  for (std::uint32_t v = 0; v < mesh.nb_vertices(); ++v) {
    out << mesh.xy[2 * v] << ' ' << mesh.xy[2 * v + 1] << ' ' << vertex_ref(mesh.vertex_kind[v])
        << '\n';
  }
  const std::vector<std::uint32_t> edges = boundary_edges(mesh);
  out << "\nEdges\n" << edges.size() / 2 << '\n';
  for (std::size_t e = 0; e < edges.size(); e += 2) {
    out << edges[e] + 1 << ' ' << edges[e + 1] + 1 << " 1\n";
  }
  out << "\nTriangles\n" << mesh.nb_triangles() << '\n';
  for (std::uint32_t t = 0; t < mesh.nb_triangles(); ++t) {
    out << mesh.triangles[3 * t] + 1 << ' ' << mesh.triangles[3 * t + 1] + 1 << ' '
        << mesh.triangles[3 * t + 2] + 1 << " 0\n";
  }
  out << "\nEnd\n";
}

// Gmsh 2.2 ASCII: the boundary edges (type 1, physical 1) and the triangles (type 2,
// physical 2).
void write_mesh_gmsh(std::ostream& out, const Mesh2& mesh) {
  out << std::setprecision(17);
  out << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n" << mesh.nb_vertices() << '\n';
  for (std::uint32_t v = 0; v < mesh.nb_vertices(); ++v) {
    out << v + 1 << ' ' << mesh.xy[2 * v] << ' ' << mesh.xy[2 * v + 1] << " 0\n";
  }
  const std::vector<std::uint32_t> edges = boundary_edges(mesh);
  const std::size_t ne = edges.size() / 2;
  out << "$EndNodes\n$Elements\n" << ne + mesh.nb_triangles() << '\n';
  std::size_t id = 1;
  for (std::size_t e = 0; e < ne; ++e) {
    out << id++ << " 1 2 1 1 " << edges[2 * e] + 1 << ' ' << edges[2 * e + 1] + 1 << '\n';
  }
  for (std::uint32_t t = 0; t < mesh.nb_triangles(); ++t) {
    out << id++ << " 2 2 2 1 " << mesh.triangles[3 * t] + 1 << ' ' << mesh.triangles[3 * t + 1] + 1
        << ' ' << mesh.triangles[3 * t + 2] + 1 << '\n';
  }
  out << "$EndElements\n";
}

// Fails before a long computation when a file could not be written at its end.
}  // namespace

// Triangles filled by their smallest angle (red below 30 degrees, through yellow to green at
// 60), the domain's rings in black, fixed vertices as dots.
void write_mesh_svg(std::ostream& out, const Domain2& domain, const Mesh2& mesh) {
  const double* lo = domain.bbox_lo();
  const double* hi = domain.bbox_hi();
  const double extent = std::max(hi[0] - lo[0], hi[1] - lo[1]);
  const double scale = 1000 / extent, margin = 10;
  const double w = (hi[0] - lo[0]) * scale, h = (hi[1] - lo[1]) * scale;
  out << std::setprecision(7);
  out << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << w + 2 * margin << "\" height=\""
      << h + 2 * margin << "\" viewBox=\"" << -margin << ' ' << -margin << ' ' << w + 2 * margin
      << ' ' << h + 2 * margin << "\">\n<rect x=\"" << -margin << "\" y=\"" << -margin
      << "\" width=\"" << w + 2 * margin << "\" height=\"" << h + 2 * margin
      << "\" fill=\"white\"/>\n";
  const auto X = [&](double x) { return (x - lo[0]) * scale; };
  const auto Y = [&](double y) { return (hi[1] - y) * scale; };
  const double stroke =
      std::max(0.05, std::min(0.6, 30 / std::sqrt(double(mesh.nb_vertices()) + 1)));
  const std::vector<double> angles = min_angles(mesh);
  // Group triangles by colour band (3-degree bands) to keep the file small.
  out << "<g stroke=\"#333\" stroke-width=\"" << stroke << "\" stroke-linejoin=\"round\">\n";
  for (int band = 0; band <= 20; ++band) {
    std::ostringstream d;
    d << std::setprecision(7);
    bool any = false;
    for (std::uint32_t t = 0; t < mesh.nb_triangles(); ++t) {
      const int b = std::min(20, static_cast<int>(angles[t] / 3));
      if (b != band) continue;
      any = true;
      for (int k = 0; k < 3; ++k) {
        const double* p = &mesh.xy[2 * std::size_t{mesh.triangles[3 * std::size_t{t} + k]}];
        d << (k == 0 ? 'M' : 'L') << X(p[0]) << ' ' << Y(p[1]);
      }
      d << 'Z';
    }
    if (!any) continue;
    // Hue 0 (red) below 30 degrees, then 30..60 degrees -> hue 50..130.
    const double a = band * 3 + 1.5;
    const int hue = a < 30 ? 0 : static_cast<int>(50 + (std::min(a, 60.0) - 30) * 80 / 30);
    out << "<path fill=\"hsl(" << hue << ",65%," << (a < 30 ? 55 : 78) << "%)\" d=\"" << d.str()
        << "\"/>\n";
  }
  out << "</g>\n<path fill=\"none\" stroke=\"black\" stroke-width=\"" << 3 * stroke << "\" d=\"";
  for (std::uint32_t r = 0; r < domain.nb_rings(); ++r) {
    for (std::uint32_t v = domain.ring_begin(r); v < domain.ring_end(r); ++v) {
      out << (v == domain.ring_begin(r) ? 'M' : 'L') << X(domain.vertex(v)[0]) << ' '
          << Y(domain.vertex(v)[1]);
    }
    out << 'Z';
  }
  out << "\"/>\n<g fill=\"black\">\n";
  const double radius = 2.5 * stroke;
  for (std::uint32_t v = 0; v < mesh.nb_vertices(); ++v) {
    if (mesh.vertex_kind[v] != Mesh2::VertexKind::kFixed) continue;
    out << "<circle cx=\"" << X(mesh.xy[2 * v]) << "\" cy=\"" << Y(mesh.xy[2 * v + 1]) << "\" r=\""
        << radius << "\"/>\n";
  }
  out << "</g>\n</svg>\n";
}

void write_mesh2_file(const std::string& path, const Domain2& domain, const Mesh2& mesh) {
  write_file_atomically(path, [&](std::ostream& out) {
    if (ends_with(path, ".svg")) {
      write_mesh_svg(out, domain, mesh);
    } else if (ends_with(path, ".vtu")) {
      write_mesh_vtu(out, mesh);
    } else if (ends_with(path, ".mesh")) {
      write_mesh_medit(out, mesh);
    } else {
      write_mesh_gmsh(out, mesh);
    }
  });
}

void run_mesh2d(const Mesh2dArgs& args, const GlobalOptions& options) {
  if (!args.output.empty() && !ends_with(args.output, ".svg") && !ends_with(args.output, ".vtu") &&
      !ends_with(args.output, ".mesh") && !ends_with(args.output, ".msh")) {
    throw UsageError("-o: the output must end in .svg, .vtu, .mesh or .msh, got '" + args.output +
                     "'");
  }
  if (!args.histogram.empty() && !ends_with(args.histogram, ".svg")) {
    throw UsageError("--histogram: the picture must end in .svg, got '" + args.histogram + "'");
  }
  const bool by_length = args.edge_length != 0;
  // A sizing field alone is the target edge length itself (--edge-length 1 scales it by 1).
  const bool sizing_alone = !args.vertices_set && !by_length &&
                            (!args.density.sizing.empty() || !args.density.sizing_file.empty());
  if (args.vertices_set == by_length && !sizing_alone) {
    throw UsageError("give exactly one of --vertices N and --edge-length H");
  }
  if (args.vertices_set && args.vertices < 3) throw UsageError("--vertices: needs at least 3");
  if (by_length && !(args.edge_length > 0 && std::isfinite(args.edge_length))) {
    throw UsageError("--edge-length: expected a positive number");
  }
  if (!(args.gradation > 0 && args.gradation <= 10)) {
    throw UsageError("--gradation: expected a number in (0, 10]");
  }
  if (!(args.sharp_angle >= 0 && args.sharp_angle < 180)) {
    throw UsageError("--sharp-angle: expected degrees in [0, 180)");
  }
  if (!(args.corner_angle >= 0 && args.corner_angle <= 180)) {
    throw UsageError("--corner-angle: expected degrees in [0, 180]");
  }
  if (args.method != "lbfgs" && args.method != "lloyd") {
    throw UsageError("--method: expected lbfgs or lloyd, got '" + args.method + "'");
  }
  check_output_path(args.output);
  check_output_path(args.histogram);
  const Domain2 domain = load_domain(args.domain);
  Mesh2Options o;
  o.nb_vertices = args.vertices;
  o.edge_length = sizing_alone ? 1.0 : args.edge_length;
  o.gradation = args.gradation;
  o.corner_angle_deg = args.corner_angle;
  o.sharp_angle_deg = args.sharp_angle;
  o.fix_input_vertices = args.fix_input_vertices;
  o.keep_gaps = args.keep_gaps;
  o.conforming = !args.circumcenter_rule;
  o.repair_rounds = args.repair_rounds;
  o.seed = args.seed;
  o.method = args.method == "lloyd" ? CvtMethod::kLloyd : CvtMethod::kLbfgs;
  o.constrained_iterations = args.iterations;
  o.density = make_density2(args.density, domain);
  std::ostream* human = human_stream(options);
  o.progress = [&](const Mesh2Progress& p) {
    // Every 10th iteration, and the start of each phase.
    if (human && (p.iteration % 10 == 0)) {
      *human << std::left << std::setw(18) << phase_name(p.phase) << std::right << " iteration "
             << std::setw(4) << p.iteration;
      if (p.phase == Mesh2Phase::kUnconstrained || p.phase == Mesh2Phase::kConstrained) {
        *human << "  energy " << std::setprecision(10) << p.energy << "  |g| "
               << std::setprecision(4) << p.gradient_norm;
      }
      *human << "  " << std::setprecision(3) << p.seconds << " s\n";
    }
    return true;
  };
  Mesh2Stats st;
  const Mesh2 mesh = mesh_domain2(domain, o, &st);
  if (mesh.nb_triangles() == 0) {
    throw Error("mesh2d: " + domain.source() + ": no triangle (too few vertices for the domain?)");
  }
  if (!st.check.empty()) {
    throw Error("mesh2d: " + domain.source() + ": the mesh failed its own check (" + st.check +
                "); no file written. This is a defect of voroclip: please report it with the "
                "input and the command");
  }
  const TriangleQuality2 q = triangle_quality2(mesh, 2.0);
  if (!args.output.empty()) write_mesh2_file(args.output, domain, mesh);
  if (!args.histogram.empty()) {
    write_file_atomically(args.histogram, [&](std::ostream& out) {
      write_quality_svg(out, q, "voroclip mesh2d: " + domain.source());
    });
  }
  if (options.stats_json) {
    nlohmann::ordered_json s;
    s["vertices"] = mesh.nb_vertices();
    s["triangles"] = mesh.nb_triangles();
    s["min_angle_deg"] = q.min_angle;
    s["mean_min_angle_deg"] = q.mean_min_angle;
    s["max_angle_deg"] = q.max_angle;
    s["mean_max_angle_deg"] = q.mean_max_angle;
    s["min_radius_ratio"] = q.min_radius_ratio;
    s["mean_radius_ratio"] = q.mean_radius_ratio;
    s["triangles_below_30_deg"] = q.nb_below_30;
    s["sites"] = st.nb_sites;
    s["fixed_sites"] = st.nb_fixed;
    s["sliding_sites"] = st.nb_sliding;
    s["sharp_corners"] = st.nb_sharp_corners;
    s["edge_length"] = st.edge_length;
    s["min_feature_size"] = st.min_size;
    s["unconstrained_iterations"] = st.unconstrained_iterations;
    s["constrained_iterations"] = st.constrained_iterations;
    s["relative_gradient"] = st.relative_gradient;
    s["gap_sites"] = st.nb_gap_sites;
    s["repair_rounds"] = st.repair_rounds;
    s["repair_removed"] = st.repair_removed;
    s["gaps"] = st.nb_gaps;
    s["covered_fraction"] = st.covered_fraction;
    s["dropped_outside"] = st.dropped_outside;
    s["removed_vertices"] = st.removed_vertices;
    s["seconds"] = st.seconds;
    s["seconds_phases"] = {{"sampling", st.seconds_sampling},
                           {"unconstrained", st.seconds_unconstrained},
                           {"constrained", st.seconds_constrained},
                           {"extraction", st.seconds_extraction}};
    s["quality"] = nlohmann::json::parse(quality_json(q));
    std::cout << s.dump() << '\n';
  }
  if (human) {
    *human << "Mesh of " << domain.source() << ": " << mesh.nb_vertices() << " vertices ("
           << st.nb_fixed << " fixed, " << st.nb_sliding << " sliding sites), "
           << mesh.nb_triangles() << " triangles in " << std::setprecision(3) << st.seconds << " s";
    if (st.nb_sharp_corners) *human << "; " << st.nb_sharp_corners << " sharp corners cut";
    if (st.dropped_outside) *human << "; " << st.dropped_outside << " triangles dropped";
    *human << "; " << std::setprecision(4) << 100 * st.covered_fraction
           << "% of the domain's area covered\n"
           << quality_text(q);
    if (!args.output.empty()) *human << "Written to " << args.output << '\n';
    if (!args.histogram.empty()) *human << "Histogram written to " << args.histogram << '\n';
  }
}

}  // namespace voroclip::cli
