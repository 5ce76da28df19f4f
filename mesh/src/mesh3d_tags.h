// The boundary triangles of a 3D CVT mesh and the tags a solver's boundary conditions and
// materials need (mesh.h, Mesh3Result: boundary_triangles, boundary_tags, tet_tags);
// mesh3d_tags.cpp. Internal to the mesh module.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "voroclip/mesh.h"

namespace voroclip::mesh3 {

struct TetRegions;  // mesh3d_pipeline.h

// The facet opposite vertex f of a right-handed tet, counter-clockwise seen from outside.
constexpr int kOutwardFacet[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

// A facet of a tet mesh: its sorted vertices and 4 tet + facet (opposite vertex).
struct FaceRef {
  std::array<std::uint32_t, 3> key;
  std::uint32_t code;
  bool operator<(const FaceRef& o) const { return key != o.key ? key < o.key : code < o.code; }
};
// Every tet facet, sorted by its vertices: a boundary facet appears once, an inner one
// twice (consecutive).
std::vector<FaceRef> sorted_faces(const std::vector<std::uint32_t>& tets);

// The faces of exactly one tet of `tets` (4 vertex indices each, right-handed: det(p1 - p0,
// p2 - p0, p3 - p0) > 0), oriented outward (counter-clockwise seen from outside), in the
// order of (tet, facet opposite vertex 0..3); `face_tet` gets each one's tet.
void boundary_triangles(const std::vector<std::uint32_t>& tets,
                        std::vector<std::uint32_t>& triangles,
                        std::vector<std::uint32_t>& face_tet);

// The patch tag of each boundary triangle (3 vertex indices each). `vertex_patch_begin` /
// `vertex_patch` list, per vertex, the input patches it lies on (increasing; none for an
// interior vertex); `patch_tag` gives each patch's tag. A triangle takes the one patch its
// three vertices share; when they share none or several (a triangle across a feature line
// the sites did not resolve), the patch of `closest_input[b]`, the input triangle closest
// to its centroid, through `input_patch`.
std::vector<std::int32_t> patch_tags(const std::vector<std::uint32_t>& triangles,
                                     const std::vector<std::uint32_t>& vertex_patch_begin,
                                     const std::vector<std::uint32_t>& vertex_patch,
                                     const std::vector<std::int32_t>& patch_tag,
                                     const std::vector<std::uint32_t>& input_patch,
                                     const std::vector<std::uint32_t>& closest_input);

// The region tag of each tet. With the domain's tet tags (a tet mesh file's regions): the
// tag of the input tet that holds the tet's centroid (exact orient3d tests), or, for a
// centroid outside every input tet (the mesh's boundary is not the input's), the tag of a
// face-adjacent tet, breadth first; when the input has a single tag, that tag. Otherwise
// one region per volume component: its face-connected tets get 1 + the rank, among the
// outer shells of the domain's surface (even depth, in shell order), of the shell that
// bounds them from outside, found from their boundary triangles' closest input triangles
// (`closest_input`, per triangle of `triangles` / `face_tet`). `tets_across`: with several
// input tags, the tets that have a vertex inside the domain but in no (closed) input tet of
// their own tag, so reach across an interface between regions; else 0.
// With `regions` (per tet, the region of a mesh that follows the interfaces between the
// input's regions: mesh3d_interfaces.cpp), each region takes the tag most of its tets'
// centroids lie in (ties to the lower tag), and `tets_across` counts the tets whose centroid
// lies in an input tet of another tag.
std::vector<std::int32_t> region_tags(const Domain3& domain, const std::vector<double>& xyz,
                                      const std::vector<std::uint32_t>& tets,
                                      const std::vector<std::uint32_t>& face_tet,
                                      const std::vector<std::uint32_t>& closest_input,
                                      const std::vector<std::uint32_t>* regions,
                                      std::uint32_t& tets_across);

// The boundary triangles of `result.tets` (outward), grouped by patch tag, with their tags,
// and the tets' region tags and the tag names (Mesh3Result). `triangle_patch`: the patch of
// each triangle of the surface the sites were sampled on, the domain's boundary triangles
// first (the domain's boundary_refs, when the file tags them, tag the patches; else patch p
// gets tag p + 1); `patches`:
// the surface patches of the sites; `index`: each site's vertex in result.xyz,
// SurfaceTree::kNone for a site no tet uses; `regions`: per tet of result.tets its region
// when the mesh follows the interfaces between the input's regions (region_tags).
void tag_mesh3(const Domain3& domain, const SurfaceTree& surface_tree,
               const std::vector<std::uint32_t>& triangle_patch, const SurfacePatches& patches,
               const std::vector<std::uint32_t>& index, const TetRegions* regions,
               Mesh3Result& result);

// Tags for what the input leaves untagged, so that every boundary triangle and every tet of
// the mesh has a positive tag (a Gmsh physical tag; a solver's condition needs one): per
// input tag not above 0 (0: no tag; a Medit ref may be negative), the fresh positive tag it
// becomes, pairs (input tag, fresh tag) in the order 0, -1, -2, ..., the fresh tags the
// smallest positive ones the input does not use in that dimension (its tags and its tag
// names; for triangles, the inner triangles' too), in increasing order. E.g. a Gmsh box with
// only its inlet (11) and outlet (12) in physical surfaces: its walls' triangles, tag 0,
// become patch 1, named "untagged boundary"; tets of refs 0 and -3: regions 1 and 2.
// Without a triangle tag (boundary_refs empty) there is no patch pair; without a tet tag,
// no region pair.
struct UntaggedTags {
  std::vector<std::pair<std::int32_t, std::int32_t>> patch, region;
  // The fresh tag of input tag t (t itself when it is positive or has none).
  static std::int32_t map(const std::vector<std::pair<std::int32_t, std::int32_t>>& pairs,
                          std::int32_t t);
  // The name of fresh tag t in `dimension` (2, 3): "untagged boundary" / "untagged region"
  // for the one of tag 0, "boundary tagged <t>" / "region tagged <t>" for a negative tag's;
  // empty when t is no fresh tag.
  std::string name(int dimension, std::int32_t t) const;
};
UntaggedTags untagged_tags(const Domain3& domain);

// The end of tag_mesh3, also for meshes put together from several (mesh3d_bodies): the
// count of the input's regions, the tag names (the input's of the tags some element has or
// the file's interface triangles have, then untagged_tags' names, then
// "patch <tag>" and "region <tag>" for the tags used without one) and the boundary triangles
// grouped by tag (stable).
void name_and_group_tags(const Domain3& domain, Mesh3Result& result);
}  // namespace voroclip::mesh3
