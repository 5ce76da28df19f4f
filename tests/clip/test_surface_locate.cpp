// Tests of SurfaceLocator (clip/src/surface_locate.h): exact point and circumcentre
// location in the volume bounded by a closed triangle surface.
//
// Oracles, independent of the ray-crossing method:
//   - analytic answers (exact comparisons of dyadic coordinates) on boxes, a hollow box,
//     two boxes, an octahedron and random voxel unions, at points on faces, edges, corners,
//     on the faces' planes and the lines through the edges (the rays run along faces and
//     edges), one ulp off them, and at circumcentres placed there exactly;
//   - the tet meshes of the shared data (tetmeshes/*.mesh), whose boundaries are exactly
//     the surfaces: a point is inside iff it lies in a closed tet, on the surface iff on a
//     boundary facet of a tet that holds it (orient3d, or orient3d_circumcenter for
//     circumcentres);
//   - and, on every shared surface, the six rays (three axes, two directions, forced) and
//     the automatic choice must give the same answer.
// CGAL's Side_of_triangle_mesh is a further oracle in test_surface_locate_vs_cgal.cpp.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <gmpxx.h>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "exact_oracle.h"
#include "surface_locate.h"
#include "voroclip/core.h"
#include "voroclip/predicates.h"

using namespace voroclip;
using namespace voroclip::test;
using detail::SurfaceLocator;

namespace {

using P3 = std::array<double, 3>;

struct Mesh {
  std::vector<double> xyz;
  std::vector<std::uint32_t> tris;
};

std::string str(const P3& p) { return "(" + hex(p[0]) + ", " + hex(p[1]) + ", " + hex(p[2]) + ")"; }

const char* sign_name(Sign s) {
  return s == Sign::positive ? "inside" : s == Sign::zero ? "on" : "outside";
}

// The box [lo, hi] as 12 triangles (two per face, outward), appended to m.
void add_box(Mesh& m, const P3& lo, const P3& hi, bool flip_diagonals = false) {
  const auto base = static_cast<std::uint32_t>(m.xyz.size() / 3);
  for (int v = 0; v < 8; ++v) {
    m.xyz.push_back((v & 1) ? hi[0] : lo[0]);
    m.xyz.push_back((v & 2) ? hi[1] : lo[1]);
    m.xyz.push_back((v & 4) ? hi[2] : lo[2]);
  }
  // Faces as quads (corners counter-clockwise seen from outside), split on a diagonal.
  static constexpr int kQuads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                       {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : kQuads) {
    const int s = flip_diagonals ? 1 : 0;
    const int c[4] = {q[s], q[(s + 1) % 4], q[(s + 2) % 4], q[(s + 3) % 4]};
    for (const int k : {c[0], c[1], c[2], c[0], c[2], c[3]}) {
      m.tris.push_back(base + static_cast<std::uint32_t>(k));
    }
  }
}

Mesh box(const P3& lo, const P3& hi) {
  Mesh m;
  add_box(m, lo, hi);
  return m;
}

// The octahedron |x| + |y| + |z| <= r.
Mesh octahedron(double r) {
  Mesh m;
  m.xyz = {r, 0, 0, -r, 0, 0, 0, r, 0, 0, -r, 0, 0, 0, r, 0, 0, -r};
  for (const std::uint32_t x : {0u, 1u}) {
    for (const std::uint32_t y : {2u, 3u}) {
      for (const std::uint32_t z : {4u, 5u}) {
        m.tris.insert(m.tris.end(), {x, y, z});
      }
    }
  }
  return m;
}

// The locator with the automatic choice, then the six forced rays.
struct Locators {
  std::vector<SurfaceLocator> all;
  explicit Locators(const Mesh& m) {
    all.emplace_back(m.xyz, m.tris);
    for (int axis = 0; axis < 3; ++axis) {
      for (const int dir : {1, -1}) all.emplace_back(m.xyz, m.tris, axis, dir);
    }
  }
  static const char* name(std::size_t i) {
    static const char* const kNames[7] = {"auto", "+x", "-x", "+y", "-y", "+z", "-z"};
    return kNames[i];
  }
};

// Counts the answers that differ from `want` (every ray), reporting the first few.
struct Tally {
  std::size_t checked = 0, failures = 0;
  std::size_t by_sign[3] = {0, 0, 0};

