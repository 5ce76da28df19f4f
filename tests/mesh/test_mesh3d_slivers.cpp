// Tests of the sliver perturbation (voroclip/mesh.h, perturb_slivers3): it raises the
// smallest dihedral angle of the extracted mesh (measured with tet_shape), keeps fixed
// sites, keeps constrained sites on their constraint, reports figures that match the mesh,
// and does not depend on the thread count.
#include <catch2/catch.hpp>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "mesh3d_pipeline.h"
#include "support/threads.h"
#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/cvt.h"
#include "voroclip/mesh.h"

using voroclip::Delaunay3;
using voroclip::Domain3;
using voroclip::TetExtractor3;
using Kind = voroclip::SiteConstraint3::Kind;

namespace {

const std::string kData = VOROCLIP_SHARED_DATA_DIR;

// Radial projection onto the unit sphere (sphere.mesh's boundary is a polyhedron inscribed
// in it; the sites only need a surface to stay on).
void on_unit_sphere(std::uint32_t, Kind, const double* p, double* q, double* d) {
  const double l = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
  for (int c = 0; c < 3; ++c) {
    q[c] = p[c] / l;
    d[c] = p[c] / l;
  }
}

struct Setup {
  Domain3 domain;
  std::vector<double> sites;
  std::vector<Kind> kinds;
};

// A short CVT in the sphere: sites whose boundary cells were pushed to the unit sphere,
// every 7th inner site fixed. Slivers remain (few iterations).
Setup make_setup() {
  Setup s{Domain3(voroclip::read_tet_mesh(kData + "/tetmeshes/sphere.mesh")), {}, {}};
  const std::uint32_t n = 600;
  s.sites = voroclip::random_points3(s.domain, n, 11);
  voroclip::Cvt3Options o;
  o.max_iterations = 8;
  voroclip::optimize_cvt3(s.domain, s.sites, o);
  const Delaunay3 dt(s.sites.data(), n);
  voroclip::ClippedVoronoi3 cv;
  cv.compute(s.domain, dt);
  s.kinds.assign(n, Kind::kFree);
  for (std::uint32_t i = 0; i < n; ++i) {
    if (cv.is_boundary(i)) {
      s.kinds[i] = Kind::kSurface;
      double q[3], d[3];
      on_unit_sphere(i, Kind::kSurface, &s.sites[3 * i], q, d);
      std::copy_n(q, 3, &s.sites[3 * i]);
    } else if (i % 7 == 0) {
      s.kinds[i] = Kind::kFixed;
    }
  }
  return s;
}

double mesh_min_dihedral(const TetExtractor3& ex, const std::vector<double>& sites,
                         std::uint32_t* below = nullptr, double target = 0) {
  const Delaunay3 dt(sites.data(), static_cast<std::uint32_t>(sites.size() / 3));
  const std::vector<std::uint32_t> tets = ex.extract(dt);
  double worst = 180;
  if (below) *below = 0;
  for (std::size_t t = 0; t < tets.size(); t += 4) {
    const double q = voroclip::tet_shape(&sites[3 * tets[t]], &sites[3 * tets[t + 1]],
                                         &sites[3 * tets[t + 2]], &sites[3 * tets[t + 3]])
                         .q1_deg;
    worst = std::min(worst, q);
    if (below && q < target) ++*below;
  }
  return worst;
}

}  // namespace

