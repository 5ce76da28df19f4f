// Boundary triangles and tags of a 3D CVT mesh (mesh3d_tags.h).
#include "mesh3d_tags.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <iterator>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "mesh3d_pipeline.h"
#include "union_find.h"
#include "voroclip/predicates.h"

namespace voroclip::mesh3 {

namespace {

constexpr std::uint32_t kNone = 0xffffffffu;

}  // namespace

std::vector<FaceRef> sorted_faces(const std::vector<std::uint32_t>& tets) {
  const std::size_t nt = tets.size() / 4;
  std::vector<FaceRef> faces(4 * nt);
  for (std::size_t t = 0; t < nt; ++t) {
    for (int f = 0; f < 4; ++f) {
      FaceRef& r = faces[4 * t + static_cast<std::size_t>(f)];
      for (int k = 0; k < 3; ++k) {
        r.key[static_cast<std::size_t>(k)] =
            tets[4 * t + static_cast<std::size_t>(kOutwardFacet[f][k])];
      }
      std::sort(r.key.begin(), r.key.end());
      r.code = static_cast<std::uint32_t>(4 * t + static_cast<std::size_t>(f));
    }
  }
  std::sort(faces.begin(), faces.end());
  return faces;
}

namespace {

// The input tets on a uniform grid of their bounding boxes, for point location.
class TetGrid {
 public:
  explicit TetGrid(const Domain3& d) : d_(d) {
    const std::uint32_t nt = d.nb_tets();
    for (int k = 0; k < 3; ++k) {
      lo_[k] = d.bbox_lo()[k];
      const double extent = d.bbox_hi()[k] - lo_[k];
      size_[k] = extent > 0 ? extent : 1;
    }
    const double cells = std::max(1.0, std::cbrt(static_cast<double>(nt)));
    for (int k = 0; k < 3; ++k) n_[k] = static_cast<std::uint32_t>(std::min(cells, 256.0));
    begin_.assign(std::size_t{n_[0]} * n_[1] * n_[2] + 1, 0);
    // Two passes: counts, then the tets.
    for (int pass = 0; pass < 2; ++pass) {
      std::vector<std::uint32_t> fill;
      if (pass == 1) {
        for (std::size_t c = 0; c + 1 < begin_.size(); ++c) begin_[c + 1] += begin_[c];
        fill.assign(begin_.begin(), begin_.end() - 1);
        tets_.resize(begin_.back());
      }
      for (std::uint32_t t = 0; t < nt; ++t) {
        std::uint32_t a[3], b[3];
        for (int k = 0; k < 3; ++k) {
          double mn = d.vertex(d.tet_vertex(t, 0))[k], mx = mn;
          for (int q = 1; q < 4; ++q) {
            mn = std::min(mn, d.vertex(d.tet_vertex(t, q))[k]);
            mx = std::max(mx, d.vertex(d.tet_vertex(t, q))[k]);
          }
          a[k] = cell(mn, k);
          b[k] = cell(mx, k);
        }
        for (std::uint32_t z = a[2]; z <= b[2]; ++z) {
          for (std::uint32_t y = a[1]; y <= b[1]; ++y) {
            for (std::uint32_t x = a[0]; x <= b[0]; ++x) {
              const std::size_t c = (std::size_t{z} * n_[1] + y) * n_[0] + x;
              if (pass == 0) {
                ++begin_[c + 1];
              } else {
                tets_[fill[c]++] = t;
              }
            }
          }
        }
      }
    }
  }

  // The input tet that holds p (on its boundary included), the lowest such index; kNone
  // when none does.
  std::uint32_t locate(const double* p) const {
    const std::size_t c = bucket(p);
    for (std::uint32_t i = begin_[c]; i < begin_[c + 1]; ++i) {
      if (holds(tets_[i], p)) return tets_[i];
    }
    return kNone;
  }

  // Whether p lies in the input (on its boundary included) but in no input tet tagged `tag`
  // (closed tets: a point on an interface belongs to both sides).
  bool only_outside_tag(const double* p, std::int32_t tag) const {
    const std::vector<std::int32_t>& refs = d_.tet_refs();
    const std::size_t c = bucket(p);
    bool in_domain = false;
    for (std::uint32_t i = begin_[c]; i < begin_[c + 1]; ++i) {
      const std::uint32_t t = tets_[i];
      if (in_domain && refs[t] != tag) continue;  // cannot change the answer
      if (!holds(t, p)) continue;
      if (refs[t] == tag) return false;
      in_domain = true;
    }
    return in_domain;
  }

