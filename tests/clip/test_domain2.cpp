// Tests of Domain2 (voroclip/clip.h): exact validation, orientation, area and locate.
//
// The oracle is independent of the library: rational arithmetic (GMP mpq) and brute force
// over all pairs of edges and all rings. Every accepted domain goes through
// check_domain(), which verifies the storage, the orientation of every ring, the area,
// the bounding box and (up to a few thousand edges) that no two edges meet. Random tests
// print their seed.
#include <catch2/catch.hpp>

#include <gmpxx.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/predicates.h"

using voroclip::Domain2;
using voroclip::PolygonRings;
using voroclip::Sign;

namespace {

const std::string kPolygons = std::string(VOROCLIP_SHARED_DATA_DIR) + "/polygons/";

using Ring = std::vector<double>;  // packed x y

PolygonRings make_rings(const std::vector<Ring>& rings, std::vector<std::int32_t> polygon = {},
                        const std::string& source = "test") {
  PolygonRings out;
  out.source = source;
  out.ring_begin.push_back(0);
  for (const Ring& r : rings) {
    out.xy.insert(out.xy.end(), r.begin(), r.end());
    out.ring_begin.push_back(static_cast<std::uint32_t>(out.xy.size() / 2));
  }
  out.ring_polygon = polygon.empty() ? std::vector<std::int32_t>(rings.size(), 0) : polygon;
  out.ring_line.assign(rings.size(), 0);
  return out;
}

std::string domain_error(const PolygonRings& rings) {
  try {
    Domain2 d(rings);
  } catch (const voroclip::Error& e) {
    return e.what();
  }
  return "";
}

std::string write_temp(const std::string& name, const std::string& content) {
  std::ofstream(name) << content;
  return name;
}

PolygonRings scaled(PolygonRings r, int exponent) {
  for (double& x : r.xy) x = std::ldexp(x, exponent);
  for (double& x : r.hole_points) x = std::ldexp(x, exponent);
  return r;
}

// A message without its coordinates, "(x, y)", which change with the scale.
std::string without_coordinates(const std::string& s) {
  const auto number_end = [&s](std::size_t i) {
    while (i < s.size() && std::string("+-0123456789.eE").find(s[i]) != std::string::npos) ++i;
    return i;
  };
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '(') {
      const std::size_t x = number_end(i + 1);
      if (x > i + 1 && s.compare(x, 2, ", ") == 0) {
        const std::size_t y = number_end(x + 2);
        if (y > x + 2 && y < s.size() && s[y] == ')') {
          out += "(x, y)";
          i = y;
          continue;
        }
      }
    }
    out += s[i];
  }
  return out;
}

// ---------------------------------------------------------------------------------------
// Exact rational oracle.

using Q = mpq_class;

int orient_q(const double* a, const double* b, const double* c) {
  const Q det =
      (Q(b[0]) - Q(a[0])) * (Q(c[1]) - Q(a[1])) - (Q(b[1]) - Q(a[1])) * (Q(c[0]) - Q(a[0]));
  return sgn(det);
}

bool in_box(const double* a, const double* b, const double* p) {
  return std::min(a[0], b[0]) <= p[0] && p[0] <= std::max(a[0], b[0]) &&
         std::min(a[1], b[1]) <= p[1] && p[1] <= std::max(a[1], b[1]);
}

bool on_segment_q(const double* a, const double* b, const double* p) {
  return in_box(a, b, p) && orient_q(a, b, p) == 0;
}

// Rings with consecutive repeats and closing repeats dropped (what Domain2 keeps).
std::vector<Ring> dedupe(const PolygonRings& in) {
  std::vector<Ring> out;
  for (std::uint32_t r = 0; r < in.nb_rings(); ++r) {
    Ring ring;
    for (std::uint32_t i = in.ring_begin[r]; i < in.ring_begin[r + 1]; ++i) {
      const double x = in.xy[2 * i], y = in.xy[2 * i + 1];
      if (!ring.empty() && ring[ring.size() - 2] == x && ring.back() == y) continue;
      ring.push_back(x);
      ring.push_back(y);
    }
    while (ring.size() >= 4 && ring[0] == ring[ring.size() - 2] && ring[1] == ring.back()) {
      ring.resize(ring.size() - 2);
    }
    out.push_back(ring);
  }
  return out;
}

Q signed_area_q(const Ring& r) {
  Q a = 0;
  const std::size_t n = r.size() / 2;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    a += Q(r[2 * i]) * Q(r[2 * j + 1]) - Q(r[2 * j]) * Q(r[2 * i + 1]);
  }
  return a / 2;
}

// Point location by brute force: on an edge, else the parity of crossings of the ray
// towards +x, the crossing abscissa computed as a rational.
Sign locate_q(const std::vector<Ring>& rings, const double* p) {
  bool inside = false;
  for (const Ring& r : rings) {
    const std::size_t n = r.size() / 2;
    for (std::size_t i = 0; i < n; ++i) {
      const double* a = &r[2 * i];
      const double* b = &r[2 * ((i + 1) % n)];
      if (on_segment_q(a, b, p)) return Sign::zero;
      if ((a[1] > p[1]) != (b[1] > p[1])) {
        const Q x = Q(a[0]) + (Q(p[1]) - Q(a[1])) * (Q(b[0]) - Q(a[0])) / (Q(b[1]) - Q(a[1]));
        if (x > Q(p[0])) inside = !inside;
      }
    }
  }
  return inside ? Sign::positive : Sign::negative;
}

bool inside_ring_q(const Ring& r, const double* p) { return locate_q({r}, p) == Sign::positive; }

// Contacts between the edges of deduplicated rings, counted per pair of edges as Domain2
// reports them: proper crossings, and "touching" = adjacent edges folding back, or
// non-adjacent edges sharing any point without crossing properly.
struct ContactCount {
  std::size_t crossing = 0, touching = 0;
  std::size_t total() const { return crossing + touching; }
};

