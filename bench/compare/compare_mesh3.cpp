// voroclip's CVT tet mesher (mesh3d) against CGAL Mesh_3 on the closed surfaces of
// ../shared/data/surfaces, both measured with voroclip's own tools so that the figures are
// comparable.
//
//   compare_mesh3 [--models a,b,...] [--vertices N = 10000] [--threads T = all cores]
//
// Per model:
//   voroclip  read_domain3(path) + mesh3d(domain, default Mesh3Options, nb_vertices = N),
//             timed together. An Error, or a non-empty shape_problem, is printed in the
//             row.
//   CGAL      Polyhedral_mesh_domain_with_features_3 on a Polyhedron_3 built from the
//             domain's validated surface (read_surface's triangles, welded and oriented
//             outward by Surface3: the volume mesh3d meshes), detect_features(40 degrees,
//             voroclip's default feature angle), Mesh_criteria_3 with one size s:
//             edge_size s / 2, facet_angle 25, facet_size s, facet_distance s / 10,
//             cell_radius_edge_ratio 3, cell_size s (the ratios of CGAL's
//             mesh_polyhedral_domain_with_features example), make_mesh_3 with perturb() and
//             exude(). s starts at c (volume / n)^(1/3), n = voroclip's vertex count (c
//             carried over from the previous model), and is rescaled (cube root of the
//             count's ratio first, then the secant of log count against log s) until CGAL's
//             vertex count is within 10 % of n, at most kMaxTries runs (fewer when the
//             count stays put while s grows 1.5x or more: the feature polylines' protecting
//             balls then set it, at any size). Only the run that is kept is in the time
//             columns; the wall time of the runs before it is in the note. The timed run
//             starts from the triangles in memory (Polyhedron, domain, features, mesh).
//             Parallel_tag when CGAL is built with TBB (CGAL_LINKED_WITH_TBB), else
//             Sequential_tag; the header line says which.
// Both meshes become flat arrays (vertices used by a tet, 4 indices per tet, det > 0) and
// are measured alike: tet_quality (Q1 = smallest dihedral angle per tet, min and mean; Q4
// min), the two-sided Hausdorff distance (hausdorff_distance, default sampling) between the
// mesh's boundary (the faces of exactly one tet, tet_mesh_boundary) and the input surface
// as read, relative to the input's bounding-box diagonal; and min Q1 of the tets with 4, 3
// and at most 2 boundary vertices (a boundary vertex is on a face of exactly one tet), and
// how many vertices are boundary vertices (CGAL's facet criteria put more of them there).
// Times: wall clock, and the process's CPU time over all threads (less disturbed by other
// load on the machine); ours / CGAL is the ratio of each. Both run on T threads
// (tbb::global_control).
// Exit status 1 when a mesher failed on some model or a mesh has inverted or degenerate
// tets.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polyhedral_mesh_domain_with_features_3.h>
#include <CGAL/make_mesh_3.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <sstream>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

#include "best_time.h"
#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/mesh.h"

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Polyhedron = CGAL::Mesh_polyhedron_3<Kernel>::type;
using MeshDomain = CGAL::Polyhedral_mesh_domain_with_features_3<Kernel>;
#ifdef CGAL_LINKED_WITH_TBB
using Concurrency = CGAL::Parallel_tag;
constexpr const char* kCgalMode = "Parallel_tag (TBB)";
#else
using Concurrency = CGAL::Sequential_tag;
constexpr const char* kCgalMode = "Sequential_tag";
#endif
using Triangulation = CGAL::Mesh_triangulation_3<MeshDomain, CGAL::Default, Concurrency>::type;
using C3t3 = CGAL::Mesh_complex_3_in_triangulation_3<Triangulation, MeshDomain::Corner_index,
                                                     MeshDomain::Curve_index>;
using Criteria = CGAL::Mesh_criteria_3<Triangulation>;

constexpr double kFeatureAngleDeg = voroclip::kDefaultFeatureAngleDeg;
constexpr double kCountTolerance = 0.10;  // CGAL's vertex count within 10 % of ours
constexpr int kMaxTries = 6;