  void point(const Locators& loc, const P3& p, Sign want, const char* what = "") {
    ++checked;
    ++by_sign[static_cast<int>(want) + 1];
    for (std::size_t i = 0; i < loc.all.size(); ++i) {
      const Sign got = loc.all[i].locate(p.data());
      if (got != want) fail(std::string(what) + " point " + str(p), i, got, want);
    }
  }
  void circumcenter(const Locators& loc, const std::array<P3, 4>& s, Sign want,
                    const char* what = "") {
    ++checked;
    ++by_sign[static_cast<int>(want) + 1];
    for (std::size_t i = 0; i < loc.all.size(); ++i) {
      const Sign got =
          loc.all[i].locate_circumcenter(s[0].data(), s[1].data(), s[2].data(), s[3].data());
      if (got != want) {
        fail(std::string(what) + " circumcentre of " + str(s[0]) + " " + str(s[1]) + " " +
                 str(s[2]) + " " + str(s[3]),
             i, got, want);
      }
    }
  }
  void fail(const std::string& what, std::size_t ray, Sign got, Sign want) {
    ++failures;
    if (failures <= 12) {
      FAIL_CHECK(what << ": ray " << Locators::name(ray) << " says " << sign_name(got)
                      << ", expected " << sign_name(want));
    }
  }
};

// The analytic answer for a box: the exact comparisons of p with its planes.
Sign box_side(const P3& lo, const P3& hi, const P3& p) {
  bool on = false;
  for (int k = 0; k < 3; ++k) {
    if (p[k] < lo[k] || p[k] > hi[k]) return Sign::negative;
    on = on || p[k] == lo[k] || p[k] == hi[k];
  }
  return on ? Sign::zero : Sign::positive;
}

// Coordinates that hit the box's planes, the lines through its edges, and the regions
// between and beyond: lo + k (hi - lo) / 4 for k = -2 .. 6 (exact: dyadic fractions).
std::vector<double> probe_values(double lo, double hi) {
  std::vector<double> v;
  for (int k = -2; k <= 6; ++k) v.push_back(lo + (hi - lo) * 0.25 * k);
  return v;
}

// The circumcentre of these four sites is exactly c (they are at distance r from c and
// not coplanar): c + r e_x, c - r e_x, c + r e_y, c + r e_z.
std::array<P3, 4> sites_around(const P3& c, double r) {
  return {P3{c[0] + r, c[1], c[2]}, P3{c[0] - r, c[1], c[2]}, P3{c[0], c[1] + r, c[2]},
          P3{c[0], c[1], c[2] + r}};
}

// Whether the four sites around c are exact (c +- r computed without rounding).
bool exact_sites(const P3& c, double r) {
  for (std::size_t k = 0; k < 3; ++k) {
    const mpq_class ck(c[k]), rq(r);
    if (mpq_class(c[k] + r) != ck + rq || mpq_class(c[k] - r) != ck - rq) return false;
  }
  return true;
}

// ---------------------------------------------------------------------------------------
// The tet-mesh oracle.

struct TetOracle {
  TetMeshInput mesh;
  std::vector<std::array<double, 6>> box;
  std::vector<std::array<int, 4>> inside_sign;  // orient3d of facet k with vertex k
  std::set<std::array<std::uint32_t, 3>> boundary;

  static constexpr int kFacet[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

  explicit TetOracle(const std::string& path) : mesh(read_tet_mesh(path)) {
    const std::uint32_t nt = mesh.nb_tets();
    box.resize(nt);
    inside_sign.resize(nt);
    for (std::uint32_t t = 0; t < nt; ++t) {
      auto& b = box[t];
      for (int c = 0; c < 3; ++c) {
        b[static_cast<std::size_t>(c)] = std::numeric_limits<double>::infinity();
        b[static_cast<std::size_t>(c + 3)] = -std::numeric_limits<double>::infinity();
      }
      for (int v = 0; v < 4; ++v) {
        const double* p = vertex(t, v);
        for (std::size_t c = 0; c < 3; ++c) {
          b[c] = std::min(b[c], p[c]);
          b[c + 3] = std::max(b[c + 3], p[c]);
        }
      }
      for (int f = 0; f < 4; ++f) {
        inside_sign[t][static_cast<std::size_t>(f)] =
            static_cast<int>(orient3d(vertex(t, kFacet[f][0]), vertex(t, kFacet[f][1]),
                                      vertex(t, kFacet[f][2]), vertex(t, f)));
      }
    }
    const TriangleSurface s = tet_mesh_boundary(mesh);
    for (std::size_t i = 0; i < s.triangles.size(); i += 3) {
      std::array<std::uint32_t, 3> k = {s.triangles[i], s.triangles[i + 1], s.triangles[i + 2]};
      std::sort(k.begin(), k.end());
      boundary.insert(k);
    }
  }

  const double* vertex(std::uint32_t t, int v) const {
    return &mesh.xyz[3 * std::size_t{mesh.tets[4 * std::size_t{t} + static_cast<std::size_t>(v)]}];
  }

  // side(a, b, c) = orient3d(a, b, c, x); [lo, hi] a box around x.
  template <class Side>
  Sign locate(const double* lo, const double* hi, const Side& side) const {
    bool inside = false;
    for (std::uint32_t t = 0; t < mesh.nb_tets(); ++t) {
      const auto& b = box[t];
      if (b[0] > hi[0] || b[1] > hi[1] || b[2] > hi[2] || b[3] < lo[0] || b[4] < lo[1] ||
          b[5] < lo[2]) {
        continue;
      }
      int zero_facets = 0;
      bool in = true;
      for (int f = 0; f < 4 && in; ++f) {
        const int s = static_cast<int>(
            side(vertex(t, kFacet[f][0]), vertex(t, kFacet[f][1]), vertex(t, kFacet[f][2])));
        if (s == 0) {
          zero_facets |= 1 << f;
        } else if (s != inside_sign[t][static_cast<std::size_t>(f)]) {
          in = false;
        }
      }
      if (!in) continue;
      inside = true;
      for (int f = 0; f < 4; ++f) {
        if ((zero_facets >> f & 1) == 0) continue;
        std::array<std::uint32_t, 3> k;
        for (int i = 0; i < 3; ++i) {
          k[static_cast<std::size_t>(i)] =
              mesh.tets[4 * std::size_t{t} + static_cast<std::size_t>(kFacet[f][i])];
        }
        std::sort(k.begin(), k.end());
        if (boundary.count(k) != 0) return Sign::zero;
      }
    }
    return inside ? Sign::positive : Sign::negative;
  }

  Sign locate(const P3& p) const {
    return locate(p.data(), p.data(), [&](const double* a, const double* b, const double* c) {
      return orient3d(a, b, c, p.data());
    });
  }
  Sign locate_circumcenter(const std::array<P3, 4>& s) const {
    double centre[3], hw[3], lo[3], hi[3];
    if (circumcenter3d_enclosure(s[0].data(), s[1].data(), s[2].data(), s[3].data(), centre, hw)) {
      for (int k = 0; k < 3; ++k) {
        lo[k] = centre[k] - hw[k];
        hi[k] = centre[k] + hw[k];
      }
    } else {
      for (int k = 0; k < 3; ++k) {
        lo[k] = -std::numeric_limits<double>::infinity();
        hi[k] = std::numeric_limits<double>::infinity();
      }
    }
    return locate(lo, hi, [&](const double* a, const double* b, const double* c) {
      return orient3d_circumcenter(a, b, c, s[0].data(), s[1].data(), s[2].data(), s[3].data());
    });
  }
};

Mesh to_mesh(const TriangleSurface& s) { return {s.xyz, s.triangles}; }

std::string surface_path(const std::string& name) {
  return std::string(VOROCLIP_SHARED_DATA_DIR) + "/surfaces/" + name;
}
std::string tetmesh_path(const std::string& name) {
  return std::string(VOROCLIP_SHARED_DATA_DIR) + "/tetmeshes/" + name;
}

void bounding_box(const Mesh& m, P3& lo, P3& hi) {
  lo = {m.xyz[0], m.xyz[1], m.xyz[2]};
  hi = lo;
  for (std::size_t i = 0; i < m.xyz.size(); i += 3) {
    for (std::size_t k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], m.xyz[i + k]);
      hi[k] = std::max(hi[k], m.xyz[i + k]);
    }
  }
}

