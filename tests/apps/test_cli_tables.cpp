// clip2d / clip3d cell tables: -o cells.csv, --neighbors pairs.csv|.json, the same values
// in -o cells.json; checked against the --stats json sums and each other.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "cli_run.h"

namespace {

const std::string kData = VOROCLIP_SHARED_DATA_DIR;

struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  std::size_t column(const std::string& name) const {
    for (std::size_t k = 0; k < header.size(); ++k) {
      if (header[k] == name) return k;
    }
    FAIL("no column " << name);
    return 0;
  }
};

Csv read_csv(const std::string& path) {
  std::istringstream in(slurp(path));
  Csv csv;
  std::string line;
  REQUIRE(std::getline(in, line));
  std::istringstream h(line);
  for (std::string cell; std::getline(h, cell, ',');) csv.header.push_back(cell);
  while (std::getline(in, line)) {
    std::istringstream r(line);
    std::vector<double> row;
    for (std::string cell; std::getline(r, cell, ',');) row.push_back(std::stod(cell));
    REQUIRE(row.size() == csv.header.size());
    csv.rows.push_back(row);
  }
  return csv;
}

// The neighbours file: site_a < site_b, each pair once; per site its number of pairs.
std::vector<int> check_pairs(const Csv& pairs, std::size_t n, double* measure_sum) {
  std::vector<int> count(n, 0);
  std::map<std::pair<long, long>, int> seen;
  *measure_sum = 0;
  for (const auto& r : pairs.rows) {
    const long a = std::lround(r[0]), b = std::lround(r[1]);
    CHECK(a < b);
    CHECK(b < static_cast<long>(n));
    CHECK(++seen[{a, b}] == 1);
    CHECK(r[2] >= 0);
    ++count[static_cast<std::size_t>(a)];
    ++count[static_cast<std::size_t>(b)];
    *measure_sum += r[2];
  }
  return count;
}

}  // namespace

TEST_CASE("clip2d -o cells.csv --neighbors pairs.csv", "[apps][table]") {
  const std::string domain = kData + "/polygons/valid/issue35.json";
  const std::string cells = temp_path(".csv"), pairs = temp_path(".csv");
  const std::string json = temp_path(".json"), pairs_json = temp_path(".json");
  const Run run = run_cli({"clip2d", domain, "--random", "500", "--seed", "4", "--stats", "json",
                           "-o", cells, "--neighbors", pairs});
  REQUIRE(run.status == 0);
  const nlohmann::json stats = nlohmann::json::parse(run.out);
  const Csv c = read_csv(cells);
  CHECK(c.header == std::vector<std::string>{"site", "x", "y", "area", "centroid_x", "centroid_y",
                                             "energy", "boundary", "neighbors"});
  REQUIRE(c.rows.size() == 500);
  double area = 0, energy = 0;
  std::size_t boundary = 0;
  for (std::size_t i = 0; i < c.rows.size(); ++i) {
    CHECK(c.rows[i][0] == static_cast<double>(i));
    area += c.rows[i][c.column("area")];
    energy += c.rows[i][c.column("energy")];
    boundary += c.rows[i][c.column("boundary")] == 1 ? 1 : 0;
  }
  // The rows hold the diagram's values: the sums are the statistics' (same order, same bits
  // up to the summation, which is in index order in both).
  CHECK(area == stats["cells_area_sum"].get<double>());
  CHECK(std::fabs(area - stats["domain_area"].get<double>()) <= 1e-12 * area);
  CHECK(std::fabs(energy - stats["energy"].get<double>()) <= 1e-12 * energy);
  CHECK(boundary == stats["boundary_sites"].get<std::size_t>());

  const Csv p = read_csv(pairs);
  CHECK(p.header == std::vector<std::string>{"site_a", "site_b", "length"});
  double length_sum = 0;
  const std::vector<int> count = check_pairs(p, 500, &length_sum);
  for (std::size_t i = 0; i < 500; ++i) CHECK(c.rows[i][c.column("neighbors")] == count[i]);
  CHECK(length_sum > 0);

  // The same run with JSON outputs: the same values per cell, the same pairs.
  const Run j = run_cli({"-q", "clip2d", domain, "--random", "500", "--seed", "4", "-o", json,
                         "--neighbors", pairs_json});
  REQUIRE(j.status == 0);
  const nlohmann::json cj = nlohmann::json::parse(slurp(json));
  REQUIRE(cj["cells"].size() == 500);
  for (std::size_t i = 0; i < 500; ++i) {
    const nlohmann::json& cell = cj["cells"][i];
    CHECK(cell["index"] == i);
    CHECK(cell["site"][0].get<double>() == c.rows[i][c.column("x")]);
    CHECK(cell["area"].get<double>() == c.rows[i][c.column("area")]);
    CHECK(cell["centroid"][1].get<double>() == c.rows[i][c.column("centroid_y")]);
    CHECK(cell["neighbors"] == count[i]);
  }
  const nlohmann::json pj = nlohmann::json::parse(slurp(pairs_json));
  REQUIRE(pj["neighbors"].size() == p.rows.size());
  for (std::size_t r = 0; r < p.rows.size(); ++r) {
    CHECK(pj["neighbors"][r]["site_a"].get<double>() == p.rows[r][0]);
    CHECK(pj["neighbors"][r]["length"].get<double>() == p.rows[r][2]);
  }
  for (const std::string& f : {cells, pairs, json, pairs_json}) std::remove(f.c_str());
}