const char* const kModels[] = {"bunny.obj",
                               "elk.off",
                               "fandisk.obj",
                               "gargoyle.off",
                               "homer.obj",
                               "rocker-arm.obj",
                               "skull_low_resolution.obj",
                               "sphere.obj"};

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point from) {
  return std::chrono::duration<double>(Clock::now() - from).count();
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string x; std::getline(in, x, ',');) out.push_back(x);
  return out;
}

std::string stem(const std::string& file) { return file.substr(0, file.find('.')); }

// A tet mesh as both meshers' results are compared: the vertices used by a tet, x y z each,
// and 4 indices per tet with det(p1 - p0, p2 - p0, p3 - p0) > 0.
struct FlatMesh {
  std::vector<double> xyz;
  std::vector<std::uint32_t> tets;
  std::uint32_t nb_vertices() const { return static_cast<std::uint32_t>(xyz.size() / 3); }
  std::uint32_t nb_tets() const { return static_cast<std::uint32_t>(tets.size() / 4); }
};

// What a row shows about a mesh.
struct Measures {
  double q1_min = 0, q1_mean = 0, q4_min = 0;
  double hausdorff_percent = 0;  // of the input's bounding-box diagonal
  // min Q1 of the tets with 4, 3, <= 2 boundary vertices (-1: no such tet)
  double q1_min_by_boundary[3] = {-1, -1, -1};
  std::uint32_t nb_bad = 0;       // inverted + degenerate tets
  std::uint32_t nb_boundary = 0;  // vertices on a face of exactly one tet
};

Measures measure(const FlatMesh& mesh, const voroclip::TriangleSurface& input) {
  voroclip::TetMeshInput tets;
  tets.source = "mesh";
  tets.xyz = mesh.xyz;
  tets.tets = mesh.tets;
  voroclip::TetQualityOptions options;
  options.keep_per_tet = true;
  const voroclip::TetQuality quality = voroclip::tet_quality(tets, options);
  const voroclip::TriangleSurface boundary = voroclip::tet_mesh_boundary(tets);

  Measures m;
  m.q1_min = quality.q1_deg.min;
  m.q1_mean = quality.q1_deg.mean;
  m.q4_min = quality.q4.min;
  m.nb_bad = static_cast<std::uint32_t>(quality.inverted.size() + quality.degenerate.size());
  m.hausdorff_percent = 100 * voroclip::hausdorff_distance(boundary, input).max_relative();

  std::vector<std::uint8_t> on_boundary(mesh.nb_vertices(), 0);
  for (const std::uint32_t v : boundary.triangles) on_boundary[v] = 1;
  for (const std::uint8_t b : on_boundary) m.nb_boundary += b;
  for (std::uint32_t t = 0; t < mesh.nb_tets(); ++t) {
    int nb = 0;
    for (int k = 0; k < 4; ++k) nb += on_boundary[mesh.tets[4 * std::size_t{t} + std::size_t(k)]];
    double& slot = m.q1_min_by_boundary[nb == 4 ? 0 : nb == 3 ? 1 : 2];
    const double q1 = quality.per_tet[t].q1_deg;
    if (slot < 0 || q1 < slot) slot = q1;
  }
  return m;
}

// ---- voroclip

// Wall and CPU seconds of one run.
struct Times {
  double wall = 0, cpu = 0;
};

struct OursRun {
  FlatMesh mesh;
  Times seconds;
  std::string note;  // the shape problem or the error
};

OursRun run_voroclip(const std::string& path, std::uint32_t nb_vertices) {
  OursRun run;
  try {
    const auto start = Clock::now();
    const double cpu = voroclip::bench::process_cpu_seconds();
    const voroclip::Domain3 domain = voroclip::read_domain3(path);
    voroclip::Mesh3Options options;
    options.nb_vertices = nb_vertices;
    voroclip::Mesh3Result result = voroclip::mesh3d(domain, options);
    run.seconds.wall = seconds_since(start);
    run.seconds.cpu = voroclip::bench::process_cpu_seconds() - cpu;
    run.mesh.xyz = std::move(result.xyz);
    run.mesh.tets = std::move(result.tets);
    if (!result.shape_problem.empty()) run.note = "shape problem: " + result.shape_problem;
  } catch (const voroclip::Error& e) {
    run.note = std::string("Error: ") + e.what();
  }
  return run;
}

