// The mesh2d command: statistics, the four mesh formats parsed back, the histogram, errors.
#include <catch2/catch.hpp>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli_run.h"

namespace {

const std::string kData = VOROCLIP_SHARED_DATA_DIR;

// The number after `keyword` on its own line (Medit sections), or -1.
long medit_count(const std::string& text, const std::string& keyword) {
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line == keyword) {
      long n = -1;
      in >> n;
      return n;
    }
  }
  return -1;
}

}  // namespace

TEST_CASE("mesh2d: statistics, quality and the four formats", "[apps]") {
  const Run run = run_cli(
      {"mesh2d", "square-holes:2,0.4", "--vertices", "500", "--seed", "2", "--stats", "json"});
  REQUIRE(run.status == 0);
  const nlohmann::json s = nlohmann::json::parse(run.out);
  const int vertices = s["vertices"], triangles = s["triangles"];
  CHECK(vertices > 400);
  CHECK(vertices < 650);
  CHECK(triangles > vertices);
  CHECK(s["min_angle_deg"].get<double>() >= 30);
  CHECK(s["mean_min_angle_deg"].get<double>() >= 51);
  CHECK(s["max_angle_deg"].get<double>() < 120);
  CHECK(s["seconds"].get<double>() > 0);
  CHECK(s["quality"]["nb_triangles"] == triangles);
  // Within 10% of the request: no vertex-count note.
  CHECK(s["vertex_count_within_tolerance"] == true);
  CHECK(s["vertex_count_note"].is_null());
  // Progress went to stderr: phases with iteration, energy and |g|.
  CHECK(contains(run.err, "unconstrained CVT"));
  CHECK(contains(run.err, "constrained CVT"));
  CHECK(contains(run.err, "|g|"));

  for (const char* ext : {".svg", ".vtu", ".mesh", ".msh"}) {
    const std::string out = temp_path(ext);
    const std::string hist = temp_path(".svg");
    const Run w = run_cli({"-q", "mesh2d", "square-holes:2,0.4", "--vertices", "500", "--seed", "2",
                           "-o", out, "--histogram", hist});
    CHECK(w.status == 0);
    CHECK(w.out.empty());
    const std::string text = slurp(out);
    const std::string h = slurp(hist);
    std::remove(out.c_str());
    std::remove(hist.c_str());
    CHECK(h.rfind("<svg", 0) == 0);
    CHECK(contains(h, "smallest angle"));
    const std::string e = ext;
    if (e == ".svg") {
      CHECK(text.rfind("<svg", 0) == 0);
      CHECK(contains(text, "</svg>"));
    } else if (e == ".vtu") {
      CHECK(contains(text, "NumberOfPoints=\"" + std::to_string(vertices) + "\""));
      // The triangles, then the boundary edges as lines (cell type 3), with their tags.
      const std::size_t cells_at = text.find("NumberOfCells=\"");
      REQUIRE(cells_at != std::string::npos);
      CHECK(std::stol(text.substr(cells_at + 15)) > triangles);
      // Tags named as mesh3d's: region (triangles), patch (boundary edges).
      CHECK(contains(text, "Name=\"region\""));
      CHECK(contains(text, "Name=\"patch\""));
      CHECK(!contains(text, "Name=\"tag\""));
    } else if (e == ".mesh") {
      CHECK(medit_count(text, "Vertices") == vertices);
      CHECK(medit_count(text, "Triangles") == triangles);
      CHECK(medit_count(text, "Edges") > 0);
      CHECK(contains(text, "Dimension 2"));
    } else {
      // Gmsh 4.1: '$Nodes' then 'numEntityBlocks numNodes minTag maxTag'.
      CHECK(text.rfind("$MeshFormat\n4.1 0 8\n", 0) == 0);
      CHECK(contains(text, "$PhysicalNames"));
      std::istringstream in(text.substr(text.find("$Nodes\n") + 7));
      long blocks = 0, nodes = 0;
      in >> blocks >> nodes;
      CHECK(nodes == vertices);
    }
  }
}

TEST_CASE("mesh2d: --fix-input-vertices, --edge-length and a real polygon", "[apps]") {
  const Run run = run_cli({"--stats", "json", "mesh2d", kData + "/polygons/valid/issue29.json",
                           "--edge-length", "4", "--fix-input-vertices"});
  REQUIRE(run.status == 0);
  const nlohmann::json s = nlohmann::json::parse(run.out);
  CHECK(s["fixed_sites"] == 40);  // every vertex of the 40-vertex polygon
  CHECK(s["edge_length"].get<double>() == 4);
  CHECK(s["vertices"].get<int>() > 100);
  CHECK(s["min_angle_deg"].get<double>() > 20);
}

