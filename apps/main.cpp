// voroclip: the command-line tool. Parses the command line (CLI11), runs one subcommand and
// turns every failure into exactly one line "voroclip: error: ..." on stderr, with exit
// status 2 for a usage error and 1 for anything that went wrong at run time.
#include <CLI/CLI.hpp>
#include <charconv>
#include <cstddef>
#include <exception>
#include <iostream>
#include <memory>
#include <string>
#include <system_error>
#include <tbb/global_control.h>

#include "cli.h"
#include "cvt3d_cmd.h"
#include "voroclip/core.h"

namespace {

// The columns of the cell tables (core.h, "Tables of the cells"), for the help.
constexpr const char* kCells2Columns =
    "site,x,y,area,centroid_x,centroid_y,energy,boundary,neighbors; site is the 0-based input "
    "index, boundary 1 when the cell meets the domain's boundary, neighbors the number of "
    "cells sharing an edge";
constexpr const char* kCells3Columns =
    "site,x,y,z,volume,centroid_x,centroid_y,centroid_z,energy,boundary,neighbors,"
    "surface_area; site is the 0-based input index, boundary 1 when the cell meets the "
    "surface, neighbors the number of cells sharing a face, surface_area its area on the "
    "surface";

constexpr int kRuntimeError = 1;
constexpr int kUsageError = 2;

// --stats json as the command line asks it, and the command it names: known before the parse,
// so that a failed parse also answers with the JSON object.
struct FailureStats {
  bool json = false;
  std::string command;  // "" when no command was recognised
};
FailureStats g_failure_stats;

int report_error(const std::string& what, int status) {
  if (g_failure_stats.json && !voroclip::cli::stats_printed()) {
    voroclip::cli::print_failure_stats(g_failure_stats.command, what);
  }
  std::cout.flush();
  std::cerr << "voroclip: error: " << voroclip::cli::error_line(what) << std::endl;
  return status;
}

// The message for a command line without a valid command: the word taken for one (the first
// argument that is neither a global option nor its value) and the list of commands; "" when
// that word is a command (the parse failed for another reason).
std::string no_command(const CLI::App& app, const std::string& word) {
  std::string commands;
  bool word_is_command = false;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    commands += (commands.empty() ? "" : ", ") + sub->get_name();
    if (sub->get_name() == word) word_is_command = true;
  }
  if (word_is_command) return "";  // the parse failed for another reason
  return (word.empty() ? std::string("no command given") : "unknown command '" + word + "'") +
         "; the commands are: " + commands + " (voroclip --help describes them)";
}

// The first argument that is neither a global option nor its value: the command.
std::string command_word(int argc, char** argv) {
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    if (a == "--threads" || a == "--stats" || a == "--progress") {
      ++k;  // its value
    } else if (a.empty() || a[0] != '-') {
      return a;
    }
  }
  return "";
}