// ---- CGAL Mesh_3

// The triangles of the domain's surface (welded, oriented outward) as a Polyhedron_3, with
// only the vertices they use.
Polyhedron polyhedron_from(const voroclip::Surface3& surface) {
  std::vector<std::uint32_t> index(surface.nb_vertices(), voroclip::Domain3::kNone);
  std::vector<Kernel::Point_3> points;
  std::vector<std::array<std::size_t, 3>> triangles;
  for (std::uint32_t t = 0; t < surface.nb_triangles(); ++t) {
    std::array<std::size_t, 3> tri{};
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = surface.triangle_vertex(t, k);
      if (index[v] == voroclip::Domain3::kNone) {
        index[v] = static_cast<std::uint32_t>(points.size());
        const double* p = surface.vertex(v);
        points.emplace_back(p[0], p[1], p[2]);
      }
      tri[static_cast<std::size_t>(k)] = index[v];
    }
    triangles.push_back(tri);
  }
  Polyhedron polyhedron;
  CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(points, triangles, polyhedron);
  return polyhedron;
}

// The cells in the complex as a FlatMesh: vertices numbered in order of first use, each
// cell oriented so that det > 0 (CGAL::orientation, exact with Epick).
FlatMesh flatten(const C3t3& c3t3) {
  struct HandleHash {
    std::size_t operator()(Triangulation::Vertex_handle v) const {
      return std::hash<const void*>()(&*v);
    }
  };
  std::unordered_map<Triangulation::Vertex_handle, std::uint32_t, HandleHash> index;
  FlatMesh mesh;
  for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c) {
    std::uint32_t tet[4];
    Kernel::Point_3 p[4];
    for (int k = 0; k < 4; ++k) {
      const Triangulation::Vertex_handle v = c->vertex(k);
      p[k] = v->point().point();
      const auto inserted = index.emplace(v, mesh.nb_vertices());
      if (inserted.second) mesh.xyz.insert(mesh.xyz.end(), {p[k].x(), p[k].y(), p[k].z()});
      tet[k] = inserted.first->second;
    }
    if (CGAL::orientation(p[0], p[1], p[2], p[3]) == CGAL::NEGATIVE) std::swap(tet[2], tet[3]);
    mesh.tets.insert(mesh.tets.end(), tet, tet + 4);
  }
  return mesh;
}

struct CgalRun {
  FlatMesh mesh;
  Times seconds;    // the run kept
  double size = 0;  // its s
  int tries = 0;    // runs before it
  double tries_seconds = 0;
  std::string note;
};

// One make_mesh_3 run with size s, from the triangles in memory; its times to `seconds`.
FlatMesh run_cgal_once(const voroclip::Surface3& surface, double s, Times& seconds) {
  const auto start = Clock::now();
  const double cpu = voroclip::bench::process_cpu_seconds();
  MeshDomain domain(polyhedron_from(surface));
  domain.detect_features(kFeatureAngleDeg);
  const Criteria criteria(
      CGAL::parameters::edge_size = s / 2, CGAL::parameters::facet_angle = 25,
      CGAL::parameters::facet_size = s, CGAL::parameters::facet_distance = s / 10,
      CGAL::parameters::cell_radius_edge_ratio = 3, CGAL::parameters::cell_size = s);
  const C3t3 c3t3 = CGAL::make_mesh_3<C3t3>(domain, criteria, CGAL::parameters::perturb(),
                                            CGAL::parameters::exude());
  FlatMesh mesh = flatten(c3t3);
  seconds.wall = seconds_since(start);
  seconds.cpu = voroclip::bench::process_cpu_seconds() - cpu;
  return mesh;
}

