// A bounding-volume hierarchy over boxes, shared by SurfaceTree (triangles) and
// FeatureTree (segments): the build (median splits) and the nearest-first traversal.
// Internal: not installed.
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

namespace voroclip::detail {

constexpr std::uint32_t kBvhLeafSize = 4;

// Squared distance from p to the box [lo, hi] (0 inside).
inline double box_distance2(const double* lo, const double* hi, const double* p) {
  double d2 = 0;
  for (int k = 0; k < 3; ++k) {
    const double d = p[k] < lo[k] ? lo[k] - p[k] : (p[k] > hi[k] ? p[k] - hi[k] : 0.0);
    d2 += d * d;
  }
  return d2;
}

// Builds a hierarchy over n primitives whose boxes are box[6 i .. 6 i + 6) (lo xyz, hi
// xyz), appending its nodes to `nodes` (Node has lo[3], hi[3], first, count). `order`
// receives the primitives in leaf order; a leaf's `first` is an index into `order` plus
// `first_offset`; an inner node's children are nodes first and first + 1. Splits at the
// median of the box centres along the longest axis of their extent (ties by index, so the
// tree is a function of the input alone). Returns the root's index; n must be > 0.
template <class Node>
std::uint32_t build_bvh(const std::vector<double>& box, std::uint32_t n, std::vector<Node>& nodes,
                        std::vector<std::uint32_t>& order, std::uint32_t first_offset) {
  order.resize(n);
  for (std::uint32_t i = 0; i < n; ++i) order[i] = i;
  const auto root = static_cast<std::uint32_t>(nodes.size());
  nodes.emplace_back();
  struct Task {
    std::uint32_t node, begin, end;
  };
  std::vector<Task> stack{{root, 0, n}};
  const auto centre = [&](std::uint32_t i, int k) {
    return box[6 * std::size_t{i} + static_cast<std::size_t>(k)] +
           box[6 * std::size_t{i} + 3 + static_cast<std::size_t>(k)];
  };
  while (!stack.empty()) {
    const Task task = stack.back();
    stack.pop_back();
    double lo[3], hi[3], clo[3], chi[3];
    for (int k = 0; k < 3; ++k) {
      lo[k] = clo[k] = std::numeric_limits<double>::infinity();
      hi[k] = chi[k] = -std::numeric_limits<double>::infinity();
    }
    for (std::uint32_t j = task.begin; j < task.end; ++j) {
      const double* b = &box[6 * std::size_t{order[j]}];
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], b[k]);
        hi[k] = std::max(hi[k], b[3 + k]);
        const double c = centre(order[j], k);
        clo[k] = std::min(clo[k], c);
        chi[k] = std::max(chi[k], c);
      }
    }
    Node& node = nodes[task.node];
    for (int k = 0; k < 3; ++k) {
      node.lo[k] = lo[k];
      node.hi[k] = hi[k];
    }
    if (task.end - task.begin <= kBvhLeafSize) {
      node.first = first_offset + task.begin;
      node.count = task.end - task.begin;
      continue;
    }
    int axis = 0;
    for (int k = 1; k < 3; ++k) {
      if (chi[k] - clo[k] > chi[axis] - clo[axis]) axis = k;
    }
    const std::uint32_t mid = task.begin + (task.end - task.begin) / 2;
    std::nth_element(order.begin() + task.begin, order.begin() + mid, order.begin() + task.end,
                     [&](std::uint32_t a, std::uint32_t b) {
                       const double ca = centre(a, axis), cb = centre(b, axis);
                       return ca < cb || (ca == cb && a < b);
                     });
    const auto children = static_cast<std::uint32_t>(nodes.size());
    nodes[task.node].first = children;
    nodes[task.node].count = 0;
    nodes.emplace_back();
    nodes.emplace_back();
    stack.push_back({children + 1, mid, task.end});
    stack.push_back({children, task.begin, mid});
  }
  return root;
}

// Visits the leaves of the tree at `root` whose box is not farther from p than `best2`,
// nearer child first: leaf(first, count) may lower best2. Boxes at exactly best2 are
// visited (ties are decided by the caller's leaf test).
template <class Node, class Leaf>
void nearest_leaves(const std::vector<Node>& nodes, std::uint32_t root, const double* p,
                    double& best2, Leaf&& leaf) {
  struct Entry {
    std::uint32_t node;
    double d2;
  };
  Entry stack[128];
  int top = 0;
  stack[top++] = {root, box_distance2(nodes[root].lo, nodes[root].hi, p)};
  while (top > 0) {
    const Entry e = stack[--top];
    if (e.d2 > best2) continue;
    const Node& node = nodes[e.node];
    if (node.count > 0) {
      leaf(node.first, node.count);
      continue;
    }
    const std::uint32_t a = node.first, b = node.first + 1;
    const double da = box_distance2(nodes[a].lo, nodes[a].hi, p);
    const double db = box_distance2(nodes[b].lo, nodes[b].hi, p);
    // The nearer child is pushed last, so it is visited first.
    if (da <= db) {
      if (db <= best2) stack[top++] = {b, db};
      if (da <= best2) stack[top++] = {a, da};
    } else {
      if (da <= best2) stack[top++] = {a, da};
      if (db <= best2) stack[top++] = {b, db};
    }
  }
}

}  // namespace voroclip::detail
