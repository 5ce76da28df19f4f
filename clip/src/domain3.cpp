// Domain3: a tetrahedral mesh validated exactly, with tet and boundary adjacency (the
// contract is the comment on Domain3 in clip.h).
//
// Passes, in this order; each reports its first defect in a fixed order (the smallest
// index it concerns), so that the message does not depend on the thread count:
//  1. Vertex indices in range; finite coordinates of the used vertices; bounding box.
//  2. Per tet (parallel, one slot per tet): a repeated vertex; the exact sign of
//     orient3d(p0, p1, p2, p3): zero is an error, negative is fixed by swapping local
//     vertices 2 and 3. Volumes |det| / 6 in floating point, summed in tet order with
//     Neumaier's compensated summation.
//  3. Duplicate vertices: the used vertices sorted by coordinates, neighbours compared.
//  4. Facets. Facet f of t is keyed by its sorted vertex triple (a < b < c); the keys are
//     bucketed by a (a counting sort, stable in facet order 4t + f), then each bucket is
//     sorted by (b, c, 4t + f) in parallel: O(n) plus tiny sorts, and the order is unique,
//     so the result does not depend on the thread count. A key met once is a boundary
//     triangle, twice an interior facet, more often an error. Both tets of an interior
//     facet are positive after pass 2, and each lists the facet so that its own fourth
//     vertex is on the negative side (kTetFacetVertex); so they lie on opposite sides of
//     the facet (orient3d of the facet as t lists it and the fourth vertex of t' > 0)
//     exactly when they list the facet with opposite orientations, i.e. when the
//     permutations that sort the two listed triples have different parities. That parity
//     test is the exact orient3d test, at no cost.
//  5. The boundary triangles, reversed (outward), become the Surface3: its passes check
//     the edges (each in exactly two boundary triangles, opposite directions: the tets
//     meet along an edge only otherwise), the fans (tets meeting at a vertex only give
//     two), the intersections between boundary triangles, the shells and their nesting.
//
// Not detected: tets that intersect without sharing a facet and without their boundary
// triangles meeting (a mesh that winds twice around an edge and closes up).
#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "validation.h"
#include "voroclip/clip.h"

namespace voroclip {

namespace {

using detail::FirstError;
using detail::Keyed;
using detail::point;
using detail::sort3;

// Names what a message is about as the file does (TetMeshInput's tet_noun, tet_label,
// vertex_label / vertex_base, numbering): "tetrahedron 6 (line 40)" in a Medit file, "tet
// 5" from 0 for a mesh built in code; numbering() is the note that says which.
struct Namer {
  const TetMeshInput& mesh;
  std::string source;

