#include <catch2/catch.hpp>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "voroclip/core.h"

namespace {

std::string write_temp(const std::string& name, const std::string& content) {
  std::ofstream(name) << content;
  return name;
}

std::string error_of(const std::string& path, int dim) {
  try {
    voroclip::read_points(path, dim);
  } catch (const voroclip::Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("read_points reads text files with comments", "[core]") {
  const auto path = write_temp("pts_ok.txt", "# header\n0 1 2\n\n  3.5 -4e-3 0x1p-2 # tail\n");
  const std::vector<double> pts = voroclip::read_points(path, 3);
  CHECK(pts == std::vector<double>{0, 1, 2, 3.5, -4e-3, 0.25});
  std::remove(path.c_str());
}

TEST_CASE("read_points reads JSON arrays", "[core]") {
  const auto path = write_temp("pts_ok.json", "  [[0, 1], [2.5, -3]]");
  CHECK(voroclip::read_points(path, 2) == std::vector<double>{0, 1, 2.5, -3});
  std::remove(path.c_str());
}

TEST_CASE("read_points names the file, the line and the defect", "[core]") {
  CHECK(error_of("no_such_file.txt", 3).find("no_such_file.txt: cannot open") == 0);
  auto p = write_temp("pts_bad1.txt", "0 0 0\n1 2\n");
  CHECK(error_of(p, 3) == p + ":2: expected 3 coordinates, found 2");
  p = write_temp("pts_bad2.txt", "0 0 0\n1 2 x3\n");
  CHECK(error_of(p, 3) == p + ":2: 'x3' is not a number");
  p = write_temp("pts_bad3.txt", "0 0 0 0\n");
  CHECK(error_of(p, 3) == p + ":1: more than 3 coordinates");
  p = write_temp("pts_bad4.txt", "1 nan 0\n");
  CHECK(error_of(p, 3) == p + ":1: 'nan' is not a finite number");
  p = write_temp("pts_bad5.json", "[[0, 1], [2]]");
  CHECK(error_of(p, 2) == p + ": point 1 (from 0) is not an array of 2 numbers");
  p = write_temp("pts_bad6.json", "[[0, 1], [2, \"a\"]]");
  CHECK(error_of(p, 2) == p + ": point 1 (from 0) has a coordinate that is not a number");
  p = write_temp("pts_bad7.json", "[[0, 1], [2, 3]");
  CHECK(error_of(p, 2).find(p + ": not valid JSON") == 0);
  p = write_temp("pts_empty.txt", "   \n");
  CHECK(error_of(p, 2) == p + ": the file holds no points");
  for (const char* f : {"pts_bad1.txt", "pts_bad2.txt", "pts_bad3.txt", "pts_bad4.txt",
                        "pts_bad5.json", "pts_bad6.json", "pts_bad7.json", "pts_empty.txt"}) {
    std::remove(f);
  }
}

TEST_CASE("write_vtk writes a legacy unstructured grid", "[core]") {
  const double xyz[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  std::ostringstream out;
  voroclip::write_vtk(out, "one tet", xyz, 4, 3, {0, 1, 2, 3}, 4);
  const std::string s = out.str();
  CHECK(s.find("# vtk DataFile Version 3.0\none tet\nASCII\nDATASET UNSTRUCTURED_GRID\n") == 0);
  CHECK(s.find("POINTS 4 double\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n") != std::string::npos);
  CHECK(s.find("CELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n10\n") != std::string::npos);
}

TEST_CASE("read_points and read_polygon read streams as files", "[core]") {
  std::istringstream text("# header\n0 1 2\n3.5 -4e-3 0x1p-2\n"), json(" [[0, 1], [2.5, -3]]");
  CHECK(voroclip::read_points(text, "t.txt", 3) == std::vector<double>{0, 1, 2, 3.5, -4e-3, 0.25});
  CHECK(voroclip::read_points(json, "t.json", 2) == std::vector<double>{0, 1, 2.5, -3});
  std::istringstream bad("0 1\n2\n");
  CHECK_THROWS_WITH(voroclip::read_points(bad, "b.txt", 2),
                    "b.txt:2: expected 2 coordinates, found 1");
  std::istringstream ring("[[[0, 0], [1, 0], [0, 1]]]");
  const voroclip::PolygonRings r = voroclip::read_polygon(ring, "r.json");
  CHECK(r.source == "r.json");
  CHECK(r.xy == std::vector<double>{0, 0, 1, 0, 0, 1});
  CHECK(r.ring_begin == std::vector<std::uint32_t>{0, 3});
  std::istringstream poly("3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n3 0\n1 1 2\n2 2 3\n3 3 1\n0\n");
  CHECK(voroclip::read_polygon(poly, "p.poly").xy == std::vector<double>{0, 0, 1, 0, 0, 1});
  std::istringstream any("[]");
  CHECK_THROWS_WITH(voroclip::read_polygon(any, "p.txt"),
                    "p.txt: unknown polygon format: expected a .json or a .poly file");
}

TEST_CASE("fuzz regression: a JSON number out of the range of a double", "[core][regression]") {
  // fuzz_points: nlohmann::json reports a number overflow ('1e3080') with out_of_range,
  // not parse_error, and it escaped read_points as an exception other than voroclip::Error.
  const std::string path = std::string(VOROCLIP_SOURCE_DIR) +
                           "/tests/core/fuzz_regressions/points_json_number_overflow.json";
  for (const int dim : {2, 3}) {
    CHECK(error_of(path, dim) == path +
                                     ": not valid JSON: [json.exception.out_of_range.406] number "
                                     "overflow parsing '1e3080'");
  }
}

TEST_CASE("read_points reads back the .csv and .txt sites the CLI writes", "[core][regression]") {
  // cvt3d -o sites.csv writes an x,y,z header and commas: read_points stopped at the
  // header ("'x,y,z' is not a number") and at every comma-separated line.
  std::istringstream csv("x,y,z\n0,0,0\n0.5,0,0\n0.1,0,0.2\n");
  CHECK(voroclip::read_points(csv, "s.csv", 3) ==
        std::vector<double>{0, 0, 0, 0.5, 0, 0, 0.1, 0, 0.2});
  std::istringstream commas("0,0,0\n0.5, 0 ,0\n");
  CHECK(voroclip::read_points(commas, "c.txt", 3) == std::vector<double>{0, 0, 0, 0.5, 0, 0});
  // A cell table (clip3d/cvt3d -o cells.csv): the columns x, y, z are the sites.
  std::istringstream table(
      "site,x,y,z,volume,centroid_x,centroid_y,centroid_z,energy,boundary\n"
      "0,0.25,0.5,0.75,1,0,0,0,0,1\n1,-1,-2,-3,1,0,0,0,0,0\n");
  CHECK(voroclip::read_points(table, "cells.csv", 3) ==
        std::vector<double>{0.25, 0.5, 0.75, -1, -2, -3});
  std::istringstream table2("site,x,y,area\n0,1,2,3\n");
  CHECK(voroclip::read_points(table2, "cells2.csv", 2) == std::vector<double>{1, 2});
  std::istringstream quoted("\"X\", \"Y\"\n1,2\n");
  CHECK(voroclip::read_points(quoted, "q.csv", 2) == std::vector<double>{1, 2});
  // Genuinely bad lines are still errors naming the line and the token.
  const auto error = [](const std::string& text, int dim) {
    std::istringstream in(text);
    try {
      voroclip::read_points(in, "e.csv", dim);
    } catch (const voroclip::Error& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  CHECK(error("x,y,z\n0,0,0\nx,y,z\n", 3) == "e.csv:3: 'x' is not a number");
  CHECK(error("0,0,0\n1,2,abc\n", 3) == "e.csv:2: 'abc' is not a number");
  CHECK(error("x,y,z\n1,2\n", 3) == "e.csv:2: expected 3 fields, as the header names, found 2");
  CHECK(error("x,y,z\n1,,2\n", 3) == "e.csv:2: field 2 is empty");
  CHECK(error("0,0,0,\n", 3) == "e.csv:1: more than 3 coordinates");
  CHECK(error("x,y,z\n1,2,3\n", 2) ==
        "e.csv:1: the header names a column z: 3D points, 2D expected");
  CHECK(error("a,b,c\n1,2,3\n", 3) == "e.csv:1: 'a' is not a number");
  CHECK(error("site,x,y\n1,2,3\n", 3) ==
        "e.csv:1: the header names no column z: 2D points, 3D expected");
  CHECK(error("{\"cells\": []}", 3) == "e.csv: expected a JSON array of points");
}

TEST_CASE("read_points: a UTF-8 BOM, CR-only line ends, a gzip file", "[core][regression]") {
  // The BOM was read as part of the first number ("'\xef\xbb\xbf0' is not a number"), CR
  // line ends made one line of the file.
  std::istringstream bom(
      "\xef\xbb\xbf"
      "0 0 0\n1 2 3\n");
  CHECK(voroclip::read_points(bom, "b.txt", 3) == std::vector<double>{0, 0, 0, 1, 2, 3});
  std::istringstream cr("# c\r0 0 0\r1 2 3\r");
  CHECK(voroclip::read_points(cr, "cr.txt", 3) == std::vector<double>{0, 0, 0, 1, 2, 3});
  std::istringstream crlf("x,y\r\n0,1\r\n");
  CHECK(voroclip::read_points(crlf, "crlf.csv", 2) == std::vector<double>{0, 1});
  std::istringstream crbad("0 0 0\r1 2\r");
  CHECK_THROWS_WITH(voroclip::read_points(crbad, "crbad.txt", 3),
                    "crbad.txt:2: expected 3 coordinates, found 2");
  std::istringstream gz(std::string("\x1f\x8b\x08\x00\x00\x00", 6));
  CHECK_THROWS_WITH(voroclip::read_points(gz, "s.txt", 3), "s.txt: the gzip data is truncated");
  // "0 0 0\n1 2 3\n" compressed by gzip (Python's gzip.compress, mtime 0): read as it is.
  std::istringstream packed(
      std::string("\x1f\x8b\x08\x00\x00\x00\x00\x00\x02\x03\x33\x50\x30\x50\x30\xe0\x32\x54\x30\x52"
                  "\x30\xe6\x02\x00\xfc\x72\xe9\x5a\x0c\x00\x00\x00",
                  32));
  CHECK(voroclip::read_points(packed, "s.txt.gz", 3) == std::vector<double>{0, 0, 0, 1, 2, 3});
  // Bytes that are not printable are escaped in messages.
  std::istringstream ctl("0 0 \x01\x7f\n");
  CHECK_THROWS_WITH(voroclip::read_points(ctl, "ctl.txt", 3),
                    "ctl.txt:1: '\\x01\\x7f' is not a number");
}

TEST_CASE("read_polygon: a UTF-8 BOM and CR-only line ends in a .poly", "[core][regression]") {
  std::istringstream poly(
      "\xef\xbb\xbf"
      "3 2 0 0\r1 0 0\r2 1 0\r3 0 1\r3 0\r1 1 2\r2 2 3\r3 3 1\r0\r");
  CHECK(voroclip::read_polygon(poly, "p.poly").xy == std::vector<double>{0, 0, 1, 0, 0, 1});
  // NAME.poly.gz is read as a .poly (inflated when its bytes are gzip data); NAME.gz is not.
  std::istringstream named("3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n3 0\n1 1 2\n2 2 3\n3 3 1\n0\n");
  CHECK(voroclip::read_polygon(named, "p.poly.gz").xy == std::vector<double>{0, 0, 1, 0, 0, 1});
  std::istringstream any("[]");
  CHECK_THROWS_WITH(voroclip::read_polygon(any, "p.gz"),
                    "p.gz: a compressed file is read by the extension before .gz (bunny.obj.gz "
                    "as an OBJ), and this one has none that voroclip reads");
}
