// Constrained Delaunay triangulation by segment insertion (cdt2.h).
#include "cdt2.h"

#include <deque>
#include <string>
#include <utility>

#include "voroclip/core.h"
#include "voroclip/predicates.h"

namespace voroclip::mesh2d {

namespace {

constexpr int next3(int k) { return k == 2 ? 0 : k + 1; }
constexpr int prev3(int k) { return k == 0 ? 2 : k - 1; }

}  // namespace

Cdt2::Cdt2(const Delaunay2& dt) : dt_(&dt) {
  const std::uint32_t nt = dt.nb_triangles();
  v_.resize(3 * std::size_t{nt});
  adj_.resize(3 * std::size_t{nt});
  con_.assign(3 * std::size_t{nt}, 0);
  vtri_.assign(dt.nb_points(), kNone);
  for (std::uint32_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = dt.tri_vertex(t, k);
      v_[3 * std::size_t{t} + k] = v;
      vtri_[v] = t;
      const std::uint32_t u = dt.tri_adjacent(t, k);
      adj_[3 * std::size_t{t} + k] =
          u < nt && !dt.is_infinite(u)
              ? 3 * u + static_cast<std::uint32_t>(dt.tri_adjacent_edge(t, k))
              : kNone;
    }
  }
}

void Cdt2::link(std::uint32_t code, std::uint32_t other) {
  adj_[code] = other;
  if (other != kNone) adj_[other] = code;
}

void Cdt2::flip(std::uint32_t t, int k) {
  const std::uint32_t bt = 3 * t;  // t < 2^29 (Delaunay2::kMaxPoints)
  const std::uint32_t code = adj_[bt + static_cast<std::uint32_t>(k)];
  const std::uint32_t u = code / 3;
  const int j = static_cast<int>(code % 3);
  const std::uint32_t bu = 3 * u;
  // t = (a, b, c) from k, u = (d, c, b) from j; the new edge is a-d.
  const std::uint32_t a = v_[bt + k], b = v_[bt + next3(k)], c = v_[bt + prev3(k)];
  const std::uint32_t d = v_[bu + j];
  const std::uint32_t adj_ab = adj_[bt + prev3(k)], adj_ca = adj_[bt + next3(k)];
  const std::uint32_t adj_dc = adj_[bu + prev3(j)], adj_bd = adj_[bu + next3(j)];
  const std::uint8_t con_ab = con_[bt + prev3(k)], con_ca = con_[bt + next3(k)];
  const std::uint8_t con_dc = con_[bu + prev3(j)], con_bd = con_[bu + next3(j)];
  // t = (a, b, d), u = (d, c, a).
  v_[bt] = a;
  v_[bt + 1] = b;
  v_[bt + 2] = d;
  v_[bu] = d;
  v_[bu + 1] = c;
  v_[bu + 2] = a;
  link(bt + 0, adj_bd);
  con_[bt + 0] = con_bd;
  link(bt + 2, adj_ab);
  con_[bt + 2] = con_ab;
  link(bu + 0, adj_ca);
  con_[bu + 0] = con_ca;
  link(bu + 2, adj_dc);
  con_[bu + 2] = con_dc;
  link(bt + 1, bu + 1);
  con_[bt + 1] = 0;
  con_[bu + 1] = 0;
  vtri_[a] = t;
  vtri_[b] = t;
  vtri_[d] = t;
  vtri_[c] = u;
  ++flips_;
}

void Cdt2::star(std::uint32_t a, std::vector<std::uint32_t>& out) const {
  out.clear();
  const std::uint32_t t0 = vtri_[a];
  if (t0 == kNone) return;
  const auto local = [&](std::uint32_t t) {
    const std::size_t b = 3 * std::size_t{t};
    return v_[b] == a ? 0 : v_[b + 1] == a ? 1 : 2;
  };
  // Counter-clockwise: across the edge opposite the vertex after a.
  std::uint32_t t = t0;
  for (;;) {
    out.push_back(t);
    const std::uint32_t code = adj_[3 * std::size_t{t} + next3(local(t))];
    if (code == kNone) break;
    t = code / 3;
    if (t == t0) return;
  }
  // On the hull: the rest clockwise from t0, then put in counter-clockwise order.
  std::vector<std::uint32_t> before;
  t = t0;
  for (;;) {
    const std::uint32_t code = adj_[3 * std::size_t{t} + prev3(local(t))];
    if (code == kNone) break;
    t = code / 3;
    before.push_back(t);
  }
  out.insert(out.begin(), before.rbegin(), before.rend());
}

