// Tetrahedral mesh files: Medit .mesh, TetGen .node/.ele, Gmsh .msh (2.2 and 4.1) and
// legacy VTK, read into a TetMeshInput and written from one.
//
// Reading. The whole file is read into memory and split into blank-separated tokens by
// Lexer (text_lexer.h), which keeps the line of each token for messages and parses numbers with
// std::from_chars (locale-independent, correctly rounded). A counted section (n entries
// announced by a header) that meets the end of the file, or a keyword, before its n-th
// entry is reported as truncated with the counts expected and found. Tetrahedra are
// collected with their vertex numbers as the file writes them (RawTets) and checked against
// the file's vertex numbering once the whole file is read: Medit and TetGen number from a
// base (1, or TetGen's first node number), VTK from 0, Gmsh by arbitrary node tags.
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
#include <limits>
#include <ostream>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <unordered_map>
#include <utility>
#include <vector>

#include "text_lexer.h"
#include "voroclip/core.h"

namespace voroclip {

namespace {

using namespace detail;  // NOLINT: the shared tokenizer and helpers of text_lexer.h

constexpr std::uint64_t kMaxVertices = std::numeric_limits<std::uint32_t>::max();

// Tetrahedra as the file numbers their vertices, with what a message needs.
struct RawTets {
  std::vector<std::uint64_t> v;      // 4 per tet
  std::vector<std::uint32_t> line;   // per tet
  std::vector<std::uint64_t> label;  // per tet: its number as the file knows it
  const char* what = "tetrahedron";  // how the format calls a tet: "element", "cell"

  void push(std::uint64_t label_in, std::uint32_t line_in, const std::uint64_t idx[4]) {
    v.insert(v.end(), idx, idx + 4);
    line.push_back(line_in);
    label.push_back(label_in);
  }
  std::size_t size() const { return line.size(); }
};

// Vertex numbers base .. base + nb_vertices - 1 (Medit, TetGen, VTK).
void finish_tets(const std::string& path, const RawTets& raw, std::uint64_t base,
                 TetMeshInput& mesh) {
  const std::uint64_t nv = mesh.nb_vertices();
  mesh.tets.resize(raw.v.size());
  for (std::size_t t = 0; t < raw.size(); ++t) {
    for (std::size_t k = 0; k < 4; ++k) {
      const std::uint64_t i = raw.v[4 * t + k];
      if (i < base || i - base >= nv) {
        fail_at(path, raw.line[t],
                std::string(raw.what) + " " + std::to_string(raw.label[t]) + ": vertex " +
                    std::to_string(i) + " is out of range " +
                    (nv == 0 ? std::string("(the file has no vertices)")
                             : std::to_string(base) + ".." + std::to_string(base + nv - 1)));
      }
      mesh.tets[4 * t + k] = static_cast<std::uint32_t>(i - base);
    }
  }
  mesh.tet_line = raw.line;
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
      {"triangles", 4},
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
      {"trianglesp2", 7},
      {"tetrahedrap2", 11},
  };
  for (const auto& s : kSizes) {
    if (kw == s.first) return s.second;
  }
  return 0;
}

TetMeshInput read_medit(const std::string& path) {
  Lexer lx(path, read_whole_file(path), '#');
  TetMeshInput mesh;
  mesh.source = path;
  RawTets raw;
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
    } else if (kw == "tetrahedra") {
      Section s{"Tetrahedra", "tetrahedra", to_uint(lx, header_token(lx, "Tetrahedra"), "count")};
      tets_section = true;
      raw.v.reserve(4 * reserve_for(lx, s.expected));
      for (; s.found < s.expected; ++s.found) {
        std::uint64_t idx[4];
        idx[0] = entry_uint(lx, s, "vertex index");
        const std::uint32_t line = lx.line();
        for (int k = 1; k < 4; ++k) idx[k] = entry_uint(lx, s, "vertex index");
        entry_token(lx, s);  // reference
        raw.push(s.found + 1, line, idx);
      }
    } else if (const int size = medit_skipped_section_size(kw); size > 0) {
      Section s{std::string(t), "entries", to_uint(lx, header_token(lx, std::string(t)), "count")};
      for (; s.found < s.expected; ++s.found) {
        for (int k = 0; k < size; ++k) entry_token(lx, s);
      }
    } else {
      lx.fail("unknown Medit keyword " + quote(t));
    }
  }
  if (raw.size() == 0) {
    throw Error(path + (tets_section ? ": the Tetrahedra section is empty"
                                     : ": no tetrahedra (no Tetrahedra section)"));
  }
  finish_tets(path, raw, 1, mesh);
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

