// Tetrahedral mesh files: Medit .mesh, TetGen .node/.ele/.face, Gmsh .msh (2.2 and 4.1)
// and legacy VTK, read into a TetMeshInput and written from one, with the triangles the
// file lists and the tags of tets and triangles (see TetMeshInput).
//
// Reading. The whole file is read into memory and split into blank-separated tokens by
// Lexer (text_lexer.h), which keeps the line of each token for messages and parses numbers with
// std::from_chars (locale-independent, correctly rounded). A counted section (n entries
// announced by a header) that meets the end of the file, or a keyword, before its n-th
// entry is reported as truncated with the counts expected and found. Tetrahedra and
// triangles are collected with their vertex numbers as the file writes them (RawCells) and
// checked against the file's vertex numbering once the whole file is read: Medit and TetGen
// number from a base (1, or TetGen's first node number), VTK from 0, Gmsh by arbitrary node
// tags. Tags are read with their elements (Gmsh 4.1: from the entity of the element's
// block, once the whole file is read); a tag vector of zeros is returned empty.
//
// Writing. Coordinates use the shortest decimal that reads back to the same double
// (std::to_chars), so every writer/reader pair round-trips exactly; files are written
// through write_file_atomically.
#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <ostream>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <unordered_map>
#include <utility>
#include <vector>

#include "binary_io.h"
#include "other_volumes.h"
#include "text_lexer.h"
#include "voroclip/core.h"
#include "vtk_cell_types.h"

namespace voroclip {

namespace {

using namespace detail;  // NOLINT: the shared tokenizer and helpers of text_lexer.h

constexpr std::uint64_t kMaxVertices = std::numeric_limits<std::uint32_t>::max();

// Tetrahedra or triangles as the file numbers their vertices, with their tags and what a
// message needs.
struct RawCells {
  std::size_t per = 4;               // vertices per cell: 4 (tets) or 3 (triangles)
  const char* what = "tetrahedron";  // how the format calls one: "element", "cell", "face"
  std::vector<std::uint64_t> v;      // `per` per cell
  std::vector<std::uint32_t> line;   // per cell
  std::vector<std::uint64_t> label;  // per cell: its number as the file knows it
  std::vector<std::int32_t> ref;     // per cell: its tag (0: none)
  std::uint64_t higher_order = 0;    // cells read by the corners of a higher-order element

