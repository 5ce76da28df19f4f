// Domain2: exact validation of a polygonal domain with holes (the contract is in clip.h).
//
// Every combinatorial decision is an exact orient2d sign or an exact comparison of input
// doubles; floating point is used only to size the search structures and to compute area().
// The steps, each reporting the first defect it finds with the input's numbering:
//   1. per ring: finite coordinates, repeated points dropped (consecutive ones and the
//      closing repeat), at least 3 points, not all collinear;
//   2. contacts: spikes (two consecutive edges folding back onto each other: orient2d = 0
//      with both neighbours on one side), two vertices at one point, and non-adjacent
//      edges (of one ring or of two) that cross properly, overlap collinearly or touch (a
//      vertex on an edge). Whether there is any is decided by a sweep in O(n log n) (see
//      sweep()); if there is, a uniform grid (below) lists them all, counted per pair of
//      edges, and the message describes the first of the most serious kind (crossing,
//      spike, overlap, touch) and gives the counts;
//   3. nesting: for each ring, the rings that contain one of its vertices (exact crossing
//      parity of a horizontal ray; the vertex is on no other ring once step 2 passed, and
//      disjoint simple rings are either nested or apart, so the containment of one vertex
//      is that of the ring). Containment is a forest; depth = number of containing rings,
//      parent = the container one level up. Roles: JSON (ring_polygon >= 0): the first
//      ring of each polygon is its outer boundary, and a hole's parent must be its own
//      outer ring, an outer ring's parent must be a hole or nothing. .poly (ring_polygon =
//      -1): odd depth is a hole. Hole markers must lie strictly inside a hole (their
//      innermost containing ring is a hole);
//   4. orientation, decided exactly by orient2d at the lowest-leftmost vertex (its two
//      neighbours are not collinear with it once spikes are gone): outer rings are made
//      counter-clockwise and holes clockwise, reversing vertex order where needed.
//
// The contact grid (only for the message: the sweep has decided). Cells are squares of
// side h over the bounding box, h about the mean edge extent (not below max-extent / 2^21,
// nor below max|coordinate| / 2^30: that keeps rounding far below h). The cell of a
// coordinate, floor((x - lo) / h) clamped, is a monotone function of x, so two segments
// that meet share a cell of their bounding boxes. An edge whose box spans few cells is
// entered in all of them; a long slanted one only in the cells along it (per column of its
// major axis, the cells its line can reach, widened by 2h: a superset, computed in floating
// point with a margin that dominates the rounding). A pair is tested in its first common
// cell only, so each once.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "validation.h"
#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/predicates.h"

namespace voroclip {

namespace {

constexpr std::uint32_t kNone = UINT32_MAX;

bool same_point(const double* a, const double* b) { return a[0] == b[0] && a[1] == b[1]; }

// a and c on the same side of b on their common line, given a, b, c collinear, a != b and
// c != b: compare along an axis on which the line is not constant.
bool same_side_on_line(const double* a, const double* b, const double* c) {
  const int axis = a[0] != b[0] ? 0 : 1;
  return (a[axis] > b[axis]) == (c[axis] > b[axis]);
}

// (x, y), each coordinate in the shortest decimal that reads back to it (160.57125 as the
// file wrote it, not 160.57124999999999).
std::string point_text(const double* p) {
  char buf[64];
  char* end = buf;
  *end++ = '(';
  end = std::to_chars(end, buf + sizeof buf, p[0]).ptr;
  *end++ = ',';
  *end++ = ' ';
  end = std::to_chars(end, buf + sizeof buf, p[1]).ptr;
  *end++ = ')';
  return std::string(buf, end);
}

int sign_int(Sign s) { return static_cast<int>(s); }

// Kahan–Babuška–Neumaier summation: the error is O(u |sum|) + O(n u^2 sum |x|).
struct CompensatedSum {
  double sum = 0, carry = 0;
  void add(double x) {
    const double t = sum + x;
    carry += std::fabs(sum) >= std::fabs(x) ? (sum - t) + x : (x - t) + sum;
    sum = t;
  }
  double value() const { return sum + carry; }
};

// The ray-crossing test of point location: the ray from p towards +x against segment
// [a, b], with the half-open rule in y (an endpoint exactly at p's height counts as below).
enum class RayHit { kMiss, kCross, kOnEdge };

RayHit ray_hit(const double* a, const double* b, const double* p) {
  const bool a_above = a[1] > p[1], b_above = b[1] > p[1];
  if (a_above == b_above) {
    // No straddle. p can still be on the segment: at an endpoint, or along a horizontal
    // segment at its height.
    if (a[1] == p[1] && b[1] == p[1]) {
      return std::min(a[0], b[0]) <= p[0] && p[0] <= std::max(a[0], b[0]) ? RayHit::kOnEdge
                                                                          : RayHit::kMiss;
    }
    return same_point(a, p) || same_point(b, p) ? RayHit::kOnEdge : RayHit::kMiss;
  }
  // a, b straddle p's height, so the segment is not horizontal: p is on it iff collinear.
  const Sign o = orient2d(a, b, p);
  if (o == Sign::zero) return RayHit::kOnEdge;
  // Upward edge (b above): the crossing is right of p iff p is left of a->b.
  return (b_above ? o == Sign::positive : o == Sign::negative) ? RayHit::kCross : RayHit::kMiss;
}

// Names for messages, in the input's numbering: rings by index (per polygon when the
// JSON holds several), .poly rings with the line where they start, vertices by their
// position in their ring or, when the format numbers them, by that number.
class Namer {
 public:
  explicit Namer(const PolygonRings& in) : in_(in) {
    std::map<std::int32_t, std::uint32_t> count;
    for (const std::int32_t q : in.ring_polygon) {
      if (q > 0) several_ = true;
      index_in_polygon_.push_back(count[q]++);
    }
  }

  std::string ring(std::uint32_t r, const std::string& detail = "") const {
    std::string name = several_ ? "polygon " + std::to_string(in_.ring_polygon[r]) + " ring " +
                                      std::to_string(index_in_polygon_[r])
                                : "ring " + std::to_string(r);
    std::string d;
    if (!in_.ring_line.empty() && in_.ring_line[r] != 0) {
      d = "line " + std::to_string(in_.ring_line[r]);
    }
    if (!detail.empty()) d += (d.empty() ? "" : ", ") + detail;
    return d.empty() ? name : name + " (" + d + ")";
  }

