// Surface3: a closed triangle surface validated exactly (the contract is the comment on
// Surface3 in clip.h).
//
// Passes, in this order; each reports its first defect (the one about the smallest
// triangle, or vertex), so that the message does not depend on the thread count:
//  1. Indices in range; finite coordinates of the used vertices; bounding box.
//  2. Welding: the used vertices sorted by coordinates; equal ones map to the smallest
//     index of their group (+0 and -0 are equal).
//  3. Per triangle (parallel): a repeated vertex (after welding); zero area (collinear3d).
//  4. Duplicates: triangles keyed by their sorted vertices.
//  5. Edges, keyed and bucketed by their smaller vertex (validation.h): each must be in
//     exactly two triangles, which run through it in opposite directions; that gives the
//     adjacency.
//  6. Fans: the triangles around each vertex, walked across edges, form one cycle.
//  7. Self-intersections (surface_intersect.cpp: exact triangle-triangle tests).
//  8. Shells: connected components, depth first from the lowest triangle of each (the
//     order); their counts, genus, area and volume.
//  9. Orientation and nesting: the exact sign of each shell's enclosed volume
//     (surface_volume_sign); which shells enclose which (shells do not meet, so one vertex
//     of a shell, located exactly in another, decides); a shell must face outward when an
//     even number of shells enclose it, inward otherwise.
// 10. The point locator over all triangles (surface_locate.cpp).
// Passes 5 to 10 (build) also serve the boundary of a tet mesh (Domain3), whose tets have
// checked what passes 1 to 4 check.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "surface_intersect.h"
#include "surface_locate.h"
#include "validation.h"
#include "voroclip/clip.h"

