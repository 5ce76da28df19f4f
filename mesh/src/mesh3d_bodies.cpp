// mesh3d of a domain of several bodies (mesh3d_pipeline.h): each body, an outer shell with
// the cavities directly inside it, meshed on its own and the meshes put together.
//
// One CVT over all the bodies would let a site's Voronoi cell hold pieces of two bodies
// wherever they are closer than the spacing: the extraction then bridges the gap with tets
// and the topology refinement, which adds sites at such cells, feeds itself (two boxes
// 0.01 apart at 1,000 vertices failed after three retries). Bodies meshed apart have no
// such cells, whatever the gaps.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "mesh3d_pipeline.h"
#include "mesh3d_tags.h"
#include "union_find.h"
#include "voroclip/mesh.h"

namespace voroclip::mesh3 {

namespace {

// Body b of a surface domain: its triangles, in the domain's order, over all the domain's
// vertices (the unused ones are ignored), so that vertex numbers stay the input's.
Domain3 surface_body(const Domain3& domain, const std::vector<std::uint32_t>& body_of_shell,
                     std::uint32_t b) {
  const Surface3& s = domain.surface();
  TriangleSurface t;
  t.source = domain.source();
  t.xyz = domain.coords();
  for (std::uint32_t f = 0; f < s.nb_triangles(); ++f) {
    if (body_of_shell[s.shell_of(f)] == b)
      t.triangles.insert(t.triangles.end(), s.triangle(f), s.triangle(f) + 3);
  }
  return Domain3(t);
}

// The bodies of a tet-mesh domain: its face-connected tets, with their tags, and the
// boundary triangles with theirs.
std::vector<Domain3> tet_bodies(const Domain3& domain,
                                const std::vector<std::uint32_t>& body_of_shell,
                                std::uint32_t nb_bodies) {
  const Surface3& s = domain.surface();
  const std::uint32_t nt = domain.nb_tets();
  UnionFind components(nt);
  for (std::uint32_t t = 0; t < nt; ++t) {
    for (int f = 0; f < 4; ++f) {
      const std::uint32_t u = domain.tet_adjacent(t, f);
      if (u != Domain3::kNone) components.unite(t, u);
    }
  }
  std::vector<std::uint32_t> body_of_root(nt, Domain3::kNone);
  for (std::uint32_t b = 0; b < s.nb_triangles(); ++b) {
    body_of_root[components.find(domain.boundary_tet(b))] = body_of_shell[s.shell_of(b)];
  }
  std::vector<TetMeshInput> inputs(nb_bodies);
  for (TetMeshInput& in : inputs) {
    in.source = domain.source();
    in.xyz = domain.coords();
    in.tag_names = domain.tag_names();
  }
  const std::vector<std::int32_t>& tet_refs = domain.tet_refs();
  for (std::uint32_t t = 0; t < nt; ++t) {
    TetMeshInput& in = inputs[body_of_root[components.find(t)]];
    for (int k = 0; k < 4; ++k) in.tets.push_back(domain.tet_vertex(t, k));
    if (!tet_refs.empty()) in.tet_ref.push_back(tet_refs[t]);
  }
  const std::vector<std::int32_t>& triangle_refs = domain.boundary_refs();
  if (!triangle_refs.empty()) {
    for (std::uint32_t b = 0; b < s.nb_triangles(); ++b) {
      TetMeshInput& in = inputs[body_of_shell[s.shell_of(b)]];
      in.triangles.insert(in.triangles.end(), s.triangle(b), s.triangle(b) + 3);
      in.triangle_ref.push_back(triangle_refs[b]);
    }
  }
  std::vector<Domain3> bodies;
  bodies.reserve(nb_bodies);
  for (const TetMeshInput& in : inputs) bodies.emplace_back(in);
  return bodies;
}

void add_cvt(CvtResult& into, const CvtResult& r, bool first) {
  if (first) {
    into = r;
    return;
  }
  into.iterations = std::max(into.iterations, r.iterations);
  into.evaluations += r.evaluations;
  into.energy += r.energy;
  into.gradient_norm = std::hypot(into.gradient_norm, r.gradient_norm);
  into.initial_gradient_norm = std::hypot(into.initial_gradient_norm, r.initial_gradient_norm);
  into.seconds += r.seconds;
  if (into.converged && !r.converged) into.stop = r.stop;
  into.converged = into.converged && r.converged;
  into.cancelled = into.cancelled || r.cancelled;
}

void add_extraction(Extract3Stats& into, const Extract3Stats& r) {
  into.nb_delaunay_tets += r.nb_delaunay_tets;
  into.nb_inside += r.nb_inside;
  into.nb_on_boundary += r.nb_on_boundary;
  into.nb_filled += r.nb_filled;
  into.nb_creases += r.nb_creases;
  into.nb_carved += r.nb_carved;
  into.nb_nonmanifold_edges += r.nb_nonmanifold_edges;
  into.nb_nonmanifold_vertices += r.nb_nonmanifold_vertices;
  into.nb_added += r.nb_added;
  into.nb_removed += r.nb_removed;
  into.nb_repair_passes = std::max(into.nb_repair_passes, r.nb_repair_passes);
  into.nb_kept += r.nb_kept;
  into.seconds += r.seconds;
}

void add_perturbation(Perturb3Stats& into, const Perturb3Stats& r, bool first) {
  if (first) {
    into = r;
    return;
  }
  into.rounds = std::max(into.rounds, r.rounds);
  into.moves += r.moves;
  into.initial_slivers += r.initial_slivers;
  into.final_slivers += r.final_slivers;
  into.initial_min_dihedral_deg =
      std::min(into.initial_min_dihedral_deg, r.initial_min_dihedral_deg);
  into.final_min_dihedral_deg = std::min(into.final_min_dihedral_deg, r.final_min_dihedral_deg);
  into.seconds += r.seconds;
  into.cancelled = into.cancelled || r.cancelled;
  into.undone = into.undone || r.undone;
}

// "(x, y, z)" of the centre of a body's bounding box (brief: 4 significant digits).
std::string centre(const Domain3& body) {
  std::string s = "(";
  for (int k = 0; k < 3; ++k)
    s += (k ? ", " : "") + brief(0.5 * (body.bbox_lo()[k] + body.bbox_hi()[k]));
  return s + ")";
}

}  // namespace

std::vector<Domain3> domain_bodies(const Domain3& domain) {
  const std::vector<Surface3::Shell>& shells = domain.surface().shells();
  std::vector<std::uint32_t> body_of_shell(shells.size(), 0);
  std::uint32_t nb_bodies = 0;
  for (std::size_t h = 0; h < shells.size(); ++h) {
    if (!shells[h].cavity()) body_of_shell[h] = nb_bodies++;
  }
  if (nb_bodies <= 1) return {};
  for (std::size_t h = 0; h < shells.size(); ++h) {
    // A cavity's innermost enclosing shell bounds its body from outside.
    if (shells[h].cavity()) body_of_shell[h] = body_of_shell[shells[h].parent];
  }
  if (domain.has_tets()) return tet_bodies(domain, body_of_shell, nb_bodies);
  std::vector<Domain3> bodies;
  bodies.reserve(nb_bodies);
  for (std::uint32_t b = 0; b < nb_bodies; ++b)
    bodies.push_back(surface_body(domain, body_of_shell, b));
  return bodies;
}

namespace {

// The bodies meshed once with the count of `options`; `clash`: the whole's shape check failed
// though each body's mesh has its shape (two bodies' meshes meet).
Mesh3Result mesh_bodies_once(const Domain3& domain, const std::vector<Domain3>& bodies,
                             const Mesh3Options& options, bool& clash) {
  clash = false;
  const auto t_start = std::chrono::steady_clock::now();
  const std::uint32_t nb_bodies = static_cast<std::uint32_t>(bodies.size());
  const std::vector<double> integral = body_site_integrals(bodies, options);
  double total = 0;
  for (const double i : integral) total += i;

  Mesh3Result result;
  result.requested_vertices = options.nb_vertices;
  result.nb_bodies = nb_bodies;
  const bool own_patch_tags = domain.boundary_refs().empty();
  const bool own_region_tags = domain.tet_refs().empty();
  // The fresh tags of what the file leaves untagged, chosen once over all the bodies: a
  // body's run picks them among its own tags only, so that two bodies could give their
  // untagged boundary two tags, or one of them another body's real tag. A body's fresh tag
  // becomes the whole's for the same input tag; a body whose triangles are all untagged (no
  // boundary_refs of its own, its patches the mesher's) takes the whole's for tag 0.
  const UntaggedTags whole_untagged = untagged_tags(domain);
  const auto to_whole = [](const std::vector<std::pair<std::int32_t, std::int32_t>>& body,
                           const std::vector<std::pair<std::int32_t, std::int32_t>>& whole,
                           std::int32_t t) {
    for (const auto& [from, to] : body) {
      if (to == t) return UntaggedTags::map(whole, from);
    }
    return t;
  };
  std::int32_t patch_offset = 0;
  // The interface tags each body's run made up (one per pair of regions, after that body's
  // patch tags, named "interface a-b"), numbered again after every body's tags below, so that
  // two bodies' interfaces never share a tag: (body, its tag) per interface triangle, and the
  // names.
  const std::vector<std::int32_t> file_tags = file_interface_tags(domain);
  std::vector<std::pair<std::uint32_t, std::int32_t>> made_up;  // per interface triangle
  std::vector<std::pair<std::pair<std::uint32_t, std::int32_t>, std::string>> made_up_names;
  double volume_capped = 0, mean_before = 0, mean_after = 0;
  for (std::uint32_t b = 0; b < nb_bodies; ++b) {
    Mesh3Options o = options;
    o.nb_vertices = static_cast<std::uint32_t>(
        std::max(4.0, std::round(options.nb_vertices * (integral[b] / total))));
    if (options.progress) {
      Mesh3Progress start;
      start.body = b + 1;
      start.nb_bodies = nb_bodies;
      start.body_vertices = o.nb_vertices;
      if (!options.progress(start)) {
        result.cancelled = true;
        break;
      }
      o.progress = [&options, b, nb_bodies](const Mesh3Progress& p) {
        Mesh3Progress q = p;
        q.body = b + 1;
        q.nb_bodies = nb_bodies;
        return options.progress(q);
      };
    }
    const std::string which = "body " + std::to_string(b + 1) + " of " + std::to_string(nb_bodies) +
                              " (the one around " + centre(bodies[b]) + ")";
    Mesh3Result r;
    try {
      r = mesh3d(bodies[b], o);
    } catch (const Error& e) {
      // The body's error, named, with its share: its counts (VertexCount::kExact: the count
      // that would do) are the body's, and scale to the whole by that share.
      const std::string what = e.what();
      const std::string head = "mesh3d: ";
      throw Error(head + which + ", its share " + std::to_string(o.nb_vertices) + " of the " +
                  std::to_string(options.nb_vertices) + " vertices: " +
                  (what.compare(0, head.size(), head) == 0 ? what.substr(head.size()) : what));
    }
    if (r.cancelled) {
      result.cancelled = true;
      break;
    }
    if (result.shape_problem.empty() && !r.shape_problem.empty())
      result.shape_problem = which + ": " + r.shape_problem;
    if (result.raised_because.empty() && !r.raised_because.empty())
      result.raised_because = which + ": " + r.raised_because;
    result.shape_retries = std::max(result.shape_retries, r.shape_retries);

    // The mesh: vertices and tets appended, tags renumbered for the whole.
    const std::uint32_t base = result.nb_vertices();
    result.xyz.insert(result.xyz.end(), r.xyz.begin(), r.xyz.end());
    result.kinds.insert(result.kinds.end(), r.kinds.begin(), r.kinds.end());
    for (const std::uint32_t v : r.tets) result.tets.push_back(base + v);
    for (const std::uint32_t v : r.boundary_triangles)
      result.boundary_triangles.push_back(base + v);
    const UntaggedTags body_untagged = untagged_tags(bodies[b]);
    const bool body_untagged_only = bodies[b].boundary_refs().empty();
    std::int32_t largest = 0;
    for (const std::int32_t t : r.boundary_tags) {
      result.boundary_tags.push_back(own_patch_tags ? t + patch_offset
                                     : body_untagged_only
                                         ? UntaggedTags::map(whole_untagged.patch, 0)
                                         : to_whole(body_untagged.patch, whole_untagged.patch, t));
      largest = std::max(largest, t);
    }
    patch_offset += largest;
    // The interfaces' triangles and tags: the file's as they are, the made-up ones for later.
    for (const std::uint32_t v : r.interface_triangles)
      result.interface_triangles.push_back(base + v);
    const auto is_file_tag = [&](std::int32_t t) {
      return std::binary_search(file_tags.begin(), file_tags.end(), t);
    };
    for (const std::int32_t t : r.interface_tags) {
      result.interface_tags.push_back(t);
      made_up.emplace_back(b, is_file_tag(t) ? 0 : t);
    }
    for (const TetMeshInput::TagName& name : r.tag_names) {
      if (name.dimension != 2 || std::find(r.interface_tags.begin(), r.interface_tags.end(),
                                           name.tag) == r.interface_tags.end()) {
        continue;
      }
      if (is_file_tag(name.tag)) {
        if (std::none_of(result.tag_names.begin(), result.tag_names.end(),
                         [&](const TetMeshInput::TagName& n) {
                           return n.dimension == 2 && n.tag == name.tag;
                         })) {
          result.tag_names.push_back(name);
        }
      } else {
        made_up_names.push_back({{b, name.tag}, name.name});
      }
    }
    for (const std::int32_t t : r.tet_tags) {
      result.tet_tags.push_back(own_region_tags
                                    ? static_cast<std::int32_t>(b + 1)
                                    : to_whole(body_untagged.region, whole_untagged.region, t));
    }

    // The figures: counts summed, the rest as each field says.
    result.nb_sites += r.nb_sites;
    result.nb_dropped_sites += r.nb_dropped_sites;
    result.nb_boundary_sites += r.nb_boundary_sites;
    result.nb_feature_sites += r.nb_feature_sites;
    result.nb_corner_sites += r.nb_corner_sites;
    result.nb_feature_lines += r.nb_feature_lines;
    result.nb_feature_corners += r.nb_feature_corners;
    result.nb_distance_sites += r.nb_distance_sites;
    result.nb_distance_sites_added += r.nb_distance_sites_added;
    volume_capped += r.lfs_capped_fraction * bodies[b].volume();
    result.lfs_cap_spacing = std::max(result.lfs_cap_spacing, r.lfs_cap_spacing);
    add_cvt(result.unconstrained, r.unconstrained, b == 0);
    add_cvt(result.constrained, r.constrained, b == 0);
    add_extraction(result.extraction, r.extraction);
    add_perturbation(result.perturbation, r.perturbation, b == 0);
    result.nb_peeled += r.nb_peeled;
    result.nb_tets_across_regions += r.nb_tets_across_regions;
    result.nb_interfaces_followed += r.nb_interfaces_followed;
    if (result.interfaces_not_followed.empty())
      result.interfaces_not_followed = r.interfaces_not_followed;
    result.nb_topology_sites += r.nb_topology_sites;
    result.topology_rounds = std::max(result.topology_rounds, r.topology_rounds);
    result.topology_defects_left += r.topology_defects_left;
    if (r.topology_capped && !result.topology_capped) {
      result.topology_capped = true;
      result.topology_capped_near = r.topology_capped_near;
      // The count of a uniform spacing over all the bodies.
      const double t = r.topology_capped_thickness;
      result.topology_capped_thickness = t;
      if (t > 0) result.topology_capped_vertices = domain.volume() / (4 * t * t * t);
    }
    result.nb_topology_deferred += r.nb_topology_deferred;
    result.nb_sliver_sites += r.nb_sliver_sites;
    result.nb_sliver_sites_inside += r.nb_sliver_sites_inside;
    result.nb_flips += r.nb_flips;
    result.nb_flip_moves += r.nb_flip_moves;
    result.nb_flip_sites += r.nb_flip_sites;
    result.nb_boundary_flips += r.nb_boundary_flips;
    result.flips_rerun_for_shape = result.flips_rerun_for_shape || r.flips_rerun_for_shape;
    result.nb_mean_flips += r.nb_mean_flips;
    result.nb_mean_moves += r.nb_mean_moves;
    result.mean_rounds = std::max(result.mean_rounds, r.mean_rounds);
    mean_before += r.mean_q1_before_deg * r.nb_tets();
    mean_after += r.mean_q1_after_deg * r.nb_tets();
    result.mean_seconds += r.mean_seconds;
    result.distance_to_edge_length =
        std::max(result.distance_to_edge_length, r.distance_to_edge_length);
    result.interface_distance_to_edge_length =
        std::max(result.interface_distance_to_edge_length, r.interface_distance_to_edge_length);
    result.distance_seconds += r.distance_seconds;
    for (int k = 0; k < kNbMesh3Phases; ++k) result.seconds[k] += r.seconds[k];
  }
  if (result.cancelled) {
    result.xyz.clear();
    result.kinds.clear();
    result.tets.clear();
    result.boundary_triangles.clear();
    result.boundary_tags.clear();
    result.interface_triangles.clear();
    result.interface_tags.clear();
    result.tet_tags.clear();
    result.total_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    return result;
  }
  // The made-up interface tags after every other triangle tag, by body, then by the body's
  // own order.
  {
    std::int32_t top = 0;
    for (const std::int32_t t : result.boundary_tags) top = std::max(top, t);
    for (const std::int32_t t : file_tags) top = std::max(top, t);
    std::vector<std::pair<std::uint32_t, std::int32_t>> keys;
    for (const auto& key : made_up) {
      if (key.second != 0) keys.push_back(key);
    }
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    const auto renumbered = [&](const std::pair<std::uint32_t, std::int32_t>& key) {
      return top + 1 +
             static_cast<std::int32_t>(std::lower_bound(keys.begin(), keys.end(), key) -
                                       keys.begin());
    };
    for (std::size_t i = 0; i < made_up.size(); ++i) {
      if (made_up[i].second != 0) result.interface_tags[i] = renumbered(made_up[i]);
    }
    for (const auto& [key, name] : made_up_names)
      result.tag_names.push_back({2, renumbered(key), name});
  }
  const auto t_whole = std::chrono::steady_clock::now();
  result.lfs_capped_fraction = volume_capped / domain.volume();
  if (result.nb_tets() > 0) {
    result.mean_q1_before_deg = mean_before / result.nb_tets();
    result.mean_q1_after_deg = mean_after / result.nb_tets();
  }
  name_and_group_tags(domain, result);
  measure_mesh3_quality(domain, result);
  // The distance of the whole boundary to the whole input; the meshes of two bodies closer
  // than their edges' sag may overlap, which only the whole's shape check sees.
  const TriangleSurface reference = boundary_surface(domain);
  TriangleSurface mine;
  mine.source = "the mesh's boundary";
  mine.xyz = result.xyz;
  mine.triangles = result.boundary_triangles;
  if (!mine.triangles.empty()) {
    result.distance =
        hausdorff_distance(mine, SurfaceTree(mine), reference, SurfaceTree(reference));
  }
  if (result.shape_problem.empty()) {
    result.shape_problem = check_mesh3_shape(domain, result.xyz, result.tets);
    clash = !result.shape_problem.empty();
  }
  const double whole =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_whole).count();
  result.seconds[static_cast<int>(Mesh3Phase::kQuality)] += whole;
  result.total_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  return result;
}

}  // namespace

Mesh3Result mesh3d_bodies(const Domain3& domain, const std::vector<Domain3>& bodies,
                          const Mesh3Options& options) {
  bool clash = false;
  Mesh3Result result = mesh_bodies_once(domain, bodies, options, clash);
  if (options.vertex_count != Mesh3Options::VertexCount::kRaise) return result;
  // Each body's mesh has its shape but two of them meet: where two bodies are closer than
  // their triangles' sag (a ball in a cavity 0.01 wider at 3,000 vertices). Again with twice
  // the vertices, as mesh3d does for one body.
  result = raise_vertices(
      options, std::move(result),
      [&](const Mesh3Options& raised) { return mesh_bodies_once(domain, bodies, raised, clash); },
      [&clash](const Mesh3Result&) { return clash; }, "the meshes of the bodies meet: ");
  return result;
}

}  // namespace voroclip::mesh3
