// voroclip check-surface: validates a closed surface as a 3D domain (Surface3: closed,
// oriented, manifold, no self-intersection, shells nested and oriented) and reports its
// shells, their genus, area and volume. Also the loading of 3D domains for clip3d and mesh3d.
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <system_error>

#include "cli.h"
#include "voroclip/clip.h"
#include "voroclip/core.h"

namespace voroclip::cli {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

void note_reoriented(const Domain3& domain, const GlobalOptions& options) {
  std::ostream* out = human_stream(options);
  if (!out) return;
  const std::vector<Surface3::Shell>& shells = domain.surface().shells();
  for (std::size_t s = 0; s < shells.size(); ++s) {
    if (!shells[s].reoriented) continue;
    *out << "note: " << domain.source() << ": shell " << s << " ("
         << count_of(shells[s].nb_triangles, "triangle") << ", the first "
         << domain.surface().triangle_name(shells[s].first_triangle)
         << ") was inside out and has been reoriented (--reorient)\n";
  }
}

// Curved (second-order or higher) elements, read as straight ones on their corners.
void note_higher_order(const Domain3& domain, const GlobalOptions& options) {
  std::ostream* out = human_stream(options);
  const std::uint64_t tets = domain.nb_higher_order_tets();
  const std::uint64_t triangles = domain.nb_higher_order_triangles();
  if (!out || tets + triangles == 0) return;
  *out << "note: " << domain.source() << ": "
       << (tets > 0 ? count_of(tets, "tetrahedron", "tetrahedra") : std::string())
       << (tets > 0 && triangles > 0 ? " and " : "")
       << (triangles > 0 ? count_of(triangles, "triangle") : std::string())
       << " of second order or higher read by " << (tets + triangles == 1 ? "its" : "their")
       << " corners: the domain is made of straight tets on those corners (the mid-edge and "
          "other nodes are not used)\n";
}

}  // namespace

Domain3 load_domain3(const std::string& path, bool reorient, const GlobalOptions& options) {
  Surface3Options so;
  so.reorient = reorient;
  // Before read_domain3 looks at the extension: `dir` is a directory, not a file with
  // no extension.
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw Error(path + ": is a directory, not a file");
  Domain3 domain = read_domain3(path, so);
  note_reoriented(domain, options);
  note_higher_order(domain, options);
  return domain;
}

void run_check_surface(const CheckSurfaceArgs& args, const GlobalOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  const bool tets = [&] {
    const std::string ext = input_extension(args.path);
    return ext == ".mesh" || ext == ".node" || ext == ".ele" || ext == ".msh" || ext == ".vtk" ||
           ext == ".vtu";
  }();
  // Read, then validate. Any defect, in the file or in the surface, is a verdict: with
  // --stats json the JSON says ok and valid false, the error and the seconds spent, then the
  // error line and exit status 1.
  const auto invalid = [&](const Error& e, double t_read, double t_validate) {
    if (options.stats_json) {
      print_failure_stats(
          options.command, e.what(),
          {{"valid", false}, {"seconds", {{"read", t_read}, {"validate", t_validate}}}});
    }
    throw e;
  };
  TriangleSurface input;
  TetMeshInput mesh;
  try {
    if (tets) {
      mesh = read_tet_mesh(args.path);
    } else {
      input = read_surface(args.path);
    }
  } catch (const Error& e) {
    invalid(e, seconds_since(t0), 0);
  }
  const double t_read = seconds_since(t0);
  const auto t1 = std::chrono::steady_clock::now();
  Domain3 domain;
  try {
    Surface3Options so;
    so.reorient = args.reorient;
    domain = tets ? Domain3(mesh) : Domain3(input, so);
  } catch (const Error& e) {
    invalid(e, t_read, seconds_since(t1));
  }
  const double t_validate = seconds_since(t1);
  note_reoriented(domain, options);
  const Surface3& s = domain.surface();
  std::uint32_t used = 0;
  {
    std::vector<std::uint8_t> seen(s.nb_vertices(), 0);
    for (const std::uint32_t v : s.triangles()) {
      used += seen[v] == 0 ? 1 : 0;
      seen[v] = 1;
    }
  }
  if (options.stats_json) {
    nlohmann::json shells = nlohmann::json::array();
    for (const Surface3::Shell& sh : s.shells()) {
      shells.push_back(
          {{"triangles", sh.nb_triangles},
           {"vertices", sh.nb_vertices},
           {"edges", sh.nb_edges},
           {"genus", sh.genus},
           {"euler_characteristic", std::int64_t{sh.nb_vertices} - std::int64_t{sh.nb_edges} +
                                        std::int64_t{sh.nb_triangles}},
           {"depth", sh.depth},
           {"parent",
            sh.parent == Surface3::kNone ? nlohmann::json(nullptr) : nlohmann::json(sh.parent)},
           {"role", sh.cavity() ? "cavity" : "outer"},
           {"area", sh.area},
           {"volume", sh.volume},
           {"reoriented", sh.reoriented}});
    }
    print_stats(nlohmann::json{{"valid", true},
                               {"source", s.source()},
                               {"vertices", s.nb_vertices()},
                               {"used_vertices", used},
                               {"welded_vertices", s.nb_welded_vertices()},
                               {"triangles", s.nb_triangles()},
                               {"shells", std::move(shells)},
                               {"area", s.area()},
                               {"volume", s.volume()},
                               {"bbox_min", {s.bbox_lo()[0], s.bbox_lo()[1], s.bbox_lo()[2]}},
                               {"bbox_max", {s.bbox_hi()[0], s.bbox_hi()[1], s.bbox_hi()[2]}},
                               {"seconds", {{"read", t_read}, {"validate", t_validate}}}},
                options);
  }
  if (std::ostream* out = human_stream(options)) {
    *out << s.source() << ": a valid closed surface: " << count_of(s.nb_triangles(), "triangle")
         << ", " << count_of(used, "vertex", "vertices");
    if (s.nb_welded_vertices() > 0) {
      *out << " (" << s.nb_welded_vertices() << " duplicates welded)";
    }
    *out << ", " << s.shells().size() << (s.shells().size() == 1 ? " shell" : " shells") << '\n';
    for (std::size_t k = 0; k < s.shells().size(); ++k) {
      const Surface3::Shell& sh = s.shells()[k];
      *out << "  shell " << k << ": " << count_of(sh.nb_triangles, "triangle") << ", "
           << count_of(sh.nb_vertices, "vertex", "vertices") << ", genus " << sh.genus << ", "
           << (sh.cavity() ? "a cavity in shell " + std::to_string(sh.parent)
               : sh.parent == Surface3::kNone
                   ? std::string("outer boundary")
                   : "outer boundary of a part inside shell " + std::to_string(sh.parent))
           << ", area " << format_double(sh.area) << ", volume " << format_double(sh.volume)
           << '\n';
    }
    *out << "volume " << format_double(s.volume()) << ", area " << format_double(s.area())
         << "; read in " << format_double(t_read) << " s, validated in "
         << format_double(t_validate) << " s\n";
  }
}

}  // namespace voroclip::cli
