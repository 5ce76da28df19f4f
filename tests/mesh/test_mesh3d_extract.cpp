// Tests of the 3D mesh extraction (voroclip/mesh.h, TetExtractor3): the circumcenter of
// every Delaunay tet located exactly (against a brute-force search over every domain tet
// with the exact predicate, and against hand-placed circumcenters on facets, edges,
// vertices and the boundary), the orientation of the output, the manifold repair (the
// result is accepted by Domain3's exact validation) and 1 vs 2 threads.
#include <catch2/catch.hpp>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "mesh_test_shapes.h"
#include "support/threads.h"
#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/mesh.h"

using voroclip::Delaunay3;
using voroclip::Domain3;
using voroclip::Extract3Options;
using voroclip::Extract3Stats;
using voroclip::Sign;
using voroclip::TetExtractor3;
using voroclip_test::cube_domain;

namespace {

const std::string kData = VOROCLIP_SHARED_DATA_DIR;

// Brute force: where the circumcenter of p lies, over every domain tet (exact predicate).
Sign brute_force_side(const Domain3& d, const std::array<const double*, 4>& p) {
  bool in_closed = false, on_boundary = false, strictly = false;
  for (std::uint32_t t = 0; t < d.nb_tets(); ++t) {
    int zero = 0;
    bool inside = true;
    for (int f = 0; f < 4 && inside; ++f) {
      const int* fv = Domain3::kTetFacetVertex[f];
      const Sign s = voroclip::orient3d_circumcenter(
          d.vertex(d.tet_vertex(t, fv[0])), d.vertex(d.tet_vertex(t, fv[1])),
          d.vertex(d.tet_vertex(t, fv[2])), p[0], p[1], p[2], p[3]);
      if (s == Sign::positive) inside = false;
      if (s == Sign::zero) {
        zero |= 1 << f;
        if (d.tet_adjacent(t, f) == Domain3::kNone) on_boundary = true;
      }
    }
    if (!inside) continue;
    in_closed = true;
    strictly = strictly || zero == 0;
  }
  (void)strictly;
  if (!in_closed) return Sign::negative;
  return on_boundary ? Sign::zero : Sign::positive;
}

// n points: half uniform in the volume, half on boundary triangles (random barycentric
// combinations, rounded: on or within rounding of the surface), which gives flat boundary
// tets with circumcenters anywhere.
std::vector<double> mixed_sites(const Domain3& d, std::uint32_t n, std::uint64_t seed) {
  std::vector<double> xyz = voroclip::random_points3(d, n / 2, seed);
  std::mt19937_64 rng(seed);
  const auto u01 = [&] { return static_cast<double>(rng() >> 11) * 0x1p-53; };
  for (std::uint32_t i = n / 2; i < n; ++i) {
    const std::uint32_t b = static_cast<std::uint32_t>(rng() % d.surface().nb_triangles());
    double w[3] = {u01(), u01(), 0};
    if (w[0] + w[1] > 1) {
      w[0] = 1 - w[0];
      w[1] = 1 - w[1];
    }
    w[2] = 1 - w[0] - w[1];
    for (int c = 0; c < 3; ++c) {
      double x = 0;
      for (int k = 0; k < 3; ++k) x += w[k] * d.vertex(d.surface().triangle_vertex(b, k))[c];
      xyz.push_back(x);
    }
  }
  return xyz;
}

std::vector<std::uint32_t> kept_by_brute_force(const Domain3& d, const Delaunay3& dt) {
  std::vector<std::uint32_t> kept;
  for (std::uint32_t t = 0; t < dt.nb_tet_slots(); ++t) {
    if (dt.is_free(t) || dt.is_infinite(t)) continue;
    const std::array<const double*, 4> p = {
        dt.point(dt.tet_vertex(t, 0)), dt.point(dt.tet_vertex(t, 1)), dt.point(dt.tet_vertex(t, 2)),
        dt.point(dt.tet_vertex(t, 3))};
    if (brute_force_side(d, p) != Sign::negative) {
      kept.insert(kept.end(), {dt.tet_vertex(t, 0), dt.tet_vertex(t, 1), dt.tet_vertex(t, 3),
                               dt.tet_vertex(t, 2)});
    }
  }
  return kept;
}

// The facets of a tet set (4 vertex ids per tet) that belong to one tet only, each with
// its vertex ids sorted.
std::vector<std::array<std::uint32_t, 3>> boundary_facets(const std::vector<std::uint32_t>& tets) {
  std::vector<std::array<std::uint32_t, 3>> faces;
  for (std::size_t t = 0; t < tets.size(); t += 4) {
    for (int f = 0; f < 4; ++f) {
      std::array<std::uint32_t, 3> key;
      int j = 0;
      for (int k = 0; k < 4; ++k) {
        if (k != f) key[static_cast<std::size_t>(j++)] = tets[t + static_cast<std::size_t>(k)];
      }
      std::sort(key.begin(), key.end());
      faces.push_back(key);
    }
  }
  std::sort(faces.begin(), faces.end());
  std::vector<std::array<std::uint32_t, 3>> once;
  for (std::size_t i = 0; i < faces.size(); ++i) {
    const bool twice =
        (i + 1 < faces.size() && faces[i + 1] == faces[i]) || (i > 0 && faces[i - 1] == faces[i]);
    if (!twice) once.push_back(faces[i]);
  }
  return once;
}

}  // namespace

