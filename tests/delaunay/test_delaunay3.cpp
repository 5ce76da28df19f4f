// Delaunay3: exact checks on every result (check_topology, check_delaunay), a brute-force
// oracle on small sets, degenerate families, duplicates, a scale sweep and real models.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numeric>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "support/threads.h"
#include "tet_set.h"
#include "voroclip/core.h"
#include "voroclip/delaunay.h"
#include "voroclip/predicates.h"
#include "with_threads.h"

using voroclip::Delaunay3;
using voroclip::Sign;

namespace {

using voroclip::test::finite_tets;
using voroclip::test::Tet;

void require_valid(const Delaunay3& dt) {
  const std::string topology = dt.check_topology();
  INFO(topology);
  REQUIRE(topology.empty());
  const std::string delaunay = dt.check_delaunay();
  INFO(delaunay);
  REQUIRE(delaunay.empty());
}

std::vector<double> random_points(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> xyz(3 * n);
  for (double& x : xyz) x = u(rng);
  return xyz;
}

// 6 x volume of finite tet t with orient3d's sign convention (det[p0-p3; p1-p3; p2-p3]),
// exact for small integer coordinates.
double six_volume(const Delaunay3& dt, const std::vector<double>& xyz, std::uint32_t t) {
  const double* p[4];
  for (int k = 0; k < 4; ++k) p[k] = &xyz[3 * static_cast<std::size_t>(dt.tet_vertex(t, k))];
  double m[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m[i][j] = p[i][j] - p[3][j];
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
         m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

// Brute force: all 4-subsets that form a tet whose circumsphere (perturbed) contains no
// other point. With symbolic perturbation the Delaunay triangulation is unique.
std::vector<Tet> brute_force(const std::vector<double>& xyz) {
  const auto n = static_cast<std::uint32_t>(xyz.size() / 3);
  const auto p = [&](std::uint32_t i) { return &xyz[3 * static_cast<std::size_t>(i)]; };
  std::vector<Tet> out;
  for (std::uint32_t a = 0; a < n; ++a)
    for (std::uint32_t b = a + 1; b < n; ++b)
      for (std::uint32_t c = b + 1; c < n; ++c)
        for (std::uint32_t d = c + 1; d < n; ++d) {
          Tet t = {a, b, c, d};
          const Sign o = voroclip::orient3d(p(a), p(b), p(c), p(d));
          if (o == Sign::zero) continue;
          if (o == Sign::negative) std::swap(t[0], t[1]);
          bool empty = true;
          for (std::uint32_t e = 0; e < n && empty; ++e) {
            if (e == a || e == b || e == c || e == d) continue;
            empty = voroclip::insphere_sos(p(t[0]), p(t[1]), p(t[2]), p(t[3]), p(e), t[0], t[1],
                                           t[2], t[3], e) == Sign::negative;
          }
          if (empty) out.push_back({a, b, c, d});
        }
  std::sort(out.begin(), out.end());
  return out;
}

// Vertices of an OBJ ("v x y z" lines) or OFF (header, counts, then coordinates) surface.
std::vector<double> read_surface_vertices(const std::string& path) {
  std::ifstream in(path);
  std::vector<double> xyz;
  if (path.size() > 4 && path.compare(path.size() - 4, 4, ".off") == 0) {
    std::string magic;
    std::size_t nv = 0, nf = 0, ne = 0;
    in >> magic >> nv >> nf >> ne;
    xyz.resize(3 * nv);
    for (double& x : xyz) in >> x;
    return xyz;
  }
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("v ", 0) != 0) continue;
    std::istringstream fields(line.substr(2));
    double x = 0, y = 0, z = 0;
    fields >> x >> y >> z;
    xyz.insert(xyz.end(), {x, y, z});
  }
  return xyz;
}

std::vector<double> read_medit_vertices(const std::string& path) {
  std::ifstream in(path);
  std::string word;
  std::vector<double> xyz;
  while (in >> word) {
    if (word == "Vertices") {
      std::size_t n = 0;
      in >> n;
      xyz.resize(3 * n);
      for (std::size_t i = 0; i < n; ++i) {
        int ref = 0;
        in >> xyz[3 * i] >> xyz[3 * i + 1] >> xyz[3 * i + 2] >> ref;
      }
      break;
    }
  }
  return xyz;
}

}  // namespace

TEST_CASE("Delaunay3 on uniform random points", "[delaunay]") {
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    INFO("seed " << seed);
    const auto xyz = random_points(5000, seed);
    const Delaunay3 dt(xyz.data(), 5000);
    require_valid(dt);
    CHECK(dt.nb_unique_points() == 5000);
    // Uniform random points in a cube: about 6.5 tets per point.
    CHECK(dt.nb_finite_tets() > 6 * 5000);
    CHECK(dt.nb_finite_tets() < 7 * 5000);
  }
}