TEST_CASE("mesh2d: errors are one line, exit status, and no file", "[apps]") {
  const std::string out = temp_path(".mesh");
  SECTION("no size") {
    const Run run = run_cli({"mesh2d", "annulus:1,2,32", "-o", out});
    CHECK(run.status == 2);
    check_one_error_line(run);
    CHECK(contains(run.err, "--vertices"));
  }
  SECTION("both sizes") {
    const Run run =
        run_cli({"mesh2d", "annulus:1,2,32", "--vertices", "100", "--edge-length", "1"});
    CHECK(run.status == 2);
    check_one_error_line(run);
  }
  SECTION("a zero or negative edge length") {
    for (const char* h : {"0", "-1"}) {
      const Run run = run_cli({"mesh2d", "annulus:1,2,32", "--edge-length", h, "-o", out});
      CHECK(run.status == 2);
      check_one_error_line(run);
      CHECK(contains(run.err, "--edge-length: expected a positive number"));
    }
  }
  SECTION("too few vertices") {
    const Run run = run_cli({"mesh2d", "annulus:1,2,32", "--vertices", "2"});
    CHECK(run.status == 2);
    check_one_error_line(run);
  }
  SECTION("an unknown output format") {
    const Run run = run_cli({"mesh2d", "annulus:1,2,32", "--vertices", "100", "-o", "m.obj"});
    CHECK(run.status == 2);
    check_one_error_line(run);
    CHECK(contains(run.err, ".msh"));
    CHECK_FALSE(exists("m.obj"));
  }
  SECTION("a degenerate polygon") {
    const Run run = run_cli({"mesh2d", kData + "/polygons/degenerate/self-touching.json",
                             "--vertices", "100", "-o", out});
    CHECK(run.status == 1);
    check_one_error_line(run);
    CHECK(contains(run.err, "self-touching.json"));
  }
  SECTION("a bad gradation") {
    const Run run =
        run_cli({"mesh2d", "annulus:1,2,32", "--vertices", "100", "--gradation", "0", "-o", out});
    CHECK(run.status == 2);
    check_one_error_line(run);
  }
  SECTION("an output in a missing directory") {
    const Run run =
        run_cli({"mesh2d", "annulus:1,2,32", "--vertices", "100", "-o", "/nonexistent/dir/m.mesh"});
    CHECK(run.status == 1);
    check_one_error_line(run);
    CHECK(contains(run.err, "/nonexistent/dir/m.mesh"));
  }
  CHECK_FALSE(exists(out));
}

TEST_CASE("mesh2d: two outputs naming one file, --msh-version without a .msh output",
          "[apps][regression]") {
  // mesh2d -o x.svg --histogram x.svg exited 0 with the histogram in x.svg, and
  // --msh-version was accepted, and ignored, with an output that is not .msh.
  SECTION("-o and --histogram naming one file") {
    const std::string svg = temp_path(".svg");
    for (const std::string& histogram : {svg, "./" + svg}) {
      INFO(histogram);
      const Run run = run_cli(
          {"mesh2d", "annulus:1,2,32", "--vertices", "100", "-o", svg, "--histogram", histogram});
      CHECK(run.status == 2);
      check_one_error_line(run);
      CHECK(contains(run.err, "-o and --histogram both name '"));
      CHECK(contains(run.err, "one would overwrite the other"));
      // Two spellings of one file read "'a' and './a' (the same file): one would ..." (it
      // was "'a' and './a', the same file,: one would ...").
      CHECK_FALSE(contains(run.err, ",:"));
      if (histogram != svg) CHECK(contains(run.err, "' (the same file): one would overwrite"));
      CHECK_FALSE(exists(svg));
    }
  }
  SECTION("--msh-version with a .mesh output, or none") {
    const std::string mesh = temp_path(".mesh");
    const Run run = run_cli(
        {"mesh2d", "annulus:1,2,32", "--vertices", "100", "-o", mesh, "--msh-version", "2.2"});
    CHECK(run.status == 2);
    check_one_error_line(run);
    CHECK(contains(run.err, "--msh-version: only a .msh output (Gmsh) has a format version, got '" +
                                mesh + "'"));
    CHECK_FALSE(exists(mesh));
    const Run none =
        run_cli({"mesh2d", "annulus:1,2,32", "--vertices", "100", "--msh-version", "4.1"});
    CHECK(none.status == 2);
    check_one_error_line(none);
    CHECK(contains(none.err,
                   "--msh-version: only a .msh output (Gmsh) has a format version, "
                   "got no output file"));
  }
  SECTION("--msh-version with a .msh output, and -o with --histogram, still written") {
    const std::string msh = temp_path(".msh"), svg = temp_path(".svg");
    const Run run = run_cli({"-q", "mesh2d", "annulus:1,2,32", "--vertices", "100", "-o", msh,
                             "--msh-version", "2.2", "--histogram", svg});
    CHECK(run.status == 0);
    CHECK(slurp(msh).rfind("$MeshFormat\n2.2 0 8\n", 0) == 0);
    CHECK(contains(slurp(svg), "smallest angle"));
    std::remove(msh.c_str());
    std::remove(svg.c_str());
  }
}