namespace voroclip {

using detail::FirstError;
using detail::Keyed;
using detail::point;

std::string Surface3::triangle_name(std::uint32_t t) const {
  const std::uint32_t line = t < triangle_line_.size() ? triangle_line_[t] : 0u;
  const std::string at_line = line != 0 ? " (line " + std::to_string(line) + ")" : "";
  switch (naming_) {
    case Naming::kFace:
      return "face " + std::to_string(triangle_face_[t]) + at_line;
    case Naming::kTetFacet:
      return tet_facet_name(t) + at_line;
    case Naming::kIndex:
      break;
  }
  return "triangle " + std::to_string(t);
}

std::string Surface3::tet_name(std::uint32_t t) const {
  return tet_noun_ + " " + std::to_string(t < tet_label_.size() ? tet_label_[t] : std::uint64_t{t});
}

std::string Surface3::vertex_number(std::uint32_t v) const {
  if (v < vertex_label_.size()) return std::to_string(vertex_label_[v]);
  return std::to_string(std::uint64_t{v} + vertex_base_);
}

std::string Surface3::vertex_name(std::uint32_t v) const { return "vertex " + vertex_number(v); }

// A tet has up to four boundary facets: its name alone does not say which one. Its vertices
// do, in increasing order of their index as Domain3 names a facet.
std::string Surface3::tet_facet_name(std::uint32_t t) const {
  std::uint32_t a = triangle_vertex(t, 0), b = triangle_vertex(t, 1), c = triangle_vertex(t, 2);
  detail::sort3(a, b, c);
  return "the boundary facet (vertices " + vertex_number(a) + " " + vertex_number(b) + " " +
         vertex_number(c) + ") of " + tet_name(triangle_face_[t]);
}

std::string Surface3::at(std::uint32_t t) const {
  const std::uint32_t line = t < triangle_line_.size() ? triangle_line_[t] : 0u;
  const std::string where = source_ + (line != 0 ? ":" + std::to_string(line) : "") + ": ";
  switch (naming_) {
    case Naming::kFace:
      return where + "face " + std::to_string(triangle_face_[t]);
    case Naming::kTetFacet:
      return where + tet_facet_name(t);
    case Naming::kIndex:
      break;
  }
  return where + "triangle " + std::to_string(t);
}

Surface3::Surface3(const TriangleSurface& surface, const Surface3Options& options)
    : source_(surface.source.empty() ? std::string("surface") : surface.source) {
  if (surface.xyz.size() % 3 != 0 || surface.triangles.size() % 3 != 0) {
    throw Error(source_ + ": the surface arrays hold " + std::to_string(surface.xyz.size()) +
                " coordinates and " + std::to_string(surface.triangles.size()) +
                " triangle vertex indices (multiples of 3 expected)");
  }
  if (surface.triangles.size() / 3 >= (std::size_t{1} << 30)) {
    throw Error(source_ + ": more than 2^30 triangles");
  }
  xyz_ = surface.xyz;
  triangles_ = surface.triangles;
  const std::uint32_t nv = nb_vertices();
  const std::uint32_t nt = nb_triangles();
  if (surface.triangle_face.size() == nt && nt > 0) {
    naming_ = Naming::kFace;
    triangle_face_ = surface.triangle_face;
  }
  if (surface.triangle_line.size() == nt) triangle_line_ = surface.triangle_line;
  vertex_base_ = surface.vertex_base;
  const auto corners = [&](std::uint32_t t) {
    std::string s;
    for (int k = 0; k < 3; ++k) {
      s += (k ? " " : "") + std::to_string(std::uint64_t{triangle_vertex(t, k)} + vertex_base_);
    }
    return s;
  };

  // ---- 1. Indices, finite coordinates.
  std::vector<std::uint32_t> first_use(nv, kNone);
  for (std::uint32_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = triangle_vertex(t, k);
      if (v >= nv) {
        throw Error(at(t) + ": vertex index " + std::to_string(std::uint64_t{v} + vertex_base_) +
                    " is out of range (the surface has " + std::to_string(nv) + " vertices)");
      }
      if (first_use[v] == kNone) first_use[v] = t;
    }
  }
  for (std::uint32_t v = 0; v < nv; ++v) {
    if (first_use[v] == kNone) continue;
    const double* p = vertex(v);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      throw Error(at(first_use[v]) + ": " + vertex_name(v) + " has a non-finite coordinate " +
                  point(p));
    }
  }

  // ---- 2. Welding.
  std::vector<std::uint32_t> rep(nv);
  for (std::uint32_t v = 0; v < nv; ++v) rep[v] = v;
  {
    std::vector<std::uint32_t> used;
    used.reserve(nv);
    for (std::uint32_t v = 0; v < nv; ++v) {
      if (first_use[v] != kNone) used.push_back(v);
    }
    const auto less = [&](std::uint32_t u, std::uint32_t v) {
      const double *p = vertex(u), *q = vertex(v);
      if (p[0] != q[0]) return p[0] < q[0];
      if (p[1] != q[1]) return p[1] < q[1];
      if (p[2] != q[2]) return p[2] < q[2];
      return u < v;
    };
    std::sort(used.begin(), used.end(), less);
    for (std::size_t i = 1; i < used.size(); ++i) {
      const double *p = vertex(used[i - 1]), *q = vertex(used[i]);
      if (p[0] == q[0] && p[1] == q[1] && p[2] == q[2]) {
        rep[used[i]] = rep[used[i - 1]];
        ++nb_welded_;
      }
    }
  }

  // ---- 3. Repeated vertices, zero area.
  constexpr std::uint8_t kRepeated = 1, kWelded = 2, kFlat = 3;
  std::vector<std::uint8_t> defect(nt, 0);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, nt, 4096), [&](const auto& r) {
    for (std::uint32_t t = r.begin(); t != r.end(); ++t) {
      std::uint32_t* v = triangles_.data() + 3 * std::size_t{t};
      if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) {
        defect[t] = kRepeated;
        continue;
      }
      for (int k = 0; k < 3; ++k) v[k] = rep[v[k]];
      if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) {
        defect[t] = kWelded;
      } else if (collinear3d(vertex(v[0]), vertex(v[1]), vertex(v[2]))) {
        defect[t] = kFlat;
      }
    }
  });
  for (std::uint32_t t = 0; t < nt; ++t) {
    if (defect[t] == 0) continue;
    const std::uint32_t* in = surface.triangles.data() + 3 * std::size_t{t};
    std::string given;
    for (int k = 0; k < 3; ++k) {
      given += (k ? " " : "") + std::to_string(std::uint64_t{in[k]} + vertex_base_);
    }
    if (defect[t] == kRepeated)
      throw Error(at(t) + " has a repeated vertex (vertices " + given + ")");
    if (defect[t] == kWelded) {
      int a = 0, b = 1;
      if (rep[in[0]] != rep[in[1]]) {
        a = rep[in[1]] == rep[in[2]] ? 1 : 0;
        b = 2;
      }
      throw Error(at(t) +
                  " has two corners at one point: " + vertex_name(in[static_cast<std::size_t>(a)]) +
                  " and " + vertex_name(in[static_cast<std::size_t>(b)]) +
                  " have the same coordinates " + point(vertex(in[static_cast<std::size_t>(a)])));
    }
    throw Error(at(t) + " has zero area: its corners (vertices " + given +
                ") are collinear (exact)");
  }

  // ---- 4. Duplicate triangles.
  {
    std::vector<std::pair<std::array<std::uint32_t, 3>, std::uint32_t>> keys(nt);
    for (std::uint32_t t = 0; t < nt; ++t) {
      std::uint32_t a = triangle_vertex(t, 0), b = triangle_vertex(t, 1), c = triangle_vertex(t, 2);
      detail::sort3(a, b, c);
      keys[t] = {{a, b, c}, t};
    }
    std::sort(keys.begin(), keys.end());
    FirstError error;
    for (std::size_t i = 1; i < keys.size(); ++i) {
      if (keys[i].first != keys[i - 1].first) continue;
      const std::uint32_t t0 = keys[i - 1].second, t1 = keys[i].second;
      if (error.wants(t0)) {
        error.set(t0, at(t0) + " and " + triangle_name(t1) +
                          " are duplicates: both have the vertices " + corners(t0));
      }
    }
    error.raise();
  }
  build(options);
}