TEST_CASE("clip3d -o cells.csv --neighbors pairs.csv", "[apps][table]") {
  const std::string domain = kData + "/surfaces/sphere.obj";
  const std::string cells = temp_path(".csv"), pairs = temp_path(".csv");
  const Run run = run_cli(
      {"clip3d", domain, "--random", "400", "--stats", "json", "-o", cells, "--neighbors", pairs});
  REQUIRE(run.status == 0);
  const nlohmann::json stats = nlohmann::json::parse(run.out);
  const Csv c = read_csv(cells);
  CHECK(c.header == std::vector<std::string>{"site", "x", "y", "z", "volume", "centroid_x",
                                             "centroid_y", "centroid_z", "energy", "boundary",
                                             "neighbors", "surface_area"});
  REQUIRE(c.rows.size() == 400);
  double volume = 0, surface = 0;
  for (const auto& row : c.rows) {
    volume += row[c.column("volume")];
    surface += row[c.column("surface_area")];
  }
  CHECK(volume == stats["cells_volume_sum"].get<double>());
  CHECK(std::fabs(volume - stats["domain_volume"].get<double>()) <= 1e-12 * volume);
  CHECK(std::fabs(surface - stats["surface_area_sum"].get<double>()) <= 1e-12 * surface);
  const Csv p = read_csv(pairs);
  CHECK(p.header == std::vector<std::string>{"site_a", "site_b", "area"});
  double area_sum = 0;
  const std::vector<int> count = check_pairs(p, 400, &area_sum);
  for (std::size_t i = 0; i < 400; ++i) CHECK(c.rows[i][c.column("neighbors")] == count[i]);
  // Each cell has at least 4 neighbours or meets the surface.
  for (std::size_t i = 0; i < 400; ++i) {
    CHECK((count[i] >= 4 || c.rows[i][c.column("boundary")] == 1));
  }
  for (const std::string& f : {cells, pairs}) std::remove(f.c_str());
}

TEST_CASE("table outputs: usage errors before any work", "[apps][table]") {
  const std::string domain = kData + "/polygons/valid/issue35.json";
  const Run bad = run_cli({"clip2d", domain, "--random", "10", "--neighbors", "pairs.txt"});
  CHECK(bad.status == 2);
  check_one_error_line(bad);
  CHECK(contains(bad.err, "--neighbors"));
  const Run dir = run_cli({"clip3d", kData + "/surfaces/sphere.obj", "--random", "10",
                           "--neighbors", "/nonexistent/dir/pairs.csv"});
  CHECK(dir.status == 1);
  check_one_error_line(dir);
  CHECK(contains(dir.err, "/nonexistent/dir/pairs.csv"));
}

