// The mesh3d command: statistics (the quality keys), the three output formats read
// back, progress per phase, errors (one line, no partial file).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "cli_run.h"
#include "voroclip/core.h"

namespace {

const std::string kData = VOROCLIP_SHARED_DATA_DIR;

}  // namespace

TEST_CASE("mesh3d: a mesh below the dihedral bound says where and what may lift it", "[apps]") {
  // Without the sliver passes the Delaunay tets of a coarse CVT keep slivers: the verdict
  // names the worst tet, its centroid and how many of its vertices lie on the boundary, as
  // the written mesh has them.
  const std::string domain = kData + "/surfaces/sphere.obj";
  const std::string out = temp_path(".mesh");
  const Run run = run_cli({"--stats", "json", "mesh3d", domain, "--vertices", "300",
                           "--unconstrained-iterations", "4", "--constrained-iterations", "6",
                           "--no-perturb", "--flip-angle", "0", "--mean-rounds", "0", "-o", out});
  REQUIRE(run.status == 0);
  const nlohmann::json s = nlohmann::json::parse(run.out);
  REQUIRE(s["dihedral_bound"]["tets_below"].get<int>() > 0);
  const voroclip::TetMeshInput mesh = voroclip::read_tet_mesh(out);
  std::remove(out.c_str());
  const std::string key = "degrees, at tet ";
  const std::size_t at = run.err.find(key);
  REQUIRE(at != std::string::npos);
  std::istringstream line(run.err.substr(at + key.size()));
  std::uint32_t t = 0;
  std::string word;
  double c[3];
  int on_boundary = -1;
  line >> t >> word >> c[0] >> c[1] >> c[2];
  CHECK(word == "(centroid");
  line.ignore(2) >> on_boundary;
  REQUIRE(t < mesh.nb_tets());
  std::vector<char> boundary(mesh.nb_vertices(), 0);
  for (const std::uint32_t v : mesh.triangles) boundary[v] = 1;
  int expected = 0;
  for (int k = 0; k < 4; ++k) {
    const std::uint32_t v = mesh.tets[4 * std::size_t{t} + k];
    expected += boundary[v];
    for (int d = 0; d < 3; ++d) c[d] -= mesh.xyz[3 * std::size_t{v} + d] / 4;
  }
  CHECK(on_boundary == expected);
  CHECK(std::fabs(c[0]) + std::fabs(c[1]) + std::fabs(c[2]) < 1e-5);
  CHECK(contains(run.err,
                 "Another --seed, or a smaller edge length there (--sizing), can lift it; "
                 "so can the sliver perturbation (off: --no-perturb)"));
}

