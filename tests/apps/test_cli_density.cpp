// cvt3d, and the user's density and sizing (--density, --density-file, --sizing,
// --sizing-file) on cvt2d, cvt3d, mesh2d and mesh3d (issue 35): progress and stop
// reason, the result is a CVT, 1 vs 2 threads and CLI vs library bit for bit, masses
// against exact integrals, edge lengths against h(x), and the errors.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_run.h"
#include "voroclip/core.h"
#include "voroclip/cvt.h"

namespace {

const std::string kData = VOROCLIP_SHARED_DATA_DIR;

// A file removed when the test ends.
struct TempFile {
  std::string path;
  explicit TempFile(const std::string& suffix, const std::string& text = "")
      : path(temp_path(suffix)) {
    if (!text.empty()) std::ofstream(path) << text;
  }
  ~TempFile() { std::remove(path.c_str()); }
};

const char* kCubeObj =
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n"
    "f 1 3 4\nf 1 4 2\nf 5 6 8\nf 5 8 7\nf 1 2 6\nf 1 6 5\n"
    "f 3 7 8\nf 3 8 4\nf 1 5 7\nf 1 7 3\nf 2 4 8\nf 2 8 6\n";

std::vector<double> read_numbers(const std::string& text) {
  std::istringstream in(text);
  std::vector<double> v;
  for (double x; in >> x;) v.push_back(x);
  return v;
}

// "iteration    0  energy E ..." from the progress lines.
std::vector<double> progress_energies(const std::string& err) {
  std::vector<double> e;
  std::istringstream in(err);
  for (std::string line; std::getline(in, line);) {
    // The progress printer's lines: "  CVT (lbfgs) iteration 3/500  energy ...".
    if (line.find(" iteration ") == std::string::npos) continue;
    const std::size_t k = line.find("energy ");
    if (k != std::string::npos) e.push_back(std::stod(line.substr(k + 7)));
  }
  return e;
}

// A legacy VTK STRUCTURED_POINTS grid of f over [0, 1]^d with n points per side.
std::string vtk_grid(int d, int n, const std::function<double(double, double, double)>& f) {
  std::ostringstream s;
  s << std::setprecision(17) << "# vtk DataFile Version 3.0\ntest grid\nASCII\n"
    << "DATASET STRUCTURED_POINTS\nDIMENSIONS " << n << ' ' << n << ' ' << (d == 3 ? n : 1)
    << "\nORIGIN 0 0 0\nSPACING " << 1.0 / (n - 1) << ' ' << 1.0 / (n - 1) << " 1\n"
    << "POINT_DATA " << n * n * (d == 3 ? n : 1) << "\nSCALARS rho double 1\n"
    << "LOOKUP_TABLE default\n";
  for (int k = 0; k < (d == 3 ? n : 1); ++k) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        s << f(i / (n - 1.0), j / (n - 1.0), k / (n - 1.0)) << '\n';
      }
    }
  }
  return s.str();
}

}  // namespace

TEST_CASE("cvt3d: the default budget reaches the default tolerance, as cvt2d's",
          "[apps][density][regression]") {
  // The budget was 100 iterations (cvt2d's 1000): 200 random sites in the sphere need 145
  // to reach |g| <= 1e-4 |g0|, and 1000 in the bunny 319; they stopped unconverged.
  const Run run = run_cli({"cvt3d", kData + "/surfaces/sphere.obj", "--random", "200", "--stats",
                           "json", "--progress", "none"});
  REQUIRE(run.status == 0);
  const nlohmann::json s = nlohmann::json::parse(run.out);
  CHECK(s["converged"] == true);
  CHECK(s["stop"] == "converged");
  CHECK(s["iterations"].get<int>() > 100);
  CHECK(s["gradient_norm"].get<double>() <= 1e-4 * s["initial_gradient_norm"].get<double>());
}

