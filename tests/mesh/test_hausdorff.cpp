// hausdorff_distance / sampled_distance: identical surfaces (0), a tet mesh's boundary
// against its source surface (0), concentric cubes (closed forms: b - a one way,
// sqrt(3) (b - a) the other, means by an independent numerical integral), concentric
// icospheres (within the chord errors of the closed form), one displaced vertex (exactly
// its displacement), sample counts, and identical results for 1 and 2 threads.
#include <catch2/catch.hpp>

#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "mesh_test_shapes.h"
#include "support/threads.h"
#include "voroclip/mesh.h"

using voroclip::HausdorffDistance;
using voroclip::TriangleSurface;

namespace {

const std::string kData = std::string(VOROCLIP_SHARED_DATA_DIR);

// A cube [-a, a]^3, two outward triangles per face.
TriangleSurface cube(double a) {
  TriangleSurface s;
  s.source = "cube";
  for (int i = 0; i < 8; ++i) {
    s.xyz.insert(s.xyz.end(), {i & 1 ? a : -a, i & 2 ? a : -a, i & 4 ? a : -a});
  }
  s.triangles = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                 2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
  return s;
}

// The largest distance from the sphere of radius r to the inscribed polyhedron: r minus
// the smallest distance from the centre to a face plane.
double chord_error(const TriangleSurface& s, double r) {
  double nearest = r;
  for (std::size_t t = 0; t < s.nb_triangles(); ++t) {
    const double* a = &s.xyz[3 * std::size_t{s.triangles[3 * t]}];
    const double* b = &s.xyz[3 * std::size_t{s.triangles[3 * t + 1]}];
    const double* c = &s.xyz[3 * std::size_t{s.triangles[3 * t + 2]}];
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                         u[0] * w[1] - u[1] * w[0]};
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    nearest = std::min(nearest, std::fabs(n[0] * a[0] + n[1] * a[1] + n[2] * a[2]) / len);
  }
  return r - nearest;
}

}  // namespace

TEST_CASE(
    "hausdorff_distance: identical surfaces, and a tet mesh's boundary against its "
    "source surface, are at distance 0",
    "[mesh][hausdorff]") {
  const TriangleSurface sphere = voroclip::read_surface(kData + "/surfaces/sphere.obj");
  const HausdorffDistance same = voroclip::hausdorff_distance(sphere, sphere);
  CHECK(same.max_relative() <= 1e-15);  // samples inside triangles: rounding only
  CHECK(same.forward.max == same.backward.max);
  CHECK(same.forward.nb_samples >= 100000);
  for (const char* name : {"sphere", "fandisk"}) {
    const TriangleSurface boundary = voroclip::tet_mesh_boundary(
        voroclip::read_tet_mesh(kData + "/tetmeshes/" + name + ".mesh"));
    const TriangleSurface source =
        voroclip::read_surface(kData + "/surfaces/" + std::string(name) + ".obj");
    const HausdorffDistance d = voroclip::hausdorff_distance(boundary, source);
    CHECK(d.max_relative() <= 1e-15);
    CHECK(d.mean_relative() <= 1e-16);
  }
}

TEST_CASE("hausdorff_distance: concentric cubes", "[mesh][hausdorff]") {
  const double a = 1, b = 1.5;
  const HausdorffDistance d = voroclip::hausdorff_distance(cube(a), cube(b));
  // From the inner cube every point is b - a from the outer one.
  CHECK(d.forward.max == Approx(b - a).epsilon(1e-14));
  CHECK(d.forward.mean == Approx(b - a).epsilon(1e-11));  // a sum of ~10^5 terms
  // From the outer cube the corners are farthest: sqrt(3) (b - a).
  CHECK(d.backward.max == Approx(std::sqrt(3.0) * (b - a)).epsilon(1e-14));
  CHECK(std::fabs(std::fabs(d.backward.where[0]) - b) == 0);
  CHECK(d.max == d.backward.max);
  CHECK(d.diagonal == Approx(2 * b * std::sqrt(3.0)).epsilon(1e-15));
  CHECK(d.max_relative() == Approx((b - a) / (2 * b)).epsilon(1e-14));
  // The mean distance from the outer cube's face z = b to the inner cube, integrated by
  // the midpoint rule on a 1000 x 1000 grid (an independent quadrature); the sampled mean
  // is a centroid rule on sub-triangles of side ~0.03: O(h^2) apart.
  constexpr int kGrid = 1000;
  double integral = 0;
  for (int i = 0; i < kGrid; ++i) {
    for (int j = 0; j < kGrid; ++j) {
      const double x = -b + 2 * b * (i + 0.5) / kGrid, y = -b + 2 * b * (j + 0.5) / kGrid;
      const double dx = std::max(std::fabs(x) - a, 0.0), dy = std::max(std::fabs(y) - a, 0.0);
      integral += std::sqrt((b - a) * (b - a) + dx * dx + dy * dy);
    }
  }
  CHECK(d.backward.mean == Approx(integral / (kGrid * kGrid)).epsilon(1e-4));
  CHECK(d.mean == d.backward.mean);
}

