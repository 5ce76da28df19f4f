// Interfaces between the regions of a tet mesh domain, followed by the mesh (mesh3d_pipeline.h,
// RegionInterfaces).
//
// A tet mesh's regions (its tet tags) meet along interfaces: the facets between two tets of
// different tags. Each region is a closed volume of its own (a Domain3 of its tets), and the
// boundary and the interfaces together make one surface, `surface`, which is not a 2-manifold
// where an interface meets the boundary or another interface (three or more triangles on an
// edge: those edges are feature lines, extract_feature_lines). The mesh follows the
// interfaces as it follows the boundary (Yan et al. 2011, sec. 5.2, applied to both): sites
// whose cells cross an interface go onto it (first from one side only, so that the interface
// gets one layer of sites, as the boundary does), the feature lines, the surface patches and
// the topology refinement (each region's surface on its own) see both, and each Delaunay tet
// takes the region its circumcentre lies in (exact). A Delaunay face between tets of two
// regions is dual to a Voronoi edge that crosses an interface: the interface of the mesh is
// the restricted Delaunay triangulation of the interface, as its boundary is that of the
// boundary. After that, flips and moves work within each region, the vertices two regions
// share fixed, so that no tet ever crosses an interface; each region's tets must have its
// shape (check_mesh3_shape).
//
// Not followed: regions whose tets are no valid volume on their own (tets of one region
// meeting along an edge or at a vertex only, as a region labelled tet by tet can): mesh3d then
// meshes the volume as one, tagging each tet by its centroid, with a warning that counts the
// tets across (region_tags) and says where.
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "mesh3d_pipeline.h"
#include "mesh3d_tags.h"
#include "union_find.h"