TEST_CASE("cvt3d: progress, stop reason, the sites are a CVT", "[apps][density]") {
  const TempFile cube(".obj", kCubeObj);
  const TempFile sites(".txt");
  const Run run = run_cli({"cvt3d", cube.path, "--random", "300", "--tolerance", "1e-3",
                           "--iterations", "500", "--stats", "json", "-o", sites.path});
  REQUIRE(run.status == 0);
  const nlohmann::json s = nlohmann::json::parse(run.out);
  CHECK(s["sites"] == 300);
  CHECK(s["converged"] == true);
  CHECK(s["stop"] == "converged");
  CHECK(s["gradient_norm"].get<double>() <= 1e-3 * s["initial_gradient_norm"].get<double>());
  // Progress on the human stream; the energy goes down.
  const std::vector<double> energies = progress_energies(run.err);
  REQUIRE(energies.size() >= 2);
  CHECK(s["energy"].get<double>() < energies.front());
  CHECK(contains(run.err, "stopped: converged"));
  // The final cells: each site near its cell's centroid (relative to the cell's size);
  // the random start is far from that, so the check can fail.
  const auto worst_offset = [&](const std::string& site_file) {
    const TempFile cells(".json");
    const Run c = run_cli({"-q", "clip3d", cube.path, "--sites", site_file, "-o", cells.path});
    REQUIRE(c.status == 0);
    const nlohmann::json j = nlohmann::json::parse(slurp(cells.path));
    REQUIRE(j["cells"].size() == 300);
    double worst = 0;
    for (const nlohmann::json& cell : j["cells"]) {
      double d2 = 0;
      for (int k = 0; k < 3; ++k) {
        const double dk = cell["site"][k].get<double>() - cell["centroid"][k].get<double>();
        d2 += dk * dk;
      }
      worst = std::max(worst, std::sqrt(d2) / std::cbrt(cell["volume"].get<double>()));
    }
    return worst;
  };
  CHECK(worst_offset(sites.path) < 0.02);
  const TempFile start(".txt");
  REQUIRE(run_cli({"cvt3d", cube.path, "--random", "300", "--iterations", "1", "--method", "lloyd",
                   "-q", "-o", start.path})
              .status == 0);
  CHECK(worst_offset(start.path) > 0.1);
  // Budget and output kinds.
  const Run budget =
      run_cli({"cvt3d", cube.path, "--random", "100", "--iterations", "2", "--stats", "json"});
  REQUIRE(budget.status == 0);
  CHECK(nlohmann::json::parse(budget.out)["stop"] == "iteration budget");
  for (const char* ext : {".csv", ".vtu", ".json", ".obj"}) {
    const TempFile out(ext);
    const Run w =
        run_cli({"-q", "cvt3d", cube.path, "--random", "50", "--iterations", "3", "-o", out.path});
    CHECK(w.status == 0);
    const std::string text = slurp(out.path);
    CHECK(!text.empty());
    if (std::string(ext) == ".csv") CHECK(std::count(text.begin(), text.end(), '\n') == 51);
    if (std::string(ext) == ".json") CHECK(nlohmann::json::parse(text)["cells"].size() == 50);
  }
}

TEST_CASE("cvt3d / cvt2d --iterations 0 and 1: the start sites; the counts in the report",
          "[apps][density][regression]") {
  // L-BFGS with --iterations 0 made one iteration and moved the sites; cvt3d's report (on
  // stdout without --stats) said "1 iterations" and "1 diagrams".
  const TempFile cube(".obj", kCubeObj);
  const TempFile square(".json", "[[[0,0],[1,0],[1,1],[0,1]]]");
  struct Case {
    const char* command;
    const TempFile& domain;
    std::string sites;
  };
  for (const Case& c :
       {Case{"cvt3d", cube, "0.1 0.2 0.3\n0.7 0.6 0.4\n0.3 0.8 0.9\n0.55 0.25 0.65\n"},
        Case{"cvt2d", square, "0.1 0.2\n0.7 0.6\n0.3 0.8\n0.55 0.25\n"}}) {
    for (const char* method : {"lbfgs", "lloyd"}) {
      INFO(c.command << " --method " << method);
      const TempFile start(".txt", c.sites);
      const TempFile out(".txt");
      const Run zero = run_cli({c.command, c.domain.path, "--sites", start.path, "--method", method,
                                "--iterations", "0", "--progress", "none", "-o", out.path});
      REQUIRE(zero.status == 0);
      CHECK(read_numbers(slurp(out.path)) == read_numbers(c.sites));
      CHECK(slurp(out.path) == c.sites);  // the shortest decimals: "0.1", not 0.10000000000000001
      CHECK(contains(zero.out, "0 iterations, 1 diagram, "));
      CHECK(contains(zero.out, "stopped: iteration budget"));
      const Run one = run_cli({c.command, c.domain.path, "--sites", start.path, "--method", method,
                               "--iterations", "1", "--progress", "none", "-o", out.path});
      REQUIRE(one.status == 0);
      CHECK(contains(one.out, "1 iteration, "));
      CHECK(!contains(one.out, "1 iterations"));
      CHECK(read_numbers(slurp(out.path)) != read_numbers(c.sites));
    }
  }
}

TEST_CASE("cvt3d: a cube scaled by 1e-300 (volume 0) is an error naming the fix",
          "[apps][density][regression]") {
  // It was a valid surface whose volume underflows to 0: cvt3d printed "stopped: converged"
  // after 0 iterations. Now the surface is an error.
  std::string obj;
  for (const char* v : {"0 0 0", "1 0 0", "0 1 0", "1 1 0", "0 0 1", "1 0 1", "0 1 1", "1 1 1"}) {
    std::istringstream in(v);
    obj += "v";
    for (double x; in >> x;) obj += x == 0 ? " 0" : " 1e-300";
    obj += "\n";
  }
  obj += std::string(kCubeObj).substr(std::string(kCubeObj).find("f "));
  const TempFile tiny(".obj", obj);
  const Run run = run_cli({"cvt3d", tiny.path, "--random", "20", "--progress", "none"});
  CHECK(run.status != 0);
  CHECK(contains(run.err, "its volume is 0 in double precision"));
  CHECK(contains(run.err, "too small"));
  CHECK(contains(run.err, "rescale the model"));
  CHECK(!contains(run.err, "converged"));
}

