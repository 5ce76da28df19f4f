// Tests of the smooth placement of surface vertices (PhongSurface, Mesh3Options::
// smooth_surface): the Phong lift interpolates the input's vertices exactly, is the identity
// on planar patches and not across a crease it must not smooth, brings points of an
// icosphere's facets nearer the sphere; mesh3d with it puts the output's surface vertices
// nearer the sphere than flat snapping does, stays valid, and is bitwise the same with 1
// and 2 threads.
#include <catch2/catch.hpp>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "mesh_test_shapes.h"
#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/mesh.h"

using voroclip::Domain3;
using voroclip::Mesh3Options;
using voroclip::Mesh3Result;
using voroclip::Mesh3VertexKind;
using voroclip::PhongSurface;
using voroclip::Sign;

namespace {

// The icosphere with every triangle on feature line 0 (none).
voroclip::TriangleSurface icosphere(int levels) {
  voroclip::TriangleSurface s = voroclip_test::icosphere(levels);
  s.triangle_line.assign(s.nb_triangles(), 0);
  return s;
}

// The ball bounded by the icosphere: one tet per triangle, with the centre.
Domain3 ball(int levels) {
  const voroclip::TriangleSurface s = icosphere(levels);
  voroclip::TetMeshInput m;
  m.source = "icosphere ball";
  m.xyz = s.xyz;
  m.xyz.insert(m.xyz.end(), {0.0, 0.0, 0.0});
  const std::uint32_t centre = s.nb_vertices();
  for (std::size_t t = 0; t < s.triangles.size(); t += 3) {
    std::uint32_t a = s.triangles[t], b = s.triangles[t + 1], c = s.triangles[t + 2];
    if (voroclip::orient3d(&m.xyz[3 * centre], &m.xyz[3 * a], &m.xyz[3 * b], &m.xyz[3 * c]) !=
        Sign::negative)
      std::swap(b, c);
    m.tets.insert(m.tets.end(), {centre, a, b, c});
  }
  return Domain3(m);
}

double radius(const double* p) { return std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]); }

Mesh3Options small_options(std::uint32_t n) {
  Mesh3Options o;
  o.nb_vertices = n;
  o.smooth_surface = true;
  o.unconstrained_iterations = 8;
  o.constrained_iterations = 12;
  o.perturbation.max_rounds = 4;
  return o;
}

// |radius - 1| over the surface vertices: {max, mean, count}.
std::array<double, 3> sphere_deviation(const Mesh3Result& r) {
  double max = 0, sum = 0, count = 0;
  for (std::uint32_t v = 0; v < r.nb_vertices(); ++v) {
    if (r.kinds[v] != Mesh3VertexKind::kSurface) continue;
    const double d = std::fabs(radius(&r.xyz[3 * std::size_t{v}]) - 1);
    max = std::max(max, d);
    sum += d;
    ++count;
  }
  return {max, count > 0 ? sum / count : 0.0, count};
}

}  // namespace

