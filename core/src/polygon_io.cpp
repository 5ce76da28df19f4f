// Polygonal domains as read (PolygonRings, core.h): JSON rings (the format of
// shared/data/polygons), Triangle's .poly (Shewchuk, https://www.cs.cmu.edu/~quake/
// triangle.poly.html), and two generators used by tests and benchmarks.
//
// Readers check only what the format says (numbers, counts, indices, how segments chain);
// the geometry (simple rings, nesting, hole markers) is validated exactly by Domain2
// (clip.h), which needs the predicates. Points are kept as given: repeated closing points
// and repeated consecutive points too.
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "text_lexer.h"
#include "voroclip/core.h"

namespace voroclip {

namespace {

// Decimal text that reads back as the same double (for the names of generated data).
std::string number_text(double x) {
  std::ostringstream out;
  out.imbue(std::locale::classic());
  out.precision(17);
  out << x;
  return out.str();
}

// ---------------------------------------------------------------------------------------
// JSON: an array of rings (one polygon) or an array of polygons (arrays of rings); a ring
// is an array of [x, y]. The form is recognised by the nesting depth of the first point
// found; every element is then checked against that form.

// Depth of nested first elements down to a number: 0 for a number, 1 for [x, y], 2 for a
// ring, 3 for a polygon; -1 when an empty array (or a non-array) hides it.
int nesting_depth(const nlohmann::json& j) {
  if (j.is_number()) return 0;
  if (!j.is_array()) return -1;
  for (const auto& e : j) {
    const int d = nesting_depth(e);
    if (d >= 0) return d + 1;
  }
  return -1;
}

PolygonRings read_json_polygon(std::istream& in, const std::string& path) {
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {  // a syntax error, or a number overflow
    throw Error(path + ": not valid JSON: " + e.what());
  }
  const char* expected =
      "expected a JSON array of rings (each an array of [x, y]) or an array of polygons "
      "(each an array of rings)";
  if (!doc.is_array()) throw Error(path + ": " + expected);
  const int depth = nesting_depth(doc);
  if (depth < 0) throw Error(path + ": the file holds no points");
  if (depth != 3 && depth != 4) {
    throw Error(path + ": " + expected + "; found arrays nested " + std::to_string(depth) +
                " deep");
  }
  const bool several = depth == 4;
  // Messages name rings, polygons and points by their positions in the arrays, from 0.
  const std::string numbering = several ? " (polygons, rings and points numbered from 0)"
                                        : " (rings and points numbered from 0)";

  PolygonRings out;
  out.source = path;
  out.ring_begin.push_back(0);
  const auto read_ring = [&](const nlohmann::json& ring, std::int32_t polygon,
                             const std::string& name) {
    if (!ring.is_array()) throw Error(path + ": " + name + ": not an array of points" + numbering);
    for (std::size_t p = 0; p < ring.size(); ++p) {
      const auto& point = ring[p];
      const std::string where = path + ": " + name + " point " + std::to_string(p) + ": ";
      if (!point.is_array() || point.size() != 2) {
        throw Error(where + "not an array of 2 numbers [x, y]" + numbering);
      }
      for (int k = 0; k < 2; ++k) {
        if (!point[static_cast<std::size_t>(k)].is_number()) {
          throw Error(where + (k == 0 ? "x" : "y") + " is not a number" + numbering);
        }
        const double v = point[static_cast<std::size_t>(k)].get<double>();
        if (!std::isfinite(v)) {
          throw Error(where + (k == 0 ? "x" : "y") + " is not finite" + numbering);
        }
        out.xy.push_back(v);
      }
    }
    if (out.xy.size() / 2 > UINT32_MAX) throw Error(path + ": too many points");
    out.ring_begin.push_back(static_cast<std::uint32_t>(out.xy.size() / 2));
    out.ring_polygon.push_back(polygon);
    out.ring_line.push_back(0);
  };
  if (!several) {
    for (std::size_t r = 0; r < doc.size(); ++r) {
      read_ring(doc[r], 0, "ring " + std::to_string(r));
    }
  } else {
    for (std::size_t q = 0; q < doc.size(); ++q) {
      const std::string polygon = "polygon " + std::to_string(q);
      if (!doc[q].is_array() || doc[q].empty()) {
        throw Error(path + ": " + polygon + ": not a non-empty array of rings" + numbering);
      }
      for (std::size_t r = 0; r < doc[q].size(); ++r) {
        read_ring(doc[q][r], static_cast<std::int32_t>(q), polygon + " ring " + std::to_string(r));
      }
    }
  }
  if (out.nb_rings() == 0) throw Error(path + ": the file holds no rings");
  return out;
}

// ---------------------------------------------------------------------------------------
// Triangle's .poly. The file is a sequence of sections, each a count line followed by that
// many item lines; blank lines and everything after '#' are ignored:
//   <#vertices> <dimension = 2> <#attributes> <#markers (0|1)>
//     <i> <x> <y> [attributes...] [marker]
//   <#segments> <#markers (0|1)>
//     <i> <v1> <v2> [marker]
//   <#holes>
//     <i> <x> <y>
//   [<#regions>                               (optional; attributes kept, areas ignored)
//     <i> <x> <y> <attribute> [<maximum area>]]
// Vertices are numbered from 0 or 1, as the first vertex line says, then consecutively.
// A vertex count of 0 means the vertices are in a separate .node file: not supported.

struct TextLine {
  std::uint32_t number = 0;
  std::vector<std::string> fields;
};

class PolyReader {
 public:
  PolyReader(std::istream& in, std::string path) : path_(std::move(path)) {
    std::string line;
    std::uint32_t number = 0;
    while (std::getline(in, line)) {
      ++number;
      const std::size_t hash = line.find('#');
      if (hash != std::string::npos) line.resize(hash);
      std::istringstream fields(line);
      TextLine t;
      t.number = number;
      std::string field;
      while (fields >> field) t.fields.push_back(field);
      if (!t.fields.empty()) lines_.push_back(std::move(t));
    }
    if (in.bad()) throw Error(path_ + ": read error");
    last_line_ = number;
  }