namespace voroclip::mesh3 {

namespace {

// The facet opposite vertex f of Domain3's tet t, clockwise seen from outside t (Domain3's
// convention: reversed, it is a boundary triangle's orientation).
std::array<std::uint32_t, 3> facet(const Domain3& d, std::uint32_t t, int f) {
  std::array<std::uint32_t, 3> v{};
  for (int k = 0; k < 3; ++k)
    v[static_cast<std::size_t>(k)] = d.tet_vertex(t, Domain3::kTetFacetVertex[f][k]);
  return v;
}

}  // namespace

bool region_interfaces(const Domain3& domain, RegionInterfaces& out, std::string& why_not) {
  why_not.clear();
  const std::vector<std::int32_t>& refs = domain.tet_refs();
  if (!domain.has_tets() || refs.empty() ||
      std::all_of(refs.begin(), refs.end(), [&](std::int32_t r) { return r == refs[0]; })) {
    return false;
  }
  // The regions, by increasing tag; each a Domain3 of its tets (the domain's vertices).
  out.tags = refs;
  std::sort(out.tags.begin(), out.tags.end());
  out.tags.erase(std::unique(out.tags.begin(), out.tags.end()), out.tags.end());
  const auto region_of_tag = [&](std::int32_t tag) {
    return static_cast<std::uint32_t>(std::lower_bound(out.tags.begin(), out.tags.end(), tag) -
                                      out.tags.begin());
  };
  // A region whose tets meet along an edge only: named by that edge (the file's numbers).
  const auto where = [&](std::uint32_t v) {
    const double* p = domain.vertex(v);
    return domain.surface().vertex_name(v) + " (" + brief(p[0]) + ", " + brief(p[1]) + ", " +
           brief(p[2]) + ")";
  };
  {
    std::vector<std::array<std::uint32_t, 3>> edges;  // (low, high, region)
    for (std::uint32_t t = 0; t < domain.nb_tets(); ++t) {
      for (int f = 0; f < 4; ++f) {
        const std::uint32_t u = domain.tet_adjacent(t, f);
        if (u != Domain3::kNone && refs[u] == refs[t]) continue;
        const std::array<std::uint32_t, 3> v = facet(domain, t, f);
        for (std::size_t k = 0; k < 3; ++k) {
          const std::uint32_t a = v[k], b = v[(k + 1) % 3];
          edges.push_back({std::min(a, b), std::max(a, b), region_of_tag(refs[t])});
        }
      }
    }
    std::sort(edges.begin(), edges.end(),
              [](const auto& x, const auto& y) { return x[2] != y[2] ? x[2] < y[2] : x < y; });
    for (std::size_t i = 0; i < edges.size();) {
      std::size_t j = i;
      while (j < edges.size() && edges[j] == edges[i]) ++j;
      if (j - i != 2) {
        why_not = "the tets of region " + std::to_string(out.tags[edges[i][2]]) +
                  " meet along an edge only, from " + where(edges[i][0]) + " to " +
                  where(edges[i][1]) + ": it is no volume of its own";
        return false;
      }
      i = j;
    }
  }
  out.regions.clear();
  for (const std::int32_t tag : out.tags) {
    TetMeshInput m;
    m.source = domain.source() + " (its region " + std::to_string(tag) + ")";
    m.xyz = domain.coords();
    for (std::uint32_t t = 0; t < domain.nb_tets(); ++t) {
      if (refs[t] != tag) continue;
      for (int k = 0; k < 4; ++k) m.tets.push_back(domain.tet_vertex(t, k));
    }
    try {
      out.regions.emplace_back(m);
    } catch (const Error& e) {
      why_not = std::string("region ") + std::to_string(tag) +
                " is no valid volume on its own: " + e.what();
      return false;
    }
  }
  // The surface: the boundary's triangles, then each interface facet as the tet of the lower
  // tag sees it from outside (Domain3's facet reversed).
  TriangleSurface& s = out.surface;
  s = TriangleSurface{};
  s.source = domain.source() + " (its boundary and the interfaces between its regions)";
  s.xyz = domain.coords();
  s.triangles = domain.surface().triangles();
  out.nb_boundary_triangles = domain.surface().nb_triangles();
  out.sides.clear();
  for (std::uint32_t t = 0; t < domain.nb_tets(); ++t) {
    for (int f = 0; f < 4; ++f) {
      const std::uint32_t u = domain.tet_adjacent(t, f);
      if (u == Domain3::kNone || u < t || refs[u] == refs[t]) continue;
      std::array<std::uint32_t, 3> v{};
      if (refs[t] < refs[u]) {
        v = facet(domain, t, f);
      } else {
        int g = 0;
        while (domain.tet_adjacent(u, g) != t) ++g;
        v = facet(domain, u, g);
      }
      s.triangles.insert(s.triangles.end(), {v[0], v[2], v[1]});
      out.sides.push_back(
          {region_of_tag(std::min(refs[t], refs[u])), region_of_tag(std::max(refs[t], refs[u]))});
    }
  }
  s.triangle_line.assign(s.triangles.size() / 3, 0);
  // The interfaces: one per pair of regions that meet, in the order of their first facet.
  out.interface_of.assign(out.sides.size(), 0);
  std::vector<std::array<std::uint32_t, 2>> pairs;
  for (std::size_t f = 0; f < out.sides.size(); ++f) {
    const auto it = std::find(pairs.begin(), pairs.end(), out.sides[f]);
    out.interface_of[f] = static_cast<std::uint32_t>(it - pairs.begin());
    if (it == pairs.end()) pairs.push_back(out.sides[f]);
  }
  out.nb_interfaces = static_cast<std::uint32_t>(pairs.size());
  out.triangle_regions.clear();
  if (out.tags.size() <= 64) {
    for (std::uint32_t b = 0; b < out.nb_boundary_triangles; ++b)
      out.triangle_regions.push_back(std::uint64_t{1}
                                     << region_of_tag(refs[domain.boundary_tet(b)]));
    for (const std::array<std::uint32_t, 2>& side : out.sides)
      out.triangle_regions.push_back(std::uint64_t{1} << side[0] | std::uint64_t{1} << side[1]);
  }
  // The tags: the boundary's, and the file's tags of the interface triangles.
  out.refs.assign(s.nb_triangles(), 0);
  bool tagged = !domain.boundary_refs().empty();
  if (tagged)
    std::copy(domain.boundary_refs().begin(), domain.boundary_refs().end(), out.refs.begin());
  for (std::uint32_t t = out.nb_boundary_triangles; t < s.nb_triangles(); ++t) {
    const std::uint32_t* v = &s.triangles[3 * std::size_t{t}];
    out.refs[t] = domain.inner_triangle_ref(v[0], v[1], v[2]);
    tagged = tagged || out.refs[t] != 0;
  }
  if (!tagged) out.refs.clear();
  return true;
}

std::vector<std::int32_t> file_interface_tags(const Domain3& domain) {
  std::vector<std::int32_t> tags;
  const std::vector<std::int32_t>& refs = domain.tet_refs();
  if (refs.empty()) return tags;
  for (std::uint32_t t = 0; t < domain.nb_tets(); ++t) {
    for (int f = 0; f < 4; ++f) {
      const std::uint32_t u = domain.tet_adjacent(t, f);
      if (u == Domain3::kNone || u < t || refs[u] == refs[t]) continue;
      const std::array<std::uint32_t, 3> v = facet(domain, t, f);
      const std::int32_t tag = domain.inner_triangle_ref(v[0], v[1], v[2]);
      if (tag != 0) tags.push_back(tag);
    }
  }
  std::sort(tags.begin(), tags.end());
  tags.erase(std::unique(tags.begin(), tags.end()), tags.end());
  return tags;
}

std::vector<Mesh3Result::EmbeddedTag> file_embedded_tags(const Domain3& domain) {
  const std::vector<std::int32_t>& refs = domain.tet_refs();
  std::vector<std::int32_t> found;  // one per triangle
  for (std::uint32_t t = 0; t < domain.nb_tets(); ++t) {
    for (int f = 0; f < 4; ++f) {
      const std::uint32_t u = domain.tet_adjacent(t, f);
      if (u == Domain3::kNone || u < t || (!refs.empty() && refs[u] != refs[t])) continue;
      const std::array<std::uint32_t, 3> v = facet(domain, t, f);
      const std::int32_t tag = domain.inner_triangle_ref(v[0], v[1], v[2]);
      if (tag != 0) found.push_back(tag);
    }
  }
  std::sort(found.begin(), found.end());
  std::vector<Mesh3Result::EmbeddedTag> tags;
  for (std::size_t i = 0; i < found.size();) {
    std::size_t j = i;
    while (j < found.size() && found[j] == found[i]) ++j;
    Mesh3Result::EmbeddedTag e;
    e.tag = found[i];
    e.nb_triangles = static_cast<std::uint32_t>(j - i);
    for (const TetMeshInput::TagName& n : domain.tag_names()) {
      if (n.dimension == 2 && n.tag == e.tag) e.name = n.name;
    }
    tags.push_back(e);
    i = j;
  }
  return tags;
}

std::uint32_t RegionInterfaces::region_of(const double* p) const {
  std::uint32_t on = kNoRegion;
  for (std::uint32_t k = 0; k < regions.size(); ++k) {
    const Sign side = regions[k].locate(p);
    if (side == Sign::positive) return k;
    if (side == Sign::zero && on == kNoRegion) on = k;
  }
  return on;
}

TetRegions interface_regions(const RegionInterfaces& interfaces, const std::vector<double>& sites,
                             const std::vector<std::uint32_t>& tets, const SurfacePatches& sp) {
  const std::size_t nt = tets.size() / 4;
  const auto nb = static_cast<std::uint32_t>(interfaces.regions.size());
  TetRegions r;
  r.nb = nb;
  r.region.assign(nt, kNoRegion);
  const auto centroid_region = [&](std::size_t t) {
    double c[3] = {0, 0, 0};
    for (int k = 0; k < 4; ++k) {
      const double* p = &sites[3 * std::size_t{tets[4 * t + static_cast<std::size_t>(k)]}];
      for (int a = 0; a < 3; ++a) c[a] += 0.25 * p[a];
    }
    return interfaces.region_of(c);
  };
  // The region holding the circumcentre (strictly; else the first whose boundary holds it);
  // a tet kept with its circumcentre outside the domain (the extraction's fill at the
  // boundary), by its centroid.
  for (std::size_t t = 0; t < nt; ++t) {
    const double* p[4];
    for (int k = 0; k < 4; ++k)
      p[k] = &sites[3 * std::size_t{tets[4 * t + static_cast<std::size_t>(k)]}];
    std::uint32_t on = kNoRegion;
    for (std::uint32_t k = 0; k < nb && r.region[t] == kNoRegion; ++k) {
      const Sign side = interfaces.regions[k].surface().locate_circumcenter(p[0], p[1], p[2], p[3]);
      if (side == Sign::positive) r.region[t] = k;
      if (side == Sign::zero && on == kNoRegion) on = k;
    }
    if (r.region[t] == kNoRegion) r.region[t] = on != kNoRegion ? on : centroid_region(t);
  }
  // The faces two tets share: (vertices, tet, tet), in face order.
  struct Shared {
    std::array<std::uint32_t, 3> v;
    std::uint32_t a, b;
  };
  std::vector<Shared> pairs;
  {
    const std::vector<FaceRef> faces = sorted_faces(tets);
    for (std::size_t i = 0; i + 1 < faces.size(); ++i) {
      if (faces[i].key == faces[i + 1].key)
        pairs.push_back({faces[i].key, faces[i].code / 4, faces[i + 1].code / 4});
    }
  }
  // The rest (a centroid outside the domain too): the region of a face neighbour, in
  // passes.
  for (bool changed = true; changed;) {
    changed = false;
    for (const auto& [v, a, b] : pairs) {
      if (r.region[a] == kNoRegion && r.region[b] != kNoRegion) {
        r.region[a] = r.region[b];
        changed = true;
      } else if (r.region[b] == kNoRegion && r.region[a] != kNoRegion) {
        r.region[b] = r.region[a];
        changed = true;
      }
    }
  }
  for (std::uint32_t& k : r.region) k = k == kNoRegion ? 0 : k;
  // The extraction's crease rule (extract3d.cpp, fill_boundary) at the interfaces: where a
  // face between two regions crosses a feature line (its vertices share no patch), a tet
  // whose centroid lies strictly in another region goes there (the chamfer of a convex edge
  // of a region, a bridge over a concave one). Each tet at most once, in passes until none
  // changes.
  const auto shared = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    const auto has = [&](std::uint32_t v, std::uint32_t patch) {
      return std::find(sp.patches.begin() + sp.begin[v], sp.patches.begin() + sp.begin[v + 1],
                       patch) != sp.patches.begin() + sp.begin[v + 1];
    };
    for (std::uint32_t i = sp.begin[a]; i < sp.begin[a + 1]; ++i) {
      if (has(b, sp.patches[i]) && has(c, sp.patches[i])) return true;
    }
    return false;
  };
  const auto strictly_in = [&](std::size_t t) {
    double c[3] = {0, 0, 0};
    for (int k = 0; k < 4; ++k) {
      const double* p = &sites[3 * std::size_t{tets[4 * t + static_cast<std::size_t>(k)]}];
      for (int a = 0; a < 3; ++a) c[a] += 0.25 * p[a];
    }
    for (std::uint32_t k = 0; k < nb; ++k) {
      if (interfaces.regions[k].locate(c) == Sign::positive) return k;
    }
    return kNoRegion;
  };
  std::vector<std::uint8_t> changed(nt, 0);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> todo;  // (tet, region)
  for (int pass = 0; pass < 8; ++pass) {
    todo.clear();
    for (const auto& [v, a, b] : pairs) {
      if (r.region[a] == r.region[b]) continue;
      if (v[2] + 1 >= sp.begin.size() || shared(v[0], v[1], v[2])) continue;
      for (const std::uint32_t t : {a, b}) {
        if (changed[t] != 0) continue;
        const std::uint32_t k = strictly_in(t);
        if (k != kNoRegion && k != r.region[t]) todo.emplace_back(t, k);
      }
    }
    if (todo.empty()) break;
    std::sort(todo.begin(), todo.end());
    todo.erase(std::unique(todo.begin(), todo.end()), todo.end());
    for (const auto& [t, k] : todo) {
      if (changed[t] != 0) continue;
      changed[t] = 1;
      r.region[t] = k;
    }
  }
  return r;
}

