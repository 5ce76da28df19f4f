// voroclip mesh2d: CVT triangle mesh of a polygonal domain (voroclip/mesh.h), its quality
// report, and the mesh written as an SVG picture, VTK .vtu, Medit .mesh or Gmsh .msh.
#include <algorithm>
#include <charconv>
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
#include "progress.h"
#include "voroclip/core.h"
#include "voroclip/mesh.h"

namespace voroclip::cli {

namespace {

// Whether the file's extension is `ext` (".svg"), in any case, as the other commands take them.
bool ends_with(const std::string& path, const std::string& ext) {
  return lower_extension(path) == ext;
}

// The tags a mesh of `rings` would carry, checked before meshing: regional attributes must
// be integers (mesh tags are), and a Gmsh file (`gmsh`) takes only positive physical tags,
// so no negative segment marker (0 means "no marker" and becomes 1, see Domain2::edge_tag)
// and no regional attribute below 1. Named as the file numbers them, with their lines.
void check_mesh_tags(const PolygonRings& rings, const Domain2& domain, bool gmsh) {
  const std::string gmsh_fix = ", but a Gmsh .msh file takes only positive physical tags; use ";
  const std::string other_formats = ", or write .vtu or .mesh, which take any integer tag";
  for (std::size_t k = 0; k < rings.region_attributes.size(); ++k) {
    const double value = rings.region_attributes[k];
    char text_buf[32];
    const std::string text_value(text_buf,
                                 std::to_chars(text_buf, text_buf + sizeof text_buf, value).ptr);
    if (!(value == std::floor(value) && std::fabs(value) <= 2147483647.0)) {
      throw Error(domain.source() + ": " + domain.region_name(k) + " is " + text_value +
                  ", not an integer: mesh regions are tagged by integers");
    }
    if (gmsh && value < 1) {
      throw Error(domain.source() + ": " + domain.region_name(k) + " is " + text_value + gmsh_fix +
                  "regional attributes >= 1" + other_formats);
    }
  }
  if (!gmsh) return;
  for (std::size_t i = 0; i < rings.segment_marker.size(); ++i) {
    const std::int32_t marker = rings.segment_marker[i];
    if (marker >= 0) continue;
    std::string where = domain.source();
    std::string segment = "segment " + std::to_string(i) + " (from 0, in the order given)";
    if (i < rings.segment_number.size())
      segment = "segment " + std::to_string(rings.segment_number[i]);
    if (i < rings.segment_line.size()) where += ":" + std::to_string(rings.segment_line[i]);
    throw Error(where + ": " + segment + " has boundary marker " + std::to_string(marker) +
                gmsh_fix + "markers >= 1 (0 means no marker and becomes 1)" + other_formats);
  }
}

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
  const std::vector<double> angles = triangle_min_angles(mesh);
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

FileWriter mesh2_file(const std::string& path, const Domain2& domain, const Mesh2& mesh, bool msh22,
                      VtuEncoding encoding) {
  return {path, [path, &domain, &mesh, msh22, encoding](std::ostream& out) {
            if (ends_with(path, ".svg")) {
              write_mesh_svg(out, domain, mesh);
            } else if (ends_with(path, ".vtu")) {
              write_mesh2(out, mesh,
                          encoding == VtuEncoding::kZlibBase64 ? Mesh2FileFormat::kVtuCompressed
                          : encoding == VtuEncoding::kBase64   ? Mesh2FileFormat::kVtuBinary
                                                               : Mesh2FileFormat::kVtu);
            } else if (ends_with(path, ".mesh")) {
              write_mesh2(out, mesh, Mesh2FileFormat::kMedit);
            } else {
              write_mesh2(out, mesh, msh22 ? Mesh2FileFormat::kGmsh22 : Mesh2FileFormat::kGmsh41);
            }
          }};
}

// Triangles with an angle below 30 degrees, each with the sharpest domain corner among its
// vertices (interior angle below 60 degrees; -1 when none): the bound there is
// min(30, that corner's angle).
struct LowAngle {
  std::uint32_t triangle;
  double min_angle;
  std::uint32_t corner;  // domain vertex, or Mesh2::kNone
  double corner_angle;
};
std::vector<LowAngle> low_angles(const Domain2& domain, const Mesh2& mesh) {
  std::vector<LowAngle> out;
  const std::vector<double> angles = triangle_min_angles(mesh);
  for (std::uint32_t t = 0; t < mesh.nb_triangles(); ++t) {
    if (angles[t] >= 30) continue;
    LowAngle low{t, angles[t], Mesh2::kNone, 180};
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v =
          mesh.vertex_domain[mesh.triangles[3 * t + static_cast<std::uint32_t>(k)]];
      if (v == Mesh2::kNone) continue;
      const double* a = domain.vertex(domain.prev(v));
      const double* p = domain.vertex(v);
      const double* c = domain.vertex(domain.next(v));
      const double ux = p[0] - a[0], uy = p[1] - a[1], wx = c[0] - p[0], wy = c[1] - p[1];
      const double interior = 180 - std::atan2(ux * wy - uy * wx, ux * wx + uy * wy) * 180 / M_PI;
      if (interior < 60 && interior < low.corner_angle) {
        low.corner = v;
        low.corner_angle = interior;
      }
    }
    out.push_back(low);
  }
  return out;
}

// Peak resident memory of a mesh2d run per vertex: 43,468 kB at --vertices 25000 and
// 146,816 kB at 100000 (a unit square, Release build, 2026-12-02, getrusage's ru_maxrss), a
// slope of 1,411 bytes per vertex; rounded down, so that only a count that clearly cannot
// fit is refused (check_vertex_count).
constexpr double kMesh2BytesPerVertex = 1400;

void run_mesh2d(const Mesh2dArgs& args, const GlobalOptions& options) {
  if (!args.output.empty() && !ends_with(args.output, ".svg") && !ends_with(args.output, ".vtu") &&
      !ends_with(args.output, ".mesh") && !ends_with(args.output, ".msh")) {
    throw UsageError("-o: the output must end in .svg, .vtu, .mesh or .msh, got '" + args.output +
                     "'");
  }
  if (!args.histogram.empty() && !ends_with(args.histogram, ".svg")) {
    throw UsageError("--histogram: the picture must end in .svg, got '" + args.histogram + "'");
  }
  if ((args.binary || args.compress) && !ends_with(args.output, ".vtu")) {
    const std::string flag = args.compress ? "--compress" : "--binary";
    const std::string ext = lower_extension(args.output);
    if (ext == ".mesh" || ext == ".msh") {
      throw UsageError(flag +
                       ": only a .vtu output (-o FILE.vtu) is written in binary or compressed; "
                       "mesh2d writes " +
                       ext + " in ASCII only");
    }
    throw UsageError(no_encoding_message(flag, ext));
  }
  const bool by_length = args.edge_length_set;
  // A sizing field alone is the target edge length itself (--edge-length 1 scales it by 1).
  const bool sizing_alone = !args.vertices_set && !by_length &&
                            (!args.density.sizing.empty() || !args.density.sizing_file.empty());
  if (args.vertices_set == by_length && !sizing_alone) {
    throw UsageError("give exactly one of --vertices N and --edge-length H");
  }
  if (args.msh_version != "2.2" && args.msh_version != "4.1") {
    throw UsageError("--msh-version: expected 2.2 or 4.1, got '" + args.msh_version + "'");
  }
  if (args.msh_version_set && !ends_with(args.output, ".msh")) {
    throw UsageError(
        "--msh-version: only a .msh output (Gmsh) has a format version, got " +
        (args.output.empty() ? std::string("no output file") : "'" + args.output + "'"));
  }
  if (args.keep_gaps && !args.circumcenter_rule) {
    throw UsageError(
        "--keep-gaps: only with --circumcenter-rule (the default extraction leaves "
        "no gaps)");
  }
  if (args.exact_vertices && !args.vertices_set) {
    throw UsageError(
        "--exact-vertices: only with --vertices N (the count it keeps; --edge-length and a "
        "sizing alone never raise the count)");
  }
  if (args.vertices_set && args.vertices < 3) throw UsageError("--vertices: needs at least 3");
  if (args.vertices_set) {
    check_vertex_count("mesh2d", "--vertices", args.vertices, kMesh2BytesPerVertex,
                       "give fewer --vertices");
  }
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
  check_outputs({{"-o", args.output}, {"--histogram", args.histogram}});
  const PolygonRings rings = load_rings(args.domain);
  const Domain2 domain(rings);
  check_mesh_tags(rings, domain, ends_with(args.output, ".msh"));
  const std::string larger_size = "give a larger --edge-length or --sizing";
  if (by_length && !args.density.given()) {
    // A uniform size h gives at least the equilateral count 2 / sqrt(3) area / h^2 (the
    // library's implied count, which also grades towards small features): refused here,
    // before the library's own bound (10^9) could refuse it without the count.
    check_vertex_count("mesh2d", "--edge-length " + format_double(args.edge_length),
                       2 / std::sqrt(3.0) * domain.area() / (args.edge_length * args.edge_length),
                       kMesh2BytesPerVertex, larger_size);
  }
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
  Progress progress(options);
  bool started = false;
  Mesh2Phase phase = Mesh2Phase::kSampling;
  o.raise_for_mean_angle = !args.exact_vertices;
  std::string refused;  // why the implied vertex count is refused (the sampling is stopped)
  o.progress = [&](const Mesh2Progress& p) {
    if (p.implied_vertices > 0) {
      return note_implied_vertices("mesh2d",
                                   by_length ? "--edge-length " + format_double(args.edge_length)
                                             : std::string("the sizing"),
                                   p.implied_vertices, kMesh2BytesPerVertex, larger_size, progress,
                                   refused);
    }
    if (p.retry_vertices > 0) {
      char mean[32];
      std::snprintf(mean, sizeof mean, "%.2f", p.energy);
      progress.note(std::string("mean smallest angle ") + mean + " below " +
                    std::to_string(static_cast<int>(o.mean_angle_target_deg)) +
                    " degrees; meshing again with " + std::to_string(p.retry_vertices) +
                    " vertices (--exact-vertices keeps the count)");
      started = false;
      return true;
    }
    // A new phase at a change of phase, and at each repair round (its CVT starts over).
    if (!started || p.phase != phase || p.iteration == 0) {
      const std::uint32_t budget = p.phase == Mesh2Phase::kUnconstrained
                                       ? o.unconstrained_iterations
                                   : p.phase == Mesh2Phase::kConstrained ? o.constrained_iterations
                                                                         : 0;
      progress.phase(phase_name(p.phase), budget);
      started = true;
      phase = p.phase;
    }
    if (p.phase == Mesh2Phase::kUnconstrained || p.phase == Mesh2Phase::kConstrained ||
        p.phase == Mesh2Phase::kRepair) {
      if (p.iteration > 0) progress.iteration(p.iteration, p.energy, p.gradient_norm, 10);
    }
    return true;
  };
  Mesh2Stats st;
  const Mesh2 mesh = mesh_domain2(domain, o, &st);
  if (!refused.empty()) throw Error(refused);
  if (mesh.nb_triangles() == 0) {
    throw Error("mesh2d: " + domain.source() + ": no triangle (too few vertices for the domain?)");
  }
  if (!st.check.empty()) {
    throw Error("mesh2d: " + domain.source() + ": the mesh failed its own check (" + st.check +
                "); no file written. This is a defect of voroclip: please report it with the "
                "input and the command");
  }
  progress.phase("quality");
  const TriangleQuality2 q = triangle_quality2(mesh, 2.0);
  const std::vector<LowAngle> lows = low_angles(domain, mesh);
  // -o and --histogram appear together or not at all.
  std::vector<FileWriter> files;
  if (!args.output.empty()) {
    files.push_back(mesh2_file(args.output, domain, mesh, args.msh_version == "2.2",
                               args.compress ? VtuEncoding::kZlibBase64
                               : args.binary ? VtuEncoding::kBase64
                                             : VtuEncoding::kAscii));
  }
  if (!args.histogram.empty()) {
    files.push_back({args.histogram, [&](std::ostream& out) {
                       write_quality_svg(out, q, "voroclip mesh2d: " + domain.source());
                     }});
  }
  if (!files.empty()) {
    progress.phase("writing " + (args.output.empty() ? args.histogram
                                 : args.histogram.empty()
                                     ? args.output
                                     : args.output + " and " + args.histogram));
    write_files_atomically(files);
  }
  progress.done();
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
    nlohmann::ordered_json below = nlohmann::ordered_json::array();
    for (const LowAngle& l : lows) {
      nlohmann::ordered_json j;
      j["triangle"] = l.triangle;
      j["min_angle_deg"] = l.min_angle;
      if (l.corner != Mesh2::kNone) {
        j["corner"] = {domain.vertex(l.corner)[0], domain.vertex(l.corner)[1]};
        j["corner_angle_deg"] = l.corner_angle;
        j["bound_met"] = l.min_angle >= std::min(30.0, l.corner_angle) - 1e-9;
      } else {
        j["corner"] = nullptr;
        j["bound_met"] = false;
      }
      below.push_back(j);
    }
    s["below_30"] = below;
    s["requested_vertices"] = st.requested_vertices;
    if (st.implied_vertices > 0) {
      s["implied_vertices"] = st.implied_vertices;
    } else {
      s["implied_vertices"] = nullptr;
    }
    s["vertex_count_runs"] = st.vertex_count_runs;
    s["feature_vertices"] = st.feature_vertices;
    s["vertex_count_within_tolerance"] = st.vertex_count_note.empty();
    if (st.vertex_count_note.empty()) {
      s["vertex_count_note"] = nullptr;
    } else {
      s["vertex_count_note"] = st.vertex_count_note;
    }
    if (st.mean_angle_note.empty()) {
      s["mean_angle_note"] = nullptr;
    } else {
      s["mean_angle_note"] = st.mean_angle_note;
    }
    s["mean_angle_runs"] = st.mean_angle_runs;
    if (st.mean_angle_raise.empty()) {
      s["mean_angle_raise"] = nullptr;
    } else {
      s["mean_angle_raise"] = st.mean_angle_raise;
    }
    s["refined_vertices"] = st.refine_added;
    s["smoothed_vertices"] = st.smoothed;
    s["flips"] = st.flips;
    s["tip_triangles"] = st.nb_tip_triangles;
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
    print_stats(s, options);
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
    if (!lows.empty()) {
      std::size_t at_corner = 0, met = 0;
      double worst_elsewhere = 180;
      for (const LowAngle& l : lows) {
        if (l.corner != Mesh2::kNone) {
          ++at_corner;
          met += l.min_angle >= std::min(30.0, l.corner_angle) - 1e-9;
        } else {
          worst_elsewhere = std::min(worst_elsewhere, l.min_angle);
        }
      }
      *human << count_of(lows.size(), "triangle") << " below 30 degrees: " << at_corner
             << " at input corners sharper than 60 degrees (" << met
             << " reaching min(30, the corner's angle))";
      if (at_corner < lows.size()) {
        *human << ", " << lows.size() - at_corner << " elsewhere (smallest " << std::setprecision(3)
               << worst_elsewhere << " degrees; --stats json lists them)";
      }
      *human << '\n';
    }
    if (!st.vertex_count_note.empty()) {
      *human << "note: " << st.vertex_count_note
             << (st.mean_angle_raise.empty() ? "" : " (--exact-vertices keeps the count)") << '\n';
    }
    if (!st.mean_angle_note.empty()) *human << "note: " << st.mean_angle_note << '\n';
    if (!args.output.empty()) *human << "Written to " << args.output << '\n';
    if (!args.histogram.empty()) *human << "Histogram written to " << args.histogram << '\n';
  }
}

}  // namespace voroclip::cli