TEST_CASE("PhongSurface: exact at the vertices, nearer the sphere than the facets",
          "[mesh][exact]") {
  const voroclip::TriangleSurface s = icosphere(2);
  const voroclip::SurfaceTree tree(s);
  const PhongSurface phong(s, {}, {}, 0.5);
  double flat_sum = 0, smooth_sum = 0, worst_ratio = 0;
  for (std::uint32_t t = 0; t < s.nb_triangles(); ++t) {
    const std::uint32_t* v = &s.triangles[3 * std::size_t{t}];
    for (int k = 0; k < 3; ++k) {
      const double* p = &s.xyz[3 * std::size_t{v[k]}];
      double q[3], n[3];
      phong.lift(t, p, q, n);
      CHECK(q[0] == p[0]);
      CHECK(q[1] == p[1]);
      CHECK(q[2] == p[2]);
      // The corner normal of a vertex of the icosphere is nearly radial.
      const double* c = phong.corner_normal(t, k);
      CHECK(c[0] * p[0] + c[1] * p[1] + c[2] * p[2] > 0.999);
    }
    // Points inside the facet: their gap to the sphere shrinks.
    for (const auto& b :
         {std::array<double, 3>{1.0 / 3, 1.0 / 3, 1.0 / 3}, std::array<double, 3>{0.5, 0.5, 0.0},
          std::array<double, 3>{0.6, 0.3, 0.1}}) {
      double x[3];
      for (int c = 0; c < 3; ++c) {
        x[c] = b[0] * s.xyz[3 * v[0] + c] + b[1] * s.xyz[3 * v[1] + c] + b[2] * s.xyz[3 * v[2] + c];
      }
      double q[3], n[3];
      phong.lift(t, x, q, n);
      const double flat = std::fabs(radius(x) - 1), smooth = std::fabs(radius(q) - 1);
      flat_sum += flat;
      smooth_sum += smooth;
      worst_ratio = std::max(worst_ratio, smooth / flat);
      // The interpolated normal is nearly radial.
      CHECK(n[0] * q[0] + n[1] * q[1] + n[2] * q[2] > 0.999 * radius(q));
      // project() lifts the closest point of the facets: x is its own closest point.
      double qp[3], np[3];
      phong.project(tree, x, qp, np);
      CHECK(std::fabs(radius(qp) - 1) == Approx(smooth).margin(1e-15));
    }
  }
  INFO("mean gap to the sphere: facets " << flat_sum / (3 * s.nb_triangles()) << ", Phong "
                                         << smooth_sum / (3 * s.nb_triangles()) << "; worst ratio "
                                         << worst_ratio);
  CHECK(smooth_sum < 0.05 * flat_sum);
  CHECK(worst_ratio < 0.15);
  // shape 0: the facets themselves, bit for bit.
  const PhongSurface flat(s, {}, {}, 0.0);
  double x[3] = {0.2, 0.3, 0.9}, q[3], n[3], c[3], cn[3];
  flat.project(tree, x, q, n);
  const voroclip::SurfaceTree::Closest closest = tree.closest(x);
  std::copy_n(closest.point, 3, c);
  std::copy_n(closest.normal, 3, cn);
  CHECK(std::equal(q, q + 3, c));
}

TEST_CASE("PhongSurface: the identity on planar patches, not across an unbroken crease",
          "[mesh][exact]") {
  // A unit cube's surface, two triangles per face.
  voroclip::TriangleSurface s;
  s.source = "cube";
  for (int k = 0; k < 8; ++k)
    s.xyz.insert(s.xyz.end(), {1.0 * (k & 1), 1.0 * ((k >> 1) & 1), 1.0 * (k >> 2)});
  s.triangles = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                 2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
  std::vector<std::uint32_t> face(12);
  for (std::uint32_t t = 0; t < 12; ++t) face[t] = t / 2;
  const PhongSurface by_face(s, face, {}, 0.5);
  const PhongSurface one_patch(s, {}, {}, 0.5);
  std::uint32_t moved = 0;
  for (std::uint32_t t = 0; t < 12; ++t) {
    const std::uint32_t* v = &s.triangles[3 * std::size_t{t}];
    double x[3];
    for (int c = 0; c < 3; ++c) {
      x[c] = (s.xyz[3 * v[0] + c] + 2 * s.xyz[3 * v[1] + c] + 4 * s.xyz[3 * v[2] + c]) / 7;
    }
    double q[3], n[3];
    by_face.lift(t, x, q, n);
    CHECK(std::equal(q, q + 3, x));
    one_patch.lift(t, x, q, n);
    moved += std::equal(q, q + 3, x) ? 0 : 1;
  }
  CHECK(moved == 12);
  // One patch, the vertices of the edge (0, 1) pinned: its points stay, those of the edge
  // (0, 2) still move (triangle 0 is (0, 2, 3), triangle 4 is (0, 1, 5)).
  std::vector<std::uint8_t> pinned(8, 0);
  pinned[0] = pinned[1] = 1;
  const PhongSurface pinned_edge(s, {}, pinned, 0.5);
  double x[3] = {0.375, 0, 0}, q[3], n[3];
  pinned_edge.lift(4, x, q, n);
  CHECK(std::equal(q, q + 3, x));
  double y[3] = {0, 0.375, 0};
  pinned_edge.lift(0, y, q, n);
  CHECK_FALSE(std::equal(q, q + 3, y));
  CHECK_THROWS_AS(PhongSurface(s, {}, std::vector<std::uint8_t>(3, 0)), voroclip::Error);

  CHECK_THROWS_AS(PhongSurface(s, std::vector<std::uint32_t>(5, 0)), voroclip::Error);
  CHECK_THROWS_AS(PhongSurface(s, {}, {}, 1.5), voroclip::Error);
  CHECK_THROWS_AS(PhongSurface(s, {}, {}, -0.1), voroclip::Error);
}