void per_region(
    std::vector<double>& sites, const std::vector<Kind>& kinds, std::vector<std::uint32_t>& tets,
    TetRegions& regions,
    const std::function<void(std::vector<std::uint32_t>&, const std::vector<Kind>&)>& pass) {
  const std::size_t nt = tets.size() / 4;
  const std::vector<std::uint32_t>& region = regions.region;
  // The vertices of tets of two regions or more stay: kFixed for the passes.
  std::vector<std::uint32_t> first(sites.size() / 3, kNoRegion);
  std::vector<Kind> fixed = kinds;
  for (std::size_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 4; ++k) {
      const std::uint32_t v = tets[4 * t + static_cast<std::size_t>(k)];
      if (first[v] == kNoRegion) {
        first[v] = region[t];
      } else if (first[v] != region[t]) {
        fixed[v] = Kind::kFixed;
      }
    }
  }
  std::vector<std::uint32_t> all, all_region, mine;
  all.reserve(tets.size());
  all_region.reserve(nt);
  for (std::uint32_t r = 0; r < regions.nb; ++r) {
    mine.clear();
    for (std::size_t t = 0; t < nt; ++t) {
      if (region[t] == r) mine.insert(mine.end(), &tets[4 * t], &tets[4 * t] + 4);
    }
    fixed.resize(sites.size() / 3, Kind::kFree);  // vertices an earlier region's pass added
    pass(mine, fixed);
    all.insert(all.end(), mine.begin(), mine.end());
    all_region.insert(all_region.end(), mine.size() / 4, r);
  }
  tets = std::move(all);
  regions.region = std::move(all_region);
}