TEST_CASE("mesh3d: statistics, progress and the output formats", "[apps]") {
  const std::string domain = kData + "/tetmeshes/sphere.mesh";
  const std::string out = temp_path(".mesh");
  const Run run =
      run_cli({"--stats", "json", "mesh3d", domain, "--vertices", "600",
               "--unconstrained-iterations", "6", "--constrained-iterations", "9", "-o", out});
  REQUIRE(run.status == 0);
  const nlohmann::json s = nlohmann::json::parse(run.out);
  for (const char* key :
       {"tets", "vertices", "min_dihedral_deg", "mean_min_dihedral_deg", "max_dihedral_deg",
        "min_q3", "mean_q3", "min_q4", "mean_q4", "hausdorff_rel"}) {
    INFO(key);
    CHECK(s.contains(key));
  }
  const voroclip::TetMeshInput mesh = voroclip::read_tet_mesh(out);
  std::remove(out.c_str());
  CHECK(s["tets"].get<std::uint32_t>() == mesh.nb_tets());
  CHECK(s["vertices"].get<std::uint32_t>() == mesh.nb_vertices());
  CHECK(mesh.nb_vertices() > 550);
  CHECK(s["min_dihedral_deg"].get<double>() > 20);
  CHECK(s["mean_min_dihedral_deg"].get<double>() > 50);
  CHECK(s["min_q4"].get<double>() > 0.4);
  CHECK(s["hausdorff_rel"].get<double>() < 0.01);
  CHECK(s["inverted_tets"].get<int>() == 0);
  CHECK(s["vertex_kinds"]["surface"].get<int>() > 0);
  CHECK(s["surface"] == "flat");
  CHECK(s["seconds"]["constrained"].get<double>() > 0);
  // The dihedral verdict: a sphere's facets meet at nearly 180 degrees, so the bound is 20,
  // and every tet's smallest angle is above it (min_dihedral_deg > 20 above).
  CHECK(s["dihedral_bound"]["bound_deg"].get<double>() == 20);
  CHECK(s["dihedral_bound"]["input_sharpest_dihedral_deg"].get<double>() > 150);
  CHECK(s["dihedral_bound"]["tets_below"].get<int>() == 0);
  CHECK(contains(run.err, "Dihedral angles: every tet's smallest is at least the bound 20.00"));
  // Human text goes to stderr with --stats json: progress per phase, then the report.
  CHECK(contains(run.err, "unconstrained CVT"));
  CHECK(contains(run.err, "constrained CVT iteration"));
  CHECK(contains(run.err, "|g|"));
  CHECK(contains(run.err, "slivers"));

  for (const char* version : {"2.2", "4.1"}) {
    const std::string msh = temp_path(".msh");
    const Run w =
        run_cli({"-q", "mesh3d", domain, "--vertices", "300", "--unconstrained-iterations", "4",
                 "--constrained-iterations", "6", "--msh-version", version, "-o", msh});
    CHECK(w.status == 0);
    CHECK(w.out.empty());
    const std::string text = slurp(msh);
    CHECK(contains(text, std::string("$MeshFormat\n") + version));
    CHECK(voroclip::read_tet_mesh(msh).nb_tets() > 0);
    std::remove(msh.c_str());
  }
  // By default the surface vertices lie on the boundary triangles: the sphere's surface
  // vertices then lie inside the unit sphere (the facets are chords); with --smooth-surface
  // not all of them.
  {
    const std::string smooth_out = temp_path(".mesh");
    const std::string flat_out = temp_path(".mesh");
    const Run a = run_cli({"-q", "mesh3d", domain, "--vertices", "300",
                           "--unconstrained-iterations", "4", "--constrained-iterations", "6",
                           "--no-perturb", "--smooth-surface", "-o", smooth_out});
    const Run b = run_cli({"--stats", "json", "mesh3d", domain, "--vertices", "300",
                           "--unconstrained-iterations", "4", "--constrained-iterations", "6",
                           "--no-perturb", "-o", flat_out});
    REQUIRE(a.status == 0);
    REQUIRE(b.status == 0);
    CHECK(nlohmann::json::parse(b.out)["surface"] == "flat");
    const auto max_radius = [](const voroclip::TetMeshInput& m) {
      double r = 0;
      for (std::uint32_t v = 0; v < m.nb_vertices(); ++v) {
        const double* p = &m.xyz[3 * std::size_t{v}];
        r = std::max(r, std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]));
      }
      return r;
    };
    CHECK(max_radius(voroclip::read_tet_mesh(flat_out)) <= 1 + 1e-12);
    CHECK(max_radius(voroclip::read_tet_mesh(smooth_out)) > 1 + 1e-6);
    std::remove(smooth_out.c_str());
    std::remove(flat_out.c_str());
  }
  const std::string vtu = temp_path(".vtu");
  const Run w = run_cli({"-q", "mesh3d", domain, "--vertices", "300", "--unconstrained-iterations",
                         "4", "--constrained-iterations", "6", "-o", vtu});
  CHECK(w.status == 0);
  CHECK(contains(slurp(vtu), "q1_min_dihedral_deg"));
  CHECK(voroclip::read_tet_mesh(vtu).nb_tets() > 0);
  std::remove(vtu.c_str());
}

TEST_CASE("mesh3d: errors name the problem, leave no file", "[apps]") {
  const std::string domain = kData + "/tetmeshes/sphere.mesh";
  const std::string out = temp_path(".mesh");
  SECTION("no vertex count") {
    const Run run = run_cli({"mesh3d", domain, "-o", out});
    CHECK(run.status == 2);
    check_one_error_line(run);
  }
  SECTION("an unknown output format") {
    const std::string bad = temp_path(".xyz");
    const Run run = run_cli({"mesh3d", domain, "--vertices", "100", "-o", bad});
    CHECK(run.status == 2);
    check_one_error_line(run);
    CHECK(contains(run.err, ".xyz"));
    CHECK_FALSE(exists(bad));
  }
  SECTION("--binary or --compress for a format that has no such encoding") {
    for (const auto& [option, file] : {std::pair<std::string, std::string>{"--binary", ".mesh"},
                                       {"--binary", ".vtu"},
                                       {"--compress", ".msh"}}) {
      INFO(option << " " << file);
      const std::string bad = temp_path(file);
      const Run run = run_cli({"mesh3d", domain, "--vertices", "100", option, "-o", bad});
      CHECK(run.status == 2);
      check_one_error_line(run);
      CHECK(contains(run.err, option));
      CHECK_FALSE(exists(bad));
    }
    const Run v22 = run_cli({"mesh3d", domain, "--vertices", "100", "--binary", "--msh-version",
                             "2.2", "-o", temp_path(".msh")});
    CHECK(v22.status == 2);
  }
  SECTION("a feature angle out of range") {
    const Run run = run_cli({"mesh3d", domain, "--vertices", "100", "--feature-angle", "200"});
    CHECK(run.status == 2);
    check_one_error_line(run);
    CHECK(contains(run.err, "feature-angle"));
  }
  SECTION("a smooth shape out of range") {
    const Run run = run_cli({"mesh3d", domain, "--vertices", "100", "--smooth-shape", "2"});
    CHECK(run.status == 2);
    check_one_error_line(run);
    CHECK(contains(run.err, "smooth-shape"));
  }
  SECTION("a bad Gmsh version") {
    const Run run = run_cli({"mesh3d", domain, "--vertices", "100", "--msh-version", "3"});
    CHECK(run.status == 2);
    check_one_error_line(run);
  }
  SECTION("a missing domain") {
    const Run run =
        run_cli({"mesh3d", kData + "/tetmeshes/no-such.mesh", "--vertices", "100", "-o", out});
    CHECK(run.status == 1);
    check_one_error_line(run);
    CHECK(contains(run.err, "no-such.mesh"));
  }
  SECTION("too few vertices") {
    const Run run = run_cli({"mesh3d", domain, "--vertices", "3", "-o", out});
    CHECK(run.status == 2);
    check_one_error_line(run);
  }
  CHECK_FALSE(exists(out));
}