ContactCount count_contacts_q(const std::vector<Ring>& rings) {
  struct Edge {
    const double *a, *b;
    std::size_t ring, index, size;
  };
  std::vector<Edge> edges;
  for (std::size_t k = 0; k < rings.size(); ++k) {
    const std::size_t n = rings[k].size() / 2;
    for (std::size_t i = 0; i < n; ++i) {
      edges.push_back({&rings[k][2 * i], &rings[k][2 * ((i + 1) % n)], k, i, n});
    }
  }
  ContactCount c;
  for (std::size_t x = 0; x < edges.size(); ++x) {
    for (std::size_t y = x + 1; y < edges.size(); ++y) {
      const Edge& e = edges[x];
      const Edge& f = edges[y];
      if (std::max(e.a[0], e.b[0]) < std::min(f.a[0], f.b[0]) ||
          std::max(f.a[0], f.b[0]) < std::min(e.a[0], e.b[0]) ||
          std::max(e.a[1], e.b[1]) < std::min(f.a[1], f.b[1]) ||
          std::max(f.a[1], f.b[1]) < std::min(e.a[1], e.b[1])) {
        continue;
      }
      const bool adjacent = e.ring == f.ring && ((e.index + 1) % e.size == f.index ||
                                                 (f.index + 1) % f.size == e.index);
      if (adjacent) {
        // They share a vertex; they fold back iff the far ends are on one ray from it.
        const double* shared = (e.index + 1) % e.size == f.index ? e.b : e.a;
        const double* u = shared == e.b ? e.a : e.b;
        const double* w = shared == f.a ? f.b : f.a;
        if (orient_q(u, shared, w) == 0) {
          const Q dot = (Q(u[0]) - Q(shared[0])) * (Q(w[0]) - Q(shared[0])) +
                        (Q(u[1]) - Q(shared[1])) * (Q(w[1]) - Q(shared[1]));
          if (dot > 0) ++c.touching;
        }
        continue;
      }
      const int o1 = orient_q(e.a, e.b, f.a), o2 = orient_q(e.a, e.b, f.b);
      const int o3 = orient_q(f.a, f.b, e.a), o4 = orient_q(f.a, f.b, e.b);
      if (o1 * o2 < 0 && o3 * o4 < 0) {
        ++c.crossing;
      } else if (on_segment_q(e.a, e.b, f.a) || on_segment_q(e.a, e.b, f.b) ||
                 on_segment_q(f.a, f.b, e.a) || on_segment_q(f.a, f.b, e.b)) {
        ++c.touching;
      }
    }
  }
  return c;
}

// The verdict of the contract (clip.h) by brute force. `message` holds substrings any of
// which the library's message must contain.
struct Verdict {
  bool valid = true;
  std::vector<std::string> message;
  ContactCount contacts;
};

Verdict validate_q(const PolygonRings& in) {
  Verdict v;
  if (in.nb_rings() == 0) {
    v.valid = false;
    v.message = {"no rings"};
    return v;
  }
  for (const double x : in.xy) {
    if (!std::isfinite(x)) {
      v.valid = false;
      v.message = {"non-finite"};
      return v;
    }
  }
  const std::vector<Ring> rings = dedupe(in);
  for (const Ring& r : rings) {
    if (r.size() < 6) {
      v.valid = false;
      v.message = {"fewer than 3 distinct points"};
      return v;
    }
    bool collinear = true;
    for (std::size_t i = 2; i < r.size() / 2; ++i) {
      collinear = collinear && orient_q(&r[0], &r[2], &r[2 * i]) == 0;
    }
    if (collinear) {
      v.valid = false;
      v.message = {"zero area"};
      return v;
    }
  }
  v.contacts = count_contacts_q(rings);
  if (v.contacts.total() > 0) {
    v.valid = false;
    v.message = v.contacts.crossing > 0 ? std::vector<std::string>{"cross"}
                                        : std::vector<std::string>{"touch", "spike", "overlap"};
    return v;
  }
  // Nesting: containers of each ring (by one vertex), depth, parent.
  const std::size_t nr = rings.size();
  std::vector<std::vector<std::size_t>> containers(nr);
  for (std::size_t r = 0; r < nr; ++r) {
    for (std::size_t s = 0; s < nr; ++s) {
      if (s != r && inside_ring_q(rings[s], &rings[r][0])) containers[r].push_back(s);
    }
  }
  const auto parent = [&](std::size_t r) {
    for (const std::size_t s : containers[r]) {
      if (containers[s].size() + 1 == containers[r].size()) return static_cast<long>(s);
    }
    return -1L;
  };
  std::vector<bool> hole(nr);
  if (in.ring_polygon[0] < 0) {
    for (std::size_t r = 0; r < nr; ++r) hole[r] = containers[r].size() % 2 == 1;
  } else {
    std::vector<long> outer(nr);
    for (std::size_t r = 0; r < nr; ++r) {
      long first = -1;
      for (std::size_t s = 0; s < nr && first < 0; ++s) {
        if (in.ring_polygon[s] == in.ring_polygon[r]) first = static_cast<long>(s);
      }
      outer[r] = first;
      hole[r] = first != static_cast<long>(r);
    }
    for (std::size_t r = 0; r < nr; ++r) {
      const long up = parent(r);
      if (hole[r] ? up != outer[r] : (up >= 0 && !hole[static_cast<std::size_t>(up)])) {
        v.valid = false;
        v.message = {"outside its outer boundary", "inside another hole", "overlap",
                     "the outer boundary of another polygon"};
        return v;
      }
    }
  }
  for (std::size_t k = 0; k < in.hole_points.size() / 2; ++k) {
    const double* q = &in.hole_points[2 * k];
    if (locate_q(rings, q) == Sign::zero) {
      v.valid = false;
      v.message = {"lies on the boundary"};
      return v;
    }
    long innermost = -1;
    for (std::size_t r = 0; r < nr; ++r) {
      if (inside_ring_q(rings[r], q) &&
          (innermost < 0 ||
           containers[r].size() > containers[static_cast<std::size_t>(innermost)].size())) {
        innermost = static_cast<long>(r);
      }
    }
    if (innermost < 0 || !hole[static_cast<std::size_t>(innermost)]) {
      v.valid = false;
      v.message = {"outside every ring", "inside the domain"};
      return v;
    }
  }
  return v;
}

// ---------------------------------------------------------------------------------------
// The checker every accepted domain goes through.