TEST_CASE("cvt3d: identical with 1 and 2 threads, and to the library's CVT",
          "[apps][density][threads]") {
  const TempFile cube(".obj", kCubeObj);
  const TempFile a(".txt"), b(".txt");
  for (const std::string& density : {std::string(), std::string("1 + 10*x")}) {
    INFO("density '" << density << "'");
    std::vector<std::string> args = {"-q",     "cvt3d", cube.path,      "--random", "200",
                                     "--seed", "7",     "--iterations", "20"};
    if (!density.empty()) args.insert(args.end(), {"--density", density});
    std::vector<std::string> one = args, two = args;
    one.insert(one.end(), {"--threads", "1", "-o", a.path});
    two.insert(two.end(), {"--threads", "2", "-o", b.path});
    REQUIRE(run_cli(one).status == 0);
    REQUIRE(run_cli(two).status == 0);
    const std::string sa = slurp(a.path);
    CHECK(!sa.empty());
    CHECK(sa == slurp(b.path));
    // The library from the same start: random_points3 with the draw cvt3d documents.
    const voroclip::Domain3 domain = voroclip::read_domain3(cube.path);
    voroclip::Cvt3Options o;
    o.max_iterations = 20;
    voroclip::Density3 draw;
    if (!density.empty()) {
      o.clip.density =
          voroclip::Density3::function([](double x, double, double) { return 1 + 10 * x; });
      draw = voroclip::Density3::function(
          [](double x, double, double) { return std::pow(1 + 10 * x, 0.6); });
    }
    std::vector<double> sites = voroclip::random_points3(domain, 200, 7, draw);
    voroclip::optimize_cvt3(domain, sites, o);
    // 17 significant digits read back as the same doubles.
    CHECK(read_numbers(sa) == sites);
  }
}

TEST_CASE("cvt2d / cvt3d --density and --density-file: masses are the exact integrals",
          "[apps][density]") {
  // rho = 1 + 10x: 6 over the unit square and the unit cube, integrated exactly (linear),
  // as a formula and as a grid file.
  const TempFile square(".json", "[[[0,0],[1,0],[1,1],[0,1]]]");
  const auto f = [](double x, double, double) { return 1 + 10 * x; };
  const TempFile grid2(".vtk", vtk_grid(2, 5, f));
  const TempFile out2(".json");
  for (const std::vector<std::string>& option :
       {std::vector<std::string>{"--density", "1+10*x"}, {"--density-file", grid2.path}}) {
    INFO(option[0]);
    std::vector<std::string> args = {"-q",           "cvt2d", square.path, "--random", "100",
                                     "--iterations", "5",     "-o",        out2.path};
    args.insert(args.end(), option.begin(), option.end());
    REQUIRE(run_cli(args).status == 0);
    double mass = 0;
    const nlohmann::json cells = nlohmann::json::parse(slurp(out2.path))["cells"];
    for (const nlohmann::json& c : cells) {
      mass += c["mass"].get<double>();
    }
    CHECK(mass == Approx(6).epsilon(1e-12));
  }
  const TempFile cube(".obj", kCubeObj);
  const TempFile grid3(".vtk", vtk_grid(3, 3, f));
  const TempFile out3(".json");
  for (const std::vector<std::string>& option :
       {std::vector<std::string>{"--density", "1+10*x"}, {"--density-file", grid3.path}}) {
    INFO(option[0]);
    std::vector<std::string> args = {"-q",           "cvt3d", cube.path, "--random", "100",
                                     "--iterations", "5",     "-o",      out3.path};
    args.insert(args.end(), option.begin(), option.end());
    REQUIRE(run_cli(args).status == 0);
    double mass = 0;
    const nlohmann::json cells = nlohmann::json::parse(slurp(out3.path))["cells"];
    for (const nlohmann::json& c : cells) {
      mass += c["mass"].get<double>();
    }
    CHECK(mass == Approx(6).epsilon(1e-12));
  }
}

TEST_CASE("cvt3d --density-file .sol on a tet mesh: linear per tet, exact mass",
          "[apps][density]") {
  const std::string mesh = kData + "/tetmeshes/sphere.mesh";
  const voroclip::TetMeshInput m = voroclip::read_tet_mesh(mesh);
  std::ostringstream sol;
  sol << std::setprecision(17) << "MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n"
      << m.nb_vertices() << "\n1 1\n";
  for (std::uint32_t v = 0; v < m.nb_vertices(); ++v) sol << 2 + m.xyz[3 * v] << '\n';
  sol << "End\n";
  const TempFile file(".sol", sol.str());
  // The exact integral of 2 + x over the tets.
  double exact = 0;
  for (std::uint32_t t = 0; t < m.nb_tets(); ++t) {
    const double* p[4];
    for (int k = 0; k < 4; ++k) p[k] = &m.xyz[3 * std::size_t{m.tets[4 * t + k]}];
    double e[3][3];
    for (int k = 0; k < 3; ++k) {
      for (int c = 0; c < 3; ++c) e[k][c] = p[k + 1][c] - p[0][c];
    }
    const double vol = std::fabs(e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                                 e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                                 e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0])) /
                       6;
    exact += vol * (2 + (p[0][0] + p[1][0] + p[2][0] + p[3][0]) / 4);
  }
  const TempFile out(".json");
  const Run run = run_cli({"-q", "cvt3d", mesh, "--random", "200", "--iterations", "3",
                           "--density-file", file.path, "-o", out.path});
  REQUIRE(run.status == 0);
  double mass = 0;
  const nlohmann::json cells = nlohmann::json::parse(slurp(out.path))["cells"];
  for (const nlohmann::json& c : cells) {
    mass += c["mass"].get<double>();
  }
  CHECK(mass == Approx(exact).epsilon(1e-11));
  // A .sol of another mesh: the error names the file and line.
  const TempFile wrong(
      ".sol", "MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n4\n1 1\n1\n2\n3\n4\nEnd\n");
  const TempFile none(".json");
  const Run bad =
      run_cli({"cvt3d", mesh, "--random", "20", "--density-file", wrong.path, "-o", none.path});
  CHECK(bad.status == 1);
  check_one_error_line(bad);
  CHECK(contains(bad.err, wrong.path + ":4"));
  CHECK(contains(bad.err, "SolAtVertices has 4 values"));
  CHECK(!exists(none.path));
}