TEST_CASE("mesh3d from a closed surface: the mesh read back, its volume the surface's", "[apps]") {
  const std::string domain = kData + "/surfaces/sphere.obj";
  const std::string out = temp_path(".mesh");
  const Run run =
      run_cli({"--stats", "json", "mesh3d", domain, "--vertices", "600",
               "--unconstrained-iterations", "6", "--constrained-iterations", "9", "-o", out});
  REQUIRE(run.status == 0);
  const nlohmann::json s = nlohmann::json::parse(run.out);
  const voroclip::TetMeshInput mesh = voroclip::read_tet_mesh(out);
  std::remove(out.c_str());
  CHECK(s["tets"].get<std::uint32_t>() == mesh.nb_tets());
  CHECK(mesh.nb_vertices() > 550);
  CHECK(s["min_dihedral_deg"].get<double>() > 20);
  CHECK(s["hausdorff_rel"].get<double>() < 0.02);
  // The tets fill the sphere's volume, less the sag of the output's coarser boundary facets
  // (about 2 % with 600 vertices).
  double volume = 0;
  for (std::uint32_t t = 0; t < mesh.nb_tets(); ++t) {
    const double* p[4];
    for (int k = 0; k < 4; ++k) p[k] = &mesh.xyz[3 * std::size_t{mesh.tets[4 * t + k]}];
    double u[3][3];
    for (int k = 0; k < 3; ++k) {
      for (int c = 0; c < 3; ++c) u[k][c] = p[k + 1][c] - p[0][c];
    }
    volume += (u[0][0] * (u[1][1] * u[2][2] - u[1][2] * u[2][1]) -
               u[0][1] * (u[1][0] * u[2][2] - u[1][2] * u[2][0]) +
               u[0][2] * (u[1][0] * u[2][1] - u[1][1] * u[2][0])) /
              6;
  }
  const voroclip::TriangleSurface sphere = voroclip::read_surface(domain);
  double enclosed = 0;
  for (std::size_t t = 0; t < sphere.triangles.size(); t += 3) {
    const double* a = &sphere.xyz[3 * std::size_t{sphere.triangles[t]}];
    const double* b = &sphere.xyz[3 * std::size_t{sphere.triangles[t + 1]}];
    const double* c = &sphere.xyz[3 * std::size_t{sphere.triangles[t + 2]}];
    enclosed += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                 a[2] * (b[0] * c[1] - b[1] * c[0])) /
                6;
  }
  CHECK(volume < enclosed);
  CHECK(volume > 0.96 * enclosed);
}