P3 random_in(Rng& rng, const P3& lo, const P3& hi, double margin) {
  P3 p;
  for (std::size_t k = 0; k < 3; ++k) {
    const double w = hi[k] - lo[k];
    p[k] = uniform(rng, lo[k] - margin * w, hi[k] + margin * w);
  }
  return p;
}

const double* corner(const Mesh& m, std::size_t t, int k) {
  return &m.xyz[3 * std::size_t{m.tris[3 * t + static_cast<std::size_t>(k)]}];
}

// A point on triangle t in floating point (barycentric, so within rounding of it).
P3 near_triangle(const Mesh& m, std::size_t t, Rng& rng) {
  double u = u01(rng), v = u01(rng);
  if (u + v > 1) {
    u = 1 - u;
    v = 1 - v;
  }
  P3 p;
  for (std::size_t k = 0; k < 3; ++k) {
    const double a = corner(m, t, 0)[k], b = corner(m, t, 1)[k], c = corner(m, t, 2)[k];
    p[k] = a + u * (b - a) + v * (c - a);
  }
  return p;
}

P3 nudged(P3 p, Rng& rng) {
  const auto k = static_cast<std::size_t>(rng() % 3);
  p[k] = nudge(p[k], coin(rng) ? 1 : -1);
  return p;
}

// The midpoint of an edge when it is exact (2 m = a + b in rationals), else false.
bool exact_midpoint(const double* a, const double* b, P3& m) {
  for (std::size_t k = 0; k < 3; ++k) {
    m[k] = 0.5 * (a[k] + b[k]);
    if (mpq_class(m[k]) * 2 != mpq_class(a[k]) + mpq_class(b[k])) return false;
  }
  return true;
}

}  // namespace

// ---------------------------------------------------------------------------------------

TEST_CASE("SurfaceLocator: the unit cube's faces, edges, corners, planes and edge lines",
          "[clip][exact][degenerate]") {
  const P3 lo = {0, 0, 0}, hi = {1, 1, 1};
  for (const bool flip : {false, true}) {
    Mesh m;
    add_box(m, lo, hi, flip);
    const Locators loc(m);
    Tally tally;
    const std::vector<double> v = probe_values(0, 1);
    for (const double x : v) {
      for (const double y : v) {
        for (const double z : v) {
          const P3 p = {x, y, z};
          tally.point(loc, p, box_side(lo, hi, p));
          // One ulp off in every direction of every coordinate.
          for (std::size_t k = 0; k < 3; ++k) {
            for (const int d : {1, -1}) {
              P3 q = p;
              q[k] = nudge(q[k], d);
              tally.point(loc, q, box_side(lo, hi, q), "nudged");
            }
          }
        }
      }
    }
    INFO(tally.checked << " points: " << tally.by_sign[2] << " inside, " << tally.by_sign[1]
                       << " on, " << tally.by_sign[0] << " outside");
    CHECK(tally.failures == 0);
    CHECK(tally.by_sign[1] > 400);
  }
}