TEST_CASE("perturb_slivers3 raises the smallest dihedral angle and keeps the constraints",
          "[mesh]") {
  Setup s = make_setup();
  const TetExtractor3 ex(s.domain);
  const std::vector<double> before = s.sites;
  std::uint32_t slivers_before = 0;
  const double worst_before = mesh_min_dihedral(ex, s.sites, &slivers_before, 25);
  INFO("before: min " << worst_before << " deg, " << slivers_before << " tets below 25 deg");
  REQUIRE(slivers_before > 0);
  voroclip::Perturb3Options o;
  o.target_dihedral_deg = 25;
  const voroclip::Perturb3Stats st =
      voroclip::perturb_slivers3(ex, s.sites, s.kinds, on_unit_sphere, o);
  std::uint32_t slivers_after = 0;
  const double worst_after = mesh_min_dihedral(ex, s.sites, &slivers_after, 25);
  INFO("after: min " << worst_after << " deg, " << slivers_after << " below 25 deg; " << st.rounds
                     << " rounds, " << st.moves << " moves");
  // The statistics describe the meshes before and after.
  // (The perturbation measures Q1 its own way; tet_shape's agrees to rounding.)
  CHECK(st.initial_min_dihedral_deg == Approx(worst_before).epsilon(1e-9));
  CHECK(st.initial_slivers == slivers_before);
  CHECK(st.final_min_dihedral_deg == Approx(worst_after).epsilon(1e-9));
  CHECK(st.final_slivers == slivers_after);
  // Better, much better.
  CHECK(worst_after > worst_before + 10);
  CHECK(slivers_after * 4 < slivers_before);
  CHECK(st.moves > 0);
  for (std::uint32_t i = 0; i < s.kinds.size(); ++i) {
    const double* p = &s.sites[3 * i];
    if (s.kinds[i] == Kind::kFixed) {
      CHECK(p[0] == before[3 * i]);
      CHECK(p[1] == before[3 * i + 1]);
      CHECK(p[2] == before[3 * i + 2]);
    } else if (s.kinds[i] == Kind::kSurface) {
      CHECK(std::fabs(std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) - 1) < 1e-15);
    }
  }
}

TEST_CASE("perturb_slivers3: keep_round undoes a refused round", "[mesh]") {
  const Setup s = make_setup();
  const TetExtractor3 ex(s.domain);
  voroclip::Perturb3Options o;
  o.target_dihedral_deg = 25;
  // Every round refused: the first is undone, the rounds go on with the free sites only,
  // the second refusal undoes that one too and stops: the sites are where they started.
  std::vector<double> sites = s.sites;
  std::uint32_t calls = 0;
  o.keep_round = [&calls](const std::vector<double>&, const std::vector<std::uint32_t>&) {
    ++calls;
    return false;
  };
  std::vector<std::uint32_t> mesh;
  const voroclip::Perturb3Stats none =
      voroclip::perturb_slivers3(ex, sites, s.kinds, on_unit_sphere, o, &mesh);
  CHECK(none.undone);
  CHECK(calls == 2);
  CHECK(sites == s.sites);
  const Delaunay3 dt(s.sites.data(), static_cast<std::uint32_t>(s.sites.size() / 3));
  CHECK(mesh == ex.extract(dt));
  // The first round refused, the others kept: the surface sites stay where they were, the
  // free ones move, and the mesh still improves.
  sites = s.sites;
  calls = 0;
  o.keep_round = [&calls](const std::vector<double>&, const std::vector<std::uint32_t>&) {
    return ++calls > 1;
  };
  const voroclip::Perturb3Stats once =
      voroclip::perturb_slivers3(ex, sites, s.kinds, on_unit_sphere, o);
  CHECK(once.undone);
  std::uint32_t free_moved = 0;
  for (std::uint32_t i = 0; i < s.kinds.size(); ++i) {
    const bool same = std::equal(&sites[3 * i], &sites[3 * i] + 3, &s.sites[3 * i]);
    if (s.kinds[i] != Kind::kFree) {
      CHECK(same);
    } else {
      free_moved += same ? 0 : 1;
    }
  }
  CHECK(free_moved > 0);
  CHECK(once.final_min_dihedral_deg > once.initial_min_dihedral_deg);
  // Every round kept: the same as without the check.
  sites = s.sites;
  std::vector<double> plain = s.sites;
  o.keep_round = [](const std::vector<double>&, const std::vector<std::uint32_t>&) { return true; };
  voroclip::perturb_slivers3(ex, sites, s.kinds, on_unit_sphere, o);
  o.keep_round = nullptr;
  voroclip::perturb_slivers3(ex, plain, s.kinds, on_unit_sphere, o);
  CHECK(sites == plain);
}