TEST_CASE("mesh2d: extensions in any case; --keep-gaps only with --circumcenter-rule",
          "[apps][regression]") {
  // mesh2d took only lower-case extensions (X.SVG was an error) and --keep-gaps without
  // --circumcenter-rule was accepted and ignored.
  const std::string svg = temp_path(".SVG");
  const Run upper = run_cli({"-q", "mesh2d", "annulus:1,2,32", "--vertices", "100", "-o", svg});
  CHECK(upper.status == 0);
  CHECK(contains(slurp(svg), "<svg"));
  std::remove(svg.c_str());
  const Run gaps = run_cli({"mesh2d", "annulus:1,2,32", "--vertices", "100", "--keep-gaps"});
  CHECK(gaps.status == 2);
  check_one_error_line(gaps);
  CHECK(contains(gaps.err, "--keep-gaps: only with --circumcenter-rule"));
  const Run both = run_cli({"-q", "mesh2d", "annulus:1,2,32", "--vertices", "100",
                            "--circumcenter-rule", "--keep-gaps"});
  CHECK(both.status == 0);
}

TEST_CASE("demo: a CVT mesh and a clipped Voronoi diagram of a domain with holes", "[apps]") {
  const std::string path = "test_cli_mesh_demo.svg";
  const Run run = run_cli({"demo", "--stats", "json", "-o", path});
  REQUIRE(run.status == 0);
  const nlohmann::json s = nlohmann::json::parse(run.out);
  const double area = s["domain_area"], cells = s["cells_area"];
  CHECK(std::fabs(area - cells) <= 1e-12 * area);
  CHECK(s["cvt_sites"] == 200);
  CHECK(s["boundary_cells"].get<int>() > 0);
  CHECK(s["mesh_vertices"].get<int>() > 400);
  CHECK(s["mesh_triangles"].get<int>() > s["mesh_vertices"].get<int>());
  CHECK(s["mesh_min_angle_deg"].get<double>() >= 30);
  CHECK(s["mesh_mean_min_angle_deg"].get<double>() >= 51);
  CHECK(contains(run.err, "CVT mesh:"));
  const std::string svg = slurp(path);
  std::remove(path.c_str());
  // The clipped diagram and the mesh, then the classroom example, nested in one picture.
  std::size_t nested = 0;
  for (std::size_t at = svg.find("<svg"); at != std::string::npos; at = svg.find("<svg", at + 1)) {
    ++nested;
  }
  CHECK(nested == 4);
  CHECK(contains(svg, "Clipped Voronoi diagram of a CVT"));
  CHECK(contains(svg, "CVT mesh:"));
  CHECK(contains(svg, "Naive floating point"));
  CHECK(svg.find("<?xml", 1) == std::string::npos);
}

TEST_CASE("mesh2d: a request the features cannot meet is said, in the text and the JSON",
          "[apps]") {
  // Corridors 0.05 wide between 36 holes: the feature sizes alone ask for several times
  // the 60 vertices asked (with --exact-vertices: no raise for the mean angle, below).
  const Run json = run_cli({"-q", "--stats", "json", "mesh2d", "square-holes:6,0.7", "--vertices",
                            "60", "--exact-vertices"});
  REQUIRE(json.status == 0);
  const nlohmann::json s = nlohmann::json::parse(json.out);
  const int vertices = s["vertices"], features = s["feature_vertices"];
  CHECK(vertices > 66);
  CHECK(features > 66);
  CHECK(s["vertex_count_within_tolerance"] == false);
  const std::string note = s["vertex_count_note"];
  CHECK(note.rfind(std::to_string(vertices) + " vertices for 60 asked (+", 0) == 0);
  CHECK(contains(note, "the small features force more"));
  CHECK(contains(note, "about " + std::to_string(features) + " vertices"));
  CHECK(s["mean_angle_runs"] == 0);
  CHECK(s["mean_angle_raise"].is_null());
  const std::string mean_note = s["mean_angle_note"];
  CHECK(mean_note.rfind("mean smallest angle ", 0) == 0);
  // The human text has them as one line each.
  const Run text =
      run_cli({"mesh2d", "square-holes:6,0.7", "--vertices", "60", "--exact-vertices"});
  REQUIRE(text.status == 0);
  CHECK(contains(text.out + text.err, "note: " + note + "\n"));
  CHECK(contains(text.out + text.err, "note: " + mean_note + "\n"));
}

