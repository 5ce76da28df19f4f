// The meshing part of `voroclip demo` (demo.h, part 3) and the demo's composite picture.
#include <cmath>
#include <ostream>
#include <sstream>
#include <string>

#include "cli.h"
#include "demo.h"

namespace voroclip::cli {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kWidth = 1164;  // the classroom picture's width (demo_svg.cpp)
constexpr int kClassroomHeight = 712;
constexpr int kPanelWidth = 550;
constexpr int kTop = 96;

// Coordinates rounded to 1e-4, so that the domain reads back the same from any printout.
double round4(double x) { return std::round(x * 1e4) / 1e4; }

std::string fixed2(double x) {
  std::ostringstream s;
  s.imbue(std::locale::classic());
  s.setf(std::ios::fixed);
  s.precision(2);
  s << x;
  return s.str();
}

// The document without an XML declaration, to nest inside another <svg>.
std::string nested(const std::string& doc) {
  if (doc.rfind("<?xml", 0) == 0) return doc.substr(doc.find('\n') + 1);
  return doc;
}

// The `width` attribute of a document written by write_clip_svg / write_mesh_svg.
double svg_width(const std::string& doc) {
  const std::size_t at = doc.find("width=\"");
  return at == std::string::npos ? 1000 : std::stod(doc.substr(at + 7));
}

}  // namespace

PolygonRings demo_domain_rings() {
  PolygonRings p;
  p.source = "the demo domain";
  p.ring_begin.push_back(0);
  const auto close_ring = [&] {
    p.ring_begin.push_back(static_cast<std::uint32_t>(p.xy.size() / 2));
    p.ring_polygon.push_back(0);
    p.ring_line.push_back(0);
  };
  // Outline: a superellipse |x/a|^(1/0.6) + |y/b|^(1/0.6) = 1 around (5, 3.5), 80 vertices.
  for (int k = 0; k < 80; ++k) {
    const double t = 2 * kPi * k / 80;
    const double c = std::cos(t), s = std::sin(t);
    p.xy.push_back(round4(5 + 4.8 * std::copysign(std::pow(std::fabs(c), 0.6), c)));
    p.xy.push_back(round4(3.5 + 3.3 * std::copysign(std::pow(std::fabs(s), 0.6), s)));
  }
  close_ring();
  for (int k = 0; k < 28; ++k) {  // a circle
    const double t = 2 * kPi * k / 28;
    p.xy.push_back(round4(3 + 1.1 * std::cos(t)));
    p.xy.push_back(round4(3.6 + 1.1 * std::sin(t)));
  }
  close_ring();
  for (int k = 0; k < 4; ++k) {  // a square turned by 30 degrees
    const double t = kPi / 6 + kPi / 2 * k;
    p.xy.push_back(round4(6.6 + 1.05 * std::cos(t)));
    p.xy.push_back(round4(4.9 + 1.05 * std::sin(t)));
  }
  close_ring();
  p.xy.insert(p.xy.end(), {6.2, 1.3, 8.4, 1.8, 7.0, 2.9});  // a triangle
  close_ring();
  return p;
}

MeshDemoResult run_mesh_demo() {
  MeshDemoResult r;
  r.domain = Domain2(demo_domain_rings());
  // A CVT of 200 sites and its clipped Voronoi diagram.
  std::vector<double> sites = random_points2(r.domain, 200, 7);
  r.cvt_sites = 200;
  Cvt2Options co;
  co.max_iterations = 60;
  co.gradient_tolerance = 1e-3;
  r.cvt = optimize_cvt2(r.domain, sites, co);
  const Delaunay2 dt(sites.data(), r.cvt_sites);
  ClippedVoronoi2 cv;
  Clip2Options clip;
  clip.keep_geometry = true;
  cv.compute(r.domain, dt, clip);
  r.boundary_cells = cv.nb_boundary_sites();
  r.cells_area = cv.total_area();
  std::ostringstream clip_svg;
  write_clip_svg(clip_svg, r.domain, sites, cv);
  r.clip_svg = clip_svg.str();
  // The CVT mesh.
  Mesh2Options mo;
  mo.nb_vertices = 500;
  r.mesh = mesh_domain2(r.domain, mo, &r.mesh_stats);
  const std::string defect = check_mesh2(r.domain, r.mesh);
  if (!defect.empty()) throw Error("demo: the mesh is not valid: " + defect);
  r.quality = triangle_quality2(r.mesh);
  std::ostringstream mesh_svg;
  write_mesh_svg(mesh_svg, r.domain, r.mesh);
  r.mesh_svg = mesh_svg.str();
  return r;
}

