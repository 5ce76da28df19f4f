// Constrained Delaunay triangulation in the plane, from a Delaunay triangulation by
// segment insertion.
//
// A segment a-b is inserted by the flip algorithm of Sloan (1993, "A fast algorithm for
// generating constrained Delaunay triangulations"): the edges it crosses are collected by a
// walk from a, then each is flipped when its quadrilateral is strictly convex, and queued
// again (after the others) when it is not or when the flipped edge still crosses a-b;
// every quadrilateral left is convex eventually, so the queue empties with a-b an edge.
// A vertex lying exactly on a-b splits it into two segments. Once every segment is in,
// Lawson flips of the unconstrained edges (a flip when the opposite vertex is strictly
// inside the circumcircle) make the triangulation constrained Delaunay. Every decision is
// an exact orient2d or incircle sign; ties never flip.
//
// Storage: triangles as in Delaunay2 (counter-clockwise vertices; edge k is opposite
// vertex k), neighbours as codes 3t + k of the edge across, kNone on the convex hull, and a
// constrained flag per half-edge (set on both sides).
#pragma once

#include <cstdint>
#include <vector>

#include "voroclip/delaunay.h"

namespace voroclip::mesh2d {

class Cdt2 {
 public:
  static constexpr std::uint32_t kNone = 0xffffffffu;

  // The finite triangles of dt, with its points (dt must outlive this object).
  explicit Cdt2(const Delaunay2& dt);

  // Inserts the segment between vertices a and b (vertices of dt: duplicate_of(v) == v) as
  // constrained edges (split at the vertices lying exactly on it); the pieces, from a to
  // b, are appended to `pieces` as vertex pairs when given. Throws Error when it crosses a
  // segment inserted before (the two are named by their vertices).
  void insert_segment(std::uint32_t a, std::uint32_t b,
                      std::vector<std::uint32_t>* pieces = nullptr);
  // Lawson flips of the unconstrained edges until the triangulation is constrained
  // Delaunay; returns the number of flips.
  std::uint32_t make_delaunay();

  std::uint32_t nb_triangles() const { return static_cast<std::uint32_t>(v_.size() / 3); }
  std::uint32_t vertex(std::uint32_t t, int k) const { return v_[3 * std::size_t{t} + k]; }
  // The code 3u + j of the edge across edge k of t, or kNone on the hull.
  std::uint32_t across(std::uint32_t t, int k) const { return adj_[3 * std::size_t{t} + k]; }
  bool constrained(std::uint32_t t, int k) const { return con_[3 * std::size_t{t} + k] != 0; }
  // The triangle holding the directed edge a -> b counter-clockwise, and the local index
  // of the edge in it (the index of its third vertex), or kNone when a-b is no such edge.
  std::uint32_t find_edge(std::uint32_t a, std::uint32_t b, int* k) const;
  std::uint32_t nb_flips() const { return flips_; }

 private:
  const double* point(std::uint32_t v) const { return dt_->point(v); }
  void link(std::uint32_t code, std::uint32_t other);
  // Flips edge k of t; t and its neighbour keep their slots.
  void flip(std::uint32_t t, int k);
  // Triangles incident to a, in counter-clockwise order when a is inside the hull.
  void star(std::uint32_t a, std::vector<std::uint32_t>& out) const;
  void set_constrained(std::uint32_t a, std::uint32_t b);
  // Makes the sub-segment a-c an edge (the edges crossed by it are `crossed`, as vertex
  // pairs, the first one right of a -> c).
  void flip_out(std::uint32_t a, std::uint32_t c, std::vector<std::uint32_t>& crossed);

  const Delaunay2* dt_;
  std::vector<std::uint32_t> v_, adj_;
  std::vector<std::uint8_t> con_;
  std::vector<std::uint32_t> vtri_;  // per vertex: one incident triangle, or kNone
  std::vector<std::uint32_t> scratch_;
  std::uint32_t flips_ = 0;
};

}  // namespace voroclip::mesh2d