  RawCells(std::size_t per_in, const char* what_in) : per(per_in), what(what_in) {}
  void push(std::uint64_t label_in, std::uint32_t line_in, const std::uint64_t* idx,
            std::int32_t ref_in) {
    v.insert(v.end(), idx, idx + per);
    line.push_back(line_in);
    label.push_back(label_in);
    ref.push_back(ref_in);
  }
  std::size_t size() const { return line.size(); }
};

// "file:line: what", or "file: what" for line 0 (binary files).
[[noreturn]] void fail_in(const std::string& path, std::uint32_t line, const std::string& what) {
  if (line == 0) throw Error(path + ": " + what);
  fail_at(path, line, what);
}

using detail::OtherVolumes;

// Tags as TetMeshInput keeps them: empty when all are 0.
std::vector<std::int32_t> tags_or_empty(const std::vector<std::int32_t>& ref) {
  const bool any = std::any_of(ref.begin(), ref.end(), [](std::int32_t r) { return r != 0; });
  return any ? ref : std::vector<std::int32_t>{};
}

// Vertex numbers base .. base + nb_vertices - 1 (Medit, TetGen, VTK) to indices from 0.
std::vector<std::uint32_t> finish_cells(const std::string& path, const RawCells& raw,
                                        std::uint64_t base, std::uint64_t nv) {
  std::vector<std::uint32_t> out(raw.v.size());
  for (std::size_t c = 0; c < raw.size(); ++c) {
    for (std::size_t k = 0; k < raw.per; ++k) {
      const std::uint64_t i = raw.v[raw.per * c + k];
      if (i < base || i - base >= nv) {
        fail_in(path, raw.line[c],
                std::string(raw.what) + " " + std::to_string(raw.label[c]) + ": vertex " +
                    std::to_string(i) + " is out of range " +
                    (nv == 0 ? std::string("(the file has no vertices)")
                             : std::to_string(base) + ".." + std::to_string(base + nv - 1)));
      }
      out[raw.per * c + k] = static_cast<std::uint32_t>(i - base);
    }
  }
  return out;
}

// The tets and triangles of a file that numbers vertices from `base`.
void finish_mesh(const std::string& tets_path, const RawCells& tets,
                 const std::string& triangles_path, const RawCells& triangles, std::uint64_t base,
                 TetMeshInput& mesh) {
  const std::uint64_t nv = mesh.nb_vertices();
  mesh.tets = finish_cells(tets_path, tets, base, nv);
  mesh.tet_line = tets.line;
  mesh.tet_noun = tets.what;
  mesh.tet_label = tets.label;
  mesh.vertex_base = base;
  mesh.tet_ref = tags_or_empty(tets.ref);
  mesh.triangles = finish_cells(triangles_path, triangles, base, nv);
  mesh.triangle_ref = tags_or_empty(triangles.ref);
  mesh.nb_higher_order_tets = tets.higher_order;
  mesh.nb_higher_order_triangles = triangles.higher_order;
}

// A tag as an integer token (a Medit ref, a Gmsh physical tag, a TetGen marker).
std::int32_t to_tag(const Lexer& lx, std::string_view t, const char* what) {
  std::string_view s = t;
  if (s.size() > 1 && s[0] == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
  std::int32_t v = 0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (r.ec == std::errc() && r.ptr == s.data() + s.size()) return v;
  lx.fail(quote(t) + " is not a valid " + what +
          (r.ec == std::errc::result_out_of_range ? " (out of the range of a 32-bit integer)"
                                                  : " (an integer)"));
}

// A tag written as any number (a TetGen attribute): its value must be a 32-bit integer.
std::int32_t to_tag_from_double(const Lexer& lx, std::string_view t, const char* what) {
  const double v = to_double(lx, t);
  if (v != std::floor(v) || v < -2147483648.0 || v > 2147483647.0) {
    lx.fail(quote(t) + " is not a valid " + what + " (a 32-bit integer)");
  }
  return static_cast<std::int32_t>(v);
}

void check_vertex_count(const Lexer& lx, std::uint64_t n) {
  if (n > kMaxVertices) lx.fail(std::to_string(n) + " vertices: more than 2^32 - 1");
}

// ---------------------------------------------------------------------------------------
// Medit .mesh (ASCII). Free format: keywords (case-insensitive) and numbers separated by
// blanks, '#' comments. A section is a keyword, a count and count entries of a fixed
// number of values.

// Sections read past: the number of values per entry.
int medit_skipped_section_size(const std::string& kw) {
  static const std::pair<const char*, int> kSizes[] = {
      {"edges", 3},
      {"quadrilaterals", 5},
      {"prisms", 7},
      {"pyramids", 6},
      {"hexahedra", 9},
      {"corners", 1},
      {"ridges", 1},
      {"requiredvertices", 1},
      {"requirededges", 1},
      {"requiredtriangles", 1},
      {"requiredquadrilaterals", 1},
      {"requiredtetrahedra", 1},
      {"normals", 3},
      {"tangents", 3},
      {"normalatvertices", 2},
      {"normalattrianglevertices", 3},
      {"normalatquadrilateralvertices", 3},
      {"tangentatvertices", 2},
      {"tangentatedgevertices", 3},
      {"edgesp2", 4},
  };
  for (const auto& s : kSizes) {
    if (kw == s.first) return s.second;
  }
  return 0;
}

// Medit's Triangles in a volume mesh are its boundary and interface faces, and their refs
// are the tags of those faces (boundary conditions: Domain3 gives each boundary facet the
// ref of the listed triangle with its three vertices). A triangle with a repeated vertex,
// or whose three vertices are no tetrahedron's face, can tag nothing: its ref would be
// dropped without a word, so it is an error naming the entry (its number from 1, as
// Medit counts across Triangles sections) and its vertices. `raw` holds the entries as
// read, `mesh` the tets and triangles once checked against the vertex count.
void check_medit_triangles(const std::string& path, const RawCells& raw, const TetMeshInput& mesh) {
  const std::size_t ntri = mesh.nb_triangles();
  if (ntri == 0) return;
  using Key = std::array<std::uint32_t, 3>;
  const auto key_of = [](const std::uint32_t* v) {
    Key k = {v[0], v[1], v[2]};
    std::sort(k.begin(), k.end());
    return k;
  };
  const auto vertices = [&](std::size_t t) {
    return "vertices " + std::to_string(raw.v[3 * t]) + " " + std::to_string(raw.v[3 * t + 1]) +
           " " + std::to_string(raw.v[3 * t + 2]);
  };
  for (std::size_t t = 0; t < ntri; ++t) {
    const Key k = key_of(&mesh.triangles[3 * t]);
    if (k[0] == k[1] || k[1] == k[2]) {
      fail_at(path, raw.line[t],
              "triangle " + std::to_string(raw.label[t]) + ": " + vertices(t) +
                  " repeat a vertex (a degenerate triangle, the face of no tetrahedron)");
    }
  }
  static constexpr int kFaces[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  std::vector<Key> faces;
  faces.reserve(4 * std::size_t{mesh.nb_tets()});
  for (std::size_t t = 0; t < mesh.nb_tets(); ++t) {
    for (const auto& f : kFaces) {
      const std::uint32_t v[3] = {mesh.tets[4 * t + static_cast<std::size_t>(f[0])],
                                  mesh.tets[4 * t + static_cast<std::size_t>(f[1])],
                                  mesh.tets[4 * t + static_cast<std::size_t>(f[2])]};
      faces.push_back(key_of(v));
    }
  }
  std::sort(faces.begin(), faces.end());
  for (std::size_t t = 0; t < ntri; ++t) {
    if (!std::binary_search(faces.begin(), faces.end(), key_of(&mesh.triangles[3 * t]))) {
      fail_at(path, raw.line[t],
              "triangle " + std::to_string(raw.label[t]) + ": " + vertices(t) +
                  " are not a face of any tetrahedron (Triangles lists boundary and interface "
                  "faces)");
    }
  }
}

TetMeshInput read_medit(const std::string& path, std::string text) {
  Lexer lx(path, std::move(text), '#');
  TetMeshInput mesh;
  mesh.source = path;
  RawCells tets(4, "tetrahedron"), triangles(3, "triangle");
  const std::string_view first = lx.next();
  if (lower(first) != "meshversionformatted") {
    lx.fail("not a Medit mesh: expected MeshVersionFormatted, found " +
            (first.empty() ? std::string("an empty file") : quote(first)));
  }
  const std::uint64_t version = to_uint(lx, header_token(lx, "MeshVersionFormatted"), "version");
  if (version < 1 || version > 4) {
    lx.fail("MeshVersionFormatted " + std::to_string(version) + ": unknown version (1 to 4)");
  }
  bool tets_section = false;
  OtherVolumes other_volumes;
  std::unordered_map<std::string, std::uint64_t> other_numbered;
  for (;;) {
    const std::string_view t = lx.next();
    if (t.empty()) break;  // "End" is optional in practice
    const std::string kw = lower(t);
    if (kw == "end") break;
    if (kw == "dimension") {
      const std::uint64_t d = to_uint(lx, header_token(lx, "Dimension"), "dimension");
      if (d != 3) lx.fail("Dimension " + std::to_string(d) + ": only 3D meshes are read");
    } else if (kw == "vertices") {
      Section s{"Vertices", "vertices", to_uint(lx, header_token(lx, "Vertices"), "count")};
      check_vertex_count(lx, s.expected);
      mesh.xyz.clear();
      mesh.xyz.reserve(3 * reserve_for(lx, s.expected));
      for (; s.found < s.expected; ++s.found) {
        for (int k = 0; k < 3; ++k) mesh.xyz.push_back(entry_double(lx, s));
        entry_token(lx, s);  // reference
      }
    } else if (kw == "tetrahedra" || kw == "triangles" || kw == "tetrahedrap2" ||
               kw == "trianglesp2") {
      // The P2 sections (10 and 6 vertex indices, then the ref: the corners first, then the
      // mid-edge vertices) by their corners.
      const bool tet = kw == "tetrahedra" || kw == "tetrahedrap2";
      const bool p2 = kw == "tetrahedrap2" || kw == "trianglesp2";
      const std::string name = std::string(tet ? "Tetrahedra" : "Triangles") + (p2 ? "P2" : "");
      RawCells& raw = tet ? tets : triangles;
      Section s{name, tet ? "tetrahedra" : "triangles",
                to_uint(lx, header_token(lx, name), "count")};
      tets_section = tets_section || tet;
      raw.v.reserve(raw.v.size() + raw.per * reserve_for(lx, s.expected));
      if (p2) raw.higher_order += s.expected;
      // Numbered from 1 on, across sections of the same kind (P2 or not).
      const std::uint64_t first_number = raw.size() + 1;
      for (; s.found < s.expected; ++s.found) {
        std::uint64_t idx[4];
        idx[0] = entry_uint(lx, s, "vertex index");
        const std::uint32_t line = lx.line();
        for (std::size_t k = 1; k < raw.per; ++k) idx[k] = entry_uint(lx, s, "vertex index");
        for (std::size_t k = 0; p2 && k < (tet ? 6u : 3u); ++k) entry_uint(lx, s, "vertex index");
        raw.push(first_number + s.found, line, idx, to_tag(lx, entry_token(lx, s), "reference"));
      }
    } else if (const int size = medit_skipped_section_size(kw); size > 0) {
      Section s{std::string(t), "entries", to_uint(lx, header_token(lx, std::string(t)), "count")};
      // Volume elements not read: an error once the file is read (OtherVolumes), each
      // numbered from 1 across sections of its kind, as Medit numbers them.
      const char* other = kw == "hexahedra"  ? "hexahedron"
                          : kw == "prisms"   ? "prism"
                          : kw == "pyramids" ? "pyramid"
                                             : nullptr;
      std::uint64_t& numbered = other_numbered[kw];
      for (; s.found < s.expected; ++s.found) {
        entry_token(lx, s);
        if (other != nullptr) {
          const std::string plural = kw == "hexahedra" ? "hexahedra" : std::string(other) + "s";
          const std::uint64_t number = ++numbered;
          other_volumes.add(other, plural, lx.line(),
                            [&] { return s.name + " entry " + std::to_string(number); });
        }
        for (int k = 1; k < size; ++k) entry_token(lx, s);
      }
    } else {
      lx.fail("unknown Medit keyword " + quote(t));
    }
  }
  other_volumes.check(path);
  if (tets.size() == 0) {
    throw Error(path + (tets_section ? ": the Tetrahedra section is empty"
                                     : ": no tetrahedra (no Tetrahedra section)"));
  }
  finish_mesh(path, tets, path, triangles, 1, mesh);
  check_medit_triangles(path, triangles, mesh);
  mesh.numbering = "Medit numbering, from 1";
  return mesh;
}

// ---------------------------------------------------------------------------------------
// TetGen .node / .ele. Line-based: a header line, then one entry per line; '#' comments.

// The next value of the current entry's line.
std::string_view line_field(Lexer& lx, const std::string& entry, std::size_t expected,
                            std::size_t found) {
  const std::string_view t = lx.next_on_line();
  if (t.empty()) {
    lx.fail(entry + ": expected " + std::to_string(expected) + " values on the line, found " +
            std::to_string(found));
  }
  return t;
}

// The three files' contents (`face_text` nullptr: no .face file); `base` names them.
TetMeshInput read_tetgen(const std::string& base, std::string node_text, std::string ele_text,
                         std::string* face_text) {
  prepare_input(base + ".node", node_text);
  prepare_input(base + ".ele", ele_text);
  if (face_text != nullptr) prepare_input(base + ".face", *face_text);
  TetMeshInput mesh;
  std::uint64_t first_node = 0;
  {
    Lexer lx(base + ".node", std::move(node_text), '#');
    const std::string h = ".node header";
    const std::uint64_t n = to_uint(lx, header_token(lx, h), "count");
    check_vertex_count(lx, n);
    const std::uint64_t dim = to_uint(lx, header_token(lx, h), "dimension");
    if (dim != 3) lx.fail("dimension " + std::to_string(dim) + ": only 3D meshes are read");
    const std::uint64_t nattr = to_uint(lx, header_token(lx, h), "attribute count");
    const std::uint64_t nmark = to_uint(lx, header_token(lx, h), "boundary marker count");
    if (nmark > 1) lx.fail("boundary marker count " + std::to_string(nmark) + ": 0 or 1");
    const std::size_t per_line = static_cast<std::size_t>(4 + nattr + nmark);
    Section s{"nodes", "nodes", n};
    mesh.xyz.reserve(3 * reserve_for(lx, n));
    for (; s.found < n; ++s.found) {
      const std::uint64_t index = to_uint(lx, entry_token(lx, s), "node number");
      if (s.found == 0) {
        if (index > 1) {
          lx.fail("the first node is numbered " + std::to_string(index) +
                  ": TetGen numbers nodes from 0 or 1");
        }
        first_node = index;
      } else if (index != first_node + s.found) {
        lx.fail("node " + std::to_string(index) + ": expected node " +
                std::to_string(first_node + s.found) + " (nodes are numbered consecutively)");
      }
      const std::string entry = "node " + std::to_string(index);
      for (std::size_t k = 1; k < 4; ++k) {
        mesh.xyz.push_back(to_double(lx, line_field(lx, entry, per_line, k)));
      }
      for (std::size_t k = 4; k < per_line; ++k) {
        to_double(lx, line_field(lx, entry, per_line, k));
      }
      lx.skip_line();
    }
  }
  Lexer lx(base + ".ele", std::move(ele_text), '#');
  mesh.source = lx.path();
  const std::string h = ".ele header";
  const std::uint64_t n = to_uint(lx, header_token(lx, h), "count");
  const std::uint64_t per_tet = to_uint(lx, header_token(lx, h), "node count");
  if (per_tet != 4 && per_tet != 10) {
    lx.fail(std::to_string(per_tet) + " nodes per tetrahedron: 4 or 10 (the first 4 are used)");
  }
  const std::uint64_t nattr = to_uint(lx, header_token(lx, h), "attribute count");
  const std::size_t per_line = static_cast<std::size_t>(1 + per_tet + nattr);
  RawCells tets(4, "tetrahedron");
  tets.v.reserve(4 * reserve_for(lx, n));
  if (per_tet == 10) tets.higher_order = n;  // second order (-o2): the corners first
  Section s{"tetrahedra", "tetrahedra", n};
  for (; s.found < n; ++s.found) {
    const std::uint64_t index = to_uint(lx, entry_token(lx, s), "tetrahedron number");
    const std::uint32_t line = lx.line();
    const std::string entry = "tetrahedron " + std::to_string(index);
    std::uint64_t idx[4];
    std::int32_t region = 0;
    for (std::size_t k = 1; k < per_line; ++k) {
      const std::string_view t = line_field(lx, entry, per_line, k);
      if (k <= 4) {
        idx[k - 1] = to_uint(lx, t, "node number");
      } else if (k <= per_tet) {
        to_uint(lx, t, "node number");
      } else if (k == per_tet + 1) {
        region = to_tag_from_double(lx, t, "region attribute");
      } else {
        to_double(lx, t);
      }
    }
    lx.skip_line();
    tets.push(index, line, idx, region);
  }
  if (tets.size() == 0) throw Error(mesh.source + ": no tetrahedra");
  // The .face file, when there is one: "index a b c [marker]" per face, anything after that
  // on the line (TetGen's adjacent tetrahedra) read past.
  RawCells faces(3, "face");
  const std::string face_path = base + ".face";
  if (face_text != nullptr) {
    Lexer fx(face_path, *face_text, '#');
    const std::string fh = ".face header";
    const std::uint64_t nf = to_uint(fx, header_token(fx, fh), "count");
    const std::uint64_t nmark = to_uint(fx, header_token(fx, fh), "boundary marker count");
    if (nmark > 1) fx.fail("boundary marker count " + std::to_string(nmark) + ": 0 or 1");
    const std::size_t per_face = static_cast<std::size_t>(4 + nmark);
    faces.v.reserve(3 * reserve_for(fx, nf));
    Section fs{"faces", "faces", nf};
    for (; fs.found < nf; ++fs.found) {
      const std::uint64_t index = to_uint(fx, entry_token(fx, fs), "face number");
      const std::uint32_t line = fx.line();
      const std::string entry = "face " + std::to_string(index);
      std::uint64_t idx[3];
      for (std::size_t k = 1; k < 4; ++k) {
        idx[k - 1] = to_uint(fx, line_field(fx, entry, per_face, k), "node number");
      }
      const std::int32_t marker =
          nmark == 0 ? 0 : to_tag(fx, line_field(fx, entry, per_face, 4), "boundary marker");
      fx.skip_line();
      faces.push(index, line, idx, marker);
    }
  }
  finish_mesh(mesh.source, tets, face_path, faces, first_node, mesh);
  mesh.numbering = "TetGen numbering, nodes from " + std::to_string(first_node);
  return mesh;
}

// ---------------------------------------------------------------------------------------
// Gmsh .msh, ASCII 2.x (2.2) and 4.1. Sections "$Name" ... "$EndName"; unknown sections
// are read past. Nodes are identified by tags, which need not be contiguous; elements of
// type 4 are 4-node tetrahedra, of type 2 3-node triangles. An element's tag is its
// physical tag: in 2.2 its first tag; in 4.1 the first physical tag of the entity of its
// block ($Entities), resolved once the whole file is read (sections in any order).

constexpr std::uint64_t kGmshTet = 4;
constexpr std::uint64_t kGmshTriangle = 2;

// Reads past a section up to its "$End..." token.
void skip_gmsh_section(Lexer& lx, std::string_view name) {
  const std::uint32_t start = lx.line();
  const std::string end = "$End" + std::string(name.substr(1));
  for (;;) {
    const std::string_view t = lx.next();
    if (t == end) return;
    if (t.empty()) fail_at(lx.path(), start, "section " + std::string(name) + " has no " + end);
  }
}

void expect_gmsh_end(Lexer& lx, const Section& s, const char* end) {
  const std::string_view t = lx.next();
  if (t != end) {
    lx.fail("section " + s.name + ": expected " + end + " after " + std::to_string(s.expected) +
            " " + s.entry + ", found " +
            (t.empty() ? std::string("the end of the file") : quote(t)));
  }
}

struct GmshNodes {
  std::vector<std::uint64_t> tag;  // per vertex
  std::vector<std::uint32_t> line;
};

// What a Gmsh file says about tags: the elements of 4.1 blocks, to be tagged by their
// entity, and the entities' first physical tags.
struct GmshTags {
  struct Block {
    std::uint64_t dim, entity;
    RawCells* cells;
    std::size_t begin, end;  // elements [begin, end) of *cells
  };
  std::vector<Block> blocks;
  // Per dimension 0..3: entity tag -> its first physical tag (entities without one absent),
  // from $Entities and from $PartitionedEntities (whose entities the blocks of a
  // partitioned mesh refer to).
  std::unordered_map<std::uint64_t, std::int32_t> physical[4], partitioned[4];
  bool have_partitioned = false;
  OtherVolumes other;  // volume elements not read: an error once $Elements is read
};

// The RawCells the `n` elements of a type go to (nullptr: not read). Tetrahedra and
// triangles of any order are read by their first 4 or 3 nodes, their corners in every Gmsh
// order (10-node tets, type 11: corners, then mid-edge nodes), and counted in
// RawCells::higher_order; nodes used only by higher-order elements are then vertices of no
// tet, as the points of a geometry are.
RawCells* gmsh_cells(std::uint64_t type, RawCells& tets, RawCells& triangles, std::uint64_t n) {
  RawCells* cells = nullptr;
  switch (type) {
    case kGmshTet:
    case 11:  // 10 nodes
    case 29:  // 20
    case 30:  // 35
    case 31:  // 56
    case 32:  // 22
    case 33:  // 28
      cells = &tets;
      break;
    case kGmshTriangle:
    case 9:  // 6 nodes
    case 20:
    case 21:
    case 22:
    case 23:
    case 24:
    case 25:
      cells = &triangles;
      break;
    default:
      return nullptr;
  }
  if (type != kGmshTet && type != kGmshTriangle) cells->higher_order += n;
  return cells;
}

// The kind of a Gmsh volume element type not read as a tetrahedron (singular and plural),
// as gmsh's GmshDefines.h names the types; {} for the types of lower dimension.
std::pair<const char*, const char*> gmsh_other_volume(std::uint64_t type) {
  if (type == 5 || type == 12 || type == 17 || type == 88 || (type >= 92 && type <= 105)) {
    return {"hexahedron", "hexahedra"};
  }
  if (type == 6 || type == 13 || type == 18 || type == 89 || (type >= 90 && type <= 91) ||
      (type >= 106 && type <= 117)) {
    return {"prism", "prisms"};
  }
  if (type == 7 || type == 14 || type == 19 || (type >= 118 && type <= 132)) {
    return {"pyramid", "pyramids"};
  }
  if (type == 35) return {"polyhedron", "polyhedra"};
  if (type == 140) return {"trihedron", "trihedra"};
  if ((type >= 71 && type <= 75) || (type >= 79 && type <= 83) || type == 87 || type == 136 ||
      type == 137 || type == 139) {
    return {"tetrahedron of an order not read", "tetrahedra of an order not read"};
  }
  return {nullptr, nullptr};
}

// Records element `tag` of `type` in `other` when it is a volume element not read.
void note_gmsh_element(OtherVolumes& other, std::uint64_t tag, std::uint64_t type,
                       std::uint32_t line) {
  const auto [kind, kinds] = gmsh_other_volume(type);
  if (kind == nullptr) return;
  other.add(kind, kinds, line,
            [&] { return "element " + std::to_string(tag) + ", type " + std::to_string(type); });
}

// $PhysicalNames (both formats): count, then `dimension tag "name"` per line.
void read_gmsh_physical_names(Lexer& lx, TetMeshInput& mesh) {
  Section s{"$PhysicalNames", "names", to_uint(lx, header_token(lx, "$PhysicalNames"), "count")};
  for (; s.found < s.expected; ++s.found) {
    TetMeshInput::TagName n;
    const std::uint64_t dim = entry_uint(lx, s, "dimension");
    if (dim > 3) lx.fail("physical name of dimension " + std::to_string(dim) + ": 0 to 3");
    n.dimension = static_cast<int>(dim);
    n.tag = to_tag(lx, entry_token(lx, s), "physical tag");
    std::string_view name = lx.rest_of_line();
    while (!name.empty() && std::isspace(static_cast<unsigned char>(name.front()))) {
      name.remove_prefix(1);
    }
    while (!name.empty() && std::isspace(static_cast<unsigned char>(name.back()))) {
      name.remove_suffix(1);
    }
    if (name.size() < 2 || name.front() != '"' || name.back() != '"') {
      lx.fail("physical name " + (name.empty() ? std::string("(none)") : quote(name)) +
              ": expected a name in double quotes");
    }
    n.name = std::string(name.substr(1, name.size() - 2));
    mesh.tag_names.push_back(std::move(n));
  }
  expect_gmsh_end(lx, s, "$EndPhysicalNames");
}

// $Entities, format 4.1: "numPoints numCurves numSurfaces numVolumes", then per point
// "tag x y z numPhysicalTags physicalTag...", per curve, surface and volume "tag minX minY
// minZ maxX maxY maxZ numPhysicalTags physicalTag... numBounding boundingTag...".
// $PartitionedEntities: first "numPartitions numGhostEntities (ghostTag partition)...",
// then the same counts and entities, each with "parentDim parentTag numPartitions
// partitionTag..." after its tag.
void read_gmsh4_entities(Lexer& lx, GmshTags& tags, bool partitioned) {
  const std::string name = partitioned ? "$PartitionedEntities" : "$Entities";
  if (partitioned) {
    to_uint(lx, header_token(lx, name), "partition count");
    Section ghosts{name, "ghost entities", to_uint(lx, header_token(lx, name), "count")};
    for (; ghosts.found < ghosts.expected; ++ghosts.found) {
      entry_token(lx, ghosts);
      entry_token(lx, ghosts);
    }
  }
  std::uint64_t count[4];
  for (auto& c : count) c = to_uint(lx, header_token(lx, name), "entity count");
  Section s{name, "entities", 0};
  for (const std::uint64_t c : count) {
    if (c > kMaxVertices) lx.fail(name + ": " + std::to_string(c) + " entities: too many");
    s.expected += c;
  }
  auto& physical = partitioned ? tags.partitioned : tags.physical;
  for (std::size_t dim = 0; dim < 4; ++dim) {
    for (std::uint64_t e = 0; e < count[dim]; ++e, ++s.found) {
      const std::uint64_t tag = entry_uint(lx, s, "entity tag");
      if (partitioned) {
        entry_uint(lx, s, "parent dimension");
        entry_token(lx, s);  // parent tag
        const std::uint64_t parts = entry_uint(lx, s, "partition count");
        for (std::uint64_t k = 0; k < parts; ++k) entry_token(lx, s);
      }
      for (std::size_t k = 0; k < (dim == 0 ? 3u : 6u); ++k) entry_double(lx, s);
      const std::uint64_t nphys = entry_uint(lx, s, "physical tag count");
      for (std::uint64_t k = 0; k < nphys; ++k) {
        const std::int32_t phys = to_tag(lx, entry_token(lx, s), "physical tag");
        if (k == 0) physical[dim].emplace(tag, phys);
      }
      if (dim > 0) {
        const std::uint64_t nbound = entry_uint(lx, s, "bounding entity count");
        for (std::uint64_t k = 0; k < nbound; ++k) entry_token(lx, s);
      }
    }
  }
  expect_gmsh_end(lx, s, ("$End" + name.substr(1)).c_str());
}

// $Nodes, format 2: count, then "tag x y z" per node.
void read_gmsh2_nodes(Lexer& lx, TetMeshInput& mesh, GmshNodes& nodes) {
  Section s{"$Nodes", "nodes", to_uint(lx, header_token(lx, "$Nodes"), "count")};
  check_vertex_count(lx, s.expected);
  for (; s.found < s.expected; ++s.found) {
    nodes.tag.push_back(entry_uint(lx, s, "node tag"));
    nodes.line.push_back(lx.line());
    for (int k = 0; k < 3; ++k) mesh.xyz.push_back(entry_double(lx, s));
  }
  expect_gmsh_end(lx, s, "$EndNodes");
}

// $Elements, format 2: count, then "tag type ntags tag... node..." per element; the first
// tag is the physical tag.
void read_gmsh2_elements(Lexer& lx, RawCells& tets, RawCells& triangles, GmshTags& tags) {
  Section s{"$Elements", "elements", to_uint(lx, header_token(lx, "$Elements"), "count")};
  for (; s.found < s.expected; ++s.found) {
    const std::uint64_t tag = entry_uint(lx, s, "element tag");
    const std::uint32_t line = lx.line();
    const std::uint64_t type = entry_uint(lx, s, "element type");
    RawCells* cells = gmsh_cells(type, tets, triangles, 1);
    if (cells == nullptr) {
      note_gmsh_element(tags.other, tag, type, line);
      lx.skip_line();
      continue;
    }
    const std::uint64_t ntags = entry_uint(lx, s, "tag count");
    std::int32_t physical = 0;
    for (std::uint64_t k = 0; k < ntags; ++k) {
      const std::string_view t = entry_token(lx, s);
      if (k == 0) physical = to_tag(lx, t, "physical tag");
    }
    std::uint64_t idx[4];
    for (std::size_t k = 0; k < cells->per; ++k) idx[k] = entry_uint(lx, s, "node tag");
    lx.skip_line();
    cells->push(tag, line, idx, physical);
  }
  expect_gmsh_end(lx, s, "$EndElements");
}

// $Nodes, format 4.1: "numEntityBlocks numNodes minTag maxTag", then per block
// "entityDim entityTag parametric numNodesInBlock", its tags (one per line), then its
// coordinates (one node per line: x y z, then u [v [w]] when parametric: skipped).
void read_gmsh4_nodes(Lexer& lx, TetMeshInput& mesh, GmshNodes& nodes) {
  const std::uint64_t blocks = to_uint(lx, header_token(lx, "$Nodes"), "block count");
  Section s{"$Nodes", "nodes", to_uint(lx, header_token(lx, "$Nodes"), "count")};
  check_vertex_count(lx, s.expected);
  to_uint(lx, header_token(lx, "$Nodes"), "node tag");
  to_uint(lx, header_token(lx, "$Nodes"), "node tag");
  mesh.xyz.reserve(3 * reserve_for(lx, s.expected));
  for (std::uint64_t b = 0; b < blocks; ++b) {
    entry_uint(lx, s, "entity dimension");
    entry_uint(lx, s, "entity tag");
    entry_uint(lx, s, "parametric flag");
    const std::uint64_t in_block = entry_uint(lx, s, "node count");
    if (in_block > s.expected - s.found) {
      lx.fail("section $Nodes: a block of " + std::to_string(in_block) + " nodes after " +
              std::to_string(s.found) + " of " + std::to_string(s.expected) + " nodes");
    }
    for (std::uint64_t i = 0; i < in_block; ++i) {
      nodes.tag.push_back(entry_uint(lx, s, "node tag"));
      nodes.line.push_back(lx.line());
    }
    for (std::uint64_t i = 0; i < in_block; ++i) {
      for (int k = 0; k < 3; ++k) mesh.xyz.push_back(entry_double(lx, s));
      lx.skip_line();
      ++s.found;
    }
  }
  if (s.found != s.expected) {
    lx.fail("section $Nodes: its blocks hold " + std::to_string(s.found) + " nodes, the header " +
            std::to_string(s.expected));
  }
  expect_gmsh_end(lx, s, "$EndNodes");
}

// $Elements, format 4.1: "numEntityBlocks numElements minTag maxTag", then per block
// "entityDim entityTag elementType numElementsInBlock" and one element per line:
// "tag node...". The blocks of tets and triangles are kept in `tags` for their entity.
void read_gmsh4_elements(Lexer& lx, RawCells& tets, RawCells& triangles, GmshTags& tags) {
  const std::uint64_t blocks = to_uint(lx, header_token(lx, "$Elements"), "block count");
  Section s{"$Elements", "elements", to_uint(lx, header_token(lx, "$Elements"), "count")};
  to_uint(lx, header_token(lx, "$Elements"), "element tag");
  to_uint(lx, header_token(lx, "$Elements"), "element tag");
  for (std::uint64_t b = 0; b < blocks; ++b) {
    const std::uint64_t dim = entry_uint(lx, s, "entity dimension");
    const std::uint64_t entity = entry_uint(lx, s, "entity tag");
    const std::uint64_t type = entry_uint(lx, s, "element type");
    const std::uint64_t in_block = entry_uint(lx, s, "element count");
    RawCells* cells = gmsh_cells(type, tets, triangles, in_block);
    if (dim > 3) lx.fail("section $Elements: a block of entity dimension " + std::to_string(dim));
    if (in_block > s.expected - s.found) {
      lx.fail("section $Elements: a block of " + std::to_string(in_block) + " elements after " +
              std::to_string(s.found) + " of " + std::to_string(s.expected) + " elements");
    }
    if (cells != nullptr) tags.blocks.push_back({dim, entity, cells, cells->size(), 0});
    for (std::uint64_t i = 0; i < in_block; ++i, ++s.found) {
      const std::uint64_t tag = entry_uint(lx, s, "element tag");
      const std::uint32_t line = lx.line();
      if (cells != nullptr) {
        std::uint64_t idx[4];
        for (std::size_t k = 0; k < cells->per; ++k) idx[k] = entry_uint(lx, s, "node tag");
        cells->push(tag, line, idx, 0);
      } else {
        note_gmsh_element(tags.other, tag, type, line);
      }
      lx.skip_line();
    }
    if (cells != nullptr) tags.blocks.back().end = cells->size();
  }
  if (s.found != s.expected) {
    lx.fail("section $Elements: its blocks hold " + std::to_string(s.found) +
            " elements, the header " + std::to_string(s.expected));
  }
  expect_gmsh_end(lx, s, "$EndElements");
}

// Node tags to vertex indices: a direct table when the tags are dense enough (the usual
// 1..n), a hash map otherwise.
void finish_gmsh(const std::string& path, const GmshNodes& nodes, const RawCells& tets,
                 const RawCells& triangles, TetMeshInput& mesh) {
  const std::size_t n = nodes.tag.size();
  const std::uint64_t max_tag = n == 0 ? 0 : *std::max_element(nodes.tag.begin(), nodes.tag.end());
  constexpr std::uint32_t kAbsent = 0xffffffffu;
  std::vector<std::uint32_t> table;
  std::unordered_map<std::uint64_t, std::uint32_t> map;
  const bool dense = max_tag <= 4 * static_cast<std::uint64_t>(n) + 1024;
  if (dense) {
    table.assign(static_cast<std::size_t>(max_tag) + 1, kAbsent);
  } else {
    map.reserve(n);
  }
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint64_t tag = nodes.tag[i];
    const auto index = static_cast<std::uint32_t>(i);
    std::uint32_t first = kAbsent;
    if (dense) {
      std::uint32_t& slot = table[static_cast<std::size_t>(tag)];
      if (slot == kAbsent) slot = index;
      first = slot;
    } else {
      first = map.try_emplace(tag, index).first->second;
    }
    if (first != index) {
      fail_in(path, nodes.line[i],
              "node tag " + std::to_string(tag) + " is repeated (first " +
                  (nodes.line[first] == 0 ? "as node " + std::to_string(first + 1) + " of $Nodes"
                                          : "at line " + std::to_string(nodes.line[first])) +
                  ")");
    }
  }
  const auto resolve = [&](const RawCells& raw) {
    std::vector<std::uint32_t> out(raw.v.size());
    for (std::size_t c = 0; c < raw.size(); ++c) {
      for (std::size_t k = 0; k < raw.per; ++k) {
        const std::uint64_t tag = raw.v[raw.per * c + k];
        std::uint32_t index = kAbsent;
        if (dense) {
          if (tag <= max_tag) index = table[static_cast<std::size_t>(tag)];
        } else if (const auto it = map.find(tag); it != map.end()) {
          index = it->second;
        }
        if (index == kAbsent) {
          fail_in(path, raw.line[c],
                  "element " + std::to_string(raw.label[c]) + ": node " + std::to_string(tag) +
                      (n == 0 ? std::string(" does not exist (the file has no nodes)")
                              : " is not in section $Nodes"));
        }
        out[raw.per * c + k] = index;
      }
    }
    return out;
  };
  mesh.tets = resolve(tets);
  mesh.tet_line = tets.line;
  mesh.tet_noun = tets.what;
  mesh.tet_label = tets.label;
  mesh.vertex_label = nodes.tag;
  mesh.numbering = "Gmsh element and node tags";
  mesh.tet_ref = tags_or_empty(tets.ref);
  mesh.triangles = resolve(triangles);
  mesh.triangle_ref = tags_or_empty(triangles.ref);
  mesh.nb_higher_order_tets = tets.higher_order;
  mesh.nb_higher_order_triangles = triangles.higher_order;
}

// The end of both readers: no tetrahedra is an error, 4.1 blocks take their entity's
// physical tag, node tags become indices.
void finish_gmsh_file(const std::string& path, bool have_elements, const GmshTags& tags,
                      const GmshNodes& nodes, RawCells& tets, RawCells& triangles,
                      TetMeshInput& mesh) {
  tags.other.check(path);
  if (tets.size() == 0) {
    throw Error(path + (have_elements ? ": no tetrahedra (element type 4, 11, ...) in $Elements"
                                      : ": no tetrahedra (no $Elements section)"));
  }
  for (const GmshTags::Block& b : tags.blocks) {
    const auto& physical = tags.have_partitioned ? tags.partitioned[b.dim] : tags.physical[b.dim];
    const auto it = physical.find(b.entity);
    if (it == physical.end()) continue;
    std::fill(b.cells->ref.begin() + static_cast<std::ptrdiff_t>(b.begin),
              b.cells->ref.begin() + static_cast<std::ptrdiff_t>(b.end), it->second);
  }
  finish_gmsh(path, nodes, tets, triangles, mesh);
}

TetMeshInput read_gmsh_binary(const std::string& path, const std::string& text);

TetMeshInput read_gmsh(const std::string& path, std::string text) {
  Lexer lx(path, std::move(text), 0);
  TetMeshInput mesh;
  mesh.source = path;
  const std::string_view first = lx.next();
  if (first != "$MeshFormat") {
    lx.fail("not a Gmsh mesh: expected $MeshFormat, found " +
            (first.empty() ? std::string("an empty file") : quote(first)));
  }
  const std::string version(header_token(lx, "$MeshFormat"));
  const std::string_view file_type = header_token(lx, "$MeshFormat");
  header_token(lx, "$MeshFormat");  // data size
  const bool v2 = version == "2" || version == "2.0" || version == "2.1" || version == "2.2";
  if (!v2 && version != "4.1") {
    lx.fail("Gmsh format version " + quote(version) + " is not supported (2.2 or 4.1)");
  }
  if (file_type == "1") return read_gmsh_binary(path, lx.text());
  if (file_type != "0") {
    lx.fail("Gmsh file-type " + quote(file_type) + ": 0 (ASCII) or 1 (binary)");
  }
  {
    const std::string_view t = lx.next();
    if (t != "$EndMeshFormat") {
      lx.fail("expected $EndMeshFormat, found " +
              (t.empty() ? std::string("the end of the file") : quote(t)));
    }
  }
  GmshNodes nodes;
  RawCells tets(4, "element"), triangles(3, "element");
  GmshTags tags;
  bool have_nodes = false, have_elements = false, have_names = false, have_entities = false;
  for (;;) {
    const std::string_view t = lx.next();
    if (t.empty()) break;
    if (t.size() < 2 || t[0] != '$') lx.fail("expected a section ($Name), found " + quote(t));
    if (t == "$Nodes") {
      if (have_nodes) lx.fail("a second $Nodes section");
      have_nodes = true;
      if (v2) {
        read_gmsh2_nodes(lx, mesh, nodes);
      } else {
        read_gmsh4_nodes(lx, mesh, nodes);
      }
    } else if (t == "$Elements") {
      if (have_elements) lx.fail("a second $Elements section");
      have_elements = true;
      if (v2) {
        read_gmsh2_elements(lx, tets, triangles, tags);
      } else {
        read_gmsh4_elements(lx, tets, triangles, tags);
      }
    } else if (t == "$PhysicalNames") {
      if (have_names) lx.fail("a second $PhysicalNames section");
      have_names = true;
      read_gmsh_physical_names(lx, mesh);
    } else if (t == "$Entities" && !v2) {
      if (have_entities) lx.fail("a second $Entities section");
      have_entities = true;
      read_gmsh4_entities(lx, tags, false);
    } else if (t == "$PartitionedEntities" && !v2) {
      if (tags.have_partitioned) lx.fail("a second $PartitionedEntities section");
      tags.have_partitioned = true;
      read_gmsh4_entities(lx, tags, true);
    } else {
      skip_gmsh_section(lx, t);
    }
  }
  finish_gmsh_file(path, have_elements, tags, nodes, tets, triangles, mesh);
  return mesh;
}

// ---------------------------------------------------------------------------------------
// Gmsh .msh binary (file-type 1), 2.2 and 4.1. The section names, the $MeshFormat line,
// $PhysicalNames and (2.2) the counts of $Nodes and $Elements are ASCII lines; the rest of
// $Nodes, $Elements, $Entities and $PartitionedEntities is binary, in the byte order of the
// writer, which the int 1 after the $MeshFormat line tells. 2.2: ints (4 bytes) and
// doubles; 4.1: ints, doubles and size_t of `data-size` bytes (counts and node and element
// tags). Elements of a type not kept are read past by the node count of their type
// (kGmshNodesPerType), so binary files can hold only the types listed there. Each section's
// binary data ends with '\n' before its $End line; other sections are read past up to it.

// Nodes per Gmsh element type 0..140 (0: no such type), as gmsh's getElementProperties
// gives them (Gmsh 4.8).
constexpr std::uint16_t kGmshNodesPerType[] = {
    0,   2,  3,  4,  4,  8,  6,  5,  3,   6,   9,   10,  27,  18,  14,   1,  8,   20,  15,  13,  9,
    10,  12, 15, 15, 21, 4,  5,  6,  20,  35,  56,  22,  28,  0,   0,    16, 25,  36,  12,  16,  20,
    28,  36, 45, 55, 66, 49, 64, 81, 100, 121, 18,  21,  24,  27,  30,   24, 28,  32,  36,  40,  7,
    8,   9,  10, 11, 0,  0,  0,  0,  84,  120, 165, 220, 286, 0,   0,    0,  34,  40,  46,  52,  58,
    1,   1,  1,  1,  1,  1,  0,  0,  64,  125, 216, 343, 512, 729, 1000, 32, 44,  56,  68,  80,  92,
    104, 0,  0,  0,  0,  0,  0,  0,  0,   0,   0,   0,   0,   30,  55,   91, 140, 204, 285, 385, 21,
    29,  37, 45, 53, 61, 69, 1,  0,  0,   0,   0,   16,  0,   0,   0};

std::uint64_t gmsh_nodes_per_type(const ByteReader& in, std::uint64_t type, const char* section) {
  const std::uint64_t n = type < std::size(kGmshNodesPerType) ? kGmshNodesPerType[type] : 0;
  if (n == 0) {
    in.fail(std::string(section) + ": element type " + std::to_string(type) +
            " is unknown (its node count is needed to read a binary file)");
  }
  return n;
}

// A binary .msh being read: the cursor, the format's integer sizes.
struct GmshBinary {
  ByteReader in;
  std::size_t size_t_bytes = 8;  // 4.1: the data-size of $MeshFormat

  std::uint64_t i32(const char* section) {
    const std::int64_t v = in.sint(4, section);
    if (v < 0) in.fail(std::string(section) + ": negative value " + std::to_string(v));
    return static_cast<std::uint64_t>(v);
  }
  std::uint64_t size(const char* section) { return in.uint(size_t_bytes, section); }
  // A coordinate of node `tag`: a finite double (as the ASCII reader requires).
  double finite(const char* section, std::uint64_t tag) {
    const double v = in.f64(section);
    if (!std::isfinite(v)) {
      in.fail(std::string(section) + ": node " + std::to_string(tag) +
              ": a coordinate is not finite");
    }
    return v;
  }

  // The $End line after a section's binary data.
  void expect_end(const char* section, const char* end) {
    const std::string_view t = in.token();
    if (t != end) {
      in.fail(std::string("section ") + section + ": expected " + end + " after its data, found " +
              (t.empty() ? std::string("the end of the file") : quote(t)));
    }
  }
};

// $Nodes, 2.2 binary: "count\n", then per node int tag, 3 doubles.
void read_gmsh2_binary_nodes(GmshBinary& f, TetMeshInput& mesh, GmshNodes& nodes) {
  const char* section = "section $Nodes";
  const std::string_view t = f.in.token();
  std::uint64_t n = 0;
  if (std::from_chars(t.data(), t.data() + t.size(), n).ptr != t.data() + t.size() || t.empty()) {
    f.in.fail(std::string(section) + ": the node count " + quote(t) + " is not a number");
  }
  f.in.end_line();
  if (n > kMaxVertices) f.in.fail(std::to_string(n) + " vertices: more than 2^32 - 1");
  f.in.need(n, 28, std::string(section) + ": " + std::to_string(n) + " nodes");
  nodes.tag.reserve(static_cast<std::size_t>(n));
  mesh.xyz.reserve(3 * static_cast<std::size_t>(n));
  for (std::uint64_t i = 0; i < n; ++i) {
    nodes.tag.push_back(f.i32(section));
    nodes.line.push_back(0);
    for (int k = 0; k < 3; ++k) mesh.xyz.push_back(f.finite(section, nodes.tag.back()));
  }
  f.expect_end("$Nodes", "$EndNodes");
}

// $Elements, 2.2 binary: "count\n", then blocks: int type, int count, int ntags, then per
// element int number, ntags ints (the first the physical tag), the node tags (ints).
void read_gmsh2_binary_elements(GmshBinary& f, RawCells& tets, RawCells& triangles,
                                GmshTags& tags) {
  const char* section = "section $Elements";
  const std::string_view t = f.in.token();
  std::uint64_t n = 0;
  if (std::from_chars(t.data(), t.data() + t.size(), n).ptr != t.data() + t.size() || t.empty()) {
    f.in.fail(std::string(section) + ": the element count " + quote(t) + " is not a number");
  }
  f.in.end_line();
  for (std::uint64_t found = 0; found < n;) {
    const std::uint64_t type = f.i32(section);
    const std::uint64_t in_block = f.i32(section);
    const std::uint64_t ntags = f.i32(section);
    if (in_block > n - found) {
      f.in.fail(std::string(section) + ": a block of " + std::to_string(in_block) +
                " elements after " + std::to_string(found) + " of " + std::to_string(n) +
                " elements");
    }
    const std::uint64_t per = gmsh_nodes_per_type(f.in, type, section);
    f.in.need(in_block, 4 * (1 + ntags + per),
              std::string(section) + ": a block of " + std::to_string(in_block) + " elements");
    RawCells* cells = gmsh_cells(type, tets, triangles, in_block);
    for (std::uint64_t e = 0; e < in_block; ++e, ++found) {
      const std::uint64_t number = f.i32(section);
      std::int32_t physical = 0;
      for (std::uint64_t k = 0; k < ntags; ++k) {
        const std::int64_t tag = f.in.sint(4, section);
        if (k == 0) physical = static_cast<std::int32_t>(tag);
      }
      std::uint64_t idx[4];
      for (std::uint64_t k = 0; k < per; ++k) {
        const std::uint64_t node = f.i32(section);
        if (k < 4) idx[k] = node;
      }
      if (cells != nullptr) {
        cells->push(number, 0, idx, physical);
      } else {
        note_gmsh_element(tags.other, number, type, 0);
      }
    }
  }
  f.expect_end("$Elements", "$EndElements");
}

// $Entities / $PartitionedEntities, 4.1 binary: as the ASCII layout (read_gmsh4_entities),
// counts as size_t, tags as int, coordinates as doubles.
void read_gmsh4_binary_entities(GmshBinary& f, GmshTags& tags, bool partitioned) {
  const char* section = partitioned ? "section $PartitionedEntities" : "section $Entities";
  if (partitioned) {
    f.size(section);  // partitions
    const std::uint64_t ghosts = f.size(section);
    f.in.skip(ghosts, 8, section);
  }
  std::uint64_t count[4];
  for (auto& c : count) c = f.size(section);
  auto& physical = partitioned ? tags.partitioned : tags.physical;
  for (std::size_t dim = 0; dim < 4; ++dim) {
    for (std::uint64_t e = 0; e < count[dim]; ++e) {
      const std::int64_t tag = f.in.sint(4, section);
      if (partitioned) {
        f.in.skip(2, 4, section);                // parent dimension and tag
        f.in.skip(f.size(section), 4, section);  // partitions
      }
      f.in.skip(dim == 0 ? 3 : 6, 8, section);  // point, or bounding box
      const std::uint64_t nphys = f.size(section);
      for (std::uint64_t k = 0; k < nphys; ++k) {
        const std::int64_t phys = f.in.sint(4, section);
        if (k == 0 && tag >= 0) {
          physical[dim].emplace(static_cast<std::uint64_t>(tag), static_cast<std::int32_t>(phys));
        }
      }
      if (dim > 0) {
        f.in.skip(f.size(section), 4, section);  // bounding entities
      }
    }
  }
  f.expect_end(partitioned ? "$PartitionedEntities" : "$Entities",
               partitioned ? "$EndPartitionedEntities" : "$EndEntities");
}

// $Nodes, 4.1 binary: 4 size_t (blocks, nodes, min and max tag), per block int dimension,
// int entity, int parametric, size_t count, the count tags (size_t), then per node x y z
// and, when parametric, `dimension` parameters (doubles).
void read_gmsh4_binary_nodes(GmshBinary& f, TetMeshInput& mesh, GmshNodes& nodes) {
  const char* section = "section $Nodes";
  const std::uint64_t blocks = f.size(section);
  const std::uint64_t n = f.size(section);
  f.size(section);
  f.size(section);
  if (n > kMaxVertices) f.in.fail(std::to_string(n) + " vertices: more than 2^32 - 1");
  f.in.need(n, f.size_t_bytes + 24, std::string(section) + ": " + std::to_string(n) + " nodes");
  nodes.tag.reserve(static_cast<std::size_t>(n));
  mesh.xyz.reserve(3 * static_cast<std::size_t>(n));
  std::uint64_t found = 0;
  for (std::uint64_t b = 0; b < blocks; ++b) {
    const std::uint64_t dim = f.i32(section);
    f.i32(section);  // entity
    const std::uint64_t parametric = f.i32(section);
    const std::uint64_t in_block = f.size(section);
    if (in_block > n - found) {
      f.in.fail(std::string(section) + ": a block of " + std::to_string(in_block) +
                " nodes after " + std::to_string(found) + " of " + std::to_string(n) + " nodes");
    }
    const std::uint64_t extra = parametric != 0 ? std::min<std::uint64_t>(dim, 3) : 0;
    f.in.need(in_block, f.size_t_bytes + 8 * (3 + extra),
              std::string(section) + ": a block of " + std::to_string(in_block) + " nodes");
    for (std::uint64_t i = 0; i < in_block; ++i) {
      nodes.tag.push_back(f.size(section));
      nodes.line.push_back(0);
    }
    for (std::uint64_t i = 0; i < in_block; ++i) {
      const std::uint64_t tag = nodes.tag[nodes.tag.size() - in_block + i];
      for (int k = 0; k < 3; ++k) mesh.xyz.push_back(f.finite(section, tag));
      f.in.skip(extra, 8, section);
    }
    found += in_block;
  }
  if (found != n) {
    f.in.fail(std::string(section) + ": its blocks hold " + std::to_string(found) +
              " nodes, the header " + std::to_string(n));
  }
  f.expect_end("$Nodes", "$EndNodes");
}

// $Elements, 4.1 binary: 4 size_t (blocks, elements, min and max tag), per block int
// dimension, int entity, int type, size_t count, then per element its tag and its node
// tags (size_t).
void read_gmsh4_binary_elements(GmshBinary& f, RawCells& tets, RawCells& triangles,
                                GmshTags& tags) {
  const char* section = "section $Elements";
  const std::uint64_t blocks = f.size(section);
  const std::uint64_t n = f.size(section);
  f.size(section);
  f.size(section);
  std::uint64_t found = 0;
  for (std::uint64_t b = 0; b < blocks; ++b) {
    const std::uint64_t dim = f.i32(section);
    const std::uint64_t entity = f.i32(section);
    const std::uint64_t type = f.i32(section);
    const std::uint64_t in_block = f.size(section);
    if (dim > 3)
      f.in.fail(std::string(section) + ": a block of entity dimension " + std::to_string(dim));
    if (in_block > n - found) {
      f.in.fail(std::string(section) + ": a block of " + std::to_string(in_block) +
                " elements after " + std::to_string(found) + " of " + std::to_string(n) +
                " elements");
    }
    const std::uint64_t per = gmsh_nodes_per_type(f.in, type, section);
    f.in.need(in_block, f.size_t_bytes * (1 + per),
              std::string(section) + ": a block of " + std::to_string(in_block) + " elements");
    RawCells* cells = gmsh_cells(type, tets, triangles, in_block);
    if (cells != nullptr) {
      tags.blocks.push_back({dim, entity, cells, cells->size(), 0});
      cells->v.reserve(cells->v.size() + cells->per * static_cast<std::size_t>(in_block));
    }
    for (std::uint64_t e = 0; e < in_block; ++e) {
      const std::uint64_t number = f.size(section);
      std::uint64_t idx[4];
      for (std::uint64_t k = 0; k < per; ++k) {
        const std::uint64_t node = f.size(section);
        if (k < 4) idx[k] = node;
      }
      if (cells != nullptr) {
        cells->push(number, 0, idx, 0);
      } else {
        note_gmsh_element(tags.other, number, type, 0);
      }
    }
    if (cells != nullptr) tags.blocks.back().end = cells->size();
    found += in_block;
  }
  if (found != n) {
    f.in.fail(std::string(section) + ": its blocks hold " + std::to_string(found) +
              " elements, the header " + std::to_string(n));
  }
  f.expect_end("$Elements", "$EndElements");
}

TetMeshInput read_gmsh_binary(const std::string& path, const std::string& text) {
  GmshBinary f{ByteReader(path, text), 8};
  TetMeshInput mesh;
  mesh.source = path;
  f.in.token();  // $MeshFormat
  const std::string version(f.in.token());
  f.in.token();  // file-type 1
  const std::string data_size(f.in.token());
  f.in.end_line();
  const bool v2 = version != "4.1";
  if (data_size != "8" && !(data_size == "4" && !v2)) {
    f.in.fail("$MeshFormat: data-size " + quote(data_size) +
              (v2 ? ": 8 (the size of a double)" : ": 4 or 8 (the size of size_t)"));
  }
  f.size_t_bytes = data_size == "4" ? 4 : 8;
  {
    // The int 1, in the writer's byte order.
    const std::uint64_t one = f.in.uint(4, "$MeshFormat");
    if (one != 1 && one != 0x01000000u) {
      f.in.fail("$MeshFormat: the binary check reads " + std::to_string(one) +
                ", not 1 in either byte order");
    }
    f.in.set_big_endian(one != 1);
    f.expect_end("$MeshFormat", "$EndMeshFormat");
  }
  GmshNodes nodes;
  RawCells tets(4, "element"), triangles(3, "element");
  GmshTags tags;
  bool have_nodes = false, have_elements = false, have_names = false, have_entities = false;
  for (;;) {
    const std::string_view t = f.in.token();
    if (t.empty()) break;
    if (t.size() < 2 || t[0] != '$') f.in.fail("expected a section ($Name), found " + quote(t));
    const auto once = [&](bool& have) {
      if (have) f.in.fail("a second " + std::string(t) + " section");
      have = true;
    };
    if (t == "$Nodes" || t == "$Elements" || t == "$Entities" || t == "$PartitionedEntities") {
      f.in.end_line();  // binary data (4.1) or the count line (2.2) starts on the next line
    }
    if (t == "$Nodes") {
      once(have_nodes);
      if (v2) {
        read_gmsh2_binary_nodes(f, mesh, nodes);
      } else {
        read_gmsh4_binary_nodes(f, mesh, nodes);
      }
    } else if (t == "$Elements") {
      once(have_elements);
      if (v2) {
        read_gmsh2_binary_elements(f, tets, triangles, tags);
      } else {
        read_gmsh4_binary_elements(f, tets, triangles, tags);
      }
    } else if (t == "$Entities" && !v2) {
      once(have_entities);
      read_gmsh4_binary_entities(f, tags, false);
    } else if (t == "$PartitionedEntities" && !v2) {
      once(tags.have_partitioned);
      read_gmsh4_binary_entities(f, tags, true);
    } else {
      // ASCII ($PhysicalNames) or read past: up to the $End line.
      const std::string end = "$End" + std::string(t.substr(1));
      const std::size_t stop = text.find(end, f.in.pos());
      if (stop == std::string::npos) {
        f.in.fail("section " + std::string(t) + " has no " + end);
      }
      if (t == "$PhysicalNames") {
        once(have_names);
        Lexer lx(path, text.substr(f.in.pos(), stop + end.size() - f.in.pos()), 0, f.in.line());
        read_gmsh_physical_names(lx, mesh);
      }
      f.in.seek(stop + end.size());
    }
  }
  finish_gmsh_file(path, have_elements, tags, nodes, tets, triangles, mesh);
  return mesh;
}

// ---------------------------------------------------------------------------------------
// Legacy VTK (.vtk), ASCII, DATASET UNSTRUCTURED_GRID: POINTS, CELLS (the classic layout
// "n i0 .. i(n-1)" per cell, or the VTK 5.1 layout OFFSETS + CONNECTIVITY), CELL_TYPES;
// cells of type 10 (VTK_TETRA) and 5 (VTK_TRIANGLE) are kept. Then POINT_DATA / CELL_DATA
// attributes and FIELD arrays: the CELL_DATA arrays of tags (SCALARS or FIELD arrays of one
// component; VtkCellTags) are kept, everything else is read past by its size.

// The tag arrays of a legacy VTK file (ASCII or binary): the first CELL_DATA array of one
// component of each name that may hold tags (kVtkTagNames); the tets' tags and the
// triangles' are then the first present in the order of kVtkTetTags and kVtkTriangleTags
// (`region` / `patch`, else meshio's names: see text_lexer.h).
struct VtkCellTags {
  std::vector<std::int32_t> arrays[std::size(kVtkTagNames)];
  bool have[std::size(kVtkTagNames)] = {};
  // The array to fill with an array `name` of `components` components (nullptr: none).
  std::vector<std::int32_t>* array(bool cell_data, std::string_view name,
                                   std::uint64_t components) {
    if (!cell_data || components != 1) return nullptr;
    for (std::size_t k = 0; k < std::size(kVtkTagNames); ++k) {
      if (name != kVtkTagNames[k]) continue;
      if (have[k]) return nullptr;
      have[k] = true;
      return &arrays[k];
    }
    return nullptr;
  }
  // The tags of the tets (`tets` true) or of the triangles, per cell (empty: none).
  const std::vector<std::int32_t>& of(bool tets) const {
    static const std::vector<std::int32_t> kNone;
    for (const std::size_t k : tets ? kVtkTetTags : kVtkTriangleTags) {
      if (have[k]) return arrays[k];
    }
    return kNone;
  }
};

// One array of a VTK attribute section: `values` of it, read (as tags) or read past.
void read_vtk_array(Lexer& lx, const std::string& name, std::uint64_t values,
                    std::vector<std::int32_t>* tags) {
  Section s{name, "values", values};
  if (tags != nullptr) tags->reserve(reserve_for(lx, values));
  for (; s.found < values; ++s.found) {
    const std::string_view t = entry_token(lx, s);
    if (tags == nullptr) continue;
    const double v = to_double(lx, t);
    if (v != std::floor(v) || v < -2147483648.0 || v > 2147483647.0) {
      lx.fail(name + ": cell " + std::to_string(s.found) + ": " + quote(t) +
              " is not a tag (a 32-bit integer)");
    }
    tags->push_back(static_cast<std::int32_t>(v));
  }
}

void finish_vtk(const std::string& path, const std::vector<std::uint64_t>& cell_begin,
                const std::vector<std::uint64_t>& cell_index,
                const std::vector<std::uint32_t>& cell_line,
                const std::vector<std::uint64_t>& cell_type,
                const std::vector<std::int32_t>& region, const std::vector<std::int32_t>& patch,
                TetMeshInput& mesh);
TetMeshInput read_vtk_binary(const std::string& path, const std::string& text);

TetMeshInput read_vtk(const std::string& path, std::string text) {
  Lexer lx(path, std::move(text), 0);
  TetMeshInput mesh;
  mesh.source = path;
  {
    const std::string_view l1 = lx.rest_of_line();
    if (lower(l1).rfind("# vtk datafile", 0) != 0) {
      lx.fail("not a legacy VTK file: line 1 should start with '# vtk DataFile Version'");
    }
    lx.next_line();
    lx.next_line();  // the title
    const std::string_view format = lx.next();
    if (lower(format) == "binary") return read_vtk_binary(path, lx.text());
    if (lower(format) != "ascii") {
      lx.fail("expected ASCII or BINARY, found " +
              (format.empty() ? std::string("the end of the file") : quote(format)));
    }
    const std::string_view dataset = lx.next();
    const std::string_view type = lx.next();
    if (lower(dataset) != "dataset") {
      lx.fail("expected DATASET, found " +
              (dataset.empty() ? std::string("the end of the file") : quote(dataset)));
    }
    if (lower(type) != "unstructured_grid") {
      lx.fail("DATASET " + quote(type) + ": only UNSTRUCTURED_GRID is read");
    }
  }
  bool have_points = false, have_cells = false, have_types = false;
  // Cells: cell c has the point indices cell_index[cell_begin[c] .. cell_begin[c + 1]).
  std::vector<std::uint64_t> cell_begin{0}, cell_index;
  std::vector<std::uint32_t> cell_line;
  std::vector<std::uint64_t> cell_type;
  // Attribute data: the number of tuples of the current POINT_DATA / CELL_DATA section
  // (none before the first), and the tag arrays found in CELL_DATA, per cell.
  enum class Data { kNone, kPoint, kCell } data = Data::kNone;
  std::uint64_t tuples = 0;
  VtkCellTags cell_tags;
  // The tag array an array of CELL_DATA named `name` with `components` fills (nullptr: none).
  const auto tag_array = [&](std::string_view name, std::uint64_t components) {
    return cell_tags.array(data == Data::kCell, name, components);
  };
  const auto need_data = [&](std::string_view kw) {
    if (data == Data::kNone) {
      lx.fail(std::string(kw) + " outside POINT_DATA and CELL_DATA");
    }
  };
  for (;;) {
    const std::string_view t = lx.next();
    if (t.empty()) break;
    const std::string kw = lower(t);
    if (kw == "points") {
      Section s{"POINTS", "points", to_uint(lx, header_token(lx, "POINTS"), "count")};
      check_vertex_count(lx, s.expected);
      header_token(lx, "POINTS");  // the data type: any numeric type is read as double
      mesh.xyz.reserve(3 * reserve_for(lx, s.expected));
      for (; s.found < s.expected; ++s.found) {
        for (int k = 0; k < 3; ++k) mesh.xyz.push_back(entry_double(lx, s));
      }
      have_points = true;
    } else if (kw == "cells") {
      const std::uint64_t n = to_uint(lx, header_token(lx, "CELLS"), "count");
      const std::uint64_t size = to_uint(lx, header_token(lx, "CELLS"), "size");
      const std::uint32_t header_line = lx.line();
      if (lower(lx.peek()) == "offsets") {
        // VTK 5.1: n offsets (cells + 1) and `size` connectivity entries.
        lx.next();
        header_token(lx, "OFFSETS");
        Section s{"OFFSETS", "offsets", n};
        cell_begin.clear();
        for (; s.found < n; ++s.found) cell_begin.push_back(entry_uint(lx, s, "offset"));
        const std::string_view conn = lx.next();
        if (lower(conn) != "connectivity") {
          lx.fail("expected CONNECTIVITY, found " +
                  (conn.empty() ? std::string("the end of the file") : quote(conn)));
        }
        header_token(lx, "CONNECTIVITY");
        Section c{"CONNECTIVITY", "indices", size};
        std::vector<std::uint32_t> index_line;
        for (; c.found < size; ++c.found) {
          cell_index.push_back(entry_uint(lx, c, "point index"));
          index_line.push_back(lx.line());
        }
        if (cell_begin.empty() || cell_begin.front() != 0 || cell_begin.back() != size ||
            !std::is_sorted(cell_begin.begin(), cell_begin.end())) {
          fail_at(path, header_line,
                  "CELLS: the offsets must rise from 0 to the connectivity size " +
                      std::to_string(size));
        }
        cell_line.clear();
        for (std::size_t cell = 0; cell + 1 < cell_begin.size(); ++cell) {
          cell_line.push_back(cell_begin[cell] < size
                                  ? index_line[static_cast<std::size_t>(cell_begin[cell])]
                                  : lx.line());
        }
      } else {
        // Classic layout: per cell, its point count and its point indices.
        Section s{"CELLS", "cells", n};
        std::uint64_t values = 0;
        for (; s.found < n; ++s.found) {
          const std::uint64_t k = entry_uint(lx, s, "point count");
          cell_line.push_back(lx.line());
          for (std::uint64_t i = 0; i < k; ++i) cell_index.push_back(entry_uint(lx, s, "index"));
          cell_begin.push_back(cell_index.size());
          values += k + 1;
        }
        if (values != size) {
          fail_at(path, header_line,
                  "CELLS " + std::to_string(n) + " " + std::to_string(size) + ": the cells hold " +
                      std::to_string(values) + " values, not " + std::to_string(size));
        }
      }
      have_cells = true;
    } else if (kw == "cell_types") {
      Section s{"CELL_TYPES", "cell types", to_uint(lx, header_token(lx, "CELL_TYPES"), "count")};
      if (!have_cells) lx.fail("CELL_TYPES before CELLS");
      if (s.expected != cell_line.size()) {
        lx.fail("CELL_TYPES " + std::to_string(s.expected) + ": CELLS has " +
                count_of(cell_line.size(), "cell"));
      }
      for (; s.found < s.expected; ++s.found) cell_type.push_back(entry_uint(lx, s, "cell type"));
      have_types = true;
    } else if (kw == "metadata") {
      lx.skip_to_blank_line();
    } else if (kw == "point_data" || kw == "cell_data") {
      const std::string name = kw == "point_data" ? "POINT_DATA" : "CELL_DATA";
      tuples = to_uint(lx, header_token(lx, name), "count");
      data = kw == "point_data" ? Data::kPoint : Data::kCell;
      if (data == Data::kCell && tuples != cell_line.size()) {
        lx.fail("CELL_DATA " + std::to_string(tuples) + ": CELLS has " +
                count_of(cell_line.size(), "cell"));
      }
    } else if (kw == "scalars") {
      // SCALARS name type [components], then LOOKUP_TABLE name (optional here).
      need_data("SCALARS");
      const std::string name(header_token(lx, "SCALARS"));
      header_token(lx, "SCALARS");
      const std::string_view nc = lx.next_on_line();
      const std::uint64_t components = nc.empty() ? 1 : to_uint(lx, nc, "component count");
      if (lower(lx.peek()) == "lookup_table") {
        lx.next();
        header_token(lx, "LOOKUP_TABLE");
      }
      read_vtk_array(lx, "SCALARS " + name, tuples * components, tag_array(name, components));
    } else if (kw == "lookup_table" || kw == "color_scalars" || kw == "vectors" ||
               kw == "normals" || kw == "tensors" || kw == "tensors6" ||
               kw == "texture_coordinates" || kw == "global_ids" || kw == "pedigree_ids") {
      // Read past: "LOOKUP_TABLE name size" (size RGBA tuples), "COLOR_SCALARS name n",
      // "TEXTURE_COORDINATES name dim type", the others "KEYWORD name type".
      const std::string head = std::string(t) + " " + std::string(header_token(lx, std::string(t)));
      std::uint64_t values = 0;
      if (kw == "lookup_table") {
        values = 4 * to_uint(lx, header_token(lx, head), "size");
      } else {
        need_data(t);
        const std::uint64_t per = kw == "color_scalars" || kw == "texture_coordinates"
                                      ? to_uint(lx, header_token(lx, head), "component count")
                                  : kw == "vectors" || kw == "normals" ? 3
                                  : kw == "tensors"                    ? 9
                                  : kw == "tensors6"                   ? 6
                                                                       : 1;
        if (kw != "color_scalars") header_token(lx, head);  // the data type
        values = tuples * per;
      }
      read_vtk_array(lx, head, values, nullptr);
    } else if (kw == "field") {
      // FIELD name n, then n arrays "name components tuples type" and their values (in
      // VTK 5.1 files each possibly followed by METADATA).
      header_token(lx, "FIELD");
      Section s{"FIELD", "arrays", to_uint(lx, header_token(lx, "FIELD"), "array count")};
      // Names and types are words: not entry_token(), which takes a word for a keyword.
      const auto word = [&]() {
        const std::string_view w = lx.next();
        if (w.empty()) truncated(lx, s, w);
        return w;
      };
      for (; s.found < s.expected; ++s.found) {
        std::string_view name = word();
        if (lower(name) == "metadata") {
          lx.skip_to_blank_line();
          name = word();
        }
        if (name == "NULL_ARRAY") continue;
        const std::string array(name);
        const std::uint64_t components = entry_uint(lx, s, "component count");
        const std::uint64_t n = entry_uint(lx, s, "tuple count");
        const std::string type = lower(word());
        if (type == "string" || type == "utf8_string") {
          // One string per line (VTK writes blanks as %20): read past by lines.
          lx.skip_line();
          for (std::uint64_t i = 0; i < n * components; ++i) {
            if (lx.peek().empty()) truncated(lx, s, {});
            lx.next_line();
          }
          lx.next_line();
          continue;
        }
        std::vector<std::int32_t>* tags = n == tuples ? tag_array(array, components) : nullptr;
        read_vtk_array(lx, "FIELD array " + array, n * components, tags);
      }
    } else {
      lx.fail("unknown VTK keyword " + quote(t));
    }
  }
  if (!have_points || !have_cells || !have_types) {
    throw Error(path + ": no " +
                std::string(!have_points  ? "POINTS"
                            : !have_cells ? "CELLS"
                                          : "CELL_TYPES") +
                " section");
  }
  finish_vtk(path, cell_begin, cell_index, cell_line, cell_type, cell_tags.of(true),
             cell_tags.of(false), mesh);
  return mesh;
}

// Cells of both readers: cell c has the points cell_index[cell_begin[c] .. cell_begin[c + 1]),
// the type cell_type[c], stands at line cell_line[c] (0: binary) and has the tags region[c]
// and patch[c] (when not empty); the tets and triangles go to `mesh`.
void finish_vtk(const std::string& path, const std::vector<std::uint64_t>& cell_begin,
                const std::vector<std::uint64_t>& cell_index,
                const std::vector<std::uint32_t>& cell_line,
                const std::vector<std::uint64_t>& cell_type,
                const std::vector<std::int32_t>& region, const std::vector<std::int32_t>& patch,
                TetMeshInput& mesh) {
  RawCells tets(4, "cell"), triangles(3, "cell");
  OtherVolumes other;
  for (std::size_t c = 0; c < cell_type.size(); ++c) {
    const vtk::VtkCellKind kind = vtk::vtk_cell_kind(cell_type[c]);
    if (kind.points == 0) {
      if (kind.other != nullptr) {
        other.add(kind.other, kind.others, cell_line[c], [&] {
          return "cell " + std::to_string(c) + ", type " + std::to_string(cell_type[c]);
        });
      }
      continue;
    }
    const bool tet = kind.corners == 4;
    RawCells& raw = tet ? tets : triangles;
    const std::uint64_t k = cell_begin[c + 1] - cell_begin[c];
    if (k != kind.points) {
      fail_in(path, cell_line[c],
              "cell " + std::to_string(c) + " of type " + kind.name + " has " +
                  count_of(k, "point") + ", not " + std::to_string(kind.points));
    }
    const std::vector<std::int32_t>& ref = tet ? region : patch;
    raw.push(c, cell_line[c], cell_index.data() + cell_begin[c], ref.empty() ? 0 : ref[c]);
    if (kind.points != kind.corners) ++raw.higher_order;
  }
  other.check(path);
  if (tets.size() == 0) throw Error(path + ": no tetrahedra (cell type 10 or 24)");
  finish_mesh(path, tets, path, triangles, 0, mesh);
  mesh.numbering = "VTK numbering, from 0";
}

// ---------------------------------------------------------------------------------------
// Legacy VTK BINARY: the same keywords on ASCII lines, each followed (on the next line) by
// its values in binary, big-endian, of the type the line names; the values end with '\n'.
// METADATA blocks are ASCII; string arrays are not read (VTK prefixes each string with a
// variable-length size), nor `bit` arrays.

// A VTK data type: its size in bytes, whether floating point, whether signed.
struct VtkType {
  std::size_t size = 0;
  bool floating = false, is_signed = false;
};

VtkType vtk_type(const ByteReader& in, std::string_view name, const std::string& where) {
  static const std::pair<const char*, VtkType> kTypes[] = {
      {"unsigned_char", {1, false, false}},
      {"char", {1, false, true}},
      {"vtktypeuint8", {1, false, false}},
      {"vtktypeint8", {1, false, true}},
      {"unsigned_short", {2, false, false}},
      {"short", {2, false, true}},
      {"vtktypeuint16", {2, false, false}},
      {"vtktypeint16", {2, false, true}},
      {"unsigned_int", {4, false, false}},
      {"int", {4, false, true}},
      {"vtktypeuint32", {4, false, false}},
      {"vtktypeint32", {4, false, true}},
      {"vtkidtype", {4, false, true}},  // VTK writes vtkIdType arrays as int
      {"unsigned_long", {8, false, false}},
      {"long", {8, false, true}},
      {"vtktypeuint64", {8, false, false}},
      {"vtktypeint64", {8, false, true}},
      {"float", {4, true, true}},
      {"vtktypefloat32", {4, true, true}},
      {"double", {8, true, true}},
      {"vtktypefloat64", {8, true, true}},
  };
  const std::string l = lower(name);
  for (const auto& [n, t] : kTypes) {
    if (l == n) return t;
  }
  in.fail(where + ": data type " + quote(name) + " is not read in a binary file");
}

// a * b, or an error naming `where` when it does not fit in 64 bits.
std::uint64_t checked_product(const ByteReader& in, std::uint64_t a, std::uint64_t b,
                              const std::string& where) {
  if (b != 0 && a > std::numeric_limits<std::uint64_t>::max() / b) {
    in.fail(where + ": " + std::to_string(a) + " x " + std::to_string(b) + " values: too many");
  }
  return a * b;
}

// `n` binary values of type `t` as doubles (integers up to 2^53 exactly), after checking
// that the file holds them.
std::vector<double> vtk_binary_values(ByteReader& in, const VtkType& t, std::uint64_t n,
                                      const std::string& where) {
  in.need(n, t.size, where + ": " + std::to_string(n) + " values");
  std::vector<double> out;
  out.reserve(static_cast<std::size_t>(n));
  const std::string what = where;
  for (std::uint64_t i = 0; i < n; ++i) {
    const std::uint64_t raw = in.uint(t.size, what.c_str());
    out.push_back(t.floating    ? (t.size == 8 ? bits_to_double(raw) : bits_to_float(raw))
                  : t.is_signed ? static_cast<double>(to_signed(raw, t.size))
                                : static_cast<double>(raw));
  }
  return out;
}

// Integers (counts, offsets, point indices): a non-negative integer type is needed.
std::vector<std::uint64_t> vtk_binary_indices(ByteReader& in, std::string_view type,
                                              std::uint64_t n, const std::string& where) {
  const VtkType t = vtk_type(in, type, where);
  if (t.floating) in.fail(where + ": data type " + quote(type) + ": an integer type is needed");
  in.need(n, t.size, where + ": " + std::to_string(n) + " values");
  std::vector<std::uint64_t> out;
  out.reserve(static_cast<std::size_t>(n));
  for (std::uint64_t i = 0; i < n; ++i) {
    const std::uint64_t raw = in.uint(t.size, where.c_str());
    if (t.is_signed && to_signed(raw, t.size) < 0) {
      in.fail(where + ": value " + std::to_string(i) + " is negative (" +
              std::to_string(to_signed(raw, t.size)) + ")");
    }
    out.push_back(raw);
  }
  return out;
}

std::uint64_t vtk_word_uint(const ByteReader& in, const std::vector<std::string_view>& w,
                            std::size_t i, const std::string& where) {
  std::uint64_t v = 0;
  if (i >= w.size()) in.fail(where + ": missing value on the line");
  const std::string_view t = w[i];
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
  if (r.ec != std::errc() || r.ptr != t.data() + t.size()) {
    in.fail(where + ": " + quote(t) + " is not a count (a non-negative integer)");
  }
  return v;
}

std::string_view vtk_word(const ByteReader& in, const std::vector<std::string_view>& w,
                          std::size_t i, const std::string& where) {
  if (i >= w.size()) in.fail(where + ": missing value on the line");
  return w[i];
}

// A METADATA block: the lines up to and including the next blank one.
void skip_vtk_metadata(ByteReader& in) {
  for (;;) {
    const std::string_view l = in.rest_of_line();
    if (std::all_of(l.begin(), l.end(),
                    [](char c) { return std::isspace(static_cast<unsigned char>(c)); })) {
      return;
    }
  }
}

TetMeshInput read_vtk_binary(const std::string& path, const std::string& text) {
  ByteReader in(path, text);
  in.set_big_endian(true);
  TetMeshInput mesh;
  mesh.source = path;
  in.end_line();  // "# vtk DataFile Version x.y"
  in.end_line();  // the title
  in.end_line();  // BINARY
  {
    const std::vector<std::string_view> w = in.words();
    if (w.size() < 2 || lower(w[0]) != "dataset") in.fail("expected DATASET on line 4");
    if (lower(w[1]) != "unstructured_grid") {
      in.fail("DATASET " + quote(w[1]) + ": only UNSTRUCTURED_GRID is read");
    }
  }
  bool have_points = false, have_cells = false, have_types = false;
  std::vector<std::uint64_t> cell_begin{0}, cell_index, cell_type;
  std::vector<std::uint32_t> cell_line;
  enum class Data { kNone, kPoint, kCell } data = Data::kNone;
  std::uint64_t tuples = 0;
  VtkCellTags cell_tags;
  // The tag array an array of CELL_DATA named `name` with `components` fills (nullptr: none).
  const auto tag_array = [&](std::string_view name, std::uint64_t components) {
    return cell_tags.array(data == Data::kCell, name, components);
  };
  // An array of `n` values of `type` named `where`: read as tags, or read past.
  const auto array = [&](std::string_view type, std::uint64_t n, const std::string& where,
                         std::vector<std::int32_t>* tags) {
    const VtkType t = vtk_type(in, type, where);
    if (tags == nullptr) {
      in.skip(n, t.size, where + ": " + std::to_string(n) + " values");
      return;
    }
    const std::vector<double> v = vtk_binary_values(in, t, n, where);
    for (std::size_t c = 0; c < v.size(); ++c) {
      if (v[c] != std::floor(v[c]) || v[c] < -2147483648.0 || v[c] > 2147483647.0) {
        std::string value;
        append(value, v[c]);
        in.fail(where + ": cell " + std::to_string(c) + ": " + value +
                " is not a tag (a 32-bit integer)");
      }
      tags->push_back(static_cast<std::int32_t>(v[c]));
    }
  };
  const auto need_data = [&](std::string_view kw) {
    if (data == Data::kNone) in.fail(std::string(kw) + " outside POINT_DATA and CELL_DATA");
  };
  for (;;) {
    const std::vector<std::string_view> w = in.words();
    if (w.empty()) break;
    const std::string kw = lower(w[0]);
    const std::string head(w[0]);
    if (kw == "points") {
      const std::uint64_t n = vtk_word_uint(in, w, 1, head);
      if (n > kMaxVertices)
        in.fail("POINTS: " + std::to_string(n) + " vertices: more than 2^32 - 1");
      mesh.xyz = vtk_binary_values(in, vtk_type(in, vtk_word(in, w, 2, head), head), 3 * n, head);
      for (std::size_t i = 0; i < mesh.xyz.size(); ++i) {
        if (!std::isfinite(mesh.xyz[i])) {
          in.fail("POINTS: point " + std::to_string(i / 3) + ": a coordinate is not finite");
        }
      }
      have_points = true;
    } else if (kw == "cells") {
      const std::uint64_t n = vtk_word_uint(in, w, 1, head);
      const std::uint64_t size = vtk_word_uint(in, w, 2, head);
      cell_begin.assign(1, 0);
      cell_index.clear();
      if (lower(in.peek_token()) == "offsets") {
        // VTK 5.1: n offsets (cells + 1), then `size` connectivity entries.
        const std::vector<std::string_view> o = in.words();
        cell_begin = vtk_binary_indices(in, vtk_word(in, o, 1, "OFFSETS"), n, "OFFSETS");
        const std::vector<std::string_view> c = in.words();
        if (c.empty() || lower(c[0]) != "connectivity") {
          in.fail("expected CONNECTIVITY after the OFFSETS of CELLS");
        }
        cell_index =
            vtk_binary_indices(in, vtk_word(in, c, 1, "CONNECTIVITY"), size, "CONNECTIVITY");
        if (cell_begin.empty() || cell_begin.front() != 0 || cell_begin.back() != size ||
            !std::is_sorted(cell_begin.begin(), cell_begin.end())) {
          in.fail("CELLS: the offsets must rise from 0 to the connectivity size " +
                  std::to_string(size));
        }
      } else {
        // Classic layout: `size` ints, per cell its point count and its point indices.
        const std::vector<std::uint64_t> v = vtk_binary_indices(in, "int", size, head);
        std::size_t i = 0;
        for (std::uint64_t c = 0; c < n; ++c) {
          if (i >= v.size() || v[i] > v.size() - i - 1) {
            in.fail("CELLS " + std::to_string(n) + " " + std::to_string(size) + ": cell " +
                    std::to_string(c) + " runs past the " + std::to_string(size) + " values");
          }
          const auto k = static_cast<std::size_t>(v[i]);
          cell_index.insert(cell_index.end(), v.begin() + static_cast<std::ptrdiff_t>(i + 1),
                            v.begin() + static_cast<std::ptrdiff_t>(i + 1 + k));
          cell_begin.push_back(cell_index.size());
          i += k + 1;
        }
        if (i != v.size()) {
          in.fail("CELLS " + std::to_string(n) + " " + std::to_string(size) + ": the cells hold " +
                  std::to_string(i) + " values, not " + std::to_string(size));
        }
      }
      cell_line.assign(cell_begin.size() - 1, 0);
      have_cells = true;
    } else if (kw == "cell_types") {
      const std::uint64_t n = vtk_word_uint(in, w, 1, head);
      if (!have_cells) in.fail("CELL_TYPES before CELLS");
      if (n != cell_line.size()) {
        in.fail("CELL_TYPES " + std::to_string(n) + ": CELLS has " +
                count_of(cell_line.size(), "cell"));
      }
      cell_type = vtk_binary_indices(in, "int", n, head);
      have_types = true;
    } else if (kw == "metadata") {
      skip_vtk_metadata(in);
    } else if (kw == "point_data" || kw == "cell_data") {
      tuples = vtk_word_uint(in, w, 1, head);
      data = kw == "point_data" ? Data::kPoint : Data::kCell;
      if (data == Data::kCell && tuples != cell_line.size()) {
        in.fail("CELL_DATA " + std::to_string(tuples) + ": CELLS has " +
                count_of(cell_line.size(), "cell"));
      }
    } else if (kw == "scalars") {
      need_data("SCALARS");
      const std::string name(vtk_word(in, w, 1, head));
      const std::string_view type = vtk_word(in, w, 2, head);
      const std::uint64_t components = w.size() > 3 ? vtk_word_uint(in, w, 3, head) : 1;
      if (lower(in.peek_token()) == "lookup_table") in.words();
      array(type, checked_product(in, tuples, components, head), "SCALARS " + name,
            tag_array(name, components));
    } else if (kw == "lookup_table") {
      in.skip(checked_product(in, vtk_word_uint(in, w, 2, head), 4, head), 1, head);
    } else if (kw == "color_scalars") {
      need_data(head);
      in.skip(checked_product(in, tuples, vtk_word_uint(in, w, 2, head), head), 1, head);
    } else if (kw == "vectors" || kw == "normals" || kw == "tensors" || kw == "tensors6" ||
               kw == "texture_coordinates" || kw == "global_ids" || kw == "pedigree_ids") {
      need_data(head);
      const bool texture = kw == "texture_coordinates";
      const std::uint64_t per = texture                              ? vtk_word_uint(in, w, 2, head)
                                : kw == "vectors" || kw == "normals" ? 3
                                : kw == "tensors"                    ? 9
                                : kw == "tensors6"                   ? 6
                                                                     : 1;
      array(vtk_word(in, w, texture ? 3 : 2, head), checked_product(in, tuples, per, head), head,
            nullptr);
    } else if (kw == "field") {
      const std::uint64_t arrays = vtk_word_uint(in, w, 2, head);
      for (std::uint64_t a = 0; a < arrays; ++a) {
        std::vector<std::string_view> h = in.words();
        if (!h.empty() && lower(h[0]) == "metadata") {
          skip_vtk_metadata(in);
          h = in.words();
        }
        if (h.empty()) {
          in.fail("FIELD: expected " + std::to_string(arrays) + " arrays, found " +
                  std::to_string(a) + " before the end of the file");
        }
        if (h[0] == "NULL_ARRAY") continue;
        const std::string name = "FIELD array " + std::string(h[0]);
        const std::uint64_t components = vtk_word_uint(in, h, 1, name);
        const std::uint64_t n = vtk_word_uint(in, h, 2, name);
        std::vector<std::int32_t>* tags = n == tuples ? tag_array(h[0], components) : nullptr;
        array(vtk_word(in, h, 3, name), checked_product(in, n, components, name), name, tags);
      }
    } else {
      in.fail("unknown VTK keyword " + quote(w[0]));
    }
  }
  if (!have_points || !have_cells || !have_types) {
    throw Error(path + ": no " +
                std::string(!have_points  ? "POINTS"
                            : !have_cells ? "CELLS"
                                          : "CELL_TYPES") +
                " section");
  }
  finish_vtk(path, cell_begin, cell_index, cell_line, cell_type, cell_tags.of(true),
             cell_tags.of(false), mesh);
  return mesh;
}

// ---------------------------------------------------------------------------------------
// Writers.

// The tag of element i of a tag vector that is empty (all 0) or holds one tag per element.
std::int32_t tag_of(const std::vector<std::int32_t>& ref, std::size_t i) {
  return ref.empty() ? 0 : ref[i];
}

void append_int(std::string& out, std::int64_t v) {
  char buf[24];
  out.append(buf, std::to_chars(buf, buf + sizeof(buf), v).ptr);
}

// Vertex i as "x y z" (shortest round-trip decimals).
void append_vertex(std::string& out, const TetMeshInput& mesh, std::size_t i) {
  append(out, mesh.xyz[3 * i]);
  out += ' ';
  append(out, mesh.xyz[3 * i + 1]);
  out += ' ';
  append(out, mesh.xyz[3 * i + 2]);
}

// Cell c of `cells` (`per` vertices each) as "a b c [d]", vertex numbers from `base`.
void append_cell(std::string& out, const std::vector<std::uint32_t>& cells, std::size_t per,
                 std::size_t c, std::uint64_t base) {
  for (std::size_t k = 0; k < per; ++k) {
    if (k > 0) out += ' ';
    append(out, cells[per * c + k] + base);
  }
}

std::string medit_text(const TetMeshInput& mesh) {
  std::string s = "MeshVersionFormatted 2\nDimension 3\nVertices\n";
  append(s, std::uint64_t{mesh.nb_vertices()});
  s += '\n';
  for (std::size_t i = 0; i < mesh.nb_vertices(); ++i) {
    append_vertex(s, mesh, i);
    s += " 0\n";
  }
  const auto section = [&](const char* name, const std::vector<std::uint32_t>& cells,
                           std::size_t per, const std::vector<std::int32_t>& ref) {
    s += name;
    s += '\n';
    append(s, std::uint64_t{cells.size() / per});
    s += '\n';
    for (std::size_t c = 0; c < cells.size() / per; ++c) {
      append_cell(s, cells, per, c, 1);
      s += ' ';
      append_int(s, tag_of(ref, c));
      s += '\n';
    }
  };
  if (mesh.nb_triangles() > 0) section("Triangles", mesh.triangles, 3, mesh.triangle_ref);
  section("Tetrahedra", mesh.tets, 4, mesh.tet_ref);
  s += "End\n";
  return s;
}

std::string tetgen_node_text(const TetMeshInput& mesh) {
  std::string s;
  append(s, std::uint64_t{mesh.nb_vertices()});
  s += " 3 0 0\n";
  for (std::size_t i = 0; i < mesh.nb_vertices(); ++i) {
    append(s, std::uint64_t{i + 1});
    s += ' ';
    append_vertex(s, mesh, i);
    s += '\n';
  }
  return s;
}

// .ele (tets, a region attribute when tagged) or .face (triangles, a boundary marker when
// tagged): "count nodes_per_tet attributes" / "count markers", then "number nodes [tag]".
std::string tetgen_cells_text(const std::vector<std::uint32_t>& cells, std::size_t per,
                              const std::vector<std::int32_t>& ref) {
  std::string s;
  append(s, std::uint64_t{cells.size() / per});
  s += per == 4 ? " 4 " : " ";
  s += ref.empty() ? "0\n" : "1\n";
  for (std::size_t c = 0; c < cells.size() / per; ++c) {
    append(s, std::uint64_t{c + 1});
    s += ' ';
    append_cell(s, cells, per, c, 1);
    if (!ref.empty()) {
      s += ' ';
      append_int(s, ref[c]);
    }
    s += '\n';
  }
  return s;
}

// Gmsh entities of one dimension: one per distinct tag, in increasing order of tag,
// numbered from 1 (at least one: the volume entity 1 holds the nodes).
struct GmshEntities {
  std::vector<std::int32_t> tags;  // entity e + 1 has tags[e]

  explicit GmshEntities(const std::vector<std::int32_t>& ref, std::size_t count, bool at_least_one)
      : tags(ref) {
    if (tags.empty() && (count > 0 || at_least_one)) tags.push_back(0);
    std::sort(tags.begin(), tags.end());
    tags.erase(std::unique(tags.begin(), tags.end()), tags.end());
  }
  std::uint64_t entity(std::int32_t tag) const {
    return static_cast<std::uint64_t>(std::lower_bound(tags.begin(), tags.end(), tag) -
                                      tags.begin()) +
           1;
  }
};

std::string gmsh_physical_names(const TetMeshInput& mesh) {
  if (mesh.tag_names.empty()) return "";
  std::string s = "$PhysicalNames\n";
  append(s, std::uint64_t{mesh.tag_names.size()});
  s += '\n';
  for (const TetMeshInput::TagName& n : mesh.tag_names) {
    append_int(s, n.dimension);
    s += ' ';
    append_int(s, n.tag);
    s += " \"" + n.name + "\"\n";
  }
  return s + "$EndPhysicalNames\n";
}

// Element tags: tets 1..nt, then triangles nt + 1..nt + ntri.
std::string gmsh22_text(const TetMeshInput& mesh) {
  const GmshEntities volumes(mesh.tet_ref, mesh.nb_tets(), true);
  const GmshEntities surfaces(mesh.triangle_ref, mesh.nb_triangles(), false);
  std::string s = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n" + gmsh_physical_names(mesh) + "$Nodes\n";
  append(s, std::uint64_t{mesh.nb_vertices()});
  s += '\n';
  for (std::size_t i = 0; i < mesh.nb_vertices(); ++i) {
    append(s, std::uint64_t{i + 1});
    s += ' ';
    append_vertex(s, mesh, i);
    s += '\n';
  }
  s += "$EndNodes\n$Elements\n";
  append(s, std::uint64_t{mesh.nb_tets()} + mesh.nb_triangles());
  s += '\n';
  std::uint64_t number = 1;
  const auto elements = [&](const std::vector<std::uint32_t>& cells, std::size_t per,
                            const std::vector<std::int32_t>& ref, const GmshEntities& entities) {
    for (std::size_t c = 0; c < cells.size() / per; ++c, ++number) {
      append(s, number);
      s += per == 4 ? " 4 2 " : " 2 2 ";  // type, two tags: physical, elementary entity
      append_int(s, tag_of(ref, c));
      s += ' ';
      append(s, entities.entity(tag_of(ref, c)));
      s += ' ';
      append_cell(s, cells, per, c, 1);
      s += '\n';
    }
  };
  elements(mesh.tets, 4, mesh.tet_ref, volumes);
  elements(mesh.triangles, 3, mesh.triangle_ref, surfaces);
  s += "$EndElements\n";
  return s;
}

// MSH 4.1 values, as text (blank-separated, lines ended by eol()) or binary (ints as
// int32, counts and tags as size_t of 8 bytes, doubles; little endian; eol() writes
// nothing).
struct Msh41Out {
  bool binary;
  std::string s;

  void int32(std::int64_t v) {
    if (binary) return put_le<std::int32_t>(s, static_cast<std::int32_t>(v));
    append_int(s, v);
    s += ' ';
  }
  void size(std::uint64_t v) {
    if (binary) return put_le<std::uint64_t>(s, v);
    append(s, v);
    s += ' ';
  }
  void real(double v) {
    if (binary) return put_le<double>(s, v);
    append(s, v);
    s += ' ';
  }
  void eol() {
    if (!binary && !s.empty() && s.back() == ' ') s.back() = '\n';
  }
  // The $End line of a section (binary data is followed by a line break first).
  void end(const char* name) {
    if (binary) s += '\n';
    s += name;
    s += '\n';
  }
};

// Surface entities for the triangle tags, volume entities for the tet tags, each entity's
// box the mesh's bounding box (a valid, if loose, bound); each node on the entity of lowest
// dimension that holds it, as Gmsh classifies nodes (so that gmsh.model.mesh.getNodes(2,
// tag) finds a patch's nodes): a corner of triangles on the surface entity of the lowest
// tag among them (Gmsh would put a node where two patches meet on a curve between them;
// there are no curve entities here), any other node on the volume entity of its first tet
// (entity 1 for a node of no tet); node blocks are the runs of consecutive nodes on one
// entity, so that the nodes keep their order, tags 1..n; element blocks: runs of equal
// tags, tets first.
std::string gmsh41_file(const TetMeshInput& mesh, bool binary) {
  const GmshEntities volumes(mesh.tet_ref, mesh.nb_tets(), true);
  const GmshEntities surfaces(mesh.triangle_ref, mesh.nb_triangles(), false);
  // Physical groups for every entity, tag 0 included, as soon as one tag is not 0 (meshio
  // wants one physical tag per element or none at all); none otherwise.
  const auto nonzero = [](std::int32_t t) { return t != 0; };
  const bool physical = std::any_of(mesh.tet_ref.begin(), mesh.tet_ref.end(), nonzero) ||
                        std::any_of(mesh.triangle_ref.begin(), mesh.triangle_ref.end(), nonzero);
  double box[6] = {0, 0, 0, 0, 0, 0};  // lo, hi
  for (std::size_t i = 0; i < mesh.nb_vertices(); ++i) {
    for (std::size_t k = 0; k < 3; ++k) {
      const double x = mesh.xyz[3 * i + k];
      box[k] = i == 0 ? x : std::min(box[k], x);
      box[k + 3] = i == 0 ? x : std::max(box[k + 3], x);
    }
  }
  const std::uint64_t nv = mesh.nb_vertices();
  const std::uint64_t ne = std::uint64_t{mesh.nb_tets()} + mesh.nb_triangles();
  Msh41Out out{binary, std::string("$MeshFormat\n4.1 ") + (binary ? "1" : "0") + " 8\n"};
  if (binary) out.int32(1);  // tells the byte order
  out.end("$EndMeshFormat");
  out.s += gmsh_physical_names(mesh) + "$Entities\n";
  for (const std::uint64_t count :
       {std::uint64_t{0}, std::uint64_t{0}, std::uint64_t{surfaces.tags.size()},
        std::uint64_t{volumes.tags.size()}}) {
    out.size(count);
  }
  out.eol();
  for (const GmshEntities* entities : {&surfaces, &volumes}) {
    for (std::size_t e = 0; e < entities->tags.size(); ++e) {
      out.int32(static_cast<std::int64_t>(e + 1));
      for (const double x : box) out.real(x);
      out.size(physical ? 1 : 0);
      if (physical) out.int32(entities->tags[e]);
      out.size(0);  // no bounding entities
      out.eol();
    }
  }
  out.end("$EndEntities");
  // Per node: its entity's dimension and number (0: none yet).
  std::vector<std::uint8_t> node_dim(nv, 3);
  std::vector<std::uint64_t> node_entity(nv, 0);
  for (std::size_t t = 0; t < mesh.nb_tets(); ++t) {
    for (std::size_t k = 0; k < 4; ++k) {
      std::uint64_t& e = node_entity[mesh.tets[4 * t + k]];
      if (e == 0) e = volumes.entity(tag_of(mesh.tet_ref, t));
    }
  }
  for (std::size_t c = 0; c < mesh.nb_triangles(); ++c) {
    const std::uint64_t e = surfaces.entity(tag_of(mesh.triangle_ref, c));
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t v = mesh.triangles[3 * c + k];
      if (node_dim[v] == 3 || e < node_entity[v]) node_entity[v] = e;
      node_dim[v] = 2;
    }
  }
  for (std::uint64_t& e : node_entity) e = std::max<std::uint64_t>(e, 1);
  const auto node_runs = [&](auto block) {
    for (std::uint64_t begin = 0, end = 0; begin < nv; begin = end) {
      for (end = begin + 1;
           end < nv && node_dim[end] == node_dim[begin] && node_entity[end] == node_entity[begin];
           ++end) {
      }
      block(begin, end);
    }
  };
  std::uint64_t nb_node_blocks = 0;
  node_runs([&](std::uint64_t, std::uint64_t) { ++nb_node_blocks; });
  out.s += "$Nodes\n";
  for (const std::uint64_t v : {nb_node_blocks, nv, std::uint64_t{nv == 0 ? 0u : 1u}, nv})
    out.size(v);
  out.eol();
  node_runs([&](std::uint64_t begin, std::uint64_t end) {
    out.int32(node_dim[begin]);
    out.int32(static_cast<std::int64_t>(node_entity[begin]));
    out.int32(0);
    out.size(end - begin);
    out.eol();
    for (std::uint64_t i = begin; i < end; ++i) {
      out.size(i + 1);
      out.eol();
    }
    for (std::uint64_t i = begin; i < end; ++i) {
      for (std::size_t k = 0; k < 3; ++k) out.real(mesh.xyz[3 * i + k]);
      out.eol();
    }
  });
  out.end("$EndNodes");
  out.s += "$Elements\n";
  std::uint64_t nb_blocks = 0;
  const auto runs = [&](const std::vector<std::int32_t>& ref, std::size_t n, auto block) {
    for (std::size_t begin = 0, end = 0; begin < n; begin = end) {
      const std::int32_t tag = tag_of(ref, begin);
      for (end = begin + 1; end < n && tag_of(ref, end) == tag; ++end) {
      }
      block(tag, begin, end);
    }
  };
  const auto count_block = [&](std::int32_t, std::size_t, std::size_t) { ++nb_blocks; };
  runs(mesh.tet_ref, mesh.nb_tets(), count_block);
  runs(mesh.triangle_ref, mesh.nb_triangles(), count_block);
  for (const std::uint64_t v : {nb_blocks, ne, std::uint64_t{ne == 0 ? 0u : 1u}, ne}) out.size(v);
  out.eol();
  std::uint64_t number = 1;
  const auto elements = [&](const std::vector<std::uint32_t>& cells, std::size_t per,
                            const std::vector<std::int32_t>& ref, const GmshEntities& entities) {
    runs(ref, cells.size() / per, [&](std::int32_t tag, std::size_t begin, std::size_t end) {
      out.int32(per == 4 ? 3 : 2);
      out.int32(static_cast<std::int64_t>(entities.entity(tag)));
      out.int32(per == 4 ? 4 : 2);
      out.size(end - begin);
      out.eol();
      for (std::size_t c = begin; c < end; ++c, ++number) {
        out.size(number);
        for (std::size_t k = 0; k < per; ++k) out.size(std::uint64_t{cells[per * c + k]} + 1);
        out.eol();
      }
    });
  };
  elements(mesh.tets, 4, mesh.tet_ref, volumes);
  elements(mesh.triangles, 3, mesh.triangle_ref, surfaces);
  out.end("$EndElements");
  return out.s;
}

// Legacy VTK: tets then triangles, cell data cell_id, region, patch (as TetMeshFormat::kVtk).
std::string vtk_text(const TetMeshInput& mesh) {
  const std::uint64_t nt = mesh.nb_tets(), nf = mesh.nb_triangles(), n = nt + nf;
  // The title is one line of at most 255 characters.
  std::string title = mesh.source.empty() ? "voroclip tetrahedral mesh" : mesh.source;
  if (title.size() > 255) title.resize(255);
  for (char& c : title) {
    if (static_cast<unsigned char>(c) < 0x20) c = ' ';
  }
  std::string s = "# vtk DataFile Version 3.0\n" + title +
                  "\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS " +
                  std::to_string(mesh.nb_vertices()) + " double\n";
  for (std::size_t i = 0; i < mesh.nb_vertices(); ++i) {
    append_vertex(s, mesh, i);
    s += '\n';
  }
  s += "CELLS " + std::to_string(n) + " " + std::to_string(5 * nt + 4 * nf) + "\n";
  for (std::size_t t = 0; t < nt; ++t) {
    s += "4 ";
    append_cell(s, mesh.tets, 4, t, 0);
    s += '\n';
  }
  for (std::size_t f = 0; f < nf; ++f) {
    s += "3 ";
    append_cell(s, mesh.triangles, 3, f, 0);
    s += '\n';
  }
  s += "CELL_TYPES " + std::to_string(n) + "\n";
  for (std::size_t c = 0; c < n; ++c) s += c < nt ? "10\n" : "5\n";
  s += "CELL_DATA " + std::to_string(n) + "\nSCALARS cell_id int 1\nLOOKUP_TABLE default\n";
  for (std::uint64_t c = 0; c < n; ++c) {
    append(s, c);
    s += '\n';
  }
  if (!mesh.tet_ref.empty()) {
    s += "SCALARS region int 1\nLOOKUP_TABLE default\n";
    for (std::size_t c = 0; c < n; ++c) {
      append_int(s, c < nt ? mesh.tet_ref[c] : 0);
      s += '\n';
    }
  }
  if (!mesh.triangle_ref.empty()) {
    s += "SCALARS patch int 1\nLOOKUP_TABLE default\n";
    for (std::size_t c = 0; c < n; ++c) {
      append_int(s, c < nt ? 0 : mesh.triangle_ref[c - nt]);
      s += '\n';
    }
  }
  return s;
}

void check_mesh_arrays(const std::string& path, const TetMeshInput& mesh) {
  const std::string what = "cannot write '" + path + "': ";
  if (mesh.xyz.size() % 3 != 0 || mesh.tets.size() % 4 != 0 || mesh.triangles.size() % 3 != 0) {
    throw Error(what + "the mesh arrays hold " + std::to_string(mesh.xyz.size()) +
                " coordinates, " + std::to_string(mesh.tets.size()) + " tet indices and " +
                std::to_string(mesh.triangles.size()) +
                " triangle indices (multiples of 3, 4 and 3 needed)");
  }
  const auto check_cells = [&](const std::vector<std::uint32_t>& cells, std::size_t per,
                               const char* name) {
    for (std::size_t i = 0; i < cells.size(); ++i) {
      if (cells[i] >= mesh.nb_vertices()) {
        throw Error(what + name + " " + std::to_string(i / per) + " has vertex " +
                    std::to_string(cells[i]) + ", the mesh has " +
                    std::to_string(mesh.nb_vertices()) + " vertices");
      }
    }
  };
  check_cells(mesh.tets, 4, "tet");
  check_cells(mesh.triangles, 3, "triangle");
  const auto check_tags = [&](const std::vector<std::int32_t>& ref, std::size_t n, const char* name,
                              const char* cell) {
    if (!ref.empty() && ref.size() != n) {
      throw Error(what + name + " has " + std::to_string(ref.size()) + " tags for " +
                  std::to_string(n) + " " + cell + "s (empty, or one tag per " + cell + ")");
    }
  };
  check_tags(mesh.tet_ref, mesh.nb_tets(), "tet_ref", "tet");
  check_tags(mesh.triangle_ref, mesh.nb_triangles(), "triangle_ref", "triangle");
}

// Gmsh physical tags: positive (Gmsh reads a negative one as its absolute value), 0 for
// none; names in double quotes on one line.
void check_gmsh_tags(const std::string& path, const TetMeshInput& mesh) {
  const std::string what = "cannot write '" + path + "' (Gmsh): ";
  const auto check = [&](const std::vector<std::int32_t>& ref, const char* name) {
    for (std::size_t i = 0; i < ref.size(); ++i) {
      if (ref[i] < 0) {
        throw Error(what + name + " " + std::to_string(i) + " has the tag " +
                    std::to_string(ref[i]) + ": physical tags are positive (0: none)");
      }
    }
  };
  check(mesh.tet_ref, "tet");
  check(mesh.triangle_ref, "triangle");
  for (const TetMeshInput::TagName& n : mesh.tag_names) {
    const std::string name =
        "the name of tag " + std::to_string(n.tag) + " of dimension " + std::to_string(n.dimension);
    if (n.dimension < 0 || n.dimension > 3) throw Error(what + name + ": dimension 0 to 3");
    if (n.tag <= 0) throw Error(what + name + ": physical tags are positive");
    if (n.name.find_first_of("\"\r\n") != std::string::npos) {
      throw Error(what + name + ": a name cannot hold '\"' or a line break");
    }
  }
}

// Throws unless `path` has the extension of a single-file format (not TetGen's).
void check_tet_mesh_extension(const std::string& path) {
  const std::string ext = input_extension_of(path);
  if (ext == ".mesh" || ext == ".msh" || ext == ".vtk" || ext == ".vtu") return;
  if (ext == ".node" || ext == ".ele") {  // (NAME.node.gz: plain ones are read before this)
    throw Error(path +
                ": TetGen's files (.node, .ele, .face) are read uncompressed: "
                "decompress them (gunzip)");
  }
  if (ext == ".meshb") {
    throw Error(path + ": binary Medit files (.meshb) are not read: convert to ASCII .mesh");
  }
  check_not_gzip_name(path);
  throw Error(path + ": unknown tetrahedral mesh format " +
              (ext.empty() ? std::string("(no extension)") : "'" + ext + "'") +
              ": expected .mesh, .node/.ele, .msh, .vtk or .vtu");
}

// The single-file formats, from the file's bytes (`path` names it and its extension,
// checked by check_tet_mesh_extension, tells the format).
TetMeshInput read_tet_mesh_text(const std::string& path, std::string text) {
  prepare_input(path, text);
  const std::string ext = input_extension_of(path);
  if (ext == ".mesh") return read_medit(path, std::move(text));
  if (ext == ".msh") return read_gmsh(path, std::move(text));
  if (ext == ".vtk") return read_vtk(path, std::move(text));
  return read_vtu_tet_mesh(path, std::move(text));
}

}  // namespace

TetMeshInput read_tet_mesh(const std::string& path) {
  check_not_directory(path);
  const std::string ext = extension_of(path);
  if (ext == ".node" || ext == ".ele") {
    const std::string base = without_extension(path);
    // Both files are opened before either is parsed: a missing one is reported first.
    std::string node_text = read_whole_file(base + ".node");
    std::string ele_text = read_whole_file(base + ".ele");
    const std::string face_path = base + ".face";
    if (std::ifstream(face_path, std::ios::binary)) {
      std::string face_text = read_whole_file(face_path);
      return read_tetgen(base, std::move(node_text), std::move(ele_text), &face_text);
    }
    return read_tetgen(base, std::move(node_text), std::move(ele_text), nullptr);
  }
  check_tet_mesh_extension(path);
  return read_tet_mesh_text(path, read_whole_file(path));
}

TetMeshInput read_tet_mesh(std::istream& in, const std::string& name) {
  const std::string ext = extension_of(name);
  if (ext == ".node" || ext == ".ele") {
    throw Error(name + ": a TetGen mesh is several files: read it with read_tetgen_mesh");
  }
  check_tet_mesh_extension(name);
  return read_tet_mesh_text(name, read_whole_stream(in, name));
}

TetMeshInput read_tetgen_mesh(std::istream& node, std::istream& ele, std::istream* face,
                              const std::string& base) {
  std::string node_text = read_whole_stream(node, base + ".node");
  std::string ele_text = read_whole_stream(ele, base + ".ele");
  if (face != nullptr) {
    std::string face_text = read_whole_stream(*face, base + ".face");
    return read_tetgen(base, std::move(node_text), std::move(ele_text), &face_text);
  }
  return read_tetgen(base, std::move(node_text), std::move(ele_text), nullptr);
}

void write_tet_mesh(const std::string& path, const TetMeshInput& mesh, TetMeshFormat format) {
  write_tet_mesh(path, mesh, format, {});
}

void write_tet_mesh(const std::string& path, const TetMeshInput& mesh, TetMeshFormat format,
                    const std::vector<VtuCellField>& fields) {
  check_mesh_arrays(path, mesh);
  const bool vtu = format == TetMeshFormat::kVtu || format == TetMeshFormat::kVtuAscii ||
                   format == TetMeshFormat::kVtuCompressed;
  if (!fields.empty() && !vtu) {
    throw Error("cannot write '" + path + "': per-cell fields go to a .vtu file only");
  }
  switch (format) {
    case TetMeshFormat::kMedit:
      write_text(path, medit_text(mesh));
      return;
    case TetMeshFormat::kTetGen: {
      // The three files appear together or not at all.
      const std::vector<std::string> paths = tet_mesh_files(path, format);
      const std::string texts[3] = {tetgen_node_text(mesh),
                                    tetgen_cells_text(mesh.tets, 4, mesh.tet_ref),
                                    tetgen_cells_text(mesh.triangles, 3, mesh.triangle_ref)};
      std::vector<FileWriter> files;
      for (std::size_t k = 0; k < 3; ++k) {
        files.push_back({paths[k], [&texts, k](std::ostream& out) {
                           out.write(texts[k].data(),
                                     static_cast<std::streamsize>(texts[k].size()));
                         }});
      }
      write_files_atomically(files);
      return;
    }
    case TetMeshFormat::kGmsh22:
      check_gmsh_tags(path, mesh);
      write_text(path, gmsh22_text(mesh));
      return;
    case TetMeshFormat::kGmsh41:
    case TetMeshFormat::kGmsh41Binary:
      check_gmsh_tags(path, mesh);
      write_text(path, gmsh41_file(mesh, format == TetMeshFormat::kGmsh41Binary));
      return;
    case TetMeshFormat::kVtu:
    case TetMeshFormat::kVtuAscii:
    case TetMeshFormat::kVtuCompressed:
      write_file_atomically(path, [&](std::ostream& out) {
        const std::size_t nt = mesh.nb_tets(), nf = mesh.nb_triangles();
        std::vector<VtuCellBlock> blocks = {{mesh.tets.data(), nt, 4}};
        if (nf > 0) blocks.push_back({mesh.triangles.data(), nf, 3});
        std::vector<VtuCellTags> tags;
        if (!mesh.tet_ref.empty()) {
          tags.push_back({"region", mesh.tet_ref});
          tags.back().values.resize(nt + nf, 0);
        }
        if (!mesh.triangle_ref.empty()) {
          tags.push_back({"patch", std::vector<std::int32_t>(nt, 0)});
          tags.back().values.insert(tags.back().values.end(), mesh.triangle_ref.begin(),
                                    mesh.triangle_ref.end());
        }
        write_vtu(out, mesh.xyz.data(), mesh.nb_vertices(), 3, blocks,
                  format == TetMeshFormat::kVtuAscii        ? VtuEncoding::kAscii
                  : format == TetMeshFormat::kVtuCompressed ? VtuEncoding::kZlibBase64
                                                            : VtuEncoding::kBase64,
                  fields, tags);
      });
      return;
    case TetMeshFormat::kVtk:
      write_text(path, vtk_text(mesh));
      return;
  }
  throw Error("cannot write '" + path + "': unknown format");
}

std::vector<std::string> tet_mesh_files(const std::string& path, TetMeshFormat format) {
  if (format != TetMeshFormat::kTetGen) return {path};
  const std::string base = without_extension(path);
  return {base + ".node", base + ".ele", base + ".face"};
}

void write_tet_mesh(const std::string& path, const TetMeshInput& mesh) {
  const std::string ext = extension_of(path);
  if (ext == ".mesh") return write_tet_mesh(path, mesh, TetMeshFormat::kMedit);
  if (ext == ".node" || ext == ".ele") return write_tet_mesh(path, mesh, TetMeshFormat::kTetGen);
  if (ext == ".msh") return write_tet_mesh(path, mesh, TetMeshFormat::kGmsh41);
  if (ext == ".vtk") return write_tet_mesh(path, mesh, TetMeshFormat::kVtk);
  if (ext == ".vtu") return write_tet_mesh(path, mesh, TetMeshFormat::kVtu);
  throw Error("cannot write '" + path + "': unknown tetrahedral mesh format " +
              (ext.empty() ? std::string("(no extension)") : "'" + ext + "'") +
              ": expected .mesh, .node/.ele, .msh, .vtk or .vtu");
}

}  // namespace voroclip