void check_domain(const Domain2& d, const PolygonRings& in) {
  const std::uint32_t n = d.nb_vertices();
  REQUIRE(d.nb_rings() == in.nb_rings());
  REQUIRE(d.nb_edges() == n);
  REQUIRE(n + d.nb_dropped_points() == in.xy.size() / 2);
  REQUIRE(d.coords().size() == 2 * std::size_t{n});
  REQUIRE(d.source() == in.source);
  const std::vector<Ring> rings = dedupe(in);
  Q total = 0;
  double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
  for (std::uint32_t r = 0; r < d.nb_rings(); ++r) {
    REQUIRE(d.source_ring(r) == r);
    const std::uint32_t b = d.ring_begin(r), e = d.ring_end(r);
    REQUIRE(b == (r == 0 ? 0u : d.ring_end(r - 1)));
    REQUIRE(e - b >= 3);
    REQUIRE(2 * std::size_t{e - b} == rings[r].size());
    Ring stored;
    for (std::uint32_t v = b; v < e; ++v) {
      REQUIRE(d.ring_of(v) == r);
      REQUIRE(d.next(v) == (v + 1 == e ? b : v + 1));
      REQUIRE(d.prev(d.next(v)) == v);
      // The vertex is its input point, from its own ring.
      const std::uint32_t s = d.source_vertex(v);
      REQUIRE(s >= in.ring_begin[r]);
      REQUIRE(s < in.ring_begin[r + 1]);
      REQUIRE(d.vertex(v)[0] == in.xy[2 * s]);
      REQUIRE(d.vertex(v)[1] == in.xy[2 * s + 1]);
      REQUIRE(
          !(d.vertex(v)[0] == d.vertex(d.next(v))[0] && d.vertex(v)[1] == d.vertex(d.next(v))[1]));
      stored.push_back(d.vertex(v)[0]);
      stored.push_back(d.vertex(v)[1]);
      for (int k = 0; k < 2; ++k) {
        lo[k] = std::min(lo[k], d.vertex(v)[k]);
        hi[k] = std::max(hi[k], d.vertex(v)[k]);
      }
      REQUIRE(d.is_corner(v) ==
              (orient_q(d.vertex(d.prev(v)), d.vertex(v), d.vertex(d.next(v))) != 0));
    }
    // Same cycle as the input ring, in one direction or the other.
    const Ring& given = rings[r];
    const std::size_t m = given.size() / 2;
    std::size_t shift = 0;
    while (shift < m && !(given[2 * shift] == stored[0] && given[2 * shift + 1] == stored[1]))
      ++shift;
    REQUIRE(shift < m);
    const bool same =
        given[2 * ((shift + 1) % m)] == stored[2] && given[2 * ((shift + 1) % m) + 1] == stored[3];
    for (std::size_t i = 0; i < m; ++i) {
      const std::size_t j = same ? (shift + i) % m : (shift + m - i) % m;
      REQUIRE(stored[2 * i] == given[2 * j]);
      REQUIRE(stored[2 * i + 1] == given[2 * j + 1]);
    }
    // Outer rings counter-clockwise, holes clockwise.
    const Q a = signed_area_q(stored);
    REQUIRE(sgn(a) == (d.is_hole(r) ? -1 : 1));
    total += a;
  }
  // area(): within 1e-13 of the exact value.
  const double exact = total.get_d();
  INFO("area " << d.area() << " exact " << exact);
  REQUIRE(exact > 0);
  REQUIRE(std::fabs(d.area() - exact) <= 1e-13 * exact);
  REQUIRE(d.bbox_lo()[0] == lo[0]);
  REQUIRE(d.bbox_lo()[1] == lo[1]);
  REQUIRE(d.bbox_hi()[0] == hi[0]);
  REQUIRE(d.bbox_hi()[1] == hi[1]);
  if (n <= 3000) {
    const ContactCount c = count_contacts_q(rings);
    REQUIRE(c.total() == 0);
  }
}

Domain2 checked(const PolygonRings& in) {
  Domain2 d(in);
  check_domain(d, in);
  return d;
}

// locate() against the oracle at random points of the (enlarged) bounding box, at every
// vertex, at edge midpoints and at points one ulp away from vertices. Returns how many
// answers were ZERO (to show the boundary was exercised).
std::size_t check_locate(const Domain2& d, const PolygonRings& in, std::size_t nb_random,
                         std::uint64_t seed) {
  INFO("seed " << seed);
  std::mt19937_64 rng(seed);
  const std::vector<Ring> rings = dedupe(in);
  const double w = d.bbox_hi()[0] - d.bbox_lo()[0], h = d.bbox_hi()[1] - d.bbox_lo()[1];
  std::uniform_real_distribution<double> ux(d.bbox_lo()[0] - 0.05 * w, d.bbox_hi()[0] + 0.05 * w);
  std::uniform_real_distribution<double> uy(d.bbox_lo()[1] - 0.05 * h, d.bbox_hi()[1] + 0.05 * h);
  std::vector<double> queries;
  for (std::size_t k = 0; k < nb_random; ++k) {
    queries.push_back(ux(rng));
    queries.push_back(uy(rng));
  }
  const std::uint32_t step = std::max<std::uint32_t>(1, d.nb_vertices() / 200);
  for (std::uint32_t v = 0; v < d.nb_vertices(); v += step) {
    const double* a = d.vertex(v);
    const double* b = d.vertex(d.next(v));
    queries.insert(queries.end(),
                   {a[0], a[1], 0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]),
                    std::nextafter(a[0], INFINITY), a[1], a[0], std::nextafter(a[1], -INFINITY)});
  }
  std::size_t zeros = 0;
  for (std::size_t k = 0; k < queries.size(); k += 2) {
    const double* q = &queries[k];
    const Sign expected = locate_q(rings, q);
    INFO("q = (" << q[0] << ", " << q[1] << ")");
    REQUIRE(d.locate(q) == expected);
    zeros += expected == Sign::zero;
  }
  return zeros;
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Shared data

TEST_CASE("Domain2 accepts every valid shared polygon, with its exact counts", "[clip][exact]") {
  // polygons/README.md: h holes, n distinct consecutive vertices, collinear vertices.
  struct Expected {
    const char* file;
    std::uint32_t holes, n, collinear;
  };
  const Expected files[] = {
      {"building.json", 0, 15, 1},    {"dude.json", 2, 104, 0},       {"earcut.json", 6, 548, 10},
      {"eberly-6.json", 15, 1401, 1}, {"hilbert.json", 0, 1026, 206}, {"issue29.json", 1, 40, 0},
      {"issue34.json", 7, 127, 0},    {"issue35.json", 29, 790, 0},   {"issue52.json", 5, 101, 1}};
  for (const Expected& f : files) {
    INFO(f.file);
    const PolygonRings in = voroclip::read_polygon(kPolygons + "valid/" + f.file);
    const Domain2 d = checked(in);
    CHECK(d.nb_rings() == f.holes + 1);
    CHECK(d.nb_vertices() == f.n);
    std::uint32_t holes = 0, straight = 0;
    for (std::uint32_t r = 0; r < d.nb_rings(); ++r) holes += d.is_hole(r) ? 1 : 0;
    for (std::uint32_t v = 0; v < d.nb_vertices(); ++v) straight += d.is_corner(v) ? 0 : 1;
    CHECK(holes == f.holes);
    CHECK(!d.is_hole(0));
    CHECK(straight == f.collinear);
    CHECK(check_locate(d, in, 300, 17) > 0);
  }
  // eberly-6 has one consecutive duplicate and its closing repeats.
  const PolygonRings e = voroclip::read_polygon(kPolygons + "valid/eberly-6.json");
  CHECK(Domain2(e).nb_dropped_points() == e.xy.size() / 2 - 1401);
}

