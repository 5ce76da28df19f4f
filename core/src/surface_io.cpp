// Triangle surface files (OBJ, OFF, STL ASCII/binary, PLY ASCII/binary) read into a
// TriangleSurface and written from one, and the boundary surface of a tet mesh.
//
// Text formats go through the Lexer of text_lexer.h (line numbers for messages, strict
// locale-independent numbers). Binary data (STL, PLY) is read through ByteReader, which
// checks every read against the end of the file, so a truncated file is reported, never
// read past. Polygons are triangulated by exact ear clipping (a convex one: the fan from
// its first vertex). Writers use the shortest
// round-trip decimals (text) or the exact bytes (binary PLY), so each writer/reader pair
// gives back the same doubles, except binary STL, whose type is float32.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <ostream>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "text_lexer.h"
#include "voroclip/core.h"

namespace voroclip {

namespace {

using namespace detail;  // NOLINT: the shared tokenizer and helpers of text_lexer.h

constexpr std::uint64_t kMaxIndex = std::numeric_limits<std::uint32_t>::max();

// Faces as the file numbers their vertices, checked once the vertex count is known (OBJ
// may reference vertices before defining them).
struct RawFaces {
  std::vector<std::int64_t> corner;     // 0-based vertex indices, as computed from the file
  std::vector<std::int64_t> written;    // the index as the file writes it, for messages
  std::vector<std::uint32_t> begin{0};  // face f has corners [begin[f], begin[f + 1])
  std::vector<std::uint32_t> line;      // per face
  std::vector<std::uint64_t> label;     // per face: its number as the format counts faces