TEST_CASE("SurfaceLocator: hollow cube, two cubes, octahedron", "[clip][exact][degenerate]") {
  SECTION("hollow cube: wall, cavity, outside") {
    const P3 olo = {0, 0, 0}, ohi = {4, 4, 4}, ilo = {1, 1, 1}, ihi = {3, 3, 3};
    Mesh m = box(olo, ohi);
    add_box(m, ilo, ihi, true);
    const Locators loc(m);
    Tally tally;
    for (int i = -1; i <= 9; ++i) {
      for (int j = -1; j <= 9; ++j) {
        for (int k = -1; k <= 9; ++k) {
          const P3 p = {0.5 * i, 0.5 * j, 0.5 * k};
          const Sign outer = box_side(olo, ohi, p), inner = box_side(ilo, ihi, p);
          const Sign want = outer == Sign::zero || inner == Sign::zero           ? Sign::zero
                            : outer == Sign::positive && inner == Sign::negative ? Sign::positive
                                                                                 : Sign::negative;
          tally.point(loc, p, want);
        }
      }
    }
    CHECK(tally.failures == 0);
    CHECK(tally.by_sign[0] > 0);
    CHECK(tally.by_sign[1] > 0);
    CHECK(tally.by_sign[2] > 0);
  }
  SECTION("two disjoint cubes in a row: rays along both") {
    const P3 alo = {0, 0, 0}, ahi = {1, 1, 1}, blo = {2, 0, 0}, bhi = {3, 1, 1};
    Mesh m = box(alo, ahi);
    add_box(m, blo, bhi);
    const Locators loc(m);
    Tally tally;
    for (int i = -2; i <= 14; ++i) {
      for (int j = -2; j <= 6; ++j) {
        for (int k = -2; k <= 6; ++k) {
          const P3 p = {0.25 * i, 0.25 * j, 0.25 * k};
          const Sign a = box_side(alo, ahi, p), b = box_side(blo, bhi, p);
          tally.point(loc, p, std::max(a, b, [](Sign s, Sign t) {
                        return static_cast<int>(s) < static_cast<int>(t);
                      }));
        }
      }
    }
    CHECK(tally.failures == 0);
  }
  SECTION("octahedron with its vertices on the axes") {
    const Mesh m = octahedron(1);
    const Locators loc(m);
    Tally tally;
    for (int i = -9; i <= 9; ++i) {
      for (int j = -9; j <= 9; ++j) {
        for (int k = -9; k <= 9; ++k) {
          const P3 p = {i / 8.0, j / 8.0, k / 8.0};
          const int l1 = std::abs(i) + std::abs(j) + std::abs(k);
          tally.point(loc, p, l1 < 8 ? Sign::positive : l1 == 8 ? Sign::zero : Sign::negative);
        }
      }
    }
    CHECK(tally.failures == 0);
    CHECK(tally.by_sign[1] > 100);
  }
}

TEST_CASE("SurfaceLocator: scale sweep 1e-9 .. 1e9, translated by 1e6",
          "[clip][exact][degenerate]") {
  for (int e = -9; e <= 9; ++e) {
    for (const double shift : {0.0, 1e6, -1e6}) {
      const double s = std::pow(10.0, e);
      const P3 lo = {shift, shift, shift}, hi = {shift + s, shift + s, shift + s};
      if (!(hi[0] > lo[0])) continue;
      INFO("scale " << s << " shift " << shift);
      const Locators loc(box(lo, hi));
      Tally tally;
      const std::vector<double> v = probe_values(lo[0], hi[0]);
      for (const double x : v) {
        for (const double y : v) {
          for (const double z : v) {
            const P3 p = {x, y, z};
            tally.point(loc, p, box_side(lo, hi, p));
            for (std::size_t k = 0; k < 3; ++k) {
              P3 q = p;
              q[k] = nudge(q[k], k == 1 ? -1 : 1);
              tally.point(loc, q, box_side(lo, hi, q), "nudged");
            }
          }
        }
      }
      // Circumcentres of sites around a point of the lattice, where exact.
      const double r = (hi[0] - lo[0]) * 0.375;
      std::size_t circumcentres = 0;
      for (const double x : v) {
        for (const double y : v) {
          const P3 c = {x, y, lo[2]};
          if (!exact_sites(c, r)) continue;
          ++circumcentres;
          tally.circumcenter(loc, sites_around(c, r), box_side(lo, hi, c));
        }
      }
      CHECK(tally.failures == 0);
      CHECK(tally.by_sign[1] > 0);
      if (shift == 0) CHECK(circumcentres > 0);
    }
  }
}

TEST_CASE("SurfaceLocator: circumcentres on a cube's faces, edges and corners",
          "[clip][exact][degenerate]") {
  const std::uint64_t seed = seed_for(0x5c1c);
  INFO("seed " << seed);
  Rng rng(seed);
  const P3 lo = {0, 0, 0}, hi = {1, 1, 1};
  const Locators loc(box(lo, hi));
  Tally tally;
  const std::vector<double> v = probe_values(0, 1);
  const auto& shell = sphere_points();
  for (const double x : v) {
    for (const double y : v) {
      for (const double z : v) {
        const P3 c = {x, y, z};
        const Sign want = box_side(lo, hi, c);
        CHECK(loc.all[0].locate(c.data()) == want);
        tally.circumcenter(loc, sites_around(c, 0.375), want, "axis-aligned");
        // Four random non-coplanar lattice points of a sphere around c, scaled by 2^-5.
        for (int rep = 0; rep < 3; ++rep) {
          std::array<P3, 4> s;
          for (auto& q : s) {
            const auto& w = shell[rng() % shell.size()];
            q = {c[0] + std::ldexp(static_cast<double>(w[0]), -5),
                 c[1] + std::ldexp(static_cast<double>(w[1]), -5),
                 c[2] + std::ldexp(static_cast<double>(w[2]), -5)};
          }
          if (orient3d(s[0].data(), s[1].data(), s[2].data(), s[3].data()) == Sign::zero) {
            continue;
          }
          tally.circumcenter(loc, s, want, "lattice sphere");
        }
      }
    }
  }
  INFO(tally.checked << " circumcentres");
  CHECK(tally.failures == 0);
  CHECK(tally.by_sign[1] > 200);
}