TEST_CASE("Domain2 rejects every degenerate shared polygon, naming the defect",
          "[clip][exact][degenerate]") {
  struct Expected {
    const char* file;
    std::vector<std::string> parts;  // substrings of the message, after "<path>: "
  };
  const Expected files[] = {
      {"degenerate.json", {"ring 0 (vertices 2-3-4) folds back at vertex 3", "zero-area spike"}},
      {"steiner.json", {"ring 1 has fewer than 3 distinct points (1 point"}},
      {"shared-points.json",
       {"ring 0 touches itself: vertices 0 and 3 are the same point (4136, 1016)", "passes twice",
        "12 touching"}},
      {"self-touching.json", {"ring 0 touches itself", "0 crossing, 8 touching"}},
      {"hole-touching-outer.json",
       {"ring 1 (vertex 1) touches ring 0 (vertex 9): they share the point (1770, 512)"}},
      {"touching-holes.json",
       {"ring 5 (vertex 1) touches ring 7 (vertex 1)", "0 crossing, 8 touching"}},
      {"eberly-3.json", {"ring 2 (vertex 0) touches ring 0 (vertex 36)", "0 crossing, 4 touching"}},
      // README: 19 proper crossings and 64 touches, counted per pair of edges.
      {"water.json",
       {"ring 0 crosses itself: edges 1-2 and 3-4 cross at a single point",
        "(edge pairs in all: 19 crossing, 64 touching: 2 folding back, 20 overlapping, 42 at a "
        "point)"}},
  };
  for (const Expected& f : files) {
    const std::string path = kPolygons + "degenerate/" + f.file;
    const PolygonRings in = voroclip::read_polygon(path);
    const std::string message = domain_error(in);
    INFO(message);
    REQUIRE(message.find(path + ": ") == 0);
    for (const std::string& part : f.parts) CHECK(message.find(part) != std::string::npos);
    // The brute-force oracle agrees on the verdict, and on the counts.
    const Verdict v = validate_q(in);
    CHECK(!v.valid);
    if (v.contacts.total() > 1) {
      CHECK(message.find("(edge pairs in all: " + std::to_string(v.contacts.crossing) +
                         " crossing, " + std::to_string(v.contacts.touching) + " touching") !=
            std::string::npos);
    }
  }
}

// ---------------------------------------------------------------------------------------
// Hand-made cases

TEST_CASE("Domain2 orients rings and drops repeated points", "[clip]") {
  // Outer ring given clockwise with a repeated closing point and a duplicate; hole given
  // counter-clockwise.
  const PolygonRings in =
      make_rings({{0, 0, 0, 4, 0, 4, 4, 4, 4, 0, 0, 0}, {1, 1, 2, 1, 2, 2, 1, 2}});
  const Domain2 d = checked(in);
  CHECK(d.nb_vertices() == 8);
  CHECK(d.nb_dropped_points() == 2);
  CHECK(!d.is_hole(0));
  CHECK(d.is_hole(1));
  CHECK(d.area() == 15);
  // Reversed: vertex v of ring 0 is input point source_vertex(v).
  CHECK(d.vertex(1)[0] == 4);
  CHECK(d.vertex(1)[1] == 0);
  CHECK(d.source_vertex(1) == 4);
  const double inside[2] = {0.5, 0.5}, in_hole[2] = {1.5, 1.5}, edge[2] = {2, 1}, out[2] = {5, 1};
  CHECK(d.locate(inside) == Sign::positive);
  CHECK(d.locate(in_hole) == Sign::negative);
  CHECK(d.locate(edge) == Sign::zero);
  CHECK(d.locate(out) == Sign::negative);
  const double nan[2] = {NAN, 0};
  CHECK_THROWS_AS(d.locate(nan), voroclip::Error);
  // A collinear vertex is not a corner.
  const Domain2 t = checked(make_rings({{0, 0, 1, 0, 2, 0, 1, 1}}));
  CHECK(!t.is_corner(1));
  CHECK(t.is_corner(0));
  CHECK(t.area() == 1);
}