TEST_CASE("clip2d / clip3d: sites outside the domain and repeated sites are named", "[apps]") {
  // The unit square's polygon: sites 1 and 3 are outside, 4 repeats 0.
  const std::string square = temp_path(".json"), sites2 = temp_path(".txt");
  {
    std::ofstream(square) << "[[[0,0],[1,0],[1,1],[0,1]]]";
    std::ofstream(sites2) << "0.5 0.5\n2 2\n0.25 0.25\n-1 0.5\n0.5 0.5\n0.75 0.25\n";
  }
  const Run run = run_cli({"clip2d", square, "--sites", sites2, "--stats", "json"});
  REQUIRE(run.status == 0);
  const nlohmann::json s = nlohmann::json::parse(run.out);
  CHECK(s["sites_outside"] == 2);
  CHECK(s["duplicate_sites"] == 1);
  CHECK(contains(run.err, "voroclip: warning: 2 sites outside the domain"));
  CHECK(contains(run.err, "(indices 1, 3, from 0 in input order)"));
  CHECK(contains(run.err, "1 site repeats an earlier site (index 4,"));
  const std::string csv = temp_path(".csv");
  const Run strict = run_cli({"clip2d", square, "--sites", sites2, "--strict", "-o", csv});
  CHECK(strict.status == 1);
  check_one_error_line(strict);
  CHECK(contains(strict.err, "2 sites outside the domain"));
  CHECK(!exists(csv));
  // All inside and distinct: no warning.
  { std::ofstream(sites2) << "0.5 0.5\n0.25 0.25\n0.75 0.25\n"; }
  const Run clean = run_cli({"clip2d", square, "--sites", sites2, "--stats", "json"});
  REQUIRE(clean.status == 0);
  CHECK(!contains(clean.err, "warning"));
  CHECK(nlohmann::json::parse(clean.out)["sites_outside"] == 0);

  // 3D: the sphere of radius 1 about the origin (sphere.obj).
  const std::string sites3 = temp_path(".txt");
  { std::ofstream(sites3) << "0 0 0\n0.5 0 0\n0 0.5 0\n0 0 0.5\n3 0 0\n0.5 0 0\n-0.3 -0.3 0\n"; }
  const Run r3 =
      run_cli({"clip3d", kData + "/surfaces/sphere.obj", "--sites", sites3, "--stats", "json"});
  REQUIRE(r3.status == 0);
  const nlohmann::json s3 = nlohmann::json::parse(r3.out);
  CHECK(s3["sites_outside"] == 1);
  CHECK(s3["duplicate_sites"] == 1);
  CHECK(contains(r3.err, "1 site outside the domain"));
  CHECK(contains(r3.err, "(index 4, from 0 in input order)"));
  CHECK(contains(r3.err, "(index 5, from 0 in input order; its cell is empty)"));
  for (const std::string& f : {square, sites2, sites3}) std::remove(f.c_str());
}

TEST_CASE("a flat tet is named as the file numbers it", "[apps]") {
  const std::string medit = temp_path(".mesh");
  {
    std::ofstream(medit) << "MeshVersionFormatted 2\nDimension 3\nVertices\n5\n0 0 0 0\n1 0 0 "
                            "0\n0 1 0 0\n0 0 1 0\n0.5 0.5 0 0\nTetrahedra\n2\n1 2 3 4 0\n1 2 3 5 "
                            "0\nEnd\n";
  }
  const Run run = run_cli({"clip3d", medit, "--random", "10"});
  CHECK(run.status == 1);
  check_one_error_line(run);
  CHECK(contains(run.err, medit + ":13: tetrahedron 2 has zero volume: its vertices 1 2 3 5 are "
                                  "coplanar (exact orient3d; Medit numbering, from 1)"));
  std::remove(medit.c_str());
}

TEST_CASE("clip2d / clip3d .vtu: ASCII, --binary and --compress hold the same cells", "[apps]") {
  const auto attribute = [](const std::string& text, const std::string& name) {
    const std::size_t at = text.find(name + "=\"");
    REQUIRE(at != std::string::npos);
    const std::size_t b = at + name.size() + 2;
    return text.substr(b, text.find('"', b) - b);
  };
  const std::string domain2 = kData + "/polygons/valid/issue35.json";
  const std::string domain3 = kData + "/surfaces/sphere.obj";
  for (const bool three : {false, true}) {
    std::string cells[3];
    const char* flags[3] = {"", "--binary", "--compress"};
    for (int k = 0; k < 3; ++k) {
      const std::string out = temp_path(".vtu");
      std::vector<std::string> args = {
          "-q", three ? "clip3d" : "clip2d", three ? domain3 : domain2, "--random", "200", "-o",
          out};
      if (k > 0) args.push_back(flags[k]);
      const Run run = run_cli(args);
      REQUIRE(run.status == 0);
      const std::string text = slurp(out);
      std::remove(out.c_str());
      cells[k] = attribute(text, "NumberOfCells") + " " + attribute(text, "NumberOfPoints");
      CHECK(contains(text, "Name=\"site_id\""));
      CHECK(contains(text, three ? "Name=\"across\"" : "Name=\"hole\""));
      CHECK(contains(text, "format=\"appended\"") == (k > 0));
      CHECK(contains(text, "vtkZLibDataCompressor") == (k == 2));
    }
    CHECK(cells[0] == cells[1]);
    CHECK(cells[0] == cells[2]);
  }
  const Run bad = run_cli({"clip2d", domain2, "--random", "10", "-o", "x.svg", "--compress"});
  CHECK(bad.status == 2);
  check_one_error_line(bad);
  CHECK(contains(bad.err, "--compress"));
}