 private:
  std::size_t bucket(const double* p) const {
    std::size_t c = 0;
    for (int k = 2; k >= 0; --k) c = c * n_[k] + cell(p[k], k);
    return c;
  }
  // Domain3's tets have orient3d(v0, v1, v2, v3) > 0: p is in tet t (closed) when replacing
  // any vertex by p keeps the sign non-negative.
  bool holds(std::uint32_t t, const double* p) const {
    const double* v[4];
    for (int q = 0; q < 4; ++q) v[q] = d_.vertex(d_.tet_vertex(t, q));
    for (int q = 0; q < 4; ++q) {
      const double* w[4] = {v[0], v[1], v[2], v[3]};
      w[q] = p;
      if (orient3d(w[0], w[1], w[2], w[3]) == Sign::negative) return false;
    }
    return true;
  }
  std::uint32_t cell(double x, int k) const {
    const double s = (x - lo_[k]) / size_[k] * n_[k];
    if (!(s > 0)) return 0;
    return std::min(static_cast<std::uint32_t>(s), n_[k] - 1);
  }
  const Domain3& d_;
  double lo_[3] = {0, 0, 0}, size_[3] = {1, 1, 1};
  std::uint32_t n_[3] = {1, 1, 1};
  std::vector<std::uint32_t> begin_, tets_;
};

// For votes (key, value) sorted: per key, the value with the most votes (ties to the lower
// value), given to take(key, value) in key order.
template <class Key, class Value, class Take>
void majority(const std::vector<std::pair<Key, Value>>& votes, const Take& take) {
  for (std::size_t i = 0; i < votes.size();) {
    std::size_t best_count = 0, j = i;
    Value best{};
    while (j < votes.size() && votes[j].first == votes[i].first) {
      std::size_t k = j;
      while (k < votes.size() && votes[k] == votes[j]) ++k;
      if (k - j > best_count) {
        best_count = k - j;
        best = votes[j].second;
      }
      j = k;
    }
    take(votes[i].first, best);
    i = j;
  }
}

}  // namespace

void boundary_triangles(const std::vector<std::uint32_t>& tets,
                        std::vector<std::uint32_t>& triangles,
                        std::vector<std::uint32_t>& face_tet) {
  const std::vector<FaceRef> faces = sorted_faces(tets);
  std::vector<std::uint32_t> codes;
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i + 1;
    while (j < faces.size() && faces[j].key == faces[i].key) ++j;
    if (j - i == 1) codes.push_back(faces[i].code);
    i = j;
  }
  std::sort(codes.begin(), codes.end());
  triangles.clear();
  face_tet.clear();
  for (const std::uint32_t code : codes) {
    const std::size_t t = code / 4;
    const int f = static_cast<int>(code % 4);
    for (int k = 0; k < 3; ++k) {
      triangles.push_back(tets[4 * t + static_cast<std::size_t>(kOutwardFacet[f][k])]);
    }
    face_tet.push_back(static_cast<std::uint32_t>(t));
  }
}

std::vector<std::int32_t> patch_tags(const std::vector<std::uint32_t>& triangles,
                                     const std::vector<std::uint32_t>& vertex_patch_begin,
                                     const std::vector<std::uint32_t>& vertex_patch,
                                     const std::vector<std::int32_t>& patch_tag,
                                     const std::vector<std::uint32_t>& input_patch,
                                     const std::vector<std::uint32_t>& closest_input) {
  const std::size_t nb = triangles.size() / 3;
  std::vector<std::int32_t> tags(nb, 0);
  std::vector<std::uint32_t> common, next;
  for (std::size_t b = 0; b < nb; ++b) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = triangles[3 * b + static_cast<std::size_t>(k)];
      const auto first = vertex_patch.begin() + vertex_patch_begin[v];
      const auto last = vertex_patch.begin() + vertex_patch_begin[std::size_t{v} + 1];
      if (k == 0) {
        common.assign(first, last);
      } else {
        next.clear();
        std::set_intersection(common.begin(), common.end(), first, last, std::back_inserter(next));
        common.swap(next);
      }
    }
    const std::uint32_t patch = common.size() == 1 ? common[0] : input_patch[closest_input[b]];
    tags[b] = patch_tag[patch];
  }
  return tags;
}