TEST_CASE("mesh2d: a mean smallest angle below 53 degrees is raised, and said", "[apps]") {
  // The same request without --exact-vertices: meshed again with more vertices until the
  // mean smallest angle reaches 53 degrees; the progress, the note and the JSON say so.
  const Run json =
      run_cli({"-q", "--stats", "json", "mesh2d", "square-holes:6,0.7", "--vertices", "60"});
  REQUIRE(json.status == 0);
  const nlohmann::json s = nlohmann::json::parse(json.out);
  const int vertices = s["vertices"];
  CHECK(s["mean_min_angle_deg"].get<double>() >= 53);
  CHECK(s["mean_angle_note"].is_null());
  CHECK(s["mean_angle_runs"].get<int>() >= 1);
  CHECK(s["requested_vertices"] == 60);
  const std::string raise = s["mean_angle_raise"];
  CHECK(raise.rfind("the mean smallest angle was ", 0) == 0);
  CHECK(contains(raise, "meshed again with " + std::to_string(vertices) + " vertices (mean "));
  CHECK(s["vertex_count_within_tolerance"] == false);
  const std::string note = s["vertex_count_note"];
  CHECK(note.rfind(std::to_string(vertices) + " vertices for 60 asked (+", 0) == 0);
  CHECK(note.size() > raise.size());
  CHECK(note.substr(note.size() - raise.size() - 4) == "%): " + raise);
  const Run text = run_cli({"mesh2d", "square-holes:6,0.7", "--vertices", "60"});
  REQUIRE(text.status == 0);
  CHECK(contains(text.out + text.err, "note: " + note + " (--exact-vertices keeps the count)\n"));
  CHECK(contains(text.err, "below 53 degrees; meshing again with "));
}

TEST_CASE("cvt2d and mesh2d: an L-shape 2^-20 wide is the same run as the unit one",
          "[apps][regression]") {
  // cvt2d on a domain in small units stopped after 0 iterations ("iteration budget" of 30)
  // and mesh2d, whose constrained CVT is cvt2d's, gave 281 vertices of mean smallest angle
  // 52.4 degrees instead of 319 of 56.2: L-BFGS-B's gradient was lost against its
  // variables. Scaled by a power of two, the runs are now the same, bit for bit.
  const auto l_shape = [](int e) {
    const double xy[12] = {0, 0, 1, 0, 1, 0.6, 0.4, 0.6, 0.4, 1, 0, 1};
    std::string text = "[[";
    for (int k = 0; k < 6; ++k) {
      char a[32], b[32];
      *std::to_chars(a, a + 31, std::ldexp(xy[2 * k], e)).ptr = '\0';
      *std::to_chars(b, b + 31, std::ldexp(xy[2 * k + 1], e)).ptr = '\0';
      text += std::string(k == 0 ? "" : ",") + "[" + a + "," + b + "]";
    }
    const std::string path = temp_path(".json");
    std::ofstream(path) << text << "]]";
    return path;
  };
  const std::string unit = l_shape(0), tiny = l_shape(-20);
  const auto stats = [](const std::vector<std::string>& args) {
    const Run run = run_cli(args);
    REQUIRE(run.status == 0);
    return nlohmann::json::parse(run.out);
  };
  const nlohmann::json c0 =
      stats({"--stats", "json", "-q", "cvt2d", unit, "--random", "300", "--iterations", "30"});
  const nlohmann::json c1 =
      stats({"--stats", "json", "-q", "cvt2d", tiny, "--random", "300", "--iterations", "30"});
  CHECK(c0["iterations"] == 30);
  CHECK(c1["iterations"] == 30);
  CHECK(c1["stop"] == "iteration budget");
  CHECK(c1["evaluations"] == c0["evaluations"]);
  CHECK(c1["energy"].get<double>() == std::ldexp(c0["energy"].get<double>(), -80));
  const nlohmann::json m0 = stats({"--stats", "json", "-q", "mesh2d", unit, "--vertices", "300"});
  const nlohmann::json m1 = stats({"--stats", "json", "-q", "mesh2d", tiny, "--vertices", "300"});
  for (const char* key : {"vertices", "triangles", "min_angle_deg", "mean_min_angle_deg"}) {
    INFO(key);
    CHECK(m1[key] == m0[key]);
  }
  std::remove(unit.c_str());
  std::remove(tiny.c_str());
}