std::uint32_t Cdt2::find_edge(std::uint32_t a, std::uint32_t b, int* k) const {
  // Around a, one way then the other (on the hull the fan is open), no allocation.
  const std::uint32_t t0 = vtri_[a];
  if (t0 == kNone) return kNone;
  for (int dir = 0; dir < 2; ++dir) {
    std::uint32_t t = t0;
    bool open = false;
    do {
      const std::size_t bt = 3 * std::size_t{t};
      const int i = v_[bt] == a ? 0 : v_[bt + 1] == a ? 1 : 2;
      if (v_[bt + next3(i)] == b) {
        *k = prev3(i);
        return t;
      }
      const std::uint32_t code = adj_[bt + (dir == 0 ? next3(i) : prev3(i))];
      if (code == kNone) {
        open = true;
        break;
      }
      t = code / 3;
    } while (t != t0);
    if (!open) break;  // a full cycle: a is inside the hull
  }
  return kNone;
}

void Cdt2::set_constrained(std::uint32_t a, std::uint32_t b) {
  int k = 0;
  std::uint32_t t = find_edge(a, b, &k);
  if (t == kNone) t = find_edge(b, a, &k);
  if (t == kNone) {
    throw Error("cdt2: internal error: " + std::to_string(a) + "-" + std::to_string(b) +
                " is not an edge after its insertion");
  }
  const std::size_t h = 3 * std::size_t{t} + static_cast<std::size_t>(k);
  con_[h] = 1;
  if (adj_[h] != kNone) con_[adj_[h]] = 1;
}

void Cdt2::flip_out(std::uint32_t a, std::uint32_t c, std::vector<std::uint32_t>& crossed) {
  std::deque<std::pair<std::uint32_t, std::uint32_t>> queue;
  for (std::size_t i = 0; i + 1 < crossed.size(); i += 2)
    queue.emplace_back(crossed[i], crossed[i + 1]);
  const double* pa = point(a);
  const double* pc = point(c);
  // Sloan's loop terminates; the bound only turns a defect into an error, not a hang.
  const std::size_t limit = 64 * (queue.size() + 4) * (queue.size() + 4) + 1000000;
  for (std::size_t iteration = 0; !queue.empty(); ++iteration) {
    if (iteration > limit) {
      throw Error("cdt2: internal error: the flips inserting " + std::to_string(a) + "-" +
                  std::to_string(c) + " do not end");
    }
    const auto [r, l] = queue.front();
    queue.pop_front();
    int k = 0;
    const std::uint32_t t = find_edge(r, l, &k);
    if (t == kNone) {
      throw Error("cdt2: internal error: crossed edge " + std::to_string(r) + "-" +
                  std::to_string(l) + " lost");
    }
    const std::uint32_t code = adj_[3 * std::size_t{t} + static_cast<std::size_t>(k)];
    const std::uint32_t y = v_[3 * std::size_t{t} + static_cast<std::size_t>(k)];
    const std::uint32_t z = v_[code];
    const Sign s1 = orient2d(point(y), point(z), point(r));
    const Sign s2 = orient2d(point(y), point(z), point(l));
    if (s1 == Sign::zero || s2 == Sign::zero || s1 == s2) {
      queue.emplace_back(r, l);  // not strictly convex yet
      continue;
    }
    flip(t, k);
    if (y == a || y == c || z == a || z == c) continue;
    const Sign sy = orient2d(pa, pc, point(y)), sz = orient2d(pa, pc, point(z));
    if (sy != Sign::zero && sz != Sign::zero && sy != sz) queue.emplace_back(y, z);
  }
}