TEST_CASE("Domain2 names each defect of hand-made rings", "[clip][degenerate]") {
  struct Case {
    const char* name;
    PolygonRings rings;
    const char* message;  // after "test: "
  };
  const Case cases[] = {
      {"bow-tie", make_rings({{0, 0, 2, 2, 2, 0, 0, 2}}),
       "ring 0 crosses itself: edges 0-1 and 2-3 cross at a single point"
       " (rings and points numbered from 0)"},
      {"two rings crossing", make_rings({{0, 0, 4, 0, 4, 4, 0, 4}, {1, 1, 5, 2, 1, 3}}),
       "ring 0 (vertices 1-2) crosses ring 1 (vertices 0-1) at a single point (edge pairs in all: "
       "2 crossing, 0 touching: 0 folding back, 0 overlapping, 0 at a point)"
       " (rings and points numbered from 0)"},
      {"vertex on an edge of its own ring",
       make_rings({{0, 0, 4, 0, 4, 4, 3, 4, 2, 0, 1, 4, 0, 4}}),
       "ring 0 touches itself: vertex 4 (2, 0) lies on edge 0-1 (edge pairs in all: 0 crossing, 2 "
       "touching: 0 folding back, 0 overlapping, 2 at a point)"
       " (rings and points numbered from 0)"},
      {"hole vertex on the outer edge", make_rings({{0, 0, 4, 0, 4, 4, 0, 4}, {2, 0, 3, 1, 1, 1}}),
       "ring 1 (vertex 0) touches ring 0 (vertices 0-1): the vertex (2, 0) lies on the edge (edge "
       "pairs in all: 0 crossing, 2 touching: 0 folding back, 0 overlapping, 2 at a point)"
       " (rings and points numbered from 0)"},
      {"collinear overlap",
       make_rings({{0, 0, 2, 0, 2, 2, 0, 2}, {2, 0.5, 4, 0.5, 4, 1.5, 2, 1.5}}, {0, 1}),
       "polygon 0 ring 0 (vertices 1-2) overlaps polygon 1 ring 0 (vertices 3-0): collinear edges "
       "sharing a segment (the rings touch along it) (edge pairs in all: 0 crossing, 3 touching: 0 "
       "folding back, 1 overlapping, 2 at a point)"
       " (polygons, rings and points numbered from 0)"},
      {"spike", make_rings({{0, 0, 4, 0, 4, 4, 2, 4, 2, 6, 2, 5, 0, 4}}),
       "ring 0 (vertices 3-4-5) folds back at vertex 4: edges 3-4 and 4-5 overlap (a zero-area "
       "spike) (edge pairs in all: 0 crossing, 2 touching: 1 folding back, 0 overlapping, 1 at a "
       "point)"
       " (rings and points numbered from 0)"},
      {"fold back at the first vertex", make_rings({{0, 6, 0, 0, 4, 0, 4, 4, 0, 4}}),
       "ring 0 (vertices 4-0-1) folds back at vertex 0: edges 4-0 and 0-1 overlap (a zero-area "
       "spike) (edge pairs in all: 0 crossing, 2 touching: 1 folding back, 0 overlapping, 1 at a "
       "point)"
       " (rings and points numbered from 0)"},
      {"hole touching the outer ring at a vertex",
       make_rings({{0, 0, 4, 0, 4, 4, 0, 4}, {0, 0, 1, 2, 2, 1}}),
       "ring 1 (vertex 0) touches ring 0 (vertex 0): they share the point (0, 0) (edge pairs in "
       "all: 0 crossing, 4 touching: 0 folding back, 0 overlapping, 4 at a point)"
       " (rings and points numbered from 0)"},
      {"ring through one point twice", make_rings({{0, 0, 2, 0, 1, 1, 2, 2, 0, 2, 1, 1}}),
       "ring 0 touches itself: vertices 2 and 5 are the same point (1, 1) (the ring passes twice "
       "through it) (edge pairs in all: 0 crossing, 4 touching: 0 folding back, 0 overlapping, 4 "
       "at a point)"
       " (rings and points numbered from 0)"},
      {"hole outside", make_rings({{0, 0, 4, 0, 4, 4, 0, 4}, {10, 10, 12, 10, 12, 12}}),
       "ring 1 is a hole but lies outside its outer boundary, ring 0"
       " (rings and points numbered from 0)"},
      {"hole in a hole",
       make_rings({{0, 0, 10, 0, 10, 10, 0, 10}, {1, 1, 9, 1, 9, 9, 1, 9}, {3, 3, 5, 3, 5, 5}}),
       "ring 2 is a hole but lies inside another hole, ring 1"
       " (rings and points numbered from 0)"},
      {"outer ring inside the outer ring of another polygon",
       make_rings({{0, 0, 10, 0, 10, 10, 0, 10}, {1, 1, 2, 1, 2, 2}}, {0, 1}),
       "polygon 1 ring 0, an outer boundary, lies inside the outer boundary polygon 0 ring 0 and "
       "not in one of its holes: the polygons overlap"
       " (polygons, rings and points numbered from 0)"},
      {"fewer than 3 points", make_rings({{0, 0, 1, 1, 1, 1, 0, 0}}),
       "ring 0 has fewer than 3 distinct points (2 points once repeats are dropped)"
       " (rings and points numbered from 0)"},
      {"empty ring", make_rings({{0, 0, 1, 0, 0, 1}, {}}),
       "ring 1 has fewer than 3 distinct points (0 points once repeats are dropped)"
       " (rings and points numbered from 0)"},
      {"collinear", make_rings({{0, 0, 1, 1, 3, 3, 2, 2}}),
       "ring 0 has zero area: its 4 points are all collinear"
       " (rings and points numbered from 0)"},
      {"non-finite", make_rings({{0, 0, 1, 0, INFINITY, 1}}),
       "ring 0 (vertex 2) has a non-finite coordinate"
       " (rings and points numbered from 0)"},
      {"no rings", make_rings({}), "no rings: the domain is empty"},
  };
  for (const Case& c : cases) {
    INFO(c.name);
    CHECK(domain_error(c.rings) == std::string("test: ") + c.message);
    CHECK(!validate_q(c.rings).valid);
  }
  PolygonRings bad = make_rings({{0, 0, 1, 0, 0, 1}});
  bad.ring_polygon = {0, 0};
  CHECK(domain_error(bad) == "test: malformed PolygonRings: ring_polygon needs one entry per ring");
  bad = make_rings({{0, 0, 1, 0, 0, 1}, {0.1, 0.1, 0.2, 0.1, 0.1, 0.2}});
  bad.ring_polygon = {-1, 0};
  CHECK(domain_error(bad) ==
        "test: malformed PolygonRings: ring_polygon must be -1 for every ring or for none");
}

TEST_CASE("Domain2 accepts several components, islands in lakes", "[clip]") {
  // Two disjoint polygons.
  const Domain2 two = checked(make_rings({{0, 0, 2, 0, 2, 2, 0, 2}, {3, 0, 5, 0, 4, 3}}, {0, 1}));
  CHECK(two.area() == 7);
  CHECK(!two.is_hole(0));
  CHECK(!two.is_hole(1));
  // An island in a lake, as two JSON polygons: outer / hole, then outer.
  const PolygonRings lake =
      make_rings({{0, 0, 10, 0, 10, 10, 0, 10}, {2, 2, 8, 2, 8, 8, 2, 8}, {4, 4, 6, 4, 6, 6, 4, 6}},
                 {0, 0, 1});
  const Domain2 d = checked(lake);
  CHECK(d.area() == 68);
  CHECK(!d.is_hole(0));
  CHECK(d.is_hole(1));
  CHECK(!d.is_hole(2));
  check_locate(d, lake, 500, 5);
  // The same rings as one polygon: the island is then a hole inside a hole.
  CHECK(domain_error(make_rings(
            {{0, 0, 10, 0, 10, 10, 0, 10}, {2, 2, 8, 2, 8, 8, 2, 8}, {4, 4, 6, 4, 6, 6, 4, 6}})) ==
        "test: ring 2 is a hole but lies inside another hole, ring 1 (rings and points numbered "
        "from 0)");
}