  std::size_t size() const { return line.size(); }
};

// The sign of a sum of doubles, exactly: the terms are added into a nonoverlapping
// expansion (Shewchuk's Grow-Expansion with Two-Sum, "Adaptive precision floating-point
// arithmetic and fast robust geometric predicates", 1997), whose largest nonzero
// component has the sign of the sum. Needs round-to-nearest and no contraction of a + b.
int exact_sign_of_sum(const double* terms, std::size_t n) {
  std::array<double, 16> e{};
  std::size_t len = 0;
  for (std::size_t i = 0; i < n; ++i) {
    double q = terms[i];
    for (std::size_t k = 0; k < len; ++k) {
      const double x = q + e[k];
      const double bv = x - q;
      const double av = x - bv;
      e[k] = (q - av) + (e[k] - bv);
      q = x;
    }
    e[len++] = q;
  }
  for (std::size_t k = len; k-- > 0;) {
    if (e[k] != 0) return e[k] > 0 ? 1 : -1;
  }
  return 0;
}

// orient2d(a, b, c), exactly: the sign of ax by - ax cy - ay bx + ay cx + bx cy - by cx,
// each product split into its rounded value and its error by fma (exact but for underflow).
int orient2d_sign(const double* a, const double* b, const double* c) {
  const double f[6][2] = {{a[0], b[1]}, {-a[0], c[1]}, {-a[1], b[0]},
                          {a[1], c[0]}, {b[0], c[1]},  {-b[1], c[0]}};
  double terms[12];
  for (int k = 0; k < 6; ++k) {
    terms[2 * k] = f[k][0] * f[k][1];
    terms[2 * k + 1] = std::fma(f[k][0], f[k][1], -terms[2 * k]);
  }
  return exact_sign_of_sum(terms, 12);
}

// Triangulates the polygon `poly` (vertex indices into xyz) by ear clipping in the plane
// of the two coordinates across its (Newell) normal's largest component, with exact
// orientation tests: ears are strictly convex corners whose triangle holds no other
// remaining corner (on its boundary included). The first candidate is always the corner
// after the first, so a convex polygon gives the fan from its first vertex, as before. A
// polygon with no ear left (non-planar or self-crossing in projection, or degenerate) has
// what remains fan-triangulated; the surface checks then report it. Appends to `out`.
void triangulate_polygon(const std::vector<double>& xyz, const std::vector<std::uint32_t>& poly,
                         std::vector<std::uint32_t>& out) {
  const std::size_t n = poly.size();
  double normal[3] = {0, 0, 0};
  for (std::size_t i = 0; i < n; ++i) {
    const double* p = &xyz[3 * std::size_t{poly[i]}];
    const double* q = &xyz[3 * std::size_t{poly[(i + 1) % n]}];
    for (int d = 0; d < 3; ++d) {
      const int d1 = (d + 1) % 3, d2 = (d + 2) % 3;
      normal[d] += (p[d1] - q[d1]) * (p[d2] + q[d2]);
    }
  }
  int axis = 0;
  for (int d = 1; d < 3; ++d) {
    if (std::fabs(normal[d]) > std::fabs(normal[axis])) axis = d;
  }
  // (u, v) = the cyclic successors of `axis`: the projected area has the sign of normal[axis].
  const int orientation = normal[axis] > 0 ? 1 : normal[axis] < 0 ? -1 : 0;
  std::vector<std::array<double, 2>> uv(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double* p = &xyz[3 * std::size_t{poly[i]}];
    uv[i] = {p[(axis + 1) % 3], p[(axis + 2) % 3]};
  }
  std::vector<std::size_t> left(n);
  for (std::size_t i = 0; i < n; ++i) left[i] = i;
  const auto emit = [&](std::size_t a, std::size_t b, std::size_t c) {
    out.push_back(poly[a]);
    out.push_back(poly[b]);
    out.push_back(poly[c]);
  };
  while (left.size() > 3 && orientation != 0) {
    bool clipped = false;
    for (std::size_t j = 1; j < left.size() && !clipped; ++j) {
      const std::size_t a = left[j - 1], b = left[j], c = left[(j + 1) % left.size()];
      if (orient2d_sign(uv[a].data(), uv[b].data(), uv[c].data()) != orientation) continue;
      bool empty = true;
      for (const std::size_t p : left) {
        if (p == a || p == b || p == c) continue;
        if (orient2d_sign(uv[a].data(), uv[b].data(), uv[p].data()) != -orientation &&
            orient2d_sign(uv[b].data(), uv[c].data(), uv[p].data()) != -orientation &&
            orient2d_sign(uv[c].data(), uv[a].data(), uv[p].data()) != -orientation) {
          empty = false;
          break;
        }
      }
      if (!empty) continue;
      emit(a, b, c);
      left.erase(left.begin() + static_cast<std::ptrdiff_t>(j));
      clipped = true;
    }
    if (!clipped) break;
  }
  for (std::size_t k = 1; k + 1 < left.size(); ++k) emit(left[0], left[k], left[k + 1]);
}

// Checks the indices and triangulates (triangulate_polygon). `binary`: no line numbers in messages.
// `base`: how the format numbers vertices in messages (OBJ from 1).
void finish_faces(const std::string& path, const RawFaces& raw, bool binary, std::int64_t base,
                  TriangleSurface& s) {
  const std::int64_t nv = s.nb_vertices();
  s.vertex_base = static_cast<std::uint32_t>(base);
  std::vector<std::uint32_t> poly;
  for (std::size_t f = 0; f < raw.size(); ++f) {
    const std::uint32_t b = raw.begin[f], e = raw.begin[f + 1];
    const std::string where =
        binary ? path + ": " : path + ":" + std::to_string(raw.line[f]) + ": ";
    for (std::uint32_t k = b; k < e; ++k) {
      if (raw.corner[k] < 0 || raw.corner[k] >= nv) {
        throw Error(where + "face " + std::to_string(raw.label[f]) + ": vertex " +
                    std::to_string(raw.written[k]) + " is out of range " +
                    (nv == 0 ? std::string("(the file has no vertices)")
                             : std::to_string(base) + ".." + std::to_string(base + nv - 1)));
      }
    }
    const std::size_t before = s.triangles.size();
    if (e - b <= 3) {
      for (std::uint32_t k = b; k < e; ++k) {
        s.triangles.push_back(static_cast<std::uint32_t>(raw.corner[k]));
      }
      if (e - b < 3) s.triangles.resize(before);
    } else {
      poly.clear();
      for (std::uint32_t k = b; k < e; ++k)
        poly.push_back(static_cast<std::uint32_t>(raw.corner[k]));
      triangulate_polygon(s.xyz, poly, s.triangles);
    }
    for (std::size_t t = before; t < s.triangles.size(); t += 3) {
      s.triangle_line.push_back(binary ? 0u : raw.line[f]);
      s.triangle_face.push_back(static_cast<std::uint32_t>(raw.label[f]));
    }
  }
  if (s.triangles.empty()) throw Error(path + ": no faces");
}

// ---------------------------------------------------------------------------------------
// OBJ. Line-based statements; only `v` and `f` matter.

// A corner "v", "v/t", "v//n" or "v/t/n": the vertex number (1-based or negative).
bool obj_corner(std::string_view t, std::int64_t& v) {
  const std::string_view num = t.substr(0, t.find('/'));
  const auto r = std::from_chars(num.data(), num.data() + num.size(), v);
  return r.ec == std::errc() && r.ptr == num.data() + num.size() && v != 0;
}

TriangleSurface read_obj(const std::string& path, std::string text) {
  TriangleSurface s;
  s.source = path;
  RawFaces raw;
  Lexer lx(path, std::move(text), '#');
  std::uint64_t nb_faces = 0;
  for (;;) {
    const std::string_view kw = lx.next();
    if (kw.empty()) break;
    const std::uint32_t line = lx.line();
    // The statement's tokens: to the end of the line, or further after a '\\'.
    auto field = [&]() -> std::string_view {
      for (;;) {
        const std::string_view t = lx.next_on_line();
        if (t != "\\") return t;
        lx.next_line();
      }
    };
    if (kw == "v") {
      double xyz[3];
      for (double& c : xyz) {
        const std::string_view t = field();
        if (t.empty()) lx.fail("vertex: expected 3 coordinates");
        c = to_double(lx, t);
      }
      if (s.nb_vertices() == kMaxIndex) lx.fail("more than 2^32 - 1 vertices");
      s.xyz.insert(s.xyz.end(), xyz, xyz + 3);
      while (!field().empty()) {
      }
    } else if (kw == "f") {
      ++nb_faces;
      const std::size_t first = raw.corner.size();
      for (std::string_view t = field(); !t.empty(); t = field()) {
        std::int64_t v = 0;
        if (!obj_corner(t, v)) {
          fail_at(path, line,
                  "face " + std::to_string(nb_faces) + ": " + quote(t) +
                      " is not a vertex reference (v, v/t, v//n or v/t/n, v a non-zero integer)");
        }
        raw.written.push_back(v);
        // Negative: relative to the vertices read so far (-1 is the last one).
        raw.corner.push_back(v > 0 ? v - 1 : static_cast<std::int64_t>(s.nb_vertices()) + v);
      }
      const std::size_t k = raw.corner.size() - first;
      if (k < 3) {
        fail_at(path, line,
                "face " + std::to_string(nb_faces) + " has " + std::to_string(k) +
                    (k == 1 ? " corner" : " corners") + ", at least 3 are needed");
      }
      raw.begin.push_back(static_cast<std::uint32_t>(raw.corner.size()));
      raw.line.push_back(line);
      raw.label.push_back(nb_faces);
    } else if (std::isalpha(static_cast<unsigned char>(kw[0]))) {
      while (!field().empty()) {
      }
    } else {
      fail_at(path, line, "not an OBJ statement: " + quote(kw));
    }
  }
  finish_faces(path, raw, false, 1, s);
  return s;
}

// ---------------------------------------------------------------------------------------
// OFF (Geomview): [ST][C][N]OFF, counts, vertices, faces; '#' comments.

TriangleSurface read_off(const std::string& path, std::string text) {
  Lexer lx(path, std::move(text), '#');
  TriangleSurface s;
  s.source = path;
  const std::string_view header = lx.next();
  {
    std::string_view h = header;
    if (h.substr(0, 2) == "ST") h.remove_prefix(2);
    if (h.substr(0, 1) == "C") h.remove_prefix(1);
    if (h.substr(0, 1) == "N") h.remove_prefix(1);
    if (h == "4OFF" || h == "nOFF" || h == "4nOFF") {
      lx.fail(quote(header) + ": only 3D OFF files are read");
    }
    if (h != "OFF") {
      lx.fail("not an OFF file: expected OFF (or COFF, NOFF, CNOFF, STOFF), found " +
              (header.empty() ? std::string("an empty file") : quote(header)));
    }
  }
  if (lower(lx.peek()) == "binary") lx.fail("binary OFF file: only ASCII OFF is read");
  const std::uint64_t nv = to_uint(lx, header_token(lx, "OFF header"), "vertex count");
  const std::uint64_t nf = to_uint(lx, header_token(lx, "OFF header"), "face count");
  to_uint(lx, header_token(lx, "OFF header"), "edge count");
  if (nv > kMaxIndex) lx.fail(std::to_string(nv) + " vertices: more than 2^32 - 1");
  lx.skip_line();
  Section vs{"vertices", "vertices", nv};
  s.xyz.reserve(3 * reserve_for(lx, nv));
  for (; vs.found < nv; ++vs.found) {
    for (int k = 0; k < 3; ++k) s.xyz.push_back(entry_double(lx, vs));
    lx.skip_line();  // colour, normal or texture coordinates
  }
  RawFaces raw;
  Section fs{"faces", "faces", nf};
  for (; fs.found < nf; ++fs.found) {
    const std::uint64_t k = entry_uint(lx, fs, "corner count");
    const std::uint32_t line = lx.line();
    if (k < 3) {
      lx.fail("face " + std::to_string(fs.found) + " has " + std::to_string(k) +
              (k == 1 ? " corner" : " corners") + ", at least 3 are needed");
    }
    for (std::uint64_t c = 0; c < k; ++c) {
      const std::uint64_t v = entry_uint(lx, fs, "vertex index");
      const auto clamped = static_cast<std::int64_t>(std::min<std::uint64_t>(v, kMaxIndex + 1));
      raw.corner.push_back(clamped);
      raw.written.push_back(clamped);
    }
    lx.skip_line();  // an optional colour
    raw.begin.push_back(static_cast<std::uint32_t>(raw.corner.size()));
    raw.line.push_back(line);
    raw.label.push_back(fs.found);
  }
  finish_faces(path, raw, false, 0, s);
  return s;
}

// ---------------------------------------------------------------------------------------
// Binary data: bounds-checked little/big-endian reads.

class ByteReader {
 public:
  ByteReader(const std::string& path, const std::string& data, std::size_t pos, bool big_endian)
      : path_(path), data_(data), pos_(pos), big_endian_(big_endian) {}