TEST_CASE("PhongSurface: an exactly planar region keeps its plane where it blends into a curve",
          "[mesh][exact]") {
  // z = 0 for x <= 1, then z = (x - 1)^2 (tangent at x = 1): a 9 x 5 grid, one patch, no
  // crease. The vertices with x < 1 inside the grid are flat (every triangle around them
  // is exactly in z = 0), so every triangle in z = 0 is in one planar region.
  voroclip::TriangleSurface s;
  s.source = "plane blending into a parabolic cylinder";
  const int nx = 9, ny = 5;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const double x = 0.25 * i, z = x > 1 ? (x - 1) * (x - 1) : 0.0;
      s.xyz.insert(s.xyz.end(), {x, 0.25 * j, z});
    }
  }
  for (int j = 0; j + 1 < ny; ++j) {
    for (int i = 0; i + 1 < nx; ++i) {
      const auto a = static_cast<std::uint32_t>(j * nx + i);
      s.triangles.insert(s.triangles.end(), {a, a + 1, a + nx + 1, a, a + nx + 1, a + nx});
    }
  }
  const PhongSurface phong(s, {}, {}, 0.75);
  std::uint32_t planar = 0, curved_moved = 0;
  for (std::uint32_t t = 0; t < s.nb_triangles(); ++t) {
    const std::uint32_t* v = &s.triangles[3 * std::size_t{t}];
    bool in_plane = true;
    for (int k = 0; k < 3; ++k) in_plane = in_plane && s.xyz[3 * v[k] + 2] == 0;
    for (int k = 0; k < 3; ++k) {
      // At the junction x = 1 every corner normal is the plane's (0, 0, 1), exactly: the
      // curved triangles there leave the plane tangentially.
      if (s.xyz[3 * v[k]] == 1 || in_plane) {
        const double* n = phong.corner_normal(t, k);
        CHECK(n[0] == 0);
        CHECK(n[1] == 0);
        CHECK(n[2] == 1);
      }
    }
    double x[3];
    for (int c = 0; c < 3; ++c) {
      x[c] = (s.xyz[3 * v[0] + c] + 2 * s.xyz[3 * v[1] + c] + 4 * s.xyz[3 * v[2] + c]) / 7;
    }
    double q[3], n[3];
    phong.lift(t, x, q, n);
    if (in_plane) {
      // Including the triangles with a corner on the junction, whose corner normals an
      // average over the blend would tilt, lifting their points off the plane.
      ++planar;
      CHECK(std::equal(q, q + 3, x));
    } else {
      curved_moved += std::equal(q, q + 3, x) ? 0 : 1;
    }
  }
  CHECK(planar == 32);
  CHECK(curved_moved == 32);  // the curved half is still smoothed
  // The same grid with one vertex of the plane raised off it by 2^-40: no vertex around it
  // is flat any more, so the corner normals near it are averages again and the triangles
  // around it are lifted.
  voroclip::TriangleSurface bumped = s;
  bumped.xyz[3 * (2 * nx + 2) + 2] = 0x1p-40;
  const PhongSurface phong_bumped(bumped, {}, {}, 0.75);
  // Cell (i, j) = (1, 2): its first triangle has the raised vertex (2, 2) as a corner.
  const std::uint32_t t = 2 * (2 * (nx - 1) + 1);
  const std::uint32_t* v = &bumped.triangles[3 * std::size_t{t}];
  double x[3];
  for (int c = 0; c < 3; ++c) {
    x[c] = (bumped.xyz[3 * v[0] + c] + bumped.xyz[3 * v[1] + c] + bumped.xyz[3 * v[2] + c]) / 3;
  }
  double q[3], n[3];
  phong_bumped.lift(t, x, q, n);
  CHECK_FALSE(std::equal(q, q + 3, x));
}