TEST_CASE("Delaunay3 equals the brute-force Delaunay tets on small sets", "[delaunay][exact]") {
  for (std::uint64_t seed = 10; seed < 16; ++seed) {
    INFO("seed " << seed);
    const auto xyz = random_points(18, seed);
    const Delaunay3 dt(xyz.data(), 18);
    require_valid(dt);
    CHECK(finite_tets(dt) == brute_force(xyz));
  }
  SECTION("degenerate: cube corners and a 3x3x3 grid") {
    std::vector<double> grid;
    for (int x = 0; x < 3; ++x)
      for (int y = 0; y < 3; ++y)
        for (int z = 0; z < 3; ++z) grid.insert(grid.end(), {double(x), double(y), double(z)});
    const Delaunay3 dt(grid.data(), 27);
    require_valid(dt);
    CHECK(finite_tets(dt) == brute_force(grid));
  }
}

TEST_CASE("Delaunay3 on grids: no flat tet, volumes add up to the box", "[delaunay][degenerate]") {
  for (const int m : {2, 4, 7}) {
    INFO("grid " << m << "^3");
    std::vector<double> xyz;
    for (int x = 0; x < m; ++x)
      for (int y = 0; y < m; ++y)
        for (int z = 0; z < m; ++z) xyz.insert(xyz.end(), {double(x), double(y), double(z)});
    const Delaunay3 dt(xyz.data(), static_cast<std::uint32_t>(m * m * m));
    require_valid(dt);
    double six_v = 0;
    for (std::uint32_t t = 0; t < dt.nb_tet_slots(); ++t) {
      if (dt.is_free(t) || dt.is_infinite(t)) continue;
      const double v = six_volume(dt, xyz, t);
      CHECK(v > 0);
      six_v += v;
    }
    const double side = m - 1;
    CHECK(six_v == 6 * side * side * side);
    CHECK(dt.hull_vertices().size() ==
          static_cast<std::size_t>(m * m * m - (m - 2) * (m - 2) * (m - 2)));
  }
}

TEST_CASE("Delaunay3 on cospherical integer points", "[delaunay][degenerate]") {
  // All integer points with x^2 + y^2 + z^2 = 3^2 * 5^2 = 225, and the centre.
  std::vector<double> xyz;
  for (int x = -15; x <= 15; ++x)
    for (int y = -15; y <= 15; ++y)
      for (int z = -15; z <= 15; ++z)
        if (x * x + y * y + z * z == 225) xyz.insert(xyz.end(), {double(x), double(y), double(z)});
  const auto n_sphere = static_cast<std::uint32_t>(xyz.size() / 3);
  REQUIRE(n_sphere > 50);
  {
    const Delaunay3 dt(xyz.data(), n_sphere);
    require_valid(dt);
    CHECK(dt.hull_vertices().size() == n_sphere);
  }
  xyz.insert(xyz.end(), {0.0, 0.0, 0.0});
  const Delaunay3 dt(xyz.data(), n_sphere + 1);
  require_valid(dt);
  std::vector<std::uint32_t> star;
  dt.vertex_neighbors(n_sphere, star);
  CHECK(star.size() == n_sphere);  // the centre sees every point of the sphere
}

TEST_CASE("Delaunay3 reports duplicates and keeps the smallest index", "[delaunay][degenerate]") {
  auto xyz = random_points(300, 7);
  std::mt19937_64 rng(99);
  // Copy points over others: index j takes the coordinates of index i.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> copies;
  for (int k = 0; k < 100; ++k) {
    const auto i = static_cast<std::uint32_t>(rng() % 300);
    const auto j = static_cast<std::uint32_t>(rng() % 300);
    if (i == j) continue;
    std::copy_n(&xyz[3 * i], 3, &xyz[3 * j]);
  }
  const Delaunay3 dt(xyz.data(), 300);
  require_valid(dt);
  std::uint32_t unique = 0;
  for (std::uint32_t i = 0; i < 300; ++i) {
    std::uint32_t smallest = i;
    for (std::uint32_t j = 0; j < i; ++j) {
      if (std::equal(&xyz[3 * j], &xyz[3 * j + 3], &xyz[3 * i])) {
        smallest = j;
        break;
      }
    }
    CHECK(dt.duplicate_of(i) == smallest);
    unique += smallest == i ? 1 : 0;
  }
  CHECK(dt.nb_unique_points() == unique);
}