TEST_CASE("mesh3d: sites added for the surface's topology, or an error naming the count",
          "[apps]") {
  const std::string domain = kData + "/surfaces/bunny.obj";
  const std::string out = temp_path(".mesh");
  const Run e = run_cli({"mesh3d", domain, "--vertices", "400", "--unconstrained-iterations", "8",
                         "--constrained-iterations", "12", "-o", out, "--exact-vertices"});
  CHECK(e.status == 1);
  CHECK(contains(e.err, "400 vertices do not resolve the surface of"));
  CHECK(contains(e.err, "vertices would"));
  CHECK_FALSE(std::ifstream(out).good());

  const Run r =
      run_cli({"--stats", "json", "mesh3d", domain, "--vertices", "400",
               "--unconstrained-iterations", "8", "--constrained-iterations", "12", "-o", out});
  REQUIRE(r.status == 0);
  const nlohmann::json s = nlohmann::json::parse(r.out);
  const int added = s["topology"]["sites_added"].get<int>();
  CHECK(added > 0);
  // The topology's sites only (it said "(400 -> N)", N with the sliver sites and the lattice's
  // deviation from 400 too).
  CHECK(contains(r.err, "note: " + std::to_string(added) + (added == 1 ? " site" : " sites") +
                            " added where 400 did not resolve the surface"));
  CHECK(s["topology"]["defects_left"].get<int>() == 0);
  CHECK(s["shape_problem"] == "");
  CHECK(s["region_tags"] == nlohmann::json::array({1}));
  const voroclip::TetMeshInput mesh = voroclip::read_tet_mesh(out);
  std::remove(out.c_str());
  CHECK(s["boundary_triangles"].get<std::uint32_t>() == mesh.nb_triangles());
  CHECK(mesh.nb_triangles() > 0);
  CHECK(mesh.triangle_ref.size() == mesh.nb_triangles());
  CHECK(
      std::all_of(mesh.tet_ref.begin(), mesh.tet_ref.end(), [](std::int32_t t) { return t == 1; }));
}

TEST_CASE("mesh3d warns of an embedded surface it does not follow, and lists it in the stats",
          "[apps][regression]") {
  // Trial 10: a Gmsh mesh with a "sensor" surface inside its one region lost it silently.
  // Here a unit cube of six Kuhn tets, one region, its inner triangle (0, 1, 7) tagged 9.
  voroclip::TetMeshInput in;
  for (std::uint32_t v = 0; v < 8; ++v) {
    for (std::uint32_t k = 0; k < 3; ++k) in.xyz.push_back(static_cast<double>((v >> k) & 1u));
  }
  in.tets = {0, 1, 3, 7, 0, 2, 3, 7, 0, 1, 5, 7, 0, 2, 6, 7, 0, 4, 5, 7, 0, 4, 6, 7};
  in.tet_ref.assign(6, 1);
  in.triangles = {0, 1, 7};
  in.triangle_ref = {9};
  in.tag_names = {{2, 9, "sensor"}, {3, 1, "air"}};
  const std::string input = temp_path(".msh");
  voroclip::write_tet_mesh(input, in, voroclip::TetMeshFormat::kGmsh41);
  const std::string out = temp_path(".msh");
  const Run run = run_cli({"--stats", "json", "mesh3d", input, "--vertices", "200", "-o", out});
  std::remove(input.c_str());
  std::remove(out.c_str());
  REQUIRE(run.status == 0);
  CHECK(contains(run.err, "warning: the mesh of " + input +
                              " does not follow the input's embedded surface of tag 9 \"sensor\" "
                              "(1 triangle)"));
  const nlohmann::json s = nlohmann::json::parse(run.out);
  const nlohmann::json expected =
      nlohmann::json::array({nlohmann::json{{"tag", 9}, {"name", "sensor"}, {"triangles", 1}}});
  CHECK(s["embedded_tags_not_followed"] == expected);
}

TEST_CASE("mesh3d and clip3d say that second-order elements are read by their corners",
          "[apps][regression]") {
  // A Gmsh 4.1 mesh of one 10-node tet (type 11) and a 6-node triangle (type 9) on its face
  // z = 0 was meshed as the straight tet without a word.
  const std::string input = temp_path(".msh");
  {
    std::ofstream f(input);
    f << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 10 1 10\n3 1 0 10\n";
    for (int i = 1; i <= 10; ++i) f << i << "\n";
    f << "0 0 0\n1 0 0\n0 1 0\n0 0 1\n0.5 0 0\n0.5 0.5 0\n0 0.5 0\n0 0 0.5\n0 0.5 0.5\n"
         "0.5 0 0.5\n$EndNodes\n$Elements\n2 2 1 2\n2 1 9 1\n1 1 3 2 7 6 5\n"
         "3 1 11 1\n2 1 2 3 4 5 6 7 8 9 10\n$EndElements\n";
  }
  const std::string out = temp_path(".mesh"), cells = temp_path(".vtu");
  const Run mesh = run_cli({"mesh3d", input, "--vertices", "60", "-o", out});
  const Run clip = run_cli({"clip3d", input, "--random", "10", "-o", cells});
  for (const std::string& f : {input, out, cells}) std::remove(f.c_str());
  const std::string note = "note: " + input +
                           ": 1 tetrahedron and 1 triangle of second order or higher read by "
                           "their corners: the domain is made of straight tets";
  REQUIRE(mesh.status == 0);
  CHECK(contains(mesh.out, note));
  CHECK(contains(clip.out + clip.err, note));
}