  bool at_end() const { return pos_ == data_.size(); }
  std::size_t remaining() const { return data_.size() - pos_; }

  // Reads n bytes in file order into out (byte-swapped when the file's order is not the
  // machine's, for numbers of size n); `what` names the item for a truncation message.
  void read(void* out, std::size_t n, bool number, const std::string& what) {
    if (remaining() < n) throw Error(path_ + ": the file is truncated in " + what);
    auto* dst = static_cast<unsigned char*>(out);
    std::memcpy(dst, data_.data() + pos_, n);
    pos_ += n;
    if (number && big_endian_ != machine_big_endian()) std::reverse(dst, dst + n);
  }
  template <class T>
  T get(const std::string& what) {
    T v;
    read(&v, sizeof v, true, what);
    return v;
  }
  void skip(std::size_t n, const std::string& what) {
    if (remaining() < n) throw Error(path_ + ": the file is truncated in " + what);
    pos_ += n;
  }

  static bool machine_big_endian() {
    const std::uint16_t one = 1;
    unsigned char first = 0;
    std::memcpy(&first, &one, 1);
    return first == 0;
  }

 private:
  const std::string& path_;
  const std::string& data_;
  std::size_t pos_;
  bool big_endian_;
};

// Merges STL vertices with equal coordinates (+0 and -0 are equal).
class VertexMerger {
 public:
  explicit VertexMerger(TriangleSurface& s) : s_(s) {}
  std::uint32_t add(const double p[3]) {
    Key key;
    for (int k = 0; k < 3; ++k) key[static_cast<std::size_t>(k)] = p[k] == 0 ? 0.0 : p[k];
    const auto [it, inserted] = map_.try_emplace(key, s_.nb_vertices());
    if (inserted) {
      if (s_.nb_vertices() == kMaxIndex) throw Error(s_.source + ": more than 2^32 - 1 vertices");
      s_.xyz.insert(s_.xyz.end(), key.begin(), key.end());
    }
    return it->second;
  }

