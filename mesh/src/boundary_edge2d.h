// The domain edge under a boundary edge a -> b of a 2D mesh (the domain on its left, so
// it runs with the ring), from the vertices' domain data: the edge starting at a's domain
// vertex or holding a; else the edge holding b or ending at b's domain vertex; kNone when
// neither vertex has boundary data. Used by the tags (tag_mesh2) and the refinement.
#pragma once

#include <cstdint>

#include "voroclip/mesh.h"

namespace voroclip::mesh2d {

inline std::uint32_t domain_edge_under(const Domain2& domain, const Mesh2& mesh, std::uint32_t a,
                                       std::uint32_t b) {
  if (mesh.vertex_domain[a] != Mesh2::kNone) return mesh.vertex_domain[a];
  if (mesh.vertex_edge[a] != Mesh2::kNone) return mesh.vertex_edge[a];
  if (mesh.vertex_edge[b] != Mesh2::kNone) return mesh.vertex_edge[b];
  if (mesh.vertex_domain[b] != Mesh2::kNone) return domain.prev(mesh.vertex_domain[b]);
  return Mesh2::kNone;
}

}  // namespace voroclip::mesh2d
