// Closed surfaces for the tests of the 3D domains, clipping and meshing (tests/support/, shared
// by the clip, cvt and mesh tests): an icosphere, a box, reversed, moved and merged surfaces,
// the boundary of a tet mesh written as OBJ and read back, and a temporary directory.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unistd.h>

#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "voroclip/core.h"

namespace voroclip_test {

// The icosahedron subdivided `levels` times, its vertices on the sphere of radius r about
// `centre` (each new vertex the normalised sum of its edge's endpoints), triangles outward
// by the right-hand rule.
inline voroclip::TriangleSurface icosphere(int levels, double r = 1,
                                           std::array<double, 3> centre = {0, 0, 0}) {
  const double g = (1 + std::sqrt(5.0)) / 2;
  std::vector<std::array<double, 3>> v = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
                                          {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
                                          {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  const auto unit = [](const std::array<double, 3>& p) {
    const double n = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    return std::array<double, 3>{p[0] / n, p[1] / n, p[2] / n};
  };
  for (auto& p : v) p = unit(p);
  std::vector<std::uint32_t> tri = {0, 11, 5, 0, 5,  1,  0,  1,  7,  0,  7, 10, 0, 10, 11,
                                    1, 5,  9, 5, 11, 4,  11, 10, 2,  10, 7, 6,  7, 1,  8,
                                    3, 9,  4, 3, 4,  2,  3,  2,  6,  3,  6, 8,  3, 8,  9,
                                    4, 9,  5, 2, 4,  11, 6,  2,  10, 8,  6, 7,  9, 8,  1};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> middle;
    const auto mid = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      const auto it = middle.find(key);
      if (it != middle.end()) return it->second;
      v.push_back(unit({v[a][0] + v[b][0], v[a][1] + v[b][1], v[a][2] + v[b][2]}));
      return middle[key] = static_cast<std::uint32_t>(v.size() - 1);
    };
    std::vector<std::uint32_t> next;
    for (std::size_t t = 0; t < tri.size(); t += 3) {
      const std::uint32_t a = tri[t], b = tri[t + 1], c = tri[t + 2];
      const std::uint32_t ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
      next.insert(next.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
    }
    tri = std::move(next);
  }
  voroclip::TriangleSurface s;
  s.source = "icosphere";
  for (const auto& p : v) {
    s.xyz.insert(s.xyz.end(), {centre[0] + r * p[0], centre[1] + r * p[1], centre[2] + r * p[2]});
  }
  s.triangles = std::move(tri);
  return s;
}

// The box [lo, hi] as 12 triangles, outward by the right-hand rule; vertex i = x + 2y + 4z
// at (x ? hi : lo, ...).
inline voroclip::TriangleSurface box_surface(const std::array<double, 3>& lo,
                                             const std::array<double, 3>& hi) {
  voroclip::TriangleSurface s;
  s.source = "box";
  for (int i = 0; i < 8; ++i) {
    for (int k = 0; k < 3; ++k) {
      s.xyz.push_back((i >> k) & 1 ? hi[static_cast<std::size_t>(k)]
                                   : lo[static_cast<std::size_t>(k)]);
    }
  }
  // Two triangles per face, counter-clockwise seen from outside.
  s.triangles = {0, 2, 3, 0, 3, 1,   // z = lo
                 4, 5, 7, 4, 7, 6,   // z = hi
                 0, 1, 5, 0, 5, 4,   // y = lo
                 2, 6, 7, 2, 7, 3,   // y = hi
                 0, 4, 6, 0, 6, 2,   // x = lo
                 1, 3, 7, 1, 7, 5};  // x = hi
  return s;
}

// A thick tube (genus 1): the annulus r_in <= |(x, y)| <= r_out, z0 <= z <= z1, its circles
// regular polygons of `segments` sides (the first vertex at angle 0), triangles outward by
// the right-hand rule. Vertices: ring k (0 inner bottom, 1 outer bottom, 2 inner top, 3
// outer top) at k * segments + i.
inline voroclip::TriangleSurface tube_surface(double r_in, double r_out, double z0, double z1,
                                              std::uint32_t segments) {
  voroclip::TriangleSurface s;
  s.source = "tube";
  const double pi = 3.14159265358979323846;
  for (int ring = 0; ring < 4; ++ring) {
    const double r = ring % 2 == 0 ? r_in : r_out;
    const double z = ring < 2 ? z0 : z1;
    for (std::uint32_t i = 0; i < segments; ++i) {
      const double a = 2 * pi * i / segments;
      s.xyz.insert(s.xyz.end(), {r * std::cos(a), r * std::sin(a), z});
    }
  }
  const auto v = [&](int ring, std::uint32_t i) {
    return static_cast<std::uint32_t>(ring) * segments + i % segments;
  };
  // A quad (a, b, c, d), counter-clockwise seen from outside, as two triangles.
  const auto quad = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
    s.triangles.insert(s.triangles.end(), {a, b, c, a, c, d});
  };
  for (std::uint32_t i = 0; i < segments; ++i) {
    const std::uint32_t j = i + 1;
    quad(v(1, i), v(1, j), v(3, j), v(3, i));  // outer wall, facing away from the axis
    quad(v(0, j), v(0, i), v(2, i), v(2, j));  // inner wall, facing the axis
    quad(v(2, i), v(3, i), v(3, j), v(2, j));  // top, facing +z
    quad(v(0, j), v(1, j), v(1, i), v(0, i));  // bottom, facing -z
  }
  return s;
}

// Every triangle listed the other way round.
inline voroclip::TriangleSurface reversed(voroclip::TriangleSurface s) {
  for (std::size_t t = 0; t < s.triangles.size(); t += 3) {
    std::swap(s.triangles[t + 1], s.triangles[t + 2]);
  }
  return s;
}

// Two surfaces as one input (vertices and triangles of b after a's).
inline voroclip::TriangleSurface merged(voroclip::TriangleSurface a,
                                        const voroclip::TriangleSurface& b) {
  const auto base = static_cast<std::uint32_t>(a.xyz.size() / 3);
  a.xyz.insert(a.xyz.end(), b.xyz.begin(), b.xyz.end());
  for (const std::uint32_t v : b.triangles) a.triangles.push_back(v + base);
  a.triangle_line.clear();
  a.triangle_face.clear();
  return a;
}

// A directory of its own under the system's temporary directory, removed with its files;
// the process id in its name keeps concurrent test runs (other worktrees) apart.
class TempDir {
 public:
  explicit TempDir(const std::string& name)
      : path_(std::filesystem::temp_directory_path() /
              ("voroclip_test_" + name + "_" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

}  // namespace voroclip_test