TEST_CASE("Delaunay3 rejects degenerate and invalid input", "[delaunay]") {
  const std::vector<double> coplanar = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 2, 3, 0};
  CHECK_THROWS_AS(Delaunay3(coplanar.data(), 5), voroclip::Error);
  const std::vector<double> collinear = {0, 0, 0, 1, 1, 1, 2, 2, 2, 3, 3, 3};
  CHECK_THROWS_AS(Delaunay3(collinear.data(), 4), voroclip::Error);
  const std::vector<double> same = {1, 2, 3, 1, 2, 3, 1, 2, 3, 1, 2, 3, 1, 2, 3};
  CHECK_THROWS_AS(Delaunay3(same.data(), 5), voroclip::Error);
  const std::vector<double> three = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  CHECK_THROWS_AS(Delaunay3(three.data(), 3), voroclip::Error);
  std::vector<double> nan = random_points(10, 1);
  nan[7] = std::nan("");
  try {
    Delaunay3 dt(nan.data(), 10);
    FAIL("expected an error");
  } catch (const voroclip::Error& e) {
    CHECK(std::string(e.what()).find("point 2") != std::string::npos);
  }
}

TEST_CASE("Delaunay3 is invariant under scaling by powers of two", "[delaunay][exact]") {
  const auto base = random_points(2000, 5);
  const Delaunay3 ref(base.data(), 2000);
  require_valid(ref);
  const auto expected = finite_tets(ref);
  for (const int e : {-40, -20, 20, 40}) {
    INFO("scale 2^" << e);
    std::vector<double> xyz(base);
    for (double& x : xyz) x = std::ldexp(x, e);
    const Delaunay3 dt(xyz.data(), 2000);
    require_valid(dt);
    CHECK(finite_tets(dt) == expected);
  }
}

TEST_CASE("Delaunay3 rebuild reuses the object", "[delaunay]") {
  Delaunay3 dt;
  for (std::uint64_t seed = 20; seed < 23; ++seed) {
    const auto xyz = random_points(1000, seed);
    dt.build(xyz.data(), 1000);
    require_valid(dt);
    const Delaunay3 fresh(xyz.data(), 1000);
    CHECK(finite_tets(dt) == finite_tets(fresh));
  }
}

TEST_CASE("Delaunay3 on the vertices of every real model", "[delaunay][data]") {
  // Every tet mesh and every surface of ../shared/data (the real-data check).
  const std::string data = VOROCLIP_SHARED_DATA_DIR;
  std::vector<std::string> files;
  for (const char* dir : {"/tetmeshes", "/surfaces"}) {
    for (const auto& entry : std::filesystem::directory_iterator(data + dir)) {
      const std::string ext = entry.path().extension().string();
      if (ext == ".mesh" || ext == ".obj" || ext == ".off") files.push_back(entry.path().string());
    }
  }
  std::sort(files.begin(), files.end());
  REQUIRE(files.size() >= 16);
  for (const std::string& path : files) {
    INFO(path);
    const auto xyz = path.compare(path.size() - 5, 5, ".mesh") == 0 ? read_medit_vertices(path)
                                                                    : read_surface_vertices(path);
    REQUIRE(xyz.size() >= 3 * 642);
    const Delaunay3 dt(xyz.data(), static_cast<std::uint32_t>(xyz.size() / 3));
    require_valid(dt);
  }
}

namespace {

// The nearest input vertex by brute force with exact comparisons; the smallest index on ties.
std::uint32_t brute_nearest(const std::vector<double>& xyz, const Delaunay3& dt, const double* p) {
  std::uint32_t best = Delaunay3::kInfinite;
  for (std::uint32_t i = 0; i < xyz.size() / 3; ++i) {
    if (dt.duplicate_of(i) != i) continue;
    if (best == Delaunay3::kInfinite ||
        voroclip::compare_distance3d(p, &xyz[3 * i], &xyz[3 * best]) == Sign::negative) {
      best = i;
    }
  }
  return best;
}

// locate's contract: a finite tet whose closed interior holds p, or an infinite tet whose
// hull facet p is strictly beyond.
bool located_correctly(const Delaunay3& dt, const std::vector<double>& xyz, std::uint32_t t,
                       const double* p) {
  const auto at = [&](std::uint32_t v) { return &xyz[3 * static_cast<std::size_t>(v)]; };
  if (dt.is_infinite(t)) {
    int s = 0;
    while (dt.tet_vertex(t, s) != Delaunay3::kInfinite) ++s;
    const int* f = Delaunay3::kFacetVertex[s];
    return voroclip::orient3d(at(dt.tet_vertex(t, f[0])), at(dt.tet_vertex(t, f[1])),
                              at(dt.tet_vertex(t, f[2])), p) == Sign::negative;
  }
  for (int g = 0; g < 4; ++g) {
    const int* f = Delaunay3::kFacetVertex[g];
    if (voroclip::orient3d(at(dt.tet_vertex(t, f[0])), at(dt.tet_vertex(t, f[1])),
                           at(dt.tet_vertex(t, f[2])), p) == Sign::positive) {
      return false;
    }
  }
  return true;
}

}  // namespace