// Runs Mesh_3 with sizes rescaled until its vertex count is within kCountTolerance of
// `wanted`; `c` (the size's factor over (volume / wanted)^(1/3)) is read as the first
// guess and updated to the last size's.
CgalRun run_cgal(const voroclip::Surface3& surface, std::uint32_t wanted, double& c,
                 const std::string& name) {
  CgalRun run;
  const double unit = std::cbrt(surface.volume() / wanted);
  double s = c * unit, last_s = 0, last_n = 0;
  for (int attempt = 0; attempt < kMaxTries; ++attempt) {
    Times seconds;
    FlatMesh mesh = run_cgal_once(surface, s, seconds);
    const double n = mesh.nb_vertices();
    std::fprintf(stderr, "  %s: CGAL size %.4g: %u vertices, %.2f s (CPU %.2f s)\n", name.c_str(),
                 s, mesh.nb_vertices(), seconds.wall, seconds.cpu);
    run.mesh = std::move(mesh);
    run.seconds = seconds;
    run.size = s;
    c = s / unit;
    if (std::fabs(n - wanted) <= kCountTolerance * wanted) return run;
    if (attempt + 1 == kMaxTries) break;
    if (last_n > 0 && std::fabs(std::log(n / last_n)) < std::log(1 + kCountTolerance) &&
        std::fabs(std::log(s / last_s)) > std::log(1.5)) {
      run.note = "count set by the features, not the size";
      return run;
    }
    run.tries += 1;
    run.tries_seconds += seconds.wall;
    // n ~ s^slope: -3 for a volume-dominated count; from the last two runs when both exist.
    double slope = -3;
    if (last_n > 0 && last_s != s && n > 0) {
      slope = std::clamp(std::log(n / last_n) / std::log(s / last_s), -4.0, -1.0);
    }
    last_s = s;
    last_n = n;
    s *= std::pow(wanted / std::max(n, 1.0), 1 / slope);
  }
  run.note = "count not within 10 % after " + std::to_string(kMaxTries) + " runs";
  return run;
}

void print_row(const std::string& model, const char* mesher, const FlatMesh& mesh,
               const Measures& m, Times seconds, const std::string& ratio,
               const std::string& note) {
  std::printf("| %s | %s | %u | %u | %u | %.2f | %.2f | %.3f | %.3f | ", model.c_str(), mesher,
              mesh.nb_vertices(), m.nb_boundary, mesh.nb_tets(), m.q1_min, m.q1_mean, m.q4_min,
              m.hausdorff_percent);
  for (const double q : m.q1_min_by_boundary) {
    if (q < 0) {
      std::printf("- | ");
    } else {
      std::printf("%.2f | ", q);
    }
  }
  std::printf("%.2f | %.2f | %s | %s |\n", seconds.wall, seconds.cpu, ratio.c_str(), note.c_str());
  std::fflush(stdout);
}

void print_failure(const std::string& model, const char* mesher, const std::string& note) {
  std::printf("| %s | %s | | | | | | | | | | | | | | %s |\n", model.c_str(), mesher, note.c_str());
  std::fflush(stdout);
}