TEST_CASE("hausdorff_distance: concentric icospheres, within the chord errors",
          "[mesh][hausdorff]") {
  const TriangleSurface inner = voroclip_test::icosphere(3, 1.0),
                        outer = voroclip_test::icosphere(4, 1.2);
  const HausdorffDistance d = voroclip::hausdorff_distance(inner, outer);
  // Each polyhedron lies between its sphere and the sphere shrunk by its chord error.
  const double e1 = chord_error(inner, 1.0), e2 = chord_error(outer, 1.2);
  CHECK(d.max >= 0.2 - e2);
  CHECK(d.max <= 0.2 + e1);
  CHECK(d.forward.max <= 0.2 + e1);
  CHECK(d.forward.max >= 0.2 - e2);
  // Inner vertices are on the unit sphere, the outer surface at 1.2 - e2 or farther.
  CHECK(d.forward.mean > 0.2 - e2);
  CHECK(d.forward.mean < 0.2 + e1);
}

TEST_CASE("hausdorff_distance: one displaced vertex", "[mesh][hausdorff]") {
  // A flat 20 x 20 grid of the unit square, then vertex (10, 7) lifted by delta.
  TriangleSurface flat;
  flat.source = "grid";
  const std::uint32_t n = 20;
  for (std::uint32_t j = 0; j <= n; ++j) {
    for (std::uint32_t i = 0; i <= n; ++i) {
      flat.xyz.insert(flat.xyz.end(), {double(i) / n, double(j) / n, 0.0});
    }
  }
  for (std::uint32_t j = 0; j < n; ++j) {
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t v = j * (n + 1) + i;
      flat.triangles.insert(flat.triangles.end(), {v, v + 1, v + n + 2, v, v + n + 2, v + n + 1});
    }
  }
  TriangleSurface bumped = flat;
  const std::size_t lifted = 7 * (n + 1) + 10;
  const double delta = 0.0123;
  bumped.xyz[3 * lifted + 2] = delta;
  const HausdorffDistance d = voroclip::hausdorff_distance(bumped, flat);
  CHECK(d.forward.max == delta);  // the lifted vertex, straight above the plane
  CHECK(d.forward.where[0] == 0.5);
  CHECK(d.forward.where[1] == 0.35);
  CHECK(d.backward.max < delta);
  CHECK(d.backward.max > 0.5 * delta);
  CHECK(d.max == delta);
  CHECK(d.max_relative() == Approx(delta / std::sqrt(2.0)).epsilon(1e-15));
  // The bump's volume is delta / 3 x its fan's area (6 triangles of 1 / 800): the mean
  // distance from the bumped surface is a little under that over the unit area.
  CHECK(d.forward.mean == Approx(delta * 6.0 / 800 / 3).epsilon(0.05));
}