std::vector<std::int32_t> region_tags(const Domain3& domain, const std::vector<double>& xyz,
                                      const std::vector<std::uint32_t>& tets,
                                      const std::vector<std::uint32_t>& face_tet,
                                      const std::vector<std::uint32_t>& closest_input,
                                      const std::vector<std::uint32_t>* regions,
                                      std::uint32_t& tets_across) {
  const auto nt = static_cast<std::uint32_t>(tets.size() / 4);
  std::vector<std::int32_t> tags(nt, 0);
  tets_across = 0;
  const std::vector<std::int32_t>& input = domain.tet_refs();
  const auto centroid = [&](std::uint32_t t, double* c) {
    c[0] = c[1] = c[2] = 0;
    for (int q = 0; q < 4; ++q) {
      for (int k = 0; k < 3; ++k)
        c[k] += 0.25 * xyz[3 * std::size_t{tets[4 * std::size_t{t} + static_cast<std::size_t>(q)]} +
                           static_cast<std::size_t>(k)];
    }
  };
  if (!input.empty()) {
    if (std::all_of(input.begin(), input.end(), [&](std::int32_t r) { return r == input[0]; })) {
      std::fill(tags.begin(), tags.end(), input[0]);
      return tags;
    }
    // The input tet holding each tet's centroid.
    const TetGrid grid(domain);
    std::vector<std::int32_t> located(nt, 0);
    std::vector<std::uint8_t> known(nt, 0);
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, nt, 1024), [&](const auto& range) {
      for (std::uint32_t t = range.begin(); t != range.end(); ++t) {
        double c[3];
        centroid(t, c);
        const std::uint32_t i = grid.locate(c);
        if (i != kNone) {
          located[t] = input[i];
          known[t] = 1;
        }
      }
    });
    if (regions != nullptr) {
      // A mesh that follows the interfaces: each region by its tets' votes.
      std::vector<std::pair<std::uint32_t, std::int32_t>> votes;  // (region, tag)
      for (std::uint32_t t = 0; t < nt; ++t) {
        if (known[t] != 0) votes.emplace_back((*regions)[t], located[t]);
      }
      std::sort(votes.begin(), votes.end());
      std::vector<std::int32_t> region_tag;
      majority(votes, [&](std::uint32_t region, std::int32_t tag) {
        if (region_tag.size() <= region) region_tag.resize(region + 1, input[0]);
        region_tag[region] = tag;
      });
      for (std::uint32_t t = 0; t < nt; ++t) {
        const std::uint32_t r = (*regions)[t];
        tags[t] = r < region_tag.size() ? region_tag[r] : input[0];
        tets_across += known[t] != 0 && located[t] != tags[t] ? 1 : 0;
      }
      return tags;
    }
    tags = located;
    // The rest from their neighbours, breadth first (in tet order within a wave).
    const std::vector<FaceRef> faces = sorted_faces(tets);
    std::vector<std::pair<std::uint32_t, std::uint32_t>> adjacent;  // (tet, tet) both ways
    for (std::size_t i = 0; i + 1 < faces.size(); ++i) {
      if (faces[i].key == faces[i + 1].key) {
        adjacent.emplace_back(faces[i].code / 4, faces[i + 1].code / 4);
        adjacent.emplace_back(faces[i + 1].code / 4, faces[i].code / 4);
      }
    }
    std::sort(adjacent.begin(), adjacent.end());
    for (bool changed = true; changed;) {
      changed = false;
      std::vector<std::pair<std::uint32_t, std::int32_t>> wave;
      for (const auto& [a, b] : adjacent) {
        if (known[a] == 0 && known[b] != 0) wave.emplace_back(a, tags[b]);
      }
      for (const auto& [t, tag] : wave) {
        if (known[t] != 0) continue;  // the first neighbour in (tet, tet) order decides
        tags[t] = tag;
        known[t] = 1;
        changed = true;
      }
    }
    // Tets with a vertex inside the input but in no input tet of their own region: they
    // reach across an interface between regions (the sites do not follow interfaces).
    std::vector<std::uint8_t> across(nt, 0);
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, nt, 1024), [&](const auto& range) {
      for (std::uint32_t t = range.begin(); t != range.end(); ++t) {
        for (int q = 0; q < 4 && across[t] == 0; ++q) {
          const std::uint32_t v = tets[4 * std::size_t{t} + static_cast<std::size_t>(q)];
          across[t] = grid.only_outside_tag(&xyz[3 * std::size_t{v}], tags[t]) ? 1 : 0;
        }
      }
    });
    tets_across = static_cast<std::uint32_t>(std::count(across.begin(), across.end(), 1));
    return tags;
  }
  // One region per volume component, numbered by its outer shell.
  const Surface3& s = domain.surface();
  std::vector<std::int32_t> outer_rank(s.shells().size(), 0);
  std::int32_t rank = 0;
  for (std::size_t h = 0; h < s.shells().size(); ++h) {
    if (!s.shells()[h].cavity()) outer_rank[h] = ++rank;
  }
  UnionFind components(nt);
  const std::vector<FaceRef> faces = sorted_faces(tets);
  for (std::size_t i = 0; i + 1 < faces.size(); ++i) {
    if (faces[i].key == faces[i + 1].key)
      components.unite(faces[i].code / 4, faces[i + 1].code / 4);
  }
  // Votes (component root, outer shell); the most votes win, ties to the lower shell.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> votes;
  for (std::size_t b = 0; b < face_tet.size(); ++b) {
    const std::uint32_t shell = s.shell_of(closest_input[b]);
    if (!s.shells()[shell].cavity()) votes.emplace_back(components.find(face_tet[b]), shell);
  }
  std::sort(votes.begin(), votes.end());
  std::vector<std::int32_t> root_tag(nt, 0);
  majority(votes,
           [&](std::uint32_t root, std::uint32_t shell) { root_tag[root] = outer_rank[shell]; });
  for (std::uint32_t t = 0; t < nt; ++t) tags[t] = root_tag[components.find(t)];
  return tags;
}

