// voroclip quality: the quality report of a tet mesh (Q1..Q4 of Yan et al. 2011, sec. 6,
// their histograms, inverted and degenerate tets) and, with --surface, the Hausdorff
// distance between its boundary and a reference surface.
#include <algorithm>
#include <cctype>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include "cli.h"
#include "progress.h"
#include "voroclip/core.h"
#include "voroclip/mesh.h"

namespace voroclip::cli {

namespace {

bool is_surface_file(const std::string& ext) {
  return ext == ".obj" || ext == ".off" || ext == ".stl" || ext == ".ply";
}

bool is_tet_mesh_file(const std::string& ext) {
  return ext == ".mesh" || ext == ".node" || ext == ".ele" || ext == ".msh" || ext == ".vtk" ||
         ext == ".vtu";
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

void run_quality(const QualityArgs& args, const GlobalOptions& options) {
  if (!args.histogram.empty() && lower_extension(args.histogram) != ".svg") {
    throw UsageError("--histogram: the picture must end in .svg, got '" + args.histogram + "'");
  }
  if (!args.output.empty() && lower_extension(args.output) != ".vtu") {
    throw UsageError("-o: the output must end in .vtu (the mesh with Q1..Q4 per tet), got '" +
                     args.output + "'");
  }
  check_outputs({{"-o", args.output}, {"--histogram", args.histogram}});
  const std::string ref_ext = input_extension(args.surface);
  std::error_code ec;
  if (!args.surface.empty() && std::filesystem::is_directory(args.surface, ec)) {
    throw Error(args.surface + ": is a directory, not a file");
  }
  if (!args.surface.empty() && !is_surface_file(ref_ext) && !is_tet_mesh_file(ref_ext)) {
    throw UsageError("--surface: unknown format " +
                     (ref_ext.empty() ? std::string("(no extension)") : "'" + ref_ext + "'") +
                     " of '" + args.surface +
                     "': expected a surface (.obj, .off, .stl, .ply) or a tet mesh (.mesh, "
                     ".node/.ele, .msh, .vtk, .vtu) whose boundary is used");
  }
  if (args.samples_set && args.surface.empty()) {
    throw UsageError("--samples: only with --surface (it sets the samples of the distance to it)");
  }
  if (args.compress && args.output.empty()) {
    throw UsageError("--compress: needs -o FILE.vtu (it compresses the .vtu output)");
  }
  const auto start = std::chrono::steady_clock::now();
  Progress progress(options);
  progress.phase("reading");
  const TetMeshInput mesh = read_tet_mesh(args.mesh);
  // Every input is read before any work (a bad reference is reported alone, at once).
  TriangleSurface reference, boundary;
  if (!args.surface.empty()) {
    reference = is_surface_file(ref_ext) ? read_surface(args.surface)
                                         : tet_mesh_boundary(read_tet_mesh(args.surface));
    boundary = tet_mesh_boundary(mesh);
    if (boundary.nb_triangles() == 0) {
      throw Error(args.mesh + ": the mesh has no boundary triangle to compare");
    }
  }
  const double t_read = seconds_since(start);
  TetQualityOptions qo;
  qo.keep_per_tet = !args.output.empty();
  progress.phase("quality");
  const auto t1 = std::chrono::steady_clock::now();
  const TetQuality q = tet_quality(mesh, qo);
  const double t_quality = seconds_since(t1);

  HausdorffDistance distance;
  double t_hausdorff = 0;
  if (!args.surface.empty()) {
    progress.phase("Hausdorff distance");
    HausdorffOptions ho;
    if (args.samples_set) ho.min_samples = args.samples;
    const auto t2 = std::chrono::steady_clock::now();
    distance = hausdorff_distance(boundary, reference, ho);
    t_hausdorff = seconds_since(t2);
  }
  const HausdorffDistance* d = args.surface.empty() ? nullptr : &distance;

  // --histogram and -o appear together or not at all.
  std::vector<FileWriter> files;
  if (!args.histogram.empty()) {
    files.push_back(
        {args.histogram, [&](std::ostream& out) { write_quality_svg(out, q, args.mesh); }});
  }
  std::vector<VtuCellField> fields;
  if (!args.output.empty()) {
    fields.resize(4);
    fields[0].name = "q1_min_dihedral_deg";
    fields[1].name = "q2_max_dihedral_deg";
    fields[2].name = "q3_radius_ratio";
    fields[3].name = "q4";
    for (auto& f : fields) f.values.reserve(q.per_tet.size());
    for (const TetShape& s : q.per_tet) {
      fields[0].values.push_back(s.q1_deg);
      fields[1].values.push_back(s.q2_deg);
      fields[2].values.push_back(s.q3);
      fields[3].values.push_back(s.q4);
    }
    files.push_back({args.output, [&](std::ostream& out) {
                       write_vtu(out, mesh.xyz.data(), mesh.nb_vertices(), 3,
                                 {{mesh.tets.data(), mesh.nb_tets(), 4}},
                                 args.compress ? VtuEncoding::kZlibBase64 : VtuEncoding::kBase64,
                                 fields);
                     }});
  }
  if (!files.empty()) {
    progress.phase("writing " + (args.histogram.empty() ? args.output
                                 : args.output.empty()  ? args.histogram
                                                        : args.histogram + " and " + args.output));
    write_files_atomically(files);
  }
  progress.done();
  if (options.stats_json) {
    std::ostringstream text;
    write_quality_json(text, q, d);
    nlohmann::json j = nlohmann::json::parse(text.str());
    j["mesh"] = args.mesh;
    if (d != nullptr) j["surface"] = args.surface;
    j["seconds"] = {{"read", t_read},
                    {"quality", t_quality},
                    {"hausdorff", t_hausdorff},
                    {"total", seconds_since(start)}};
    print_stats(j, options);
  }
  if (std::ostream* out = human_stream(options)) {
    write_quality_text(*out, q, args.mesh, d, args.surface);
    if (!args.histogram.empty()) *out << "Histograms written to " << args.histogram << '\n';
    if (!args.output.empty()) *out << "Per-tet quality written to " << args.output << '\n';
  }
}

}  // namespace voroclip::cli