namespace {

// A square [0, 4]^2 with the hole [1.5, 2.5]^2, 0-based; the outer segments have marker
// `outer`, the hole's `hole` (segment k on line 11 + k), and a regional attribute
// `region` numbered 0 on line 22 when given.
std::string square_poly(const std::string& outer, const std::string& hole,
                        const std::string& region = "") {
  std::string s =
      "8 2 0 0\n0 0 0\n1 4 0\n2 4 4\n3 0 4\n4 1.5 1.5\n5 2.5 1.5\n6 2.5 2.5\n"
      "7 1.5 2.5\n8 1\n";
  for (int k = 0; k < 8; ++k) {
    const int a = k, b = k < 4 ? (k + 1) % 4 : 4 + (k - 3) % 4;
    s += std::to_string(k) + " " + std::to_string(a) + " " + std::to_string(b) + " " +
         (k < 4 ? outer : hole) + "\n";
  }
  s += "1\n0 2 2\n";
  if (!region.empty()) s += "1\n0 0.5 0.5 " + region + " 0\n";
  return s;
}

// The $PhysicalNames entries of a .msh file, "dim tag name" per line.
std::vector<std::string> physical_names(const std::string& msh) {
  std::istringstream in(msh);
  std::string line;
  while (std::getline(in, line) && line != "$PhysicalNames") {
  }
  std::vector<std::string> names;
  long n = 0;
  in >> n;
  std::getline(in, line);
  for (long k = 0; k < n && std::getline(in, line); ++k) names.push_back(line);
  return names;
}

}  // namespace

TEST_CASE("mesh2d: .poly marker 0 is no marker (tag 1), in .msh as in .vtu", "[apps][regression]") {
  // Gmsh physical tags are positive: a marker 0 written as tag 0 became a nameless group
  // (and in .msh 2.2 the lines lost their group). Now 0 means "no marker" and gives 1, as
  // in Triangle's output, in every format.
  const std::string poly = temp_path(".poly");
  std::ofstream(poly) << square_poly("0", "4");
  const std::string msh = temp_path(".msh"), msh22 = temp_path(".msh"), vtu = temp_path(".vtu");
  REQUIRE(run_cli({"-q", "mesh2d", poly, "--vertices", "200", "-o", msh}).status == 0);
  REQUIRE(run_cli({"-q", "mesh2d", poly, "--vertices", "200", "--msh-version", "2.2", "-o", msh22})
              .status == 0);
  REQUIRE(run_cli({"-q", "mesh2d", poly, "--vertices", "200", "-o", vtu}).status == 0);
  const std::vector<std::string> expected = {"1 1 \"boundary 1\"", "1 4 \"boundary 4\"",
                                             "2 1 \"region 1\""};
  CHECK(physical_names(slurp(msh)) == expected);
  CHECK(physical_names(slurp(msh22)) == expected);
  // The .vtu's tags, per cell (the triangles, then the boundary edges): patch 1 and 4 on the
  // edges (0 on the triangles), region 1 on the triangles (0 on the edges), as mesh3d's.
  const std::string text = slurp(vtu);
  const auto values_of = [&](const std::string& name) {
    const std::size_t at = text.find("Name=\"" + name + "\"");
    REQUIRE(at != std::string::npos);
    std::istringstream values(text.substr(text.find('>', at) + 1));
    std::vector<long> out;
    for (long t; values >> t;) out.push_back(t);
    return out;
  };
  const std::vector<long> patch = values_of("patch"), region = values_of("region");
  REQUIRE(patch.size() == region.size());
  std::set<long> edge_tags, triangle_regions;
  for (std::size_t c = 0; c < patch.size(); ++c) {
    // A cell is a triangle or an edge: exactly one of its two tags is 0.
    CHECK((patch[c] == 0) != (region[c] == 0));
    (patch[c] != 0 ? edge_tags : triangle_regions).insert(patch[c] != 0 ? patch[c] : region[c]);
  }
  CHECK(edge_tags == std::set<long>{1, 4});
  CHECK(triangle_regions == std::set<long>{1});
  for (const std::string& f : {poly, msh, msh22, vtu}) std::remove(f.c_str());
}