TEST_CASE("circumcenter_side: circumcenters on facets, edges, vertices and the boundary",
          "[mesh][exact][degenerate]") {
  const Domain3 cube = cube_domain();
  const TetExtractor3 ex(cube);
  // Four points at distance r from c (not coplanar): their circumcenter is c exactly.
  const auto side = [&](double cx, double cy, double cz) {
    const double r = 0.75;
    const double p[4][3] = {{cx + r, cy, cz}, {cx - r, cy, cz}, {cx, cy + r, cz}, {cx, cy, cz + r}};
    return ex.circumcenter_side(p[0], p[1], p[2], p[3]);
  };
  CHECK(side(1, 1, 1) == Sign::positive);       // on the diagonal shared by the six tets
  CHECK(side(1, 0.5, 0.25) == Sign::positive);  // inside one tet
  CHECK(side(1, 1, 0.5) == Sign::positive);     // on a facet between two tets
  CHECK(side(1, 1, 0) == Sign::zero);           // on the boundary, inside a face
  CHECK(side(2, 1, 0) == Sign::zero);           // on a boundary edge
  CHECK(side(0, 0, 0) == Sign::zero);           // at a corner
  CHECK(side(1, 0, 1) == Sign::zero);           // on a face diagonal (a boundary edge)
  CHECK(side(2.5, 1, 1) == Sign::negative);
  CHECK(side(1, 1, -0x1p-50) == Sign::negative);  // just below the bottom face
  CHECK(side(1, 1, 0x1p-50) == Sign::positive);
  CHECK(side(100, 0, 0) == Sign::negative);
  // Coplanar points: no circumcenter.
  const double q[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  CHECK_THROWS_AS(ex.circumcenter_side(q[0], q[1], q[2], q[3]), voroclip::Error);
}

TEST_CASE("circumcenter_side: nearly flat tets, no floating-point enclosure",
          "[mesh][exact][degenerate]") {
  const Domain3 cube = cube_domain();
  const TetExtractor3 ex(cube);
  const double lift = 0x1p-60;
  struct Case {
    double p[4][3];
    Sign expected;
  };
  const Case cases[] = {
      // Three corners of the bottom face and a point lifted just above it: the circumcenter
      // is far below the cube (the six bounding-box planes decide).
      {{{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0.5, 0.5, lift}}, Sign::negative},
      // The same at the top face: far above.
      {{{0, 0, 2}, {2, 0, 2}, {0, 2, 2}, {0.5, 0.5, 2 - 0x1p-52}}, Sign::negative},
      // Four points of the circle of radius 3/4 about (1, 1, 1) in z = 1, one lifted by
      // 2^-52: the circumcenter is (1, 1, 1 + 2^-53), inside the cube, so the search goes
      // on past the bounding box to the domain's tets.
      {{{1.75, 1, 1}, {0.25, 1, 1}, {1, 1.75, 1}, {1, 0.25, 1 + 0x1p-52}}, Sign::positive},
      // The same circle in the bottom face z = 0, the point lifted up: the circumcenter is
      // (1, 1, 2^-61), just inside.
      {{{1.75, 1, 0}, {0.25, 1, 0}, {1, 1.75, 0}, {1, 0.25, lift}}, Sign::positive},
      // ... and lifted down: (1, 1, -2^-61), just below the bounding box's plane z = 0.
      {{{1.75, 1, 0}, {0.25, 1, 0}, {1, 1.75, 0}, {1, 0.25, -lift}}, Sign::negative},
  };
  for (const Case& c : cases) {
    const std::array<const double*, 4> p = {c.p[0], c.p[1], c.p[2], c.p[3]};
    double centre[3], halfwidth[3];
    // The tet is too flat for the enclosure: the path under test.
    REQUIRE_FALSE(voroclip::circumcenter3d_enclosure(p[0], p[1], p[2], p[3], centre, halfwidth));
    CHECK(ex.circumcenter_side(p[0], p[1], p[2], p[3]) == c.expected);
    CHECK(brute_force_side(cube, p) == c.expected);
  }
}

TEST_CASE("point_side: exact point location in the domain", "[mesh][exact][degenerate]") {
  const Domain3 cube = cube_domain();
  const TetExtractor3 ex(cube);
  const auto side = [&](double x, double y, double z) {
    const double p[3] = {x, y, z};
    return ex.point_side(p);
  };
  CHECK(side(1, 1, 1) == Sign::positive);  // on the diagonal shared by six tets
  CHECK(side(0.5, 1, 1.5) == Sign::positive);
  CHECK(side(1, 1, 0) == Sign::zero);  // inside a face
  CHECK(side(2, 2, 1) == Sign::zero);  // on an edge
  CHECK(side(2, 2, 2) == Sign::zero);  // a corner
  CHECK(side(1, 1, -0x1p-60) == Sign::negative);
  CHECK(side(1, 1, 0x1p-60) == Sign::positive);
  CHECK(side(3, 1, 1) == Sign::negative);
  const double bad[3] = {std::nan(""), 0, 0};
  CHECK_THROWS_AS(ex.point_side(bad), voroclip::Error);
  // Against the brute force on a real model: random points in the bounding box.
  const Domain3 d(voroclip::read_tet_mesh(kData + "/tetmeshes/fandisk.mesh"));
  const TetExtractor3 fx(d);
  std::mt19937_64 rng(5);
  const auto u01 = [&] { return static_cast<double>(rng() >> 11) * 0x1p-53; };
  std::uint32_t inside = 0;
  for (int i = 0; i < 300; ++i) {
    double p[3];
    for (int c = 0; c < 3; ++c) p[c] = d.bbox_lo()[c] + u01() * (d.bbox_hi()[c] - d.bbox_lo()[c]);
    bool in = false;
    for (std::uint32_t t = 0; t < d.nb_tets() && !in; ++t) {
      bool all = true;
      for (int f = 0; f < 4 && all; ++f) {
        const int* fv = Domain3::kTetFacetVertex[f];
        all = voroclip::orient3d(d.vertex(d.tet_vertex(t, fv[0])), d.vertex(d.tet_vertex(t, fv[1])),
                                 d.vertex(d.tet_vertex(t, fv[2])), p) != Sign::positive;
      }
      in = all;
    }
    inside += in ? 1 : 0;
    CHECK((fx.point_side(p) != Sign::negative) == in);
  }
  CHECK(inside > 30);
}

TEST_CASE("extract: exactly the Delaunay tets whose circumcenter lies in the closed domain",
          "[mesh][exact]") {
  const Domain3 d(voroclip::read_tet_mesh(kData + "/tetmeshes/sphere.mesh"));
  const TetExtractor3 ex(d);
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    INFO("seed " << seed);
    const std::vector<double> sites = mixed_sites(d, 400, seed);
    const Delaunay3 dt(sites.data(), static_cast<std::uint32_t>(sites.size() / 3));
    Extract3Options raw;
    raw.repair_manifold = false;
    Extract3Stats st;
    const std::vector<std::uint32_t> tets = ex.extract(dt, raw, &st);
    CHECK(tets == kept_by_brute_force(d, dt));
    CHECK(st.nb_kept * 4 == tets.size());
    CHECK(st.nb_inside == st.nb_kept);
    CHECK(st.nb_delaunay_tets == dt.nb_finite_tets());
    // Some circumcenters are outside (the flat tets on the surface), most inside.
    CHECK(st.nb_kept < st.nb_delaunay_tets);
    CHECK(st.nb_kept > st.nb_delaunay_tets / 2);
    // Every tet listed right-handed: orient3d(p0, p1, p2, p3) < 0, exactly.
    for (std::size_t t = 0; t < tets.size(); t += 4) {
      CHECK(voroclip::orient3d(&sites[3 * tets[t]], &sites[3 * tets[t + 1]],
                               &sites[3 * tets[t + 2]], &sites[3 * tets[t + 3]]) == Sign::negative);
    }
  }
}