TEST_CASE("Delaunay3 locate and nearest_vertex agree with brute force", "[delaunay][exact]") {
  const auto xyz = random_points(2000, 31);
  const Delaunay3 dt(xyz.data(), 2000);
  std::mt19937_64 rng(32);
  std::uniform_real_distribution<double> u(-0.5, 1.5);  // inside and outside the hull
  for (int i = 0; i < 2000; ++i) {
    const double p[3] = {u(rng), u(rng), u(rng)};
    const std::uint32_t t = dt.locate(p);
    CHECK(located_correctly(dt, xyz, t, p));
    CHECK(dt.nearest_vertex(p, t) == brute_nearest(xyz, dt, p));
  }
  for (std::uint32_t v = 0; v < 2000; v += 37) CHECK(dt.nearest_vertex(&xyz[3 * v]) == v);
  const double nan[3] = {0, std::nan(""), 0};
  CHECK_THROWS_AS(dt.locate(nan), voroclip::Error);
}

TEST_CASE("Delaunay3 nearest_vertex breaks ties by the smallest index", "[delaunay][degenerate]") {
  std::vector<double> xyz;
  for (int x = 0; x < 5; ++x)
    for (int y = 0; y < 5; ++y)
      for (int z = 0; z < 5; ++z) xyz.insert(xyz.end(), {double(x), double(y), double(z)});
  const Delaunay3 dt(xyz.data(), 125);
  // Cell centres are equidistant from 8 grid points, edge midpoints from 2, and so on.
  for (double x = 0.5; x < 4; x += 1.0)
    for (double y = 0; y < 4.5; y += 0.5)
      for (double z = 0; z < 4.5; z += 0.5) {
        const double p[3] = {x, y, z};
        CHECK(dt.nearest_vertex(p) == brute_nearest(xyz, dt, p));
      }
}

namespace {

// Everything a build exposes, in one array: every slot's vertices and neighbour codes, then
// vertex_tet and duplicate_of of every point.
std::vector<std::uint32_t> all_arrays(const Delaunay3& dt) {
  std::vector<std::uint32_t> out;
  out.push_back(dt.nb_tet_slots());
  out.push_back(dt.nb_finite_tets());
  for (std::uint32_t t = 0; t < dt.nb_tet_slots(); ++t) {
    for (int k = 0; k < 4; ++k) {
      out.push_back(dt.tet_vertex(t, k));
      out.push_back(dt.neighbor_code(t, k));
    }
  }
  for (std::uint32_t v = 0; v < dt.nb_points(); ++v) {
    out.push_back(dt.vertex_tet(v));
    out.push_back(dt.duplicate_of(v));
  }
  return out;
}

// (a^3, 2 b^3, 3 c^3) for a, b, c uniform in [0, 1): across any axis, the halves of the
// bounding box hold about 79 % and 21 % of the points.
std::vector<double> skewed_points(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> xyz;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = u(rng), b = u(rng), c = u(rng);
    xyz.insert(xyz.end(), {a * a * a, 2 * b * b * b, 3 * c * c * c});
  }
  return xyz;
}

// Inputs for the parallel construction: uniform, a grid (cospherical everywhere, symbolic
// perturbation decides), points on a sphere (all on the hull), duplicates.
std::vector<std::pair<std::string, std::vector<double>>> parallel_inputs() {
  std::vector<std::pair<std::string, std::vector<double>>> inputs;
  inputs.emplace_back("uniform", random_points(20000, 61));
  std::vector<double> grid;
  for (int x = 0; x < 20; ++x)
    for (int y = 0; y < 20; ++y)
      for (int z = 0; z < 20; ++z) grid.insert(grid.end(), {double(x), double(y), double(z)});
  inputs.emplace_back("grid 20^3", grid);
  std::mt19937_64 rng(62);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> sphere;
  for (int i = 0; i < 10000; ++i) {
    const double v[3] = {g(rng), g(rng), g(rng)};
    const double r = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    sphere.insert(sphere.end(), {v[0] / r, v[1] / r, v[2] / r});
  }
  inputs.emplace_back("sphere", sphere);
  auto duplicated = random_points(15000, 63);
  for (std::size_t i = 0; i < 15000; i += 7) {
    const std::size_t j = (i * 7919) % 15000;  // j takes the coordinates of i
    std::copy_n(&duplicated[3 * i], 3, &duplicated[3 * j]);
  }
  inputs.emplace_back("duplicates", duplicated);
  inputs.emplace_back("skewed", skewed_points(20000, 64));
  return inputs;
}