void Surface3::build(const Surface3Options& options) {
  const std::uint32_t nv = nb_vertices();
  const std::uint32_t nt = nb_triangles();
  const auto edge_text = [&](std::uint32_t a, std::uint32_t b) {
    return "(vertices " + vertex_number(a) + " " + vertex_number(b) + ")";
  };

  // ---- 5. Edges: edge e of t runs from corner e + 1 to corner e + 2.
  adjacent_.assign(3 * std::size_t{nt}, kNone);
  {
    std::vector<Keyed> keys(3 * std::size_t{nt});
    std::vector<std::uint32_t> bucket(keys.size());
    for (std::uint32_t t = 0; t < nt; ++t) {
      for (int e = 0; e < 3; ++e) {
        const std::uint32_t u = triangle_vertex(t, (e + 1) % 3);
        const std::uint32_t w = triangle_vertex(t, (e + 2) % 3);
        const std::size_t i = 3 * std::size_t{t} + static_cast<std::size_t>(e);
        keys[i] = {std::max(u, w), 0, static_cast<std::uint32_t>(i), u < w ? 0u : 1u};
        bucket[i] = std::min(u, w);
      }
    }
    const std::vector<std::uint32_t> begin = detail::bucket_sort(keys, bucket, nv);
    FirstError error;
    for (std::uint32_t a = 0; a < nv; ++a) {
      for (std::uint32_t i = begin[a]; i < begin[a + 1];) {
        std::uint32_t j = i + 1;
        while (j < begin[a + 1] && keys[j].hi0 == keys[i].hi0) ++j;
        const std::uint32_t t0 = keys[i].code / 3;
        if (j - i == 2 && keys[i].parity != keys[i + 1].parity) {
          adjacent_[keys[i].code] = keys[i + 1].code / 3;
          adjacent_[keys[i + 1].code] = t0;
        } else if (!error.wants(t0)) {
        } else if (j - i == 1) {
          error.set(t0, at(t0) + ": the surface is not closed: its edge " +
                            edge_text(a, keys[i].hi0) + " belongs to no other triangle");
        } else if (j - i == 2) {
          error.set(t0, at(t0) + " and " + triangle_name(keys[i + 1].code / 3) +
                            " run through their common edge " + edge_text(a, keys[i].hi0) +
                            " in the same direction: the surface is not consistently oriented");
        } else {
          std::string list;
          for (std::uint32_t k = i; k < j; ++k) {
            list += (k == i ? "" : k + 1 == j ? " and " : ", ") + triangle_name(keys[k].code / 3);
          }
          error.set(t0, at(t0) + ": the surface is not a 2-manifold: the edge " +
                            edge_text(a, keys[i].hi0) + " is in " + std::to_string(j - i) +
                            " triangles (2 expected): " + list);
        }
        i = j;
      }
    }
    error.raise();
  }

  // ---- 6. One fan of triangles around each vertex.
  {
    std::vector<std::uint8_t> visited(3 * std::size_t{nt}, 0);
    std::vector<std::uint32_t> nb_corners(nv, 0), first_fan(nv, kNone);
    for (const std::uint32_t v : triangles_) ++nb_corners[v];
    FirstError error;
    for (std::uint32_t t = 0; t < nt; ++t) {
      for (int k = 0; k < 3; ++k) {
        if (visited[3 * std::size_t{t} + static_cast<std::size_t>(k)]) continue;
        const std::uint32_t v = triangle_vertex(t, k);
        if (first_fan[v] == kNone) {
          first_fan[v] = t;
        } else if (error.wants(v)) {
          error.set(v, source_ + ": the surface is not a 2-manifold at " + vertex_name(v) + " " +
                           point(vertex(v)) +
                           " (a pinched vertex): its triangles form several "
                           "fans, one with " +
                           triangle_name(first_fan[v]) + ", another with " + triangle_name(t));
        }
        // Walk around v: across the edge opposite the next corner, which holds v.
        std::uint32_t cur = t;
        int loc = k;
        for (std::uint32_t steps = 0;; ++steps) {
          visited[3 * std::size_t{cur} + static_cast<std::size_t>(loc)] = 1;
          cur = adjacent(cur, (loc + 1) % 3);
          loc = triangle_vertex(cur, 0) == v ? 0 : triangle_vertex(cur, 1) == v ? 1 : 2;
          if (cur == t) break;
          if (steps > nb_corners[v]) {
            throw Error(source_ + ": internal error: the fan around " + vertex_name(v) +
                        " does not close");
          }
        }
      }
    }
    error.raise();
  }

  // ---- 7. Self-intersections.
  {
    const detail::TrianglePair pair = detail::first_intersecting_pair(xyz_, triangles_);
    if (pair.found()) {
      throw Error(at(pair.a) + " and " + triangle_name(pair.b) +
                  " intersect (they meet other than at a shared edge or vertex)");
    }
  }

  // ---- 8. Shells, depth first; counts, area, volume.
  order_.clear();
  order_.reserve(nt);
  shell_of_.assign(nt, kNone);
  shells_.clear();
  bool any_vertex = false;
  {
    std::vector<std::uint32_t> stack;
    std::vector<std::uint32_t> vertex_shell(nv, kNone);
    for (std::uint32_t t0 = 0; t0 < nt; ++t0) {
      if (shell_of_[t0] != kNone) continue;
      const auto s = static_cast<std::uint32_t>(shells_.size());
      Shell shell;
      shell.first_triangle = t0;
      const std::size_t first = order_.size();
      shell_of_[t0] = s;
      stack.assign(1, t0);
      while (!stack.empty()) {
        const std::uint32_t t = stack.back();
        stack.pop_back();
        order_.push_back(t);
        for (int k = 0; k < 3; ++k) {
          const std::uint32_t v = triangle_vertex(t, k);
          if (vertex_shell[v] != s) {
            vertex_shell[v] = s;
            ++shell.nb_vertices;
          }
          const std::uint32_t t2 = adjacent(t, k);
          if (shell_of_[t2] == kNone) {
            shell_of_[t2] = s;
            stack.push_back(t2);
          }
        }
      }
      shell.nb_triangles = static_cast<std::uint32_t>(order_.size() - first);
      shell.nb_edges = 3 * shell.nb_triangles / 2;
      const std::int64_t chi =
          std::int64_t{shell.nb_vertices} - shell.nb_edges + shell.nb_triangles;
      shell.genus = static_cast<std::uint32_t>((2 - chi) / 2);
      // Area and volume, in order: cones from the first vertex.
      const double* o = vertex(triangle_vertex(t0, 0));
      detail::CompensatedSum area, volume;
      for (std::size_t q = first; q < order_.size(); ++q) {
        const std::uint32_t* v = triangle(order_[q]);
        double d[3][3];
        for (int k = 0; k < 3; ++k) {
          for (int c = 0; c < 3; ++c) d[k][c] = vertex(v[k])[c] - o[c];
        }
        const double u[3] = {d[1][0] - d[0][0], d[1][1] - d[0][1], d[1][2] - d[0][2]};
        const double w[3] = {d[2][0] - d[0][0], d[2][1] - d[0][1], d[2][2] - d[0][2]};
        const double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                             u[0] * w[1] - u[1] * w[0]};
        area.add(0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]));
        const double det = d[0][0] * (d[1][1] * d[2][2] - d[1][2] * d[2][1]) -
                           d[0][1] * (d[1][0] * d[2][2] - d[1][2] * d[2][0]) +
                           d[0][2] * (d[1][0] * d[2][1] - d[1][1] * d[2][0]);
        volume.add(det / 6);
      }
      shell.area = area.value();
      shell.volume = volume.value();
      shells_.push_back(shell);
    }
    for (std::uint32_t v = 0; v < nv; ++v) {
      if (vertex_shell[v] == kNone) continue;
      const double* p = vertex(v);
      for (int k = 0; k < 3; ++k) {
        bbox_[k] = any_vertex ? std::min(bbox_[k], p[k]) : p[k];
        bbox_[k + 3] = any_vertex ? std::max(bbox_[k + 3], p[k]) : p[k];
      }
      any_vertex = true;
    }
  }
  const auto nb_shells = static_cast<std::uint32_t>(shells_.size());

  // ---- 9. Orientation and nesting.
  std::vector<std::vector<std::uint32_t>> shell_triangles(nb_shells);
  for (std::uint32_t t = 0; t < nt; ++t) {
    std::vector<std::uint32_t>& list = shell_triangles[shell_of_[t]];
    list.insert(list.end(), triangle(t), triangle(t) + 3);
  }
  std::vector<Sign> facing(nb_shells);
  std::vector<std::array<double, 6>> box(nb_shells);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, nb_shells, 1), [&](const auto& r) {
    for (std::uint32_t s = r.begin(); s != r.end(); ++s) {
      const std::vector<std::uint32_t>& list = shell_triangles[s];
      facing[s] = surface_volume_sign(xyz_.data(), list.data(), list.size() / 3);
      std::array<double, 6>& b = box[s];
      for (int c = 0; c < 3; ++c)
        b[static_cast<std::size_t>(c)] = b[3 + std::size_t(c)] = vertex(list[0])[c];
      for (const std::uint32_t v : list) {
        for (int c = 0; c < 3; ++c) {
          b[static_cast<std::size_t>(c)] = std::min(b[static_cast<std::size_t>(c)], vertex(v)[c]);
          b[3 + std::size_t(c)] = std::max(b[3 + std::size_t(c)], vertex(v)[c]);
        }
      }
    }
  });
  for (std::uint32_t s = 0; s < nb_shells; ++s) {
    if (facing[s] == Sign::zero) {
      throw Error(at(shells_[s].first_triangle) +
                  ": internal error: a closed shell without self-intersections encloses no "
                  "volume");
    }
  }
  // enclosing[s]: the shells that enclose s.
  std::vector<std::vector<std::uint32_t>> enclosing(nb_shells);
  if (nb_shells > 1) {
    std::vector<std::unique_ptr<detail::SurfaceLocator>> locators(nb_shells);
    for (std::uint32_t r = 0; r < nb_shells; ++r) {
      for (std::uint32_t s = 0; s < nb_shells; ++s) {
        if (s == r) continue;
        const std::array<double, 6>& bs = box[s];
        const std::array<double, 6>& br = box[r];
        bool within = true;
        for (std::size_t c = 0; c < 3; ++c)
          within = within && br[c] <= bs[c] && bs[3 + c] <= br[3 + c];
        if (!within) continue;
        if (!locators[r]) {
          locators[r] = std::make_unique<detail::SurfaceLocator>(xyz_, shell_triangles[r]);
        }
        const Sign side = locators[r]->locate(vertex(shell_triangles[s][0]));
        if (side == Sign::zero) {
          throw Error(source_ + ": internal error: a vertex of shell " + std::to_string(s) +
                      " lies on shell " + std::to_string(r) + ", which it does not intersect");
        }
        if (side == Sign::positive) enclosing[s].push_back(r);
      }
    }
  }
  for (std::uint32_t s = 0; s < nb_shells; ++s) {
    Shell& shell = shells_[s];
    shell.depth = static_cast<std::uint32_t>(enclosing[s].size());
    for (const std::uint32_t r : enclosing[s]) {
      if (enclosing[r].size() + 1 == enclosing[s].size()) shell.parent = r;
    }
  }
  for (std::uint32_t s = 0; s < nb_shells; ++s) {
    Shell& shell = shells_[s];
    const bool outward = facing[s] == Sign::positive;
    if (outward != !shell.cavity()) {
      if (options.reorient) {
        shell.reoriented = true;
        for (std::uint32_t t = 0; t < nt; ++t) {
          if (shell_of_[t] != s) continue;
          std::swap(triangles_[3 * std::size_t{t} + 1], triangles_[3 * std::size_t{t} + 2]);
          std::swap(adjacent_[3 * std::size_t{t} + 1], adjacent_[3 * std::size_t{t} + 2]);
        }
        shell.volume = -shell.volume;
        continue;
      }
      const std::string what = "shell " + std::to_string(s) + " (" +
                               std::to_string(shell.nb_triangles) + " triangles, the first " +
                               triangle_name(shell.first_triangle) + ")";
      if (shell.depth == 0) {
        throw Error(source_ + ": the surface is inside out: " + what +
                    " faces inward (its triangles' right-hand normals point into the volume it "
                    "bounds); reverse the order of its faces' corners, or let voroclip reorient "
                    "it (Surface3Options::reorient, --reorient)");
      }
      throw Error(source_ + ": " + what + " lies inside " + std::to_string(shell.depth) +
                  (shell.depth == 1 ? " shell" : " shells") + " (the innermost is shell " +
                  std::to_string(shell.parent) + ") and faces " +
                  (outward ? "outward; as the wall of a cavity it must face into the cavity"
                           : "inward; as the outer wall of a part inside a cavity it must "
                             "face outward") +
                  " (reverse the order of its faces' corners, or let voroclip reorient it: "
                  "Surface3Options::reorient, --reorient)");
    }
  }
  area_ = volume_ = 0;
  detail::CompensatedSum area, volume;
  for (const Shell& shell : shells_) {
    area.add(shell.area);
    volume.add(shell.volume);
  }
  area_ = area.value();
  volume_ = volume.value();
  // Coordinates whose area or volume double cannot hold (beyond about 1e77 the area's
  // squares overflow, below about 1e-100 the volume underflows): every integral over the
  // domain would be inf, NaN or 0, and the cells' volumes with them.
  if (nt > 0 && !(std::isfinite(area_) && std::isnormal(volume_))) {
    double largest = 0;
    for (const double c : xyz_) largest = std::max(largest, std::abs(c));
    const bool large = !std::isfinite(area_) || !std::isfinite(volume_);
    throw Error(source_ + ": its " +
                (large ? std::string(std::isfinite(volume_) ? "area is " : "area and volume are ") +
                             "not finite in double precision"
                       : "volume is " + detail::number(volume_) + " in double precision") +
                " (coordinates up to " + detail::number(largest) + ": too " +
                (large ? "large, it overflows" : "small, it underflows") +
                "); rescale the model (e.g. to a size of about 1)");
  }

  // ---- 10. The locator.
  locator_.reset();
  if (nt > 0) locator_ = std::make_shared<const detail::SurfaceLocator>(xyz_, triangles_);
}

Sign Surface3::locate(const double* p) const {
  if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
    throw Error("locate: the point " + point(p) + " has a non-finite coordinate");
  }
  if (!locator_) return Sign::negative;
  return locator_->locate(p);
}

Sign Surface3::locate_circumcenter(const double* p0, const double* p1, const double* p2,
                                   const double* p3) const {
  if (!locator_) {
    if (orient3d(p0, p1, p2, p3) == Sign::zero) {
      throw Error(
          "locate_circumcenter: the four points are coplanar: their circumcenter is not "
          "defined");
    }
    return Sign::negative;
  }
  return locator_->locate_circumcenter(p0, p1, p2, p3);
}

}  // namespace voroclip