  std::uint32_t line(std::uint32_t t) const {
    return t < mesh.tet_line.size() ? mesh.tet_line[t] : 0u;
  }
  // "tetrahedron 6", "element 12", "tet 5".
  std::string tet_number(std::uint32_t t) const {
    return (mesh.tet_noun.empty() ? std::string("tet") : mesh.tet_noun) + " " +
           std::to_string(t < mesh.tet_label.size() ? mesh.tet_label[t] : std::uint64_t{t});
  }
  // "tet 5 (line 40)", or "tet 5" when the line is not known.
  std::string tet(std::uint32_t t) const {
    const std::uint32_t l = line(t);
    return tet_number(t) + (l != 0 ? " (line " + std::to_string(l) + ")" : "");
  }
  // "source:40: tet 5", the start of a message about tet t.
  std::string at(std::uint32_t t) const {
    const std::uint32_t l = line(t);
    return source + (l != 0 ? ":" + std::to_string(l) : "") + ": " + tet_number(t);
  }
  std::string vertex(std::uint32_t v) const {
    return std::to_string(v < mesh.vertex_label.size() ? mesh.vertex_label[v]
                                                       : mesh.vertex_base + v);
  }
  // "1 2 3 4": the vertices of tet t as the file numbers them.
  std::string vertices(std::uint32_t t) const {
    std::string s;
    for (std::size_t k = 0; k < 4; ++k) {
      s += (k ? " " : "") + vertex(mesh.tets[4 * static_cast<std::size_t>(t) + k]);
    }
    return s;
  }
  // "Medit numbering, from 1": how the numbers above count.
  std::string numbering() const {
    return mesh.numbering.empty() ? std::string("numbered from 0") : mesh.numbering;
  }
};

}  // namespace

Domain3::Domain3(const TriangleSurface& surface, const Surface3Options& options)
    : surface_(surface, options) {}

Domain3::Domain3(Surface3 surface) : surface_(std::move(surface)) {}

Domain3::Domain3(const TetMeshInput& mesh) {
  const Namer name{mesh, mesh.source.empty() ? std::string("tetrahedral mesh") : mesh.source};
  if (mesh.xyz.size() % 3 != 0 || mesh.tets.size() % 4 != 0) {
    throw Error(name.source + ": the mesh arrays hold " + std::to_string(mesh.xyz.size()) +
                " coordinates and " + std::to_string(mesh.tets.size()) +
                " tet vertex indices (multiples of 3 and 4 expected)");
  }
  const std::uint32_t nv = mesh.nb_vertices();
  const std::uint32_t nt = mesh.nb_tets();
  if (mesh.tets.size() / 4 >= (std::size_t{1} << 30)) {
    throw Error(name.source + ": more than 2^30 tets");
  }
  Surface3& surface = surface_;
  surface.source_ = name.source;
  surface.xyz_ = mesh.xyz;
  tets_ = mesh.tets;
  const auto vertex = [&](std::uint32_t v) { return surface.vertex(v); };

  // ---- 1. Indices, finite coordinates, bounding box.
  std::vector<std::uint32_t> first_tet(nv, kNone);  // the first tet using each vertex
  for (std::uint32_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 4; ++k) {
      const std::uint32_t v = tet_vertex(t, k);
      if (v >= nv) {
        throw Error(name.at(t) + ": vertex index " + std::to_string(v) +
                    " is out of range (the mesh has " + count_of(nv, "vertex", "vertices") +
                    "; tets and vertices " + name.numbering() + ")");
      }
      if (first_tet[v] == kNone) first_tet[v] = t;
    }
  }
  for (std::uint32_t v = 0; v < nv; ++v) {
    if (first_tet[v] == kNone) continue;
    const double* p = vertex(v);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      throw Error(name.at(first_tet[v]) + ": vertex " + name.vertex(v) +
                  " has a non-finite coordinate " + point(p) + " (" + name.numbering() + ")");
    }
  }

  // ---- 2. Repeated vertices, exact orientation, volumes.
  constexpr std::int8_t kRepeated = 2;
  std::vector<std::int8_t> sign(nt);
  std::vector<double> tet_volume(nt);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, nt, 4096), [&](const auto& r) {
    for (std::uint32_t t = r.begin(); t != r.end(); ++t) {
      const std::uint32_t* v = tets_.data() + 4 * static_cast<std::size_t>(t);
      if (v[0] == v[1] || v[0] == v[2] || v[0] == v[3] || v[1] == v[2] || v[1] == v[3] ||
          v[2] == v[3]) {
        sign[t] = kRepeated;
        continue;
      }
      const double *p0 = vertex(v[0]), *p1 = vertex(v[1]), *p2 = vertex(v[2]), *p3 = vertex(v[3]);
      sign[t] = static_cast<std::int8_t>(orient3d(p0, p1, p2, p3));
      const double a[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
      const double b[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
      const double c[3] = {p3[0] - p0[0], p3[1] - p0[1], p3[2] - p0[2]};
      const double det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                         a[2] * (b[0] * c[1] - b[1] * c[0]);
      tet_volume[t] = std::fabs(det) / 6;
    }
  });
  for (std::uint32_t t = 0; t < nt; ++t) {
    if (sign[t] == kRepeated) {
      throw Error(name.at(t) + " has a repeated vertex (vertices " + name.vertices(t) + "; " +
                  name.numbering() + ")");
    }
    if (sign[t] == 0) {
      throw Error(name.at(t) + " has zero volume: its vertices " + name.vertices(t) +
                  " are coplanar (exact orient3d; " + name.numbering() + ")");
    }
    if (sign[t] < 0) std::swap(tets_[4 * static_cast<std::size_t>(t) + 2], tets_[4 * t + 3]);
  }
  tet_volume_ = detail::compensated_sum(tet_volume);

  // ---- 3. Duplicate vertices among the used ones.
  {
    std::vector<std::uint32_t> used;
    used.reserve(nv);
    for (std::uint32_t v = 0; v < nv; ++v) {
      if (first_tet[v] != kNone) used.push_back(v);
    }
    const auto less = [&](std::uint32_t u, std::uint32_t v) {
      const double *p = vertex(u), *q = vertex(v);
      if (p[0] != q[0]) return p[0] < q[0];
      if (p[1] != q[1]) return p[1] < q[1];
      if (p[2] != q[2]) return p[2] < q[2];
      return u < v;
    };
    std::sort(used.begin(), used.end(), less);
    FirstError error;
    for (std::size_t i = 1; i < used.size(); ++i) {
      const std::uint32_t u = used[i - 1], v = used[i];
      const double *p = vertex(u), *q = vertex(v);
      if (p[0] == q[0] && p[1] == q[1] && p[2] == q[2] && error.wants(u)) {
        error.set(u, name.source + ": vertices " + name.vertex(u) + " and " + name.vertex(v) +
                         " have the same coordinates " + point(p) +
                         " (duplicate vertices), used by " + name.tet(first_tet[u]) + " and " +
                         name.tet(first_tet[v]) + " (" + name.numbering() + ")");
      }
    }
    error.raise();
  }

  // ---- 4. Facets: adjacency, boundary triangles.
  tet_adjacent_.assign(4 * static_cast<std::size_t>(nt), kNone);
  std::vector<std::uint32_t> boundary_codes;  // 4t + f of the boundary facets
  {
    std::vector<Keyed> keys(4 * static_cast<std::size_t>(nt));
    std::vector<std::uint32_t> bucket(keys.size());
    for (std::uint32_t t = 0; t < nt; ++t) {
      for (int f = 0; f < 4; ++f) {
        std::uint32_t a = tet_vertex(t, kTetFacetVertex[f][0]);
        std::uint32_t b = tet_vertex(t, kTetFacetVertex[f][1]);
        std::uint32_t c = tet_vertex(t, kTetFacetVertex[f][2]);
        const std::uint32_t parity = sort3(a, b, c);
        const std::size_t i = 4 * static_cast<std::size_t>(t) + static_cast<std::size_t>(f);
        keys[i] = {b, c, static_cast<std::uint32_t>(i), parity};
        bucket[i] = a;
      }
    }
    const std::vector<std::uint32_t> begin = bucket_sort(keys, bucket, nv);
    FirstError error;
    for (std::uint32_t a = 0; a < nv; ++a) {
      for (std::uint32_t i = begin[a]; i < begin[a + 1];) {
        std::uint32_t j = i + 1;
        while (j < begin[a + 1] && keys[j].hi0 == keys[i].hi0 && keys[j].hi1 == keys[i].hi1) ++j;
        const std::uint32_t t0 = keys[i].code / 4;
        const auto facet = [&] {
          return "(vertices " + name.vertex(a) + " " + name.vertex(keys[i].hi0) + " " +
                 name.vertex(keys[i].hi1) + "; " + name.numbering() + ")";
        };
        if (j - i == 1) {
          boundary_codes.push_back(keys[i].code);
        } else if (j - i == 2) {
          const std::uint32_t t1 = keys[i + 1].code / 4;
          if (keys[i].parity == keys[i + 1].parity) {
            if (error.wants(t0)) {
              error.set(t0, name.at(t0) + " and " + name.tet(t1) +
                                " overlap: both lie on the same side of their shared facet " +
                                facet());
            }
          } else {
            tet_adjacent_[keys[i].code] = t1;
            tet_adjacent_[keys[i + 1].code] = t0;
          }
        } else if (error.wants(t0)) {
          std::string tets;
          for (std::uint32_t k = i; k < j; ++k) {
            tets += (k == i ? "" : k + 1 == j ? " and " : ", ") + name.tet(keys[k].code / 4);
          }
          error.set(t0, name.at(t0) + ": the facet " + facet() + " is shared by " +
                            std::to_string(j - i) + " tets (at most 2): " + tets);
        }
        i = j;
      }
    }
    error.raise();
  }
  std::sort(boundary_codes.begin(), boundary_codes.end());
  const auto nb = static_cast<std::uint32_t>(boundary_codes.size());
  boundary_tet_.resize(nb);
  boundary_facet_.resize(nb);
  surface.triangles_.resize(3 * static_cast<std::size_t>(nb));
  surface.triangle_face_.resize(nb);
  surface.triangle_line_.resize(nb);
  tet_boundary_begin_.assign(static_cast<std::size_t>(nt) + 1, 0);
  for (std::uint32_t b = 0; b < nb; ++b) {
    const std::uint32_t t = boundary_codes[b] / 4;
    const int f = static_cast<int>(boundary_codes[b] % 4);
    boundary_tet_[b] = t;
    boundary_facet_[b] = static_cast<std::int8_t>(f);
    // Reversed: the facet as the tet lists it is clockwise seen from outside.
    for (int k = 0; k < 3; ++k) {
      surface.triangles_[3 * static_cast<std::size_t>(b) + static_cast<std::size_t>(k)] =
          tet_vertex(t, kTetFacetVertex[f][k == 0 ? 0 : 3 - k]);
    }
    surface.triangle_face_[b] = t;
    surface.triangle_line_[b] = name.line(t);
    ++tet_boundary_begin_[t + 1];
  }
  for (std::size_t t = 0; t < nt; ++t) tet_boundary_begin_[t + 1] += tet_boundary_begin_[t];
  surface.naming_ = Surface3::Naming::kTetFacet;
  surface.tet_noun_ = mesh.tet_noun.empty() ? std::string("tet") : mesh.tet_noun;
  surface.tet_label_ = mesh.tet_label;
  surface.vertex_label_ = mesh.vertex_label;
  surface.vertex_base_ = static_cast<std::uint32_t>(mesh.vertex_base);  // 0 or 1
  surface.build(Surface3Options{});

  source_tet_.resize(nt);
  for (std::uint32_t t = 0; t < nt; ++t) source_tet_[t] = t;

  // ---- Tags: the tets' region tags as given; each boundary triangle takes the tag of the
  // input triangle with its three vertices (the first one listed), 0 when none is listed.
  if (!mesh.tet_ref.empty() && mesh.tet_ref.size() != nt) {
    throw Error(name.source + ": " + count_of(mesh.tet_ref.size(), "tet tag") + " for " +
                count_of(nt, "tet"));
  }
  tet_ref_ = mesh.tet_ref;
  tag_names_ = mesh.tag_names;
  higher_order_[0] = mesh.nb_higher_order_tets;
  higher_order_[1] = mesh.nb_higher_order_triangles;
  const std::uint32_t ntri = mesh.nb_triangles();
  if (!mesh.triangle_ref.empty() && mesh.triangle_ref.size() != ntri) {
    throw Error(name.source + ": " + count_of(mesh.triangle_ref.size(), "triangle tag") + " for " +
                count_of(ntri, "triangle"));
  }
  bool any_tag = false;
  for (const std::int32_t r : mesh.triangle_ref) any_tag = any_tag || r != 0;
  if (any_tag) {
    using Key = std::array<std::uint32_t, 3>;
    const auto key_of = [](const std::uint32_t* v) {
      Key k = {v[0], v[1], v[2]};
      std::sort(k.begin(), k.end());
      return k;
    };
    std::vector<std::pair<Key, std::uint32_t>> listed(ntri);
    for (std::uint32_t i = 0; i < ntri; ++i) {
      listed[i] = {key_of(mesh.triangles.data() + 3 * std::size_t{i}), i};
    }
    std::sort(listed.begin(), listed.end());
    boundary_ref_.assign(nb, 0);
    std::vector<std::uint8_t> on_surface(ntri, 0);
    for (std::uint32_t b = 0; b < nb; ++b) {
      const Key k = key_of(surface.triangle(b));
      auto it = std::lower_bound(listed.begin(), listed.end(), std::make_pair(k, 0u));
      if (it != listed.end() && it->first == k) boundary_ref_[b] = mesh.triangle_ref[it->second];
      for (; it != listed.end() && it->first == k; ++it) on_surface[it->second] = 1;
    }
    // No surface triangle tagged: none (the boundary's patches are then the mesher's own).
    if (std::all_of(boundary_ref_.begin(), boundary_ref_.end(),
                    [](std::int32_t r) { return r == 0; }))
      boundary_ref_.clear();
    // The rest, tagged: faces inside the volume (interfaces), or no face at all.
    for (const auto& [k, i] : listed) {
      if (on_surface[i] == 0 && mesh.triangle_ref[i] != 0)
        inner_ref_.emplace_back(k, mesh.triangle_ref[i]);
    }
  }
}