TetMeshInput read_tetgen(const std::string& base) {
  TetMeshInput mesh;
  std::uint64_t first_node = 0;
  // Both files are opened before either is parsed: a missing one is reported first.
  std::string node_text = read_whole_file(base + ".node");
  std::string ele_text = read_whole_file(base + ".ele");
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
  RawTets raw;
  raw.v.reserve(4 * reserve_for(lx, n));
  Section s{"tetrahedra", "tetrahedra", n};
  for (; s.found < n; ++s.found) {
    const std::uint64_t index = to_uint(lx, entry_token(lx, s), "tetrahedron number");
    const std::uint32_t line = lx.line();
    const std::string entry = "tetrahedron " + std::to_string(index);
    std::uint64_t idx[4];
    for (std::size_t k = 1; k < per_line; ++k) {
      const std::string_view t = line_field(lx, entry, per_line, k);
      if (k <= 4) {
        idx[k - 1] = to_uint(lx, t, "node number");
      } else if (k <= per_tet) {
        to_uint(lx, t, "node number");
      } else {
        to_double(lx, t);
      }
    }
    lx.skip_line();
    raw.push(index, line, idx);
  }
  if (raw.size() == 0) throw Error(mesh.source + ": no tetrahedra");
  finish_tets(mesh.source, raw, first_node, mesh);
  return mesh;
}

// ---------------------------------------------------------------------------------------
// Gmsh .msh, ASCII 2.x (2.2) and 4.1. Sections "$Name" ... "$EndName"; unknown sections
// (and $Entities, $PhysicalNames...) are read past. Nodes are identified by tags, which
// need not be contiguous; elements of type 4 are 4-node tetrahedra.

constexpr std::uint64_t kGmshTet = 4;

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

