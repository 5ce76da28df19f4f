// Exact self-intersection test of a triangle surface (Surface3 validation; the method is in
// clip/src/surface_intersect.cpp).
#pragma once

#include <cstdint>
#include <vector>

namespace voroclip::detail {

// Two triangles of a surface that meet where they should not.
struct TrianglePair {
  static constexpr std::uint32_t kNone = 0xffffffffu;
  std::uint32_t a = kNone, b = kNone;  // a < b; kNone: no such pair
  bool found() const { return a != kNone; }
};

// The first pair of triangles (smallest a, then smallest b) whose intersection is more
// than what they share: for two triangles with no common vertex, any common point (touching
// counts); with one common vertex, any common point but that vertex; with a common edge,
// any common point off that edge (the two triangles fold onto each other: coplanar and on
// the same side of the edge). Exact (orient3d and orient2d, filtered; no epsilon).
//
// Preconditions (Surface3 checks them first): every index < xyz.size() / 3, finite
// coordinates, no triangle with a repeated vertex or of zero area, vertices with equal
// coordinates welded to one index, no two triangles on the same three vertices.
// Parallel (TBB); the answer does not depend on the thread count.
TrianglePair first_intersecting_pair(const std::vector<double>& xyz,
                                     const std::vector<std::uint32_t>& triangles);

}  // namespace voroclip::detail