TEST_CASE("extract: the repair leaves a closed 2-manifold boundary", "[mesh][exact]") {
  // fandisk: concave creases, where the raw rule gives non-manifold edges and vertices.
  const Domain3 d(voroclip::read_tet_mesh(kData + "/tetmeshes/fandisk.mesh"));
  const TetExtractor3 ex(d);
  std::uint32_t found = 0;
  for (const std::uint64_t seed : {1u, 2u, 3u, 4u}) {
    INFO("seed " << seed);
    const std::vector<double> sites =
        mixed_sites(d, 300 + 100 * static_cast<std::uint32_t>(seed), seed);
    const Delaunay3 dt(sites.data(), static_cast<std::uint32_t>(sites.size() / 3));
    Extract3Stats st;
    const std::vector<std::uint32_t> tets = ex.extract(dt, {}, &st);
    INFO(st.nb_nonmanifold_edges << " non-manifold edges, " << st.nb_nonmanifold_vertices
                                 << " vertices; " << st.nb_added << " added, " << st.nb_removed
                                 << " removed");
    found += st.nb_nonmanifold_edges + st.nb_nonmanifold_vertices;
    voroclip::TetMeshInput m;
    m.source = "extracted";
    m.xyz = sites;
    m.tets = tets;
    // Domain3 validates exactly: no zero-volume tet, every facet in at most two tets on
    // opposite sides, boundary edges in exactly two triangles, one fan per vertex.
    CHECK_NOTHROW(Domain3(m));
    CHECK(st.nb_kept + st.nb_removed == st.nb_inside + st.nb_added);
  }
  // The inputs exercise the repair.
  CHECK(found > 0);
}

