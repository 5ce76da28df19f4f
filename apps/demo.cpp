#include "demo.h"

#include <chrono>
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <utility>

#include "cli.h"
#include "voroclip/core.h"

namespace voroclip::cli {
namespace {

std::array<double, 3> cube_corner(std::uint32_t k) {
  return {static_cast<double>(k & 1u), static_cast<double>((k >> 1) & 1u),
          static_cast<double>((k >> 2) & 1u)};
}

std::string corner_text(std::uint32_t k) {
  const std::array<double, 3> c = cube_corner(k);
  return "(" + format_double(c[0]) + "," + format_double(c[1]) + "," + format_double(c[2]) + ")";
}

std::string percent(std::size_t part, std::size_t whole) {
  // One decimal, rounded half up, in integer arithmetic: no locale, no printf.
  const std::size_t tenths = (part * 1000 + whole / 2) / whole;
  return std::to_string(tenths / 10) + "." + std::to_string(tenths % 10) + "%";
}

std::string milliseconds(double seconds) {
  const auto tenths = static_cast<long long>(seconds * 1e4 + 0.5);
  return std::to_string(tenths / 10) + "." + std::to_string(tenths % 10);
}

void print_report(std::ostream& out, const ClassroomResult& classroom, const CubeResult& cube,
                  const MeshDemoResult& mesh, double seconds, std::size_t threads) {
  constexpr std::size_t kPoints = ClassroomResult::kGrid * ClassroomResult::kGrid;
  out << "voroclip demo: exact predicates versus plain floating point\n\n"
      << "Classroom example (Kettner, Mehlhorn, Pion, Schirra, Yap, CGTA 2008):\n"
      << "  orient2d(p, q, r) for q = (12, 12), r = (24, 24) and the " << kPoints << " points\n"
      << "  p = (0.5 + i*u, 0.5 + j*u), u = 2^-53, 0 <= i, j < 256, all within 2^-45 of y = x\n"
      << "  naive floating point: " << classroom.naive_wrong << " wrong signs ("
      << percent(classroom.naive_wrong, kPoints) << ")\n"
      << "                        " << classroom.naive_false_zero << " zero off the line, "
      << classroom.naive_false_nonzero << " non-zero on it, " << classroom.naive_flipped
      << " of the opposite sign\n"
      << "  exact:                " << classroom.exact_counts.positive << " positive, "
      << classroom.exact_counts.zero << " zero, " << classroom.exact_counts.negative
      << " negative,\n"
      << "                        each checked against the closed form sign(p.y - p.x)\n\n"
      << "Symbolic perturbation on the unit cube (corner k = (k&1, k>>1&1, k>>2&1)):\n"
      << "  fixed positive tetrahedron: corners";
  for (const std::uint32_t k : cube.tetrahedron) out << ' ' << k << corner_text(k);
  out << "\n";
  for (const CubeTest& t : cube.tests) {
    out << "  fifth point corner " << t.corner << corner_text(t.corner) << ": insphere "
        << sign_name(t.exact) << " (cospherical), insphere_sos " << sign_name(t.sos) << "\n";
  }
  const TriangleQuality2& q = mesh.quality;
  out << "\nCVT meshing (Yan, Wang, Levy, Liu, CAD 2011) of a domain with three holes:\n"
      << "  centroidal Voronoi tessellation of " << mesh.cvt_sites
      << " sites: " << mesh.cvt.iterations << " L-BFGS iterations, |g|/|g0| = "
      << format_double(std::round(mesh.cvt.gradient_norm / mesh.cvt.initial_gradient_norm * 1e5) /
                       1e5)
      << ",\n"
      << "    " << mesh.boundary_cells << " boundary cells; cells' area "
      << format_double(std::round(mesh.cells_area * 1e9) / 1e9) << ", domain "
      << format_double(std::round(mesh.domain.area() * 1e9) / 1e9) << "\n"
      << "  CVT mesh: " << mesh.mesh.nb_vertices() << " vertices, " << mesh.mesh.nb_triangles()
      << " triangles, angles " << format_double(std::round(q.min_angle * 100) / 100) << " to "
      << format_double(std::round(q.max_angle * 100) / 100) << " degrees, mean smallest angle "
      << format_double(std::round(q.mean_min_angle * 100) / 100) << ";\n"
      << "    checked exactly: every triangle counter-clockwise and inside the domain\n";
  out << "\nTime: " << milliseconds(seconds) << " ms on " << threads
      << (threads == 1 ? " thread\n" : " threads\n");
}

}  // namespace

void SignCounts::add(Sign s) {
  if (s == Sign::positive) {
    ++positive;
  } else if (s == Sign::negative) {
    ++negative;
  } else {
    ++zero;
  }
}

ClassroomResult run_classroom_example() {
  constexpr std::size_t kGrid = ClassroomResult::kGrid;
  constexpr double kUlp = 0x1p-53;
  const double q[2] = {12, 12};
  const double r[2] = {24, 24};
  ClassroomResult result;
  result.naive.resize(kGrid * kGrid);
  result.exact.resize(kGrid * kGrid);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, kGrid),
                    [&](const tbb::blocked_range<std::size_t>& rows) {
                      for (std::size_t j = rows.begin(); j != rows.end(); ++j) {
                        for (std::size_t i = 0; i < kGrid; ++i) {
                          const double p[2] = {0.5 + static_cast<double>(i) * kUlp,
                                               0.5 + static_cast<double>(j) * kUlp};
                          result.naive[j * kGrid + i] = orient2d_fast(p, q, r);
                          result.exact[j * kGrid + i] = orient2d(p, q, r);
                        }
                      }
                    });
  for (std::size_t j = 0; j < kGrid; ++j) {
    for (std::size_t i = 0; i < kGrid; ++i) {
      const double px = 0.5 + static_cast<double>(i) * kUlp;
      const double py = 0.5 + static_cast<double>(j) * kUlp;
      const Sign expected = py > px ? Sign::positive : (py < px ? Sign::negative : Sign::zero);
      const Sign exact = result.exact[j * kGrid + i];
      const Sign naive = result.naive[j * kGrid + i];
      if (exact != expected) {
        throw Error("demo: exact orient2d returned " + std::string(sign_name(exact)) +
                    " for the classroom point i=" + std::to_string(i) + ", j=" + std::to_string(j) +
                    " whose exact sign is " + sign_name(expected));
      }
      result.exact_counts.add(exact);
      result.naive_counts.add(naive);
      if (naive != exact) {
        ++result.naive_wrong;
        if (naive == Sign::zero) {
          ++result.naive_false_zero;
        } else if (exact == Sign::zero) {
          ++result.naive_false_nonzero;
        } else {
          ++result.naive_flipped;
        }
      }
    }
  }
  return result;
}