TEST_CASE("SurfaceLocator: nearly flat tets without an enclosure, coplanar sites",
          "[clip][exact][degenerate]") {
  // Sites on the circle of radius 5/32 around c in the plane z = c_z, the fourth lifted by
  // d: the circumcentre is c + (0, 0, d / 2) exactly (|(3, 4)| = 5), and for |d| tiny the
  // tet is too flat for circumcenter3d_enclosure.
  const auto flat = [](const P3& c, double d) {
    const double r = 5.0 / 32;
    return std::array<P3, 4>{P3{c[0] + r, c[1], c[2]}, P3{c[0] - r, c[1], c[2]},
                             P3{c[0], c[1] + r, c[2]},
                             P3{c[0] + 3.0 / 32, c[1] + 4.0 / 32, c[2] + d}};
  };
  const P3 lo = {0, 0, 0}, hi = {1, 1, 1};
  Mesh hollow = box({-1, -1, -1}, {2, 2, 2});
  add_box(hollow, lo, hi, true);  // a cavity: the unit cube
  const Locators cube(box(lo, hi)), cavity(hollow);
  Tally tally;
  std::size_t unboxed = 0;
  for (const double x : probe_values(0, 1)) {
    for (const double y : probe_values(0, 1)) {
      for (const double z : {0.0, 0.5, 1.0, 1.5, -1.0, 2.0, 3.0}) {
        // The lift: 2^-70 at 0, else one ulp of z either way (so that z + d is exact).
        const double up = z == 0 ? std::ldexp(1.0, -70) : nudge(z, 1) - z;
        const double down = z == 0 ? -std::ldexp(1.0, -70) : nudge(z, -1) - z;
        for (const double dd : {up, down}) {
          const auto s = flat({x, y, z}, dd);
          const P3 x_exact = {x, y, z + dd / 2};  // exact in rationals, not as a double
          double centre[3], hw[3];
          unboxed += !circumcenter3d_enclosure(s[0].data(), s[1].data(), s[2].data(), s[3].data(),
                                               centre, hw);
          // The side of the cube: z + d/2 is strictly between the doubles around z.
          Sign want = Sign::negative;
          const bool xy_closed = x >= 0 && x <= 1 && y >= 0 && y <= 1;
          const bool xy_open = x > 0 && x < 1 && y > 0 && y < 1;
          const bool z_open = (z == 0 && dd > 0) || (z == 1 && dd < 0) || (z > 0 && z < 1);
          if (xy_closed && z_open) want = xy_open ? Sign::positive : Sign::zero;
          tally.circumcenter(cube, s, want, "flat");
          // In the hollow box the unit cube is the cavity: inside becomes outside.
          const bool in_outer = x_exact[0] > -1 && x_exact[0] < 2 && x_exact[1] > -1 &&
                                x_exact[1] < 2 && (z > -1 || (z == -1 && dd > 0)) &&
                                (z < 2 || (z == 2 && dd < 0));
          const Sign want_hollow = want == Sign::zero       ? Sign::zero
                                   : want == Sign::positive ? Sign::negative
                                   : in_outer               ? Sign::positive
                                                            : Sign::negative;
          tally.circumcenter(cavity, s, want_hollow, "flat in hollow");
        }
      }
    }
  }
  INFO(unboxed << " without an enclosure");
  CHECK(tally.failures == 0);
  CHECK(unboxed * 4 > tally.checked);  // most of them
  CHECK(tally.by_sign[1] > 0);
  CHECK(tally.by_sign[2] > 0);
  // Coplanar sites: no circumcentre.
  for (const auto& l : cube.all) {
    const auto s = flat({0.5, 0.5, 0.5}, 0);
    CHECK_THROWS_AS(l.locate_circumcenter(s[0].data(), s[1].data(), s[2].data(), s[3].data()),
                    Error);
    const auto far = flat({50, 0.5, 0.5}, 0);  // outside the bounding box too
    CHECK_THROWS_AS(
        l.locate_circumcenter(far[0].data(), far[1].data(), far[2].data(), far[3].data()), Error);
  }
}

namespace {

// A union of unit voxels of an n^3 grid (filled at random), scaled by 2^e and shifted: its
// boundary squares, each split on a random diagonal. Edges where two voxels meet along an
// edge only are in four triangles (closed mod 2, as the locator needs). The answer at a
// point: the voxels whose closed cube holds it, all filled: inside, none: outside, else on
// the boundary.
struct Voxels {
  int n;
  std::vector<char> filled;
  double scale, shift;
  Mesh mesh;

  bool at(int x, int y, int z) const {
    if (x < 0 || y < 0 || z < 0 || x >= n || y >= n || z >= n) return false;
    return filled[static_cast<std::size_t>((z * n + y) * n + x)] != 0;
  }
  double coord(double lattice) const { return shift + lattice * scale; }

