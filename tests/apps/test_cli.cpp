// Runs the built `voroclip` binary (VOROCLIP_CLI_PATH) and checks what it prints, its exit
// status and the files it writes.
#include <catch2/catch.hpp>

#include <stdlib.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <fstream>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_run.h"
#include "voroclip/core.h"
#include "voroclip/predicates.h"

namespace {

nlohmann::json demo_stats(const std::string& threads) {
  const Run run = run_cli({"--threads", threads, "demo", "--stats", "json"});
  REQUIRE(run.status == 0);
  return nlohmann::json::parse(run.out);
}

}  // namespace

TEST_CASE("--version prints the library version", "[apps]") {
  const Run run = run_cli({"--version"});
  CHECK(run.status == 0);
  CHECK(run.out == std::string("voroclip ") + voroclip::version() + "\n");
  CHECK(run.err.empty());
}

TEST_CASE("--help lists the subcommands and global options", "[apps]") {
  const Run run = run_cli({"--help"});
  CHECK(run.status == 0);
  CHECK(contains(run.out, "demo"));
  CHECK(contains(run.out, "predicate"));
  CHECK(contains(run.out, "--threads"));
  CHECK(contains(run.out, "--stats"));
  CHECK(contains(run.out, "--quiet"));
}

TEST_CASE("usage errors exit with status 2 and one error line", "[apps]") {
  SECTION("no subcommand") {
    const Run run = run_cli({});
    CHECK(run.status == 2);
    check_one_error_line(run);
  }
  SECTION("unknown option") {
    const Run run = run_cli({"--no-such-option", "demo"});
    CHECK(run.status == 2);
    check_one_error_line(run);
  }
  SECTION("--threads 0") {
    const Run run = run_cli({"--threads", "0", "demo"});
    CHECK(run.status == 2);
    check_one_error_line(run);
    CHECK(contains(run.err, "--threads"));
  }
  SECTION("--threads not a number") {
    const Run run = run_cli({"--threads", "two", "demo"});
    CHECK(run.status == 2);
    check_one_error_line(run);
    CHECK(contains(run.err, "--threads"));
  }
  SECTION("demo -o with an empty file name") {
    const Run run = run_cli({"demo", "-o", ""});
    CHECK(run.status == 2);
    check_one_error_line(run);
  }
  SECTION("--stats in an unknown format") {
    const Run run = run_cli({"demo", "--stats", "xml"});
    CHECK(run.status == 2);
    check_one_error_line(run);
  }
}

TEST_CASE("demo --stats json reports the classroom example's exact facts", "[apps][exact]") {
  const Run run = run_cli({"demo", "--stats", "json"});
  REQUIRE(run.status == 0);
  const nlohmann::json stats = nlohmann::json::parse(run.out);  // one object, nothing else
  REQUIRE(stats.is_object());
  CHECK(stats.at("points") == 65536);
  // Kettner et al.: naive floating point gets some of these signs wrong.
  CHECK(stats.at("naive_wrong").get<long>() > 0);
  CHECK(stats.at("naive_false_zero").get<long>() + stats.at("naive_false_nonzero").get<long>() +
            stats.at("naive_flipped").get<long>() ==
        stats.at("naive_wrong").get<long>());
  CHECK(stats.at("naive_positive").get<long>() + stats.at("naive_zero").get<long>() +
            stats.at("naive_negative").get<long>() ==
        65536);
  // Exact: p is on the line exactly when i == j, above it (positive) when j > i.
  CHECK(stats.at("exact_zero") == 256);
  CHECK(stats.at("exact_positive") == 32640);
  CHECK(stats.at("exact_negative") == 32640);
  CHECK(stats.at("exact_positive").get<long>() + stats.at("exact_zero").get<long>() +
            stats.at("exact_negative").get<long>() ==
        65536);
  // Four 5-tuples of cospherical cube corners, each decided by insphere_sos.
  CHECK(stats.at("cospherical_tests") == 4);
  CHECK(stats.at("sos_positive").get<long>() + stats.at("sos_negative").get<long>() ==
        stats.at("cospherical_tests").get<long>());
  CHECK(stats.at("seconds").is_number());
  CHECK(stats.at("svg").is_null());
  // With --stats json the human report moves to stderr.
  CHECK(contains(run.err, "Classroom example"));
}