// vertex_tet's contract by brute force: for every point, the smallest-numbered finite tet
// incident to it, or kNoTet for a duplicate (not a vertex).
void check_vertex_tets(const Delaunay3& dt) {
  std::vector<std::uint32_t> smallest(dt.nb_points(), Delaunay3::kNoTet);
  for (std::uint32_t t = dt.nb_tet_slots(); t-- > 0;) {
    if (dt.is_infinite(t)) continue;
    for (int k = 0; k < 4; ++k) smallest[dt.tet_vertex(t, k)] = t;
  }
  std::size_t wrong = 0;
  for (std::uint32_t v = 0; v < dt.nb_points(); ++v) {
    const bool vertex = dt.duplicate_of(v) == v;
    wrong += dt.vertex_tet(v) != smallest[v] || (smallest[v] == Delaunay3::kNoTet) == vertex;
  }
  CHECK(wrong == 0);
}

}  // namespace

TEST_CASE("Delaunay3 is bitwise identical with 1, 2 and 4 threads", "[delaunay][threads]") {
  // Small zones, so that these sizes go through the parallel passes (with default options
  // only rounds of 57344 points or more do, or in a build with no such round but one of
  // 14336, those of 3584 or more, or in a build whose largest round has 3584 to 14335
  // points, those of 896 or more: the next test).
  Delaunay3::Options zoned;
  zoned.points_per_zone = 512;
  Delaunay3::Options sequential;
  sequential.points_per_zone = 0xffffffffu;
  for (const auto& [name, xyz] : parallel_inputs()) {
    INFO(name);
    const Delaunay3 one = voroclip::test::build_with_threads<Delaunay3>(xyz, 1, zoned);
    require_valid(one);
    check_vertex_tets(one);
    CHECK(one.stats().zoned_passes >= 4);
    CHECK(one.stats().zoned_points > one.stats().sequential_points);
    CHECK(one.stats().deferred_points > 0);
    // The perturbed Delaunay triangulation is unique: the zones change the slots, not the set.
    const Delaunay3 reference = voroclip::test::build_with_threads<Delaunay3>(xyz, 1, sequential);
    require_valid(reference);
    CHECK(reference.stats().zoned_passes == 0);
    CHECK(finite_tets(one) == finite_tets(reference));
    const auto arrays = all_arrays(one);
    for (const std::size_t threads : {2u, 4u}) {
      INFO(threads << " threads");
      const Delaunay3 dt = voroclip::test::build_with_threads<Delaunay3>(xyz, threads, zoned);
      check_vertex_tets(dt);
      CHECK(all_arrays(dt) == arrays);
    }
  }
}

TEST_CASE("Delaunay3 zones a build of 10^4 points with the default options",
          "[delaunay][threads]") {
  // mesh3d's CVT builds one triangulation of about 10^4 sites per evaluation; their largest
  // BRIO round (about 5k points) and the rounds down to 896 points take two zones. 5,000
  // points (largest round about 2.5k) stay sequential.
  Delaunay3::Options sequential;
  sequential.points_per_zone = 0xffffffffu;
  const auto xyz = random_points(10000, 65);
  const Delaunay3 one = voroclip::test::build_with_threads<Delaunay3>(xyz, 1, {});
  require_valid(one);
  CHECK(one.stats().zoned_passes >= 2);
  CHECK(one.stats().zoned_points > one.stats().sequential_points);
  const Delaunay3 reference = voroclip::test::build_with_threads<Delaunay3>(xyz, 1, sequential);
  CHECK(finite_tets(one) == finite_tets(reference));
  for (const std::size_t threads : {2u, 4u}) {
    INFO(threads << " threads");
    const Delaunay3 dt = voroclip::test::build_with_threads<Delaunay3>(xyz, threads, {});
    CHECK(all_arrays(dt) == all_arrays(one));
  }
  const Delaunay3 half =
      voroclip::test::build_with_threads<Delaunay3>(random_points(5000, 66), 2, {});
  CHECK(half.stats().zoned_passes == 0);
}