TEST_CASE("extract: dent filling leaves only surface vertices on the boundary", "[mesh]") {
  const Domain3 d(voroclip::read_tet_mesh(kData + "/tetmeshes/sphere.mesh"));
  const TetExtractor3 ex(d);
  // Interior points, and points exactly on boundary triangles (mixed_sites) flagged as on
  // the surface.
  const std::vector<double> sites = mixed_sites(d, 800, 21);
  const auto n = static_cast<std::uint32_t>(sites.size() / 3);
  std::vector<std::uint8_t> on_surface(n, 0);
  for (std::uint32_t i = n / 2; i < n; ++i) on_surface[i] = 1;
  // One patch: a smooth surface.
  voroclip::SurfacePatches patches;
  patches.begin.push_back(0);
  for (std::uint32_t i = 0; i < n; ++i) {
    if (on_surface[i] != 0) patches.patches.push_back(0);
    patches.begin.push_back(static_cast<std::uint32_t>(patches.patches.size()));
  }
  const Delaunay3 dt(sites.data(), n);
  // Boundary facets of a tet set (4 per tet) with a vertex off the surface, and a finite
  // Delaunay tet across.
  const auto dents = [&](const std::vector<std::uint32_t>& tets) {
    std::uint32_t count = 0;
    for (const std::array<std::uint32_t, 3>& face : boundary_facets(tets)) {
      if (on_surface[face[0]] && on_surface[face[1]] && on_surface[face[2]]) continue;
      // Off-surface boundary facet: is there a finite Delaunay tet across (not kept)?
      std::uint32_t finite = 0;
      for (std::uint32_t s = 0; s < dt.nb_tet_slots(); ++s) {
        if (dt.is_free(s) || dt.is_infinite(s)) continue;
        int hit = 0;
        for (int k = 0; k < 4; ++k) {
          const std::uint32_t w = dt.tet_vertex(s, k);
          hit += w == face[0] || w == face[1] || w == face[2] ? 1 : 0;
        }
        finite += hit == 3 ? 1 : 0;
      }
      count += finite == 2 ? 1 : 0;
    }
    return count;
  };
  Extract3Options plain;
  plain.repair_manifold = false;
  const std::vector<std::uint32_t> raw = ex.extract(dt, plain);
  Extract3Options filling = plain;
  filling.surface = &patches;
  Extract3Stats st;
  const std::vector<std::uint32_t> filled = ex.extract(dt, filling, &st);
  const std::uint32_t before = dents(raw), after = dents(filled);
  INFO(before << " dents before, " << after << " after; " << st.nb_filled << " tets added");
  CHECK(before > 0);
  CHECK(after == 0);
  CHECK(st.nb_filled > 0);
  CHECK(filled.size() == raw.size() + 4 * std::size_t{st.nb_filled});
  CHECK(st.nb_creases == 0);
  // Too few entries: an error.
  patches.begin.pop_back();
  CHECK_THROWS_AS(ex.extract(dt, filling), voroclip::Error);
}

