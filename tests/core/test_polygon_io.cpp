// Tests of the polygon readers and generators (voroclip/core.h: read_polygon, annulus_rings,
// square_with_holes). Readers keep points as given; the geometry is Domain2's business
// (tests/clip/test_domain2.cpp).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "voroclip/core.h"

using voroclip::PolygonRings;

namespace {

const std::string kPolygons = std::string(VOROCLIP_SHARED_DATA_DIR) + "/polygons/";

std::string write_temp(const std::string& name, const std::string& content) {
  std::ofstream(name) << content;
  return name;
}

std::string error_of(const std::string& path) {
  try {
    voroclip::read_polygon(path);
  } catch (const voroclip::Error& e) {
    return e.what();
  }
  return "";
}

// Every reader result has this shape.
void check_shape(const PolygonRings& r) {
  REQUIRE(r.xy.size() % 2 == 0);
  REQUIRE(!r.ring_begin.empty());
  REQUIRE(r.ring_begin.front() == 0);
  REQUIRE(r.ring_begin.back() == r.xy.size() / 2);
  for (std::uint32_t k = 0; k < r.nb_rings(); ++k) REQUIRE(r.ring_begin[k] <= r.ring_begin[k + 1]);
  REQUIRE(r.ring_polygon.size() == r.nb_rings());
  REQUIRE(r.ring_line.size() == r.nb_rings());
  REQUIRE((r.point_number.empty() || r.point_number.size() == r.xy.size() / 2));
  REQUIRE(r.hole_line.size() * 2 == (r.hole_line.empty() ? 0 : r.hole_points.size()));
  for (const double x : r.xy) REQUIRE(std::isfinite(x));
}

std::vector<double> ring_points(const PolygonRings& r, std::uint32_t k) {
  return {r.xy.begin() + 2 * r.ring_begin[k], r.xy.begin() + 2 * r.ring_begin[k + 1]};
}

}  // namespace

// ---------------------------------------------------------------------------------------
// JSON

TEST_CASE("read_polygon reads every shared polygon as given", "[core]") {
  // ring counts, and points as in the file (the closing repeats and duplicates included).
  struct Expected {
    const char* file;
    std::uint32_t rings;
  };
  const Expected files[] = {
      {"valid/building.json", 1},     {"valid/dude.json", 3},       {"valid/earcut.json", 7},
      {"valid/eberly-6.json", 16},    {"valid/hilbert.json", 1},    {"valid/issue29.json", 2},
      {"valid/issue34.json", 8},      {"valid/issue35.json", 30},   {"valid/issue52.json", 6},
      {"degenerate/steiner.json", 5}, {"degenerate/water.json", 10}};
  for (const Expected& f : files) {
    INFO(f.file);
    const PolygonRings r = voroclip::read_polygon(kPolygons + f.file);
    check_shape(r);
    CHECK(r.source == kPolygons + f.file);
    CHECK(r.nb_rings() == f.rings);
    for (const std::int32_t q : r.ring_polygon) CHECK(q == 0);
    for (const std::uint32_t l : r.ring_line) CHECK(l == 0);
    CHECK(r.hole_points.empty());
    CHECK(r.point_number.empty());
  }
  // building.json, literally.
  const PolygonRings b = voroclip::read_polygon(kPolygons + "valid/building.json");
  REQUIRE(b.xy.size() == 30);
  CHECK(b.xy[0] == 661);
  CHECK(b.xy[1] == 112);
  CHECK(b.xy[28] == 666);
  CHECK(b.xy[29] == 112);
  // steiner.json: one-point rings are read as they are (Domain2 rejects them).
  const PolygonRings s = voroclip::read_polygon(kPolygons + "degenerate/steiner.json");
  CHECK(ring_points(s, 1) == std::vector<double>{50, 50});
}

