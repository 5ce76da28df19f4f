// voroclip's CVT triangle mesher (mesh_domain2) against CGAL Mesh_2 on the polygons of
// ../shared/data/polygons/valid, both measured the same way by this program.
//
//   compare_mesh2 [--polygon FILE] [--vertices N = 1000] [--runs R = 3] [--threads T = 1]
//                 [--lloyd-iterations I = 0] [--json]
//
// Per polygon (read with read_polygon, validated as a Domain2; not timed):
//   1. voroclip at nb_vertices = N (default Mesh2Options otherwise, but no raise for the mean
//      smallest angle: raise_for_mean_angle = false) gives its edge length H
//      (Mesh2Stats::edge_length).
//   2. CGAL: a Constrained_Delaunay_triangulation_2 (Epick, Exact_predicates_tag) with the
//      domain's rings as constraints, refine_Delaunay_mesh_2 with
//      Delaunay_mesh_size_criteria_2(0.125, H) (shape bound 0.125: smallest angle about
//      20.7 degrees; H bounds the longest edge) and one seed in each hole, then
//      lloyd_optimize_mesh_2 with the same seeds (max_iteration_number I; 0 is CGAL's
//      default: up to 1000 iterations, convergence 0.001, freeze bound 0.001). Its mesh is
//      the faces marked in the domain. CGAL's vertex count C is the target of step 3.
//   3. voroclip at nb_vertices = C, then rescaled by C / (vertices it gave) until its count
//      is within 10 % of C (at most kMaxTries runs). Where voroclip's count is set by the
//      domain's small features and stays above C, CGAL's size bound is rescaled instead,
//      to voroclip's count (see compare_polygon); the row's note says so.
// The two final configurations are then run R times each, round robin (best_time.h), and
// the best wall and CPU times reported; CGAL's time covers building the triangulation from
// the domain's rings, refinement and Lloyd; voroclip's is mesh_domain2. Both run on T
// threads (tbb::global_control; CGAL Mesh_2 is sequential, hence T = 1 by default).
// voroclip's timed runs must repeat its mesh; CGAL's Lloyd step does not repeat (see
// compare_polygon), so its row measures its first run and the note gives the spread.
// N sets the size only: the rows have CGAL's count, about 2x N on these polygons.
//
// Both meshes are measured alike (a CGAL mesh becomes a Mesh2 with the vertices its faces
// use): triangle_quality2 (min angle, mean of the per-triangle min angle), coverage = sum of
// the triangles' signed areas (long double) / Domain2::area(), the triangles whose
// centroid (rounded) is not strictly inside the domain (Domain2::locate, exact), and
// check_mesh2 (exact: counter-clockwise, non-degenerate, inside the closed domain,
// conforming edges; its first defect goes to the note).
// CGAL's meshes can fail check_mesh2: with Epick the points it inserts on a constrained
// edge (midpoints, then Lloyd keeps them) are rounded, a few ulps off the domain's edge,
// so a domain edge may cross a triangle next to it by that much.
// Exit status 1 when a mesher failed (threw, or gave no triangle) on some polygon or
// voroclip's mesh fails check_mesh2.
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/lloyd_optimize_mesh_2.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <functional>
#include <string>
#include <unordered_map>
#include <vector>

#include "best_time.h"
#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/mesh.h"

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Delaunay_mesh_vertex_base_2<Kernel>;
using Fb = CGAL::Delaunay_mesh_face_base_2<Kernel>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::Exact_predicates_tag>;
using Criteria = CGAL::Delaunay_mesh_size_criteria_2<Cdt>;
using CgalPoint = Cdt::Point;

constexpr double kShapeBound = 0.125;
constexpr double kCountTolerance = 0.10;  // voroclip's vertex count within 10 % of CGAL's
constexpr int kMaxTries = 5;

std::string stem(const std::string& path) { return std::filesystem::path(path).stem().string(); }

// ---- measures

struct Measures {
  std::uint32_t nb_vertices = 0, nb_triangles = 0;
  double min_angle = 0, mean_min_angle = 0;
  double coverage = 0;           // sum of triangle areas / domain area
  std::uint32_t nb_outside = 0;  // triangles whose centroid is not strictly inside
  std::string check;             // check_mesh2: empty when valid
};