TEST_CASE("--density / --sizing errors: position in the formula, the point, no file",
          "[apps][density]") {
  const TempFile cube(".obj", kCubeObj);
  const TempFile square(".json", "[[[0,0],[1,0],[1,1],[0,1]]]");
  const TempFile out(".txt"), svg(".svg");
  struct Case {
    std::vector<std::string> args;
    int status;
    std::vector<std::string> says;
  };
  const std::vector<Case> cases = {
      {{"cvt3d", cube.path, "--random", "20", "--density", "1+*x"}, 2, {"position 2", "1+*x"}},
      {{"cvt3d", cube.path, "--random", "20", "--density", "1 + w"}, 2, {"\"w\"", "position 4"}},
      {{"cvt2d", square.path, "--random", "20", "--density", "x + z"}, 2, {"\"z\"", "position 4"}},
      {{"cvt2d", square.path, "--random", "20", "--density", "  "}, 2, {"empty"}},
      {{"cvt3d", cube.path, "--random", "20", "--density", "x - 0.5"},
       1,
       {"--density \"x - 0.5\" is -", " at (", "finite and positive"}},
      {{"cvt2d", square.path, "--random", "20", "--density", "1/(x-x)"}, 1, {"inf", "at ("}},
      {{"cvt3d", cube.path, "--random", "20", "--density", "1", "--density-file", "a.vtk"},
       2,
       {"excludes"}},
      {{"cvt3d", cube.path, "--random", "20", "--density-file", "/nonexistent.vtk"},
       1,
       {"/nonexistent.vtk"}},
      {{"cvt3d", cube.path, "--random", "20", "--density-file", cube.path}, 2, {".sol"}},
      {{"mesh2d", square.path, "-q", "--sizing", "0", "--vertices", "50"},
       1,
       {"--sizing \"0\" is 0"}},
  };
  for (const Case& c : cases) {
    std::vector<std::string> args = c.args;
    const std::string& file = args[0] == "mesh2d" ? svg.path : out.path;
    args.insert(args.end(), {"-o", file});
    const Run run = run_cli(args);
    CHECK(run.status == c.status);
    check_one_error_line(run);
    for (const std::string& s : c.says) CHECK(contains(run.err, s));
    CHECK(!exists(file));
  }
  // A grid file with a bad value names its line.
  const TempFile grid(".vtk",
                      "# vtk DataFile Version 3.0\ng\nASCII\nDATASET STRUCTURED_POINTS\n"
                      "DIMENSIONS 2 2 1\nORIGIN 0 0 0\nSPACING 1 1 1\nPOINT_DATA 4\n"
                      "SCALARS rho double\nLOOKUP_TABLE default\n1\n2\n-3\n4\n");
  const Run run = run_cli({"cvt2d", square.path, "--random", "20", "--density-file", grid.path});
  CHECK(run.status == 1);
  check_one_error_line(run);
  CHECK(contains(run.err, grid.path + ":13: value 3 is -3"));
  // A grid of 2^30 points in a file of four values: refused before 8 GB are allocated.
  const TempFile huge(".vtk",
                      "# vtk DataFile Version 3.0\ng\nASCII\nDATASET STRUCTURED_POINTS\n"
                      "DIMENSIONS 1024 1024 1024\nPOINT_DATA 1073741824\n"
                      "SCALARS rho double 1\nLOOKUP_TABLE default\n1\n2\n3\n4\n");
  const Run big = run_cli({"cvt3d", cube.path, "--random", "20", "--density-file", huge.path});
  CHECK(big.status == 1);
  check_one_error_line(big);
  CHECK(contains(big.err, huge.path + ":9: POINT_DATA 1073741824: the file has 4 values left"));
  // Two SCALARS arrays (regression: the first was used without a word): an error naming both,
  // at the second's line, for --sizing-file as for --density-file.
  const TempFile two(".vtk",
                     "# vtk DataFile Version 3.0\ng\nASCII\nDATASET STRUCTURED_POINTS\n"
                     "DIMENSIONS 2 2 1\nORIGIN 0 0 0\nSPACING 1 1 1\nPOINT_DATA 4\n"
                     "SCALARS h double\nLOOKUP_TABLE default\n1\n2\n3\n4\n"
                     "SCALARS rho double 1\nLOOKUP_TABLE default\n1\n1\n1\n1\n");
  for (const char* option : {"--density-file", "--sizing-file"}) {
    INFO(option);
    const bool sizing = option[2] == 's';
    const Run both =
        sizing
            ? run_cli({"mesh2d", square.path, "-q", option, two.path, "--vertices", "50", "-o",
                       svg.path})
            : run_cli({"cvt2d", square.path, "--random", "20", option, two.path, "-o", out.path});
    CHECK(both.status == 1);
    check_one_error_line(both);
    CHECK(contains(both.err, two.path + ":15: the grid has 2 SCALARS arrays, 'h' and 'rho': " +
                                 "which one is the " + (sizing ? "size" : "density") +
                                 " is ambiguous"));
    CHECK(!exists(out.path));
    CHECK(!exists(svg.path));
  }
}