void write_demo_svg(const ClassroomResult& classroom, const MeshDemoResult& mesh,
                    std::ostream& out) {
  std::ostringstream classroom_svg;
  write_classroom_svg(classroom, classroom_svg);
  const double scale = kPanelWidth / svg_width(mesh.clip_svg);
  // Panel height from the documents' aspect (both pictures have the domain's box).
  const std::size_t at = mesh.clip_svg.find("height=\"");
  const double panel_height = scale * std::stod(mesh.clip_svg.substr(at + 8));
  const int top_height = kTop + static_cast<int>(panel_height) + 40;
  const int height = top_height + kClassroomHeight;
  const int x1 = 24, x2 = kWidth - 24 - kPanelWidth;
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kWidth << "\" height=\"" << height
      << "\" viewBox=\"0 0 " << kWidth << ' ' << height
      << "\" font-family=\"DejaVu Sans, Helvetica, Arial, sans-serif\">\n"
      << "<title>voroclip demo: CVT meshing, clipped Voronoi diagram, exact predicates</title>\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>\n"
      << "<text x=\"" << kWidth / 2
      << "\" y=\"30\" text-anchor=\"middle\" font-size=\"18\" font-weight=\"bold\">"
      << "Centroidal Voronoi tessellation and CVT meshing of a domain with holes</text>\n"
      << "<text x=\"" << kWidth / 2 << "\" y=\"52\" text-anchor=\"middle\" font-size=\"13\">"
      << "Yan, Wang, L&#233;vy and Liu, &#8220;Efficient computation of clipped Voronoi diagram "
      << "for mesh generation&#8221; (CAD 2011); every decision exact</text>\n";
  const auto caption = [&](int x, const std::string& text) {
    out << "<text x=\"" << x + kPanelWidth / 2 << "\" y=\"" << kTop - 12
        << "\" text-anchor=\"middle\" font-size=\"13\">" << text << "</text>\n";
  };
  caption(x1, "Clipped Voronoi diagram of a CVT: " + std::to_string(mesh.cvt_sites) + " sites, " +
                  std::to_string(mesh.boundary_cells) + " boundary cells (warm)");
  caption(x2, "CVT mesh: " + std::to_string(mesh.mesh.nb_vertices()) + " vertices, " +
                  std::to_string(mesh.mesh.nb_triangles()) + " triangles, angles " +
                  fixed2(mesh.quality.min_angle) + "&#176;&#8211;" +
                  fixed2(mesh.quality.max_angle) + "&#176;");
  out << "<g transform=\"translate(" << x1 << ',' << kTop << ") scale(" << scale << ")\">\n"
      << nested(mesh.clip_svg) << "</g>\n"
      << "<g transform=\"translate(" << x2 << ',' << kTop << ") scale(" << scale << ")\">\n"
      << nested(mesh.mesh_svg) << "</g>\n"
      << "<text x=\"" << x2 + kPanelWidth / 2 << "\" y=\"" << kTop + panel_height + 22
      << "\" text-anchor=\"middle\" font-size=\"12\">coloured by smallest angle (red below "
      << "30&#176;, green at 60&#176;); mean smallest angle " << fixed2(mesh.quality.mean_min_angle)
      << "&#176;</text>\n"
      << "<g transform=\"translate(0," << top_height << ")\">\n"
      << nested(classroom_svg.str()) << "</g>\n</svg>\n";
}

}  // namespace voroclip::cli