TEST_CASE("read_polygon keeps closing and repeated points", "[core]") {
  const auto p = write_temp(
      "poly_repeat.json", "[[[0,0],[1,0],[1,0],[1,1],[0,0]], [[0.25,0.25],[0.5,0.5],[0.5,0.25]]]");
  const PolygonRings r = voroclip::read_polygon(p);
  check_shape(r);
  REQUIRE(r.nb_rings() == 2);
  CHECK(ring_points(r, 0) == std::vector<double>{0, 0, 1, 0, 1, 0, 1, 1, 0, 0});
  CHECK(ring_points(r, 1) == std::vector<double>{0.25, 0.25, 0.5, 0.5, 0.5, 0.25});
  CHECK(r.ring_polygon == std::vector<std::int32_t>{0, 0});
  std::remove(p.c_str());
}

TEST_CASE("read_polygon reads an array of polygons", "[core]") {
  // Depth is found past empty arrays; ring_polygon numbers the polygons.
  const auto p = write_temp("poly_multi.json",
                            "[ [[[0,0],[4,0],[4,4],[0,4]], [[1,1],[1,2],[2,2]]],\n"
                            "  [[[10,0],[12,0],[11,1]]] ]");
  const PolygonRings r = voroclip::read_polygon(p);
  check_shape(r);
  REQUIRE(r.nb_rings() == 3);
  CHECK(r.ring_polygon == std::vector<std::int32_t>{0, 0, 1});
  CHECK(r.ring_begin == std::vector<std::uint32_t>{0, 4, 7, 10});
  CHECK(ring_points(r, 2) == std::vector<double>{10, 0, 12, 0, 11, 1});
  // An empty first ring does not hide the depth.
  const auto q = write_temp("poly_empty_first.json", "[[], [[0,0],[1,0],[0,1]]]");
  const PolygonRings e = voroclip::read_polygon(q);
  CHECK(e.nb_rings() == 2);
  CHECK(e.ring_begin == std::vector<std::uint32_t>{0, 0, 3});
  std::remove(p.c_str());
  std::remove(q.c_str());
}

TEST_CASE("read_polygon names the JSON ring, point and defect", "[core]") {
  CHECK(error_of("no_such_polygon.json") == "no_such_polygon.json: cannot open the file");
  CHECK(error_of("polygon.txt").find("polygon.txt: unknown polygon format") == 0);
  struct Case {
    const char* name;
    const char* content;
    const char* message;  // after "<file>: "
  };
  const Case cases[] = {
      {"pj_bad1.json", "[[[0,0],[1,0],[1]]]",
       "ring 0 point 2: not an array of 2 numbers [x, y]"
       " (rings and points numbered from 0)"},
      {"pj_bad2.json", "[[[0,0],[1,0],[1,1]], [[0,0],[1,\"a\"]]]",
       "ring 1 point 1: y is not a number (rings and points numbered from 0)"},
      {"pj_bad3.json", "[[[[0,0],[1,0],[1,1]]], [[[0,0],[1,0],[1,1,2]]]]",
       "polygon 1 ring 0 point 2: not an array of 2 numbers [x, y]"
       " (polygons, rings and points numbered from 0)"},
      {"pj_bad4.json", "[[[[0,0],[1,0],[1,1]]], []]",
       "polygon 1: not a non-empty array of rings"
       " (polygons, rings and points numbered from 0)"},
      {"pj_bad5.json", "[[0,0],[1,0]]",
       "expected a JSON array of rings (each an array of [x, y]) or an array of polygons (each an "
       "array of rings); found arrays nested 2 deep"},
      {"pj_bad6.json", "[[], []]", "the file holds no points"},
      {"pj_bad7.json", "{\"rings\": []}",
       "expected a JSON array of rings (each an array of [x, y]) or an array of polygons (each an "
       "array of rings)"},
      {"pj_bad8.json", "[[[0,0],[1,0],[1e999,1]]]",
       "ring 0 point 2: x is not finite (rings and points numbered from 0)"},
  };
  for (const Case& c : cases) {
    const auto p = write_temp(c.name, c.content);
    const std::string e = error_of(p);
    INFO(e);
    // 1e999 may be refused by the JSON parser itself, also naming the file.
    if (std::string(c.name) == "pj_bad8.json" && e.find(p + ": not valid JSON") == 0) {
      std::remove(p.c_str());
      continue;
    }
    CHECK(e == p + ": " + c.message);
    std::remove(p.c_str());
  }
  const auto p = write_temp("pj_bad9.json", "[[[0,0],[1,0],[1,1]]");
  CHECK(error_of(p).find(p + ": not valid JSON") == 0);
  std::remove(p.c_str());
}

