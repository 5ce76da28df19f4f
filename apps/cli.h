// What the subcommands of the voroclip tool share: global options, where human-readable
// text goes, the usage-error type, and strict parsing of numbers given on the command line.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "density_options.h"
#include "voroclip/clip.h"
#include "voroclip/mesh.h"
#include "voroclip/predicates.h"

namespace voroclip::cli {

/// A mistake in the command line (bad value, wrong count...). main() reports it like a
/// CLI11 parse error: one line on stderr and exit status 2. Runtime failures use
/// voroclip::Error and exit status 1.
class UsageError : public std::runtime_error {
 public:
  explicit UsageError(const std::string& what) : std::runtime_error(what) {}
};

struct GlobalOptions {
  int threads = 0;  // 0: TBB's default, all cores
  bool stats_json = false;
  bool quiet = false;
  std::string progress = "auto";  // --progress: auto, bar, lines or none (progress.h)
  std::string command;            // the command run ("mesh2d"), named by the JSON statistics
};

/// Human-readable text goes to stdout, or to stderr when stdout carries the JSON statistics
/// (--stats json); with --quiet it is dropped (nullptr).
std::ostream* human_stream(const GlobalOptions& options);

/// A library message as the command line says it: the library's API names that it gives
/// for a caller of the library (Surface3Options::reorient, ClippedVoronoi3::compute) become
/// the options and commands that do the same. Every error line and JSON "error" goes
/// through it.
std::string cli_message(const std::string& what);

/// The one line of an error as the command line says it: cli_message, line breaks as spaces,
/// no trailing space. The "voroclip: error: " line on stderr and the JSON "error" are it.
std::string error_line(const std::string& what);

/// --stats json: `stats` as one JSON object on one line of stdout, after "command" (the
/// command run) and "ok": true. A command prints it once, after its output files are written.
void print_stats(const nlohmann::ordered_json& stats, const GlobalOptions& options);

/// --stats json when the command fails: {"command": ..., "ok": false, "error": error_line(what)}
/// and then `fields` (check-surface's verdict), on one line of stdout; `command` null when no
/// command was recognised. main() prints it for every failure unless the command did
/// (stats_printed()), so that a script reading stdout always gets one object.
void print_failure_stats(const std::string& command, const std::string& what,
                         const nlohmann::ordered_json& fields = nlohmann::ordered_json::object());

/// Whether print_stats or print_failure_stats has printed the object of this run.
bool stats_printed();

/// Refuses, before any work, a vertex count that a meshing command cannot make: one above
/// 2^32 - 1 (vertex indices are 32-bit), or one whose memory, `count` x `bytes_per_vertex`
/// (each command's measured peak per vertex), exceeds the machine's physical memory or the
/// address-space limit (ulimit -v) when that is lower. Throws Error "<command>: <what> asks
/// for about N vertices; at most M fit <in what>: <advice>".
void check_vertex_count(const std::string& command, const std::string& what, double count,
                        double bytes_per_vertex, const std::string& advice);

class Progress;

/// The vertex count an absolute size implies (mesh2d's and mesh3d's progress event, before
/// the run): check_vertex_count's message into `refused` and false (the progress callback
/// returns it: the run stops) when it cannot be made, else the note "<command>: about N
/// vertices for this size" (three significant digits: the count made differs from it)
/// and true.
bool note_implied_vertices(const std::string& command, const std::string& what, double count,
                           double bytes_per_vertex, const std::string& advice, Progress& progress,
                           std::string& refused);

/// Parses a finite double written in decimal ("-1.25e-3") or C99 hexadecimal ("0x1.8p-3"),
/// independently of the locale; the whole string must be the number. `what` names the
/// argument in the error message, e.g. "coordinate 3".
double parse_finite_double(const std::string& text, const std::string& what);

/// Parses a decimal integer in [0, 2^32 - 1]; the whole string must be the number.
std::uint32_t parse_index(const std::string& text, const std::string& what);

/// Shortest decimal text that reads back as the same double ("0.1", "1e-300"), independent
/// of the locale.
std::string format_double(double x);

/// "positive", "negative" or "zero".
const char* sign_name(Sign s);

/// The extension of a file name in lower case, with its dot (".vtu"); "" when it has none
/// (a dot in a directory name does not count).
std::string lower_extension(const std::string& path);
/// The extension an input file is read by: lower_extension, or for NAME.EXT.gz (a
/// gzip-compressed file, which every reader inflates) that of NAME.EXT.
std::string input_extension(const std::string& path);

// The usage error for --binary / --compress (`flag`) with an output of extension `ext`
// that has no such variant: "<flag>: only a .vtu output ... (<ext> is a text format ...)".
std::string no_encoding_message(const std::string& flag, const std::string& ext);

/// An output file of a command: the option that names it ("-o", "--neighbors") and the path.
struct OutputOption {
  std::string option;
  std::string path;  // empty: not written
};

/// Checks a command's outputs before any work: two options naming the same file (same_file:
/// also through "..", symbolic or hard links) are a UsageError naming both, then every path
/// must be writable (check_output_path, an Error otherwise).
void check_outputs(const std::vector<OutputOption>& outputs);

/// Input indices (0-based) of the sites that repeat the coordinates of an earlier site (in
/// input order): their cells are empty. `sites` holds `dimension` values per site.
std::vector<std::uint32_t> repeated_sites(const std::vector<double>& sites, int dimension);

/// Sites that are outside the domain or repeat an earlier site (input indices from 0):
/// one warning line on stderr, with the counts and the first indices (the current phase of
/// `progress` ended first, so that a live bar does not run into it), or, with `strict`, an
/// Error naming them. Nothing when both are empty.
void report_sites(const std::string& source, const std::vector<std::uint32_t>& outside,
                  const std::vector<std::uint32_t>& repeated, bool strict, Progress& progress);

struct DemoArgs {
  std::string svg_path;  // empty: no picture
};

struct PredicateArgs {
  std::string name;
  std::vector<std::string> coordinates;
  std::vector<std::string> sos_indices;
  bool sos = false;
};

struct DelaunayArgs {
  int dimension = 3;
  std::string input;  // point file; empty with --random
  std::uint32_t random = 0;
  bool random_set = false;
  std::uint64_t seed = 1;
  bool check = false;
  std::string output;  // .vtk; empty: no file
};

struct ClipArgs {
  std::string domain;  // polygon file or generator spec
  std::string sites;   // site file; empty with --random
  std::uint32_t random = 0;
  bool random_set = false;
  std::uint64_t seed = 1;
  std::string output;     // .svg, .vtu, .json, .csv (cvt2d also .txt); empty: no file
  std::string neighbors;  // .csv or .json table of neighbouring cells; empty: none
  bool reorient = false;  // clip3d: reorient inside-out shells of a surface domain
  bool strict = false;    // sites outside the domain or repeated: an error, not a warning
  bool binary = false;    // .vtu: base64 appended data (default: ASCII)
  bool compress = false;  // .vtu: zlib-compressed data
  // cvt2d
  std::string method = "lbfgs";
  std::uint32_t iterations = 1000;
  double tolerance = 1e-4;
  DensityArgs density;  // cvt2d
};

struct Mesh2dArgs {
  std::string domain;  // polygon file or generator spec
  std::uint32_t vertices = 0;
  bool vertices_set = false;
  double edge_length = 0;
  bool edge_length_set = false;  // --edge-length given (0 is then an error, not "absent")
  bool fix_input_vertices = false;
  bool keep_gaps = false;
  bool circumcenter_rule = false;
  std::string msh_version = "4.1";
  bool msh_version_set = false;  // --msh-version given (an error without a .msh output)
  std::uint32_t repair_rounds = 4;
  std::uint64_t seed = 1;
  double gradation = 0.3;
  double corner_angle = 0;
  double sharp_angle = 30;
  std::string method = "lbfgs";
  std::uint32_t iterations = 200;  // constrained CVT budget
  bool exact_vertices = false;     // no raise for the mean smallest angle
  std::string output;              // .svg, .vtu, .mesh, .msh; empty: no file
  std::string histogram;           // .svg angle histograms; empty: none
  bool binary = false;             // .vtu: base64 appended data (default: ASCII)
  bool compress = false;           // .vtu: zlib-compressed data
  DensityArgs density;
};

void run_clip2d(const ClipArgs& args, const GlobalOptions& options);
void run_clip3d(const ClipArgs& args, const GlobalOptions& options);
/// The writer of a 3D clipped diagram's file, by extension (for write_files_atomically):
/// .obj the restricted surface (keep_surface; its header names `command`), .vtu every
/// cell's faces (keep_geometry; in `encoding`), .csv / .json the per-cell table
/// (keep_geometry, for the neighbour counts: `neighbors`, computed when not given). It
/// refers to `sites`, `cv` and `neighbors`, which must outlive it.
FileWriter cells3_file(const std::string& path, const std::string& command,
                       const std::vector<double>& sites, const ClippedVoronoi3& cv,
                       VtuEncoding encoding = VtuEncoding::kAscii,
                       const NeighborTable* neighbors = nullptr);
void run_cvt2d(const ClipArgs& args, const GlobalOptions& options);

/// The rings of a 2D command's domain: a polygon file (.json, .poly) or a built-in
/// generator, "annulus:R_IN,R_OUT,SEGMENTS" or "square-holes:K,FRACTION".
PolygonRings load_rings(const std::string& spec);
/// The domain of those rings (Domain2(load_rings(spec))).
Domain2 load_domain(const std::string& spec);
/// SVG picture of a clipped diagram (computed with keep_geometry).
void write_clip_svg(std::ostream& out, const Domain2& domain, const std::vector<double>& sites,
                    const ClippedVoronoi2& cv);

struct QualityArgs {
  std::string mesh;       // tet mesh, any format read_tet_mesh reads
  std::string surface;    // reference: a surface file or a tet mesh (its boundary); optional
  std::string histogram;  // .svg picture of the histograms; empty: none
  std::string output;     // .vtu with Q1..Q4 per tet; empty: none
  std::uint64_t samples = 100000;  // minimum samples per surface for the distance
  bool samples_set = false;
  bool compress = false;  // -o .vtu: zlib-compressed data
};

/// The quality report of a tet mesh (and the Hausdorff distance to a reference surface).
void run_quality(const QualityArgs& args, const GlobalOptions& options);

void run_mesh2d(const Mesh2dArgs& args, const GlobalOptions& options);
/// SVG picture of a 2D mesh: triangles coloured by their smallest angle (red below 30
/// degrees), the domain's rings, fixed vertices as dots.
void write_mesh_svg(std::ostream& out, const Domain2& domain, const Mesh2& mesh);
/// The writer of a 2D mesh's file, by extension (for write_files_atomically): .svg
/// (triangles coloured by their smallest angle), .vtu, .mesh (Medit), .msh (Gmsh 4.1, or
/// 2.2 with `msh22`). The mesh carries its tags (mesh_domain2 fills them; tag_mesh2). A .vtu
/// is written in `encoding` (--binary, --compress). It refers to `domain` and `mesh`, which
/// must outlive it.
FileWriter mesh2_file(const std::string& path, const Domain2& domain, const Mesh2& mesh,
                      bool msh22 = false, VtuEncoding encoding = VtuEncoding::kAscii);

struct Mesh3dArgs {
  std::string domain;  // closed surface or tet mesh (read_domain3)
  bool reorient = false;
  bool exact_vertices = false;        // fail instead of adding the sites the topology needs
  bool allow_shape_mismatch = false;  // write a mesh whose boundary differs, with a warning
  std::uint32_t vertices = 10000;
  bool vertices_set = false;  // --vertices given (else --sizing is absolute)
  bool adaptive = false;
  double lfs_cap = 0;  // Mesh3Options::lfs_cap
  double facet_distance = Mesh3Options{}.facet_distance;
  double max_boundary_distance = Mesh3Options{}.max_boundary_distance;
  double feature_angle = 40;
  bool no_features = false;
  std::uint64_t seed = 1;
  std::uint32_t unconstrained_iterations = 16, constrained_iterations = 30;
  bool no_perturb = false;
  bool smooth_surface = false;
  double smooth_shape = 0.75;
  double sliver_angle = 30;
  double flip_angle = Mesh3Options{}.flip_dihedral_deg;
  std::uint32_t mean_rounds = Mesh3Options{}.mean_rounds;
  std::string output;  // .mesh, .msh, .vtu, .node / .ele; empty: no file
  std::string msh_version = "4.1";
  bool msh_version_set = false;  // --msh-version given (an error without a .msh output)
  bool binary = false;           // .msh: Gmsh 4.1 binary
  bool compress = false;         // .vtu: zlib-compressed data
  DensityArgs density;
};

/// CVT tetrahedral meshing of a volume (mesh3d), with the quality report.
void run_mesh3d(const Mesh3dArgs& args, const GlobalOptions& options);

struct CheckSurfaceArgs {
  std::string path;  // a surface (.obj, .off, .stl, .ply) or a tet mesh (its boundary)
  bool reorient = false;
};

/// Validates a closed surface (Surface3) and reports its shells, genus, area and volume.
void run_check_surface(const CheckSurfaceArgs& args, const GlobalOptions& options);

/// Reads a 3D domain (read_domain3) and prints a note for each shell it reoriented.
Domain3 load_domain3(const std::string& path, bool reorient, const GlobalOptions& options);

void run_demo(const DemoArgs& args, const GlobalOptions& options);
void run_delaunay(const DelaunayArgs& args, const GlobalOptions& options);
void run_predicate(const PredicateArgs& args, const GlobalOptions& options);

}  // namespace voroclip::cli