TEST_CASE("extract: crease filling keeps the edges of a box", "[mesh]") {
  const Domain3 cube = cube_domain();  // [0, 2]^3
  const TetExtractor3 ex(cube);
  // Random sites inside, on the six faces, on the twelve edges, and the corners, with
  // their patches (the face x_c = 2 s has patch 2 c + s).
  std::vector<double> xyz;
  voroclip::SurfacePatches sp;
  sp.begin.push_back(0);
  std::mt19937_64 rng(9);
  const auto u01 = [&] { return static_cast<double>(rng() >> 11) * 0x1p-53; };
  // fixed[c]: -1 free in (0, 2), else the coordinate is 2 * fixed[c].
  const auto add = [&](const int(&fixed)[3]) {
    for (int c = 0; c < 3; ++c) {
      xyz.push_back(fixed[c] < 0 ? 0.05 + 1.9 * u01() : 2.0 * fixed[c]);
      if (fixed[c] >= 0) sp.patches.push_back(static_cast<std::uint32_t>(2 * c + fixed[c]));
    }
    sp.begin.push_back(static_cast<std::uint32_t>(sp.patches.size()));
  };
  for (int i = 0; i < 300; ++i) add({-1, -1, -1});
  for (int c = 0; c < 3; ++c) {
    for (int side = 0; side < 2; ++side) {
      for (int i = 0; i < 40; ++i) {
        int f[3] = {-1, -1, -1};
        f[c] = side;
        add(f);
      }
    }
  }
  for (int c = 0; c < 3; ++c) {  // edges along axis c
    for (int a = 0; a < 2; ++a) {
      for (int b = 0; b < 2; ++b) {
        for (int i = 0; i < 6; ++i) {
          int f[3];
          f[c] = -1;
          f[(c + 1) % 3] = a;
          f[(c + 2) % 3] = b;
          add(f);
        }
      }
    }
  }
  for (int k = 0; k < 8; ++k) add({k & 1, (k >> 1) & 1, (k >> 2) & 1});
  const Delaunay3 dt(xyz.data(), static_cast<std::uint32_t>(xyz.size() / 3));
  // A boundary facet lies in a face when its three vertices have the same coordinate 0 or 2.
  const auto off_faces = [&](const std::vector<std::uint32_t>& tets) {
    std::uint32_t count = 0;
    for (const std::array<std::uint32_t, 3>& face : boundary_facets(tets)) {
      bool in_face = false;
      for (int c = 0; c < 3 && !in_face; ++c) {
        for (const double v : {0.0, 2.0}) {
          bool all = true;
          for (const std::uint32_t w : face)
            all = all && xyz[3 * w + static_cast<std::size_t>(c)] == v;
          in_face = in_face || all;
        }
      }
      count += in_face ? 0 : 1;
    }
    return count;
  };
  Extract3Options plain;
  const std::vector<std::uint32_t> raw = ex.extract(dt, plain);
  Extract3Options filling;
  filling.surface = &sp;
  Extract3Stats st;
  const std::vector<std::uint32_t> filled = ex.extract(dt, filling, &st);
  const std::uint32_t before = off_faces(raw), after = off_faces(filled);
  INFO(before << " boundary facets off the faces before, " << after << " after; " << st.nb_creases
              << " tets added across creases");
  CHECK(before > 0);
  CHECK(after == 0);
  CHECK(st.nb_creases > 0);
}

TEST_CASE("extract: the same result with 1 and 2 threads", "[mesh][threads]") {
  const Domain3 d(voroclip::read_tet_mesh(kData + "/tetmeshes/sphere.mesh"));
  const TetExtractor3 ex(d);
  const std::vector<double> sites = mixed_sites(d, 2000, 7);
  const Delaunay3 dt(sites.data(), static_cast<std::uint32_t>(sites.size() / 3));
  std::vector<std::uint32_t> one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = ex.extract(dt);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism,
                          voroclip_test::test_threads());
    two = ex.extract(dt);
  }
  CHECK(one == two);
}