TEST_CASE("Domain2 reads roles from nesting in .poly files, checks hole markers", "[clip]") {
  // Island in a lake: rings at depth 0, 1, 2 are outer, hole, outer. 0-based, with the
  // hole ring listed first.
  const std::string body =
      "12 2 0 0\n"
      "0 2 2\n1 8 2\n2 8 8\n3 2 8\n"
      "4 0 0\n5 10 0\n6 10 10\n7 0 10\n"
      "8 4 4\n9 6 4\n10 6 6\n11 4 6\n"
      "12 0\n"
      "0 0 1\n1 1 2\n2 2 3\n3 3 0\n"
      "4 4 5\n5 5 6\n6 6 7\n7 7 4\n"
      "8 8 9\n9 9 10\n10 10 11\n11 11 8\n";
  const auto p = write_temp("island.poly", body + "1\n0 3 3\n");
  const PolygonRings in = voroclip::read_polygon(p);
  const Domain2 d = checked(in);
  CHECK(d.is_hole(0));
  CHECK(!d.is_hole(1));
  CHECK(!d.is_hole(2));
  CHECK(d.area() == 68);
  const double island[2] = {5, 5}, lake[2] = {3, 3}, land[2] = {1, 1}, shore[2] = {2, 5};
  CHECK(d.locate(island) == Sign::positive);
  CHECK(d.locate(lake) == Sign::negative);
  CHECK(d.locate(land) == Sign::positive);
  CHECK(d.locate(shore) == Sign::zero);
  check_locate(d, in, 500, 6);
  // Hole markers that are not in a hole. Line 28 holds the marker.
  struct Case {
    const char* marker;
    const char* message;
  };
  const Case cases[] = {
      {"0 5 5",
       "hole 0 (line 28) at (5, 5) lies inside the domain (its innermost ring, "
       "ring 2 (line 23), is an outer boundary), not in a hole"
       " (.poly numbering: the file's vertex numbers and lines)"},
      {"0 20 5", "hole 0 (line 28) at (20, 5) lies outside every ring, not in a hole"},
      {"0 2 5",
       "hole 0 (line 28) at (2, 5) lies on the boundary, on ring 0 (line 15)"
       " (.poly numbering: the file's vertex numbers and lines)"},
  };
  for (const Case& c : cases) {
    const auto q = write_temp("island_bad.poly", body + "1\n" + c.marker + "\n");
    CHECK(domain_error(voroclip::read_polygon(q)) == q + ": " + c.message);
    std::remove(q.c_str());
  }
  // A ring that nesting makes a hole, without a marker: Triangle meshes it (its ring an
  // inner boundary), so it is refused, not made a hole.
  const auto u = write_temp("island_unmarked.poly", body + "0\n");
  CHECK(domain_error(voroclip::read_polygon(u)) ==
        u + ": ring 0 (line 15) lies inside ring 1 (line 19) and no hole marker lies in it: in "
            "a .poly file a region is a hole only where a hole marker is (Triangle meshes it, "
            "the ring an inner boundary, which voroclip does not take); add a hole marker "
            "inside it to make it a hole (.poly numbering: the file's vertex numbers and "
            "lines)");
  std::remove(u.c_str());
  // A crossing is reported with the file's vertex numbers and the ring's first line.
  const auto x = write_temp("crossing.poly",
                            "7 2 0 0\n1 0 0\n2 4 0\n3 4 4\n4 0 4\n5 1 1\n6 5 2\n7 1 3\n"
                            "7 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n5 5 6\n6 6 7\n7 7 5\n0\n");
  CHECK(domain_error(voroclip::read_polygon(x)) ==
        x + ": ring 0 (line 10, vertices 2-3) crosses ring 1 (line 14, vertices 5-6) at a single "
            "point (edge pairs in all: 2 crossing, 0 touching: 0 folding back, 0 overlapping, 0 at "
            "a point) (.poly numbering: the file's vertex numbers and lines)");
  std::remove(p.c_str());
  std::remove(x.c_str());
}

// ---------------------------------------------------------------------------------------
// Generators

TEST_CASE("Domain2 of the generators has the analytic area of their polygons", "[clip]") {
  for (const std::uint32_t n : {3u, 4u, 7u, 64u, 1000u}) {
    INFO("segments " << n);
    const PolygonRings in = voroclip::annulus_rings(0.25, 1.5, n);
    const Domain2 d = checked(in);
    CHECK(d.is_hole(1));
    CHECK(d.nb_dropped_points() == 0);
    const double pi = 3.141592653589793;
    const double expected = 0.5 * n * std::sin(2 * pi / n) * (1.5 * 1.5 - 0.25 * 0.25);
    CHECK(std::fabs(d.area() - expected) <= 1e-12 * expected);
    if (n == 64) check_locate(d, in, 500, 7);
  }
  for (const std::uint32_t k : {0u, 1u, 3u, 10u}) {
    for (const double f : {0.1, 0.5, 0.9}) {
      INFO("k " << k << " fraction " << f);
      const PolygonRings in = voroclip::square_with_holes(k, f);
      const Domain2 d = checked(in);
      CHECK(d.nb_rings() == k * k + 1);
      const double expected = k == 0 ? 1.0 : 1 - f * f;
      CHECK(std::fabs(d.area() - expected) <= 1e-13);
      if (k == 3) check_locate(d, in, 500, 8);
    }
  }
}

TEST_CASE("Domain2 validates 10^5 edges quickly (sweep), however they are shaped", "[clip]") {
  // Long radial edges packed around a circle: dense for any bounding-box search, easy for
  // the sweep.
  PolygonRings star = make_rings({});
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.5, 1.0);
  const std::uint32_t n = 100000;
  star.ring_begin = {0, n};
  for (std::uint32_t k = 0; k < n; ++k) {
    const double t = 6.283185307179586 * k / n, r = u(rng);
    star.xy.push_back(r * std::cos(t));
    star.xy.push_back(r * std::sin(t));
  }
  star.ring_polygon = {0};
  star.ring_line = {0};
  const Domain2 d(star);
  CHECK(d.nb_vertices() == n);
  // A crossing added near the end is found; the edges are too long and dense to count every
  // contact, so the one the sweep found is reported.
  star.xy[2 * 77777] *= 3;
  const std::string message = domain_error(star);
  CHECK(message.find("crosses itself") != std::string::npos);
  CHECK(message.find("(the first contact found; too many candidates to count them all)") !=
        std::string::npos);
  // Many holes.
  const Domain2 h(voroclip::square_with_holes(150, 0.5));
  CHECK(h.nb_rings() == 22501);
  CHECK(std::fabs(h.area() - 0.75) < 1e-12);
}

// ---------------------------------------------------------------------------------------
// Random rings against the oracle, and scale invariance

namespace {

// Random rings: a star-shaped outer ring and small holes on a coarse lattice (so that
// collinear points, shared points and touching edges are frequent), optionally scaled by
// a non-representable step (0.1) so that near-degeneracies are decided by rounding.
PolygonRings random_rings(std::mt19937_64& rng, bool several_polygons, bool by_nesting) {
  std::uniform_int_distribution<int> coord(0, 8), nb_holes(0, 3), nb_points(3, 6);
  std::uniform_real_distribution<double> angle(0, 6.283185307179586);
  const double step = rng() % 3 == 0 ? 0.1 : 1.0;
  std::vector<Ring> rings;
  Ring outer;
  std::vector<double> angles(static_cast<std::size_t>(nb_points(rng)) + 2);
  for (double& a : angles) a = angle(rng);
  std::sort(angles.begin(), angles.end());
  for (const double a : angles) {
    const double r = 1 + static_cast<double>(rng() % 4);
    outer.push_back(step * std::round(4 + r * std::cos(a)));
    outer.push_back(step * std::round(4 + r * std::sin(a)));
  }
  if (rng() % 2) std::reverse(outer.begin(), outer.end());  // (x, y) swapped: still a ring
  rings.push_back(outer);
  const int holes = nb_holes(rng);
  for (int h = 0; h < holes; ++h) {
    Ring ring;
    const int k = nb_points(rng) - 2;
    const int cx = coord(rng), cy = coord(rng);
    for (int i = 0; i < k; ++i) {
      ring.push_back(step * (cx + static_cast<int>(rng() % 3) - 1));
      ring.push_back(step * (cy + static_cast<int>(rng() % 3) - 1));
    }
    rings.push_back(ring);
  }
  std::vector<std::int32_t> polygon(rings.size(), 0);
  if (several_polygons) {
    for (std::size_t r = 1; r < rings.size(); ++r)
      polygon[r] = static_cast<std::int32_t>(rng() % 2);
    std::sort(polygon.begin(), polygon.end());  // the first ring of polygon 1 is its outer one
  }
  if (by_nesting) polygon.assign(rings.size(), -1);
  PolygonRings out = make_rings(rings, polygon, "random");
  if (by_nesting && rng() % 2) {
    out.hole_points = {step * coord(rng), step * coord(rng)};
  }
  return out;
}

}  // namespace

