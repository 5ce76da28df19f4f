// voroclip/mesh.h — mesh generation (the module's one public header).
#pragma once

#include <cstdint>
#include <vector>

#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/cvt.h"

namespace voroclip {

// =======================================================================================
// 3D sizing field (paper sec. 5.2, "Initialization", after Alliez, Cohen-Steiner, Yvinec
// & Desbrun, "Variational tetrahedral meshing", SIGGRAPH 2005, sec. 5).
//
// The local feature size (lfs) of each boundary vertex is its distance to the medial
// axis, approximated by the poles of the Voronoi diagram of the boundary vertices
// (Amenta & Bern 1999): the inner pole of vertex v is the farthest Voronoi vertex of v's
// cell on the inner side of the surface (the side opposite its outward normal), the outer
// pole the farthest on the outer side (none for a vertex of the convex hull, whose cell is
// unbounded outwards); lfs(v) is the distance from v to the nearer of its poles (the
// pole distance; on a dense sampling it approaches the distance to the medial axis).
// The sizing field is the largest g-Lipschitz function below lfs on the boundary,
//     h(x) = max(h_min, min over boundary vertices v of (lfs(v) + g |x - v|)),
// sampled at the nodes of a regular grid over the domain's bounding box (the minimising
// vertex of each node found by propagation over grid neighbours, as in vector distance
// transforms, and the value computed exactly for it) and interpolated trilinearly.
// h_min = max lfs / max_ratio keeps sharp edges (where lfs tends to 0) from asking for
// arbitrarily small elements. Only relative sizes matter for CVT meshing: the density is
// rho = h^-(d+2) = h^-5 (the CVT energy's scaling, Du, Faber & Gunzburger 1999), and the
// number of vertices sets the absolute scale.
struct Sizing3Options {
  double gradation = 0.5;         // g: h grows by at most g per unit length
  double max_ratio = 20;          // h_min = max lfs / max_ratio
  std::uint32_t resolution = 64;  // grid nodes along the longest side of the bounding box
};

class SizingField3 {
 public:
  // Throws Error for a domain without boundary triangles, or invalid options.
  SizingField3(const Domain3& domain, const Sizing3Options& options = {});

  // h at p (trilinear on the grid; points outside the grid clamp to it).
  double size(const double* p) const;
  // rho = h^-5 at every vertex of the domain (for Clip3Options::vertex_density and
  // random_points3).
  std::vector<double> vertex_density(const Domain3& domain) const;

  // Per domain vertex: its lfs estimate if it is a boundary vertex, else 0.
  const std::vector<double>& vertex_lfs() const { return lfs_; }
  double min_size() const { return h_min_; }
  // The grid: n[0] x n[1] x n[2] nodes from lo with spacing `spacing`, values x-fastest.
  const std::uint32_t* grid_size() const { return n_; }
  const double* grid_origin() const { return lo_; }
  double grid_spacing() const { return spacing_; }
  const std::vector<double>& grid_values() const { return h_; }

 private:
  std::vector<double> lfs_;
  std::vector<double> h_;
  std::uint32_t n_[3] = {0, 0, 0};
  double lo_[3] = {0, 0, 0};
  double spacing_ = 1;
  double h_min_ = 0;
};

}  // namespace voroclip