 private:
  using Key = std::array<double, 3>;
  struct Hash {
    std::size_t operator()(const Key& k) const {
      std::uint64_t h = 0x9e3779b97f4a7c15ull;
      for (const double x : k) {
        std::uint64_t bits = 0;
        std::memcpy(&bits, &x, sizeof bits);
        h ^= bits + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
      }
      return static_cast<std::size_t>(h);
    }
  };
  TriangleSurface& s_;
  std::unordered_map<Key, std::uint32_t, Hash> map_;
};

// ---------------------------------------------------------------------------------------
// STL.

TriangleSurface read_stl_binary(const std::string& path, const std::string& data) {
  TriangleSurface s;
  s.source = path;
  ByteReader in(path, data, 80, false);
  const auto n = in.get<std::uint32_t>("the triangle count");
  VertexMerger merge(s);
  s.triangles.reserve(3 * std::size_t{n});
  s.triangle_line.assign(n, 0);
  s.triangle_face.resize(n);
  for (std::uint32_t t = 0; t < n; ++t) {
    s.triangle_face[t] = t;
    const std::string what = "facet " + std::to_string(t);
    in.skip(12, what);  // the normal
    for (int k = 0; k < 3; ++k) {
      double p[3];
      for (double& c : p) {
        c = static_cast<double>(in.get<float>(what));
        if (!std::isfinite(c)) {
          throw Error(path + ": facet " + std::to_string(t) + ": a coordinate is not finite");
        }
      }
      s.triangles.push_back(merge.add(p));
    }
    in.skip(2, what);  // attribute byte count
  }
  if (n == 0) throw Error(path + ": no faces (binary STL with 0 triangles)");
  return s;
}

void expect_word(Lexer& lx, std::string_view word) {
  const std::string_view t = lx.next();
  if (lower(t) != word) {
    lx.fail("expected '" + std::string(word) + "', found " +
            (t.empty() ? std::string("the end of the file") : quote(t)));
  }
}

TriangleSurface read_stl_ascii(const std::string& path, std::string data) {
  TriangleSurface s;
  s.source = path;
  VertexMerger merge(s);
  Lexer lx(path, std::move(data), 0);
  expect_word(lx, "solid");
  lx.skip_line();  // the name
  for (;;) {
    const std::string_view t = lx.next();
    const std::string kw = lower(t);
    if (kw == "facet") {
      const std::uint32_t line = lx.line();
      expect_word(lx, "normal");
      for (int k = 0; k < 3; ++k) to_double(lx, header_token(lx, "facet normal"));
      expect_word(lx, "outer");
      expect_word(lx, "loop");
      for (int k = 0; k < 3; ++k) {
        expect_word(lx, "vertex");
        double p[3];
        for (double& c : p) c = to_double(lx, header_token(lx, "vertex"));
        s.triangles.push_back(merge.add(p));
      }
      expect_word(lx, "endloop");
      expect_word(lx, "endfacet");
      s.triangle_face.push_back(static_cast<std::uint32_t>(s.triangle_line.size()));
      s.triangle_line.push_back(line);
    } else if (kw == "endsolid") {
      lx.skip_line();
      const std::string_view more = lx.next();
      if (more.empty()) break;
      if (lower(more) != "solid") {
        lx.fail("expected 'solid' or the end of the file after 'endsolid', found " + quote(more));
      }
      lx.skip_line();
    } else {
      lx.fail("expected 'facet' or 'endsolid', found " +
              (t.empty() ? std::string("the end of the file") : quote(t)));
    }
  }
  if (s.triangles.empty()) throw Error(path + ": no faces");
  return s;
}

// Binary or ASCII. A file whose size is 84 + 50 x the triangle count of its bytes 80..83 is
// binary, even when its header starts with "solid" (as some exporters write); else one
// that starts with "solid" is ASCII; else it is binary with a size that does not match.
//
// Trailing bytes. Readers disagree on a binary STL longer than 84 + 50 N bytes: meshio
// reads it as binary only when the size matches exactly (else as ASCII, which fails);
// numpy-stl reads N triangles and ignores what follows (and, for a header that starts
// with "solid", requires floor((size - 84) / 50) == N); Gmsh reads header, count and
// triangles again until the end of the file (concatenated solids), so that a tail shorter
// than a header is ignored. We accept a tail made only of zero bytes (padding: an
// exporter or a transfer that rounds the size up), and reject any other: a tail of data
// means that the count and the triangles disagree (a count too small, two files joined),
// and reading N triangles of it would silently drop the others.
TriangleSurface read_stl(const std::string& path, std::string data) {
  std::uint64_t count = 0, expected = 0;
  if (data.size() >= 84) {
    std::uint32_t n = 0;
    ByteReader(path, data, 80, false).read(&n, 4, true, "the triangle count");
    count = n;
    expected = 84 + 50 * count;
    if (data.size() == expected) return read_stl_binary(path, data);
  }
  prepare_input(path, data);
  std::size_t first = 0;
  while (first < data.size() && std::isspace(static_cast<unsigned char>(data[first]))) ++first;
  if (lower(std::string_view(data).substr(first, 5)) == "solid") {
    return read_stl_ascii(path, std::move(data));
  }
  const std::string not_stl = path + ": not an STL file: it does not start with 'solid' (ASCII)";
  if (data.size() < 84) {
    throw Error(not_stl + ", and it has " + std::to_string(data.size()) +
                " bytes, fewer than the 84 of a binary STL's header and triangle count");
  }
  if (data.size() > expected && std::all_of(data.begin() + static_cast<std::ptrdiff_t>(expected),
                                            data.end(), [](char c) { return c == 0; })) {
    data.resize(static_cast<std::size_t>(expected));  // zero padding, see above
    return read_stl_binary(path, data);
  }
  throw Error(path + ": binary STL: the header says " + std::to_string(count) +
              " triangles (84 + 50 x " + std::to_string(count) + " = " + std::to_string(expected) +
              " bytes) but the file has " + std::to_string(data.size()) + " bytes" +
              (data.size() > expected ? " (a tail that is not zero padding)" : ""));
}

// ---------------------------------------------------------------------------------------
// PLY.

enum class PlyType : std::uint8_t {
  kInt8,
  kUInt8,
  kInt16,
  kUInt16,
  kInt32,
  kUInt32,
  kFloat32,
  kFloat64
};

bool ply_type(std::string_view t, PlyType& out) {
  static const std::pair<const char*, PlyType> kNames[] = {
      {"char", PlyType::kInt8},       {"int8", PlyType::kInt8},       {"uchar", PlyType::kUInt8},
      {"uint8", PlyType::kUInt8},     {"short", PlyType::kInt16},     {"int16", PlyType::kInt16},
      {"ushort", PlyType::kUInt16},   {"uint16", PlyType::kUInt16},   {"int", PlyType::kInt32},
      {"int32", PlyType::kInt32},     {"uint", PlyType::kUInt32},     {"uint32", PlyType::kUInt32},
      {"float", PlyType::kFloat32},   {"float32", PlyType::kFloat32}, {"double", PlyType::kFloat64},
      {"float64", PlyType::kFloat64},
  };
  for (const auto& [name, type] : kNames) {
    if (t == name) {
      out = type;
      return true;
    }
  }
  return false;
}

bool ply_integral(PlyType t) { return t != PlyType::kFloat32 && t != PlyType::kFloat64; }

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kFloat64;
  bool list = false;
  PlyType count_type = PlyType::kUInt8;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::uint32_t line = 0;
  std::vector<PlyProperty> properties;
};

// One binary value of type t as a double (integers of up to 32 bits are exact).
double ply_binary_value(ByteReader& in, PlyType t, const std::string& what) {
  switch (t) {
    case PlyType::kInt8:
      return in.get<std::int8_t>(what);
    case PlyType::kUInt8:
      return in.get<std::uint8_t>(what);
    case PlyType::kInt16:
      return in.get<std::int16_t>(what);
    case PlyType::kUInt16:
      return in.get<std::uint16_t>(what);
    case PlyType::kInt32:
      return in.get<std::int32_t>(what);
    case PlyType::kUInt32:
      return in.get<std::uint32_t>(what);
    case PlyType::kFloat32:
      return static_cast<double>(in.get<float>(what));
    case PlyType::kFloat64:
      return in.get<double>(what);
  }
  return 0;
}

// A value that must be an integer index or count (ASCII: written as an integer).
std::int64_t ply_ascii_integer(Lexer& lx, std::string_view t, const char* what) {
  std::int64_t v = 0;
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
  if (r.ec != std::errc() || r.ptr != t.data() + t.size()) {
    lx.fail(quote(t) + " is not a valid " + what + " (an integer)");
  }
  return v;
}

TriangleSurface read_ply(const std::string& path, const std::string& data) {
  // The header is text up to and including the line "end_header".
  std::size_t header_end = std::string::npos;
  for (std::size_t pos = 0; pos < data.size();) {
    std::size_t eol = data.find('\n', pos);
    if (eol == std::string::npos) eol = data.size();
    std::string_view l = std::string_view(data).substr(pos, eol - pos);
    if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
    while (!l.empty() && (l.back() == ' ' || l.back() == '\t')) l.remove_suffix(1);
    if (l == "end_header") {
      header_end = std::min(eol + 1, data.size());
      break;
    }
    pos = eol + 1;
  }
  const bool has_end = header_end != std::string::npos;
  Lexer hx(path, data.substr(0, has_end ? header_end : std::min<std::size_t>(data.size(), 4096)),
           0);
  {
    const std::string_view magic = hx.next();
    if (magic != "ply") {
      hx.fail("not a PLY file: expected 'ply', found " +
              (magic.empty() ? std::string("an empty file") : quote(magic)));
    }
  }
  if (!has_end) throw Error(path + ": PLY header without 'end_header'");
  enum class Format { kAscii, kLittle, kBig } format = Format::kAscii;
  bool have_format = false;
  std::vector<PlyElement> elements;
  for (;;) {
    const std::string_view kw = hx.next();
    if (kw == "end_header") break;
    if (kw == "comment" || kw == "obj_info") {
      hx.skip_line();
    } else if (kw == "format") {
      const std::string_view f = header_token(hx, "format");
      if (f == "ascii") {
        format = Format::kAscii;
      } else if (f == "binary_little_endian") {
        format = Format::kLittle;
      } else if (f == "binary_big_endian") {
        format = Format::kBig;
      } else {
        hx.fail("unknown PLY format " + quote(f));
      }
      const std::string_view v = header_token(hx, "format");
      if (v != "1.0" && v != "1") hx.fail("PLY version " + quote(v) + ": only 1.0 is read");
      have_format = true;
    } else if (kw == "element") {
      PlyElement e;
      e.name = std::string(header_token(hx, "element"));
      e.line = hx.line();
      e.count = to_uint(hx, header_token(hx, "element"), "element count");
      elements.push_back(std::move(e));
    } else if (kw == "property") {
      if (elements.empty()) hx.fail("'property' before any 'element'");
      PlyProperty p;
      std::string_view t = header_token(hx, "property");
      if (t == "list") {
        p.list = true;
        const std::string_view ct = header_token(hx, "property list");
        if (!ply_type(ct, p.count_type) || !ply_integral(p.count_type)) {
          hx.fail("property list: " + quote(ct) + " is not an integer type");
        }
        t = header_token(hx, "property list");
      }
      if (!ply_type(t, p.type)) hx.fail("property: unknown type " + quote(t));
      p.name = std::string(header_token(hx, "property"));
      elements.back().properties.push_back(std::move(p));
    } else {
      hx.fail("unknown PLY header keyword " +
              (kw.empty() ? std::string("(end of the header)") : quote(kw)));
    }
  }
  if (!have_format) throw Error(path + ": PLY header without a 'format' line");

  TriangleSurface s;
  s.source = path;
  RawFaces raw;
  bool have_vertices = false, have_faces = false;
  // Where x, y, z and the face list sit in their elements (or -1).
  auto find = [](const PlyElement& e, const char* name) {
    for (std::size_t i = 0; i < e.properties.size(); ++i) {
      if (e.properties[i].name == name) return static_cast<int>(i);
    }
    return -1;
  };
  const bool binary = format != Format::kAscii;
  const auto header_lines = static_cast<std::uint32_t>(
      std::count(data.begin(), data.begin() + static_cast<std::ptrdiff_t>(header_end), '\n'));
  Lexer lx(path, binary ? std::string() : data.substr(header_end), 0, header_lines + 1);
  ByteReader in(path, data, header_end, format == Format::kBig);
  for (const PlyElement& e : elements) {
    const bool is_vertex = e.name == "vertex";
    const bool is_face = e.name == "face";
    int xyz[3] = {-1, -1, -1};
    int list = -1;
    if (is_vertex) {
      have_vertices = true;
      xyz[0] = find(e, "x");
      xyz[1] = find(e, "y");
      xyz[2] = find(e, "z");
      for (int k = 0; k < 3; ++k) {
        if (xyz[k] < 0 || e.properties[static_cast<std::size_t>(xyz[k])].list) {
          fail_at(path, e.line, std::string("element vertex: no scalar property ") + "xyz"[k]);
        }
      }
      if (e.count > kMaxIndex) {
        fail_at(path, e.line, std::to_string(e.count) + " vertices: more than 2^32 - 1");
      }
      s.xyz.reserve(3 * static_cast<std::size_t>(std::min<std::uint64_t>(e.count, data.size())));
    } else if (is_face) {
      have_faces = true;
      list = find(e, "vertex_indices");
      if (list < 0) list = find(e, "vertex_index");
      if (list < 0 || !e.properties[static_cast<std::size_t>(list)].list ||
          !ply_integral(e.properties[static_cast<std::size_t>(list)].type)) {
        fail_at(path, e.line,
                "element face: no integer list property vertex_indices (or vertex_index)");
      }
    }
    Section sec{"element " + e.name, "entries", e.count};
    for (; sec.found < e.count; ++sec.found) {
      const std::string what = "element " + e.name + " " + std::to_string(sec.found);
      double p[3] = {0, 0, 0};
      std::uint32_t line = 0;
      for (std::size_t q = 0; q < e.properties.size(); ++q) {
        const PlyProperty& prop = e.properties[q];
        const auto qi = static_cast<int>(q);
        std::uint64_t n = 1;
        if (prop.list) {
          if (binary) {
            const double c = ply_binary_value(in, prop.count_type, what);
            if (c < 0) throw Error(path + ": " + what + ": negative list length");
            n = static_cast<std::uint64_t>(c);
          } else {
            const std::string_view t = entry_token(lx, sec);
            if (q == 0) line = lx.line();
            const std::int64_t c = ply_ascii_integer(lx, t, "list length");
            if (c < 0) lx.fail(what + ": negative list length");
            n = static_cast<std::uint64_t>(c);
          }
          if (qi == list && n < 3) {
            const std::string msg = "face " + std::to_string(sec.found) + " has " +
                                    std::to_string(n) + (n == 1 ? " corner" : " corners") +
                                    ", at least 3 are needed";
            if (binary) throw Error(path + ": " + msg);
            lx.fail(msg);
          }
        }
        for (std::uint64_t i = 0; i < n; ++i) {
          if (binary) {
            const double v = ply_binary_value(in, prop.type, what);
            if (qi == list) {
              raw.corner.push_back(static_cast<std::int64_t>(v));
              raw.written.push_back(static_cast<std::int64_t>(v));
            } else if (is_vertex) {
              for (int k = 0; k < 3; ++k) {
                if (qi == xyz[k]) {
                  if (!std::isfinite(v)) {
                    throw Error(path + ": vertex " + std::to_string(sec.found) +
                                ": a coordinate is not finite");
                  }
                  p[k] = v;
                }
              }
            }
          } else {
            const std::string_view t = entry_token(lx, sec);
            if (q == 0 && i == 0 && !prop.list) line = lx.line();
            if (qi == list) {
              const std::int64_t v = ply_ascii_integer(lx, t, "vertex index");
              raw.corner.push_back(v);
              raw.written.push_back(v);
            } else if (is_vertex && (qi == xyz[0] || qi == xyz[1] || qi == xyz[2])) {
              p[qi == xyz[0] ? 0 : qi == xyz[1] ? 1 : 2] = to_double(lx, t);
            } else {
              to_double(lx, t);  // checked even when unused
            }
          }
        }
      }
      if (is_vertex) s.xyz.insert(s.xyz.end(), p, p + 3);
      if (is_face) {
        raw.begin.push_back(static_cast<std::uint32_t>(raw.corner.size()));
        raw.line.push_back(line);
        raw.label.push_back(sec.found);
      }
    }
  }
  if (!have_vertices) throw Error(path + ": no 'vertex' element");
  if (!have_faces) throw Error(path + ": no 'face' element");
  finish_faces(path, raw, binary, 0, s);
  return s;
}

// ---------------------------------------------------------------------------------------
// Writers.

void check_surface_arrays(const std::string& path, const TriangleSurface& s) {
  if (s.xyz.size() % 3 != 0 || s.triangles.size() % 3 != 0) {
    throw Error("cannot write '" + path + "': the surface arrays hold " +
                std::to_string(s.xyz.size()) + " coordinates and " +
                std::to_string(s.triangles.size()) + " triangle indices (multiples of 3 needed)");
  }
  for (std::size_t i = 0; i < s.triangles.size(); ++i) {
    if (s.triangles[i] >= s.nb_vertices()) {
      throw Error("cannot write '" + path + "': triangle " + std::to_string(i / 3) +
                  " has vertex " + std::to_string(s.triangles[i]) + ", the surface has " +
                  count_of(s.nb_vertices(), "vertex", "vertices"));
    }
  }
}

void append_xyz(std::string& out, const double* p) {
  append(out, p[0]);
  out += ' ';
  append(out, p[1]);
  out += ' ';
  append(out, p[2]);
}

// The unit normal of triangle t by the right-hand rule (0 0 0 when degenerate).
void unit_normal(const TriangleSurface& s, std::size_t t, double n[3]) {
  const double* a = &s.xyz[3 * std::size_t{s.triangles[3 * t]}];
  const double* b = &s.xyz[3 * std::size_t{s.triangles[3 * t + 1]}];
  const double* c = &s.xyz[3 * std::size_t{s.triangles[3 * t + 2]}];
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  n[0] = u[1] * v[2] - u[2] * v[1];
  n[1] = u[2] * v[0] - u[0] * v[2];
  n[2] = u[0] * v[1] - u[1] * v[0];
  const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (int k = 0; k < 3; ++k) n[k] = len > 0 ? n[k] / len : 0.0;
}

std::string obj_text(const TriangleSurface& s) {
  std::string out = "# voroclip\n";
  for (std::size_t i = 0; i < s.nb_vertices(); ++i) {
    out += "v ";
    append_xyz(out, &s.xyz[3 * i]);
    out += '\n';
  }
  for (std::size_t t = 0; t < s.nb_triangles(); ++t) {
    out += 'f';
    for (std::size_t k = 0; k < 3; ++k) {
      out += ' ';
      append(out, std::uint64_t{s.triangles[3 * t + k]} + 1);
    }
    out += '\n';
  }
  return out;
}

std::string off_text(const TriangleSurface& s) {
  std::string out = "OFF\n";
  append(out, std::uint64_t{s.nb_vertices()});
  out += ' ';
  append(out, std::uint64_t{s.nb_triangles()});
  out += " 0\n";
  for (std::size_t i = 0; i < s.nb_vertices(); ++i) {
    append_xyz(out, &s.xyz[3 * i]);
    out += '\n';
  }
  for (std::size_t t = 0; t < s.nb_triangles(); ++t) {
    out += '3';
    for (std::size_t k = 0; k < 3; ++k) {
      out += ' ';
      append(out, std::uint64_t{s.triangles[3 * t + k]});
    }
    out += '\n';
  }
  return out;
}

std::string stl_ascii_text(const TriangleSurface& s) {
  std::string out = "solid voroclip\n";
  for (std::size_t t = 0; t < s.nb_triangles(); ++t) {
    double n[3];
    unit_normal(s, t, n);
    out += "facet normal ";
    append_xyz(out, n);
    out += "\n outer loop\n";
    for (std::size_t k = 0; k < 3; ++k) {
      out += "  vertex ";
      append_xyz(out, &s.xyz[3 * std::size_t{s.triangles[3 * t + k]}]);
      out += '\n';
    }
    out += " endloop\nendfacet\n";
  }
  out += "endsolid voroclip\n";
  return out;
}

// Little-endian bytes of a number, whatever the machine's order.
template <class T>
void put_le(std::string& out, T v) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (ByteReader::machine_big_endian()) std::reverse(b, b + sizeof(T));
  out.append(reinterpret_cast<const char*>(b), sizeof(T));
}