  // Input point p of ring r.
  std::string point(std::uint32_t r, std::uint32_t p) const {
    if (!in_.point_number.empty()) return std::to_string(in_.point_number[p]);
    return std::to_string(p - in_.ring_begin[r]);
  }

 private:
  const PolygonRings& in_;
  bool several_ = false;
  std::vector<std::uint32_t> index_in_polygon_;
};

// A contact between two edges e1 < e2 (edge e: vertex e to next(e)): non-adjacent ones
// that meet, or adjacent ones that fold back (a spike). Kinds in the order of reporting.
struct Contact {
  enum Kind : std::uint8_t { kCross = 0, kSpike = 1, kOverlap = 2, kTouch = 3 };
  Kind kind = kTouch;
  std::uint32_t e1 = 0, e2 = 0;
  // kSpike: the vertex where the edges fold back. kTouch: the vertex that touches (an
  // endpoint of e1 or e2) and, when it coincides with an endpoint of the other edge, that
  // endpoint (else kNone: it is inside the other edge).
  std::uint32_t vertex = kNone, other_vertex = kNone;
};

// The grid of the contact search (see the header comment).
struct Grid {
  double lo[2] = {0, 0};
  double h = 1;
  std::int64_t n[2] = {1, 1};

  std::int64_t cell(double x, int axis) const {
    const double t = (x - lo[axis]) / h;
    if (!(t >= 0)) return 0;  // also NaN
    if (t >= static_cast<double>(n[axis])) return n[axis] - 1;
    return static_cast<std::int64_t>(t);
  }
  std::uint64_t key(std::int64_t cx, std::int64_t cy) const {
    return static_cast<std::uint64_t>(cy) * static_cast<std::uint64_t>(n[0]) +
           static_cast<std::uint64_t>(cx);
  }

  // Appends the cells segment [p, q] may meet (a superset, see the header comment).
  void cells_of_segment(const double* p, const double* q, std::vector<std::uint64_t>& out) const {
    std::int64_t c0[2], c1[2];
    for (int a = 0; a < 2; ++a) {
      c0[a] = cell(std::min(p[a], q[a]), a);
      c1[a] = cell(std::max(p[a], q[a]), a);
    }
    const std::int64_t nx = c1[0] - c0[0] + 1, ny = c1[1] - c0[1] + 1;
    if (nx * ny <= 2 * (nx + ny) + 4) {
      for (std::int64_t cy = c0[1]; cy <= c1[1]; ++cy) {
        for (std::int64_t cx = c0[0]; cx <= c1[0]; ++cx) out.push_back(key(cx, cy));
      }
      return;
    }
    // Long and slanted: walk the columns of the major axis `a`; nx * ny above the bound
    // implies at least 5 cells along `a`, so the endpoints differ there and |slope| < 2.
    const int a = nx >= ny ? 0 : 1, o = 1 - a;
    const double* s = p[a] <= q[a] ? p : q;
    const double* t = p[a] <= q[a] ? q : p;
    const double slope = (t[o] - s[o]) / (t[a] - s[a]);
    for (std::int64_t c = c0[a]; c <= c1[a]; ++c) {
      const double u0 = std::max(s[a], lo[a] + static_cast<double>(c - 1) * h);
      const double u1 = std::min(t[a], lo[a] + static_cast<double>(c + 2) * h);
      const double v0 = s[o] + (u0 - s[a]) * slope, v1 = s[o] + (u1 - s[a]) * slope;
      const std::int64_t r0 = std::max(c0[o], cell(std::min(v0, v1) - 2 * h, o));
      const std::int64_t r1 = std::min(c1[o], cell(std::max(v0, v1) + 2 * h, o));
      for (std::int64_t r = r0; r <= r1; ++r) out.push_back(a == 0 ? key(c, r) : key(r, c));
    }
  }
};

}  // namespace

// ---------------------------------------------------------------------------------------

struct Domain2Impl {
  Domain2& d;
  const PolygonRings& in;
  Namer names;

  Domain2Impl(Domain2& domain, const PolygonRings& rings) : d(domain), in(rings), names(rings) {}

  // Every message about numbered elements says how it numbers them: .poly files by the
  // file's vertex numbers, rings and hole markers also by their lines (and markers from 0
  // in the file's order); other input (JSON, arrays) by positions in the arrays, from 0.
  // Messages about the PolygonRings structure itself name no element.
  [[noreturn]] void fail(const std::string& what) const {
    const bool poly = !in.point_number.empty();
    const bool numbered =
        what.rfind("malformed", 0) != 0 &&
        (what.find("ring ") != std::string::npos || what.find("vert") != std::string::npos ||
         what.find("polygon ") != std::string::npos || what.find("marker ") != std::string::npos);
    const std::string note = !numbered ? ""
                             : poly    ? " (.poly numbering: the file's vertex numbers and lines)"
                             : what.find("polygon ") != std::string::npos
                                 ? " (polygons, rings and points numbered from 0)"
                                 : " (rings and points numbered from 0)";
    throw Error((d.source_.empty() ? std::string("polygon") : d.source_) + ": " + what + note);
  }

  const double* p(std::uint32_t v) const { return d.vertex(v); }
  std::string label(std::uint32_t v) const {
    return names.point(d.source_ring_[d.ring_of_[v]], d.source_vertex_[v]);
  }
  std::string edge_label(std::uint32_t e) const { return label(e) + "-" + label(d.next(e)); }
  std::string ring_name(std::uint32_t r, const std::string& detail = "") const {
    return names.ring(d.source_ring_[r], detail);
  }
  // Hole marker k (in the order given) as the file names it: its own number and line.
  std::string hole_name(std::size_t k) const {
    if (in.hole_number.empty()) {
      std::string name = "hole marker " + std::to_string(k) + " (from 0, in the order given";
      if (!in.hole_line.empty()) name += "; line " + std::to_string(in.hole_line[k]);
      return name + ")";
    }
    std::string name = "hole " + std::to_string(in.hole_number[k]);
    if (!in.hole_line.empty()) name += " (line " + std::to_string(in.hole_line[k]) + ")";
    return name;
  }

  void check_structure() const;
  void copy_rings();
  bool contact(std::uint32_t e, std::uint32_t f, Contact* out) const;
  bool sweep(Contact* found) const;
  std::string describe(const Contact& c) const;
  void check_contacts() const;
  void build_bands();
  void nest_and_orient();
  void compute_area();