std::string interface_shape(const RegionInterfaces& interfaces, const std::vector<double>& xyz,
                            const std::vector<std::uint32_t>& tets, const TetRegions& regions) {
  // Each region's tets must have its shape, shell for shell.
  for (std::uint32_t k = 0; k < regions.nb; ++k) {
    std::vector<std::uint32_t> mine;
    for (std::size_t t = 0; t < tets.size() / 4; ++t) {
      if (regions.region[t] == k) mine.insert(mine.end(), &tets[4 * t], &tets[4 * t] + 4);
    }
    const std::string problem = check_mesh3_shape(interfaces.regions[k], xyz, mine);
    if (!problem.empty()) {
      return "the tets of its region " + std::to_string(interfaces.tags[k]) +
             " do not have the input region's shape: " + problem;
    }
  }
  return "";
}

void tag_interfaces(const RegionInterfaces& interfaces, const SurfaceTree& sampled_tree,
                    const TetRegions& regions, Mesh3Result& result) {
  // Made-up tags follow every tag of the boundary and of the file's triangles.
  std::int32_t base = 0;
  for (const std::int32_t t : result.boundary_tags) base = std::max(base, t);
  for (const std::int32_t t : interfaces.refs) base = std::max(base, t);
  const std::vector<std::uint32_t>& tets = result.tets;
  const std::vector<FaceRef> faces = sorted_faces(tets);
  struct Face {
    std::int32_t tag;
    std::uint32_t code;  // 4 tet + facet, of the tet of the lower region
    std::uint32_t low, high;
  };
  std::vector<Face> found;
  for (std::size_t i = 0; i + 1 < faces.size(); ++i) {
    const FaceRef& a = faces[i];
    const FaceRef& b = faces[i + 1];
    if (a.key != b.key) continue;
    const std::uint32_t ra = regions.region[a.code / 4], rb = regions.region[b.code / 4];
    if (ra == rb) continue;
    const std::uint32_t code = ra < rb ? a.code : b.code;
    const std::array<std::uint32_t, 2> pair = {std::min(ra, rb), std::max(ra, rb)};
    double c[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) {
      for (int q = 0; q < 3; ++q)
        c[q] += result.xyz[3 * std::size_t{a.key[static_cast<std::size_t>(k)]} +
                           static_cast<std::size_t>(q)] /
                3;
    }
    // The file's tag of the nearest input interface triangle (between the same regions),
    // else one tag per interface (its rank among the input's).
    const std::uint32_t nearest = sampled_tree.closest(c).triangle;
    std::int32_t tag = 0;
    if (nearest >= interfaces.nb_boundary_triangles) {
      const std::uint32_t f = nearest - interfaces.nb_boundary_triangles;
      if (interfaces.sides[f] == pair && !interfaces.refs.empty()) tag = interfaces.refs[nearest];
    }
    if (tag == 0) {
      const auto it = std::find(interfaces.sides.begin(), interfaces.sides.end(), pair);
      const std::uint32_t rank =
          it == interfaces.sides.end()
              ? interfaces.nb_interfaces
              : interfaces.interface_of[static_cast<std::size_t>(it - interfaces.sides.begin())];
      tag = base + static_cast<std::int32_t>(rank + 1);
    }
    found.push_back({tag, code, pair[0], pair[1]});
  }
  std::stable_sort(found.begin(), found.end(), [](const Face& x, const Face& y) {
    return x.tag != y.tag ? x.tag < y.tag : x.code < y.code;
  });
  result.interface_triangles.clear();
  result.interface_tags.clear();
  for (const Face& f : found) {
    const std::size_t t = f.code / 4;
    const int k = static_cast<int>(f.code % 4);
    for (int q = 0; q < 3; ++q)
      result.interface_triangles.push_back(
          tets[4 * t + static_cast<std::size_t>(kOutwardFacet[k][q])]);
    result.interface_tags.push_back(f.tag);
    const bool named = std::any_of(
        result.tag_names.begin(), result.tag_names.end(),
        [&](const TetMeshInput::TagName& n) { return n.dimension == 2 && n.tag == f.tag; });
    if (!named) {
      result.tag_names.push_back({2, f.tag,
                                  "interface " + std::to_string(interfaces.tags[f.low]) + "-" +
                                      std::to_string(interfaces.tags[f.high])});
    }
  }
}