std::int32_t UntaggedTags::map(const std::vector<std::pair<std::int32_t, std::int32_t>>& pairs,
                               std::int32_t t) {
  for (const auto& [from, to] : pairs) {
    if (from == t) return to;
  }
  return t;
}

std::string UntaggedTags::name(int dimension, std::int32_t t) const {
  for (const auto& [from, to] : dimension == 2 ? patch : region) {
    if (to != t) continue;
    if (from == 0) return dimension == 2 ? "untagged boundary" : "untagged region";
    return (dimension == 2 ? "boundary tagged " : "region tagged ") + std::to_string(from);
  }
  return "";
}

namespace {

// Pairs (tag, fresh tag) for the tags of `tags` not above 0 (0, -1, -2, ...), the fresh
// tags the smallest positive ones not in `used`.
std::vector<std::pair<std::int32_t, std::int32_t>> fresh_tags(std::vector<std::int32_t> tags,
                                                              std::vector<std::int32_t> used) {
  std::vector<std::pair<std::int32_t, std::int32_t>> pairs;
  tags.erase(std::remove_if(tags.begin(), tags.end(), [](std::int32_t t) { return t > 0; }),
             tags.end());
  std::sort(tags.begin(), tags.end(), std::greater<>());
  tags.erase(std::unique(tags.begin(), tags.end()), tags.end());
  std::sort(used.begin(), used.end());
  std::int32_t next = 1;
  for (const std::int32_t t : tags) {
    while (std::binary_search(used.begin(), used.end(), next)) ++next;
    pairs.emplace_back(t, next++);
  }
  return pairs;
}

}  // namespace