CubeResult run_cube_example() {
  CubeResult result;
  result.tetrahedron = {0, 1, 2, 4};
  std::array<std::array<double, 3>, 8> corners;
  for (std::uint32_t k = 0; k < 8; ++k) corners[k] = cube_corner(k);
  const auto point = [&](std::uint32_t k) { return corners[k].data(); };
  std::array<std::uint32_t, 4>& t = result.tetrahedron;
  const Sign orientation = orient3d(point(t[0]), point(t[1]), point(t[2]), point(t[3]));
  if (orientation == Sign::zero) throw Error("demo: the fixed cube tetrahedron is flat");
  if (orientation == Sign::negative) std::swap(t[0], t[1]);
  for (std::uint32_t e = 0; e < 8; ++e) {
    if (e == t[0] || e == t[1] || e == t[2] || e == t[3]) continue;
    const Sign exact = insphere(point(t[0]), point(t[1]), point(t[2]), point(t[3]), point(e));
    if (exact != Sign::zero) {
      throw Error("demo: exact insphere returned " + std::string(sign_name(exact)) +
                  " for cospherical cube corners");
    }
    const Sign sos = insphere_sos(point(t[0]), point(t[1]), point(t[2]), point(t[3]), point(e),
                                  t[0], t[1], t[2], t[3], e);
    result.tests.push_back({e, exact, sos});
    result.sos_counts.add(sos);
  }
  return result;
}

void run_demo(const DemoArgs& args, const GlobalOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  check_output_path(args.svg_path);
  const ClassroomResult classroom = run_classroom_example();
  const CubeResult cube = run_cube_example();
  const MeshDemoResult mesh = run_mesh_demo();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::size_t threads =
      tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);

  if (!args.svg_path.empty()) {
    write_file_atomically(args.svg_path,
                          [&](std::ostream& out) { write_demo_svg(classroom, mesh, out); });
  }

  if (std::ostream* human = human_stream(options)) {
    print_report(*human, classroom, cube, mesh, seconds, threads);
    if (!args.svg_path.empty()) *human << "Picture written to " << args.svg_path << "\n";
  }
  if (options.stats_json) {
    nlohmann::ordered_json stats;
    stats["points"] = classroom.exact.size();
    stats["naive_wrong"] = classroom.naive_wrong;
    stats["naive_false_zero"] = classroom.naive_false_zero;
    stats["naive_false_nonzero"] = classroom.naive_false_nonzero;
    stats["naive_flipped"] = classroom.naive_flipped;
    stats["naive_positive"] = classroom.naive_counts.positive;
    stats["naive_zero"] = classroom.naive_counts.zero;
    stats["naive_negative"] = classroom.naive_counts.negative;
    stats["exact_positive"] = classroom.exact_counts.positive;
    stats["exact_zero"] = classroom.exact_counts.zero;
    stats["exact_negative"] = classroom.exact_counts.negative;
    stats["cospherical_tests"] = cube.tests.size();
    stats["sos_positive"] = cube.sos_counts.positive;
    stats["sos_negative"] = cube.sos_counts.negative;
    stats["cvt_sites"] = mesh.cvt_sites;
    stats["cvt_iterations"] = mesh.cvt.iterations;
    stats["boundary_cells"] = mesh.boundary_cells;
    stats["cells_area"] = mesh.cells_area;
    stats["domain_area"] = mesh.domain.area();
    stats["mesh_vertices"] = mesh.mesh.nb_vertices();
    stats["mesh_triangles"] = mesh.mesh.nb_triangles();
    stats["mesh_min_angle_deg"] = mesh.quality.min_angle;
    stats["mesh_mean_min_angle_deg"] = mesh.quality.mean_min_angle;
    stats["mesh_max_angle_deg"] = mesh.quality.max_angle;
    stats["threads"] = threads;
    stats["seconds"] = seconds;
    stats["svg"] =
        args.svg_path.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(args.svg_path);
    print_stats(stats, options);
  }
}

}  // namespace voroclip::cli