std::string interface_distance(const RegionInterfaces& interfaces,
                               const HausdorffOptions& edge_length, double bound,
                               Mesh3Result& result) {
  result.interface_distance_to_edge_length = 0;
  TriangleSurface input, mine;
  input.source = "the input's interfaces";
  input.xyz = interfaces.surface.xyz;
  const std::vector<std::uint32_t>& all = interfaces.surface.triangles;
  input.triangles.assign(all.begin() + 3 * std::ptrdiff_t{interfaces.nb_boundary_triangles},
                         all.end());
  mine.source = "the mesh's interfaces";
  mine.xyz = result.xyz;
  mine.triangles = result.interface_triangles;
  if (input.triangles.empty() || mine.triangles.empty()) {
    return mine.triangles.empty() ? "it has no interface between its regions" : "";
  }
  const SurfaceTree input_tree(input), mine_tree(mine);
  const OneSidedDistance forward = sampled_distance(mine, input_tree, edge_length);
  const OneSidedDistance backward = sampled_distance(input, mine_tree, edge_length);
  const bool cut = backward.max >= forward.max;
  const OneSidedDistance& worst = cut ? backward : forward;
  result.interface_distance_to_edge_length = worst.max;
  if (!(bound > 0 && worst.max > bound)) return "";
  return std::string(cut ? "the input's interface between regions at (" : "its interface at (") +
         brief(worst.where[0]) + ", " + brief(worst.where[1]) + ", " + brief(worst.where[2]) +
         ") is " + brief(worst.max) + " local edge lengths from " +
         (cut ? "the mesh's" : "the input's") + " (bound " + brief(bound) +
         "): an inclusion thinner than the edges, or closer than them to another";
}

void Pipeline::mark_interface_sites(std::vector<std::uint8_t>& boundary, bool both_sides) const {
  if (!interfaces) return;
  const auto m = static_cast<std::uint32_t>(sites.size() / 3);  // n is set from step 4 on
  boundary.resize(m, 0);
  std::vector<std::uint32_t> own(m);
  for (std::uint32_t v = 0; v < m; ++v) own[v] = interfaces->region_of(&sites[3 * std::size_t{v}]);
  // A site of region j whose cell reaches into region k (its cell clipped to k is a boundary
  // cell there) crosses their interface; first only when j > k (one side).
  for (std::uint32_t k = 0; k < interfaces->regions.size(); ++k) {
    ClippedVoronoi3 cv;
    cv.compute(interfaces->regions[k], sites.data(), m);
    for (std::uint32_t v = 0; v < m; ++v) {
      if ((kinds.size() > v && kinds[v] != Kind::kFree) || own[v] == k || own[v] == kNoRegion)
        continue;
      if (cv.is_boundary(v) && (both_sides || own[v] > k)) boundary[v] = 1;
    }
  }
}

}  // namespace voroclip::mesh3