Measures measure(const voroclip::Domain2& domain, const voroclip::Mesh2& mesh) {
  Measures m;
  const voroclip::TriangleQuality2 q = voroclip::triangle_quality2(mesh);
  m.nb_vertices = mesh.nb_vertices();
  m.nb_triangles = mesh.nb_triangles();
  m.min_angle = q.min_angle;
  m.mean_min_angle = q.mean_min_angle;
  long double area = 0;
  for (std::uint32_t t = 0; t < mesh.nb_triangles(); ++t) {
    const double* p[3];
    for (std::size_t k = 0; k < 3; ++k) {
      p[k] = mesh.xy.data() + 2 * std::size_t{mesh.triangles[3 * std::size_t{t} + k]};
    }
    const long double ux = static_cast<long double>(p[1][0]) - p[0][0];
    const long double uy = static_cast<long double>(p[1][1]) - p[0][1];
    const long double vx = static_cast<long double>(p[2][0]) - p[0][0];
    const long double vy = static_cast<long double>(p[2][1]) - p[0][1];
    area += (ux * vy - uy * vx) / 2;
    const double centroid[2] = {(p[0][0] + p[1][0] + p[2][0]) / 3,
                                (p[0][1] + p[1][1] + p[2][1]) / 3};
    if (domain.locate(centroid) != voroclip::Sign::positive) ++m.nb_outside;
  }
  m.coverage = static_cast<double>(area / static_cast<long double>(domain.area()));
  m.check = voroclip::check_mesh2(domain, mesh);
  return m;
}

// ---- CGAL Mesh_2

// A point strictly inside each hole: the centroid of the triangle of the constrained
// triangulation of the rings alone (no Steiner point) that lies on the hole's side of one
// of the hole's edges (the domain is on the left of an edge, the hole on its right). That
// triangle lies in the hole, since no triangle crosses a constraint; the rounded centroid
// is checked to be outside the domain (exact), else the next edge is tried.
std::vector<CgalPoint> hole_seeds(const voroclip::Domain2& domain, const Cdt& cdt,
                                  const std::vector<Cdt::Vertex_handle>& handle) {
  std::vector<CgalPoint> seeds;
  for (std::uint32_t r = 0; r < domain.nb_rings(); ++r) {
    if (!domain.is_hole(r)) continue;
    bool found = false;
    for (std::uint32_t v = domain.ring_begin(r); v < domain.ring_end(r) && !found; ++v) {
      Cdt::Face_handle f;
      int i = 0;
      if (!cdt.is_edge(handle[v], handle[domain.next(v)], f, i)) continue;
      // Counter-clockwise in f, its edge i runs from f->vertex(ccw(i)) to f->vertex(cw(i)),
      // with f on its left; the hole is on the right of v -> next(v).
      if (f->vertex(Cdt::ccw(i)) == handle[v]) f = f->neighbor(i);
      if (cdt.is_infinite(f)) continue;
      const CgalPoint c =
          CGAL::centroid(f->vertex(0)->point(), f->vertex(1)->point(), f->vertex(2)->point());
      const double p[2] = {c.x(), c.y()};
      if (domain.locate(p) == voroclip::Sign::negative) {
        seeds.push_back(c);
        found = true;
      }
    }
    if (!found) {
      throw voroclip::Error(domain.source() + ": no seed found in hole ring " +
                            std::to_string(domain.source_ring(r)));
    }
  }
  return seeds;
}

struct CgalResult {
  voroclip::Mesh2 mesh;
  std::string lloyd;  // how Lloyd stopped
};

const char* lloyd_code(CGAL::Mesh_optimization_return_code code) {
  switch (code) {
    case CGAL::CONVERGENCE_REACHED:
      return "converged";
    case CGAL::MAX_ITERATION_NUMBER_REACHED:
      return "max iterations";
    case CGAL::ALL_VERTICES_FROZEN:
      return "all vertices frozen";
    case CGAL::CANT_IMPROVE_ANYMORE:
      return "cannot improve";
    case CGAL::TIME_LIMIT_REACHED:
      return "time limit";
    default:
      return "other";
  }
}