  PolygonRings read();

 private:
  [[noreturn]] void fail(std::uint32_t line, const std::string& what) const {
    throw Error(path_ + ":" + std::to_string(line) + ": " + what);
  }

  bool at_end() const { return next_ == lines_.size(); }

  // The next non-blank line, with between min_fields and max_fields fields.
  const TextLine& take(const std::string& expected, std::size_t min_fields,
                       std::size_t max_fields) {
    if (at_end()) fail(last_line_, "unexpected end of file: expected " + expected);
    const TextLine& t = lines_[next_++];
    if (t.fields.size() < min_fields || t.fields.size() > max_fields) {
      std::string count = std::to_string(min_fields);
      if (max_fields != min_fields) count += " to " + std::to_string(max_fields);
      fail(t.number, "expected " + expected + " (" + count + " fields), found " +
                         std::to_string(t.fields.size()) + " fields");
    }
    return t;
  }

  double number(const TextLine& t, std::size_t k, const char* what) const {
    const std::string& s = t.fields[k];
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (end != s.c_str() + s.size()) {
      fail(t.number, std::string(what) + " '" + s + "' is not a number");
    }
    if (!std::isfinite(v)) {
      fail(t.number, std::string(what) + " '" + s + "' is not a finite number");
    }
    return v;
  }

  long long integer(const TextLine& t, std::size_t k, const char* what, long long lo,
                    long long hi) const {
    const std::string& s = t.fields[k];
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(s.c_str(), &end, 10);
    if (end != s.c_str() + s.size() || s.empty()) {
      fail(t.number, std::string(what) + " '" + s + "' is not an integer");
    }
    if (errno == ERANGE || v < lo || v > hi) {
      fail(t.number, std::string(what) + " " + s + " is out of range (" + std::to_string(lo) +
                         " to " + std::to_string(hi) + ")");
    }
    return v;
  }