UntaggedTags untagged_tags(const Domain3& domain) {
  UntaggedTags u;
  const std::vector<std::int32_t>& triangle_refs = domain.boundary_refs();
  const std::vector<std::int32_t>& tet_refs = domain.tet_refs();
  std::vector<std::int32_t> used_2, used_3;
  for (const TetMeshInput::TagName& n : domain.tag_names()) {
    if (n.dimension == 2) used_2.push_back(n.tag);
    if (n.dimension == 3) used_3.push_back(n.tag);
  }
  if (std::any_of(triangle_refs.begin(), triangle_refs.end(),
                  [](std::int32_t t) { return t <= 0; })) {
    used_2.insert(used_2.end(), triangle_refs.begin(), triangle_refs.end());
    // The file's tags of inner triangles (interfaces, embedded surfaces) are taken too.
    for (std::uint32_t t = 0; t < domain.nb_tets(); ++t) {
      for (int f = 0; f < 4; ++f) {
        const std::uint32_t n = domain.tet_adjacent(t, f);
        if (n == Domain3::kNone || n < t) continue;
        std::uint32_t v[3];
        for (int k = 0; k < 3; ++k) v[k] = domain.tet_vertex(t, Domain3::kTetFacetVertex[f][k]);
        const std::int32_t tag = domain.inner_triangle_ref(v[0], v[1], v[2]);
        if (tag != 0) used_2.push_back(tag);
      }
    }
    u.patch = fresh_tags(triangle_refs, std::move(used_2));
  }
  if (std::any_of(tet_refs.begin(), tet_refs.end(), [](std::int32_t t) { return t <= 0; })) {
    used_3.insert(used_3.end(), tet_refs.begin(), tet_refs.end());
    u.region = fresh_tags(tet_refs, std::move(used_3));
  }
  return u;
}

void tag_mesh3(const Domain3& domain, const SurfaceTree& surface_tree,
               const std::vector<std::uint32_t>& triangle_patch, const SurfacePatches& patches,
               const std::vector<std::uint32_t>& index, const TetRegions* regions,
               Mesh3Result& result) {
  std::vector<std::uint32_t> face_tet;
  boundary_triangles(result.tets, result.boundary_triangles, face_tet);
  const std::size_t nb = face_tet.size();
  std::vector<std::uint32_t> closest(nb);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nb, 256), [&](const auto& range) {
    for (std::size_t b = range.begin(); b != range.end(); ++b) {
      double c[3] = {0, 0, 0};
      for (int k = 0; k < 3; ++k) {
        const double* p =
            &result.xyz[3 * std::size_t{
                                result.boundary_triangles[3 * b + static_cast<std::size_t>(k)]}];
        for (int q = 0; q < 3; ++q) c[q] += p[q] / 3;
      }
      closest[b] = surface_tree.closest(c).triangle;
    }
  });
  std::vector<std::uint32_t> vertex_patch_begin{0}, vertex_patch;
  for (std::size_t s = 0; s < index.size(); ++s) {
    if (index[s] == SurfaceTree::kNone) continue;
    vertex_patch.insert(vertex_patch.end(), patches.patches.begin() + patches.begin[s],
                        patches.patches.begin() + patches.begin[std::size_t{s} + 1]);
    vertex_patch_begin.push_back(static_cast<std::uint32_t>(vertex_patch.size()));
  }
  const std::uint32_t nb_patches =
      triangle_patch.empty() ? 0
                             : 1 + *std::max_element(triangle_patch.begin(), triangle_patch.end());
  std::vector<std::int32_t> patch_tag(nb_patches, 0);
  for (std::uint32_t p = 0; p < nb_patches; ++p) patch_tag[p] = static_cast<std::int32_t>(p + 1);
  // The boundary's tags (its triangles come first in `triangle_patch`, in the domain's
  // order) when the file tags it; the interfaces' patches keep p + 1 (tag_interfaces tags
  // the interface triangles).
  const std::vector<std::int32_t>& input_tags = domain.boundary_refs();
  // Untagged (0) and negative tags become fresh positive ones (untagged_tags).
  const UntaggedTags untagged = untagged_tags(domain);
  for (std::size_t t = input_tags.size(); t-- > 0;)
    patch_tag[triangle_patch[t]] = UntaggedTags::map(untagged.patch, input_tags[t]);
  result.boundary_tags = patch_tags(result.boundary_triangles, vertex_patch_begin, vertex_patch,
                                    patch_tag, triangle_patch, closest);
  result.tet_tags =
      region_tags(domain, result.xyz, result.tets, face_tet, closest,
                  regions ? &regions->region : nullptr, result.nb_tets_across_regions);
  if (!untagged.region.empty()) {
    for (std::int32_t& t : result.tet_tags) t = UntaggedTags::map(untagged.region, t);
  }
  name_and_group_tags(domain, result);
}