// Mesh_2 of the domain with size bound `size`; the faces in the domain as a Mesh2 (the
// vertices they use, numbered in order of first use; CGAL's faces are counter-clockwise).
CgalResult run_cgal(const voroclip::Domain2& domain, double size, int lloyd_iterations) {
  Cdt cdt;
  std::vector<Cdt::Vertex_handle> handle(domain.nb_vertices());
  for (std::uint32_t v = 0; v < domain.nb_vertices(); ++v) {
    handle[v] = cdt.insert(CgalPoint(domain.vertex(v)[0], domain.vertex(v)[1]));
  }
  for (std::uint32_t v = 0; v < domain.nb_vertices(); ++v) {
    cdt.insert_constraint(handle[v], handle[domain.next(v)]);
  }
  const std::vector<CgalPoint> seeds = hole_seeds(domain, cdt, handle);
  // mark = false: the seeds' components are outside the domain.
  CGAL::refine_Delaunay_mesh_2(cdt, seeds.begin(), seeds.end(), Criteria(kShapeBound, size), false);
  const CGAL::Mesh_optimization_return_code code = CGAL::lloyd_optimize_mesh_2(
      cdt, CGAL::parameters::max_iteration_number = lloyd_iterations,
      CGAL::parameters::seeds_begin = seeds.begin(), CGAL::parameters::seeds_end = seeds.end(),
      CGAL::parameters::mark = false);

  CgalResult result;
  result.lloyd = lloyd_code(code);
  voroclip::Mesh2& mesh = result.mesh;
  std::unordered_map<const void*, std::uint32_t> index;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (!f->is_in_domain()) continue;
    for (int k = 0; k < 3; ++k) {
      const Cdt::Vertex_handle v = f->vertex(k);
      const auto inserted = index.emplace(&*v, mesh.nb_vertices());
      if (inserted.second) mesh.xy.insert(mesh.xy.end(), {v->point().x(), v->point().y()});
      mesh.triangles.push_back(inserted.first->second);
    }
  }
  const std::uint32_t n = mesh.nb_vertices();
  mesh.vertex_kind.assign(n, voroclip::Mesh2::VertexKind::kInterior);
  mesh.vertex_domain.assign(n, voroclip::Mesh2::kNone);
  mesh.vertex_edge.assign(n, voroclip::Mesh2::kNone);
  mesh.vertex_site.assign(n, voroclip::Mesh2::kNone);
  return result;
}

// ---- one polygon

struct Row {
  std::string mesher;
  Measures m;
  voroclip::bench::Best seconds;
  std::string note;
  bool ok = false;
};

struct PolygonResult {
  std::string name;
  double edge_length = 0;                // voroclip's H at --vertices
  double cgal_size = 0;                  // CGAL's size bound (H, or rescaled: see above)
  std::uint32_t nb_vertices_option = 0;  // voroclip's final nb_vertices
  std::vector<Row> rows;                 // voroclip, CGAL; empty on an error
  std::string error;
};

bool within(double count, double wanted) {
  return std::fabs(count - wanted) <= kCountTolerance * wanted;
}

// Rescales CGAL's size bound until its vertex count is within 10 % of `wanted`: count ~
// size^-2 first, then the slope of the last two runs. `cgal` holds the run at `size` on
// entry and the last run on return; false when the count is not reached in kMaxTries runs.
bool match_cgal(const voroclip::Domain2& domain, double wanted, int lloyd_iterations,
                const std::string& name, double& size, CgalResult& cgal) {
  double last_size = 0, last_n = 0;
  for (int attempt = 0; attempt < kMaxTries; ++attempt) {
    const double n = cgal.mesh.nb_vertices();
    if (within(n, wanted)) return true;
    double slope = -2;
    if (last_n > 0 && last_n != n && n > 0) {
      slope = std::clamp(std::log(n / last_n) / std::log(size / last_size), -4.0, -0.5);
    }
    last_size = size;
    last_n = n;
    size *= std::pow(wanted / std::max(n, 1.0), 1 / slope);
    cgal = run_cgal(domain, size, lloyd_iterations);
    std::fprintf(stderr, "  %s: CGAL at size %.6g: %u vertices (Lloyd: %s)\n", name.c_str(), size,
                 cgal.mesh.nb_vertices(), cgal.lloyd.c_str());
  }
  return within(cgal.mesh.nb_vertices(), wanted);
}