TEST_CASE("mesh2d: tags a .msh cannot hold are an error before meshing, naming the item",
          "[apps][regression]") {
  const std::string poly = temp_path(".poly");
  const std::string msh = temp_path(".msh"), vtu = temp_path(".vtu");
  const std::string fix = ", but a Gmsh .msh file takes only positive physical tags; use ";
  const std::string other = ", or write .vtu or .mesh, which take any integer tag\n";
  // A negative marker: named by the file, the segment's line and its own number. Before
  // meshing: the error is the only line (after meshing, the phases' lines came first).
  std::ofstream(poly) << square_poly("2", "-3");
  Run run = run_cli({"mesh2d", poly, "--vertices", "200", "-o", msh});
  CHECK(run.status == 1);
  check_one_error_line(run);
  CHECK(run.err == "voroclip: error: " + poly + ":15: segment 4 has boundary marker -3" + fix +
                       "markers >= 1 (0 means no marker and becomes 1)" + other);
  CHECK(!exists(msh));
  // A .vtu takes it.
  run = run_cli({"-q", "mesh2d", poly, "--vertices", "200", "-o", vtu});
  CHECK(run.status == 0);
  CHECK(contains(slurp(vtu), "\n-3\n"));
  std::remove(vtu.c_str());
  // A regional attribute 0 (and -2): named by its own number and line.
  for (const char* value : {"0", "-2"}) {
    std::ofstream(poly) << square_poly("2", "3", value);
    run = run_cli({"mesh2d", poly, "--vertices", "200", "-o", msh});
    CHECK(run.status == 1);
    check_one_error_line(run);
    CHECK(run.err == "voroclip: error: " + poly + ": regional attribute 0 (line 22) is " + value +
                         fix + "regional attributes >= 1" + other);
    CHECK(!exists(msh));
    run = run_cli({"-q", "mesh2d", poly, "--vertices", "200", "-o", vtu});
    CHECK(run.status == 0);
    std::remove(vtu.c_str());
  }
  // A regional attribute that is no integer, whatever the format, before meshing.
  std::ofstream(poly) << square_poly("2", "3", "1.5");
  run = run_cli({"mesh2d", poly, "--vertices", "200", "-o", vtu});
  CHECK(run.status == 1);
  check_one_error_line(run);
  CHECK(run.err == "voroclip: error: " + poly +
                       ": regional attribute 0 (line 22) is 1.5, not an integer: mesh regions "
                       "are tagged by integers\n");
  CHECK(!exists(vtu));
  std::remove(poly.c_str());
}

TEST_CASE("mesh2d: --exact-vertices without --vertices is a usage error", "[apps][regression]") {
  // It keeps the count --vertices asks; with --edge-length or a sizing alone it meant
  // nothing and was accepted silently.
  const std::string out = temp_path(".vtu");
  for (const std::vector<std::string>& size : {std::vector<std::string>{"--edge-length", "0.1"},
                                               std::vector<std::string>{"--sizing", "0.1"}}) {
    std::vector<std::string> args = {"mesh2d", "square-holes:1,0.3", "--exact-vertices", "-o", out};
    args.insert(args.end(), size.begin(), size.end());
    const Run run = run_cli(args);
    CHECK(run.status == 2);
    check_one_error_line(run);
    CHECK(contains(run.err, "--exact-vertices: only with --vertices N"));
    CHECK(!exists(out));
  }
}

TEST_CASE("mesh2d: an edge length or a sizing says the vertex count it implies, before meshing",
          "[apps][regression]") {
  // --sizing 0.001 on a unit square implies about 1,150,000 vertices; it ran over 10
  // minutes showing only "sampling: still running", never the count (the too-thin check,
  // with --vertices only, names one). The note comes before the sampling; the JSON has the
  // count, and the mesh made is within 25% of it (the boundary step and the refinement add
  // vertices: +3% on the square at 0.05, +17% on dude.json at 5).
  const std::string square = temp_path(".json");
  std::ofstream(square) << "[[[0,0],[1,0],[1,1],[0,1]]]\n";
  struct Case {
    std::vector<std::string> args;
    double uniform;  // 2 / sqrt(3) area / h^2 of a uniform size h, or 0
  };
  const double uniform = 2 / std::sqrt(3.0) / (0.05 * 0.05);  // 461.9
  for (const Case& c : {Case{{square, "--edge-length", "0.05"}, uniform},
                        Case{{square, "--sizing", "0.05"}, uniform},
                        Case{{kData + "/polygons/valid/dude.json", "--edge-length", "5"}, 0}}) {
    std::vector<std::string> args = {"--stats", "json", "mesh2d"};
    args.insert(args.end(), c.args.begin(), c.args.end());
    INFO(args[3] << " " << args[4] << " " << args[5]);
    const Run run = run_cli(args);
    REQUIRE(run.status == 0);
    const nlohmann::json s = nlohmann::json::parse(run.out);
    REQUIRE(s["implied_vertices"].is_number());
    const double implied = s["implied_vertices"], made = s["vertices"];
    if (c.uniform > 0) CHECK(std::fabs(implied - c.uniform) < 1);
    CHECK(made >= implied / 1.25);
    CHECK(made <= implied * 1.25);
    // The note (three significant digits, here the count itself), before the first CVT.
    const std::string note =
        "mesh2d: about " + std::to_string(static_cast<long>(implied)) + " vertices for this size\n";
    const std::size_t at = run.err.find(note);
    CHECK(at != std::string::npos);
    CHECK(at < run.err.find("unconstrained CVT"));
    // -q: no note.
    args.insert(args.begin(), "-q");
    const Run quiet = run_cli(args);
    REQUIRE(quiet.status == 0);
    CHECK_FALSE(contains(quiet.err, "vertices for this size"));
  }
  // A vertex count is the count itself: no implied count, no note.
  const Run count = run_cli({"--stats", "json", "mesh2d", square, "--vertices", "100"});
  REQUIRE(count.status == 0);
  CHECK(nlohmann::json::parse(count.out)["implied_vertices"].is_null());
  CHECK_FALSE(contains(count.err, "vertices for this size"));
  std::remove(square.c_str());
}

