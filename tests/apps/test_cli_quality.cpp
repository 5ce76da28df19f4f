// The quality command: its JSON statistics equal the library's figures, the text report,
// the SVG and VTU outputs, inverted and degenerate tets reported, and errors with the file
// and line, leaving no output file.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_run.h"
#include "voroclip/core.h"
#include "voroclip/mesh.h"

namespace {

const std::string kData = VOROCLIP_SHARED_DATA_DIR;

void write_text_file(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

}  // namespace

TEST_CASE("quality: --stats json equals the library's figures", "[apps]") {
  const std::string mesh = kData + "/tetmeshes/bunny.mesh";
  const std::string ref = kData + "/surfaces/bunny.obj";
  const Run run = run_cli({"quality", mesh, "--surface", ref, "--stats", "json"});
  REQUIRE(run.status == 0);
  const nlohmann::json s = nlohmann::json::parse(run.out);
  const voroclip::TetMeshInput input = voroclip::read_tet_mesh(mesh);
  const voroclip::TetQuality q = voroclip::tet_quality(input);
  CHECK(s["tets"] == 14050);
  CHECK(s["vertices"] == 4083);
  CHECK(s["inverted_tets"] == 0);
  CHECK(s["degenerate_tets"] == 0);
  // JSON numbers round-trip doubles: the same bits.
  CHECK(s["min_dihedral_deg"].get<double>() == q.q1_deg.min);
  CHECK(s["mean_min_dihedral_deg"].get<double>() == q.q1_deg.mean);
  CHECK(s["max_dihedral_deg"].get<double>() == q.q2_deg.max);
  CHECK(s["min_q3"].get<double>() == q.q3.min);
  CHECK(s["mean_q3"].get<double>() == q.q3.mean);
  CHECK(s["min_q4"].get<double>() == q.q4.min);
  CHECK(s["mean_q4"].get<double>() == q.q4.mean);
  CHECK(s["histograms"]["dihedral_deg"]["counts"].get<std::vector<std::uint64_t>>() ==
        q.dihedral_histogram);
  // The tet mesh's boundary is the reference surface (data README): distance 0.
  const voroclip::HausdorffDistance d =
      voroclip::hausdorff_distance(voroclip::tet_mesh_boundary(input), voroclip::read_surface(ref));
  CHECK(s["hausdorff_rel"].get<double>() == d.max_relative());
  CHECK(s["hausdorff_mean_rel"].get<double>() == d.mean_relative());
  CHECK(s["hausdorff_rel"].get<double>() <= 1e-15);
  CHECK(s["seconds"]["total"].get<double>() >= 0);
  // Without --surface there is no distance.
  const Run plain = run_cli({"quality", mesh, "--stats", "json", "-q"});
  REQUIRE(plain.status == 0);
  CHECK_FALSE(nlohmann::json::parse(plain.out).contains("hausdorff_rel"));
}

TEST_CASE("quality: a reference given as a tet mesh, the text report and the files", "[apps]") {
  const std::string svg = temp_path(".svg"), vtu = temp_path(".vtu");
  const std::string mesh = kData + "/tetmeshes/sphere.mesh";
  const Run run = run_cli({"quality", mesh, "--surface", kData + "/tetmeshes/sphere-fine.mesh",
                           "--histogram", svg, "-o", vtu, "--samples", "20000"});
  REQUIRE(run.status == 0);
  CHECK(contains(run.out, "Tet mesh quality of " + mesh + ": 2413 tets, 763 vertices"));
  CHECK(contains(run.out, "every tet has the same orientation"));
  CHECK(contains(run.out, "Q1 min dihedral angle (deg)"));
  CHECK(contains(run.out, "Hausdorff distance to " + kData + "/tetmeshes/sphere-fine.mesh"));
  const std::string picture = slurp(svg);
  CHECK(picture.rfind("<svg", 0) == 0);
  CHECK(contains(picture, "Q4 = 12 (9V^2)^(1/3) / sum l^2"));
  const voroclip::TetMeshInput back = voroclip::read_tet_mesh(vtu);
  const voroclip::TetMeshInput input = voroclip::read_tet_mesh(mesh);
  CHECK(back.xyz == input.xyz);
  CHECK(back.tets == input.tets);
  CHECK(contains(slurp(vtu), "Name=\"q1_min_dihedral_deg\""));
  std::remove(svg.c_str());
  std::remove(vtu.c_str());
}

TEST_CASE("quality: inverted and degenerate tets are reported, exit status 0", "[apps]") {
  const std::string path = temp_path(".mesh");
  write_text_file(path,
                  "MeshVersionFormatted 2\nDimension 3\nVertices\n5\n"
                  "0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n1 1 0 0\n"
                  "Tetrahedra\n4\n1 2 3 4 0\n2 5 3 4 0\n1 3 2 4 0\n1 2 5 3 0\nEnd\n");
  const Run run = run_cli({"quality", path});
  CHECK(run.status == 0);
  CHECK(contains(run.out, "WARNING: 1 inverted tet (oriented unlike the other 2): 2"));
  CHECK(contains(run.out, "WARNING: 1 degenerate tet (zero volume, exact): 3"));
  const Run json = run_cli({"-q", "--stats", "json", "quality", path});
  REQUIRE(json.status == 0);
  const nlohmann::json s = nlohmann::json::parse(json.out);
  CHECK(s["inverted_tets"] == 1);
  CHECK(s["degenerate_tets"] == 1);
  CHECK(s["inverted"] == nlohmann::json::array({2}));
  CHECK(s["min_dihedral_deg"].get<double>() == 0);
  std::remove(path.c_str());
}

TEST_CASE("quality: errors name the file and line, leave no file", "[apps]") {
  const std::string svg = temp_path(".svg");
  SECTION("a missing mesh") {
    const Run run = run_cli({"quality", "/nonexistent.mesh", "--histogram", svg});
    CHECK(run.status == 1);
    check_one_error_line(run);
    CHECK(contains(run.err, "/nonexistent.mesh: cannot open the file"));
  }
  SECTION("a bad line in the mesh") {
    const std::string path = temp_path(".mesh");
    write_text_file(path,
                    "MeshVersionFormatted 2\nDimension 3\nVertices\n4\n"
                    "0 0 0 0\n1 0 0 0\n0 1 x 0\n0 0 1 0\nTetrahedra\n1\n1 2 3 4 0\nEnd\n");
    const Run run = run_cli({"quality", path, "--histogram", svg});
    CHECK(run.status == 1);
    check_one_error_line(run);
    CHECK(contains(run.err, path + ":7: 'x' is not a number"));
    std::remove(path.c_str());
  }
  SECTION("a bad reference surface: no partial picture") {
    const std::string ref = temp_path(".obj");
    write_text_file(ref, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 5\n");
    const Run run = run_cli(
        {"quality", kData + "/tetmeshes/sphere.mesh", "--surface", ref, "--histogram", svg});
    CHECK(run.status == 1);
    check_one_error_line(run);
    CHECK(contains(run.err, ref + ":4: face 1: vertex 5 is out of range 1..3"));
    std::remove(ref.c_str());
  }
  SECTION("an unknown reference format") {
    const Run run = run_cli({"quality", kData + "/tetmeshes/sphere.mesh", "--surface", "ref.xyz"});
    CHECK(run.status == 2);
    check_one_error_line(run);
    CHECK(contains(run.err, "--surface: unknown format '.xyz'"));
  }
  SECTION("a histogram that is not SVG") {
    const Run run = run_cli({"quality", kData + "/tetmeshes/sphere.mesh", "--histogram", "h.png"});
    CHECK(run.status == 2);
    check_one_error_line(run);
  }
  CHECK_FALSE(exists(svg));
}

TEST_CASE("quality --compress: a zlib .vtu that reads back the same", "[apps]") {
  const std::string mesh = kData + "/tetmeshes/sphere.mesh";
  const std::string vtu = temp_path(".vtu");
  const Run run = run_cli({"-q", "quality", mesh, "-o", vtu, "--compress"});
  REQUIRE(run.status == 0);
  const std::string text = slurp(vtu);
  CHECK(contains(text, "compressor=\"vtkZLibDataCompressor\""));
  CHECK(contains(text, "Name=\"q4\""));
  const voroclip::TetMeshInput back = voroclip::read_tet_mesh(vtu);
  const voroclip::TetMeshInput input = voroclip::read_tet_mesh(mesh);
  CHECK(back.xyz == input.xyz);
  CHECK(back.tets == input.tets);
  std::remove(vtu.c_str());
  const Run bad = run_cli({"quality", mesh, "--compress"});
  CHECK(bad.status == 2);
  check_one_error_line(bad);
  CHECK(contains(bad.err, "--compress"));
}

TEST_CASE("quality: --samples without --surface is a usage error", "[apps][regression]") {
  // It was accepted and ignored: no distance is measured without a reference surface.
  const Run run = run_cli({"quality", kData + "/tetmeshes/sphere.mesh", "--samples", "1000"});
  CHECK(run.status == 2);
  CHECK(run.err.find("--samples: only with --surface") != std::string::npos);
  CHECK(run.out.empty());
}
