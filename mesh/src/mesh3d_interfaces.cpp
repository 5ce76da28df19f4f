// Interfaces between the regions of a tet mesh domain, followed by the mesh (mesh3d_pipeline.h,
// RegionInterfaces).
//
// A tet mesh's regions (its tet tags) meet along interfaces: the facets between two tets of
// different tags. When each interface is a closed surface inside the volume (an inclusion, a
// core in a shell of another material), the boundary and the interfaces together make one
// surface, `surfaces`, whose shells are nested: the volume outside every inclusion is a
// domain with the interfaces as cavities (an inclusion in an inclusion a body again). The
// mesh follows the interfaces as it follows the boundary (Yan et al. 2011, sec. 5.2, applied
// to both): sites whose cells cross an interface from its inside go onto it (one side only, so
// that the interface gets one layer of sites, as the boundary does), the feature lines, the
// surface patches and the topology refinement see both, and each Delaunay tet takes the side
// of `surfaces` its circumcentre lies on (exact). A Delaunay face between tets of two sides
// is dual to a Voronoi edge that crosses an interface: the interface of the mesh is the
// restricted Delaunay triangulation of the interface, as its boundary is that of the
// boundary. The regions are then the face-connected parts of one side; after that, flips and
// moves work within each region, the vertices two regions share fixed, so that no tet ever
// crosses an interface.
//
// Interfaces that meet the boundary or each other (layers across the whole part, three
// regions along one curve, tets of one region meeting along an edge only) are not closed
// surfaces inside the volume: `surfaces` would not be a 2-manifold. region_interfaces says
// where (a vertex of the boundary on an interface, an edge of more than two interface facets,
// or Surface3's own message), and mesh3d meshes the volume as one, tagging each tet by its
// centroid, with a warning that counts the tets across (region_tags).
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "mesh3d_pipeline.h"
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
  TriangleSurface s;
  s.source = domain.source() + " (its boundary and the interfaces between its regions)";
  s.xyz = domain.coords();
  s.triangles = domain.surface().triangles();
  const std::uint32_t nb_boundary = domain.surface().nb_triangles();
  // Each interface facet as the tet of the lower tag sees it from outside (the boundary's
  // orientation: Domain3's facet reversed): the same side along a whole closed interface,
  // whose orientation Surface3Options::reorient then fixes by its nesting.
  std::vector<std::pair<std::int32_t, std::int32_t>> sides;  // per interface facet: its tags
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
      sides.emplace_back(std::min(refs[t], refs[u]), std::max(refs[t], refs[u]));
    }
  }
  s.triangle_line.assign(s.triangles.size() / 3, 0);
  // Where an interface meets the boundary (a vertex of both) or other interfaces (an edge of
  // more than two interface facets), named by the first such vertex or edge.
  const Surface3& boundary = domain.surface();
  const auto where = [&](std::uint32_t v) {
    const double* p = domain.vertex(v);
    return boundary.vertex_name(v) + " (" + brief(p[0]) + ", " + brief(p[1]) + ", " + brief(p[2]) +
           ")";
  };
  const auto between = [](const std::pair<std::int32_t, std::int32_t>& tags) {
    return "regions " + std::to_string(tags.first) + " and " + std::to_string(tags.second);
  };
  std::vector<std::uint8_t> on_boundary(domain.nb_vertices(), 0);
  for (const std::uint32_t v : boundary.triangles()) on_boundary[v] = 1;
  std::vector<std::array<std::uint32_t, 3>> edges;  // (low vertex, high vertex, facet)
  for (std::size_t i = 3 * std::size_t{nb_boundary}; i < s.triangles.size(); i += 3) {
    const auto f = static_cast<std::uint32_t>(i / 3 - nb_boundary);
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t v = s.triangles[i + k], w = s.triangles[i + (k + 1) % 3];
      if (on_boundary[v] != 0) {
        why_not =
            "the interface between " + between(sides[f]) + " meets the boundary at " + where(v);
        return false;
      }
      edges.push_back({std::min(v, w), std::max(v, w), f});
    }
  }
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j][0] == edges[i][0] && edges[j][1] == edges[i][1]) ++j;
    if (j - i != 2) {
      std::vector<std::int32_t> tags;
      for (std::size_t k = i; k < j; ++k) {
        tags.push_back(sides[edges[k][2]].first);
        tags.push_back(sides[edges[k][2]].second);
      }
      std::sort(tags.begin(), tags.end());
      tags.erase(std::unique(tags.begin(), tags.end()), tags.end());
      std::string list;
      for (std::size_t k = 0; k < tags.size(); ++k)
        list += (k == 0 ? "" : k + 1 == tags.size() ? " and " : ", ") + std::to_string(tags[k]);
      why_not = (tags.size() == 2 ? "the interface between regions " + list +
                                        " touches itself (tets of one region meet along an "
                                        "edge only)"
                                  : "the interfaces between regions " + list + " meet") +
                " along the edge from " + where(edges[i][0]) + " to " + where(edges[i][1]);
      return false;
    }
    i = j;
  }
  Surface3Options so;
  so.reorient = true;
  try {
    out.surfaces = Domain3(s, so);
  } catch (const Error& e) {
    why_not = e.what();
    return false;
  }
  out.nb_boundary_triangles = nb_boundary;
  out.nb_shells = static_cast<std::uint32_t>(out.surfaces.surface().shells().size() -
                                             domain.surface().shells().size());
  // The tags: the boundary's, and the file's tags of the interface triangles.
  out.refs.assign(out.surfaces.surface().nb_triangles(), 0);
  bool tagged = !domain.boundary_refs().empty();
  if (tagged)
    std::copy(domain.boundary_refs().begin(), domain.boundary_refs().end(), out.refs.begin());
  for (std::uint32_t t = nb_boundary; t < out.surfaces.surface().nb_triangles(); ++t) {
    const std::uint32_t* v = &s.triangles[3 * std::size_t{t}];
    out.refs[t] = domain.inner_triangle_ref(v[0], v[1], v[2]);
    tagged = tagged || out.refs[t] != 0;
  }
  if (!tagged) out.refs.clear();
  return true;
}