TEST_CASE("Domain2 agrees with the brute-force oracle on random rings",
          "[clip][exact][degenerate]") {
  const std::uint64_t seed = 20261122;
  INFO("seed " << seed);
  std::mt19937_64 rng(seed);
  std::size_t nb_valid = 0, nb_contact = 0, nb_nesting = 0;
  for (int t = 0; t < 3000; ++t) {
    const PolygonRings in = random_rings(rng, t % 3 == 1, t % 3 == 2);
    const Verdict v = validate_q(in);
    const std::string message = domain_error(in);
    INFO("case " << t << ": " << message);
    REQUIRE(message.empty() == v.valid);
    if (v.valid) {
      ++nb_valid;
      const Domain2 d = checked(in);
      if (t % 10 == 0) check_locate(d, in, 50, seed + static_cast<std::uint64_t>(t));
      continue;
    }
    bool named = false;
    for (const std::string& part : v.message)
      named = named || message.find(part) != std::string::npos;
    CHECK(named);
    if (v.contacts.total() > 0) ++nb_contact;
    if (v.contacts.total() > 1) {
      CHECK(message.find("(edge pairs in all: " + std::to_string(v.contacts.crossing) +
                         " crossing, " + std::to_string(v.contacts.touching) + " touching") !=
            std::string::npos);
    }
    if (v.contacts.total() == 0 && v.message.size() > 1) ++nb_nesting;
  }
  // Each family occurs often enough to mean something.
  CHECK(nb_valid > 300);
  CHECK(nb_contact > 300);
  CHECK(nb_nesting > 30);
}

TEST_CASE("Domain2 agrees with the oracle on larger random star-shaped rings", "[clip][.slow]") {
  // Star-shaped rings of up to 60 lattice points around the centre (valid unless the
  // lattice rounding folds them) and lattice holes: many collinear runs and contacts.
  const std::uint64_t seed = 777;
  INFO("seed " << seed);
  std::mt19937_64 rng(seed);
  std::size_t nb_valid = 0;
  for (int t = 0; t < 20000; ++t) {
    std::vector<Ring> rings;
    std::vector<double> angles(3 + rng() % 58);
    std::uniform_real_distribution<double> angle(0, 6.283185307179586);
    for (double& a : angles) a = angle(rng);
    std::sort(angles.begin(), angles.end());
    Ring outer;
    for (const double a : angles) {
      const double r = 4 + static_cast<double>(rng() % 12);
      outer.push_back(std::round(16 + r * std::cos(a)));
      outer.push_back(std::round(16 + r * std::sin(a)));
    }
    rings.push_back(outer);
    for (int h = static_cast<int>(rng() % 4); h > 0; --h) {
      const double cx = static_cast<double>(8 + rng() % 16),
                   cy = static_cast<double>(8 + rng() % 16);
      const double s = static_cast<double>(1 + rng() % 3);
      rings.push_back({cx - s, cy - s, cx, cy + s, cx + s, cy - s});
    }
    const PolygonRings in = make_rings(rings, {}, "random");
    const Verdict v = validate_q(in);
    const std::string message = domain_error(in);
    INFO("case " << t << ": " << message);
    REQUIRE(message.empty() == v.valid);
    if (v.valid) {
      ++nb_valid;
      checked(in);
    } else if (v.contacts.total() > 1) {
      REQUIRE(message.find("(edge pairs in all: " + std::to_string(v.contacts.crossing) +
                           " crossing, " + std::to_string(v.contacts.touching) + " touching") !=
              std::string::npos);
    }
  }
  CHECK(nb_valid > 1000);
}

TEST_CASE("Domain2 finds the one defect made by moving one vertex of a valid domain",
          "[clip][exact][degenerate]") {
  // A square with 5 x 5 holes on an integer lattice (holes [2, 6] + 8 i, 8 apart); one
  // vertex moves by up to 4 along each axis, to the lattice, often onto a vertex or an edge
  // of its own ring or of a neighbour, or far away: the sweep must find exactly what the
  // brute force finds.
  PolygonRings base = voroclip::square_with_holes(5, 0.5);
  for (double& x : base.xy) x *= 40;
  const std::uint64_t seed = 4242;
  INFO("seed " << seed);
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> offset(-2, 2), far(0, 40);
  std::size_t nb_valid = 0;
  for (int t = 0; t < 600; ++t) {
    PolygonRings in = base;
    const std::size_t v = rng() % (in.xy.size() / 2);
    if (t % 5 == 0) {
      in.xy[2 * v] = 5.0 * far(rng);
      in.xy[2 * v + 1] = 5.0 * far(rng);
    } else {
      in.xy[2 * v] += 2.0 * offset(rng);
      in.xy[2 * v + 1] += 2.0 * offset(rng);
    }
    const Verdict verdict = validate_q(in);
    const std::string message = domain_error(in);
    INFO("case " << t << ": " << message);
    REQUIRE(message.empty() == verdict.valid);
    if (verdict.valid) {
      ++nb_valid;
      checked(in);
    } else if (verdict.contacts.total() > 1) {
      CHECK(message.find("(edge pairs in all: " + std::to_string(verdict.contacts.crossing) +
                         " crossing, " + std::to_string(verdict.contacts.touching) + " touching") !=
            std::string::npos);
    }
  }
  CHECK(nb_valid > 100);
  CHECK(nb_valid < 500);
}

TEST_CASE("Domain2 lists every contact of long slanted edges (grid walk)", "[clip][exact]") {
  // Squares along the diagonal, and a long thin hole along it: its edges are long and
  // slanted, so the grid enters them in the cells along their line only. One variant
  // crosses the squares, the other passes exactly through their corners.
  for (const bool through_corners : {false, true}) {
    INFO("through corners " << through_corners);
    const int n = 300;
    std::vector<Ring> rings = {{-1, -1, n + 1.0, -1, n + 1.0, n + 1.0, -1, n + 1.0}};
    for (int i = 0; i < n; ++i) {
      const double a = i + 0.25, b = i + 0.75;
      rings.push_back({a, a, a, b, b, b, b, a});
    }
    if (through_corners) {
      rings.push_back({0, 0, n - 0.5, n - 0.5, 0, 1});  // the edge 0-1 lies on y = x
    } else {
      rings.push_back({0, 0.1, n - 0.5, n - 0.3, 0, 0.5});
    }
    const PolygonRings in = make_rings(rings);
    const Verdict v = validate_q(in);
    const std::string message = domain_error(in);
    INFO(message);
    REQUIRE(!v.valid);
    REQUIRE(v.contacts.total() > static_cast<std::size_t>(n));
    CHECK(message.find("(edge pairs in all: " + std::to_string(v.contacts.crossing) +
                       " crossing, " + std::to_string(v.contacts.touching) + " touching") !=
          std::string::npos);
  }
}

