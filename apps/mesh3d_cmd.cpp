// voroclip mesh3d: CVT tetrahedral meshing of a volume, given by its closed surface or a tet
// mesh (mesh3d in
// voroclip/mesh.h): progress per phase, the mesh as Medit, Gmsh or VTK XML, and the quality
// report (Q1..Q4, Hausdorff distance of the boundary to the input's) in --stats json.
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli.h"
#include "progress.h"
#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/mesh.h"

namespace voroclip::cli {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

std::string fixed(double x, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, x);
  return buf;
}

// x to 4 significant digits.
std::string brief(double x) {
  std::ostringstream out;
  out << std::setprecision(4) << x;
  return out.str();
}

// A count to 2 significant digits ("250000"; "3.1e+13" past 1e12).
std::string about_count(double x) {
  char buf[64];
  if (x >= 1e12) {
    std::snprintf(buf, sizeof buf, "%.1e", x);
    return buf;
  }
  const double unit = x < 100 ? 1 : std::pow(10.0, std::floor(std::log10(x)) - 1);
  std::snprintf(buf, sizeof buf, "%.0f", std::round(x / unit) * unit);
  return buf;
}

}  // namespace

// Peak resident memory of a mesh3d run per vertex: 28,044 kB at --vertices 5000 and
// 58,420 kB at 20000 (sphere.obj, Release build, 2026-12-02, getrusage's ru_maxrss), a
// slope of 2,074 bytes per vertex; rounded down, so that only a count that clearly cannot
// fit is refused (check_vertex_count, as mesh2d's).
constexpr double kMesh3BytesPerVertex = 2000;