TEST_CASE("mesh2d: a coarse mesh graded to small features is not called corridors",
          "[apps][regression]") {
  // dude.json at 10 vertices (edge length 23.3, smallest feature 0.371): the note said
  // "corridors a few triangles wide ... about 7200000 vertices (estimate)" (7,900,000 at 3),
  // for a domain meshed fine at 2,501. The mean is low for the grading and the boundary.
  for (const char* count : {"10", "3"}) {
    INFO(count);
    const Run run = run_cli({"-q", "--stats", "json", "mesh2d", kData + "/polygons/valid/dude.json",
                             "--vertices", count, "--exact-vertices"});
    REQUIRE(run.status == 0);
    const nlohmann::json s = nlohmann::json::parse(run.out);
    REQUIRE(s["mean_angle_note"].is_string());
    const std::string note = s["mean_angle_note"];
    INFO(note);
    CHECK(s["edge_length"].get<double>() > 4 * s["min_feature_size"].get<double>());
    CHECK_FALSE(contains(note, "corridors"));
    CHECK_FALSE(contains(note, "(estimate)"));
  }
}

TEST_CASE("mesh2d: --binary and --compress write the .vtu data appended, as clip2d does",
          "[apps]") {
  // mesh2d's .vtu was ASCII only (clip2d, clip3d and mesh3d had --binary / --compress).
  // check_mesh2d_tags.py reads the files back with meshio and compares them with the ASCII.
  const std::string ascii = temp_path(".vtu"), binary = temp_path(".vtu"), zlib = temp_path(".VTU");
  for (const auto& [path, flag] : {std::pair<std::string, std::string>{ascii, ""},
                                   {binary, "--binary"},
                                   {zlib, "--compress"}}) {
    std::vector<std::string> args = {"-q", "mesh2d", "annulus:1,2,32", "--vertices", "100",
                                     "-o", path};
    if (!flag.empty()) args.push_back(flag);
    const Run run = run_cli(args);
    REQUIRE(run.status == 0);
  }
  const std::string a = slurp(ascii), b = slurp(binary), z = slurp(zlib);
  CHECK(contains(a, "format=\"ascii\""));
  CHECK(!contains(a, "AppendedData"));
  CHECK(contains(b, "<AppendedData encoding=\"base64\">"));
  CHECK(!contains(b, "format=\"ascii\""));
  CHECK(!contains(b, "compressor="));
  CHECK(contains(z, "compressor=\"vtkZLibDataCompressor\""));
  CHECK(!contains(z, "format=\"ascii\""));
  CHECK(z.size() < b.size());
  for (const std::string& path : {ascii, binary, zlib}) std::remove(path.c_str());
  // Only a .vtu has those variants: a usage error before meshing, and no file.
  for (const auto& [ext, flag] : {std::pair<std::string, std::string>{".msh", "--binary"},
                                  {".mesh", "--compress"},
                                  {".svg", "--binary"}}) {
    const std::string out = temp_path(ext);
    const Run run = run_cli({"mesh2d", "annulus:1,2,32", "--vertices", "100", "-o", out, flag});
    CHECK(run.status == 2);
    check_one_error_line(run);
    CHECK(contains(run.err, flag + ": only a .vtu output (-o FILE.vtu) is written in binary or "
                                   "compressed"));
    CHECK(!exists(out));
  }
  const Run none = run_cli({"mesh2d", "annulus:1,2,32", "--vertices", "100", "--compress"});
  CHECK(none.status == 2);
  CHECK(contains(none.err, "(no output file is given)"));
}