std::string stl_binary_bytes(const TriangleSurface& s) {
  std::string out = "voroclip binary STL";  // must not start with "solid"
  out.resize(80, ' ');
  put_le<std::uint32_t>(out, s.nb_triangles());
  out.reserve(84 + 50 * std::size_t{s.nb_triangles()});
  for (std::size_t t = 0; t < s.nb_triangles(); ++t) {
    double n[3];
    unit_normal(s, t, n);
    for (const double c : n) put_le<float>(out, static_cast<float>(c));
    for (std::size_t k = 0; k < 3; ++k) {
      const double* p = &s.xyz[3 * std::size_t{s.triangles[3 * t + k]}];
      for (int c = 0; c < 3; ++c) put_le<float>(out, static_cast<float>(p[c]));
    }
    put_le<std::uint16_t>(out, 0);
  }
  return out;
}

std::string ply_header(const TriangleSurface& s, bool binary) {
  std::string out = "ply\nformat ";
  out += binary ? "binary_little_endian" : "ascii";
  out += " 1.0\ncomment voroclip\nelement vertex ";
  append(out, std::uint64_t{s.nb_vertices()});
  out += "\nproperty double x\nproperty double y\nproperty double z\nelement face ";
  append(out, std::uint64_t{s.nb_triangles()});
  out += "\nproperty list uchar int vertex_indices\nend_header\n";
  return out;
}