  // Calls visit(e, hit) for the edges e of q's band along `axis` (0: the ray runs towards
  // +x, 1: towards +y), hit being the exact RayHit of that ray with edge e.
  template <class Visit>
  static void cast_ray(const Domain2& d, int axis, const double* q, Visit&& visit) {
    const Domain2::Bands& bands = d.bands_[axis];
    const std::uint32_t k = bands.band(q[1 - axis]);
    for (std::uint32_t i = bands.begin[k]; i < bands.begin[k + 1]; ++i) {
      const std::uint32_t e = bands.edge[i];
      const double* a = d.vertex(e);
      const double* b = d.vertex(d.next(e));
      if (axis == 0) {
        visit(e, ray_hit(a, b, q));
      } else {
        // The same test with x and y exchanged: the ray towards +y (parity is all we need,
        // and it does not depend on the ray's direction).
        const double as[2] = {a[1], a[0]}, bs[2] = {b[1], b[0]}, qs[2] = {q[1], q[0]};
        visit(e, ray_hit(as, bs, qs));
      }
    }
  }
  // The axis whose band through q lists fewer edges.
  static int best_axis(const Domain2& d, const double* q) {
    std::uint32_t count[2];
    for (int axis = 0; axis < 2; ++axis) {
      const Domain2::Bands& bands = d.bands_[axis];
      const std::uint32_t k = bands.band(q[1 - axis]);
      count[axis] = bands.begin[k + 1] - bands.begin[k];
    }
    return count[1] < count[0] ? 1 : 0;
  }
};

void Domain2Impl::check_structure() const {
  const auto fail_structure = [this](const std::string& what) {
    fail("malformed PolygonRings: " + what);
  };
  if (in.xy.size() % 2 != 0) fail_structure("xy holds an odd number of coordinates");
  if (in.nb_rings() == 0) fail("no rings: the domain is empty");
  if (in.ring_begin.front() != 0 || in.ring_begin.back() != in.xy.size() / 2) {
    fail_structure("ring_begin must run from 0 to the number of points");
  }
  for (std::uint32_t r = 0; r < in.nb_rings(); ++r) {
    if (in.ring_begin[r] > in.ring_begin[r + 1]) fail_structure("ring_begin decreases");
  }
  if (in.ring_polygon.size() != in.nb_rings()) {
    fail_structure("ring_polygon needs one entry per ring");
  }
  const bool by_nesting = in.ring_polygon.front() < 0;
  for (const std::int32_t q : in.ring_polygon) {
    if ((q < 0) != by_nesting) {
      fail_structure("ring_polygon must be -1 for every ring or for none");
    }
  }
  if (!in.ring_line.empty() && in.ring_line.size() != in.nb_rings()) {
    fail_structure("ring_line must be empty or have one entry per ring");
  }
  if (!in.point_number.empty() && in.point_number.size() != in.xy.size() / 2) {
    fail_structure("point_number must be empty or have one entry per point");
  }
  if (in.hole_points.size() % 2 != 0) fail_structure("hole_points holds an odd count");
  if (!in.hole_line.empty() && in.hole_line.size() != in.hole_points.size() / 2) {
    fail_structure("hole_line must be empty or have one entry per hole marker");
  }
  if (!in.hole_number.empty() && in.hole_number.size() != in.hole_points.size() / 2) {
    fail_structure("hole_number must be empty or have one entry per hole marker");
  }
  const std::size_t nb_points = in.xy.size() / 2;
  if (!in.segment_number.empty() && in.segment_number.size() != nb_points) {
    fail_structure("segment_number must be empty or have one entry per point");
  }
  if (!in.segment_line.empty() && in.segment_line.size() != nb_points) {
    fail_structure("segment_line must be empty or have one entry per point");
  }
  if (in.region_points.size() != 2 * in.region_attributes.size()) {
    fail_structure("region_points must hold two coordinates per regional attribute");
  }
  if (!in.region_number.empty() && in.region_number.size() != in.region_attributes.size()) {
    fail_structure("region_number must be empty or have one entry per regional attribute");
  }
  if (!in.region_line.empty() && in.region_line.size() != in.region_attributes.size()) {
    fail_structure("region_line must be empty or have one entry per regional attribute");
  }
  for (std::size_t k = 0; k < in.hole_points.size(); ++k) {
    if (!std::isfinite(in.hole_points[k])) {
      fail(hole_name(k / 2) + " has a non-finite coordinate");
    }
  }
}

// Step 1: copy ring after ring, dropping repeated points, and check each ring alone.
void Domain2Impl::copy_rings() {
  const std::uint32_t nb_rings = in.nb_rings();
  d.ring_begin_.assign(1, 0);
  for (std::uint32_t r = 0; r < nb_rings; ++r) {
    const std::uint32_t b = static_cast<std::uint32_t>(d.ring_of_.size());
    for (std::uint32_t i = in.ring_begin[r]; i < in.ring_begin[r + 1]; ++i) {
      const double* q = &in.xy[2 * std::size_t{i}];
      if (!std::isfinite(q[0]) || !std::isfinite(q[1])) {
        fail(names.ring(r, "vertex " + names.point(r, i)) + " has a non-finite coordinate");
      }
      if (d.ring_of_.size() > b && same_point(q, &d.xy_[d.xy_.size() - 2])) {
        ++d.nb_dropped_;
        continue;
      }
      d.xy_.push_back(q[0]);
      d.xy_.push_back(q[1]);
      d.ring_of_.push_back(r);
      d.source_vertex_.push_back(i);
    }
    while (d.ring_of_.size() > b + 1 &&
           same_point(&d.xy_[2 * std::size_t{b}], &d.xy_[d.xy_.size() - 2])) {
      d.xy_.resize(d.xy_.size() - 2);
      d.ring_of_.pop_back();
      d.source_vertex_.pop_back();
      ++d.nb_dropped_;
    }
    const std::uint32_t e = static_cast<std::uint32_t>(d.ring_of_.size());
    d.ring_begin_.push_back(e);
    d.source_ring_.push_back(r);
    d.ring_polygon_.push_back(in.ring_polygon[r]);
    d.ring_hole_.push_back(0);
    if (e - b < 3) {
      fail(names.ring(r) + " has fewer than 3 distinct points (" + std::to_string(e - b) +
           (e - b == 1 ? " point" : " points") + " once repeats are dropped)");
    }
    // All collinear: zero area. b and b + 1 differ (repeats are gone).
    bool collinear = true;
    for (std::uint32_t v = b + 2; v < e && collinear; ++v) {
      collinear = orient2d(p(b), p(b + 1), p(v)) == Sign::zero;
    }
    if (collinear) {
      fail(names.ring(r) + " has zero area: its " + std::to_string(e - b) +
           " points are all collinear");
    }
  }
  d.xy_.shrink_to_fit();
}

// The contact between edges e < f, if any (adjacent edges excepted: they meet at their
// common vertex, and fold back only as a spike, which is checked on its own).
bool Domain2Impl::contact(std::uint32_t e, std::uint32_t f, Contact* out) const {
  if (d.next(e) == f || d.next(f) == e) return false;
  const double* a = p(e);
  const double* b = p(d.next(e));
  const double* c = p(f);
  const double* dd = p(d.next(f));
  if (std::max(a[0], b[0]) < std::min(c[0], dd[0]) ||
      std::max(c[0], dd[0]) < std::min(a[0], b[0]) ||
      std::max(a[1], b[1]) < std::min(c[1], dd[1]) ||
      std::max(c[1], dd[1]) < std::min(a[1], b[1])) {
    return false;
  }
  const int o1 = sign_int(orient2d(a, b, c)), o2 = sign_int(orient2d(a, b, dd));
  if (o1 * o2 > 0) return false;
  const int o3 = sign_int(orient2d(c, dd, a)), o4 = sign_int(orient2d(c, dd, b));
  if (o3 * o4 > 0) return false;
  Contact t{Contact::kTouch, e, f};
  if (o1 == 0 && o2 == 0) {
    // Collinear: compare along an axis on which the common line is not constant.
    const int axis = a[0] != b[0] ? 0 : 1;
    const double lo_ab = std::min(a[axis], b[axis]), hi_ab = std::max(a[axis], b[axis]);
    const double lo_cd = std::min(c[axis], dd[axis]), hi_cd = std::max(c[axis], dd[axis]);
    const double lo_both = std::max(lo_ab, lo_cd), hi_both = std::min(hi_ab, hi_cd);
    if (lo_both > hi_both) return false;
    if (lo_both < hi_both) {
      t.kind = Contact::kOverlap;
    } else {
      // One common point, an endpoint of both.
      t.vertex = a[axis] == lo_both ? e : d.next(e);
      t.other_vertex = c[axis] == lo_both ? f : d.next(f);
    }
  } else if (o1 != 0 && o2 != 0 && o3 != 0 && o4 != 0) {
    t.kind = Contact::kCross;
  } else {
    // They meet at one point, an endpoint lying on the line of the other edge.
    t.vertex = o1 == 0 ? f : o2 == 0 ? d.next(f) : o3 == 0 ? e : d.next(e);
    const bool of_e = t.vertex == e || t.vertex == d.next(e);
    const std::uint32_t g = of_e ? f : e;
    if (same_point(p(t.vertex), p(g))) {
      t.other_vertex = g;
    } else if (same_point(p(t.vertex), p(d.next(g)))) {
      t.other_vertex = d.next(g);
    }
  }
  *out = t;
  return true;
}

// Whether any contact exists (a spike, two vertices at one point, or two non-adjacent
// edges meeting), and one of them: the sweep of Shamos & Hoey (1976), in the form of
// CGAL's is_simple_2, O(n log n) whatever the shape. Vertices are visited in lexicographic
// (x, y) order; the status holds the edges met by the sweep line, from below to above;
// every pair of edges that becomes adjacent in the status is tested exactly, which finds
// the leftmost contact when the sweep reaches it at the latest. The order of two edges is
// read at the lexicographically later of their left endpoints (orient2d), so it needs no
// sweep position and holds while the status has no contact.
bool Domain2Impl::sweep(Contact* found) const {
  const std::uint32_t n = d.nb_vertices();
  const auto lex_less = [this](std::uint32_t u, std::uint32_t v) {
    return p(u)[0] < p(v)[0] || (p(u)[0] == p(v)[0] && p(u)[1] < p(v)[1]);
  };
  for (std::uint32_t v = 0; v < n; ++v) {
    const std::uint32_t u = d.prev(v), w = d.next(v);
    if (orient2d(p(u), p(v), p(w)) == Sign::zero && same_side_on_line(p(u), p(v), p(w))) {
      *found = {Contact::kSpike, std::min(u, v), std::max(u, v), v};
      return true;
    }
  }
  std::vector<std::uint32_t> order(n), left(n), right(n);
  for (std::uint32_t v = 0; v < n; ++v) {
    order[v] = v;
    const bool forward = lex_less(v, d.next(v));
    left[v] = forward ? v : d.next(v);
    right[v] = forward ? d.next(v) : v;
  }
  std::sort(order.begin(), order.end(), lex_less);
  for (std::uint32_t i = 1; i < n; ++i) {
    const std::uint32_t a = std::min(order[i - 1], order[i]), b = std::max(order[i - 1], order[i]);
    if (same_point(p(a), p(b))) {
      *found = {Contact::kTouch, a, b, a, b};  // two vertices at one point
      return true;
    }
  }

  // Sign of (e - f) in the status: negative when e is below f. Antisymmetric; on a contact
  // (a zero orientation) it falls back to the other endpoint, then to edge numbers: the
  // neighbour tests after each update find that contact.
  const auto compare_later = [&](std::uint32_t e, std::uint32_t f) {
    // left[e] is at or after left[f].
    const double* lf = p(left[f]);
    const double* rf = p(right[f]);
    if (left[e] == left[f]) {
      const Sign s = orient2d(lf, p(right[e]), rf);  // rf above the line of e: e below f
      if (s != Sign::zero) return s == Sign::positive ? -1 : 1;
    } else {
      const Sign s = orient2d(lf, rf, p(left[e]));
      if (s != Sign::zero) return s == Sign::negative ? -1 : 1;
      const Sign t = orient2d(lf, rf, p(right[e]));
      if (t != Sign::zero) return t == Sign::negative ? -1 : 1;
    }
    return e < f ? -1 : 1;
  };
  const auto below = [&](std::uint32_t e, std::uint32_t f) {
    if (e == f) return false;
    if (left[e] == left[f] || !lex_less(left[e], left[f])) return compare_later(e, f) < 0;
    return compare_later(f, e) > 0;
  };
  using Status = std::set<std::uint32_t, decltype(below)>;
  Status status(below);
  std::vector<Status::iterator> where(n, status.end());
  const auto meet = [&](Status::iterator a, Status::iterator b) {
    if (a == status.end() || b == status.end()) return false;
    return contact(std::min(*a, *b), std::max(*a, *b), found);
  };
  const auto before = [&](Status::iterator it) {
    return it == status.begin() ? status.end() : std::prev(it);
  };
  for (const std::uint32_t v : order) {
    const std::uint32_t edges[2] = {d.prev(v), v};
    // Edges ending at v leave the status; their neighbours become adjacent.
    for (const std::uint32_t e : edges) {
      if (right[e] != v) continue;
      const auto it = where[e];
      const auto up = std::next(it), down = before(it);
      status.erase(it);
      if (meet(down, up)) return true;
    }
    // Edges starting at v enter it; each is tested against its new neighbours.
    for (const std::uint32_t e : edges) {
      if (left[e] != v) continue;
      const auto inserted = status.insert(e);
      if (!inserted.second) fail("internal error: the sweep order is not strict");
      where[e] = inserted.first;
    }
    for (const std::uint32_t e : edges) {
      if (left[e] != v) continue;
      if (meet(before(where[e]), where[e]) || meet(where[e], std::next(where[e]))) return true;
    }
  }
  return false;
}

// Step 2: contacts. The sweep decides; when it finds one, the grid lists them all for the
// message, unless the candidate pairs are too many (edges long and dense, e.g. thousands of
// long spikes side by side): then the contact the sweep found is reported alone.
void Domain2Impl::check_contacts() const {
  Contact found;
  if (!sweep(&found)) return;
  const std::uint32_t n = d.nb_vertices();
  const double* lo = d.bbox_lo();
  const double* hi = d.bbox_hi();
  Grid grid;
  {
    double mean = 0, max_abs = 0;
    for (std::uint32_t e = 0; e < n; ++e) {
      const double* a = p(e);
      const double* b = p(d.next(e));
      mean += std::max(std::fabs(b[0] - a[0]), std::fabs(b[1] - a[1]));
      max_abs = std::max(max_abs, std::max(std::fabs(a[0]), std::fabs(a[1])));
    }
    mean /= n;
    constexpr double kMaxCells = 0x1p21;
    const double extent = std::max(hi[0] - lo[0], hi[1] - lo[1]);
    const double h = std::max({mean, extent / kMaxCells, max_abs * 0x1p-30});
    grid.lo[0] = lo[0];
    grid.lo[1] = lo[1];
    if (h > 0 && std::isfinite(h) && std::isfinite(extent)) {
      grid.h = h;
      for (int a = 0; a < 2; ++a) {
        grid.n[a] = std::min(static_cast<std::int64_t>(kMaxCells),
                             static_cast<std::int64_t>((hi[a] - lo[a]) / h) + 1);
      }
    } else {
      grid.h = std::numeric_limits<double>::infinity();  // one cell: every pair is tested
    }
  }
  // Per edge, its sorted cells; then (cell, edge) entries sorted by cell.
  std::vector<std::uint32_t> cell_begin(std::size_t{n} + 1, 0);
  std::vector<std::uint64_t> cells;
  for (std::uint32_t e = 0; e < n; ++e) {
    const std::size_t first = cells.size();
    grid.cells_of_segment(p(e), p(d.next(e)), cells);
    std::sort(cells.begin() + static_cast<std::ptrdiff_t>(first), cells.end());
    cell_begin[e + 1] = static_cast<std::uint32_t>(cells.size());
  }
  std::vector<std::pair<std::uint64_t, std::uint32_t>> entries;
  entries.reserve(cells.size());
  for (std::uint32_t e = 0; e < n; ++e) {
    for (std::uint32_t k = cell_begin[e]; k < cell_begin[e + 1]; ++k)
      entries.emplace_back(cells[k], e);
  }
  std::sort(entries.begin(), entries.end());

  // The first cell shared by edges e and f (their lists are sorted).
  const auto first_common = [&](std::uint32_t e, std::uint32_t f) {
    std::uint32_t i = cell_begin[e], j = cell_begin[f];
    while (i < cell_begin[e + 1] && j < cell_begin[f + 1]) {
      if (cells[i] == cells[j]) return cells[i];
      if (cells[i] < cells[j]) {
        ++i;
      } else {
        ++j;
      }
    }
    return std::uint64_t{UINT64_MAX};
  };

  std::size_t nb_candidates = 0;
  for (std::size_t i = 0; i < entries.size();) {
    std::size_t j = i;
    while (j < entries.size() && entries[j].first == entries[i].first) ++j;
    nb_candidates += (j - i) * (j - i - 1) / 2;
    i = j;
  }
  if (nb_candidates > 16 * std::size_t{n} + (std::size_t{1} << 20)) {
    fail(describe(found) + " (the first contact found; too many candidates to count them all)");
  }

  std::vector<Contact> contacts;
  for (std::uint32_t v = 0; v < n; ++v) {
    const std::uint32_t u = d.prev(v), w = d.next(v);
    if (orient2d(p(u), p(v), p(w)) == Sign::zero && same_side_on_line(p(u), p(v), p(w))) {
      contacts.push_back({Contact::kSpike, std::min(u, v), std::max(u, v), v});
    }
  }

  for (std::size_t i = 0; i < entries.size();) {
    std::size_t j = i;
    while (j < entries.size() && entries[j].first == entries[i].first) ++j;
    for (std::size_t x = i; x < j; ++x) {
      for (std::size_t y = x + 1; y < j; ++y) {
        const std::uint32_t e = entries[x].second, f = entries[y].second;
        Contact t;
        if (first_common(e, f) == entries[i].first && contact(e, f, &t)) contacts.push_back(t);
      }
    }
    i = j;
  }
  if (contacts.empty()) fail("internal error: the sweep found a contact, the grid none");

  // Report the first contact of the most serious kind, and the counts.
  std::size_t counts[4] = {0, 0, 0, 0};
  for (const Contact& c : contacts) ++counts[c.kind];
  const Contact& c =
      *std::min_element(contacts.begin(), contacts.end(), [](const Contact& x, const Contact& y) {
        return std::make_tuple(x.kind, x.e1, x.e2) < std::make_tuple(y.kind, y.e1, y.e2);
      });
  std::string what = describe(c);
  if (contacts.size() > 1) {
    // Counted per pair of edges (a vertex touching at a corner is several pairs).
    const std::size_t touching =
        counts[Contact::kSpike] + counts[Contact::kOverlap] + counts[Contact::kTouch];
    what += " (edge pairs in all: " + std::to_string(counts[Contact::kCross]) + " crossing, " +
            std::to_string(touching) + " touching: " + std::to_string(counts[Contact::kSpike]) +
            " folding back, " + std::to_string(counts[Contact::kOverlap]) + " overlapping, " +
            std::to_string(counts[Contact::kTouch]) + " at a point)";
  }
  fail(what);
}

std::string Domain2Impl::describe(const Contact& c) const {
  const std::uint32_t r1 = d.ring_of(c.e1), r2 = d.ring_of(c.e2);
  std::string what;
  if (c.kind == Contact::kCross) {
    what = r1 == r2 ? ring_name(r1) + " crosses itself: edges " + edge_label(c.e1) + " and " +
                          edge_label(c.e2) + " cross at a single point"
                    : ring_name(r1, "vertices " + edge_label(c.e1)) + " crosses " +
                          ring_name(r2, "vertices " + edge_label(c.e2)) + " at a single point";
  } else if (c.kind == Contact::kSpike) {
    const std::uint32_t u = d.prev(c.vertex), v = c.vertex, w = d.next(c.vertex);
    what = ring_name(r1, "vertices " + label(u) + "-" + label(v) + "-" + label(w)) +
           " folds back at vertex " + label(v) + ": edges " + label(u) + "-" + label(v) + " and " +
           label(v) + "-" + label(w) + " overlap (a zero-area spike)";
  } else if (c.kind == Contact::kOverlap) {
    what = r1 == r2
               ? ring_name(r1) + " overlaps itself: edges " + edge_label(c.e1) + " and " +
                     edge_label(c.e2) + " are collinear and share a segment (they touch along it)"
               : ring_name(r1, "vertices " + edge_label(c.e1)) + " overlaps " +
                     ring_name(r2, "vertices " + edge_label(c.e2)) +
                     ": collinear edges sharing a segment (the rings touch along it)";
  } else {
    const std::uint32_t v = c.vertex;
    const std::uint32_t rv = d.ring_of(v);
    const std::string at = point_text(p(v));
    if (c.other_vertex != kNone) {
      const std::uint32_t w = c.other_vertex;
      const std::uint32_t rw = d.ring_of(w);
      what = rv == rw ? ring_name(rv) + " touches itself: vertices " + label(std::min(v, w)) +
                            " and " + label(std::max(v, w)) + " are the same point " + at +
                            " (the ring passes twice through it)"
                      : ring_name(rv, "vertex " + label(v)) + " touches " +
                            ring_name(rw, "vertex " + label(w)) + ": they share the point " + at;
    } else {
      const std::uint32_t g = (v == c.e1 || v == d.next(c.e1)) ? c.e2 : c.e1;
      const std::uint32_t rg = d.ring_of(g);
      what = rv == rg ? ring_name(rv) + " touches itself: vertex " + label(v) + " " + at +
                            " lies on edge " + edge_label(g)
                      : ring_name(rv, "vertex " + label(v)) + " touches " +
                            ring_name(rg, "vertices " + edge_label(g)) + ": the vertex " + at +
                            " lies on the edge";
    }
  }
  return what;
}

std::uint32_t Domain2::Bands::band(double t) const {
  const auto nb_bands = static_cast<std::uint32_t>(begin.size() - 1);
  const double u = (t - lo) / h;
  if (!(u >= 0)) return 0;  // also NaN
  if (u >= static_cast<double>(nb_bands)) return nb_bands - 1;
  return static_cast<std::uint32_t>(u);
}

// Band width: the mean extent of the edges across the bands (so an edge is in about two
// bands), at least 2^-22 of the whole extent.
void Domain2Impl::build_bands() {
  const std::uint32_t n = d.nb_vertices();
  for (int axis = 0; axis < 2; ++axis) {
    Domain2::Bands& bands = d.bands_[axis];
    const int c = 1 - axis;  // the coordinate that selects a band
    double mean = 0;
    for (std::uint32_t e = 0; e < n; ++e) mean += std::fabs(p(d.next(e))[c] - p(e)[c]);
    mean /= n;
    constexpr double kMaxBands = 0x1p22;
    const double extent = d.bbox_hi()[c] - d.bbox_lo()[c];
    const double h = std::max(mean, extent / kMaxBands);
    bands.lo = d.bbox_lo()[c];
    std::uint32_t nb_bands = 1;
    if (h > 0 && std::isfinite(h) && std::isfinite(extent)) {
      bands.h = h;
      nb_bands = static_cast<std::uint32_t>(std::min(kMaxBands, std::floor(extent / h) + 1));
    } else {
      bands.h = std::numeric_limits<double>::infinity();  // one band
    }
    bands.begin.assign(std::size_t{nb_bands} + 1, 0);
    for (int pass = 0; pass < 2; ++pass) {  // count per band, then fill
      std::vector<std::uint32_t> fill;
      if (pass == 1) {
        for (std::uint32_t k = 0; k < nb_bands; ++k) bands.begin[k + 1] += bands.begin[k];
        bands.edge.assign(bands.begin.back(), 0);
        fill.assign(bands.begin.begin(), bands.begin.end() - 1);
      }
      for (std::uint32_t e = 0; e < n; ++e) {
        const double t0 = p(e)[c], t1 = p(d.next(e))[c];
        const std::uint32_t k0 = bands.band(std::min(t0, t1)), k1 = bands.band(std::max(t0, t1));
        for (std::uint32_t k = k0; k <= k1; ++k) {
          if (pass == 0) {
            ++bands.begin[k + 1];
          } else {
            bands.edge[fill[k]++] = e;
          }
        }
      }
    }
  }
}

// Steps 3 and 4.
void Domain2Impl::nest_and_orient() {
  const std::uint32_t nb_rings = d.nb_rings();
  // The rings containing point q, ring `skip` excepted; when q is on a ring, that ring is
  // returned in *on_ring instead. parity[r]: bit 0 the crossing parity, bit 1 "in touched".
  std::vector<std::uint8_t> parity(nb_rings, 0);
  std::vector<std::uint32_t> touched;
  const auto containers = [&](const double* q, std::uint32_t skip, std::uint32_t* on_ring,
                              std::vector<std::uint32_t>& out) {
    out.clear();
    touched.clear();
    cast_ray(d, best_axis(d, q), q, [&](std::uint32_t e, RayHit hit) {
      const std::uint32_t r = d.ring_of(e);
      if (r == skip || hit == RayHit::kMiss) return;
      if (hit == RayHit::kOnEdge) {
        *on_ring = r;
      } else {
        if ((parity[r] & 2) == 0) touched.push_back(r);
        parity[r] = static_cast<std::uint8_t>((parity[r] ^ 1) | 2);
      }
    });
    for (const std::uint32_t r : touched) {
      if (parity[r] & 1) out.push_back(r);
      parity[r] = 0;
    }
    std::sort(out.begin(), out.end());
  };

  std::vector<std::uint32_t> container_begin(1, 0), container_list, depth(nb_rings);
  std::vector<std::uint32_t> list;
  for (std::uint32_t r = 0; r < nb_rings; ++r) {
    std::uint32_t on_ring = kNone;
    containers(p(d.ring_begin_[r]), r, &on_ring, list);
    if (on_ring != kNone) fail("internal error: a ring vertex on another ring after validation");
    depth[r] = static_cast<std::uint32_t>(list.size());
    container_list.insert(container_list.end(), list.begin(), list.end());
    container_begin.push_back(static_cast<std::uint32_t>(container_list.size()));
  }
  const auto parent = [&](std::uint32_t r) {
    for (std::uint32_t i = container_begin[r]; i < container_begin[r + 1]; ++i) {
      if (depth[container_list[i]] + 1 == depth[r]) return container_list[i];
    }
    return kNone;
  };
  const auto contains = [&](std::uint32_t outer, std::uint32_t r) {
    for (std::uint32_t i = container_begin[r]; i < container_begin[r + 1]; ++i) {
      if (container_list[i] == outer) return true;
    }
    return false;
  };

  if (in.ring_polygon.front() < 0) {
    for (std::uint32_t r = 0; r < nb_rings; ++r) {
      d.ring_hole_[r] = static_cast<std::uint8_t>(depth[r] % 2);
    }
  } else {
    std::map<std::int32_t, std::uint32_t> outer_of;
    for (std::uint32_t r = 0; r < nb_rings; ++r) {
      const auto found = outer_of.emplace(in.ring_polygon[d.source_ring_[r]], r);
      d.ring_hole_[r] = static_cast<std::uint8_t>(found.second ? 0 : 1);
    }
    for (std::uint32_t r = 0; r < nb_rings; ++r) {
      const std::uint32_t up = parent(r);
      const std::uint32_t outer = outer_of[in.ring_polygon[d.source_ring_[r]]];
      if (d.ring_hole_[r]) {
        if (up == outer) continue;
        if (!contains(outer, r)) {
          fail(ring_name(r) + " is a hole but lies outside its outer boundary, " +
               ring_name(outer));
        }
        fail(ring_name(r) + " is a hole but lies inside " +
             (d.ring_hole_[up] ? "another hole, " + ring_name(up)
                               : ring_name(up) +
                                     ", the outer boundary of another polygon, "
                                     "within its own outer boundary " +
                                     ring_name(outer)));
      } else if (up != kNone && !d.ring_hole_[up]) {
        fail(ring_name(r) + ", an outer boundary, lies inside the outer boundary " + ring_name(up) +
             " and not in one of its holes: the polygons overlap");
      }
    }
  }

  // Hole markers: each strictly inside a hole (its innermost containing ring is a hole).
  std::vector<std::uint8_t> marked(nb_rings, 0);
  for (std::size_t k = 0; k < in.hole_points.size() / 2; ++k) {
    const double* q = &in.hole_points[2 * k];
    const std::string name = hole_name(k) + " at " + point_text(q);
    std::uint32_t on_ring = kNone;
    containers(q, kNone, &on_ring, list);
    if (on_ring != kNone) fail(name + " lies on the boundary, on " + ring_name(on_ring));
    std::uint32_t innermost = kNone;
    for (const std::uint32_t r : list) {
      if (innermost == kNone || depth[r] > depth[innermost]) innermost = r;
    }
    if (innermost == kNone) fail(name + " lies outside every ring, not in a hole");
    if (!d.ring_hole_[innermost]) {
      fail(name + " lies inside the domain (its innermost ring, " + ring_name(innermost) +
           ", is an outer boundary), not in a hole");
    }
    marked[innermost] = 1;
  }
  if (in.holes_need_markers) {
    for (std::uint32_t r = 0; r < nb_rings; ++r) {
      if (!d.ring_hole_[r] || marked[r]) continue;
      fail(ring_name(r) + " lies inside " + ring_name(parent(r)) +
           " and no hole marker lies in it: in a .poly file a region is a hole only where a "
           "hole marker is (Triangle meshes it, the ring an inner boundary, which voroclip "
           "does not take); add a hole marker inside it to make it a hole");
    }
  }

  // Orientation: outer counter-clockwise, holes clockwise.
  bool reversed = false;
  std::vector<std::uint8_t> ring_reversed(nb_rings, 0);
  for (std::uint32_t r = 0; r < nb_rings; ++r) {
    const std::uint32_t b = d.ring_begin_[r], e = d.ring_begin_[r + 1];
    std::uint32_t low = b;
    for (std::uint32_t v = b + 1; v < e; ++v) {
      if (p(v)[1] < p(low)[1] || (p(v)[1] == p(low)[1] && p(v)[0] < p(low)[0])) low = v;
    }
    const Sign o = orient2d(p(d.prev(low)), p(low), p(d.next(low)));
    if (o == Sign::zero) fail("internal error: collinear neighbours at the lowest vertex");
    if ((o == Sign::positive) == (d.ring_hole_[r] != 0)) {
      for (std::uint32_t i = b + 1, j = e - 1; i < j; ++i, --j) {  // the first vertex stays
        std::swap(d.xy_[2 * std::size_t{i}], d.xy_[2 * std::size_t{j}]);
        std::swap(d.xy_[2 * std::size_t{i} + 1], d.xy_[2 * std::size_t{j} + 1]);
        std::swap(d.source_vertex_[i], d.source_vertex_[j]);
      }
      reversed = true;
      ring_reversed[r] = 1;
    }
  }
  if (reversed) build_bands();  // edge numbers changed

  // Edge tags: the .poly segment markers, else the ring's: with polygons given, its
  // position in the input from 1 (so that the outer rings of several polygons differ), by
  // nesting outer 1, holes 2, 3, ...
  const bool markers = in.segment_marker.size() == in.xy.size() / 2;
  const bool by_polygon = in.ring_polygon.front() >= 0;
  std::int32_t next_hole_tag = 2;
  d.edge_tag_.resize(d.nb_vertices());
  for (std::uint32_t r = 0; r < nb_rings; ++r) {
    const std::int32_t ring_tag = by_polygon ? static_cast<std::int32_t>(d.source_ring_[r] + 1)
                                  : d.ring_hole_[r] ? next_hole_tag++
                                                    : 1;
    const std::uint32_t first = in.ring_begin[r], end = in.ring_begin[r + 1];
    // The input segment ending at input point i starts at its predecessor in the ring.
    const auto before = [&](std::uint32_t i) { return i == first ? end - 1 : i - 1; };
    for (std::uint32_t v = d.ring_begin_[r]; v < d.ring_begin_[r + 1]; ++v) {
      const std::uint32_t i = d.source_vertex_[v], j = d.source_vertex_[d.next(v)];
      // Marker 0 means "no marker", as in Triangle, whose output gives such boundary
      // segments marker 1.
      const std::int32_t marker =
          markers ? in.segment_marker[before(ring_reversed[r] ? i : j)] : ring_tag;
      d.edge_tag_[v] = marker == 0 ? 1 : marker;
    }
  }
  d.region_points_ = in.region_points;
  d.region_attributes_ = in.region_attributes;
  d.region_number_ = in.region_number;
  d.region_line_ = in.region_line;
  // A region point names the part of the domain it lies in: it must lie inside.
  for (std::size_t k = 0; 2 * k + 1 < d.region_points_.size(); ++k) {
    const double* q = &d.region_points_[2 * k];
    if (d.locate(q) != Sign::positive) {
      fail(d.region_name(k) + ": its point " + point_text(q) + " is not inside the domain");
    }
  }
}

// The signed area of each ring, relative to its first vertex: the coordinate differences
// are split into a rounded value and its exact error (two_diff), the leading product of
// each shoelace term is kept exactly (two_product by fma), the small cross terms are
// rounded, and everything goes into a compensated sum. The error is then about 2u |area|
// plus n u^2 times the sum of the term magnitudes: close to the exactly rounded area even
// when the terms cancel heavily.
void Domain2Impl::compute_area() {
  const auto two_diff = [](double x, double y, double& hi, double& lo) {
    hi = x - y;
    const double bv = x - hi;
    lo = (x - (hi + bv)) + (bv - y);
  };
  CompensatedSum total;
  for (std::uint32_t r = 0; r < d.nb_rings(); ++r) {
    const std::uint32_t b = d.ring_begin_[r], e = d.ring_begin_[r + 1];
    const double* o = p(b);
    CompensatedSum sum;
    const auto add_product = [&sum](double xh, double xl, double yh, double yl, double sign) {
      const double hh = xh * yh;
      sum.add(sign * hh);
      sum.add(sign * std::fma(xh, yh, -hh));
      sum.add(sign * (xh * yl + xl * yh + xl * yl));
    };
    for (std::uint32_t v = b + 1; v + 1 < e; ++v) {
      double xi, xil, yi, yil, xj, xjl, yj, yjl;
      two_diff(p(v)[0], o[0], xi, xil);
      two_diff(p(v)[1], o[1], yi, yil);
      two_diff(p(v + 1)[0], o[0], xj, xjl);
      two_diff(p(v + 1)[1], o[1], yj, yjl);
      add_product(xi, xil, yj, yjl, 1.0);
      add_product(xj, xjl, yi, yil, -1.0);
    }
    total.add(0.5 * sum.value());
  }
  d.area_ = total.value();
  // Coordinates whose area double cannot hold (beyond about 1e154 it overflows, below about
  // 1e-154 it underflows): every integral over the domain would be inf, NaN or 0.
  if (d.nb_rings() > 0 && !std::isnormal(d.area_)) {
    double largest = 0;
    for (const double c : d.xy_) largest = std::max(largest, std::abs(c));
    const bool large = !std::isfinite(d.area_);
    throw Error(d.source_ + ": its area is " +
                (large ? std::string("not finite") : detail::number(d.area_)) +
                " in double precision (coordinates up to " + detail::number(largest) + ": too " +
                (large ? "large, it overflows" : "small, it underflows") +
                "); rescale the model (e.g. to a size of about 1)");
  }
}

// ---------------------------------------------------------------------------------------

Domain2::Domain2(const PolygonRings& rings) {
  source_ = rings.source;
  Domain2Impl impl(*this, rings);
  impl.check_structure();
  impl.copy_rings();
  bbox_[0] = bbox_[2] = xy_[0];
  bbox_[1] = bbox_[3] = xy_[1];
  for (std::size_t i = 0; i < xy_.size(); i += 2) {
    bbox_[0] = std::min(bbox_[0], xy_[i]);
    bbox_[1] = std::min(bbox_[1], xy_[i + 1]);
    bbox_[2] = std::max(bbox_[2], xy_[i]);
    bbox_[3] = std::max(bbox_[3], xy_[i + 1]);
  }
  impl.check_contacts();
  impl.build_bands();
  impl.nest_and_orient();
  impl.compute_area();
}

bool Domain2::is_corner(std::uint32_t v) const {
  return orient2d(vertex(prev(v)), vertex(v), vertex(next(v))) != Sign::zero;
}

std::string Domain2::region_name(std::size_t k) const {
  if (region_number_.empty()) {
    return "regional attribute " + std::to_string(k) + " (from 0, in the order given)";
  }
  std::string name = "regional attribute " + std::to_string(region_number_[k]);
  if (!region_line_.empty()) name += " (line " + std::to_string(region_line_[k]) + ")";
  return name;
}

Sign Domain2::locate(const double* q) const {
  if (!std::isfinite(q[0]) || !std::isfinite(q[1])) {
    throw Error("Domain2::locate: the point " + point_text(q) + " is not finite");
  }
  if (bands_[0].begin.empty() || q[0] < bbox_[0] || q[0] > bbox_[2] || q[1] < bbox_[1] ||
      q[1] > bbox_[3]) {
    return Sign::negative;
  }
  bool inside = false, on_edge = false;
  Domain2Impl::cast_ray(*this, Domain2Impl::best_axis(*this, q), q, [&](std::uint32_t, RayHit hit) {
    if (hit == RayHit::kOnEdge) on_edge = true;
    if (hit == RayHit::kCross) inside = !inside;
  });
  if (on_edge) return Sign::zero;
  return inside ? Sign::positive : Sign::negative;
}

}  // namespace voroclip