// $Elements, format 2: count, then "tag type ntags tag... node..." per element.
void read_gmsh2_elements(Lexer& lx, RawTets& raw) {
  Section s{"$Elements", "elements", to_uint(lx, header_token(lx, "$Elements"), "count")};
  for (; s.found < s.expected; ++s.found) {
    const std::uint64_t tag = entry_uint(lx, s, "element tag");
    const std::uint32_t line = lx.line();
    const std::uint64_t type = entry_uint(lx, s, "element type");
    if (type != kGmshTet) {
      lx.skip_line();
      continue;
    }
    const std::uint64_t ntags = entry_uint(lx, s, "tag count");
    for (std::uint64_t k = 0; k < ntags; ++k) entry_token(lx, s);
    std::uint64_t idx[4];
    for (auto& i : idx) i = entry_uint(lx, s, "node tag");
    lx.skip_line();
    raw.push(tag, line, idx);
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
// "tag node...".
void read_gmsh4_elements(Lexer& lx, RawTets& raw) {
  const std::uint64_t blocks = to_uint(lx, header_token(lx, "$Elements"), "block count");
  Section s{"$Elements", "elements", to_uint(lx, header_token(lx, "$Elements"), "count")};
  to_uint(lx, header_token(lx, "$Elements"), "element tag");
  to_uint(lx, header_token(lx, "$Elements"), "element tag");
  for (std::uint64_t b = 0; b < blocks; ++b) {
    entry_uint(lx, s, "entity dimension");
    entry_uint(lx, s, "entity tag");
    const std::uint64_t type = entry_uint(lx, s, "element type");
    const std::uint64_t in_block = entry_uint(lx, s, "element count");
    if (in_block > s.expected - s.found) {
      lx.fail("section $Elements: a block of " + std::to_string(in_block) + " elements after " +
              std::to_string(s.found) + " of " + std::to_string(s.expected) + " elements");
    }
    for (std::uint64_t i = 0; i < in_block; ++i, ++s.found) {
      const std::uint64_t tag = entry_uint(lx, s, "element tag");
      const std::uint32_t line = lx.line();
      if (type == kGmshTet) {
        std::uint64_t idx[4];
        for (auto& n : idx) n = entry_uint(lx, s, "node tag");
        raw.push(tag, line, idx);
      }
      lx.skip_line();
    }
  }
  if (s.found != s.expected) {
    lx.fail("section $Elements: its blocks hold " + std::to_string(s.found) +
            " elements, the header " + std::to_string(s.expected));
  }
  expect_gmsh_end(lx, s, "$EndElements");
}

// Node tags to vertex indices: a direct table when the tags are dense enough (the usual
// 1..n), a hash map otherwise.
void finish_gmsh(const std::string& path, const GmshNodes& nodes, const RawTets& raw,
                 TetMeshInput& mesh) {
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
      fail_at(path, nodes.line[i],
              "node tag " + std::to_string(tag) + " is repeated (first at line " +
                  std::to_string(nodes.line[first]) + ")");
    }
  }
  mesh.tets.resize(raw.v.size());
  for (std::size_t t = 0; t < raw.size(); ++t) {
    for (std::size_t k = 0; k < 4; ++k) {
      const std::uint64_t tag = raw.v[4 * t + k];
      std::uint32_t index = kAbsent;
      if (dense) {
        if (tag <= max_tag) index = table[static_cast<std::size_t>(tag)];
      } else if (const auto it = map.find(tag); it != map.end()) {
        index = it->second;
      }
      if (index == kAbsent) {
        fail_at(path, raw.line[t],
                "element " + std::to_string(raw.label[t]) + ": node " + std::to_string(tag) +
                    (n == 0 ? std::string(" does not exist (the file has no nodes)")
                            : " is not in section $Nodes"));
      }
      mesh.tets[4 * t + k] = index;
    }
  }
  mesh.tet_line = raw.line;
}

TetMeshInput read_gmsh(const std::string& path) {
  Lexer lx(path, read_whole_file(path), 0);
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
  if (file_type != "0") {
    lx.fail("binary Gmsh file (file-type " + quote(file_type) +
            "): only ASCII .msh is read (save it with Mesh.Binary = 0)");
  }
  {
    const std::string_view t = lx.next();
    if (t != "$EndMeshFormat") {
      lx.fail("expected $EndMeshFormat, found " +
              (t.empty() ? std::string("the end of the file") : quote(t)));
    }
  }
  GmshNodes nodes;
  RawTets raw;
  raw.what = "element";
  bool have_nodes = false, have_elements = false;
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
        read_gmsh2_elements(lx, raw);
      } else {
        read_gmsh4_elements(lx, raw);
      }
    } else {
      skip_gmsh_section(lx, t);
    }
  }
  if (raw.size() == 0) {
    throw Error(path + (have_elements ? ": no tetrahedra (element type 4) in $Elements"
                                      : ": no tetrahedra (no $Elements section)"));
  }
  finish_gmsh(path, nodes, raw, mesh);
  return mesh;
}

// ---------------------------------------------------------------------------------------
// Legacy VTK (.vtk), ASCII, DATASET UNSTRUCTURED_GRID: POINTS, CELLS (the classic layout
// "n i0 .. i(n-1)" per cell, or the VTK 5.1 layout OFFSETS + CONNECTIVITY), CELL_TYPES;
// cells of type 10 (VTK_TETRA) are kept. Reading stops at POINT_DATA / CELL_DATA / FIELD.

constexpr std::uint64_t kVtkTetra = 10;