std::string ply_text(const TriangleSurface& s, bool binary) {
  std::string out = ply_header(s, binary);
  for (std::size_t i = 0; i < s.nb_vertices(); ++i) {
    if (binary) {
      for (int c = 0; c < 3; ++c) put_le<double>(out, s.xyz[3 * i + static_cast<std::size_t>(c)]);
    } else {
      append_xyz(out, &s.xyz[3 * i]);
      out += '\n';
    }
  }
  for (std::size_t t = 0; t < s.nb_triangles(); ++t) {
    if (binary) {
      put_le<std::uint8_t>(out, 3);
      for (std::size_t k = 0; k < 3; ++k) {
        put_le<std::int32_t>(out, static_cast<std::int32_t>(s.triangles[3 * t + k]));
      }
    } else {
      out += '3';
      for (std::size_t k = 0; k < 3; ++k) {
        out += ' ';
        append(out, std::uint64_t{s.triangles[3 * t + k]});
      }
      out += '\n';
    }
  }
  return out;
}

// The format of `path` by its extension: 0 obj, 1 off, 2 stl, 3 ply; throws for another.
int surface_format_of(const std::string& path) {
  const std::string ext = input_extension_of(path);
  if (ext == ".obj") return 0;
  if (ext == ".off") return 1;
  if (ext == ".stl") return 2;
  if (ext == ".ply") return 3;
  check_not_gzip_name(path);
  throw Error(path + ": unknown surface format " +
              (ext.empty() ? std::string("(no extension)") : "'" + ext + "'") +
              ": expected .obj, .off, .stl or .ply");
}