  std::string path_;
  std::vector<TextLine> lines_;
  std::size_t next_ = 0;
  std::uint32_t last_line_ = 0;
};

PolygonRings PolyReader::read() {
  constexpr long long kMaxCount = INT32_MAX;
  PolygonRings out;
  out.source = path_;
  out.ring_begin.push_back(0);

  // Vertices.
  const TextLine& header =
      take("the vertex header '<#vertices> <dimension> <#attributes> <#markers>'", 1, 4);
  const long long nb_vertices = integer(header, 0, "the vertex count", 0, kMaxCount);
  if (nb_vertices == 0) {
    fail(header.number,
         "the vertex count is 0: the vertices are in a separate .node file, which is not "
         "supported; put them in the .poly file");
  }
  if (header.fields.size() > 1 && integer(header, 1, "the dimension", 0, kMaxCount) != 2) {
    fail(header.number, "the dimension is " + header.fields[1] + "; only 2 is supported");
  }
  const long long nb_attributes =
      header.fields.size() > 2 ? integer(header, 2, "the attribute count", 0, 1 << 20) : 0;
  const long long nb_vertex_markers =
      header.fields.size() > 3 ? integer(header, 3, "the boundary marker count", 0, 1) : 0;
  // Counts are not trusted for allocation: a truncated file must fail by its message.
  std::vector<double> vertex_xy;
  long long base = 0;
  for (long long k = 0; k < nb_vertices; ++k) {
    const TextLine& t =
        take("vertex line " + std::to_string(k + 1) + " of " + std::to_string(nb_vertices) +
                 ": '<i> <x> <y> [attributes] [marker]'",
             3, static_cast<std::size_t>(3 + nb_attributes + nb_vertex_markers));
    const long long id = integer(t, 0, "the vertex number", 0, kMaxCount);
    if (k == 0) {
      if (id > 1) {
        fail(t.number,
             "the first vertex is numbered " + t.fields[0] + "; vertices are numbered from 0 or 1");
      }
      base = id;
    } else if (id != base + k) {
      fail(t.number, "vertex numbered " + t.fields[0] + ", expected " + std::to_string(base + k) +
                         " (vertices are numbered consecutively)");
    }
    vertex_xy.push_back(number(t, 1, "x"));
    vertex_xy.push_back(number(t, 2, "y"));
    for (std::size_t f = 3; f < t.fields.size(); ++f) number(t, f, "the attribute or marker");
  }

  // Segments: every vertex they use must end exactly two of them (closed rings).
  const TextLine& seg_header = take("the segment header '<#segments> <#markers>'", 1, 2);
  const long long nb_segments = integer(seg_header, 0, "the segment count", 0, kMaxCount);
  const long long nb_segment_markers =
      seg_header.fields.size() > 1 ? integer(seg_header, 1, "the boundary marker count", 0, 1) : 0;
  const auto nv = static_cast<std::size_t>(nb_vertices);
  const auto ns = static_cast<std::size_t>(nb_segments);
  constexpr std::uint32_t kNone = UINT32_MAX;
  std::vector<std::uint32_t> seg_end, seg_line;
  std::vector<std::int64_t> seg_number;
  std::vector<std::int32_t> seg_marker;
  std::vector<std::uint32_t> incident(2 * nv, kNone);  // the (at most) two segments of a vertex
  std::vector<std::uint8_t> degree(nv, 0);
  const auto vertex_name = [base](std::size_t v) {
    return std::to_string(static_cast<long long>(v) + base);
  };
  for (std::size_t s = 0; s < ns; ++s) {
    const TextLine& t = take("segment line " + std::to_string(s + 1) + " of " +
                                 std::to_string(nb_segments) + ": '<i> <v1> <v2> [marker]'",
                             3, static_cast<std::size_t>(3 + nb_segment_markers));
    seg_number.push_back(integer(t, 0, "the segment number", 0, kMaxCount));
    seg_line.push_back(t.number);
    seg_end.resize(2 * s + 2);
    for (int k = 0; k < 2; ++k) {
      const long long id =
          integer(t, static_cast<std::size_t>(1 + k), "the endpoint", INT64_MIN / 2, INT64_MAX / 2);
      if (id < base || id >= base + nb_vertices) {
        fail(t.number, "segment endpoint " + t.fields[static_cast<std::size_t>(1 + k)] +
                           " is not a vertex (vertices are numbered " + std::to_string(base) +
                           " to " + std::to_string(base + nb_vertices - 1) + ")");
      }
      seg_end[2 * s + static_cast<std::size_t>(k)] = static_cast<std::uint32_t>(id - base);
    }
    seg_marker.push_back(
        t.fields.size() > 3
            ? static_cast<std::int32_t>(integer(t, 3, "the boundary marker", INT32_MIN, INT32_MAX))
            : 0);
    if (seg_end[2 * s] == seg_end[2 * s + 1]) {
      fail(t.number, "the segment joins vertex " + t.fields[1] + " to itself");
    }
    for (int k = 0; k < 2; ++k) {
      const std::uint32_t v = seg_end[2 * s + static_cast<std::size_t>(k)];
      if (degree[v] == 2) {
        fail(t.number, "vertex " + vertex_name(v) +
                           " ends a third segment (the others are on lines " +
                           std::to_string(seg_line[incident[2 * v]]) + " and " +
                           std::to_string(seg_line[incident[2 * v + 1]]) +
                           "); every vertex used by segments must end exactly two, so that "
                           "they form closed rings");
      }
      incident[2 * v + degree[v]++] = static_cast<std::uint32_t>(s);
    }
  }
  for (std::size_t s = 0; s < ns; ++s) {
    for (int k = 0; k < 2; ++k) {
      const std::uint32_t v = seg_end[2 * s + static_cast<std::size_t>(k)];
      if (degree[v] == 1) {
        fail(seg_line[s], "vertex " + vertex_name(v) +
                              " ends only this segment; every vertex used by segments must end "
                              "exactly two, so that they form closed rings");
      }
    }
  }

  // Holes.
  const TextLine& hole_header = take("the hole count '<#holes>'", 1, 1);
  const long long nb_holes = integer(hole_header, 0, "the hole count", 0, kMaxCount);
  for (long long k = 0; k < nb_holes; ++k) {
    const TextLine& t = take("hole line " + std::to_string(k + 1) + " of " +
                                 std::to_string(nb_holes) + ": '<i> <x> <y>'",
                             3, 3);
    out.hole_number.push_back(integer(t, 0, "the hole number", 0, kMaxCount));
    out.hole_points.push_back(number(t, 1, "x"));
    out.hole_points.push_back(number(t, 2, "y"));
    out.hole_line.push_back(t.number);
  }

  // Optional regional attributes (kept) and area constraints (checked, then ignored).
  if (!at_end()) {
    const TextLine& region_header = take("the region count '<#regions>'", 1, 1);
    const long long nb_regions = integer(region_header, 0, "the region count", 0, kMaxCount);
    for (long long k = 0; k < nb_regions; ++k) {
      const TextLine& t =
          take("region line " + std::to_string(k + 1) + " of " + std::to_string(nb_regions) +
                   ": '<i> <x> <y> <attribute> [<maximum area>]'",
               4, 5);
      out.region_number.push_back(integer(t, 0, "the region number", 0, kMaxCount));
      out.region_line.push_back(t.number);
      for (std::size_t f = 1; f < t.fields.size(); ++f) number(t, f, "the region value");
      out.region_points.push_back(number(t, 1, "x"));
      out.region_points.push_back(number(t, 2, "y"));
      out.region_attributes.push_back(number(t, 3, "the regional attribute"));
    }
    if (!at_end()) {
      fail(lines_[next_].number, "unexpected data after the last section (regions)");
    }
  }

  // Chain the segments into rings, each starting at the first unused segment in file order
  // and running in that segment's direction.
  if (ns == 0) fail(seg_header.number, "the file has no segments, hence no boundary");
  std::vector<std::uint8_t> used(ns, 0);
  for (std::size_t first = 0; first < ns; ++first) {
    if (used[first]) continue;
    std::size_t s = first;
    std::uint32_t v = seg_end[2 * s];
    do {
      used[s] = 1;
      out.xy.push_back(vertex_xy[2 * std::size_t{v}]);
      out.xy.push_back(vertex_xy[2 * std::size_t{v} + 1]);
      out.point_number.push_back(static_cast<std::uint32_t>(v + base));
      if (nb_segment_markers > 0) out.segment_marker.push_back(seg_marker[s]);
      out.segment_number.push_back(seg_number[s]);
      out.segment_line.push_back(seg_line[s]);
      const std::uint32_t w = seg_end[2 * s] == v ? seg_end[2 * s + 1] : seg_end[2 * s];
      s = incident[2 * w] == s ? incident[2 * w + 1] : incident[2 * w];
      v = w;
    } while (s != first);
    out.ring_begin.push_back(static_cast<std::uint32_t>(out.xy.size() / 2));
    out.ring_polygon.push_back(-1);
    out.ring_line.push_back(seg_line[first]);
  }
  out.holes_need_markers = true;
  return out;
}

}  // namespace

PolygonRings read_polygon(std::istream& in, const std::string& name) {
  const std::string ext = detail::input_extension_of(name);
  const bool json = ext == ".json";
  if (!json && ext != ".poly") {
    detail::check_not_gzip_name(name);
    throw Error(name + ": unknown polygon format: expected a .json or a .poly file");
  }
  std::string text = detail::read_whole_stream(in, name);
  detail::prepare_input(name, text);
  std::istringstream stream(text);
  if (json) return read_json_polygon(stream, name);
  return PolyReader(stream, name).read();
}

PolygonRings read_polygon(const std::string& path) {
  detail::check_not_directory(path);
  const std::string ext = detail::input_extension_of(path);
  if (ext != ".json" && ext != ".poly") {
    detail::check_not_gzip_name(path);
    throw Error(path + ": unknown polygon format: expected a .json or a .poly file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open the file");
  return read_polygon(in, path);
}

// ---------------------------------------------------------------------------------------
// Generators. Both emit the outer ring counter-clockwise and the holes clockwise, as one
// polygon (ring 0 outer): already in Domain2's orientation.

PolygonRings annulus_rings(double r_inner, double r_outer, std::uint32_t segments) {
  if (!(std::isfinite(r_inner) && std::isfinite(r_outer) && 0 < r_inner && r_inner < r_outer)) {
    throw Error("annulus_rings: need 0 < r_inner < r_outer, finite; got r_inner = " +
                number_text(r_inner) + ", r_outer = " + number_text(r_outer));
  }
  if (segments < 3) {
    throw Error("annulus_rings: need at least 3 segments per circle, got " +
                std::to_string(segments));
  }
  PolygonRings out;
  out.source = "annulus(" + number_text(r_inner) + ", " + number_text(r_outer) + ", " +
               std::to_string(segments) + ")";
  constexpr double kTwoPi = 6.283185307179586476925286766559;
  const auto circle = [&](double r, bool clockwise) {
    for (std::uint32_t k = 0; k < segments; ++k) {
      const double t = kTwoPi * static_cast<double>(k) / static_cast<double>(segments);
      out.xy.push_back(r * std::cos(t));
      out.xy.push_back(clockwise ? -r * std::sin(t) : r * std::sin(t));
    }
    out.ring_begin.push_back(static_cast<std::uint32_t>(out.xy.size() / 2));
    out.ring_polygon.push_back(0);
    out.ring_line.push_back(0);
  };
  out.ring_begin.push_back(0);
  circle(r_outer, false);
  circle(r_inner, true);
  return out;
}

PolygonRings square_with_holes(std::uint32_t k, double hole_fraction) {
  if (!(0 < hole_fraction && hole_fraction < 1)) {
    throw Error("square_with_holes: need 0 < hole_fraction < 1, got " + number_text(hole_fraction));
  }
  if (k > 4096) throw Error("square_with_holes: k = " + std::to_string(k) + " is above 4096");
  PolygonRings out;
  out.source = "square_with_holes(" + std::to_string(k) + ", " + number_text(hole_fraction) + ")";
  const auto ring = [&out](double x0, double y0, double x1, double y1, bool clockwise) {
    const double corners[8] = {x0, y0, x1, y0, x1, y1, x0, y1};
    for (int c = 0; c < 4; ++c) {
      const int i = clockwise ? (4 - c) % 4 : c;
      out.xy.push_back(corners[2 * i]);
      out.xy.push_back(corners[2 * i + 1]);
    }
    out.ring_begin.push_back(static_cast<std::uint32_t>(out.xy.size() / 2));
    out.ring_polygon.push_back(0);
    out.ring_line.push_back(0);
  };
  out.ring_begin.push_back(0);
  ring(0, 0, 1, 1, false);
  const double kd = static_cast<double>(k);
  const double half = 0.5 * hole_fraction;
  for (std::uint32_t j = 0; j < k; ++j) {
    for (std::uint32_t i = 0; i < k; ++i) {
      const double cx = static_cast<double>(i) + 0.5, cy = static_cast<double>(j) + 0.5;
      ring((cx - half) / kd, (cy - half) / kd, (cx + half) / kd, (cy + half) / kd, true);
    }
  }
  return out;
}

}  // namespace voroclip