TEST_CASE("peel_flat_boundary_tets removes a flat tet on the boundary", "[mesh]") {
  // The unit cube as six tets, and a seventh on its top triangle (4, 5, 7) with its apex
  // 0.01 above that triangle's centroid: three faces on the boundary, dihedral angles of
  // about 1.7 degrees at its base.
  std::vector<double> sites;
  for (std::uint32_t k = 0; k < 8; ++k) {
    sites.insert(sites.end(), {double(k & 1), double((k >> 1) & 1), double((k >> 2) & 1)});
  }
  sites.insert(sites.end(), {2.0 / 3, 1.0 / 3, 1.01});
  const std::vector<std::uint32_t> cube = {0, 1, 3, 7, 0, 3, 2, 7, 0, 5, 1, 7,
                                           0, 2, 6, 7, 0, 4, 5, 7, 0, 6, 4, 7};
  std::vector<std::uint32_t> tets = cube;
  tets.insert(tets.end(), {4, 5, 7, 8});
  const double q1 = voroclip::tet_shape(&sites[12], &sites[15], &sites[21], &sites[24]).q1_deg;
  REQUIRE(q1 < 5);
  std::vector<Kind> kinds(9, Kind::kSurface);
  std::vector<std::uint32_t> t = tets;
  CHECK(voroclip::mesh3::peel_flat_boundary_tets(sites, kinds, t, 20, 4, nullptr) == 1);
  CHECK(t == cube);
  // Below the threshold only (q1 less a rounding margin: the peel measures it its own way).
  t = tets;
  CHECK(voroclip::mesh3::peel_flat_boundary_tets(sites, kinds, t, q1 - 1e-9, 4, nullptr) == 0);
  CHECK(t == tets);
  // Not with a free vertex (an interior site can still move).
  kinds[8] = Kind::kFree;
  CHECK(voroclip::mesh3::peel_flat_boundary_tets(sites, kinds, t, 20, 4, nullptr) == 0);
  CHECK(t == tets);
  kinds[8] = Kind::kSurface;
  // Not when `keep` refuses the result; `keep` sees the mesh without it.
  std::vector<std::uint32_t> seen;
  const auto refuse = [&seen](const std::vector<std::uint32_t>& m) {
    seen = m;
    return false;
  };
  CHECK(voroclip::mesh3::peel_flat_boundary_tets(sites, kinds, t, 20, 4, refuse) == 0);
  CHECK(t == tets);
  CHECK(seen == cube);
}

TEST_CASE("perturb_slivers3: the same sites with 1 and 2 threads", "[mesh][threads]") {
  const Setup s = make_setup();
  const TetExtractor3 ex(s.domain);
  std::vector<double> one = s.sites, two = s.sites;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    voroclip::perturb_slivers3(ex, one, s.kinds, on_unit_sphere);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism,
                          voroclip_test::test_threads());
    voroclip::perturb_slivers3(ex, two, s.kinds, on_unit_sphere);
  }
  CHECK(one == two);
}

TEST_CASE("perturb_slivers3: errors", "[mesh]") {
  const Domain3 d(voroclip::read_tet_mesh(kData + "/tetmeshes/sphere.mesh"));
  const TetExtractor3 ex(d);
  std::vector<double> sites = voroclip::random_points3(d, 50, 3);
  std::vector<Kind> kinds(49, Kind::kFree);
  CHECK_THROWS_AS(voroclip::perturb_slivers3(ex, sites, kinds, nullptr), voroclip::Error);
  kinds.assign(50, Kind::kSurface);
  CHECK_THROWS_AS(voroclip::perturb_slivers3(ex, sites, kinds, nullptr), voroclip::Error);
  sites.pop_back();
  CHECK_THROWS_AS(voroclip::perturb_slivers3(ex, sites, {}, nullptr), voroclip::Error);
}