void name_and_group_tags(const Domain3& domain, Mesh3Result& result) {
  result.embedded_tags_dropped = file_embedded_tags(domain);
  {
    std::vector<std::int32_t> refs = domain.tet_refs();
    std::sort(refs.begin(), refs.end());
    result.nb_input_regions =
        static_cast<std::uint32_t>(std::unique(refs.begin(), refs.end()) - refs.begin());
  }
  // The input's names, then one for each tag used without a name: "patch <tag>" on the
  // boundary, "region <tag>" for the tets (as mesh2d names its "boundary" and "region"
  // groups), so that a Gmsh file's physical groups all carry a name; the interfaces keep the
  // names they have (tag_interfaces: "interface <a>-<b>").
  std::vector<TetMeshInput::TagName> interface_names;
  for (const TetMeshInput::TagName& n : result.tag_names) {
    if (n.dimension == 2 && std::find(result.interface_tags.begin(), result.interface_tags.end(),
                                      n.tag) != result.interface_tags.end())
      interface_names.push_back(n);
  }
  // Only the names of tags some element has: a name without elements (an embedded surface
  // the mesh does not keep, a curve's group) would be a Gmsh physical group with nothing in
  // it. The file's interface tags count: tag_interfaces gives them to triangles later.
  result.tag_names.clear();
  {
    std::vector<std::int32_t> triangle_tags = file_interface_tags(domain);
    triangle_tags.insert(triangle_tags.end(), result.boundary_tags.begin(),
                         result.boundary_tags.end());
    triangle_tags.insert(triangle_tags.end(), result.interface_tags.begin(),
                         result.interface_tags.end());
    std::vector<std::int32_t> tet_tags = result.tet_tags;
    for (std::vector<std::int32_t>* tags : {&triangle_tags, &tet_tags}) {
      std::sort(tags->begin(), tags->end());
      tags->erase(std::unique(tags->begin(), tags->end()), tags->end());
    }
    for (const TetMeshInput::TagName& n : domain.tag_names()) {
      const std::vector<std::int32_t>* tags = n.dimension == 2   ? &triangle_tags
                                              : n.dimension == 3 ? &tet_tags
                                                                 : nullptr;
      if (tags != nullptr && std::binary_search(tags->begin(), tags->end(), n.tag))
        result.tag_names.push_back(n);
    }
  }
  const UntaggedTags untagged = untagged_tags(domain);
  const auto name_the_rest = [&](int dimension, std::vector<std::int32_t> tags, const char* what) {
    std::sort(tags.begin(), tags.end());
    tags.erase(std::unique(tags.begin(), tags.end()), tags.end());
    for (const std::int32_t t : tags) {
      const bool named = std::any_of(
          result.tag_names.begin(), result.tag_names.end(),
          [&](const TetMeshInput::TagName& n) { return n.dimension == dimension && n.tag == t; });
      if (named) continue;
      const std::string fresh = untagged.name(dimension, t);
      result.tag_names.push_back({dimension, t, fresh.empty() ? what + std::to_string(t) : fresh});
    }
  };
  for (const TetMeshInput::TagName& n : interface_names) {
    const bool named = std::any_of(
        result.tag_names.begin(), result.tag_names.end(),
        [&](const TetMeshInput::TagName& m) { return m.dimension == 2 && m.tag == n.tag; });
    if (!named) result.tag_names.push_back(n);
  }
  name_the_rest(2, result.boundary_tags, "patch ");
  name_the_rest(3, result.tet_tags, "region ");
  // Triangles grouped by patch tag (stable: (tet, facet) order within a patch), so that
  // a file has one block per patch rather than one per run of the tet order.
  std::vector<std::uint32_t> order(result.boundary_tags.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return result.boundary_tags[a] < result.boundary_tags[b];
  });
  std::vector<std::uint32_t> triangles(result.boundary_triangles.size());
  std::vector<std::int32_t> tags(order.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    std::copy_n(&result.boundary_triangles[3 * std::size_t{order[i]}], 3, &triangles[3 * i]);
    tags[i] = result.boundary_tags[order[i]];
  }
  result.boundary_triangles = std::move(triangles);
  result.boundary_tags = std::move(tags);
}

}  // namespace voroclip::mesh3