TEST_CASE("mesh2d --sizing: edge lengths follow h(x) (median ratio within 10 %)",
          "[apps][density]") {
  // h = 0.01 + 0.1 |x| on the unit square; without --vertices / --edge-length the sizing is
  // the edge length itself. Median of |e| / h(midpoint of e) near the origin, in the middle
  // and far from it: each within 10 % of 1.
  const TempFile square(".json", "[[[0,0],[1,0],[1,1],[0,1]]]");
  const TempFile mesh(".mesh");
  const Run run = run_cli(
      {"-q", "mesh2d", square.path, "--sizing", "0.01 + 0.1*sqrt(x^2+y^2)", "-o", mesh.path});
  REQUIRE(run.status == 0);
  std::istringstream in(slurp(mesh.path));
  std::vector<double> xy;
  std::vector<std::uint32_t> tri;
  for (std::string word; in >> word;) {
    if (word == "Vertices") {
      std::size_t n = 0;
      in >> n;
      for (std::size_t k = 0; k < n; ++k) {
        double x = 0, y = 0;
        int ref = 0;
        in >> x >> y >> ref;
        xy.insert(xy.end(), {x, y});
      }
    } else if (word == "Triangles") {
      std::size_t n = 0;
      in >> n;
      for (std::size_t k = 0; k < n; ++k) {
        std::uint32_t a = 0, b = 0, c = 0;
        int ref = 0;
        in >> a >> b >> c >> ref;
        tri.insert(tri.end(), {a - 1, b - 1, c - 1});
      }
    }
  }
  REQUIRE(tri.size() > 300);
  std::vector<double> ratio[3];
  for (std::size_t t = 0; t < tri.size(); t += 3) {
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t a = tri[t + e], b = tri[t + (e + 1) % 3];
      if (a > b) continue;  // each interior edge once (boundary edges: half of them)
      const double mx = 0.5 * (xy[2 * a] + xy[2 * b]), my = 0.5 * (xy[2 * a + 1] + xy[2 * b + 1]);
      const double r = std::hypot(mx, my);
      const double len = std::hypot(xy[2 * a] - xy[2 * b], xy[2 * a + 1] - xy[2 * b + 1]);
      ratio[r < 0.4 ? 0 : r < 0.8 ? 1 : 2].push_back(len / (0.01 + 0.1 * r));
    }
  }
  for (auto& v : ratio) {
    REQUIRE(v.size() > 30);
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    const double median = v[v.size() / 2];
    INFO(v.size() << " edges, median ratio " << median);
    CHECK(std::fabs(median - 1) <= 0.1);
  }
}