TEST_CASE("demo without options prints a report on stdout", "[apps]") {
  const Run run = run_cli({"demo"});
  CHECK(run.status == 0);
  CHECK(contains(run.out, "Classroom example"));
  CHECK(contains(run.out, "insphere_sos"));
  CHECK(run.err.empty());
}

TEST_CASE("--quiet with --stats json prints only the JSON object", "[apps]") {
  const Run run = run_cli({"-q", "demo", "--stats", "json"});
  CHECK(run.status == 0);
  CHECK(run.err.empty());
  CHECK(nlohmann::json::parse(run.out).at("exact_zero") == 256);
}

TEST_CASE("demo counts are identical with 1 and 2 threads", "[apps][threads]") {
  nlohmann::json one = demo_stats("1");
  nlohmann::json two = demo_stats("2");
  CHECK(one.at("threads") == 1);
  for (nlohmann::json* stats : {&one, &two}) {
    stats->erase("seconds");
    stats->erase("threads");
  }
  CHECK(one == two);
}

TEST_CASE("demo -o writes a complete SVG picture", "[apps]") {
  const std::string path = "test_cli_demo.svg";
  std::remove(path.c_str());
  const Run run = run_cli({"demo", "-o", path, "--stats", "json"});
  REQUIRE(run.status == 0);
  CHECK(nlohmann::json::parse(run.out).at("svg") == path);
  const std::string svg = slurp(path);
  CHECK((svg.rfind("<?xml", 0) == 0 || svg.rfind("<svg", 0) == 0));
  CHECK(contains(svg, "<svg xmlns=\"http://www.w3.org/2000/svg\""));
  CHECK(svg.size() > 7);
  CHECK(svg.substr(svg.size() - 7) == "</svg>\n");
  CHECK_FALSE(exists(path + ".voroclip-tmp"));

  // The picture is a function of the input only, not of the number of threads.
  const std::string path1 = "test_cli_demo_1thread.svg";
  REQUIRE(run_cli({"--threads", "1", "demo", "-o", path1}).status == 0);
  CHECK(slurp(path1) == svg);
  std::remove(path.c_str());
  std::remove(path1.c_str());
}

TEST_CASE("demo -o into a missing directory fails and creates nothing", "[apps]") {
  const std::string path = "/nonexistent/dir/x.svg";
  REQUIRE_FALSE(exists("/nonexistent"));
  const Run run = run_cli({"demo", "-o", path});
  CHECK(run.status == 1);
  CHECK(run.err.rfind("voroclip: error: ", 0) == 0);
  CHECK(std::count(run.err.begin(), run.err.end(), '\n') == 1);
  CHECK(contains(run.err, path));
  CHECK_FALSE(exists("/nonexistent"));
}

TEST_CASE("predicate prints the exact sign", "[apps][exact]") {
  CHECK(run_cli({"predicate", "orient2d", "0", "0", "1", "0", "0", "1"}).out == "positive\n");
  CHECK(run_cli({"predicate", "orient2d", "0", "0", "0", "1", "1", "0"}).out == "negative\n");
  CHECK(run_cli({"predicate", "orient2d", "0", "0", "1", "1", "2", "2"}).out == "zero\n");
  // Negative numbers are coordinates, not options.
  CHECK(run_cli({"predicate", "orient2d", "0", "0", "-1", "0", "0", "-1"}).out == "positive\n");
  CHECK(run_cli({"predicate", "orient2d", "--", "0", "0", "-.5", "0", "0", "1"}).out ==
        "negative\n");
  CHECK(run_cli({"predicate", "incircle", "0", "0", "1", "0", "0", "1", "0.5", "0.5"}).out ==
        "positive\n");
  CHECK(run_cli({"predicate", "incircle", "0", "0", "1", "0", "0", "1", "1", "1"}).out == "zero\n");
  CHECK(
      run_cli({"predicate", "orient3d", "0", "0", "0", "1", "0", "0", "0", "1", "0", "0", "0", "1"})
          .out == "negative\n");
}

TEST_CASE("predicate reads hexadecimal floats exactly", "[apps][exact]") {
  // 0x1.0000000000001p-1 is 0.5 + 2^-53: point (i, j) = (1, 1) and (1, 0) of the demo.
  const std::string p = "0x1.0000000000001p-1";
  const Run on_line = run_cli({"predicate", "orient2d", p, p, "12", "12", "24", "24"});
  CHECK(on_line.status == 0);
  CHECK(on_line.out == "zero\n");
  CHECK(run_cli({"predicate", "orient2d", p, "0x1p-1", "12", "12", "24", "24"}).out ==
        "negative\n");
  CHECK(run_cli({"predicate", "orient2d", "0.5000000000000001", p, "12", "12", "24", "24"}).out ==
        "zero\n");
}