TetMeshInput read_vtk(const std::string& path) {
  Lexer lx(path, read_whole_file(path), 0);
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
    if (lower(format) == "binary") lx.fail("binary VTK file: only ASCII legacy .vtk is read");
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
                std::to_string(cell_line.size()) + " cells");
      }
      for (; s.found < s.expected; ++s.found) cell_type.push_back(entry_uint(lx, s, "cell type"));
      have_types = true;
    } else if (kw == "metadata") {
      lx.skip_to_blank_line();
    } else if (kw == "point_data" || kw == "cell_data" || kw == "field") {
      break;
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
  RawTets raw;
  raw.what = "cell";
  for (std::size_t c = 0; c < cell_type.size(); ++c) {
    if (cell_type[c] != kVtkTetra) continue;
    const std::uint64_t k = cell_begin[c + 1] - cell_begin[c];
    if (k != 4) {
      fail_at(path, cell_line[c],
              "cell " + std::to_string(c) + " of type 10 (tetra) has " + std::to_string(k) +
                  " points, not 4");
    }
    raw.push(c, cell_line[c], cell_index.data() + cell_begin[c]);
  }
  if (raw.size() == 0) throw Error(path + ": no tetrahedra (cell type 10)");
  finish_tets(path, raw, 0, mesh);
  return mesh;
}

// ---------------------------------------------------------------------------------------
// Writers.

// Vertex i as "x y z" (shortest round-trip decimals).
void append_vertex(std::string& out, const TetMeshInput& mesh, std::size_t i) {
  append(out, mesh.xyz[3 * i]);
  out += ' ';
  append(out, mesh.xyz[3 * i + 1]);
  out += ' ';
  append(out, mesh.xyz[3 * i + 2]);
}

// Tet t as "a b c d", vertex numbers from `base`.
void append_tet(std::string& out, const TetMeshInput& mesh, std::size_t t, std::uint64_t base) {
  for (std::size_t k = 0; k < 4; ++k) {
    if (k > 0) out += ' ';
    append(out, mesh.tets[4 * t + k] + base);
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
  s += "Tetrahedra\n";
  append(s, std::uint64_t{mesh.nb_tets()});
  s += '\n';
  for (std::size_t t = 0; t < mesh.nb_tets(); ++t) {
    append_tet(s, mesh, t, 1);
    s += " 0\n";
  }
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

std::string tetgen_ele_text(const TetMeshInput& mesh) {
  std::string s;
  append(s, std::uint64_t{mesh.nb_tets()});
  s += " 4 0\n";
  for (std::size_t t = 0; t < mesh.nb_tets(); ++t) {
    append(s, std::uint64_t{t + 1});
    s += ' ';
    append_tet(s, mesh, t, 1);
    s += '\n';
  }
  return s;
}

std::string gmsh22_text(const TetMeshInput& mesh) {
  std::string s = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n";
  append(s, std::uint64_t{mesh.nb_vertices()});
  s += '\n';
  for (std::size_t i = 0; i < mesh.nb_vertices(); ++i) {
    append(s, std::uint64_t{i + 1});
    s += ' ';
    append_vertex(s, mesh, i);
    s += '\n';
  }
  s += "$EndNodes\n$Elements\n";
  append(s, std::uint64_t{mesh.nb_tets()});
  s += '\n';
  for (std::size_t t = 0; t < mesh.nb_tets(); ++t) {
    append(s, std::uint64_t{t + 1});
    s += " 4 2 0 1 ";  // type 4, two tags: physical 0, elementary entity 1
    append_tet(s, mesh, t, 1);
    s += '\n';
  }
  s += "$EndElements\n";
  return s;
}

// One volume entity (tag 1, the bounding box of the vertices) holding every node and tet.
std::string gmsh41_text(const TetMeshInput& mesh) {
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  for (std::size_t i = 0; i < mesh.nb_vertices(); ++i) {
    for (std::size_t k = 0; k < 3; ++k) {
      const double x = mesh.xyz[3 * i + k];
      lo[k] = i == 0 ? x : std::min(lo[k], x);
      hi[k] = i == 0 ? x : std::max(hi[k], x);
    }
  }
  const std::uint64_t nv = mesh.nb_vertices(), nt = mesh.nb_tets();
  std::string s = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n0 0 0 1\n1";
  for (const double x : {lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]}) {
    s += ' ';
    append(s, x);
  }
  s += " 0 0\n$EndEntities\n$Nodes\n";
  s += "1 " + std::to_string(nv) + " 1 " + std::to_string(nv) + "\n3 1 0 " + std::to_string(nv) +
       "\n";
  for (std::uint64_t i = 0; i < nv; ++i) {
    append(s, i + 1);
    s += '\n';
  }
  for (std::size_t i = 0; i < nv; ++i) {
    append_vertex(s, mesh, i);
    s += '\n';
  }
  s += "$EndNodes\n$Elements\n";
  s += "1 " + std::to_string(nt) + " 1 " + std::to_string(nt) + "\n3 1 4 " + std::to_string(nt) +
       "\n";
  for (std::size_t t = 0; t < nt; ++t) {
    append(s, std::uint64_t{t + 1});
    s += ' ';
    append_tet(s, mesh, t, 1);
    s += '\n';
  }
  s += "$EndElements\n";
  return s;
}

void check_mesh_arrays(const std::string& path, const TetMeshInput& mesh) {
  if (mesh.xyz.size() % 3 != 0 || mesh.tets.size() % 4 != 0) {
    throw Error("cannot write '" + path + "': the mesh arrays hold " +
                std::to_string(mesh.xyz.size()) + " coordinates and " +
                std::to_string(mesh.tets.size()) + " tet indices (multiples of 3 and 4 needed)");
  }
  for (std::size_t i = 0; i < mesh.tets.size(); ++i) {
    if (mesh.tets[i] >= mesh.nb_vertices()) {
      throw Error("cannot write '" + path + "': tet " + std::to_string(i / 4) + " has vertex " +
                  std::to_string(mesh.tets[i]) + ", the mesh has " +
                  std::to_string(mesh.nb_vertices()) + " vertices");
    }
  }
}

}  // namespace

