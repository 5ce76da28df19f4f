// The clip2d, cvt2d and clip3d commands: statistics, output files, errors.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli_run.h"
#include "voroclip/core.h"

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
  // Messages say how they number: JSON rings, points and sites by position, from 0.
  SECTION("a JSON polygon: rings and points numbered from 0, and said so") {
    const std::string bowtie = temp_path(".json");
    std::ofstream(bowtie) << "[[[0,0],[2,0],[0,2],[2,2]]]";
    const Run run = run_cli({"clip2d", bowtie, "--random", "10", "-o", out});
    std::remove(bowtie.c_str());
    CHECK(run.status == 1);
    check_one_error_line(run);
    CHECK(contains(run.err, "ring 0 crosses itself: edges 1-2 and 3-0"));
    CHECK(contains(run.err, "(rings and points numbered from 0)"));
  }
  SECTION("a JSON site file: points numbered from 0, and said so") {
    const std::string sites = temp_path(".json");
    std::ofstream(sites) << "[[0.1, 0.1], [0.2], [0.3, 0.3]]";
    const Run run = run_cli({"clip2d", "annulus:1,2,64", "--sites", sites, "-o", out});
    std::remove(sites.c_str());
    CHECK(run.status == 1);
    check_one_error_line(run);
    CHECK(contains(run.err, "point 1 (from 0) is not an array of 2 numbers"));
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

TEST_CASE("clip3d from a closed surface (OBJ, OFF, STL, PLY)", "[apps]") {
  // bunny.obj as is, and written as binary STL and PLY by the library, elk.off as is.
  const std::string obj = kData + "/surfaces/bunny.obj";
  const std::string stl = temp_path(".stl"), ply = temp_path(".ply");
  voroclip::write_surface(stl, voroclip::read_surface(obj), voroclip::SurfaceFormat::kStlBinary);
  voroclip::write_surface(ply, voroclip::read_surface(obj), voroclip::SurfaceFormat::kPlyBinary);
  double volume_obj = 0;
  for (const std::string& domain : {obj, stl, ply, kData + "/surfaces/elk.off"}) {
    const Run run = run_cli({"clip3d", domain, "--random", "3000", "--stats", "json"});
    REQUIRE(run.status == 0);
    const nlohmann::json s = nlohmann::json::parse(run.out);
    CHECK(s["tets"] == 0);
    CHECK(s["shells"] == 1);
    CHECK(s["sites"] == 3000);
    const double volume = s["domain_volume"], sum = s["cells_volume_sum"];
    CHECK(std::fabs(volume - sum) <= 1e-12 * volume);
    if (domain == obj) {
      CHECK(s["boundary_triangles"] == 6598);
      volume_obj = volume;
    } else if (domain == ply) {
      CHECK(volume == volume_obj);  // binary PLY keeps the doubles
    } else if (domain == stl) {
      CHECK(std::fabs(volume - volume_obj) <= 1e-6 * volume_obj);  // float32 coordinates
    }
  }
  std::remove(stl.c_str());
  std::remove(ply.c_str());
  // The cells' faces from the surface alone.
  const std::string out = temp_path(".vtu");
  const Run w = run_cli({"-q", "clip3d", obj, "--random", "300", "-o", out});
  CHECK(w.status == 0);
  const std::string text = slurp(out);
  std::remove(out.c_str());
  CHECK(contains(text, "Name=\"across\""));
  // An inside-out surface: rejected with the shell and what to do, or reoriented on demand.
  voroclip::TriangleSurface inside_out = voroclip::read_surface(kData + "/surfaces/sphere.obj");
  for (std::size_t t = 0; t < inside_out.triangles.size(); t += 3) {
    std::swap(inside_out.triangles[t + 1], inside_out.triangles[t + 2]);
  }
  const std::string inverted = temp_path(".obj");
  voroclip::write_surface(inverted, inside_out, voroclip::SurfaceFormat::kObj);
  const std::string vtu = temp_path(".vtu");
  const Run bad = run_cli({"clip3d", inverted, "--random", "100", "-o", vtu});
  CHECK(bad.status == 1);
  check_one_error_line(bad);
  CHECK(contains(bad.err, "inside out"));
  CHECK(contains(bad.err, "--reorient"));
  CHECK(!exists(vtu));
  const Run fixed = run_cli({"clip3d", inverted, "--reorient", "--random", "100"});
  CHECK(fixed.status == 0);
  CHECK(contains(fixed.out, "note: "));
  CHECK(contains(fixed.out, "reoriented"));
  std::remove(inverted.c_str());
}

TEST_CASE("check-surface: the verdict, the shells, genus, area and volume", "[apps]") {
  const Run run = run_cli({"check-surface", kData + "/surfaces/skull_low_resolution.obj"});
  REQUIRE(run.status == 0);
  CHECK(contains(run.out, "a valid closed surface: 10312 triangles"));
  CHECK(contains(run.out, "shell 0: 10312 triangles, 5154 vertices, genus 2, outer boundary"));
  const Run json =
      run_cli({"--stats", "json", "check-surface", kData + "/surfaces/rocker-arm.obj"});
  REQUIRE(json.status == 0);
  const nlohmann::json s = nlohmann::json::parse(json.out);
  CHECK(s["valid"] == true);
  CHECK(s["triangles"] == 20088);
  REQUIRE(s["shells"].size() == 1);
  CHECK(s["shells"][0]["genus"] == 1);
  CHECK(s["shells"][0]["euler_characteristic"] == 0);
  CHECK(s["volume"].get<double>() > 0);
  CHECK(s["area"].get<double>() > 0);
  // A defect: the verdict on stdout as JSON, the message on stderr, exit status 1.
  const std::string open = temp_path(".off");
  {
    std::ofstream f(open);
    f << "OFF\n4 3 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n";
  }
  const Run defect = run_cli({"--stats", "json", "check-surface", open});
  CHECK(defect.status == 1);
  const nlohmann::json d = nlohmann::json::parse(defect.out);
  CHECK(d["valid"] == false);
  CHECK(contains(d["error"].get<std::string>(), "is not closed"));
  CHECK(contains(defect.err, open + ":"));
  CHECK(contains(defect.err, "face 0: the surface is not closed"));
  std::remove(open.c_str());
}

TEST_CASE("check-surface: a tet mesh's message tells the facets of one tet apart",
          "[apps][regression]") {
  // Two tets sharing only the edge (1, 2): its four boundary triangles, two facets of each
  // tet, were named "the boundary facet of tetrahedron 1 (line 13)" twice, and the same
  // for tetrahedron 2. Their vertices tell them apart, numbered as the file numbers them.
  const std::string path = temp_path(".mesh");
  std::ofstream(path) << "MeshVersionFormatted 2\nDimension 3\nVertices\n6\n"
                         "0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 -1 0 0\n0 0 -1 0\n"
                         "Tetrahedra\n2\n1 2 3 4 0\n1 2 5 6 0\nEnd\n";
  const Run run = run_cli({"check-surface", path});
  CHECK(run.status == 1);
  check_one_error_line(run);
  CHECK(run.err ==
        "voroclip: error: " + path +
            ":13: the boundary facet (vertices 1 2 3) of tetrahedron 1: the surface is not a "
            "2-manifold: the edge (vertices 1 2) is in 4 triangles (2 expected): the boundary "
            "facet (vertices 1 2 3) of tetrahedron 1 (line 13), the boundary facet (vertices 1 2 "
            "4) of tetrahedron 1 (line 13), the boundary facet (vertices 1 2 5) of tetrahedron 2 "
            "(line 14) and the boundary facet (vertices 1 2 6) of tetrahedron 2 (line 14)\n");
  std::remove(path.c_str());
}

TEST_CASE("check-surface --stats json: every invalid input says valid false and the error",
          "[apps][regression]") {
  // Defects found while reading (an index out of range, a coordinate that is not finite, a
  // truncated or empty file) printed no JSON at all, only the error line.
  const std::vector<std::pair<std::string, std::string>> files = {
      {".obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 5\nf 2 3 4\n"},
      {".obj", "v 0 0 0\nv 1 0 0\nv 0 nan 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"},
      {".off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n"},
      {".obj", ""},
      {".mesh", "MeshVersionFormatted 2\nDimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n"},
  };
  std::vector<std::string> paths;
  for (const auto& [ext, text] : files) {
    paths.push_back(temp_path(ext));
    std::ofstream(paths.back()) << text;
  }
  paths.push_back(temp_path(".obj"));  // no such file
  for (const std::string& path : paths) {
    INFO(path);
    const Run run = run_cli({"--stats", "json", "check-surface", path});
    CHECK(run.status == 1);
    REQUIRE(!run.out.empty());
    const nlohmann::json j = nlohmann::json::parse(run.out);
    CHECK(j["valid"] == false);
    // The JSON's error is the error line's.
    const std::string error = j["error"].get<std::string>();
    CHECK(run.err == "voroclip: error: " + error + "\n");
    CHECK(contains(error, path));
    CHECK(j["seconds"].contains("read"));
    std::remove(path.c_str());
  }
}

TEST_CASE("clip3d, clip2d: --binary / --compress refuse outputs without such a variant", "[apps]") {
  // OBJ (and SVG, CSV, JSON) have no binary or compressed form in their specifications.
  const std::string sphere = kData + "/surfaces/sphere.obj";
  const std::string obj = temp_path(".obj");
  const Run run = run_cli({"clip3d", sphere, "--random", "20", "--compress", "-o", obj});
  CHECK(run.status == 2);
  check_one_error_line(run);
  CHECK(contains(run.err,
                 "--compress: only a .vtu output (-o FILE.vtu) is written in binary or "
                 "compressed (.obj is a text format with no binary or compressed variant"));
  CHECK(!exists(obj));
  const std::string svg = temp_path(".svg");
  const Run run2 = run_cli({"clip2d", "annulus:1,2,64", "--random", "20", "--binary", "-o", svg});
  CHECK(run2.status == 2);
  CHECK(contains(run2.err, "--binary: only a .vtu output"));
  CHECK(contains(run2.err, ".svg is a text format"));
  CHECK(!exists(svg));
}

TEST_CASE("clip2d and cvt2d: one site, two, or all on a line: strips of the domain",
          "[apps][regression]") {
  // They have no Delaunay triangulation of their own and used to be an error; now the
  // library adds far auxiliary sites. In the unit square: the areas in closed form (strips
  // cut by the bisectors), and cvt2d's single site goes to the centroid (energy 1/6).
  const std::string domain = temp_path(".json"), out = temp_path(".json");
  std::ofstream(domain) << "[[[0, 0], [1, 0], [1, 1], [0, 1]]]";
  struct Case {
    const char* text;
    std::vector<double> areas;
    int duplicates;
  };
  const Case cases[] = {
      {"0.5 0.5\n", {1.0}, 0},
      {"0.2 0.5\n0.8 0.5\n", {0.5, 0.5}, 0},
      {"0.1 0.1\n0.5 0.5\n0.9 0.9\n", {0.18, 0.64, 0.18}, 0},  // x + y = 0.6, 1.4
      {"0.3 0.3\n0.3 0.3\n0.3 0.3\n0.3 0.3\n", {1.0, 0, 0, 0}, 3},
  };
  for (const Case& c : cases) {
    INFO(c.text);
    const std::string sites = temp_path(".txt");
    std::ofstream(sites) << c.text;
    const Run run = run_cli(
        {"-q", "clip2d", domain, "--sites", sites, "-o", out, "--stats", "json", "--threads", "1"});
    REQUIRE(run.status == 0);
    CHECK(run.err.empty() == (c.duplicates == 0));  // repeated sites: a warning
    const nlohmann::json st = nlohmann::json::parse(run.out);
    CHECK(st["sites"] == c.areas.size());
    CHECK(st["unique_sites"] == c.areas.size() - static_cast<std::size_t>(c.duplicates));
    CHECK(std::fabs(st["cells_area_sum"].get<double>() - 1) <= 1e-15);
    const nlohmann::json j = nlohmann::json::parse(slurp(out));
    REQUIRE(j["cells"].size() == c.areas.size());
    for (std::size_t i = 0; i < c.areas.size(); ++i) {
      CHECK(std::fabs(j["cells"][i]["area"].get<double>() - c.areas[i]) <= 1e-15);
    }
    const Run cvt = run_cli({"-q", "cvt2d", domain, "--sites", sites, "--stats", "json"});
    std::remove(sites.c_str());
    REQUIRE(cvt.status == 0);
    const nlohmann::json sc = nlohmann::json::parse(cvt.out);
    CHECK(sc["converged"] == true);
    if (c.areas.size() == 1) {
      CHECK(std::fabs(sc["energy"].get<double>() - 1.0 / 6) <= 1e-12);
    }
  }
  // --random 1 and 2 draw and clip too.
  for (const char* n : {"1", "2"}) {
    const Run run = run_cli({"-q", "clip2d", domain, "--random", n, "--stats", "json"});
    REQUIRE(run.status == 0);
    CHECK(std::fabs(nlohmann::json::parse(run.out)["cells_area_sum"].get<double>() - 1) <= 1e-15);
  }
  std::remove(domain.c_str());
  std::remove(out.c_str());
}

TEST_CASE("--seed without --random is a usage error in every command that has both",
          "[apps][regression]") {
  // --seed seeds --random's points; with points from a file it meant nothing and was
  // accepted silently.
  const std::string sites2 = temp_path(".txt"), sites3 = temp_path(".txt");
  std::ofstream(sites2) << "0.1 0.1\n0.5 0.5\n0.9 0.1\n";
  std::ofstream(sites3) << "0.1 0.1 0.1\n0.5 0.5 0.5\n0.9 0.1 0.2\n0.3 0.8 0.4\n";
  const std::string cube = temp_path(".obj");
  std::ofstream(cube) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\n"
                         "v 1 1 1\nf 1 3 4\nf 1 4 2\nf 5 6 8\nf 5 8 7\nf 1 2 6\nf 1 6 5\n"
                         "f 3 7 8\nf 3 8 4\nf 1 5 7\nf 1 7 3\nf 2 4 8\nf 2 8 6\n";
  const std::string out = temp_path(".csv");
  const std::vector<std::vector<std::string>> commands = {
      {"clip2d", "square-holes:1,0.2", "--sites", sites2, "-o", out},
      {"cvt2d", "square-holes:1,0.2", "--sites", sites2, "-o", out},
      {"clip3d", cube, "--sites", sites3, "-o", out},
      {"cvt3d", cube, "--sites", sites3, "-o", out},
      {"delaunay2d", sites2},
      {"delaunay3d", sites3},
  };
  for (std::vector<std::string> args : commands) {
    args.push_back("--seed");
    args.push_back("5");
    const Run run = run_cli(args);
    CHECK(run.status == 2);
    check_one_error_line(run);
    CHECK(contains(run.err, "--seed: only with --random N, whose points it seeds"));
    CHECK(!exists(out));
  }
  std::remove(sites2.c_str());
  std::remove(sites3.c_str());
  std::remove(cube.c_str());
}