TriangleSurface read_surface_text(const std::string& path, std::string text) {
  const int format = surface_format_of(path);
  if (format != 2) prepare_input(path, text);  // STL: once it is known not to be binary
  switch (format) {
    case 0:
      return read_obj(path, std::move(text));
    case 1:
      return read_off(path, std::move(text));
    case 2:
      return read_stl(path, std::move(text));
    default:
      return read_ply(path, text);
  }
}

}  // namespace

TriangleSurface read_surface(const std::string& path) {
  check_not_directory(path);
  surface_format_of(path);
  return read_surface_text(path, read_whole_file(path));
}

TriangleSurface read_surface(std::istream& in, const std::string& name) {
  surface_format_of(name);
  return read_surface_text(name, read_whole_stream(in, name));
}

void write_surface(const std::string& path, const TriangleSurface& surface, SurfaceFormat format) {
  check_surface_arrays(path, surface);
  if (format == SurfaceFormat::kPlyBinary &&
      surface.nb_vertices() > std::uint64_t{std::numeric_limits<std::int32_t>::max()}) {
    throw Error("cannot write '" + path + "': binary PLY indices are int32");
  }
  switch (format) {
    case SurfaceFormat::kObj:
      return write_text(path, obj_text(surface));
    case SurfaceFormat::kOff:
      return write_text(path, off_text(surface));
    case SurfaceFormat::kStlAscii:
      return write_text(path, stl_ascii_text(surface));
    case SurfaceFormat::kStlBinary:
      return write_text(path, stl_binary_bytes(surface));
    case SurfaceFormat::kPlyAscii:
      return write_text(path, ply_text(surface, false));
    case SurfaceFormat::kPlyBinary:
      return write_text(path, ply_text(surface, true));
  }
  throw Error("cannot write '" + path + "': unknown format");
}