TetMeshInput read_tet_mesh(const std::string& path) {
  const std::string ext = extension_of(path);
  if (ext == ".mesh") return read_medit(path);
  if (ext == ".node" || ext == ".ele") return read_tetgen(without_extension(path));
  if (ext == ".msh") return read_gmsh(path);
  if (ext == ".vtk") return read_vtk(path);
  if (ext == ".meshb") {
    throw Error(path + ": binary Medit files (.meshb) are not read: convert to ASCII .mesh");
  }
  if (ext == ".vtu") return read_vtu_tet_mesh(path);
  throw Error(path + ": unknown tetrahedral mesh format " +
              (ext.empty() ? std::string("(no extension)") : "'" + ext + "'") +
              ": expected .mesh, .node/.ele, .msh, .vtk or .vtu");
}

void write_tet_mesh(const std::string& path, const TetMeshInput& mesh, TetMeshFormat format) {
  check_mesh_arrays(path, mesh);
  switch (format) {
    case TetMeshFormat::kMedit:
      write_text(path, medit_text(mesh));
      return;
    case TetMeshFormat::kTetGen: {
      const std::string base = without_extension(path);
      write_text(base + ".node", tetgen_node_text(mesh));
      write_text(base + ".ele", tetgen_ele_text(mesh));
      return;
    }
    case TetMeshFormat::kGmsh22:
      write_text(path, gmsh22_text(mesh));
      return;
    case TetMeshFormat::kGmsh41:
      write_text(path, gmsh41_text(mesh));
      return;
    case TetMeshFormat::kVtu:
    case TetMeshFormat::kVtuAscii:
      write_file_atomically(path, [&](std::ostream& out) {
        write_vtu(out, mesh.xyz.data(), mesh.nb_vertices(), 3, mesh.tets, 4,
                  format == TetMeshFormat::kVtu);
      });
      return;
    case TetMeshFormat::kVtk:
      write_file_atomically(path, [&](std::ostream& out) {
        write_vtk(out, mesh.source.empty() ? "voroclip tetrahedral mesh" : mesh.source,
                  mesh.xyz.data(), mesh.nb_vertices(), 3, mesh.tets, 4);
      });
      return;
  }
  throw Error("cannot write '" + path + "': unknown format");
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