// Meshes one model with both and prints their rows; false when a mesher failed or left
// inverted or degenerate tets.
bool compare_model(const std::string& name, const std::string& path, std::uint32_t nb_vertices,
                   double& c) {
  const voroclip::TriangleSurface input = voroclip::read_surface(path);
  const voroclip::Domain3 domain(input);

  const OursRun ours = run_voroclip(path, nb_vertices);
  std::fprintf(stderr, "  %s: voroclip %u vertices, %.2f s (CPU %.2f s)\n", name.c_str(),
               ours.mesh.nb_vertices(), ours.seconds.wall, ours.seconds.cpu);
  CgalRun cgal;
  try {
    cgal = run_cgal(domain.surface(),
                    ours.mesh.nb_tets() > 0 ? ours.mesh.nb_vertices() : nb_vertices, c, name);
  } catch (const std::exception& e) {
    cgal.note = std::string("CGAL threw: ") + e.what();
  }

  bool ok = true;
  if (ours.mesh.nb_tets() > 0) {
    const Measures m = measure(ours.mesh, input);
    char ratio[64] = "-";
    if (cgal.mesh.nb_tets() > 0) {
      std::snprintf(ratio, sizeof ratio, "%.2f, %.2f", ours.seconds.wall / cgal.seconds.wall,
                    ours.seconds.cpu / cgal.seconds.cpu);
    }
    std::string note = ours.note;
    if (m.nb_bad > 0) note += " " + std::to_string(m.nb_bad) + " inverted/degenerate tets";
    print_row(name, "voroclip", ours.mesh, m, ours.seconds, ratio, note);
    ok = ours.note.empty() && m.nb_bad == 0;
  } else {
    print_failure(name, "voroclip", ours.note);
    ok = false;
  }
  if (cgal.mesh.nb_tets() > 0) {
    const Measures m = measure(cgal.mesh, input);
    char note[160];
    std::snprintf(note, sizeof note, "size %.4g; %d earlier tries, %.1f s", cgal.size, cgal.tries,
                  cgal.tries_seconds);
    std::string text = note;
    if (!cgal.note.empty()) text += "; " + cgal.note;
    if (m.nb_bad > 0) text += "; " + std::to_string(m.nb_bad) + " inverted/degenerate tets";
    print_row(name, "CGAL", cgal.mesh, m, cgal.seconds, "", text);
    ok = ok && m.nb_bad == 0;
  } else {
    print_failure(name, "CGAL", cgal.note.empty() ? "no tets" : cgal.note);
    ok = false;
  }
  return ok;
}
}  // namespace

int main(int argc, char** argv) {
  int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::uint32_t nb_vertices = 10000;
  std::vector<std::string> models;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    const bool has_value = a + 1 < argc;
    if (arg == "--threads" && has_value) {
      threads = std::max(1, std::atoi(argv[++a]));
    } else if (arg == "--vertices" && has_value) {
      nb_vertices = static_cast<std::uint32_t>(std::max(4L, std::atol(argv[++a])));
    } else if (arg == "--models" && has_value) {
      models = split(argv[++a]);
    } else {
      std::fprintf(stderr,
                   "usage: compare_mesh3 [--models a,b,...] [--vertices N] [--threads T]\n");
      return 2;
    }
  }
  for (const std::string& m : models) {
    if (std::none_of(std::begin(kModels), std::end(kModels),
                     [&](const char* k) { return m == stem(k); })) {
      std::fprintf(stderr, "compare_mesh3: no model '%s'\n", m.c_str());
      return 2;
    }
  }
  const tbb::global_control control(tbb::global_control::max_allowed_parallelism,
                                    static_cast<std::size_t>(threads));

  std::printf(
      "voroclip mesh3d (default options, %u vertices) against CGAL Mesh_3 (%s, features at "
      "%g degrees, perturb + exude, size matched to 10 %% of our vertex count), %d "
      "thread(s); seconds\n\n",
      nb_vertices, kCgalMode, kFeatureAngleDeg, threads);
  std::printf(
      "| model | mesher | vertices | boundary vertices | tets | min Q1 | mean Q1 | min Q4 | "
      "Hausdorff %% | min Q1 "
      "(4 bnd) | (3 bnd) | (<=2 bnd) | wall s | CPU s | ours / CGAL wall, CPU | note |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  std::fflush(stdout);

  bool ok = true;
  double c = 1;  // CGAL's size factor, carried from model to model
  for (const char* file : kModels) {
    const std::string name = stem(file);
    if (!models.empty() && std::find(models.begin(), models.end(), name) == models.end()) {
      continue;
    }
    const std::string path = std::string(VOROCLIP_SHARED_DATA_DIR) + "/surfaces/" + file;
    try {
      ok = compare_model(name, path, nb_vertices, c) && ok;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "compare_mesh3: %s: %s\n", name.c_str(), e.what());
      print_failure(name, "-", e.what());
      ok = false;
    }
  }
  return ok ? 0 : 1;
}