TEST_CASE("mesh2d and mesh3d: a vertex count that cannot be made is refused before any work",
          "[apps][regression]") {
  // --sizing 1e-7 on a unit square implies about 10^14 vertices: the error said "more than
  // 10^9" without the count or what to change (now it says both); a count below 10^9 that the
  // memory cannot hold (--sizing 1e-4: 1.15e8 vertices, about 160 GB) was tried, and --vertices 4e9
  // gave "std::bad_alloc". Now: the count, the limit (32-bit indices, or the memory: physical, or
  // ulimit -v, at the bytes per vertex measured) and the option to change; no file.
  const std::string square = temp_path(".json");
  std::ofstream(square) << "[[[0,0],[1,0],[1,1],[0,1]]]\n";
  const std::string out = temp_path(".vtu");
  const std::string ulimit = "ulimit -v 1000000 &&";  // 1 GB: the memory bound, anywhere
  struct Case {
    std::vector<std::string> args;
    std::string prefix;
    std::string message;
  };
  const std::string larger = ": give a larger --edge-length or --sizing\n";
  const std::string in_ulimit = " fit in the address space allowed (ulimit -v) (1.02 GB at about ";
  const std::vector<Case> cases = {
      {{"mesh2d", square, "--edge-length", "1e-7", "-o", out},
       "",
       "mesh2d: --edge-length 1e-07 asks for about 115470053837925 vertices; at most 4294967295 "
       "fit 32-bit vertex indices" +
           larger},
      {{"mesh2d", square, "--sizing", "1e-7", "-o", out},
       "",
       "mesh2d: the edge length or sizing asks for about 115470053837925 vertices; at most "
       "10^9, the most mesh2d makes" +
           larger},
      {{"mesh2d", square, "--sizing", "1e-4", "-o", out},
       ulimit,
       "mesh2d: the sizing asks for about 115470054 vertices; at most 731428" + in_ulimit +
           "1400 bytes per vertex)" + larger},
      {{"mesh2d", square, "--vertices", "4000000000", "-o", out},
       ulimit,
       "mesh2d: --vertices asks for about 4000000000 vertices; at most 731428" + in_ulimit +
           "1400 bytes per vertex): give fewer --vertices\n"},
      {{"mesh3d", kData + "/surfaces/sphere.obj", "--vertices", "4000000000", "-o", out},
       ulimit,
       "mesh3d: --vertices asks for about 4000000000 vertices; at most 512000" + in_ulimit +
           "2000 bytes per vertex): give fewer --vertices\n"},
      // An absolute size alone: the count it implies is checked before the run, also under
      // -q (mesh3d ran out of memory).
      {{"mesh3d", kData + "/surfaces/sphere.obj", "--sizing", "0.005", "-o", out},
       ulimit,
       "mesh3d: the sizing asks for about 63043056 vertices; at most 512000" + in_ulimit +
           "2000 bytes per vertex): give a larger --sizing (or --vertices N)\n"},
      {{"mesh3d", kData + "/surfaces/sphere.obj", "--sizing", "0.005", "-q", "-o", out},
       ulimit,
       "mesh3d: the sizing asks for about 63043056 vertices; at most 512000" + in_ulimit +
           "2000 bytes per vertex): give a larger --sizing (or --vertices N)\n"},
  };
  for (const Case& c : cases) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
    // A sanitizer's shadow memory (terabytes of address space) cannot be reserved under
    // ulimit -v: the binary aborts before main. The memory bound is checked unsanitized.
    if (!c.prefix.empty()) continue;
#endif
    const Run run = run_cli(c.args, c.prefix);
    CHECK(run.status == 1);
    check_one_error_line(run);
    CHECK(run.err == "voroclip: error: " + c.message);
    CHECK_FALSE(contains(run.err, "vertices for this size"));  // refused before the note
    CHECK(!exists(out));
  }
  // A count that fits is said before the run, as mesh2d's.
  const Run fits = run_cli({"mesh3d", kData + "/surfaces/sphere.obj", "--sizing", "0.15"});
  CHECK(fits.status == 0);
  CHECK(contains(fits.out + fits.err, "mesh3d: about 2340 vertices for this size\n"));
  // mesh3d's bound on an absolute size says what to change too.
  const Run sizing = run_cli({"mesh3d", kData + "/surfaces/sphere.obj", "--sizing", "1e-5"});
  CHECK(sizing.status == 1);
  CHECK(contains(sizing.err,
                 " vertices; at most 2e9, the most mesh3d makes: give a larger "
                 "--sizing (or --vertices N)\n"));
  std::remove(square.c_str());
}