  Voxels(int size, double fill, Rng& rng, double s, double t)
      : n(size), filled(static_cast<std::size_t>(size * size * size)), scale(s), shift(t) {
    for (auto& f : filled) f = u01(rng) < fill ? 1 : 0;
    const auto vertex = [&](int x, int y, int z) {
      mesh.xyz.insert(mesh.xyz.end(), {coord(x), coord(y), coord(z)});
      return static_cast<std::uint32_t>(mesh.xyz.size() / 3 - 1);
    };
    for (int z = 0; z <= n; ++z) {
      for (int y = 0; y <= n; ++y) {
        for (int x = 0; x <= n; ++x) vertex(x, y, z);
      }
    }
    const auto id = [&](int x, int y, int z) {
      return static_cast<std::uint32_t>((z * (n + 1) + y) * (n + 1) + x);
    };
    // The face of voxel v normal to axis k at its upper side, between v and v + e_k.
    for (int k = 0; k < 3; ++k) {
      for (int z = -1; z < n; ++z) {
        for (int y = -1; y < n; ++y) {
          for (int x = -1; x < n; ++x) {
            int c[3] = {x, y, z};
            if ((k != 0 && x < 0) || (k != 1 && y < 0) || (k != 2 && z < 0)) continue;
            int d[3] = {x, y, z};
            d[k] += 1;
            if (at(c[0], c[1], c[2]) == at(d[0], d[1], d[2])) continue;
            // The square's corners, in order around it.
            int q[4][3];
            for (int i = 0; i < 4; ++i) {
              q[i][0] = d[0];
              q[i][1] = d[1];
              q[i][2] = d[2];
            }
            const int i1 = (k + 1) % 3, i2 = (k + 2) % 3;
            q[1][i1] += 1;
            q[2][i1] += 1;
            q[2][i2] += 1;
            q[3][i2] += 1;
            const int s0 = coin(rng) ? 0 : 1;
            const auto corner_id = [&](int i) {
              const int* r = q[(i + s0) % 4];
              return id(r[0], r[1], r[2]);
            };
            mesh.tris.insert(mesh.tris.end(), {corner_id(0), corner_id(1), corner_id(2)});
            mesh.tris.insert(mesh.tris.end(), {corner_id(0), corner_id(2), corner_id(3)});
          }
        }
      }
    }
  }

  // The answer at lattice point (half-integers h / 2), exactly.
  Sign side(const int h[3]) const {
    int lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
      // h even: on a grid plane, voxels h/2 - 1 and h/2; odd: inside voxel (h - 1) / 2.
      const int f = h[k] >= 0 ? h[k] / 2 : -((1 - h[k]) / 2);
      lo[k] = h[k] % 2 == 0 ? f - 1 : f;
      hi[k] = f;
    }
    int total = 0, full = 0;
    for (int z = lo[2]; z <= hi[2]; ++z) {
      for (int y = lo[1]; y <= hi[1]; ++y) {
        for (int x = lo[0]; x <= hi[0]; ++x) {
          ++total;
          full += at(x, y, z) ? 1 : 0;
        }
      }
    }
    return full == total ? Sign::positive : full == 0 ? Sign::negative : Sign::zero;
  }
};

}  // namespace

TEST_CASE("SurfaceLocator: voxel unions (rays along faces and edges everywhere), scaled",
          "[clip][exact][degenerate]") {
  const std::uint64_t seed = seed_for(0x5c20);
  INFO("seed " << seed);
  Rng rng(seed);
  for (int rep = 0; rep < 8; ++rep) {
    // Scales 2^-40 .. 2^40; every other one shifted by 3 2^j times the scale (j <= 40: the
    // lattice stays exact, its spacing far above an ulp).
    const int e = static_cast<int>(rand_int(rng, -40, 40));
    const double scale = std::ldexp(1.0, e);
    const double shift =
        rep % 2 == 0 ? 0.0 : std::ldexp(3.0, e + static_cast<int>(rand_int(rng, 0, 40)));
    const Voxels vox(5, 0.45, rng, scale, shift);
    INFO("rep " << rep << " scale " << scale << " shift " << shift << ": "
                << vox.mesh.tris.size() / 3 << " triangles");
    if (vox.mesh.tris.empty()) continue;
    // Exactness of the lattice coordinates (the shift must not round them).
    bool exact = true;
    for (int h = -2; h <= 12; ++h) {
      const double x = vox.coord(h * 0.5);
      exact = exact && mpq_class(x) == mpq_class(shift) + mpq_class(h * 0.5) * mpq_class(scale);
    }
    REQUIRE(exact);
    const Locators loc(vox.mesh);
    Tally tally;
    for (int hz = -1; hz <= 11; ++hz) {
      for (int hy = -1; hy <= 11; ++hy) {
        for (int hx = -1; hx <= 11; ++hx) {
          const int h[3] = {hx, hy, hz};
          const P3 p = {vox.coord(hx * 0.5), vox.coord(hy * 0.5), vox.coord(hz * 0.5)};
          tally.point(loc, p, vox.side(h));
          // Circumcentres at the lattice point, every fourth.
          if ((hx + 2 * hy + 3 * hz) % 4 == 0) {
            tally.circumcenter(loc, sites_around(p, 0.5 * scale), vox.side(h), "around");
          }
        }
      }
    }
    // Points one ulp off the lattice points (far less than the lattice's spacing): on the
    // side of the open unit interval the move enters (h even: a grid plane, left for the
    // interval beside it; h odd: already inside one).
    for (int i = 0; i < 1500; ++i) {
      int hh[3];
      P3 p;
      for (std::size_t k = 0; k < 3; ++k) {
        hh[k] = static_cast<int>(rand_int(rng, -1, 11));
        p[k] = vox.coord(hh[k] * 0.5);
      }
      const auto k = static_cast<std::size_t>(rng() % 3);
      const int dir = coin(rng) ? 1 : -1;
      p[k] = nudge(p[k], dir);
      if (hh[k] % 2 == 0) hh[k] += dir;
      tally.point(loc, p, vox.side(hh), "nudged");
    }
    CHECK(tally.failures == 0);
    CHECK(tally.by_sign[0] > 0);
    CHECK(tally.by_sign[1] > 0);
  }
}