// The vertex counts are matched as follows. voroclip at nb_vertices = N gives V0 and its
// edge length H; CGAL at size bound H gives C. When V0 > 1.1 C already (voroclip's count
// is set by the domain's small features, not by N), voroclip stays at N and CGAL's size
// bound is rescaled to V0. Otherwise voroclip's nb_vertices is rescaled toward C (C, then
// times C / count, at most kMaxTries runs), and if that fails CGAL's size bound is
// rescaled to voroclip's last count.
PolygonResult compare_polygon(const std::string& path, std::uint32_t nb_vertices, int runs,
                              int lloyd_iterations) {
  PolygonResult result;
  result.name = stem(path);
  const char* name = result.name.c_str();
  const voroclip::Domain2 domain(voroclip::read_polygon(path));

  voroclip::Mesh2Options options;
  options.nb_vertices = nb_vertices;
  // Both meshers at one vertex count: no raise for the mean smallest angle (it would
  // change voroclip's count, which step 3 matches to CGAL's).
  options.raise_for_mean_angle = false;
  voroclip::Mesh2Stats stats;
  voroclip::Mesh2 ours = voroclip::mesh_domain2(domain, options, &stats);
  result.edge_length = stats.edge_length;
  std::fprintf(stderr, "  %s: voroclip at %u: %u vertices, H = %.6g\n", name, nb_vertices,
               ours.nb_vertices(), stats.edge_length);

  result.cgal_size = result.edge_length;
  CgalResult cgal = run_cgal(domain, result.cgal_size, lloyd_iterations);
  const double cgal_first = cgal.mesh.nb_vertices();
  std::fprintf(stderr, "  %s: CGAL at size %.6g: %u vertices (Lloyd: %s)\n", name, result.cgal_size,
               cgal.mesh.nb_vertices(), cgal.lloyd.c_str());

  std::string ours_note;
  bool matched = within(ours.nb_vertices(), cgal_first);
  if (!matched && ours.nb_vertices() < (1 + kCountTolerance) * cgal_first) {
    double option = cgal_first;
    for (int attempt = 0; attempt < kMaxTries && !matched; ++attempt) {
      options.nb_vertices = static_cast<std::uint32_t>(std::max(4L, std::lround(option)));
      ours = voroclip::mesh_domain2(domain, options, &stats);
      std::fprintf(stderr, "  %s: voroclip at %u: %u vertices\n", name, options.nb_vertices,
                   ours.nb_vertices());
      matched = within(ours.nb_vertices(), cgal_first);
      if (ours.nb_vertices() == 0) break;
      option *= cgal_first / ours.nb_vertices();
    }
  }
  std::string cgal_note;
  if (!matched) {
    cgal_note = "rescaled to voroclip's count";
    if (!match_cgal(domain, ours.nb_vertices(), lloyd_iterations, result.name, result.cgal_size,
                    cgal)) {
      cgal_note += "; counts not within 10 % after " + std::to_string(kMaxTries) + " runs";
    }
  }
  result.nb_vertices_option = options.nb_vertices;

  // The timed runs. voroclip's must give the mesh above (it is deterministic). CGAL's need
  // not: lloyd_optimize_mesh_2 moves the vertices in the order of a std::set of vertex
  // handles, i.e. of their addresses, so its mesh changes from run to run; the row measures
  // the first run (above) and the note gives the range of the timed runs.
  std::vector<voroclip::Mesh2> ours_timed;
  std::vector<voroclip::Mesh2> cgal_timed;
  const std::vector<voroclip::bench::Best> best = voroclip::bench::best_times(
      runs,
      {[&] { ours_timed.push_back(voroclip::mesh_domain2(domain, options)); },
       [&] { cgal_timed.push_back(run_cgal(domain, result.cgal_size, lloyd_iterations).mesh); }});
  for (const voroclip::Mesh2& mesh : ours_timed) {
    if (mesh.xy != ours.xy || mesh.triangles != ours.triangles) {
      ours_note += (ours_note.empty() ? "" : "; ") + std::string("timed run gave another mesh");
      break;
    }
  }
  bool cgal_repeats = true;
  const Measures cgal_measures = measure(domain, cgal.mesh);
  Measures lo = cgal_measures, hi = cgal_measures;
  for (const voroclip::Mesh2& mesh : cgal_timed) {
    if (mesh.xy == cgal.mesh.xy && mesh.triangles == cgal.mesh.triangles) continue;
    cgal_repeats = false;
    const Measures m = measure(domain, mesh);
    lo.nb_vertices = std::min(lo.nb_vertices, m.nb_vertices);
    hi.nb_vertices = std::max(hi.nb_vertices, m.nb_vertices);
    lo.min_angle = std::min(lo.min_angle, m.min_angle);
    hi.min_angle = std::max(hi.min_angle, m.min_angle);
    lo.mean_min_angle = std::min(lo.mean_min_angle, m.mean_min_angle);
    hi.mean_min_angle = std::max(hi.mean_min_angle, m.mean_min_angle);
  }
  if (!cgal_repeats) {
    char range[200];
    std::snprintf(range, sizeof range,
                  "; runs differ: vertices %u-%u, min angle %.2f-%.2f, mean min %.2f-%.2f",
                  lo.nb_vertices, hi.nb_vertices, lo.min_angle, hi.min_angle, lo.mean_min_angle,
                  hi.mean_min_angle);
    cgal.lloyd += range;
  }

  Row row_ours{"voroclip", measure(domain, ours), best[0], "", false};
  char text[160];
  std::snprintf(text, sizeof text, "nb_vertices %u; H %.4g; %u repair rounds", options.nb_vertices,
                stats.edge_length, stats.repair_rounds);
  row_ours.note = text + (ours_note.empty() ? "" : "; " + ours_note);
  Row row_cgal{"CGAL", cgal_measures, best[1], "", false};
  std::snprintf(text, sizeof text, "size bound %.4g", result.cgal_size);
  row_cgal.note =
      text + (cgal_note.empty() ? "" : " (" + cgal_note + ")") + "; Lloyd: " + cgal.lloyd;
  for (Row* row : {&row_ours, &row_cgal}) {
    if (!row->m.check.empty()) row->note += "; check_mesh2: " + row->m.check;
  }
  row_ours.ok = row_ours.m.nb_triangles > 0 && row_ours.m.check.empty();
  row_cgal.ok = row_cgal.m.nb_triangles > 0;
  result.rows = {row_ours, row_cgal};
  return result;
}