TEST_CASE("predicate rejects bad arguments with a clear message", "[apps]") {
  SECTION("5 coordinates for orient2d") {
    const Run run = run_cli({"predicate", "orient2d", "0", "0", "1", "0", "0"});
    CHECK(run.status == 2);
    check_one_error_line(run);
    CHECK(contains(run.err, "orient2d takes 6 coordinates"));
    CHECK(contains(run.err, "got 5"));
  }
  SECTION("NaN") {
    const Run run = run_cli({"predicate", "orient2d", "0", "0", "nan", "0", "0", "1"});
    CHECK(run.status == 2);
    check_one_error_line(run);
    CHECK(contains(run.err, "coordinate 3 'nan'"));
  }
  SECTION("infinity") {
    const Run run = run_cli({"predicate", "orient2d", "--", "0", "0", "1", "-inf", "0", "1"});
    CHECK(run.status == 2);
    check_one_error_line(run);
    CHECK(contains(run.err, "coordinate 4 '-inf'"));
  }
  SECTION("a coordinate that looks like an option") {
    const Run run = run_cli({"predicate", "orient2d", "0", "0", "1", "-inf", "0", "1"});
    CHECK(run.status == 2);
    check_one_error_line(run);
    CHECK(contains(run.err, "write -- before"));
  }
  SECTION("trailing garbage") {
    const Run run = run_cli({"predicate", "orient2d", "0", "0", "1", "0", "0", "1.5x"});
    CHECK(run.status == 2);
    check_one_error_line(run);
    CHECK(contains(run.err, "coordinate 6 '1.5x'"));
  }
  SECTION("overflow") {
    const Run run = run_cli({"predicate", "orient2d", "0", "0", "1e400", "0", "0", "1"});
    CHECK(run.status == 2);
    check_one_error_line(run);
    CHECK(contains(run.err, "'1e400'"));
  }
  SECTION("unknown predicate") {
    const Run run = run_cli({"predicate", "orient4d", "0", "0", "1", "0", "0", "1"});
    CHECK(run.status == 2);
    check_one_error_line(run);
    CHECK(contains(run.err, "orient4d"));
  }
  SECTION("wrong number of --sos indices") {
    const Run run = run_cli({"predicate", "orient2d", "0", "0", "1", "0", "0", "1", "--sos", "0"});
    CHECK(run.status == 2);
    check_one_error_line(run);
    CHECK(contains(run.err, "--sos takes 3 indices"));
  }
  SECTION("repeated --sos index") {
    const Run run =
        run_cli({"predicate", "orient2d", "0", "0", "1", "0", "0", "1", "--sos", "0", "1", "0"});
    CHECK(run.status == 2);
    check_one_error_line(run);
    CHECK(contains(run.err, "distinct"));
  }
  SECTION("negative --sos index") {
    const Run run =
        run_cli({"predicate", "orient2d", "0", "0", "1", "0", "0", "1", "--sos", "0", "1", "-2"});
    CHECK(run.status == 2);
    check_one_error_line(run);
    CHECK(contains(run.err, "'-2'"));
  }
}

TEST_CASE("predicate insphere: cospherical points are zero, --sos decides", "[apps][degenerate]") {
  // Five corners of the unit cube: all on the cube's circumsphere.
  const std::vector<double> c = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1};
  const Run exact = run_cli({"predicate", "insphere", "0", "0", "0", "1", "0", "0", "0", "1", "0",
                             "0", "0", "1", "1", "1", "1"});
  CHECK(exact.status == 0);
  CHECK(exact.out == "zero\n");

  const voroclip::Sign direct =
      voroclip::insphere_sos(&c[0], &c[3], &c[6], &c[9], &c[12], 0, 1, 2, 3, 4);
  REQUIRE(direct != voroclip::Sign::zero);
  const Run sos =
      run_cli({"predicate", "insphere", "0", "0", "0", "1",     "0", "0", "0", "1", "0", "0",
               "0",         "1",        "1", "1", "1", "--sos", "0", "1", "2", "3", "4"});
  CHECK(sos.status == 0);
  CHECK(sos.out == (direct == voroclip::Sign::positive ? "positive\n" : "negative\n"));

  const Run json = run_cli({"predicate", "insphere", "0", "0", "0", "1",       "0",   "0", "0",
                            "1",         "0",        "0", "0", "1", "1",       "1",   "1", "--sos",
                            "0",         "1",        "2", "3", "4", "--stats", "json"});
  CHECK(json.status == 0);
  const nlohmann::json stats = nlohmann::json::parse(json.out);
  CHECK(stats.at("predicate") == "insphere");
  CHECK(stats.at("sign") == static_cast<int>(direct));
  CHECK(stats.at("sos") == true);

  const Run plain_json = run_cli({"predicate", "insphere", "0", "0", "0", "1", "0", "0", "0", "1",
                                  "0", "0", "0", "1", "1", "1", "1", "--stats", "json"});
  CHECK(nlohmann::json::parse(plain_json.out) ==
        nlohmann::json::parse(
            R"({"command": "predicate", "ok": true, "predicate": "insphere", "sign": 0,
                "sos": false})"));
}