// ---------------------------------------------------------------------------------------
// Triangle .poly

TEST_CASE("read_polygon reads Triangle .poly files", "[core]") {
  // A square with a square hole, 1-based, with comments, blank lines, attributes, markers,
  // an unused vertex, segments out of ring order, and the optional region section.
  const auto p = write_temp("poly_ok.poly",
                            "# square with a hole\n"
                            "9 2 1 1   # vertices\n"
                            "1 0 0 0.5 1\n"
                            "2 4 0 0.5 1\n"
                            "3 4 4 0.5 1\n"
                            "4 0 4 0.5 1\n"
                            "\n"
                            "5 1 1 0 0\n"
                            "6 3 1 0 0\n"
                            "7 3 3 0 0\n"
                            "8 1 3 0 0\n"
                            "9 7 7 0 0   # not used by any segment\n"
                            "8 1\n"
                            "1 1 2 1\n"
                            "2 3 4 1\n"
                            "3 5 6 0\n"
                            "4 2 3 1\n"
                            "5 7 8 0\n"
                            "6 4 1 1\n"
                            "7 8 5 0\n"
                            "8 6 7 0\n"
                            "1\n"
                            "1 2 2\n"
                            "1\n"
                            "1 0.5 0.5 3 0.1\n");
  const PolygonRings r = voroclip::read_polygon(p);
  check_shape(r);
  REQUIRE(r.nb_rings() == 2);
  // Rings start at the first unused segment in file order and follow its direction.
  CHECK(ring_points(r, 0) == std::vector<double>{0, 0, 4, 0, 4, 4, 0, 4});
  CHECK(ring_points(r, 1) == std::vector<double>{1, 1, 3, 1, 3, 3, 1, 3});
  CHECK(r.point_number == std::vector<std::uint32_t>{1, 2, 3, 4, 5, 6, 7, 8});
  CHECK(r.ring_polygon == std::vector<std::int32_t>{-1, -1});
  CHECK(r.ring_line == std::vector<std::uint32_t>{14, 16});
  CHECK(r.hole_points == std::vector<double>{2, 2});
  CHECK(r.hole_line == std::vector<std::uint32_t>{23});
  // The items' own numbers and lines, for messages: per point the segment from it.
  CHECK(r.segment_marker == std::vector<std::int32_t>{1, 1, 1, 1, 0, 0, 0, 0});
  CHECK(r.segment_number == std::vector<std::int64_t>{1, 4, 2, 6, 3, 8, 5, 7});
  CHECK(r.segment_line == std::vector<std::uint32_t>{14, 17, 15, 19, 16, 21, 18, 20});
  CHECK(r.hole_number == std::vector<std::int64_t>{1});
  CHECK(r.region_points == std::vector<double>{0.5, 0.5});
  CHECK(r.region_attributes == std::vector<double>{3});
  CHECK(r.region_number == std::vector<std::int64_t>{1});
  CHECK(r.region_line == std::vector<std::uint32_t>{25});
  std::remove(p.c_str());
}

TEST_CASE("read_polygon reads 0-based .poly files and minimal headers", "[core]") {
  const auto p =
      write_temp("poly_zero.poly", "3\n0 0 0\n1 1 0\n2 0.5 1\n3\n0 2 1\n1 1 0\n2 0 2\n0\n");
  const PolygonRings r = voroclip::read_polygon(p);
  check_shape(r);
  REQUIRE(r.nb_rings() == 1);
  // First segment 2 -> 1, then 1 -> 0, then 0 -> 2.
  CHECK(ring_points(r, 0) == std::vector<double>{0.5, 1, 1, 0, 0, 0});
  CHECK(r.point_number == std::vector<std::uint32_t>{2, 1, 0});
  CHECK(r.hole_points.empty());
  std::remove(p.c_str());
}