TEST_CASE("sampled_distance: sample counts follow the documented rule", "[mesh][hausdorff]") {
  TriangleSurface one;
  one.xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  one.triangles = {0, 1, 2};
  voroclip::HausdorffOptions o;
  o.samples_per_triangle = 0;
  o.min_samples = 50;  // h = sqrt(0.5 / 50) = 0.1
  const voroclip::SurfaceTree tree(one);
  const voroclip::OneSidedDistance d = voroclip::sampled_distance(one, tree, o);
  // 3 vertices; edges of 1, 1, sqrt 2: 10, 10, 14 pieces, 9 + 9 + 13 inner points;
  // n = round(sqrt(0.5) / 0.1) = 7: 49 sub-triangle centroids.
  CHECK(d.nb_samples == 3 + 31 + 49);
  CHECK(d.max <= 1e-15);
  CHECK_THROWS_AS(voroclip::hausdorff_distance(one, TriangleSurface{}), voroclip::Error);
}

TEST_CASE("hausdorff_distance: the same bits for 1 and 2 threads", "[mesh][hausdorff][threads]") {
  const TriangleSurface a = voroclip::read_surface(kData + "/surfaces/bunny.obj");
  TriangleSurface b = a;
  for (std::size_t i = 0; i < b.xyz.size(); i += 3) b.xyz[i] *= 1.01;
  HausdorffDistance one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = voroclip::hausdorff_distance(a, b);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism,
                          voroclip_test::test_threads());
    two = voroclip::hausdorff_distance(a, b);
  }
  CHECK(one.forward.max == two.forward.max);
  CHECK(one.forward.mean == two.forward.mean);
  CHECK(one.backward.max == two.backward.max);
  CHECK(one.backward.mean == two.backward.mean);
  CHECK(one.forward.where[0] == two.forward.where[0]);
  CHECK(one.max > 0);
}

TEST_CASE("sampled_distance: a local scale, point by point or a block at a time",
          "[mesh][hausdorff][regression]") {
  // mesh3d divides each sample's distance by the local edge length. A Python sizing was
  // called once per sample from two threads (23 s of a 29 s run, fandisk at 1000
  // vertices); scale_batch takes a block of samples per call and must give the same bits.
  // From the inner cube every sample is exactly b - a = 1 from the outer one, so the
  // scaled maximum is the largest 1 / scale over the samples the function was given.
  const TriangleSurface inner = cube(1), outer = cube(2);
  const voroclip::SurfaceTree tree(outer);
  const auto scale = [](const double* p) { return 1 + p[0] * p[0] + 0.25 * p[1]; };
  voroclip::HausdorffOptions pointwise;
  pointwise.scale = scale;
  const voroclip::OneSidedDistance one = voroclip::sampled_distance(inner, tree, pointwise);

  std::mutex lock;
  std::vector<double> given;  // every point scale_batch was given
  std::size_t calls = 0, largest = 0;
  voroclip::HausdorffOptions batched;
  batched.scale = [](const double*) { return 0.0; };  // not used: scale_batch is
  batched.scale_batch = [&](const double* xyz, std::size_t n, double* out) {
    for (std::size_t k = 0; k < n; ++k) out[k] = scale(xyz + 3 * k);
    const std::lock_guard<std::mutex> hold(lock);
    given.insert(given.end(), xyz, xyz + 3 * n);
    ++calls;
    largest = std::max(largest, n);
  };
  const voroclip::OneSidedDistance two = voroclip::sampled_distance(inner, tree, batched);
  CHECK(two.max == one.max);
  CHECK(two.mean == one.mean);
  CHECK(two.nb_samples == one.nb_samples);
  for (int k = 0; k < 3; ++k) CHECK(two.where[k] == one.where[k]);
  REQUIRE(given.size() == 3 * one.nb_samples);
  CHECK(calls < one.nb_samples / 100);
  CHECK(largest <= 4096);
  double expected = 0;
  for (std::size_t k = 0; k < given.size(); k += 3) {
    expected = std::max(expected, 1 / scale(&given[k]));
  }
  CHECK(two.max == expected);
  // A constant scale divides the maximum exactly.
  voroclip::HausdorffOptions halved;
  halved.scale_batch = [](const double*, std::size_t n, double* out) {
    std::fill(out, out + n, 2.0);
  };
  const voroclip::OneSidedDistance plain = voroclip::sampled_distance(inner, tree, {});
  CHECK(voroclip::sampled_distance(inner, tree, halved).max == plain.max / 2);
}