TEST_CASE("SurfaceLocator: zero-area triangles are on the surface, never crossed",
          "[clip][exact][degenerate]") {
  // The unit cube and, inside it, a pair of collinear triangles (p, m, q), (q, m, p) on the
  // segment from p to q (closed: each of its edges in two triangles).
  Mesh m = box({0, 0, 0}, {1, 1, 1});
  const auto base = static_cast<std::uint32_t>(m.xyz.size() / 3);
  m.xyz.insert(m.xyz.end(), {0.25, 0.5, 0.5, 0.5, 0.5, 0.5, 0.75, 0.5, 0.5});
  m.tris.insert(m.tris.end(), {base, base + 1, base + 2, base + 2, base + 1, base});
  const Locators loc(m);
  Tally tally;
  for (const double x : {0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875}) {
    const bool on = x >= 0.25 && x <= 0.75;
    const P3 p = {x, 0.5, 0.5};
    tally.point(loc, p, on ? Sign::zero : Sign::positive, "segment");
    tally.point(loc, {x, nudge(0.5, 1), 0.5}, Sign::positive, "beside");
    tally.circumcenter(loc, sites_around(p, 0.125), on ? Sign::zero : Sign::positive, "segment");
  }
  CHECK(tally.failures == 0);
}

TEST_CASE("SurfaceLocator: invalid input", "[clip][exact]") {
  const Mesh m = box({0, 0, 0}, {1, 1, 1});
  std::vector<std::uint32_t> bad = m.tris;
  bad[5] = 8;
  CHECK_THROWS_AS(SurfaceLocator(m.xyz, bad), Error);
  std::vector<double> xyz = m.xyz;
  xyz[4] = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(SurfaceLocator(xyz, m.tris), Error);
  // An unused vertex may be anything.
  xyz = m.xyz;
  xyz.insert(xyz.end(), {std::numeric_limits<double>::infinity(), 0, 0});
  const SurfaceLocator l(xyz, m.tris);
  const double p[3] = {0.5, 0.5, 0.5}, nan[3] = {0.5, std::nan(""), 0.5};
  CHECK(l.locate(p) == Sign::positive);
  CHECK_THROWS_AS(l.locate(nan), Error);
  // No triangles: everything is outside.
  const SurfaceLocator empty(m.xyz, {});
  CHECK(empty.locate(p) == Sign::negative);
  const SurfaceLocator none;
  CHECK(none.locate(p) == Sign::negative);
}

TEST_CASE("SurfaceLocator: the six rays agree on every shared surface", "[clip][exact]") {
  const std::uint64_t seed = seed_for(0x5c1d);
  INFO("seed " << seed);
  Rng rng(seed);
  for (const char* name : {"sphere.obj", "bunny.obj", "homer.obj", "rocker-arm.obj", "elk.off",
                           "fandisk.obj", "skull_low_resolution.obj", "gargoyle.off"}) {
    INFO(name);
    const Mesh m = to_mesh(read_surface(surface_path(name)));
    const Locators loc(m);
    P3 lo, hi;
    bounding_box(m, lo, hi);
    std::size_t failures = 0, counts[3] = {0, 0, 0};
    const auto check = [&](const P3& p, const char* what, bool on_surface) {
      const Sign s0 = loc.all[0].locate(p.data());
      ++counts[static_cast<int>(s0) + 1];
      bool ok = !on_surface || s0 == Sign::zero;
      for (std::size_t i = 1; i < loc.all.size(); ++i) ok = ok && loc.all[i].locate(p.data()) == s0;
      if (!ok && ++failures <= 10) {
        std::string answers;
        for (const auto& l : loc.all) answers += std::string(" ") + sign_name(l.locate(p.data()));
        FAIL_CHECK(what << " " << str(p) << ":" << answers);
      }
    };
    const std::size_t nt = m.tris.size() / 3;
    for (std::size_t i = 0; i < scaled(3000); ++i)
      check(random_in(rng, lo, hi, 0.05), "random", false);
    for (std::size_t i = 0; i < scaled(2000); ++i) {
      const std::size_t t = rng() % nt;
      check(near_triangle(m, t, rng), "near a triangle", false);
      const P3 v = {corner(m, t, 0)[0], corner(m, t, 0)[1], corner(m, t, 0)[2]};
      check(v, "vertex", true);
      check(nudged(v, rng), "nudged vertex", false);
      P3 mid;
      if (exact_midpoint(corner(m, t, 0), corner(m, t, 1), mid)) {
        check(mid, "edge midpoint", true);
        check(nudged(mid, rng), "nudged edge midpoint", false);
      }
    }
    INFO(counts[2] << " inside, " << counts[1] << " on, " << counts[0] << " outside");
    CHECK(failures == 0);
    CHECK(counts[2] > scaled(500));
    CHECK(counts[0] > scaled(500));
  }
}

