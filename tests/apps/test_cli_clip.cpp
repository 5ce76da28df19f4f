// The clip2d, cvt2d and clip3d commands: statistics, output files, errors.
#include <catch2/catch.hpp>

#include <cmath>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli_run.h"

namespace {

const std::string kData = VOROCLIP_SHARED_DATA_DIR;

}  // namespace

TEST_CASE("clip2d: statistics and the three output formats", "[apps]") {
  const std::string domain = kData + "/polygons/valid/issue35.json";
  const Run run = run_cli({"clip2d", domain, "--random", "2000", "--seed", "3", "--stats", "json"});
  REQUIRE(run.status == 0);
  const nlohmann::json s = nlohmann::json::parse(run.out);
  CHECK(s["sites"] == 2000);
  CHECK(s["boundary_sites"].get<int>() > 0);
  const double area = s["domain_area"], sum = s["cells_area_sum"];
  CHECK(std::fabs(area - sum) <= 1e-12 * area);
  for (const char* ext : {".svg", ".vtu", ".json"}) {
    const std::string out = temp_path(ext);
    const Run w = run_cli({"-q", "clip2d", domain, "--random", "300", "-o", out});
    CHECK(w.status == 0);
    const std::string text = slurp(out);
    std::remove(out.c_str());
    if (std::string(ext) == ".svg") CHECK(text.rfind("<svg", 0) == 0);
    if (std::string(ext) == ".vtu") CHECK(text.find("Name=\"site_id\"") != std::string::npos);
    if (std::string(ext) == ".json") {
      const nlohmann::json j = nlohmann::json::parse(text);
      REQUIRE(j["cells"].size() == 300);
      double total = 0;
      for (const auto& c : j["cells"]) total += c["area"].get<double>();
      CHECK(std::fabs(total - area) <= 1e-12 * area);
      CHECK(j["cells"][0]["polygons"].is_array());
    }
  }
}

TEST_CASE("clip2d and cvt2d: errors name the problem, leave no file", "[apps]") {
  const std::string out = temp_path(".svg");
  SECTION("a degenerate polygon") {
    const Run run =
        run_cli({"clip2d", kData + "/polygons/degenerate/water.json", "--random", "10", "-o", out});
    CHECK(run.status == 1);
    check_one_error_line(run);
    CHECK(contains(run.err, "water.json"));
    CHECK(contains(run.err, "cross"));
  }
  SECTION("a missing site file") {
    const Run run = run_cli({"clip2d", "annulus:1,2,64", "--sites", "/nonexistent.txt", "-o", out});
    CHECK(run.status == 1);
    check_one_error_line(run);
  }
  SECTION("both --sites and --random") {
    const Run run = run_cli({"cvt2d", "annulus:1,2,64", "--sites", "x.txt", "--random", "5"});
    CHECK(run.status == 2);
    check_one_error_line(run);
  }
  SECTION("a bad generator") {
    const Run run = run_cli({"clip2d", "annulus:2,1,64", "--random", "5"});
    CHECK(run.status == 2);
    check_one_error_line(run);
  }
  SECTION("an unknown output format") {
    const Run run = run_cli({"clip2d", "annulus:1,2,64", "--random", "5", "-o", "x.png"});
    CHECK(run.status == 2);
    check_one_error_line(run);
  }
  CHECK(!exists(out));
}

TEST_CASE("cvt2d: progress, convergence and the final sites", "[apps]") {
  const std::string out = temp_path(".txt");
  const Run run = run_cli({"cvt2d", "square-holes:2,0.4", "--random", "200", "--tolerance", "1e-3",
                           "--iterations", "500", "--stats", "json", "-o", out});
  REQUIRE(run.status == 0);
  const nlohmann::json s = nlohmann::json::parse(run.out);
  CHECK(s["converged"] == true);
  CHECK(s["gradient_norm"].get<double>() <= 1e-3 * s["initial_gradient_norm"].get<double>());
  CHECK(contains(run.err, "iteration"));  // progress on the human stream
  const std::string sites = slurp(out);
  std::remove(out.c_str());
  CHECK(std::count(sites.begin(), sites.end(), '\n') == 200);
}

TEST_CASE("clip3d: statistics, outputs and errors", "[apps]") {
  const std::string mesh = kData + "/tetmeshes/bunny.mesh";
  const Run run = run_cli({"clip3d", mesh, "--random", "2000", "--stats", "json"});
  REQUIRE(run.status == 0);
  const nlohmann::json s = nlohmann::json::parse(run.out);
  CHECK(s["tets"] == 14050);
  CHECK(s["boundary_triangles"] == 6598);
  CHECK(s["sites"] == 2000);
  const double volume = s["domain_volume"], sum = s["cells_volume_sum"];
  CHECK(std::fabs(volume - sum) <= 1e-12 * volume);
  for (const char* key : {"delaunay", "surface_rvd", "boundary_cells", "inner_cells", "total"}) {
    CHECK(s["seconds"][key].get<double>() >= 0);
  }
  for (const char* ext : {".obj", ".vtu", ".json"}) {
    const std::string out = temp_path(ext);
    const Run w = run_cli({"-q", "clip3d", mesh, "--random", "200", "-o", out});
    CHECK(w.status == 0);
    const std::string text = slurp(out);
    std::remove(out.c_str());
    CHECK(!text.empty());
    if (std::string(ext) == ".json") CHECK(nlohmann::json::parse(text)["cells"].size() == 200);
    if (std::string(ext) == ".obj") CHECK(text.find("\nf ") != std::string::npos);
    if (std::string(ext) == ".vtu") {
      // Every cell has faces (200 sites inside the volume): site_id takes all 200 values;
      // across is -1 on the surface, another site on a bisector.
      const auto array = [&](const std::string& name) {
        const std::string open = "Name=\"" + name + "\" format=\"ascii\">\n";
        const std::size_t b = text.find(open);
        REQUIRE(b != std::string::npos);
        std::istringstream in(text.substr(b + open.size(), text.find("</DataArray>", b) - b));
        std::vector<long long> values;
        for (long long x; in >> x;) values.push_back(x);
        return values;
      };
      const std::vector<long long> site = array("site_id"), across = array("across");
      REQUIRE(site.size() == across.size());
      CHECK(std::set<long long>(site.begin(), site.end()).size() == 200);
      std::size_t on_surface = 0;
      for (std::size_t k = 0; k < site.size(); ++k) {
        CHECK(across[k] >= -1);
        CHECK(across[k] < 200);
        CHECK(across[k] != site[k]);
        on_surface += across[k] == -1 ? 1 : 0;
      }
      CHECK(on_surface > 0);
      CHECK(on_surface < site.size());
    }
  }
  const std::string out = temp_path(".vtu");
  const Run bad = run_cli({"clip3d", "/nonexistent.mesh", "--random", "10", "-o", out});
  CHECK(bad.status == 1);
  check_one_error_line(bad);
  CHECK(contains(bad.err, "nonexistent.mesh"));
  CHECK(!exists(out));
}