TEST_CASE("delaunay3d on random points: exact check, stats, VTK output", "[apps][delaunay]") {
  const std::string out = "test_cli_d3.vtk";
  std::remove(out.c_str());
  const Run run = run_cli(
      {"--stats", "json", "delaunay3d", "--random", "3000", "--seed", "7", "--check", "-o", out});
  REQUIRE(run.status == 0);
  const auto stats = nlohmann::json::parse(run.out);
  CHECK(stats["points"] == 3000);
  CHECK(stats["unique_points"] == 3000);
  CHECK(stats["check"] == "passed");
  CHECK(stats["tetrahedra"].get<int>() > 6 * 3000);
  CHECK(stats["peak_rss_bytes"].get<double>() > 0);
  const std::string vtk = slurp(out);
  CHECK(vtk.rfind("# vtk DataFile Version 3.0\n", 0) == 0);
  CHECK(contains(vtk, "CELLS " + std::to_string(stats["tetrahedra"].get<int>()) + " "));
  std::remove(out.c_str());
}

TEST_CASE("delaunay3d writes right-handed tets, as VTK and mesh3d have them", "[apps][delaunay]") {
  // The unit tet's corners: one tet, det(p1 - p0, p2 - p0, p3 - p0) must be > 0 (VTK's
  // convention: the first three counter-clockwise seen from the fourth). Before, the tets
  // were written as Delaunay3 stores them (det < 0), every one inverted for VTK.
  const std::string in = "test_cli_d3_four.txt", out = "test_cli_d3_four.vtk";
  {
    std::ofstream f(in);
    f << "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
  }
  std::remove(out.c_str());
  REQUIRE(run_cli({"-q", "delaunay3d", in, "-o", out}).status == 0);
  std::istringstream vtk(slurp(out));
  std::string word;
  while (vtk >> word && word != "CELLS") {
  }
  int cells = 0, entries = 0, per = 0;
  std::array<int, 4> v{};
  vtk >> cells >> entries >> per >> v[0] >> v[1] >> v[2] >> v[3];
  REQUIRE(cells == 1);
  REQUIRE(per == 4);
  const double p[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  double e[3][3];
  for (int k = 0; k < 3; ++k)
    for (int c = 0; c < 3; ++c) e[k][c] = p[v[k + 1]][c] - p[v[0]][c];
  const double det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                     e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                     e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
  CHECK(det == 1);
  // voroclip's own quality command reads it back with every tet right-handed.
  const Run q = run_cli({"quality", out});
  CHECK(q.status == 0);
  CHECK(contains(q.out + q.err, "det(p1-p0, p2-p0, p3-p0) > 0"));
  std::remove(in.c_str());
  std::remove(out.c_str());
}

TEST_CASE("delaunay2d on a grid file: the exact triangle count", "[apps][delaunay]") {
  // 10 x 10 integer grid: n' = 100 points, b = 36 on the hull boundary, so exactly
  // 2 n' - b - 2 = 162 triangles and no zero-area one.
  const std::string in = "test_cli_grid.txt";
  {
    std::ofstream f(in);
    f << "# a 10 x 10 grid\n";
    for (int x = 0; x < 10; ++x)
      for (int y = 0; y < 10; ++y) f << x << ' ' << y << '\n';
  }
  const Run run = run_cli({"--stats", "json", "delaunay2d", in, "--check"});
  REQUIRE(run.status == 0);
  const auto stats = nlohmann::json::parse(run.out);
  CHECK(stats["triangles"] == 162);
  CHECK(stats["hull_vertices"] == 36);
  std::remove(in.c_str());
}

TEST_CASE("delaunay3d reports bad input with file and line, and writes nothing",
          "[apps][delaunay]") {
  const std::string in = "test_cli_bad_points.txt";
  const std::string out = "test_cli_bad.vtk";
  std::remove(out.c_str());
  std::ofstream(in) << "0 0 0\n1 0 0\n0 1 0\n0 0 1 5\n";
  Run run = run_cli({"delaunay3d", in, "-o", out});
  CHECK(run.status == 1);
  check_one_error_line(run);
  CHECK(contains(run.err, in + ":4: more than 3 coordinates"));
  CHECK_FALSE(exists(out));
  std::ofstream(in) << "0 0 0\n1 0 0\n2 0 0\n3 0 0\n";  // collinear: no tetrahedron
  run = run_cli({"delaunay3d", in, "-o", out});
  CHECK(run.status == 1);
  check_one_error_line(run);
  CHECK(contains(run.err, "affinely independent"));
  CHECK_FALSE(exists(out));
  run = run_cli({"delaunay3d"});
  CHECK(run.status == 2);
  check_one_error_line(run);
  run = run_cli({"delaunay3d", "--random", "10", "-o", "x.obj"});
  CHECK(run.status == 2);
  check_one_error_line(run);
  std::remove(in.c_str());
}

TEST_CASE("an output in a missing directory fails before any work", "[apps]") {
  const std::string data = VOROCLIP_SHARED_DATA_DIR;
  const std::string bunny = data + "/surfaces/bunny.obj";
  const std::vector<std::vector<std::string>> commands = {
      {"mesh3d", bunny, "--vertices", "2000", "-o", "/nonexistent/dir/out.mesh"},
      {"clip3d", bunny, "--random", "1000", "-o", "/nonexistent/dir/cells.vtu"},
      {"delaunay3d", "--random", "1000", "-o", "/nonexistent/dir/dt.vtk"},
      {"demo", "-o", "/nonexistent/dir/demo.svg"},
  };
  for (const std::vector<std::string>& c : commands) {
    INFO(c[0]);
    const Run run = run_cli(c);
    CHECK(run.status == 1);
    CHECK(contains(run.err, "cannot write '/nonexistent/dir/"));
    CHECK(contains(run.err, "no directory '/nonexistent/dir'"));
    CHECK(run.out.empty());  // no progress, no report: nothing was computed
  }
}

TEST_CASE("an output where no file can be created fails before any work", "[apps][regression]") {
  // The check was access(dir, W_OK), which root passes for /proc: mesh3d ran to its end and
  // failed writing. The temporary file is now created and removed: the output's error
  // comes before the domain (which does not exist) is even read.
  for (const std::string out : {"/proc/out.mesh", "/proc/out.node", "/proc/out.vtu"}) {
    INFO(out);
    const Run run = run_cli({"mesh3d", "no-such-domain.obj", "--vertices", "300", "-o", out});
    CHECK(run.status == 1);
    check_one_error_line(run);
    CHECK(contains(run.err, "cannot write '/proc/out."));
    CHECK_FALSE(contains(run.err, "no-such-domain"));
  }
}

TEST_CASE("mesh3d -o FILE.node: TetGen's three files checked first, written together",
          "[apps][regression]") {
  // With a directory named like the .face, the .node and .ele were written and left behind
  // (the exit status 1 came after the whole run).
  const std::string dir = temp_path("_tetgen");
  REQUIRE(::mkdir(dir.c_str(), 0755) == 0);
  const std::string base = dir + "/tg";
  REQUIRE(::mkdir((base + ".face").c_str(), 0755) == 0);
  const std::string sphere = std::string(VOROCLIP_SHARED_DATA_DIR) + "/surfaces/sphere.obj";
  for (const char* ext : {".node", ".ele"}) {
    INFO(ext);
    const Run run = run_cli({"mesh3d", sphere, "--vertices", "300", "-o", base + ext});
    CHECK(run.status == 1);
    check_one_error_line(run);
    CHECK(contains(run.err, "cannot write '" + base + ".face': it is a directory"));
    CHECK_FALSE(exists(base + ".node"));
    CHECK_FALSE(exists(base + ".ele"));
  }
  REQUIRE(::rmdir((base + ".face").c_str()) == 0);
  const Run run = run_cli({"-q", "mesh3d", sphere, "--vertices", "300", "-o", base + ".ele"});
  REQUIRE(run.status == 0);
  const voroclip::TetMeshInput mesh = voroclip::read_tet_mesh(base + ".node");
  CHECK(mesh.nb_tets() > 0);
  CHECK(mesh.nb_triangles() > 0);  // from tg.face
  for (const char* ext : {".node", ".ele", ".face"}) std::remove((base + ext).c_str());
  ::rmdir(dir.c_str());
}

TEST_CASE("two outputs naming one file: a usage error before any work", "[apps][regression]") {
  // clip3d -o x.csv --neighbors x.csv exited 0 with the pairs table in x.csv.
  const std::string data = VOROCLIP_SHARED_DATA_DIR;
  const std::string sphere = data + "/surfaces/sphere.obj";
  const std::string polygon = data + "/polygons/valid/issue35.json";
  const std::string csv = temp_path(".csv"), json = temp_path(".json");
  const std::vector<std::vector<std::string>> commands = {
      {"clip3d", sphere, "--random", "100", "-o", csv, "--neighbors", csv},
      {"clip3d", sphere, "--random", "100", "-o", json, "--neighbors", "./" + json},
      {"clip2d", polygon, "--random", "10", "-o", csv, "--neighbors", csv},
      {"cvt2d", polygon, "--random", "10", "-o", json, "--neighbors", "../" + json},
  };
  for (std::vector<std::string> c : commands) {
    if (c.back().rfind("../", 0) == 0) {
      // The same file through its directory's parent.
      char cwd[4096];
      REQUIRE(::getcwd(cwd, sizeof cwd) != nullptr);
      const std::string here = cwd;
      c.back() = "../" + here.substr(here.find_last_of('/') + 1) + "/" + json;
    }
    INFO(c[0] << " " << c.back());
    const Run run = run_cli(c);
    CHECK(run.status == 2);
    check_one_error_line(run);
    CHECK(contains(run.err, "-o and --neighbors both name"));
    CHECK_FALSE(exists(csv));
    CHECK_FALSE(exists(json));
  }
}

TEST_CASE("messages say what the command line calls things", "[apps][regression]") {
  // Library API names and printf artefacts had leaked into the error lines.
  SECTION("an inside-out surface: --reorient, not Surface3Options::reorient") {
    const std::string obj = temp_path(".obj");
    std::ofstream(obj) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                          "f 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n";
    for (const char* command : {"check-surface", "clip3d"}) {
      INFO(command);
      const Run run = std::string(command) == "clip3d" ? run_cli({command, obj, "--random", "10"})
                                                       : run_cli({command, obj});
      CHECK(run.status == 1);
      check_one_error_line(run);
      CHECK(contains(run.err, "the surface is inside out"));
      CHECK(contains(run.err, "(--reorient)"));
      CHECK_FALSE(contains(run.err, "::"));
    }
    const Run json = run_cli({"--stats", "json", "check-surface", obj});
    CHECK_FALSE(contains(nlohmann::json::parse(json.out)["error"].get<std::string>(), "::"));
    std::remove(obj.c_str());
  }
  SECTION("delaunay3d: too few points, or all in a plane") {
    const std::string one = temp_path(".txt"), plane = temp_path(".txt");
    std::ofstream(one) << "0 0 0\n";
    std::ofstream(plane) << "0 0 0\n1 0 0\n0 1 0\n1 1 0\n";
    const Run few = run_cli({"delaunay3d", one});
    CHECK(few.status == 1);
    check_one_error_line(few);
    CHECK(contains(few.err, one + ": 1 point; delaunay3d needs at least 4 points"));
    const Run flat = run_cli({"delaunay3d", plane});
    CHECK(flat.status == 1);
    check_one_error_line(flat);
    CHECK(contains(flat.err, plane + ": all points are coplanar"));
    CHECK(contains(flat.err, "clip3d takes them"));
    for (const Run* r : {&few, &flat}) {
      CHECK_FALSE(contains(r->err, "Delaunay3"));
      CHECK_FALSE(contains(r->err, "::"));
    }
    const Run random = run_cli({"delaunay2d", "--random", "2"});
    CHECK(random.status == 1);
    CHECK(contains(random.err, "--random 2: 2 points; delaunay2d needs at least 3 points"));
    std::remove(one.c_str());
    std::remove(plane.c_str());
  }
  SECTION("a directory given as the input") {
    const std::string dir = temp_path(".obj");
    REQUIRE(::mkdir(dir.c_str(), 0755) == 0);
    const Run run = run_cli({"check-surface", dir});
    CHECK(run.status == 1);
    check_one_error_line(run);
    CHECK(contains(run.err, dir + ": is a directory, not a file"));
    ::rmdir(dir.c_str());
  }
  SECTION("cvt3d -o FILE.obj: the header names cvt3d") {
    const std::string sphere = std::string(VOROCLIP_SHARED_DATA_DIR) + "/surfaces/sphere.obj";
    const std::string obj = temp_path(".obj");
    const Run run =
        run_cli({"-q", "cvt3d", sphere, "--random", "20", "--iterations", "1", "-o", obj});
    REQUIRE(run.status == 0);
    const std::string text = slurp(obj);
    CHECK(text.rfind("# voroclip cvt3d: restricted Voronoi diagram", 0) == 0);
    std::remove(obj.c_str());
  }
  SECTION("mesh3d --msh-version without a .msh output, as --binary") {
    const std::string sphere = std::string(VOROCLIP_SHARED_DATA_DIR) + "/surfaces/sphere.obj";
    const std::string mesh = temp_path(".mesh");
    for (const char* option : {"--binary", "--msh-version"}) {
      INFO(option);
      std::vector<std::string> args = {"mesh3d", sphere, "--vertices", "100", "-o", mesh, option};
      if (std::string(option) == "--msh-version") args.push_back("2.2");
      const Run run = run_cli(args);
      CHECK(run.status == 2);
      check_one_error_line(run);
      CHECK(contains(run.err, std::string(option) + ": only a .msh output"));
      CHECK_FALSE(exists(mesh));
    }
  }
}

TEST_CASE("the sites and cell tables the commands write read back as --sites",
          "[apps][regression]") {
  // cvt3d -o sites.csv wrote an x,y,z header and commas that --sites rejected
  // ("'x,y,z' is not a number").
  const std::string sphere = std::string(VOROCLIP_SHARED_DATA_DIR) + "/surfaces/sphere.obj";
  for (const char* ext : {".csv", ".txt"}) {
    INFO(ext);
    const std::string sites = temp_path(ext), cells = temp_path(".csv"), again = temp_path(".csv");
    REQUIRE(run_cli({"-q", "cvt3d", sphere, "--random", "20", "--iterations", "2", "-o", sites})
                .status == 0);
    const std::vector<double> xyz = voroclip::read_points(sites, 3);
    CHECK(xyz.size() == 60);
    const Run clip = run_cli({"-q", "clip3d", sphere, "--sites", sites, "-o", cells});
    CHECK(clip.status == 0);
    CHECK(clip.err.empty());
    // The cell table's x, y, z columns are the sites, and read back as sites in turn.
    CHECK(voroclip::read_points(cells, 3) == xyz);
    CHECK(run_cli({"-q", "clip3d", sphere, "--sites", cells, "-o", again}).status == 0);
    CHECK(slurp(again) == slurp(cells));
    const Run delaunay = run_cli({"--stats", "json", "delaunay3d", sites});
    CHECK(delaunay.status == 0);
    CHECK(nlohmann::json::parse(delaunay.out)["points"] == 20);
    for (const std::string& f : {sites, cells, again}) std::remove(f.c_str());
  }
  const std::string sites2 = temp_path(".txt"), cells2 = temp_path(".csv");
  REQUIRE(run_cli({"-q", "cvt2d", "annulus:1,2,64", "--random", "10", "--iterations", "2", "-o",
                   sites2})
              .status == 0);
  CHECK(run_cli({"-q", "clip2d", "annulus:1,2,64", "--sites", sites2, "-o", cells2}).status == 0);
  CHECK(voroclip::read_points(cells2, 2) == voroclip::read_points(sites2, 2));
  CHECK(run_cli({"-q", "cvt2d", "annulus:1,2,64", "--sites", cells2, "--iterations", "1"}).status ==
        0);
  std::remove(sites2.c_str());
  std::remove(cells2.c_str());
}

TEST_CASE("a directory as a 3D domain is named as a directory", "[apps][regression]") {
  // "unknown 3D domain format ''" for a directory without an extension.
  const std::string dir = temp_path("");
  REQUIRE(::mkdir(dir.c_str(), 0755) == 0);
  for (const char* command : {"check-surface", "clip3d", "cvt3d", "mesh3d"}) {
    INFO(command);
    std::vector<std::string> args = {command, dir};
    if (std::string(command) != "check-surface") {
      args.insert(args.end(), {"--random", "5"});
    }
    if (std::string(command) == "mesh3d") args = {command, dir, "--vertices", "100"};
    const Run run = run_cli(args);
    CHECK(run.status == 1);
    check_one_error_line(run);
    CHECK(contains(run.err, dir + ": is a directory, not a file"));
  }
  ::rmdir(dir.c_str());
}

TEST_CASE("A failure with --stats json prints one JSON object: ok false and the error line",
          "[apps][regression]") {
  // A failed command printed nothing on stdout with --stats json: a script parsing it got an
  // empty string. Now every command, whatever failed (the command line, an input file, an
  // output path), prints {"command", "ok": false, "error"}; the error is the stderr line's.
  const std::string missing = temp_path(".json");  // no such file
  const std::string out = temp_path("");
  const std::string no_dir = out + "/x";  // in a directory that does not exist
  const std::string bad_poly = temp_path(".poly");
  std::ofstream(bad_poly) << "3 2 0 0\n1 0 0\n2 1 0\n";  // the third vertex is missing
  struct Case {
    std::string command;  // "" for none
    std::vector<std::string> args;
    int status;
    std::string in_error;  // a piece of the message
    std::string output;    // a file that must not be written; "" for none
  };
  const std::vector<Case> cases = {
      {"demo", {"demo", "-o", no_dir + ".svg"}, 1, "cannot write", no_dir + ".svg"},
      {"predicate", {"predicate", "orient2d", "0", "0", "1"}, 2, "orient2d", ""},
      {"delaunay2d", {"delaunay2d", missing}, 1, missing, ""},
      {"delaunay3d", {"delaunay3d", "--random", "x"}, 2, "--random", ""},
      {"clip2d",
       {"clip2d", missing, "--random", "10", "-o", out + ".svg"},
       1,
       missing,
       out + ".svg"},
      {"cvt2d", {"cvt2d", "square-holes:2,0.4", "--iterations", "-1"}, 2, "--iterations", ""},
      {"mesh2d",
       {"mesh2d", bad_poly, "--vertices", "100", "-o", out + ".vtu"},
       1,
       bad_poly,
       out + ".vtu"},
      {"mesh2d", {"mesh2d", "square-holes:2,0.4"}, 2, "--vertices", ""},
      {"clip3d", {"clip3d", missing + ".obj", "--random", "10"}, 1, missing, ""},
      {"cvt3d",
       {"cvt3d", missing + ".obj", "--random", "10", "-o", out + ".vtu"},
       1,
       missing,
       out + ".vtu"},
      {"quality", {"quality", missing + ".mesh"}, 1, missing, ""},
      {"mesh3d",
       {"mesh3d", missing + ".obj", "--vertices", "100", "-o", out + ".mesh"},
       1,
       missing,
       out + ".mesh"},
      {"check-surface", {"check-surface", missing + ".obj"}, 1, missing, ""},
      {"", {"no-such-command"}, 2, "unknown command 'no-such-command'", ""},
  };
  for (const Case& c : cases) {
    for (const bool before : {true, false}) {  // --stats json before or after the command
      std::vector<std::string> args = c.args;
      args.insert(before ? args.begin() : args.end(), {"--stats", "json"});
      const Run run = run_cli(args);
      CHECK(run.status == c.status);
      REQUIRE(std::count(run.out.begin(), run.out.end(), '\n') == 1);
      const nlohmann::json j = nlohmann::json::parse(run.out);
      CHECK(j.at("ok") == false);
      CHECK(j.at("command") ==
            (c.command.empty() ? nlohmann::json(nullptr) : nlohmann::json(c.command)));
      const std::string error = j.at("error").get<std::string>();
      CHECK(run.err == "voroclip: error: " + error + "\n");
      CHECK(contains(error, c.in_error));
      if (!c.output.empty()) CHECK(!exists(c.output));
      if (c.command == "check-surface") CHECK(j.at("valid") == false);
    }
  }
  // Without --stats json a failure prints nothing on stdout, as before.
  check_one_error_line(run_cli({"delaunay2d", missing}));
  // A success says the same two keys first.
  const Run ok = run_cli({"--stats", "json", "delaunay2d", "--random", "10"});
  REQUIRE(ok.status == 0);
  CHECK(ok.out.rfind(R"({"command":"delaunay2d","ok":true,)", 0) == 0);
  std::remove(bad_poly.c_str());
}