TEST_CASE("mesh3d --sizing-file: edge lengths follow h(x) (median ratio within 10 %)",
          "[apps][density]") {
  // h = 0.08 + 0.12 (x + 1.1) on a 9^3 grid around the unit sphere (linear: trilinear
  // interpolation is exact); h goes 1 : 3.4 across it. mesh3d scales h to --vertices, so
  // the ratio |e| / h(midpoint) is compared with its median over all edges, in four slabs
  // along x: each slab's median within 10 % of it. A uniform mesh has slab medians of |e|
  // in the ratios of h's, not 1 (measured: 0.99, 1.01, 1.02, 1.02 at 3000 vertices).
  std::ostringstream grid;
  grid << std::setprecision(17) << "# vtk DataFile Version 3.0\nsizing\nASCII\n"
       << "DATASET STRUCTURED_POINTS\nDIMENSIONS 9 9 9\nORIGIN -1.1 -1.1 -1.1\n"
       << "SPACING 0.275 0.275 0.275\nPOINT_DATA 729\nSCALARS h double 1\n"
       << "LOOKUP_TABLE default\n";
  for (int k = 0; k < 9; ++k) {
    for (int j = 0; j < 9; ++j) {
      for (int i = 0; i < 9; ++i) grid << 0.08 + 0.12 * (0.275 * i) << '\n';
    }
  }
  const TempFile h(".vtk", grid.str());
  const TempFile mesh(".mesh");
  const Run run = run_cli({"-q", "mesh3d", kData + "/surfaces/sphere.obj", "--vertices", "2000",
                           "--sizing-file", h.path, "-o", mesh.path});
  REQUIRE(run.status == 0);
  const voroclip::TetMeshInput m = voroclip::read_tet_mesh(mesh.path);
  REQUIRE(m.nb_tets() > 5000);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  for (std::uint32_t t = 0; t < m.nb_tets(); ++t) {
    for (int a = 0; a < 4; ++a) {
      for (int b = a + 1; b < 4; ++b) {
        const std::uint32_t u = m.tets[4 * t + a], v = m.tets[4 * t + b];
        edges.emplace_back(std::min(u, v), std::max(u, v));
      }
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  std::vector<double> all, slab[4];
  for (const auto& [u, v] : edges) {
    const double* p = &m.xyz[3 * std::size_t{u}];
    const double* q = &m.xyz[3 * std::size_t{v}];
    const double mx = 0.5 * (p[0] + q[0]);
    const double len = std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                                 (p[2] - q[2]) * (p[2] - q[2]));
    const double r = len / (0.08 + 0.12 * (mx + 1.1));
    all.push_back(r);
    slab[std::clamp(static_cast<int>((mx + 1) * 2), 0, 3)].push_back(r);
  }
  const auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  const double global = median(all);
  for (int s = 0; s < 4; ++s) {
    REQUIRE(slab[s].size() > 100);
    INFO("slab " << s << ": " << slab[s].size() << " edges, median ratio / global "
                 << median(slab[s]) / global);
    CHECK(std::fabs(median(slab[s]) / global - 1) <= 0.1);
  }
}

namespace {

// An ASCII .vtu of mesh m's tets with one PointData array `rho` (values), and the exact
// integral of a function linear per tet with those values at the vertices.
std::string vtu_with_point_data(const voroclip::TetMeshInput& m,
                                const std::vector<double>& values) {
  std::ostringstream s;
  s << std::setprecision(17) << "<?xml version=\"1.0\"?>\n"
    << "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
    << "<UnstructuredGrid>\n<Piece NumberOfPoints=\"" << m.nb_vertices() << "\" NumberOfCells=\""
    << m.nb_tets() << "\">\n<PointData Scalars=\"rho\">\n"
    << "<DataArray type=\"Float64\" Name=\"rho\" format=\"ascii\">\n";
  for (const double v : values) s << v << '\n';
  s << "</DataArray>\n</PointData>\n<Points>\n"
    << "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (const double x : m.xyz) s << x << '\n';
  s << "</DataArray>\n</Points>\n<Cells>\n"
    << "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (const std::uint32_t v : m.tets) s << v << '\n';
  s << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (std::uint32_t t = 1; t <= m.nb_tets(); ++t) s << 4 * t << '\n';
  s << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (std::uint32_t t = 0; t < m.nb_tets(); ++t) s << "10\n";
  s << "</DataArray>\n</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
  return s.str();
}

double linear_integral(const voroclip::TetMeshInput& m, const std::vector<double>& values) {
  double exact = 0;
  for (std::uint32_t t = 0; t < m.nb_tets(); ++t) {
    const double* p[4];
    double mean = 0;
    for (int k = 0; k < 4; ++k) {
      p[k] = &m.xyz[3 * std::size_t{m.tets[4 * t + k]}];
      mean += values[m.tets[4 * t + k]] / 4;
    }
    double e[3][3];
    for (int k = 0; k < 3; ++k) {
      for (int c = 0; c < 3; ++c) e[k][c] = p[k + 1][c] - p[0][c];
    }
    const double vol = std::fabs(e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                                 e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                                 e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0])) /
                       6;
    exact += vol * mean;
  }
  return exact;
}

}  // namespace

TEST_CASE("cvt3d --density-file .vtu with point data: linear in its tets, exact mass",
          "[apps][density]") {
  // rho = 2 + x + 0.5 y at the vertices of sphere.mesh (a convex polyhedron: every cone of
  // the cell integrals stays in its tets), given as a .vtu over that mesh, on the same
  // domain: the interpolant is the linear function itself, which the degree-5 rule
  // integrates exactly.
  const std::string mesh = kData + "/tetmeshes/sphere.mesh";
  const voroclip::TetMeshInput m = voroclip::read_tet_mesh(mesh);
  std::vector<double> values(m.nb_vertices());
  for (std::uint32_t v = 0; v < m.nb_vertices(); ++v) {
    values[v] = 2 + m.xyz[3 * v] + 0.5 * m.xyz[3 * v + 1];
  }
  const TempFile file(".vtu", vtu_with_point_data(m, values));
  const voroclip::TetMeshInput back = voroclip::read_tet_mesh(file.path);
  CHECK(back.point_data == values);
  CHECK(back.point_data_name == "rho");
  const TempFile out(".json");
  const Run run = run_cli({"-q", "cvt3d", mesh, "--random", "200", "--iterations", "3",
                           "--density-file", file.path, "-o", out.path});
  REQUIRE(run.status == 0);
  double mass = 0;
  const nlohmann::json cells = nlohmann::json::parse(slurp(out.path))["cells"];
  for (const nlohmann::json& c : cells) {
    mass += c["mass"].get<double>();
  }
  CHECK(mass == Approx(linear_integral(m, values)).epsilon(1e-11));

  // A value that is not positive: the file, the DataArray's line, the point (from 0).
  std::vector<double> bad_values = values;
  bad_values[7] = -1;
  const TempFile bad(".vtu", vtu_with_point_data(m, bad_values));
  const TempFile none(".json");
  const Run r1 =
      run_cli({"cvt3d", mesh, "--random", "20", "--density-file", bad.path, "-o", none.path});
  CHECK(r1.status == 1);
  check_one_error_line(r1);
  CHECK(contains(r1.err, bad.path + ":6: PointData rho: point 7 (from 0): -1"));
  CHECK(!exists(none.path));
  // A .vtu without point data.
  std::string text = vtu_with_point_data(m, values);
  text.erase(text.find("<PointData"), text.find("<Points>") - text.find("<PointData"));
  const TempFile empty(".vtu", text);
  const Run r3 =
      run_cli({"cvt3d", mesh, "--random", "20", "--density-file", empty.path, "-o", none.path});
  CHECK(r3.status == 1);
  check_one_error_line(r3);
  CHECK(contains(r3.err, empty.path + ": no PointData array"));
  CHECK(!exists(none.path));
}