// ---- output

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(c));
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

void print_table_row(const std::string& name, const Row& row) {
  std::printf("| %s | %s | %u | %u | %.2f | %.2f | %.9f | %u | %.3f | %.3f | %s |\n", name.c_str(),
              row.mesher.c_str(), row.m.nb_vertices, row.m.nb_triangles, row.m.min_angle,
              row.m.mean_min_angle, row.m.coverage, row.m.nb_outside, row.seconds.wall,
              row.seconds.cpu, row.note.c_str());
  std::fflush(stdout);
}

void print_json(const std::vector<PolygonResult>& results, std::uint32_t nb_vertices, int runs,
                int threads, int lloyd_iterations) {
  std::printf(
      "{\n  \"vertices\": %u, \"runs\": %d, \"threads\": %d, \"shape_bound\": %g, "
      "\"lloyd_max_iterations\": %d,\n  \"polygons\": [",
      nb_vertices, runs, threads, kShapeBound, lloyd_iterations);
  for (std::size_t i = 0; i < results.size(); ++i) {
    const PolygonResult& r = results[i];
    std::printf(
        "%s\n    {\"polygon\": %s, \"edge_length\": %.17g, \"cgal_size_bound\": %.17g, "
        "\"nb_vertices_option\": %u, "
        "\"error\": %s, \"meshers\": [",
        i ? "," : "", json_string(r.name).c_str(), r.edge_length, r.cgal_size, r.nb_vertices_option,
        json_string(r.error).c_str());
    for (std::size_t k = 0; k < r.rows.size(); ++k) {
      const Row& row = r.rows[k];
      std::printf(
          "%s\n      {\"mesher\": %s, \"vertices\": %u, \"triangles\": %u, "
          "\"min_angle_deg\": %.17g, \"mean_min_angle_deg\": %.17g, \"coverage\": %.17g, "
          "\"triangles_outside\": %u, \"check_mesh2\": %s, \"wall_seconds\": %.6g, "
          "\"cpu_seconds\": %.6g, \"note\": %s}",
          k ? "," : "", json_string(row.mesher).c_str(), row.m.nb_vertices, row.m.nb_triangles,
          row.m.min_angle, row.m.mean_min_angle, row.m.coverage, row.m.nb_outside,
          json_string(row.m.check).c_str(), row.seconds.wall, row.seconds.cpu,
          json_string(row.note).c_str());
    }
    std::printf("]}");
  }
  std::printf("\n  ]\n}\n");
}

}  // namespace