TetRegions interface_regions(const RegionInterfaces& interfaces, const std::vector<double>& sites,
                             const std::vector<std::uint32_t>& tets, const SurfacePatches& sp) {
  const std::size_t nt = tets.size() / 4;
  std::vector<std::uint8_t> side(nt, 0);
  const Surface3& s = interfaces.surfaces.surface();
  for (std::size_t t = 0; t < nt; ++t) {
    const double* p[4];
    for (int k = 0; k < 4; ++k)
      p[k] = &sites[3 * std::size_t{tets[4 * t + static_cast<std::size_t>(k)]}];
    side[t] = s.locate_circumcenter(p[0], p[1], p[2], p[3]) == Sign::positive ? 1 : 0;
  }
  std::vector<std::array<std::uint32_t, 4>> faces;  // sorted vertices, tet
  faces.reserve(4 * nt);
  for (std::size_t t = 0; t < nt; ++t) {
    for (int f = 0; f < 4; ++f) {
      std::array<std::uint32_t, 3> v{};
      std::size_t j = 0;
      for (int k = 0; k < 4; ++k) {
        if (k != f) v[j++] = tets[4 * t + static_cast<std::size_t>(k)];
      }
      std::sort(v.begin(), v.end());
      faces.push_back({v[0], v[1], v[2], static_cast<std::uint32_t>(t)});
    }
  }
  std::sort(faces.begin(), faces.end());
  // The extraction's crease rule (extract3d.cpp, fill_boundary) at the interfaces: where a
  // face between the two sides crosses a feature line of an interface (its vertices share no
  // patch), a tet whose centroid lies strictly on the other side goes there (the chamfer of a
  // convex edge of an inclusion, a bridge over a concave one). Each tet at most once, in
  // passes until none changes.
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
  const auto centroid_side = [&](std::uint32_t t) {
    double c[3] = {0, 0, 0};
    for (int k = 0; k < 4; ++k) {
      const double* p =
          &sites[3 * std::size_t{tets[4 * std::size_t{t} + static_cast<std::size_t>(k)]}];
      for (int a = 0; a < 3; ++a) c[a] += 0.25 * p[a];
    }
    return s.locate(c);
  };
  std::vector<std::uint8_t> changed(nt, 0);
  std::vector<std::uint32_t> todo;
  for (int pass = 0; pass < 8; ++pass) {
    todo.clear();
    for (std::size_t i = 0; i + 1 < faces.size(); ++i) {
      const auto& a = faces[i];
      const auto& b = faces[i + 1];
      if (a[0] != b[0] || a[1] != b[1] || a[2] != b[2] || side[a[3]] == side[b[3]]) continue;
      if (a[0] + 1 >= sp.begin.size() || a[1] + 1 >= sp.begin.size() ||
          a[2] + 1 >= sp.begin.size() || shared(a[0], a[1], a[2]))
        continue;
      for (const std::uint32_t t : {a[3], b[3]}) {
        if (changed[t] != 0) continue;
        const Sign c = centroid_side(t);
        if ((c == Sign::positive && side[t] == 0) || (c == Sign::negative && side[t] == 1))
          todo.push_back(t);
      }
    }
    if (todo.empty()) break;
    std::sort(todo.begin(), todo.end());
    todo.erase(std::unique(todo.begin(), todo.end()), todo.end());
    for (const std::uint32_t t : todo) {
      changed[t] = 1;
      side[t] ^= 1;
    }
  }
  // Face-connected parts of one side, numbered in the order of their first tet.
  UnionFind parts(static_cast<std::uint32_t>(nt));
  for (std::size_t i = 0; i + 1 < faces.size(); ++i) {
    const auto& a = faces[i];
    const auto& b = faces[i + 1];
    if (a[0] == b[0] && a[1] == b[1] && a[2] == b[2] && side[a[3]] == side[b[3]])
      parts.unite(a[3], b[3]);
  }
  TetRegions r;
  std::vector<std::uint32_t> number(nt, kNoRegion);
  r.region.resize(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    const std::uint32_t root = parts.find(static_cast<std::uint32_t>(t));
    if (number[root] == kNoRegion) {
      number[root] = static_cast<std::uint32_t>(r.outside.size());
      r.outside.push_back(side[t]);
    }
    r.region[t] = number[root];
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
  for (std::uint32_t r = 0; r < regions.outside.size(); ++r) {
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
  // The tets outside every inclusion (the regions whose circumcentres lie in `surfaces`'s
  // volume: the parts that border the outer boundary, and those in an inclusion of an
  // inclusion): their boundary must be `surfaces`, shell for shell.
  std::vector<std::uint32_t> kept;
  for (std::size_t t = 0; t < tets.size() / 4; ++t) {
    if (regions.outside[regions.region[t]] != 0)
      kept.insert(kept.end(), &tets[4 * t], &tets[4 * t] + 4);
  }
  const std::string problem = check_mesh3_shape(interfaces.surfaces, xyz, kept);
  if (problem.empty()) return "";
  return "the tets outside the inclusions (the interfaces between the regions as cavities) "
         "do not have the input's shape: " +
         problem;
}

void tag_interfaces(const RegionInterfaces& interfaces, const SurfaceTree& sampled_tree,
                    Mesh3Result& result) {
  // The interface shells of `surfaces` (those after the boundary's triangles), ranked.
  const Surface3& s = interfaces.surfaces.surface();
  std::vector<std::uint32_t> rank(s.shells().size(), 0);
  std::uint32_t nb_interfaces = 0;
  for (std::size_t h = 0; h < s.shells().size(); ++h) {
    if (s.shells()[h].first_triangle >= interfaces.nb_boundary_triangles) rank[h] = ++nb_interfaces;
  }
  std::int32_t base = 0;
  for (const std::int32_t t : result.boundary_tags) base = std::max(base, t);
  // The faces shared by two tets of different tags; right-handed tets, so the facet opposite
  // vertex f listed as kOutward[f] is counter-clockwise seen from outside its tet.
  static constexpr int kOutward[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  const std::vector<std::uint32_t>& tets = result.tets;
  const std::size_t nt = tets.size() / 4;
  std::vector<std::array<std::uint32_t, 4>> faces;  // sorted vertices, 4 tet + facet
  faces.reserve(4 * nt);
  for (std::size_t t = 0; t < nt; ++t) {
    for (int f = 0; f < 4; ++f) {
      std::array<std::uint32_t, 3> v{};
      for (int k = 0; k < 3; ++k)
        v[static_cast<std::size_t>(k)] = tets[4 * t + static_cast<std::size_t>(kOutward[f][k])];
      std::sort(v.begin(), v.end());
      faces.push_back(
          {v[0], v[1], v[2], static_cast<std::uint32_t>(4 * t) + static_cast<std::uint32_t>(f)});
    }
  }
  std::sort(faces.begin(), faces.end());
  struct Face {
    std::int32_t tag;
    std::uint32_t code;  // 4 tet + facet, of the tet of the lower region tag
    std::int32_t low, high;
  };
  std::vector<Face> found;
  for (std::size_t i = 0; i + 1 < faces.size(); ++i) {
    const auto& a = faces[i];
    const auto& b = faces[i + 1];
    if (a[0] != b[0] || a[1] != b[1] || a[2] != b[2]) continue;
    const std::int32_t ta = result.tet_tags[a[3] / 4], tb = result.tet_tags[b[3] / 4];
    if (ta == tb) continue;
    const std::uint32_t code = ta < tb ? a[3] : b[3];
    double c[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) {
      for (int q = 0; q < 3; ++q)
        c[q] += result.xyz[3 * std::size_t{a[static_cast<std::size_t>(k)]} +
                           static_cast<std::size_t>(q)] /
                3;
    }
    // The file's tag of the nearest input interface triangle, else one per interface.
    const std::uint32_t nearest = sampled_tree.closest(c).triangle;
    const std::uint32_t shell = s.shell_of(nearest);
    const std::int32_t input = interfaces.refs.empty() ? 0 : interfaces.refs[nearest];
    const std::int32_t tag =
        input != 0 ? input
                   : base + static_cast<std::int32_t>(std::max<std::uint32_t>(rank[shell], 1));
    found.push_back({tag, code, std::min(ta, tb), std::max(ta, tb)});
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
      result.interface_triangles.push_back(tets[4 * t + static_cast<std::size_t>(kOutward[k][q])]);
    result.interface_tags.push_back(f.tag);
    const bool named = std::any_of(
        result.tag_names.begin(), result.tag_names.end(),
        [&](const TetMeshInput::TagName& n) { return n.dimension == 2 && n.tag == f.tag; });
    if (!named) {
      result.tag_names.push_back(
          {2, f.tag, "interface " + std::to_string(f.low) + "-" + std::to_string(f.high)});
    }
  }
}

std::string interface_distance(const RegionInterfaces& interfaces,
                               const std::function<double(const double*)>& edge_length,
                               double bound, Mesh3Result& result) {
  result.interface_distance_to_edge_length = 0;
  TriangleSurface input, mine;
  input.source = "the input's interfaces";
  input.xyz = interfaces.surfaces.coords();
  const std::vector<std::uint32_t>& all = interfaces.surfaces.surface().triangles();
  input.triangles.assign(all.begin() + 3 * std::ptrdiff_t{interfaces.nb_boundary_triangles},
                         all.end());
  mine.source = "the mesh's interfaces";
  mine.xyz = result.xyz;
  mine.triangles = result.interface_triangles;
  if (input.triangles.empty() || mine.triangles.empty()) {
    return mine.triangles.empty() ? "it has no interface between its regions" : "";
  }
  const SurfaceTree input_tree(input), mine_tree(mine);
  HausdorffOptions relative;
  relative.scale = edge_length;
  const OneSidedDistance forward = sampled_distance(mine, input_tree, relative);
  const OneSidedDistance backward = sampled_distance(input, mine_tree, relative);
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
  ClippedVoronoi3 cv;
  cv.compute(interfaces->surfaces, sites.data(), m);
  boundary.resize(m, 0);
  const Surface3& s = interfaces->surfaces.surface();
  for (std::uint32_t v = 0; v < m; ++v) {
    if (kinds.size() > v && kinds[v] != Kind::kFree) continue;
    if (cv.is_boundary(v) && (both_sides || s.locate(&sites[3 * std::size_t{v}]) != Sign::positive))
      boundary[v] = 1;
  }
}

}  // namespace voroclip::mesh3