TEST_CASE("mesh3d --sizing-file .sol and .vtu: h at the vertices of a tet mesh",
          "[apps][density]") {
  // h = 0.35 + 0.1 x at the vertices of sphere.mesh, as a .sol (the domain's own vertices)
  // and as a .vtu, absolute (no --vertices): both give the same mesh (the same interpolant).
  // A .sol on a surface domain is refused, naming the option.
  const std::string mesh = kData + "/tetmeshes/sphere.mesh";
  const voroclip::TetMeshInput m = voroclip::read_tet_mesh(mesh);
  std::vector<double> h(m.nb_vertices());
  std::ostringstream sol;
  sol << std::setprecision(17) << "MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n"
      << m.nb_vertices() << "\n1 1\n";
  for (std::uint32_t v = 0; v < m.nb_vertices(); ++v) {
    h[v] = 0.35 + 0.1 * m.xyz[3 * v];
    sol << h[v] << '\n';
  }
  sol << "End\n";
  const TempFile sol_file(".sol", sol.str());
  const TempFile vtu_file(".vtu", vtu_with_point_data(m, h));
  const TempFile a(".mesh"), b(".mesh");
  const Run ra = run_cli({"-q", "mesh3d", mesh, "--sizing-file", sol_file.path, "-o", a.path});
  REQUIRE(ra.status == 0);
  const Run rb = run_cli({"-q", "mesh3d", mesh, "--sizing-file", vtu_file.path, "-o", b.path});
  REQUIRE(rb.status == 0);
  const voroclip::TetMeshInput ma = voroclip::read_tet_mesh(a.path);
  CHECK(ma.nb_tets() > 500);
  CHECK(slurp(a.path) == slurp(b.path));
  const TempFile none(".mesh");
  const Run bad = run_cli(
      {"mesh3d", kData + "/surfaces/sphere.obj", "--sizing-file", sol_file.path, "-o", none.path});
  CHECK(bad.status != 0);
  check_one_error_line(bad);
  CHECK(contains(bad.err, "--sizing-file: a .sol gives values at the vertices of a tet mesh"));
  CHECK(!exists(none.path));
  // Without --vertices, --density (no unit) is refused.
  const Run no_count = run_cli({"mesh3d", mesh, "--density", "1+x^2", "-o", none.path});
  CHECK(no_count.status != 0);
  CHECK(contains(no_count.err, "--vertices N is required"));
}