void run_mesh3d(const Mesh3dArgs& args, const GlobalOptions& options) {
  const std::string ext = lower_extension(args.output);
  if (!args.output.empty() && ext != ".mesh" && ext != ".msh" && ext != ".vtu" && ext != ".node" &&
      ext != ".ele") {
    throw UsageError(
        "-o: the output must end in .mesh (Medit), .msh (Gmsh), .vtu (VTK XML) or .node / .ele "
        "(TetGen), got '" +
        args.output + "'");
  }
  if (args.msh_version != "2.2" && args.msh_version != "4.1") {
    throw UsageError("--msh-version: expected 2.2 or 4.1, got '" + args.msh_version + "'");
  }
  if (args.binary && (ext != ".msh" || args.msh_version != "4.1")) {
    throw UsageError("--binary: only a .msh output in Gmsh 4.1 is written in binary");
  }
  if (args.msh_version_set && ext != ".msh") {
    throw UsageError(
        "--msh-version: only a .msh output (Gmsh) has a format version, got " +
        (args.output.empty() ? std::string("no output file") : "'" + args.output + "'"));
  }
  if (args.compress && ext != ".vtu") {
    throw UsageError("--compress: only a .vtu output is compressed");
  }
  // TetGen's three files are checked, and written, together.
  {
    std::vector<OutputOption> outputs;
    for (const std::string& path :
         tet_mesh_files(args.output, ext == ".node" || ext == ".ele" ? TetMeshFormat::kTetGen
                                                                     : TetMeshFormat::kMedit)) {
      outputs.push_back({"-o", path});
    }
    check_outputs(outputs);
  }
  // --sizing / --sizing-file alone: h is the edge length in model units and the vertex
  // count follows from it; with --vertices, h gives the shape and --vertices the count.
  const bool sizing = !args.density.sizing.empty() || !args.density.sizing_file.empty();
  if (!args.vertices_set && !sizing) {
    throw UsageError(
        "--vertices N is required (without it only --sizing or --sizing-file, "
        "whose h is then the edge length in model units)");
  }
  if (args.vertices_set && args.vertices < 4) {
    throw UsageError("--vertices: needs at least 4 vertices");
  }
  if (args.vertices_set) {
    check_vertex_count("mesh3d", "--vertices", args.vertices, kMesh3BytesPerVertex,
                       "give fewer --vertices");
  }
  if (!(args.feature_angle >= 0 && args.feature_angle <= 180)) {
    throw UsageError("--feature-angle: expected degrees in [0, 180], got " +
                     format_double(args.feature_angle));
  }
  if (!(args.sliver_angle >= 0 && args.sliver_angle < 70.5)) {
    throw UsageError("--sliver-angle: expected degrees in [0, 70.5), got " +
                     format_double(args.sliver_angle));
  }
  if (!(args.flip_angle >= 0 && args.flip_angle < 70.5)) {
    throw UsageError("--flip-angle: expected degrees in [0, 70.5), got " +
                     format_double(args.flip_angle));
  }
  if (!(args.lfs_cap >= 0) || !std::isfinite(args.lfs_cap)) {
    throw UsageError("--lfs-cap: expected a number >= 0, got " + format_double(args.lfs_cap));
  }
  if (!(args.facet_distance >= 0) || !std::isfinite(args.facet_distance)) {
    throw UsageError("--facet-distance: expected a number >= 0, got " +
                     format_double(args.facet_distance));
  }
  if (!(args.max_boundary_distance >= 0) || !std::isfinite(args.max_boundary_distance)) {
    throw UsageError("--max-boundary-distance: expected a number >= 0, got " +
                     format_double(args.max_boundary_distance));
  }
  if (!(args.smooth_shape >= 0 && args.smooth_shape <= 1)) {
    throw UsageError("--smooth-shape: expected a value in [0, 1], got " +
                     format_double(args.smooth_shape));
  }
  const auto start = std::chrono::steady_clock::now();
  Progress progress(options);
  progress.phase("reading");
  const Domain3 domain = load_domain3(args.domain, args.reorient, options);
  const double t_read = seconds_since(start);

  std::ostream* out = human_stream(options);
  Mesh3Options o;
  o.nb_vertices = args.vertices;
  o.adaptive = args.adaptive;
  o.lfs_cap = args.lfs_cap;
  o.facet_distance = args.facet_distance;
  o.max_boundary_distance = args.max_boundary_distance;
  if (args.adaptive && args.density.given()) {
    throw UsageError("--adaptive and " + args.density.describe() + " exclude each other");
  }
  o.density = make_density3(args.density, domain, /*pointwise=*/true);
  if (!args.vertices_set) o.edge_length = 1;  // h itself (rho = h^-5)
  o.features = !args.no_features;
  o.feature_angle_deg = args.feature_angle;
  o.seed = args.seed;
  o.unconstrained_iterations = args.unconstrained_iterations;
  o.constrained_iterations = args.constrained_iterations;
  o.perturb = !args.no_perturb;
  o.smooth_surface = args.smooth_surface;
  o.smooth_shape = args.smooth_shape;
  o.perturbation.target_dihedral_deg = args.sliver_angle;
  o.flip_dihedral_deg = args.flip_angle;
  o.mean_rounds = args.mean_rounds;
  o.vertex_count =
      args.exact_vertices ? Mesh3Options::VertexCount::kExact : Mesh3Options::VertexCount::kRaise;
  // Installed also under -q: the count an absolute size implies is checked against the
  // memory before the run (check_vertex_count), as mesh2d's.
  std::string refused;  // why the implied vertex count is refused (the run is not started)
  o.progress = [&progress, &args, &refused](const Mesh3Progress& p) {
    if (p.implied_vertices > 0) {
      return note_implied_vertices("mesh3d", "the sizing", p.implied_vertices, kMesh3BytesPerVertex,
                                   "give a larger --sizing (or --vertices N)", progress, refused);
    }
    if (p.retry_vertices > 0) {
      progress.note("the mesh does not have the domain's shape; meshing again with " +
                    std::to_string(p.retry_vertices) + " vertices");
      return true;
    }
    if (p.body_vertices > 0) {
      progress.note("body " + std::to_string(p.body) + " of " + std::to_string(p.nb_bodies) +
                    " (each outer shell is meshed on its own): " + std::to_string(p.body_vertices) +
                    " vertices");
      return true;
    }
    const std::string name = mesh3_phase_name(p.phase);
    const bool begins = p.iteration == 0 && p.energy == 0 && !p.topology_round;
    if (p.phase == Mesh3Phase::kUnconstrained || p.phase == Mesh3Phase::kConstrained) {
      if (begins) {
        progress.phase(name + " CVT", p.phase == Mesh3Phase::kUnconstrained
                                          ? args.unconstrained_iterations
                                          : args.constrained_iterations);
      } else {
        progress.iteration(p.iteration, p.energy, p.gradient_norm);
      }
    } else if (p.phase == Mesh3Phase::kTopology) {
      if (!p.topology_round) {
        // The phase's start, or an iteration of a short CVT after the rounds.
        if (begins) {
          progress.phase("topology");
        } else if (p.iteration > 0) {
          progress.iteration(p.iteration, p.energy, -1, 5);
        }
      } else if (p.iteration == 0 && p.defects == 0) {
        progress.note("the restricted Voronoi diagram has the closed-ball property");
      } else {
        progress.note("topology round " + std::to_string(p.iteration) + ": " +
                      std::to_string(p.defects) +
                      " restricted cells not yet disks meeting along single arcs, " +
                      std::to_string(p.added_sites) + " sites added");
      }
    } else if (p.phase == Mesh3Phase::kSlivers && (p.iteration > 0 || p.slivers > 0)) {
      progress.note("slivers round " + std::to_string(p.iteration) + ": " +
                    std::to_string(p.slivers) + (p.slivers == 1 ? " tet" : " tets") +
                    " below the target, smallest dihedral angle " + fixed(p.min_dihedral_deg, 2) +
                    " deg");
    } else if (p.iteration == 0) {
      progress.phase(name);
    }
    return true;
  };
  const Mesh3Result r = mesh3d(domain, o);
  if (!refused.empty()) throw Error(refused);
  progress.done();
  if (!r.shape_problem.empty() && !args.allow_shape_mismatch) {
    throw Error(
        "mesh3d: the mesh of " + domain.source() + " does not have its shape: " + r.shape_problem +
        "; no file written (" +
        (r.shape_retries > 0 && r.nb_bodies > 1
             ? "also after " + count_of(r.shape_retries, "run") + " with twice the vertices; "
         : r.shape_retries > 0 ? "also with " + std::to_string(r.nb_sites) + " sites after " +
                                     count_of(r.shape_retries, "run") + " with twice the vertices; "
                               : std::string()) +
        (r.topology_capped
             ? "the sites needed to resolve the surface near (" + brief(r.topology_capped_near[0]) +
                   ", " + brief(r.topology_capped_near[1]) + ", " +
                   brief(r.topology_capped_near[2]) + ") grew past " +
                   format_double(o.max_topology_sites) +
                   " times the vertices, a part far thinner than the spacing" +
                   (r.topology_capped_thickness > 0
                        ? " (about " + brief(r.topology_capped_thickness) +
                              " across there, where a uniform spacing needs about " +
                              about_count(r.topology_capped_vertices) + " vertices" +
                              (r.shape_retries_skipped
                                   ? ": not meshed again, " + count_of(o.max_shape_retries, "run") +
                                         " with twice the vertices would stay far short"
                                   : std::string()) +
                              ")"
                        : std::string()) +
                   ": give it a smaller edge length (--sizing), or "
             : "try more --vertices, a smaller edge length where the shape is lost "
               "(--sizing), or ") +
        "--allow-shape-mismatch to write it anyway)");
  }
  if (!r.shape_problem.empty()) {
    std::cerr << "voroclip: warning: the mesh of " << domain.source()
              << " does not have its shape: " << r.shape_problem << '\n';
  }
  if (r.nb_tets_across_regions > 0 && r.nb_interfaces_followed > 0) {
    std::cerr << "voroclip: warning: the mesh of " << domain.source() << " follows the "
              << count_of(r.nb_interfaces_followed, "interface") << " between its "
              << r.nb_input_regions << " regions, yet " << count_of(r.nb_tets_across_regions, "tet")
              << " have their centroid in an input tet of another region (a region thinner "
                 "than the edges; try more --vertices)\n";
  } else if (r.nb_tets_across_regions > 0) {
    std::cerr << "voroclip: warning: the mesh of " << domain.source()
              << " does not follow the interfaces between its " << r.nb_input_regions
              << " regions: " << count_of(r.nb_tets_across_regions, "tet")
              << " reach across one (a tet takes the region of the input tet holding its "
                 "centroid): mesh3d follows the interfaces when each region is a volume of its "
                 "own, and here "
              << r.interfaces_not_followed << "\n";
  }
  if (!r.embedded_tags_dropped.empty()) {
    // An embedded surface (a sensor's, a crack's): the mesh neither keeps its triangles nor
    // puts vertices on it.
    std::string which;
    for (const Mesh3Result::EmbeddedTag& e : r.embedded_tags_dropped) {
      which += (which.empty() ? "" : ", ") + std::to_string(e.tag) +
               (e.name.empty() ? std::string() : " \"" + e.name + "\"") + " (" +
               count_of(e.nb_triangles, "triangle") + ")";
    }
    std::cerr << "voroclip: warning: the mesh of " << domain.source()
              << " does not follow the input's embedded "
              << (r.embedded_tags_dropped.size() == 1 ? "surface of tag " : "surfaces of tags ")
              << which
              << ": tagged triangles inside the volume with the same region on both "
                 "sides (neither boundary nor an interface between regions); the mesh's tets "
                 "cross them and the output has no triangle of "
              << (r.embedded_tags_dropped.size() == 1 ? "that tag" : "those tags")
              << " (give each side a region tag of its own to have it followed as an "
                 "interface)\n";
  }
  if (r.shape_retries > 0 && out && r.shape_problem.empty() && r.nb_bodies > 1) {
    *out << "note: a mesh without the domain's shape (" << r.raised_because
         << ") was meshed again with twice the vertices (" << count_of(r.shape_retries, "run")
         << " at most), which has it; --exact-vertices fails instead\n";
  } else if (r.shape_retries > 0 && out && r.shape_problem.empty()) {
    *out << "note: " << r.requested_vertices << " vertices gave a mesh without the domain's shape ("
         << r.raised_because << "); meshed again with " << (r.requested_vertices << r.shape_retries)
         << " vertices (" << count_of(r.shape_retries, "run")
         << " with twice the vertices), which has it; --exact-vertices fails instead\n";
  }
  if (r.nb_topology_sites > 0 && out) {
    // With several bodies, the sites before the refinement (the bodies' shares, retries and
    // corners included).
    const std::uint32_t asked = r.nb_bodies > 1 ? r.nb_sites - r.nb_topology_sites
                                                : r.requested_vertices << r.shape_retries;
    // Only the topology's sites: the final count also has the lattice's deviation from the
    // count asked and the sliver phase's sites.
    *out << "note: " << count_of(r.nb_topology_sites, "site") << " added where " << asked
         << " did not resolve the surface (restricted Voronoi cells not disks, or a part in "
            "fewer than four cells); "
            "--exact-vertices fails instead\n";
  }

  TetMeshInput mesh;
  mesh.source = args.output.empty() ? std::string("mesh3d") : args.output;
  mesh.xyz = r.xyz;
  mesh.tets = r.tets;
  // Tags for boundary conditions and materials: the boundary triangles with their patch
  // tags, the tets with their region tags (every format keeps them; Gmsh also the names).
  mesh.triangles = r.boundary_triangles;
  mesh.triangle_ref = r.boundary_tags;
  // The interfaces between regions the mesh follows, after the boundary.
  mesh.triangles.insert(mesh.triangles.end(), r.interface_triangles.begin(),
                        r.interface_triangles.end());
  mesh.triangle_ref.insert(mesh.triangle_ref.end(), r.interface_tags.begin(),
                           r.interface_tags.end());
  mesh.tet_ref = r.tet_tags;
  mesh.tag_names = r.tag_names;
  // The Hausdorff distance between the output's boundary and the input's: mesh3d measured
  // it for its shape check.
  const HausdorffDistance& distance = r.distance;
  const double t_hausdorff = r.distance_seconds;

  if (!args.output.empty()) {
    progress.phase("writing " + args.output);
    if (ext == ".vtu") {
      // The tets, then the boundary and interface triangles (write_tet_mesh: cell data
      // "region", 0 on triangles, and "patch", 0 on tets), and per tet its smallest dihedral
      // angle (NaN on the triangles); the vertex kinds go with the statistics only.
      write_tet_mesh(args.output, mesh,
                     args.compress ? TetMeshFormat::kVtuCompressed : TetMeshFormat::kVtu,
                     tet_quality_fields(mesh));
    } else if (ext == ".msh") {
      write_tet_mesh(args.output, mesh,
                     args.msh_version == "2.2" ? TetMeshFormat::kGmsh22
                     : args.binary             ? TetMeshFormat::kGmsh41Binary
                                               : TetMeshFormat::kGmsh41);
    } else if (ext == ".node" || ext == ".ele") {
      write_tet_mesh(args.output, mesh, TetMeshFormat::kTetGen);
    } else {
      write_tet_mesh(args.output, mesh, TetMeshFormat::kMedit);
    }
  }

  progress.done();
  std::uint32_t counts[4] = {0, 0, 0, 0};
  for (const Mesh3VertexKind k : r.kinds) ++counts[static_cast<int>(k)];
  if (options.stats_json) {
    std::ostringstream text;
    write_quality_json(text, r.quality, &distance);
    nlohmann::json j = nlohmann::json::parse(text.str());
    j["domain"] = args.domain;
    j["sites"] = r.nb_sites;
    j["dropped_sites"] = r.nb_dropped_sites;
    j["vertex_kinds"] = {{"interior", counts[0]},
                         {"surface", counts[1]},
                         {"feature", counts[2]},
                         {"corner", counts[3]}};
    j["topology"] = {{"sites_added", r.nb_topology_sites},
                     {"rounds", r.topology_rounds},
                     {"deferred", r.nb_topology_deferred},
                     {"defects_left", r.topology_defects_left},
                     {"capped", r.topology_capped},
                     {"capped_thickness", r.topology_capped_thickness},
                     {"capped_vertices_needed", r.topology_capped_vertices}};
    j["sliver_sites"] = r.nb_sliver_sites;
    j["sliver_sites_inside"] = r.nb_sliver_sites_inside;
    j["shape_problem"] = r.shape_problem;
    j["hausdorff_to_edge_length"] = r.distance_to_edge_length;
    j["requested_vertices"] = r.requested_vertices;
    j["shape_retries"] = r.shape_retries;
    j["bodies"] = r.nb_bodies;
    j["raised_because"] = r.raised_because;
    {
      const char* names[3] = {"4", "3", "0-2"};
      nlohmann::json classes = nlohmann::json::array();
      for (int c = 0; c < 3; ++c) {
        const Mesh3Result::Q1Class& q = r.q1_by_boundary_vertices[c];
        classes.push_back({{"boundary_vertices", names[c]},
                           {"tets", q.nb_tets},
                           {"min_deg", q.min_deg},
                           {"mean_deg", q.mean_deg}});
      }
      j["q1_by_boundary_vertices"] = classes;
    }
    j["regions"] = {{"input_regions", r.nb_input_regions},
                    {"tets_across_interfaces", r.nb_tets_across_regions},
                    {"interfaces_followed", r.nb_interfaces_followed},
                    {"interface_distance_to_edge_length", r.interface_distance_to_edge_length},
                    {"interfaces_not_followed", r.interfaces_not_followed}};
    {
      nlohmann::json dropped = nlohmann::json::array();
      for (const Mesh3Result::EmbeddedTag& e : r.embedded_tags_dropped)
        dropped.push_back({{"tag", e.tag}, {"name", e.name}, {"triangles", e.nb_triangles}});
      j["embedded_tags_not_followed"] = dropped;
    }
    j["dihedral_bound"] = {{"bound_deg", r.dihedral_bound_deg},
                           {"input_sharpest_dihedral_deg", r.input_sharpest_dihedral_deg},
                           {"tets_below", r.nb_tets_below_bound}};
    {
      std::vector<std::int32_t> patches = r.boundary_tags, regions = r.tet_tags;
      std::sort(patches.begin(), patches.end());
      patches.erase(std::unique(patches.begin(), patches.end()), patches.end());
      std::sort(regions.begin(), regions.end());
      regions.erase(std::unique(regions.begin(), regions.end()), regions.end());
      j["boundary_triangles"] = r.boundary_triangles.size() / 3;
      j["interface_triangles"] = r.interface_triangles.size() / 3;
      j["patch_tags"] = patches;
      j["region_tags"] = regions;
    }
    j["lfs_cap"] = {{"factor", o.lfs_cap},
                    {"capped_volume_fraction", r.lfs_capped_fraction},
                    {"uniform_spacing", r.lfs_cap_spacing}};
    j["facet_distance"] = {{"factor", o.facet_distance},
                           {"sites", r.nb_distance_sites},
                           {"sites_added", r.nb_distance_sites_added}};
    j["feature_lines"] = r.nb_feature_lines;
    j["feature_corners"] = r.nb_feature_corners;
    j["surface"] = args.smooth_surface ? "smooth" : "flat";
    j["cvt"] = {{"unconstrained",
                 {{"iterations", r.unconstrained.iterations},
                  {"evaluations", r.unconstrained.evaluations},
                  {"energy", r.unconstrained.energy},
                  {"gradient_norm", r.unconstrained.gradient_norm}}},
                {"constrained",
                 {{"iterations", r.constrained.iterations},
                  {"evaluations", r.constrained.evaluations},
                  {"energy", r.constrained.energy},
                  {"gradient_norm", r.constrained.gradient_norm}}}};
    j["extraction"] = {{"delaunay_tets", r.extraction.nb_delaunay_tets},
                       {"inside", r.extraction.nb_inside},
                       {"on_boundary", r.extraction.nb_on_boundary},
                       {"nonmanifold_edges", r.extraction.nb_nonmanifold_edges},
                       {"nonmanifold_vertices", r.extraction.nb_nonmanifold_vertices},
                       {"added", r.extraction.nb_added},
                       {"removed", r.extraction.nb_removed}};
    j["perturbation"] = {{"rounds", r.perturbation.rounds},
                         {"moves", r.perturbation.moves},
                         {"initial_slivers", r.perturbation.initial_slivers},
                         {"final_slivers", r.perturbation.final_slivers},
                         {"initial_min_dihedral_deg", r.perturbation.initial_min_dihedral_deg},
                         {"round_undone", r.perturbation.undone},
                         {"peeled_tets", r.nb_peeled},
                         {"flips", r.nb_flips},
                         {"flip_moves", r.nb_flip_moves},
                         {"flip_sites", r.nb_flip_sites},
                         {"boundary_flips", r.nb_boundary_flips},
                         {"mean_flips", r.nb_mean_flips},
                         {"mean_moves", r.nb_mean_moves},
                         {"mean_rounds", r.mean_rounds},
                         {"mean_q1_before_deg", r.mean_q1_before_deg},
                         {"mean_q1_after_deg", r.mean_q1_after_deg},
                         {"mean_seconds", r.mean_seconds},
                         {"flips_rerun_for_shape", r.flips_rerun_for_shape}};
    nlohmann::json seconds = {{"read", t_read}};
    for (int p = 0; p < kNbMesh3Phases; ++p)
      seconds[mesh3_phase_name(static_cast<Mesh3Phase>(p))] = r.seconds[p];
    seconds["meshing"] = r.total_seconds;
    seconds["hausdorff"] = t_hausdorff;
    seconds["total"] = seconds_since(start);
    j["seconds"] = seconds;
    print_stats(j, options);
  }
  if (out) {
    *out << "Mesh: " << r.nb_vertices() << " vertices (" << counts[0] << " interior, " << counts[1]
         << " surface, " << counts[2] << " feature, " << counts[3] << " corner), " << r.nb_tets()
         << " tets in " << fixed(r.total_seconds, 2) << " s\n";
    if (r.lfs_capped_fraction > 0) {
      *out << "Sizing: the spacing is capped at " << format_double(o.lfs_cap)
           << " x the local feature size in " << fixed(100 * r.lfs_capped_fraction, 1)
           << " % of the volume"
           << (r.lfs_cap_spacing > 0
                   ? ", uniform elsewhere"
                   : " (the cap alone needs more than the vertices asked: its shape, scaled)")
           << "; --lfs-cap 0 for a uniform size\n";
    }
    {
      std::vector<std::int32_t> patches = r.boundary_tags, regions = r.tet_tags;
      std::sort(patches.begin(), patches.end());
      patches.erase(std::unique(patches.begin(), patches.end()), patches.end());
      std::sort(regions.begin(), regions.end());
      regions.erase(std::unique(regions.begin(), regions.end()), regions.end());
      const auto list = [](const std::vector<std::int32_t>& v) {
        std::string text;
        for (std::size_t i = 0; i < v.size() && i < 12; ++i) {
          text += (i == 0 ? "" : " ") + std::to_string(v[i]);
        }
        return v.size() > 12 ? text + " ..." : text;
      };
      *out << "Boundary: " << r.boundary_triangles.size() / 3 << " triangles in " << patches.size()
           << " patch tag(s) [" << list(patches) << "]; " << regions.size() << " region tag(s) ["
           << list(regions) << "]\n";
      if (r.nb_interfaces_followed > 0) {
        std::vector<std::int32_t> tags = r.interface_tags;
        std::sort(tags.begin(), tags.end());
        tags.erase(std::unique(tags.begin(), tags.end()), tags.end());
        *out << "Regions: the mesh follows the " << count_of(r.nb_interfaces_followed, "interface")
             << " between the input's " << r.nb_input_regions
             << " regions (vertices on them, each tet on one side): "
             << r.interface_triangles.size() / 3 << " interface triangles, tag(s) [" << list(tags)
             << "]\n";
      }
    }
    write_quality_text(*out, r.quality, args.output.empty() ? std::string("mesh3d") : args.output,
                       &distance, domain.source());
    // The distance against the local target edge length (mesh3d's shape check).
    *out << "Distance: the boundary is at most " << fixed(r.distance_to_edge_length, 2)
         << " local edge lengths from the input's surface either way";
    if (args.max_boundary_distance > 0) {
      *out << " (bound " << format_double(args.max_boundary_distance)
           << ", --max-boundary-distance)";
    } else {
      *out << " (not checked: --max-boundary-distance 0)";
    }
    *out << '\n';
    *out << "Smallest dihedral angle (Q1) by boundary vertices per tet:";
    const char* names[3] = {"4", "3", "0-2"};
    for (int c = 0; c < 3; ++c) {
      const Mesh3Result::Q1Class& q = r.q1_by_boundary_vertices[c];
      *out << (c == 0 ? " " : "; ") << names[c] << ": ";
      if (q.nb_tets == 0) {
        *out << "no tets";
      } else {
        *out << "min " << fixed(q.min_deg, 2) << ", mean " << fixed(q.mean_deg, 2) << " degrees ("
             << count_of(q.nb_tets, "tet") << ")";
      }
    }
    *out << '\n';
    // The verdict on the dihedral angles, against min(20, alpha / 2).
    *out << "Dihedral angles: "
         << (r.nb_tets_below_bound == 0 ? "every tet's smallest is at least "
                                        : count_of(r.nb_tets_below_bound, "tet") + " below ")
         << "the bound " << fixed(r.dihedral_bound_deg, 2) << " degrees (min(20, alpha / 2), "
         << "alpha = " << fixed(r.input_sharpest_dihedral_deg, 2)
         << " degrees the input's sharpest dihedral angle)";
    if (r.nb_tets_below_bound > 0) {
      // Where the worst tet is and what may lift it: a tet whose four vertices lie on the
      // boundary sits in a thin part or at a sharp edge of the solid, which only a smaller
      // spacing there gives interior vertices.
      const std::uint32_t t = r.quality.q1_deg.argmin;
      double c[3] = {0, 0, 0};
      int on_boundary = 0;
      for (int k = 0; k < 4; ++k) {
        const std::uint32_t v = r.tets[4 * std::size_t{t} + k];
        for (int d = 0; d < 3; ++d) c[d] += r.xyz[3 * std::size_t{v} + d] / 4;
        on_boundary += r.kinds[v] != Mesh3VertexKind::kInterior ? 1 : 0;
      }
      *out << "; the smallest is " << fixed(r.quality.q1_deg.min, 2) << " degrees, at tet " << t
           << " (centroid " << c[0] << ' ' << c[1] << ' ' << c[2] << ", " << on_boundary
           << " of its vertices on the boundary"
           << (on_boundary == 4 ? ": a thin part or a sharp edge of the solid" : "")
           << "). Another --seed, or a smaller edge length there (--sizing), can lift it"
           << (args.no_perturb        ? "; so can the sliver perturbation (off: --no-perturb)"
               : args.flip_angle == 0 ? "; so can the flips against slivers (off: --flip-angle 0)"
                                      : "");
    }
    *out << '\n';
    if (!args.output.empty()) *out << "Written to " << args.output << '\n';
  }
}

}  // namespace voroclip::cli