TEST_CASE("read_polygon names the .poly line and the defect", "[core]") {
  const std::string tri = "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n";
  struct Case {
    const char* name;
    std::string content;
    const char* message;  // after "<file>:"
  };
  const Case cases[] = {
      {"pp_node.poly", "0 2 0 1\n3 1\n1 1 2\n2 2 3\n3 3 1\n0\n",
       "1: the vertex count is 0: the vertices are in a separate .node file, which is not "
       "supported; put them in the .poly file"},
      {"pp_dim.poly", "3 3 0 0\n", "1: the dimension is 3; only 2 is supported"},
      {"pp_nan.poly", "3 2 0 0\n1 0 0\n2 nan 0\n", "3: x 'nan' is not a finite number"},
      {"pp_word.poly", "3 2 0 0\n1 0 0\n2 1 zero\n", "3: y 'zero' is not a number"},
      {"pp_count.poly", "x 2 0 0\n", "1: the vertex count 'x' is not an integer"},
      {"pp_first.poly", "3 2 0 0\n5 0 0\n",
       "2: the first vertex is numbered 5; vertices are "
       "numbered from 0 or 1"},
      {"pp_order.poly", "3 2 0 0\n1 0 0\n3 1 0\n",
       "3: vertex numbered 3, expected 2 (vertices "
       "are numbered consecutively)"},
      {"pp_fields.poly", "3 2 0 0\n1 0 0 7\n",
       "2: expected vertex line 1 of 3: '<i> <x> <y> [attributes] [marker]' (3 fields), found 4 "
       "fields"},
      {"pp_trunc1.poly", "3 2 0 0\n1 0 0\n2 1 0\n",
       "3: unexpected end of file: expected vertex line 3 of 3: '<i> <x> <y> [attributes] "
       "[marker]'"},
      {"pp_trunc2.poly", tri + "3 0\n1 1 2\n2 2 3\n",
       "7: unexpected end of file: expected segment line 3 of 3: '<i> <v1> <v2> [marker]'"},
      {"pp_trunc3.poly", tri + "3 0\n1 1 2\n2 2 3\n3 3 1\n",
       "8: unexpected end of file: expected the hole count '<#holes>'"},
      {"pp_trunc4.poly", tri + "3 0\n1 1 2\n2 2 3\n3 3 1\n2\n1 0.1 0.1\n",
       "10: unexpected end of file: expected hole line 2 of 2: '<i> <x> <y>'"},
      {"pp_range.poly", tri + "3 0\n1 1 2\n2 2 4\n3 3 1\n0\n",
       "7: segment endpoint 4 is not a vertex (vertices are numbered 1 to 3)"},
      {"pp_range0.poly", tri + "3 0\n1 1 2\n2 2 0\n3 3 1\n0\n",
       "7: segment endpoint 0 is not a vertex (vertices are numbered 1 to 3)"},
      {"pp_self.poly", tri + "3 0\n1 1 2\n2 2 2\n3 3 1\n0\n",
       "7: the segment joins vertex 2 to itself"},
      {"pp_third.poly", "4 2 0 0\n1 0 0\n2 1 0\n3 0 1\n4 1 1\n4 0\n1 1 2\n2 2 3\n3 3 1\n4 1 4\n0\n",
       "10: vertex 1 ends a third segment (the others are on lines 7 and 9); every vertex used by "
       "segments must end exactly two, so that they form closed rings"},
      {"pp_open.poly", "4 2 0 0\n1 0 0\n2 1 0\n3 0 1\n4 1 1\n3 0\n1 1 2\n2 2 3\n3 3 4\n0\n",
       "7: vertex 1 ends only this segment; every vertex used by segments must end exactly two, "
       "so that they form closed rings"},
      {"pp_noseg.poly", tri + "0 0\n0\n", "5: the file has no segments, hence no boundary"},
      {"pp_marker.poly", "3 2 0 2\n", "1: the boundary marker count 2 is out of range (0 to 1)"},
      {"pp_trail.poly", tri + "3 0\n1 1 2\n2 2 3\n3 3 1\n0\n0\n5 5\n",
       "11: unexpected data after the last section (regions)"},
      {"pp_inf.poly", tri + "3 0\n1 1 2\n2 2 3\n3 3 1\n1\n1 inf 0\n",
       "10: x 'inf' is not a finite number"},
  };
  for (const Case& c : cases) {
    const auto p = write_temp(c.name, c.content);
    const std::string e = error_of(p);
    INFO(c.name << ": " << e);
    CHECK(e == p + ":" + c.message);
    std::remove(p.c_str());
  }
  CHECK(error_of("no_such_polygon.poly") == "no_such_polygon.poly: cannot open the file");
}