TEST_CASE("Delaunay3 first-pass zones along the round's Hilbert curve when they are balanced",
          "[delaunay][threads][large]") {
  // 200k uniform points, zones of 8192: the rounds of about 100k, 50k and 25k points take
  // 8, 4 and 2 first-pass zones of about 12.5k points (and those of 12.5k and 6.2k two),
  // and their box's octants, quarters and halves hold equal counts to within 2 % (binomial
  // deviations of about 1 %): the passes take them as zones. Skewed points: never (the kd split by
  // count instead). Either way the arrays are the same for 1 and 2 threads and the tets those of
  // the sequential build.
  Delaunay3::Options zoned;
  zoned.points_per_zone = 8192;
  Delaunay3::Options sequential;
  sequential.points_per_zone = 0xffffffffu;
  for (const bool uniform : {true, false}) {
    INFO((uniform ? "uniform" : "skewed"));
    const auto xyz = uniform ? random_points(200000, 65) : skewed_points(200000, 66);
    const Delaunay3 one = voroclip::test::build_with_threads<Delaunay3>(xyz, 1, zoned);
    require_valid(one);
    const Delaunay3::Stats& stats = one.stats();
    INFO("zoned passes " << stats.zoned_passes << ", along the curve " << stats.curve_zoned_passes);
    CHECK(stats.zoned_passes >= 5);
    if (uniform) {
      CHECK(stats.curve_zoned_passes == 5);  // every first pass: rounds of 100k ... 6.2k points
    } else {
      CHECK(stats.curve_zoned_passes == 0);
    }
    const Delaunay3 reference = voroclip::test::build_with_threads<Delaunay3>(xyz, 1, sequential);
    CHECK(finite_tets(one) == finite_tets(reference));
    const Delaunay3 two = voroclip::test::build_with_threads<Delaunay3>(xyz, 2, zoned);
    CHECK(all_arrays(two) == all_arrays(one));
  }
}

// The points in the order hilbert_sort gives them.
std::vector<double> hilbert_sorted(const std::vector<double>& xyz) {
  const auto n = static_cast<std::uint32_t>(xyz.size() / 3);
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  voroclip::hilbert_sort(xyz.data(), 3, order.data(), order.data() + n);
  std::vector<double> sorted;
  for (const std::uint32_t i : order) sorted.insert(sorted.end(), &xyz[3 * i], &xyz[3 * i] + 3);
  return sorted;
}

TEST_CASE("Delaunay3 on presorted points: the same tets, the same arrays on 1 and 2 threads",
          "[delaunay][threads][large]") {
  Delaunay3::Options zoned;
  zoned.points_per_zone = 512;
  Delaunay3::Options presorted = zoned;
  presorted.presorted = true;
  Delaunay3::Options sequential;
  sequential.points_per_zone = 0xffffffffu;
  for (const auto& [name, input] : parallel_inputs()) {
    INFO(name);
    const std::vector<double> xyz = hilbert_sorted(input);
    const Delaunay3 one = voroclip::test::build_with_threads<Delaunay3>(xyz, 1, presorted);
    require_valid(one);
    check_vertex_tets(one);
    CHECK(one.stats().zoned_passes >= 4);
    const Delaunay3 reference = voroclip::test::build_with_threads<Delaunay3>(xyz, 1, sequential);
    CHECK(finite_tets(one) == finite_tets(reference));
    const Delaunay3 two = voroclip::test::build_with_threads<Delaunay3>(xyz, 2, presorted);
    CHECK(all_arrays(two) == all_arrays(one));
    // Not in a spatial order: slower, still the same tets.
    const Delaunay3 unsorted = voroclip::test::build_with_threads<Delaunay3>(input, 2, presorted);
    require_valid(unsorted);
    CHECK(finite_tets(unsorted) ==
          finite_tets(voroclip::test::build_with_threads<Delaunay3>(input, 1, sequential)));
  }
  // Uniform points: every first pass takes the zones along the curve, from the box of all
  // the points (as without presorted, from each round's box: see the test above).
  Delaunay3::Options large = presorted;
  large.points_per_zone = 8192;
  const Delaunay3 uniform = voroclip::test::build_with_threads<Delaunay3>(
      hilbert_sorted(random_points(200000, 65)), 2, large);
  CHECK(uniform.stats().curve_zoned_passes == 5);
}