// Whether the command line asks for --stats json (CLI11 takes "--stats json" and
// "--stats=json"; after "--" every argument is positional).
bool stats_json_asked(int argc, char** argv) {
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    if (a == "--") return false;
    if (a == "--stats=json" ||
        (a == "--stats" && k + 1 < argc && std::string(argv[k + 1]) == "json")) {
      return true;
    }
  }
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  using voroclip::cli::GlobalOptions;
  CLI::App app{
      "voroclip: exact clipped Voronoi diagrams, centroidal Voronoi tessellations and "
      "meshing in 2D and 3D.",
      "voroclip"};
  app.set_version_flag("--version", std::string("voroclip ") + voroclip::version(),
                       "Print the version and exit");
  // Positionals are named once ("DOMAIN (required)", not CLI11's "DOMAIN DOMAIN REQUIRED").
  app.get_formatter()->label("REQUIRED", "(required)");
  app.require_subcommand(1);
  app.fallthrough();  // global options may also follow the subcommand

  GlobalOptions global;
  std::string stats_format;
  app.add_option("--threads", global.threads,
                 "Number of threads (default: all cores); results do not depend on it")
      ->type_name("N")
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            int n = 0;
            const char* last = text.data() + text.size();
            const std::from_chars_result r = std::from_chars(text.data(), last, n);
            if (text.empty() || r.ec != std::errc() || r.ptr != last || n < 1) {
              return "expected a whole number of threads >= 1, got '" + text + "'";
            }
            return "";
          },
          ""));
  app.add_option("--stats", stats_format,
                 "Print machine-readable statistics on stdout as one JSON object (json is the "
                 "only format; the human report then goes to stderr)")
      ->type_name("json")
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            return text == "json" ? "" : "expected 'json', got '" + text + "'";
          },
          ""));
  app.add_flag("-q,--quiet", global.quiet, "Print no human-readable text (no progress either)");
  app.add_option("--progress", global.progress,
                 "Progress on stderr: auto (default: a live bar per phase on a terminal, plain "
                 "lines otherwise), bar, lines or none")
      ->type_name("MODE")
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            return text == "auto" || text == "bar" || text == "lines" || text == "none"
                       ? ""
                       : "expected auto, bar, lines or none, got '" + text + "'";
          },
          ""));

  voroclip::cli::DemoArgs demo_args;
  CLI::App* demo = app.add_subcommand(
      "demo",
      "CVT meshing and a clipped Voronoi diagram of a domain with holes; exact versus naive "
      "predicates on the classroom example of Kettner et al. (CGTA 2008); symbolic "
      "perturbation on the cube's corners");
  CLI::Option* output =
      demo->add_option("-o,--output", demo_args.svg_path,
                       "Write an SVG picture (the clipped diagram, the mesh, the naive and exact "
                       "signs) to FILE");
  output->type_name("FILE.svg");

  voroclip::cli::PredicateArgs predicate_args;
  CLI::App* predicate = app.add_subcommand(
      "predicate",
      "Evaluate one exact predicate and print positive, negative or zero. Sign conventions "
      "are Shewchuk's: orient2d > 0 for counter-clockwise points, incircle/insphere > 0 when "
      "the last point is inside the circle/sphere of the others (positively oriented)");
  predicate->add_option("NAME", predicate_args.name, "orient2d, incircle, orient3d or insphere")
      ->required()
      ->type_name("");
  predicate
      ->add_option("COORDS", predicate_args.coordinates,
                   "Coordinates of the points in order: 6, 8, 12 or 15 numbers, decimal or "
                   "C99 hexadecimal (0x1.8p-3); write -- before them if one is like -.5 or "
                   "-inf")
      ->type_name("X");
  CLI::Option* sos = predicate->add_option(
      "--sos", predicate_args.sos_indices,
      "Use the symbolically perturbed predicate (never zero) with these distinct point "
      "indices, one per point");
  sos->type_name("I");

  // delaunay2d / delaunay3d share their options.
  voroclip::cli::DelaunayArgs delaunay_args[2];
  CLI::App* delaunay_cmd[2] = {nullptr, nullptr};
  for (int d = 0; d < 2; ++d) {
    voroclip::cli::DelaunayArgs& a = delaunay_args[d];
    a.dimension = d + 2;
    const std::string dim = std::to_string(a.dimension);
    CLI::App* cmd = app.add_subcommand(
        "delaunay" + dim + "d",
        "Delaunay triangulation of " + dim +
            "D points (exact predicates, symbolic perturbation; duplicates are reported)");
    cmd->add_option("INPUT", a.input,
                    "Point file: a JSON array of points ([[x,y" + std::string(d ? ",z" : "") +
                        "],...]) or text with one point per line ('#' comments)")
        ->type_name("FILE");
    cmd->add_option("--random", a.random,
                    "Use N uniform random points in the unit " +
                        std::string(d ? "cube" : "square") + " instead")
        ->type_name("N");
    cmd->add_option("--seed", a.seed, "Seed of --random (default 1)")->type_name("S");
    cmd->add_flag("--check", a.check,
                  "Verify the result exactly (adjacency, orientation, local Delaunay)");
    cmd->add_option("-o,--output", a.output, "Write the triangulation as legacy VTK")
        ->type_name("FILE.vtk");
    delaunay_cmd[d] = cmd;
  }

  // clip2d / cvt2d share their options.
  voroclip::cli::ClipArgs clip_args[2];
  CLI::App* clip_cmd[2] = {nullptr, nullptr};
  for (int c = 0; c < 2; ++c) {
    voroclip::cli::ClipArgs& a = clip_args[c];
    CLI::App* cmd = app.add_subcommand(
        c == 0 ? "clip2d" : "cvt2d",
        c == 0 ? "Voronoi diagram of sites clipped to a polygonal domain with holes (exact)"
               : "Centroidal Voronoi tessellation of a polygonal domain (L-BFGS or Lloyd), "
                 "from given or random sites");
    cmd->add_option("DOMAIN", a.domain,
                    "Polygon file (.json rings as in shared/data/polygons, or Triangle .poly), "
                    "or a generator: annulus:R_IN,R_OUT,SEGMENTS or square-holes:K,FRACTION")
        ->required()
        ->type_name("");
    cmd->add_option("--sites", a.sites,
                    "Site file: one 'x y' per line ('#' comments) or a JSON array [[x,y],...]")
        ->type_name("FILE");
    cmd->add_option("--random", a.random,
                    c == 0 ? "Use N uniform random sites inside the domain"
                           : "Use N random sites inside the domain (uniform; with a --density "
                             "or --density-file, drawn with density rho^(1/2), the CVT's)")
        ->type_name("N");
    cmd->add_option("--seed", a.seed, "Seed of --random (default 1)")->type_name("S");
    cmd->add_option("-o,--output", a.output,
                    std::string("Write the cells: .svg picture, .vtu polygons with site_id, "
                                ".csv one row per cell (") +
                        kCells2Columns + "), .json the same per cell with mass and polygons" +
                        (c == 1 ? ", or .txt the final sites" : ""))
        ->type_name("FILE");
    cmd->add_flag("--binary", a.binary, "Write a .vtu output's data in binary (base64, appended)");
    cmd->add_flag("--compress", a.compress,
                  "Compress a .vtu output's data with zlib (vtkZLibDataCompressor, as meshio "
                  "and ParaView write it)");
    cmd->add_flag("--strict", a.strict,
                  "Given sites outside the domain or repeating an earlier site are an error "
                  "(default: a warning naming them)");
    cmd->add_option("--neighbors", a.neighbors,
                    "Write the pairs of neighbouring cells, .csv (site_a,site_b,length: the "
                    "length of their common edge; site_a < site_b) or .json")
        ->type_name("FILE");
    if (c == 1) {
      cmd->add_option("--method", a.method, "lbfgs (default) or lloyd")->type_name("NAME");
      cmd->add_option("--iterations", a.iterations,
                      "Iteration budget (default 1000: enough for L-BFGS to reach the default "
                      "tolerance on the shared polygons from random sites)")
          ->type_name("N");
      cmd->add_option("--tolerance", a.tolerance,
                      "Stop when |gradient| <= tolerance * initial |gradient| (default 1e-4)")
          ->type_name("T");
      voroclip::cli::add_density_options(cmd, a.density, 2, false);
    }
    clip_cmd[c] = cmd;
  }

  voroclip::cli::Mesh2dArgs mesh_args;
  CLI::App* mesh2d = app.add_subcommand(
      "mesh2d",
      "CVT triangle mesh of a polygonal domain (Yan et al. 2011, sec. 5.1) with its quality "
      "report");
  mesh2d
      ->add_option("DOMAIN", mesh_args.domain,
                   "Polygon file (.json rings, Triangle .poly) or a generator: "
                   "annulus:R_IN,R_OUT,SEGMENTS or square-holes:K,FRACTION")
      ->required()
      ->type_name("");
  mesh2d->add_option("--vertices", mesh_args.vertices, "Target number of mesh vertices")
      ->type_name("N");
  mesh2d->add_flag("--exact-vertices", mesh_args.exact_vertices,
                   "With --vertices: keep the count even when the mean smallest angle stays "
                   "below 53 degrees (by default the domain is meshed again with more vertices, "
                   "at most 3 times, and the note says by how much; the small features may "
                   "still force more)");
  mesh2d
      ->add_option("--edge-length", mesh_args.edge_length,
                   "Target edge length away from small features (instead of --vertices)")
      ->type_name("H");
  mesh2d->add_flag("--fix-input-vertices", mesh_args.fix_input_vertices,
                   "Make every vertex of the domain a mesh vertex (sharp corners are still cut)");
  mesh2d
      ->add_option("--msh-version", mesh_args.msh_version,
                   "Gmsh format of a .msh output: 4.1 (default) or 2.2")
      ->type_name("V");
  mesh2d->add_flag("--circumcenter-rule", mesh_args.circumcenter_rule,
                   "The paper's extraction instead of the conforming one: keep the Delaunay "
                   "triangles whose circumcenter is inside (leaves notches at the boundary)");
  mesh2d->add_flag("--keep-gaps", mesh_args.keep_gaps,
                   "With --circumcenter-rule: also keep the triangles inside the domain whose "
                   "circumcenter is outside");
  mesh2d
      ->add_option("--repair-rounds", mesh_args.repair_rounds,
                   "Rounds removing the vertex at the largest angle of triangles with an angle "
                   "below 30 degrees, each followed by a short CVT (default 4; 0: none)")
      ->type_name("N");
  mesh2d->add_option("--seed", mesh_args.seed, "Seed of the initial sampling (default 1)")
      ->type_name("S");
  mesh2d
      ->add_option("--gradation", mesh_args.gradation,
                   "Growth of the edge length away from small features, per unit length "
                   "(default 0.3)")
      ->type_name("G");
  mesh2d
      ->add_option("--corner-angle", mesh_args.corner_angle,
                   "Convex vertices turning by at least this many degrees are fixed corners "
                   "(default 0: every corner; above 0 the mesh may cut the smaller bends, "
                   "coarsening curved-looking input); reflex vertices are always fixed")
      ->type_name("DEG");
  mesh2d
      ->add_option("--sharp-angle", mesh_args.sharp_angle,
                   "Corners with an interior angle below this are cut where the domain is as "
                   "wide as the edge length (default 30)")
      ->type_name("DEG");
  mesh2d->add_option("--method", mesh_args.method, "lbfgs (default) or lloyd")->type_name("NAME");
  mesh2d
      ->add_option("--iterations", mesh_args.iterations,
                   "Iteration budget of the constrained CVT (default 200)")
      ->type_name("N");
  mesh2d
      ->add_option("-o,--output", mesh_args.output,
                   "Write the mesh: .svg picture (triangles coloured by their smallest angle), "
                   ".vtu, .mesh (Medit) or .msh (Gmsh 4.1 or 2.2); boundary edges carry their "
                   "tags (.poly segment markers, else 1 outer, 2, 3, ... holes), triangles "
                   "their region (.poly regional attributes, else 1)")
      ->type_name("FILE");
  mesh2d
      ->add_option("--histogram", mesh_args.histogram,
                   "Write the angle histograms as an SVG bar chart")
      ->type_name("FILE.svg");
  mesh2d->add_flag("--binary", mesh_args.binary,
                   "Write a .vtu output's data in binary (base64, appended)");
  mesh2d->add_flag("--compress", mesh_args.compress,
                   "Compress a .vtu output's data with zlib (vtkZLibDataCompressor, as meshio "
                   "and ParaView write it)");
  voroclip::cli::add_density_options(mesh2d, mesh_args.density, 2, true);

  const std::string domain3_help =
      "The volume: a closed surface (.obj, .off, .stl, .ply; validated exactly: closed, "
      "manifold, oriented outward, no self-intersection; several shells and cavities allowed) "
      "or a tet mesh (Medit .mesh, TetGen .node/.ele, Gmsh .msh 2.2 or 4.1 ASCII or binary, legacy "
      "VTK "
      ".vtk or VTK XML .vtu)";
  const std::string reorient_help =
      "Reverse the shells of a surface that face the wrong way (inside out) instead of "
      "rejecting it; a note names each one";

  voroclip::cli::ClipArgs clip3d_args;
  CLI::App* clip3d = app.add_subcommand(
      "clip3d",
      "Voronoi diagram of sites clipped to a volume given by its surface or a tet mesh (exact)");
  clip3d->add_option("DOMAIN", clip3d_args.domain, domain3_help)->required()->type_name("");
  clip3d->add_flag("--reorient", clip3d_args.reorient, reorient_help);
  clip3d
      ->add_option("--sites", clip3d_args.sites,
                   "Site file: one 'x y z' per line ('#' comments) or a JSON array")
      ->type_name("FILE");
  clip3d->add_option("--random", clip3d_args.random, "Use N uniform random sites in the volume")
      ->type_name("N");
  clip3d->add_option("--seed", clip3d_args.seed, "Seed of --random (default 1)")->type_name("S");
  clip3d
      ->add_option("-o,--output", clip3d_args.output,
                   std::string("Write .vtu (every cell's faces, shrunk towards its centroid, "
                               "with site_id and across: the neighbouring site, -1 on the "
                               "surface), .obj (the restricted surface coloured by cell), .csv "
                               "one row per cell (") +
                       kCells3Columns + ") or .json (the same per cell)")
      ->type_name("FILE");
  clip3d->add_flag("--binary", clip3d_args.binary,
                   "Write a .vtu output's data in binary (base64, appended)");
  clip3d->add_flag("--compress", clip3d_args.compress,
                   "Compress a .vtu output's data with zlib (vtkZLibDataCompressor, as meshio "
                   "and ParaView write it)");
  clip3d->add_flag("--strict", clip3d_args.strict,
                   "Given sites outside the volume or repeating an earlier site are an error "
                   "(default: a warning naming them)");
  clip3d
      ->add_option("--neighbors", clip3d_args.neighbors,
                   "Write the pairs of neighbouring cells, .csv (site_a,site_b,area: the area "
                   "of their common face; site_a < site_b) or .json")
      ->type_name("FILE");

  voroclip::cli::Cvt3dArgs cvt3d_args;
  CLI::App* cvt3d = voroclip::cli::add_cvt3d_command(app, cvt3d_args, domain3_help, reorient_help);

  voroclip::cli::QualityArgs quality_args;
  CLI::App* quality = app.add_subcommand(
      "quality",
      "Quality of a tet mesh: Q1 = min and Q2 = max dihedral angle, Q3 = 3 r_in / r_circ, Q4 = "
      "12 (9V^2)^(1/3) / sum l^2 per tet (min / mean / max, histograms), inverted and "
      "degenerate tets; with --surface the Hausdorff distance of its boundary to a reference");
  quality
      ->add_option("MESH", quality_args.mesh,
                   "Tet mesh: Medit .mesh, TetGen .node/.ele, Gmsh .msh, legacy .vtk or .vtu; "
                   "inverted and zero-volume tets are reported, not rejected")
      ->required()
      ->type_name("");
  quality
      ->add_option("--surface", quality_args.surface,
                   "Reference surface (.obj, .off, .stl, .ply), or a tet mesh whose boundary "
                   "is used: adds the two-sided Hausdorff distance (Metro-style sampling), "
                   "relative to the reference's bounding-box diagonal")
      ->type_name("REF");
  quality->add_option("--histogram", quality_args.histogram, "Write the histograms as SVG")
      ->type_name("FILE.svg");
  quality
      ->add_option("-o,--output", quality_args.output,
                   "Write the mesh as .vtu with Q1..Q4 per tet as cell data")
      ->type_name("FILE.vtu");
  quality->add_flag("--compress", quality_args.compress,
                    "Compress the .vtu output's data with zlib (vtkZLibDataCompressor, as meshio "
                    "and ParaView write it)");
  quality
      ->add_option("--samples", quality_args.samples,
                   "Minimum number of samples on each surface for the distance (default "
                   "100000; 10 per triangle when more)")
      ->type_name("N");

  voroclip::cli::Mesh3dArgs mesh3d_args;
  CLI::App* mesh3d = app.add_subcommand(
      "mesh3d",
      "Tetrahedral mesh of a volume (a closed surface or a tet mesh) by centroidal Voronoi "
      "tessellation (Yan et "
      "al. 2011, sec. 5.2): CVT, boundary and feature sites constrained, exact extraction, "
      "sliver perturbation; a tet mesh's regions keep their tags and the interfaces between "
      "them are followed (when each region is a volume of its own); progress per "
      "phase and the quality report");
  mesh3d->add_option("DOMAIN", mesh3d_args.domain, domain3_help)->required()->type_name("");
  mesh3d->add_flag("--reorient", mesh3d_args.reorient, reorient_help);
  mesh3d->add_flag(
      "--exact-vertices", mesh3d_args.exact_vertices,
      "Fail, naming where and how many vertices would do, when --vertices cannot "
      "resolve the surface's shape (default: add the sites needed and, when the mesh still "
      "lacks the shape, mesh again with twice the vertices, up to 3 times, with a "
      "note)");
  mesh3d->add_flag(
      "--allow-shape-mismatch", mesh3d_args.allow_shape_mismatch,
      "Write the mesh even when its boundary does not have the domain's shape "
      "(another number of shells or genus, or farther than --max-boundary-distance), with "
      "a warning; by default that is an "
      "error and no file is written");
  mesh3d
      ->add_option("--vertices", mesh3d_args.vertices,
                   "Number of vertices (sites) wanted; required except with --sizing or "
                   "--sizing-file alone, whose h is then the edge length in model units (with "
                   "--vertices, h gives only the shape and N the count)")
      ->type_name("N");
  mesh3d
      ->add_option("--lfs-cap", mesh3d_args.lfs_cap,
                   "Without --adaptive or a size: cap the uniform spacing at K times the local "
                   "feature size (off the sharp edges), so that thin parts and close sheets get "
                   "vertices; the spacing elsewhere grows to keep --vertices; 0 (default): no "
                   "cap")
      ->type_name("K")
      ->default_str("0");
  mesh3d
      ->add_option("--max-boundary-distance", mesh3d_args.max_boundary_distance,
                   "The mesh's boundary may be at most K local edge lengths from the input's "
                   "surface (either way); farther, a part thinner than the edges is cut off or a "
                   "gap bridged, and the shape is wrong (default 1; 0: not checked)")
      ->type_name("K")
      ->default_str(voroclip::cli::format_double(voroclip::Mesh3Options{}.max_boundary_distance));
  mesh3d
      ->add_option("--facet-distance", mesh3d_args.facet_distance,
                   "Fix a vertex at each input vertex farther than F times the local spacing "
                   "from the mesh's boundary (tips, ridges, thin parts; farthest first, at most "
                   "3 % of --vertices); 0: none")
      ->type_name("F")
      ->default_str(voroclip::cli::format_double(voroclip::Mesh3Options{}.facet_distance));
  mesh3d->add_flag("--adaptive", mesh3d_args.adaptive,
                   "Size the elements by the local feature size of the boundary (density "
                   "h^-5) instead of uniformly");
  mesh3d
      ->add_option("--feature-angle", mesh3d_args.feature_angle,
                   "Boundary edges whose triangles' normals differ by more than DEG degrees are "
                   "sharp features (default 40)")
      ->type_name("DEG");
  mesh3d->add_flag("--no-features", mesh3d_args.no_features, "Do not keep sharp features");
  mesh3d->add_option("--seed", mesh3d_args.seed, "Seed of the initial sampling (default 1)")
      ->type_name("S");
  mesh3d
      ->add_option("--unconstrained-iterations", mesh3d_args.unconstrained_iterations,
                   "L-BFGS iterations of the unconstrained CVT (default 16)")
      ->type_name("N");
  mesh3d
      ->add_option("--constrained-iterations", mesh3d_args.constrained_iterations,
                   "L-BFGS iterations of the constrained CVT (default 30)")
      ->type_name("N");
  mesh3d
      ->add_option("--sliver-angle", mesh3d_args.sliver_angle,
                   "Perturb the vertices of tets whose smallest dihedral angle is below DEG "
                   "degrees (default 30)")
      ->type_name("DEG");
  mesh3d->add_flag("--no-perturb", mesh3d_args.no_perturb, "No sliver perturbation");
  mesh3d
      ->add_option("--flip-angle", mesh3d_args.flip_angle,
                   "Last, flips, vertex moves and insertions against the tets whose smallest "
                   "dihedral angle is below DEG degrees (the mesh then need not be Delaunay; "
                   "default 30, 0: none)")
      ->type_name("DEG");
  mesh3d
      ->add_option("--mean-rounds", mesh3d_args.mean_rounds,
                   "Then N rounds of flips and vertex moves that raise the mean smallest "
                   "dihedral angle of all the tets (default 3, 0: none)")
      ->type_name("N");
  mesh3d->add_flag("--smooth-surface", mesh3d_args.smooth_surface,
                   "Surface vertices on the smooth (Phong) interpolant of the input's boundary "
                   "triangles, not on the triangles themselves");
  mesh3d
      ->add_option("--smooth-shape", mesh3d_args.smooth_shape,
                   "Shape factor of the Phong interpolant (--smooth-surface), in [0, 1] "
                   "(default 0.75; 0: the triangles)")
      ->type_name("F");
  mesh3d
      ->add_option("-o,--output", mesh3d_args.output,
                   "Write the mesh with its boundary triangles and tags: .mesh (Medit), .msh "
                   "(Gmsh), .vtu (VTK XML, with the smallest dihedral angle per tet) or .node / "
                   ".ele (TetGen: .node, .ele and .face written together)")
      ->type_name("FILE");
  mesh3d
      ->add_option("--msh-version", mesh3d_args.msh_version,
                   "Gmsh format of a .msh output: 4.1 (default) or 2.2")
      ->type_name("V");
  mesh3d->add_flag("--binary", mesh3d_args.binary,
                   "Write a .msh output as Gmsh 4.1 binary (little endian)");
  mesh3d->add_flag("--compress", mesh3d_args.compress,
                   "Compress a .vtu output's data with zlib (vtkZLibDataCompressor, as meshio "
                   "and ParaView write it)");
  voroclip::cli::add_density_options(mesh3d, mesh3d_args.density, 3, true);

  voroclip::cli::CheckSurfaceArgs check_args;
  CLI::App* check_surface = app.add_subcommand(
      "check-surface",
      "Validate a closed surface as the boundary of a volume, exactly (closed, 2-manifold, "
      "consistently oriented, no self-intersection, shells nested and facing the right way) "
      "and report its shells (genus, role), area and volume; exit status 1 with the defect "
      "otherwise");
  check_surface
      ->add_option("FILE", check_args.path,
                   "A surface (.obj, .off, .stl, .ply), or a tet mesh (its boundary is checked)")
      ->required()
      ->type_name("");
  check_surface->add_flag("--reorient", check_args.reorient, reorient_help);

  std::string help_topic;
  CLI::App* help = app.add_subcommand(
      "help", "Print the help of a command (voroclip help clip3d), or of the tool without one");
  help->add_option("COMMAND", help_topic, "The command")->type_name("");

  g_failure_stats.json = stats_json_asked(argc, argv);
  {
    const std::string word = command_word(argc, argv);
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
      if (sub->get_name() == word) g_failure_stats.command = word;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    std::string what = e.what();
    if (app.get_subcommands().empty()) {
      const std::string message = no_command(app, command_word(argc, argv));
      if (!message.empty()) return report_error(message, kUsageError);
    }
    if (dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr && predicate->parsed()) {
      what += " (write -- before the coordinates to pass one like -.5 or -inf)";
    }
    return report_error(what, kUsageError);
  }
  if (output->count() > 0 && demo_args.svg_path.empty()) {
    return report_error("-o,--output: the file name is empty", kUsageError);
  }
  global.stats_json = stats_format == "json";
  for (const CLI::App* sub : app.get_subcommands()) global.command = sub->get_name();
  g_failure_stats = {global.stats_json, global.command};
  predicate_args.sos = sos->count() > 0;

  if (*help) {
    if (help_topic.empty() || help_topic == "help") {
      // (app.help() would show the selected subcommand's, help's own.)
      std::cout << app.get_formatter()->make_help(&app, "voroclip", CLI::AppFormatMode::Normal);
      return 0;
    }
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
      if (sub->get_name() == help_topic) {
        std::cout << sub->help("voroclip");
        return 0;
      }
    }
    return report_error(no_command(app, help_topic), kUsageError);
  }

  try {
    std::unique_ptr<tbb::global_control> parallelism;
    if (global.threads > 0) {
      parallelism = std::make_unique<tbb::global_control>(
          tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(global.threads));
    }
    // --seed seeds --random's points: with given points it would mean nothing.
    for (CLI::App* cmd :
         {clip_cmd[0], clip_cmd[1], clip3d, cvt3d, delaunay_cmd[0], delaunay_cmd[1]}) {
      if (*cmd && cmd->get_option("--seed")->count() > 0 &&
          cmd->get_option("--random")->count() == 0) {
        throw voroclip::cli::UsageError(
            "--seed: only with --random N, whose points it seeds (the points of a file are "
            "used as they are)");
      }
    }
    if (*demo) {
      voroclip::cli::run_demo(demo_args, global);
    } else if (*predicate) {
      voroclip::cli::run_predicate(predicate_args, global);
    }
    if (*mesh3d) {
      mesh3d_args.vertices_set = mesh3d->get_option("--vertices")->count() > 0;
      mesh3d_args.msh_version_set = mesh3d->get_option("--msh-version")->count() > 0;
      voroclip::cli::run_mesh3d(mesh3d_args, global);
    }
    if (*check_surface) voroclip::cli::run_check_surface(check_args, global);
    if (*quality) {
      quality_args.samples_set = quality->get_option("--samples")->count() > 0;
      voroclip::cli::run_quality(quality_args, global);
    } else if (*mesh2d) {
      mesh_args.vertices_set = mesh2d->get_option("--vertices")->count() > 0;
      mesh_args.edge_length_set = mesh2d->get_option("--edge-length")->count() > 0;
      mesh_args.msh_version_set = mesh2d->get_option("--msh-version")->count() > 0;
      voroclip::cli::run_mesh2d(mesh_args, global);
    }
    if (*clip3d) {
      clip3d_args.random_set = clip3d->get_option("--random")->count() > 0;
      voroclip::cli::run_clip3d(clip3d_args, global);
    }
    if (*cvt3d) {
      cvt3d_args.random_set = cvt3d->get_option("--random")->count() > 0;
      voroclip::cli::run_cvt3d(cvt3d_args, global);
    }
    for (int c = 0; c < 2; ++c) {
      if (*clip_cmd[c]) {
        clip_args[c].random_set = clip_cmd[c]->get_option("--random")->count() > 0;
        if (c == 0) {
          voroclip::cli::run_clip2d(clip_args[c], global);
        } else {
          voroclip::cli::run_cvt2d(clip_args[c], global);
        }
      }
    }
    for (int d = 0; d < 2; ++d) {
      if (*delaunay_cmd[d]) {
        delaunay_args[d].random_set = delaunay_cmd[d]->get_option("--random")->count() > 0;
        voroclip::cli::run_delaunay(delaunay_args[d], global);
      }
    }
    std::cout.flush();
    if (!std::cout) return report_error("cannot write to standard output", kRuntimeError);
    return 0;
  } catch (const voroclip::cli::UsageError& e) {
    return report_error(e.what(), kUsageError);
  } catch (const voroclip::Error& e) {
    return report_error(e.what(), kRuntimeError);
  } catch (const std::exception& e) {
    return report_error(e.what(), kRuntimeError);
  } catch (...) {
    return report_error("unknown internal error", kRuntimeError);
  }
}