TEST_CASE("Domain2 verdicts do not depend on the scale (x 2^-400, x 2^400)", "[clip][exact]") {
  std::vector<PolygonRings> inputs;
  for (const char* f :
       {"valid/building.json", "valid/dude.json", "valid/eberly-6.json", "valid/issue35.json",
        "degenerate/degenerate.json", "degenerate/self-touching.json", "degenerate/water.json",
        "degenerate/eberly-3.json", "degenerate/steiner.json"}) {
    inputs.push_back(voroclip::read_polygon(kPolygons + f));
  }
  std::mt19937_64 rng(99);
  for (int t = 0; t < 300; ++t) inputs.push_back(random_rings(rng, t % 3 == 1, t % 3 == 2));
  for (const PolygonRings& in : inputs) {
    const std::string message = without_coordinates(domain_error(in));
    INFO(in.source << ": " << message);
    for (const int e : {-400, 400}) {
      const PolygonRings s = scaled(in, e);
      CHECK(without_coordinates(domain_error(s)) == message);
      if (message.empty()) {
        const Domain2 d(in), ds(s);
        CHECK(ds.area() == std::ldexp(d.area(), 2 * e));
        CHECK(ds.nb_vertices() == d.nb_vertices());
        for (std::uint32_t r = 0; r < d.nb_rings(); ++r) CHECK(ds.is_hole(r) == d.is_hole(r));
        for (std::uint32_t v = 0; v < d.nb_vertices(); v += 7) {
          const double q[2] = {std::ldexp(0.5 * (d.vertex(v)[0] + d.vertex(d.next(v))[0]), e),
                               std::ldexp(0.5 * (d.vertex(v)[1] + d.vertex(d.next(v))[1]), e)};
          const double q0[2] = {std::ldexp(q[0], -e), std::ldexp(q[1], -e)};
          CHECK(ds.locate(q) == d.locate(q0));
        }
      }
    }
  }
}

TEST_CASE("Domain2 keeps edge tags and regions; a region point outside is refused",
          "[clip][exact]") {
  // A square with a square hole: ring tags 1 (outer) and 2 (hole) without markers.
  PolygonRings r = make_rings({{0, 0, 4, 0, 4, 4, 0, 4}, {1, 1, 1, 3, 3, 3, 3, 1}});
  const Domain2 plain(r);
  for (std::uint32_t e = 0; e < plain.nb_edges(); ++e) {
    CHECK(plain.edge_tag(e) == (plain.is_hole(plain.ring_of(e)) ? 2 : 1));
  }
  // Markers per input segment follow their segment through the hole's reversal.
  r.segment_marker = {10, 11, 12, 13, 20, 21, 22, 23};
  const Domain2 marked(r);
  for (std::uint32_t e = 0; e < marked.nb_edges(); ++e) {
    const double* a = marked.vertex(e);
    const double* b = marked.vertex(marked.next(e));
    // The input segment from point i to i + 1 has marker 10 + i (outer) or 20 + i (hole).
    bool found = false;
    for (std::uint32_t ring = 0; ring < 2; ++ring) {
      for (std::uint32_t i = 0; i < 4; ++i) {
        const double* p = &r.xy[2 * (4 * ring + i)];
        const double* q = &r.xy[2 * (4 * ring + (i + 1) % 4)];
        const bool same = (p[0] == a[0] && p[1] == a[1] && q[0] == b[0] && q[1] == b[1]) ||
                          (p[0] == b[0] && p[1] == b[1] && q[0] == a[0] && q[1] == a[1]);
        if (same) {
          CHECK(marked.edge_tag(e) == static_cast<std::int32_t>(10 * (ring + 1) + i));
          found = true;
        }
      }
    }
    CHECK(found);
  }
  r.region_points = {0.5, 0.5};
  r.region_attributes = {7};
  CHECK(Domain2(r).region_attributes().size() == 1);
  r.region_points = {2, 2};  // in the hole
  CHECK_THROWS_WITH(Domain2(r),
                    Catch::Contains("regional attribute 0 (from 0, in the order given)") &&
                        Catch::Contains("not inside the domain"));
  // Segment marker 0 means "no marker": tag 1, as in Triangle's output (Gmsh takes no
  // physical tag 0), whatever the ring; other markers stay.
  r.region_points.clear();
  r.region_attributes.clear();
  r.segment_marker = {0, 0, 5, 0, 0, -3, 0, 0};
  const Domain2 zero(r);
  std::vector<std::int32_t> tags;
  for (std::uint32_t e = 0; e < zero.nb_edges(); ++e) tags.push_back(zero.edge_tag(e));
  std::sort(tags.begin(), tags.end());
  CHECK(tags == std::vector<std::int32_t>{-3, 1, 1, 1, 1, 1, 1, 5});
}

TEST_CASE("Domain2 names .poly holes and regional attributes by their own numbers and lines",
          "[clip][regression]") {
  // 1-based vertices and holes, a 0-based region; the hole numbered 1 stands on line 13,
  // the region numbered 0 on line 15 (the file's numbers, not positions from 0 or 1).
  const std::string head =
      "# a square\n4 2 0 0\n1 0 0\n2 4 0\n3 4 4\n4 0 4\n"
      "4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n";
  const auto hole = write_temp("hole_numbers.poly", head + "1\n1 2 2\n");
  CHECK(domain_error(voroclip::read_polygon(hole)) ==
        hole +
            ": hole 1 (line 13) at (2, 2) lies inside the domain (its innermost ring, ring 0 "
            "(line 8), is an outer boundary), not in a hole (.poly numbering: the file's "
            "vertex numbers and lines)");
  const auto region = write_temp("region_numbers.poly", head + "0\n\n1\n0 9 9 3\n");
  CHECK(domain_error(voroclip::read_polygon(region)) ==
        region + ": regional attribute 0 (line 15): its point (9, 9) is not inside the domain");
  std::remove(hole.c_str());
  std::remove(region.c_str());
}

TEST_CASE("Domain2: coordinates whose area double cannot hold are an error", "[clip][regression]") {
  // A square scaled by 1e200 had area inf, by 1e-200 area 0: every cell's area with it.
  for (const double k : {1e200, 1e-200}) {
    INFO(k);
    PolygonRings r = make_rings({{0, 0, k, 0, k, k, 0, k}});
    r.source = "square";
    REQUIRE_THROWS_WITH(
        Domain2(r),
        std::string("square: its area is ") + (k > 1 ? "not finite" : "0") +
            " in double precision (coordinates up to " +
            (k > 1 ? "1e+200: too large, it overflows" : "1e-200: too small, it underflows") +
            "); rescale the model (e.g. to a size of about 1)");
  }
}