void Cdt2::insert_segment(std::uint32_t a, std::uint32_t b, std::vector<std::uint32_t>* pieces) {
  std::vector<std::uint32_t> tris, crossed;
  const double* pb = point(b);
  while (a != b) {
    star(a, tris);
    const double* pa = point(a);
    std::uint32_t next = kNone;
    for (const std::uint32_t t : tris) {
      const std::size_t bt = 3 * std::size_t{t};
      const int i = v_[bt] == a ? 0 : v_[bt + 1] == a ? 1 : 2;
      const std::uint32_t p = v_[bt + next3(i)], q = v_[bt + prev3(i)];
      if (p == b || q == b) {
        next = b;
        break;
      }
      const Sign op = orient2d(pa, point(p), pb);
      const Sign oq = orient2d(pa, point(q), pb);
      if (op == Sign::negative || oq == Sign::positive) continue;  // b outside the wedge
      if (op == Sign::zero) {
        next = p;  // p lies on a-b
        break;
      }
      if (oq == Sign::zero) {
        next = q;
        break;
      }
      // a-b leaves t across p-q (p on the right of a -> b): walk to b or to a vertex on a-b.
      crossed.clear();
      std::uint32_t r = p, l = q, cur = t;
      int edge = i;
      for (;;) {
        const std::size_t h = 3 * std::size_t{cur} + static_cast<std::size_t>(edge);
        if (con_[h]) {
          throw Error("the boundary segment from point " + std::to_string(a) + " to point " +
                      std::to_string(b) + " crosses the boundary segment " + std::to_string(r) +
                      "-" + std::to_string(l));
        }
        crossed.push_back(r);
        crossed.push_back(l);
        const std::uint32_t code = adj_[h];
        const std::uint32_t u = code / 3;
        const int j = static_cast<int>(code % 3);
        const std::uint32_t x = v_[code];
        if (x == b) {
          next = b;
          break;
        }
        const Sign s = orient2d(pa, pb, point(x));
        if (s == Sign::zero) {
          next = x;
          break;
        }
        cur = u;
        if (s == Sign::negative) {
          r = x;
          edge = prev3(j);  // (x, l), opposite r's old position
        } else {
          l = x;
          edge = next3(j);  // (r, x)
        }
      }
      flip_out(a, next, crossed);
      break;
    }
    if (next == kNone) {
      throw Error("cdt2: internal error: no triangle around point " + std::to_string(a) +
                  " faces point " + std::to_string(b));
    }
    set_constrained(a, next);
    if (pieces) {
      pieces->push_back(a);
      pieces->push_back(next);
    }
    a = next;
  }
}

std::uint32_t Cdt2::make_delaunay() {
  const std::uint32_t before = flips_;
  std::vector<std::uint32_t>& stack = scratch_;
  stack.clear();
  for (std::uint32_t h = 0; h < adj_.size(); ++h) {
    if (adj_[h] != kNone && h < adj_[h] && !con_[h]) stack.push_back(h);
  }
  while (!stack.empty()) {
    const std::uint32_t h = stack.back();
    stack.pop_back();
    if (adj_[h] == kNone || con_[h]) continue;
    const std::uint32_t t = h / 3;
    const std::size_t bt = 3 * std::size_t{t};
    const std::uint32_t z = v_[adj_[h]];
    if (incircle(point(v_[bt]), point(v_[bt + 1]), point(v_[bt + 2]), point(z)) != Sign::positive) {
      continue;
    }
    const std::uint32_t u = adj_[h] / 3;
    flip(t, static_cast<int>(h % 3));
    stack.push_back(3 * t + 0);
    stack.push_back(3 * t + 2);
    stack.push_back(3 * u + 0);
    stack.push_back(3 * u + 2);
  }
  return flips_ - before;
}

}  // namespace voroclip::mesh2d