TEST_CASE("Delaunay3 with and without the AVX2 determinant builds the same arrays",
          "[delaunay][threads][large][exact]") {
  bool cpu_avx2 = false;
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  __builtin_cpu_init();
  cpu_avx2 = __builtin_cpu_supports("avx2");
#endif
  if (!cpu_avx2) WARN("no AVX2 on this CPU: only the SSE2 insphere determinant runs");
  using Simd = Delaunay3::Options::InsphereSimd;
  Delaunay3::Options baseline;
  baseline.points_per_zone = 512;
  baseline.insphere_simd = Simd::sse2;
  Delaunay3::Options avx2 = baseline;
  avx2.insphere_simd = Simd::avx2;
  for (const auto& [name, xyz] : parallel_inputs()) {
    INFO(name);
    const Delaunay3 reference = voroclip::test::build_with_threads<Delaunay3>(xyz, 1, baseline);
    require_valid(reference);
    CHECK_FALSE(reference.stats().avx2);
    CHECK(reference.stats().zoned_passes >= 4);
    const auto arrays = all_arrays(reference);
    for (const std::size_t threads : {std::size_t{1}, voroclip_test::test_threads()}) {
      INFO(threads << " threads");
      const Delaunay3 dt = voroclip::test::build_with_threads<Delaunay3>(xyz, threads, avx2);
      CHECK(dt.stats().avx2 == cpu_avx2);
      CHECK(all_arrays(dt) == arrays);
    }
  }
  // Default zones on 150k points: BRIO rounds of 57344 points and more go through zones.
  const auto xyz = random_points(150000, 64);
  Delaunay3::Options plain;
  plain.insphere_simd = Simd::sse2;
  const Delaunay3 reference = voroclip::test::build_with_threads<Delaunay3>(xyz, 2, plain);
  CHECK(reference.stats().zoned_passes > 0);
  Delaunay3::Options wide;
  wide.insphere_simd = Simd::avx2;
  const Delaunay3 forced = voroclip::test::build_with_threads<Delaunay3>(xyz, 2, wide);
  CHECK(forced.stats().avx2 == cpu_avx2);
  CHECK(all_arrays(forced) == all_arrays(reference));
  // The default (automatic) takes AVX2 where the CPU has it, except on AMD Zen 1.
  bool zen1 = false;
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  zen1 = __builtin_cpu_is("znver1");
#endif
  CHECK(Delaunay3::automatic_uses_avx2() == (cpu_avx2 && !zen1));
  const Delaunay3 dt = voroclip::test::build_with_threads<Delaunay3>(xyz, 2, {});
  CHECK(dt.stats().avx2 == Delaunay3::automatic_uses_avx2());
  CHECK(all_arrays(dt) == all_arrays(reference));
}

TEST_CASE("Delaunay3 slot limit of the sequential rounds: deferred points, same arrays",
          "[delaunay][threads][degenerate]") {
  // Points near the moment curve (t, t^2, t^3): Theta(n^2) tets, far more than the 8 slots
  // per point the sequential rounds before the first zoned one may use while the other
  // threads fault in the rest of the tet array; the points that need more are inserted after.
  const std::uint64_t seed = 71;
  INFO("seed " << seed);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> xyz;
  for (int i = 0; i < 300; ++i) {
    const double t = u(rng);
    xyz.insert(xyz.end(), {t, t * t, t * t * t});
  }
  Delaunay3::Options zoned;
  // The last BRIO round (about 150 points) reaches 7/16 * 256 = 112 points: it is zoned, and
  // the rounds before it are the sequential prefix, under the slot limit.
  zoned.points_per_zone = 256;
  Delaunay3::Options sequential;
  sequential.points_per_zone = 0xffffffffu;
  const Delaunay3 one = voroclip::test::build_with_threads<Delaunay3>(xyz, 1, zoned);
  require_valid(one);
  CHECK(one.stats().zoned_passes > 0);
  CHECK(one.stats().limited_points > 0);
  CHECK(one.nb_finite_tets() > 16 * 300);
  const Delaunay3 reference = voroclip::test::build_with_threads<Delaunay3>(xyz, 1, sequential);
  require_valid(reference);
  CHECK(reference.stats().limited_points == 0);
  CHECK(finite_tets(one) == finite_tets(reference));
  const auto arrays = all_arrays(one);
  for (const std::size_t threads : {2u, 4u}) {
    INFO(threads << " threads");
    const Delaunay3 dt = voroclip::test::build_with_threads<Delaunay3>(xyz, threads, zoned);
    CHECK(dt.stats().limited_points == one.stats().limited_points);
    CHECK(all_arrays(dt) == arrays);
  }
}

TEST_CASE("Delaunay3 default zones in a build with no round of 57344 points",
          "[delaunay][threads]") {
  // 30k points: the last BRIO round (about 15k) is at least 7/64 * 131072 = 14336 points,
  // so the rounds of 7/256 * 131072 = 3584 points or more (about 15k, 7.5k and 3.7k) go
  // through two zones each; the smaller ones (about 3.7k points in all) are sequential.
  const auto xyz = random_points(30000, 43);
  const Delaunay3 one = voroclip::test::build_with_threads<Delaunay3>(xyz, 1, {});
  require_valid(one);
  CHECK(one.stats().zoned_passes >= 3);
  CHECK(one.stats().zoned_points > 24000);
  CHECK(one.stats().zoned_points < 28000);
  CHECK(one.stats().deferred_points > 0);
  const Delaunay3 two = voroclip::test::build_with_threads<Delaunay3>(xyz, 2, {});
  CHECK(all_arrays(two) == all_arrays(one));
}

TEST_CASE("Delaunay3 default zones: 1 and 2 threads agree on 300k points",
          "[delaunay][threads][large][.slow]") {
  const auto xyz = random_points(300000, 41);
  const Delaunay3 one = voroclip::test::build_with_threads<Delaunay3>(xyz, 1, {});
  const Delaunay3 two = voroclip::test::build_with_threads<Delaunay3>(xyz, 2, {});
  CHECK(one.stats().zoned_passes > 0);
  require_valid(two);
  CHECK(all_arrays(one) == all_arrays(two));
}