TEST_CASE(
    "mesh3d on an icosphere ball: smooth placement puts the surface vertices nearer "
    "the sphere",
    "[mesh]") {
  const Domain3 d = ball(2);
  Mesh3Options o = small_options(500);
  o.smooth_shape = 0.5;  // the shape that reproduces a sphere (the default 3/4 overshoots)
  const Mesh3Result smooth = voroclip::mesh3d(d, o);
  o.smooth_shape = 0.75;
  const Mesh3Result overshoot = voroclip::mesh3d(d, o);
  o.smooth_surface = false;
  const Mesh3Result flat = voroclip::mesh3d(d, o);
  CHECK(smooth.nb_feature_lines == 0);
  for (const Mesh3Result* r : {&smooth, &overshoot, &flat}) {
    REQUIRE(r->nb_tets() > 0);
    // Right-handed, exactly; a closed 2-manifold boundary (Domain3's validation).
    std::size_t wrong = 0;
    for (std::uint32_t t = 0; t < r->nb_tets(); ++t) {
      const std::uint32_t* v = &r->tets[4 * std::size_t{t}];
      wrong += voroclip::orient3d(&r->xyz[3 * v[0]], &r->xyz[3 * v[1]], &r->xyz[3 * v[2]],
                                  &r->xyz[3 * v[3]]) != Sign::negative
                   ? 1
                   : 0;
    }
    CHECK(wrong == 0);
    voroclip::TetMeshInput m;
    m.source = "mesh3d output";
    m.xyz = r->xyz;
    m.tets = r->tets;
    CHECK_NOTHROW(Domain3(m));
  }
  const auto s = sphere_deviation(smooth);
  const auto f = sphere_deviation(flat);
  INFO("surface vertices |r - 1|: smooth max " << s[0] << " mean " << s[1] << " (" << s[2]
                                               << "); flat max " << f[0] << " mean " << f[1] << " ("
                                               << f[2] << ")");
  CHECK(s[2] > 100);
  CHECK(f[2] > 100);
  CHECK(s[1] < 0.05 * f[1]);
  CHECK(s[0] < 0.2 * f[0]);
  // 3/4: the surface vertices lie outside the sphere by about half the facets' sag, and
  // nearer it than the flat ones (which are inside by up to the sag).
  std::uint32_t outside = 0, surface = 0;
  for (std::uint32_t v = 0; v < overshoot.nb_vertices(); ++v) {
    if (overshoot.kinds[v] != Mesh3VertexKind::kSurface) continue;
    ++surface;
    outside += radius(&overshoot.xyz[3 * std::size_t{v}]) > 1 ? 1 : 0;
  }
  const auto o3 = sphere_deviation(overshoot);
  INFO("3/4: max " << o3[0] << " mean " << o3[1] << "; " << outside << " of " << surface
                   << " outside");
  CHECK(outside > surface / 2);
  CHECK(o3[1] < 0.6 * f[1]);
}

TEST_CASE("mesh3d with smooth placement: the same mesh with 1 and 2 threads", "[mesh][threads]") {
  const Mesh3Result one =
      voroclip_test::check_same_mesh3d_with_1_and_2_threads(ball(2), small_options(300));
  CHECK(std::count(one.kinds.begin(), one.kinds.end(), Mesh3VertexKind::kSurface) > 50);
}
