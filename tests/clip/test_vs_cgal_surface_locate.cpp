// SurfaceLocator against CGAL (tests only; the only surface-location test that includes
// CGAL). The oracle is CGAL::Side_of_triangle_mesh with the exact-constructions kernel
// (Epeck): the circumcentre is constructed exactly (Construct_circumcenter_3) and located
// by CGAL's own ray shooting on an AABB tree, an independent implementation.
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "surface_locate.h"
#include "voroclip/core.h"
#include "voroclip/predicates.h"

using voroclip::Sign;
using voroclip::detail::SurfaceLocator;

namespace {

using K = CGAL::Exact_predicates_exact_constructions_kernel;
using Point = K::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using Side = CGAL::Side_of_triangle_mesh<Mesh, K>;
using P3 = std::array<double, 3>;

Mesh to_cgal(const voroclip::TriangleSurface& s) {
  Mesh m;
  std::vector<Mesh::Vertex_index> v;
  for (std::size_t i = 0; i < s.xyz.size(); i += 3) {
    v.push_back(m.add_vertex(Point(s.xyz[i], s.xyz[i + 1], s.xyz[i + 2])));
  }
  for (std::size_t t = 0; t < s.triangles.size(); t += 3) {
    m.add_face(v[s.triangles[t]], v[s.triangles[t + 1]], v[s.triangles[t + 2]]);
  }
  return m;
}

Sign to_sign(CGAL::Bounded_side b) {
  return b == CGAL::ON_BOUNDED_SIDE ? Sign::positive
         : b == CGAL::ON_BOUNDARY   ? Sign::zero
                                    : Sign::negative;
}

std::string str(const P3& p) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "(%a, %a, %a)", p[0], p[1], p[2]);
  return buf;
}

}  // namespace

TEST_CASE("SurfaceLocator agrees with CGAL::Side_of_triangle_mesh (Epeck)", "[clip][exact][cgal]") {
  const std::uint64_t seed = 0x5c1f;
  INFO("seed " << seed);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u01(0, 1);
  for (const char* name : {"sphere.obj", "bunny.obj", "fandisk.obj"}) {
    INFO(name);
    const voroclip::TriangleSurface s =
        voroclip::read_surface(std::string(VOROCLIP_SHARED_DATA_DIR) + "/surfaces/" + name);
    const Mesh mesh = to_cgal(s);
    const Side side(mesh);
    const SurfaceLocator locator(s.xyz, s.triangles);
    P3 lo = {s.xyz[0], s.xyz[1], s.xyz[2]}, hi = lo;
    for (std::size_t i = 0; i < s.xyz.size(); ++i) {
      lo[i % 3] = std::min(lo[i % 3], s.xyz[i]);
      hi[i % 3] = std::max(hi[i % 3], s.xyz[i]);
    }
    std::size_t failures = 0, counts[3] = {0, 0, 0}, checked = 0;
    const auto report = [&](const std::string& what, Sign got, Sign want) {
      ++checked;
      ++counts[static_cast<int>(want) + 1];
      if (got != want && ++failures <= 10) {
        FAIL_CHECK(what << ": SurfaceLocator " << static_cast<int>(got) << ", CGAL "
                        << static_cast<int>(want));
      }
    };
    // Circumcentres of small tets around the box (some nearly flat), and of tets with
    // corners on the surface's vertices (their circumcentres near the surface).
    const double r = 0.05 * (hi[0] - lo[0]);
    for (int i = 0; i < 600; ++i) {
      std::array<P3, 4> p;
      if (i % 2 == 0) {
        for (int k = 0; k < 3; ++k) {
          p[0][static_cast<std::size_t>(k)] =
              lo[static_cast<std::size_t>(k)] +
              (hi[static_cast<std::size_t>(k)] - lo[static_cast<std::size_t>(k)]) * u01(rng);
        }
        for (std::size_t j = 1; j < 4; ++j) {
          for (std::size_t k = 0; k < 3; ++k) p[j][k] = p[0][k] + r * (2 * u01(rng) - 1);
        }
      } else {
        const std::size_t t = rng() % (s.triangles.size() / 3);
        const std::size_t t2 = rng() % (s.triangles.size() / 3);
        for (std::size_t j = 0; j < 4; ++j) {
          const std::size_t v = j < 3 ? s.triangles[3 * t + j] : s.triangles[3 * t2];
          p[j] = {s.xyz[3 * v], s.xyz[3 * v + 1], s.xyz[3 * v + 2]};
        }
      }
      if (voroclip::orient3d(p[0].data(), p[1].data(), p[2].data(), p[3].data()) == Sign::zero) {
        continue;
      }
      const Point c = K::Construct_circumcenter_3()(
          Point(p[0][0], p[0][1], p[0][2]), Point(p[1][0], p[1][1], p[1][2]),
          Point(p[2][0], p[2][1], p[2][2]), Point(p[3][0], p[3][1], p[3][2]));
      report("circumcentre of " + str(p[0]) + " " + str(p[1]) + " " + str(p[2]) + " " + str(p[3]),
             locator.locate_circumcenter(p[0].data(), p[1].data(), p[2].data(), p[3].data()),
             to_sign(side(c)));
    }
    // Points: uniform in the box, and the surface's vertices.
    for (int i = 0; i < 1000; ++i) {
      P3 p;
      for (std::size_t k = 0; k < 3; ++k) p[k] = lo[k] + (hi[k] - lo[k]) * u01(rng);
      report("point " + str(p), locator.locate(p.data()), to_sign(side(Point(p[0], p[1], p[2]))));
    }
    for (std::size_t v = 0; v < s.xyz.size() / 3; v += 7) {
      const P3 p = {s.xyz[3 * v], s.xyz[3 * v + 1], s.xyz[3 * v + 2]};
      report("vertex " + str(p), locator.locate(p.data()), to_sign(side(Point(p[0], p[1], p[2]))));
    }
    INFO(checked << " queries: " << counts[2] << " inside, " << counts[1] << " on, " << counts[0]
                 << " outside");
    CHECK(failures == 0);
    CHECK(counts[2] > 100);
    CHECK(counts[1] > 50);
    CHECK(counts[0] > 100);
  }
}