TEST_CASE("mesh3d --sizing alone: h is the edge length (median ratio within 10 %)",
          "[apps][density]") {
  // h = 0.1 + 0.12 (x + 1) on the unit sphere, in model units, no --vertices: the median of
  // |e| / h(midpoint of e) over all edges, and in four slabs along x, each within 10 % of 1.
  const TempFile mesh(".mesh");
  const Run run = run_cli({"-q", "mesh3d", kData + "/surfaces/sphere.obj", "--sizing",
                           "0.1 + 0.12*(x + 1)", "-o", mesh.path});
  REQUIRE(run.status == 0);
  const voroclip::TetMeshInput m = voroclip::read_tet_mesh(mesh.path);
  REQUIRE(m.nb_tets() > 3000);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  for (std::uint32_t t = 0; t < m.nb_tets(); ++t) {
    for (int a = 0; a < 4; ++a) {
      for (int b = a + 1; b < 4; ++b) {
        const std::uint32_t u = m.tets[4 * t + a], v = m.tets[4 * t + b];
        edges.emplace_back(std::min(u, v), std::max(u, v));
      }
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  std::vector<double> all, slab[4];
  for (const auto& [u, v] : edges) {
    const double* p = &m.xyz[3 * std::size_t{u}];
    const double* q = &m.xyz[3 * std::size_t{v}];
    const double mx = 0.5 * (p[0] + q[0]);
    const double len = std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                                 (p[2] - q[2]) * (p[2] - q[2]));
    const double r = len / (0.1 + 0.12 * (mx + 1));
    all.push_back(r);
    slab[std::clamp(static_cast<int>((mx + 1) * 2), 0, 3)].push_back(r);
  }
  const auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  INFO(m.nb_vertices() << " vertices, " << edges.size() << " edges, median ratio " << median(all));
  CHECK(std::fabs(median(all) - 1) <= 0.1);
  for (int s = 0; s < 4; ++s) {
    REQUIRE(slab[s].size() > 100);
    INFO("slab " << s << ": " << slab[s].size() << " edges, median ratio " << median(slab[s]));
    CHECK(std::fabs(median(slab[s]) - 1) <= 0.1);
  }
}

// ---------------------------------------------------------------------------------------
// Findings of fuzz_density_vtu (fuzz/fuzz_density.cpp), inputs in tests/apps/fuzz_regressions/.

TEST_CASE("fuzz regression: .vtu densities on meshes 1e-200 and 2e308 across",
          "[apps][density][regression]") {
  // The two-tet .vtu of the fuzz seeds with its points scaled: the interpolant's bucket
  // grid was sized from the mesh's volume, a product that overflowed (points at -1e308 and
  // 1e308: a NaN count of buckets, then a crash in the lookup) or underflowed (a mesh 1e-200
  // across: 512^3 buckets, 537 MB for a file of 700 bytes). Both now give a density.
  const std::string dir = std::string(VOROCLIP_SOURCE_DIR) + "/tests/apps/fuzz_regressions/";
  const TempFile cube(".obj", kCubeObj);
  for (const char* name : {"density_vtu_extent_overflow.vtu", "density_vtu_extent_1e-200.vtu"}) {
    const TempFile out(".json");
    const std::vector<std::string> args = {
        "-q", "cvt3d", cube.path, "--random", "20", "--density-file", dir + name, "-o", out.path};
#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
    // Without a sanitizer (whose shadow memory needs the address space), under a limit of
    // 400 MB of address space (the run needs far less): the 537 MB of buckets failed.
    const Run run = run_cli(args, "ulimit -v 400000 &&");
#else
    const Run run = run_cli(args);
#endif
    INFO(name);
    CHECK(run.status == 0);
    CHECK(run.err.empty());
    std::ifstream in(out.path);
    const nlohmann::json result = nlohmann::json::parse(in, nullptr, false);
    REQUIRE(result.is_object());
    CHECK(result["cells"].size() == 20);
  }
}

TEST_CASE("cvt3d --random: a .sol density draws the start sites as the same .vtu does",
          "[apps][density][regression]") {
  // rho = 2 + x + z/2 at the vertices of sphere.mesh, as a .sol and as a .vtu of the same
  // tets: the same density, hence the same start sites (drawn with rho^(3/5)), bit for bit.
  // The .sol's used to be drawn uniformly.
  const std::string mesh = kData + "/tetmeshes/sphere.mesh";
  const voroclip::TetMeshInput m = voroclip::read_tet_mesh(mesh);
  std::vector<double> rho(m.nb_vertices());
  std::ostringstream sol;
  sol << std::setprecision(17) << "MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n"
      << m.nb_vertices() << "\n1 1\n";
  for (std::uint32_t v = 0; v < m.nb_vertices(); ++v) {
    rho[v] = 2 + m.xyz[3 * v] + 0.5 * m.xyz[3 * v + 2];
    sol << rho[v] << '\n';
  }
  sol << "End\n";
  const TempFile sol_file(".sol", sol.str());
  const TempFile vtu_file(".vtu", vtu_with_point_data(m, rho));
  const TempFile a(".txt"), b(".txt"), uniform(".txt");
  const auto start = [&](const std::vector<std::string>& density, const std::string& out) {
    std::vector<std::string> args = {"-q",           "cvt3d", mesh, "--random", "3000",
                                     "--iterations", "0",     "-o", out};
    args.insert(args.end(), density.begin(), density.end());
    REQUIRE(run_cli(args).status == 0);
    return read_numbers(slurp(out));
  };
  const std::vector<double> from_sol = start({"--density-file", sol_file.path}, a.path);
  const std::vector<double> from_vtu = start({"--density-file", vtu_file.path}, b.path);
  const std::vector<double> flat = start({}, uniform.path);
  REQUIRE(from_sol.size() == 3 * 3000);
  CHECK(slurp(a.path) == slurp(b.path));
  // Drawn with the density, not uniformly: the mean x is pulled towards larger rho.
  double mean_sol = 0, mean_flat = 0;
  for (std::size_t i = 0; i < 3000; ++i) {
    mean_sol += from_sol[3 * i] / 3000;
    mean_flat += flat[3 * i] / 3000;
  }
  CHECK(mean_sol > mean_flat + 0.03);
}

TEST_CASE("cvt2d --random with a density draws the start sites with rho^(1/2)",
          "[apps][density][regression]") {
  // rho = (1 + 10x)^2 on the unit square: start sites with density 1 + 10x, so a fraction
  // 1.75 / 6 = 0.2917 of them left of x = 0.5 (sigma 0.0083 for 3,000); they were uniform.
  const TempFile square(".json", "[[[0,0],[1,0],[1,1],[0,1]]]");
  const TempFile out(".txt");
  const Run run = run_cli({"-q", "cvt2d", square.path, "--random", "3000", "--iterations", "0",
                           "--density", "(1+10*x)^2", "-o", out.path});
  REQUIRE(run.status == 0);
  const std::vector<double> xy = read_numbers(slurp(out.path));
  REQUIRE(xy.size() == 2 * 3000);
  std::size_t left = 0;
  for (std::size_t i = 0; i < 3000; ++i) left += xy[2 * i] < 0.5;
  CHECK(static_cast<double>(left) / 3000 == Approx(1.75 / 6).margin(0.04));
}