std::int32_t Domain3::inner_triangle_ref(std::uint32_t a, std::uint32_t b, std::uint32_t c) const {
  std::array<std::uint32_t, 3> k = {a, b, c};
  std::sort(k.begin(), k.end());
  const auto it =
      std::lower_bound(inner_ref_.begin(), inner_ref_.end(), k,
                       [](const std::pair<std::array<std::uint32_t, 3>, std::int32_t>& e,
                          const std::array<std::uint32_t, 3>& key) { return e.first < key; });
  return it != inner_ref_.end() && it->first == k ? it->second : 0;
}

std::uint32_t Domain3::tet_boundary(std::uint32_t t, int f) const {
  assert(t < nb_tets() && f >= 0 && f < 4);
  for (std::uint32_t b = tet_boundary_begin_[t]; b < tet_boundary_begin_[t + 1]; ++b) {
    if (boundary_facet_[b] == f) return b;
  }
  return kNone;
}

Domain3 read_domain3(const std::string& path, const Surface3Options& options) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw Error(path + ": is a directory, not a file");
  const auto extension = [](const std::string& name) {
    const std::size_t dot = name.find_last_of('.');
    const std::size_t slash = name.find_last_of("/\\");
    std::string e = dot == std::string::npos || (slash != std::string::npos && dot < slash)
                        ? std::string()
                        : name.substr(dot);
    for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return e;
  };
  // NAME.EXT.gz is read as NAME.EXT (the readers inflate gzip data).
  std::string ext = extension(path);
  if (ext == ".gz") ext = extension(path.substr(0, path.size() - 3));
  if (ext == ".obj" || ext == ".off" || ext == ".stl" || ext == ".ply") {
    return Domain3(read_surface(path), options);
  }
  if (ext == ".mesh" || ext == ".node" || ext == ".ele" || ext == ".msh" || ext == ".vtk" ||
      ext == ".vtu") {
    return Domain3(read_tet_mesh(path));
  }
  throw Error(path + ": unknown 3D domain format '" + ext +
              "' (closed surfaces: .obj .off .stl .ply; tetrahedral meshes: .mesh .node .ele "
              ".msh .vtk .vtu)");
}

}  // namespace voroclip