int main(int argc, char** argv) {
  int threads = 1;
  int runs = 3;
  int lloyd_iterations = 0;
  std::uint32_t nb_vertices = 1000;
  bool json = false;
  std::vector<std::string> paths;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    const bool has_value = a + 1 < argc;
    if (arg == "--threads" && has_value) {
      threads = std::max(1, std::atoi(argv[++a]));
    } else if (arg == "--runs" && has_value) {
      runs = std::max(1, std::atoi(argv[++a]));
    } else if (arg == "--lloyd-iterations" && has_value) {
      lloyd_iterations = std::max(0, std::atoi(argv[++a]));
    } else if (arg == "--vertices" && has_value) {
      nb_vertices = static_cast<std::uint32_t>(std::max(4L, std::atol(argv[++a])));
    } else if (arg == "--polygon" && has_value) {
      paths.emplace_back(argv[++a]);
    } else if (arg == "--json") {
      json = true;
    } else {
      std::fprintf(stderr,
                   "usage: compare_mesh2 [--polygon FILE] [--vertices N] [--runs R] "
                   "[--threads T] [--lloyd-iterations I] [--json]\n");
      return 2;
    }
  }
  if (paths.empty()) {
    const std::string dir = std::string(VOROCLIP_SHARED_DATA_DIR) + "/polygons/valid";
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
      if (entry.path().extension() == ".json") paths.push_back(entry.path().string());
    }
    if (ec || paths.empty()) {
      std::fprintf(stderr, "compare_mesh2: no polygons in %s\n", dir.c_str());
      return 2;
    }
    std::sort(paths.begin(), paths.end());
  }
  const tbb::global_control control(tbb::global_control::max_allowed_parallelism,
                                    static_cast<std::size_t>(threads));

  if (!json) {
    std::printf(
        "voroclip mesh_domain2 (default options but raise_for_mean_angle off, nb_vertices "
        "matched to 10 %% of CGAL's count) against CGAL Mesh_2 (criteria %g / voroclip's edge "
        "length at %u vertices, or rescaled "
        "to voroclip's count where its small features set it; then "
        "lloyd_optimize_mesh_2), %d thread(s), best of %d; coverage = sum of triangle areas / "
        "domain area; outside = triangles whose centroid is not inside; seconds\n\n",
        kShapeBound, nb_vertices, threads, runs);
    std::printf(
        "| polygon | mesher | vertices | triangles | min angle | mean min angle | "
        "coverage | outside | wall s | CPU s | note |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
    std::fflush(stdout);
  }
  bool ok = true;
  std::vector<PolygonResult> results;
  for (const std::string& path : paths) {
    PolygonResult result;
    try {
      result = compare_polygon(path, nb_vertices, runs, lloyd_iterations);
    } catch (const std::exception& e) {
      result.name = stem(path);
      result.error = e.what();
      std::fprintf(stderr, "compare_mesh2: %s\n", e.what());
    }
    ok = ok && result.error.empty();
    for (const Row& row : result.rows) ok = ok && row.ok;
    if (!json) {
      if (!result.error.empty()) {
        std::printf("| %s | - | | | | | | | | | %s |\n", result.name.c_str(), result.error.c_str());
      }
      for (const Row& row : result.rows) print_table_row(result.name, row);
    }
    results.push_back(std::move(result));
  }
  if (json) print_json(results, nb_vertices, runs, threads, lloyd_iterations);
  return ok ? 0 : 1;
}