void write_surface(const std::string& path, const TriangleSurface& surface) {
  const std::string ext = extension_of(path);
  if (ext == ".obj") return write_surface(path, surface, SurfaceFormat::kObj);
  if (ext == ".off") return write_surface(path, surface, SurfaceFormat::kOff);
  if (ext == ".stl") return write_surface(path, surface, SurfaceFormat::kStlBinary);
  if (ext == ".ply") return write_surface(path, surface, SurfaceFormat::kPlyBinary);
  throw Error("cannot write '" + path + "': unknown surface format " +
              (ext.empty() ? std::string("(no extension)") : "'" + ext + "'") +
              ": expected .obj, .off, .stl or .ply");
}

TriangleSurface tet_mesh_boundary(const TetMeshInput& mesh) {
  // Facet k of a tet, oriented outward for det(v1 - v0, v2 - v0, v3 - v0) > 0.
  static constexpr int kFacet[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  const std::size_t nt = mesh.nb_tets();
  if (mesh.tets.size() != 4 * nt) throw Error(mesh.source + ": tet array size not a multiple of 4");
  struct Facet {
    std::array<std::uint32_t, 3> key;  // sorted vertices
    std::uint64_t id;                  // 4 * tet + k
  };
  std::vector<Facet> facets(4 * nt);
  for (std::size_t t = 0; t < nt; ++t) {
    for (std::size_t k = 0; k < 4; ++k) {
      Facet& f = facets[4 * t + k];
      for (std::size_t j = 0; j < 3; ++j) {
        f.key[j] = mesh.tets[4 * t + static_cast<std::size_t>(kFacet[k][j])];
      }
      std::sort(f.key.begin(), f.key.end());
      f.id = 4 * t + k;
    }
  }
  std::sort(facets.begin(), facets.end(), [](const Facet& a, const Facet& b) {
    return a.key != b.key ? a.key < b.key : a.id < b.id;
  });
  std::vector<std::uint64_t> boundary;
  for (std::size_t i = 0; i < facets.size();) {
    std::size_t j = i + 1;
    while (j < facets.size() && facets[j].key == facets[i].key) ++j;
    if (j == i + 1) boundary.push_back(facets[i].id);
    i = j;
  }
  std::sort(boundary.begin(), boundary.end());
  TriangleSurface s;
  s.source = "boundary of " + mesh.source;
  s.xyz = mesh.xyz;
  s.triangles.reserve(3 * boundary.size());
  s.triangle_line.reserve(boundary.size());
  for (const std::uint64_t id : boundary) {
    const std::size_t t = static_cast<std::size_t>(id / 4);
    const auto k = static_cast<std::size_t>(id % 4);
    for (std::size_t j = 0; j < 3; ++j) {
      s.triangles.push_back(mesh.tets[4 * t + static_cast<std::size_t>(kFacet[k][j])]);
    }
    s.triangle_line.push_back(t < mesh.tet_line.size() ? mesh.tet_line[t] : 0u);
  }
  return s;
}

}  // namespace voroclip