TEST_CASE("SurfaceLocator agrees with the tet meshes (points and circumcentres)", "[clip][exact]") {
  const std::uint64_t seed = seed_for(0x5c1e);
  INFO("seed " << seed);
  Rng rng(seed);
  for (const char* name : {"sphere", "bunny"}) {
    INFO(name);
    const TetOracle oracle(tetmesh_path(std::string(name) + ".mesh"));
    const Mesh m = to_mesh(read_surface(surface_path(std::string(name) + ".obj")));
    const Locators loc(m);
    P3 lo, hi;
    bounding_box(m, lo, hi);
    Tally points, circumcentres;
    const std::size_t nt = m.tris.size() / 3;
    for (std::size_t i = 0; i < scaled(1500); ++i) {
      const P3 p = random_in(rng, lo, hi, 0.05);
      points.point(loc, p, oracle.locate(p), "random");
    }
    for (std::size_t i = 0; i < scaled(800); ++i) {
      const std::size_t t = rng() % nt;
      const P3 p = near_triangle(m, t, rng);
      points.point(loc, p, oracle.locate(p), "near a triangle");
      const P3 v = {corner(m, t, 1)[0], corner(m, t, 1)[1], corner(m, t, 1)[2]};
      const P3 q = nudged(v, rng);
      points.point(loc, q, oracle.locate(q), "nudged vertex");
      P3 mid;
      if (exact_midpoint(corner(m, t, 1), corner(m, t, 2), mid)) {
        points.point(loc, mid, Sign::zero, "edge midpoint");
        const P3 r = nudged(mid, rng);
        points.point(loc, r, oracle.locate(r), "nudged edge midpoint");
      }
    }
    // The tet mesh's own vertices (interior Steiner points are inside).
    for (std::uint32_t v = 0; v < oracle.mesh.nb_vertices(); v += 3) {
      const P3 p = {oracle.mesh.xyz[3 * v], oracle.mesh.xyz[3 * v + 1], oracle.mesh.xyz[3 * v + 2]};
      points.point(loc, p, oracle.locate(p), "tet vertex");
    }
    INFO(points.checked << " points: " << points.by_sign[2] << " inside, " << points.by_sign[1]
                        << " on, " << points.by_sign[0] << " outside");
    CHECK(points.failures == 0);
    CHECK(points.by_sign[1] > scaled(100));

    // Circumcentres: of the mesh's tets (the extraction's queries: near the surface, some
    // outside), of small random quadruples, and of quadruples of surface vertices.
    const auto site = [&](std::uint32_t v) {
      return P3{oracle.mesh.xyz[3 * std::size_t{v}], oracle.mesh.xyz[3 * std::size_t{v} + 1],
                oracle.mesh.xyz[3 * std::size_t{v} + 2]};
    };
    const std::uint32_t ntets = oracle.mesh.nb_tets();
    for (std::size_t i = 0; i < scaled(500); ++i) {
      const std::size_t t = rng() % ntets;
      std::array<P3, 4> s;
      for (std::size_t k = 0; k < 4; ++k) s[k] = site(oracle.mesh.tets[4 * t + k]);
      circumcentres.circumcenter(loc, s, oracle.locate_circumcenter(s), "tet");
    }
    for (std::size_t i = 0; i < scaled(400); ++i) {
      std::array<P3, 4> s;
      s[0] = random_in(rng, lo, hi, 0.02);
      const double r = 0.05 * (hi[0] - lo[0]);
      for (std::size_t k = 1; k < 4; ++k) {
        s[k] = {s[0][0] + uniform(rng, -r, r), s[0][1] + uniform(rng, -r, r),
                s[0][2] + uniform(rng, -r, r)};
      }
      circumcentres.circumcenter(loc, s, oracle.locate_circumcenter(s), "small random");
    }
    for (std::size_t i = 0; i < scaled(200); ++i) {
      std::array<P3, 4> s;
      const std::size_t t = rng() % nt;
      for (std::size_t k = 0; k < 3; ++k)
        s[k] = {corner(m, t, static_cast<int>(k))[0], corner(m, t, static_cast<int>(k))[1],
                corner(m, t, static_cast<int>(k))[2]};
      const std::size_t t2 = rng() % nt;
      s[3] = {corner(m, t2, 0)[0], corner(m, t2, 0)[1], corner(m, t2, 0)[2]};
      if (orient3d(s[0].data(), s[1].data(), s[2].data(), s[3].data()) == Sign::zero) continue;
      circumcentres.circumcenter(loc, s, oracle.locate_circumcenter(s), "surface vertices");
    }
    INFO(circumcentres.checked << " circumcentres: " << circumcentres.by_sign[2] << " inside, "
                               << circumcentres.by_sign[1] << " on, " << circumcentres.by_sign[0]
                               << " outside");
    CHECK(circumcentres.failures == 0);
    // About a fifth of them fall outside; VOROCLIP_TEST_SCALE shrinks every count.
    CHECK(circumcentres.by_sign[2] > scaled(100));
    CHECK(circumcentres.by_sign[0] > scaled(50));
  }
}
