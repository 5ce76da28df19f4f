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