TEST_CASE("Delaunay3 zone boxes: the one-axis test answers as the box test", "[delaunay]") {
  // Every pattern of bounds per axis (none, lower, upper, both) in both frames, with
  // points on the bounds, next to them and at random: inside() must equal contains(), and
  // the one-axis path is taken exactly for frame-0 boxes bounded on at most one axis (the
  // two zones of a first pass).
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::mt19937_64 rng(47);
  std::uniform_real_distribution<double> u(-2, 2);
  std::size_t slabs = 0;
  for (int frame = 0; frame < 2; ++frame) {
    for (int pattern = 0; pattern < 64; ++pattern) {
      voroclip::detail::ZoneBox box;
      box.frame = frame;
      int bounded = 0;
      for (int a = 0; a < 3; ++a) {
        const int kind = pattern >> (2 * a) & 3;
        const double m = u(rng), w = std::fabs(u(rng)) + 0.25;
        box.lo[a] = (kind & 1) != 0 ? m - w : -kInf;
        box.hi[a] = (kind & 2) != 0 ? m + w : kInf;
        bounded += kind != 0 ? 1 : 0;
      }
      box.prepare_inside();
      const bool slab = frame == 0 && bounded <= 1;
      CHECK((box.slab_axis >= 0) == slab);
      slabs += box.slab_axis >= 0 ? 1 : 0;
      std::vector<std::array<double, 3>> pts;
      for (int k = 0; k < 200; ++k) pts.push_back({u(rng), u(rng), u(rng)});
      for (int a = 0; a < 3; ++a) {
        for (const double b : {box.lo[a], box.hi[a]}) {
          if (std::isinf(b)) continue;
          for (const double x : {b, std::nextafter(b, -kInf), std::nextafter(b, kInf)}) {
            std::array<double, 3> p = {u(rng), u(rng), u(rng)};
            p[static_cast<std::size_t>(a)] = x;
            pts.push_back(p);
          }
        }
      }
      for (const auto& p : pts) CHECK(box.inside(p.data()) == box.contains(p.data()));
    }
  }
  // Frame 0: the pattern with no bound and 3 axes x 3 one-axis patterns.
  CHECK(slabs == 10);
}

TEST_CASE("Delaunay3 prefetch_tet leaves every record unchanged", "[delaunay]") {
  const auto xyz = random_points(2000, 52);
  const Delaunay3 dt(xyz.data(), 2000);
  const auto records = [&dt] {
    std::vector<std::uint32_t> r;
    for (std::uint32_t t = 0; t < dt.nb_tet_slots(); ++t) {
      for (int k = 0; k < 4; ++k) r.insert(r.end(), {dt.tet_vertex(t, k), dt.neighbor_code(t, k)});
    }
    return r;
  };
  const std::vector<std::uint32_t> before = records();
  for (std::uint32_t t = dt.nb_tet_slots(); t-- > 0;) dt.prefetch_tet(t);
  CHECK(records() == before);
  require_valid(dt);
}

TEST_CASE("Delaunay3 vertex stars and circumcenters", "[delaunay]") {
  const auto xyz = random_points(3000, 51);
  const Delaunay3 dt(xyz.data(), 3000);
  // Brute force: the finite tets containing each vertex.
  std::vector<std::vector<std::uint32_t>> expected(3000);
  for (std::uint32_t t = 0; t < dt.nb_tet_slots(); ++t) {
    if (dt.is_free(t) || dt.is_infinite(t)) continue;
    for (int k = 0; k < 4; ++k) expected[dt.tet_vertex(t, k)].push_back(t);
  }
  std::vector<std::uint32_t> star;
  for (std::uint32_t v = 0; v < 3000; v += 7) {
    dt.vertex_tets(v, star);
    CHECK(star == expected[v]);
  }
  // The circumcenter is equidistant from the four vertices (floating point: to 1e-9).
  for (std::uint32_t t = 0; t < dt.nb_tet_slots(); t += 11) {
    if (dt.is_free(t) || dt.is_infinite(t)) continue;
    double c[3];
    dt.circumcenter(t, c);
    double r[4];
    for (int k = 0; k < 4; ++k) {
      const double* p = &xyz[3 * static_cast<std::size_t>(dt.tet_vertex(t, k))];
      r[k] = std::sqrt((p[0] - c[0]) * (p[0] - c[0]) + (p[1] - c[1]) * (p[1] - c[1]) +
                       (p[2] - c[2]) * (p[2] - c[2]));
    }
    for (int k = 1; k < 4; ++k) CHECK(std::fabs(r[k] - r[0]) <= 1e-9 * (1 + r[0]));
  }
}