// ---------------------------------------------------------------------------------------
// Generators

TEST_CASE("annulus_rings: outer ring counter-clockwise, then the inner ring", "[core]") {
  const PolygonRings r = voroclip::annulus_rings(0.5, 2.0, 16);
  check_shape(r);
  CHECK(r.source == "annulus(0.5, 2, 16)");
  REQUIRE(r.nb_rings() == 2);
  CHECK(r.ring_begin == std::vector<std::uint32_t>{0, 16, 32});
  CHECK(r.ring_polygon == std::vector<std::int32_t>{0, 0});
  for (std::uint32_t k = 0; k < 32; ++k) {
    const double radius = std::hypot(r.xy[2 * k], r.xy[2 * k + 1]);
    CHECK(radius == Approx(k < 16 ? 2.0 : 0.5).epsilon(1e-15));
  }
  // Outer ring counter-clockwise (positive shoelace), inner one clockwise.
  for (std::uint32_t ring = 0; ring < 2; ++ring) {
    double a = 0;
    const std::uint32_t b = r.ring_begin[ring], e = r.ring_begin[ring + 1];
    for (std::uint32_t i = b; i < e; ++i) {
      const std::uint32_t j = i + 1 == e ? b : i + 1;
      a += r.xy[2 * i] * r.xy[2 * j + 1] - r.xy[2 * j] * r.xy[2 * i + 1];
    }
    CHECK((ring == 0 ? a > 0 : a < 0));
  }
  CHECK_THROWS_WITH(
      voroclip::annulus_rings(1, 1, 8),
      "annulus_rings: need 0 < r_inner < r_outer, finite; got r_inner = 1, r_outer = 1");
  CHECK_THROWS_WITH(voroclip::annulus_rings(0.5, 1, 2),
                    "annulus_rings: need at least 3 segments per circle, got 2");
  CHECK_THROWS_AS(voroclip::annulus_rings(0, 1, 8), voroclip::Error);
  CHECK_THROWS_AS(voroclip::annulus_rings(0.5, INFINITY, 8), voroclip::Error);
}

TEST_CASE("square_with_holes: the unit square and k x k centred square holes", "[core]") {
  const PolygonRings r = voroclip::square_with_holes(2, 0.5);
  check_shape(r);
  CHECK(r.source == "square_with_holes(2, 0.5)");
  REQUIRE(r.nb_rings() == 5);
  CHECK(ring_points(r, 0) == std::vector<double>{0, 0, 1, 0, 1, 1, 0, 1});
  // Hole (0, 0): side 0.25 centred at (0.25, 0.25), clockwise.
  CHECK(ring_points(r, 1) ==
        std::vector<double>{0.125, 0.125, 0.125, 0.375, 0.375, 0.375, 0.375, 0.125});
  // Hole (1, 1), the last one.
  CHECK(ring_points(r, 4) ==
        std::vector<double>{0.625, 0.625, 0.625, 0.875, 0.875, 0.875, 0.875, 0.625});
  CHECK(voroclip::square_with_holes(0, 0.5).nb_rings() == 1);
  CHECK_THROWS_WITH(voroclip::square_with_holes(3, 1.0),
                    "square_with_holes: need 0 < hole_fraction < 1, got 1");
  CHECK_THROWS_AS(voroclip::square_with_holes(3, 0.0), voroclip::Error);
  CHECK_THROWS_AS(voroclip::square_with_holes(3, NAN), voroclip::Error);
}
