// VTK XML unstructured grids (.vtu): the writer (ASCII, or binary as base64-encoded
// appended data, zlib-compressed or not) and the reader behind read_tet_mesh for .vtu
// files.
//
// Binary layout (VTK's, not spelled out by its format document): every binary array is a
// header — the array's byte count as UInt32 (header_type="UInt32", the default) or UInt64
// — followed by its bytes, in the file's byte order. Inline ("binary") and appended
// base64 data encode the header and the bytes as one base64 stream or as two (header,
// then bytes, each padded); decoding group by group of 4 characters reads both. An
// appended array's `offset` counts characters (base64) or bytes (raw) after the '_' that
// opens the AppendedData section.
//
// Compressed files (compressor="vtkZLibDataCompressor"; VTK's vtkXMLDataParser and
// vtkXMLWriter): the array's bytes are cut into blocks of a fixed uncompressed size, the
// last one maybe shorter, each compressed on its own as one zlib stream. The header is
// [number of blocks, block size, size of the last block (0: a full block), compressed size
// of each block], each word of header_type, then the compressed blocks one after the
// other; base64 encodes the header and the blocks as one stream or as two. The reader
// checks the header against the bytes that follow, bounds what a block may inflate to by
// deflate's largest ratio, inflates it into memory that grows with what actually comes out
// (not with what the header claims), and checks each block's inflated size against the
// header. Other compressors (LZ4, LZMA) are rejected.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <limits>
#include <ostream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <zlib.h>

#include "binary_io.h"
#include "other_volumes.h"
#include "text_lexer.h"
#include "voroclip/core.h"
#include "vtk_cell_types.h"

namespace voroclip {

namespace {

using namespace detail;  // NOLINT: the shared tokenizer and helpers of text_lexer.h

// Deflate's largest compression factor (zlib's documentation, "Maximum compression
// factor": 1032:1), which bounds what a compressed block can inflate to before inflating.
constexpr std::uint64_t kZlibMaxRatio = 1032;

// The uncompressed size of the blocks write_vtu compresses (VTK's default too).
constexpr std::size_t kVtuBlockSize = 32768;

constexpr char kBase64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

void base64_append(std::string& out, const unsigned char* data, std::size_t n) {
  std::size_t i = 0;
  for (; i + 3 <= n; i += 3) {
    const std::uint32_t v = (std::uint32_t{data[i]} << 16) | (std::uint32_t{data[i + 1]} << 8) |
                            std::uint32_t{data[i + 2]};
    for (int s = 18; s >= 0; s -= 6) out += kBase64[(v >> s) & 63];
  }
  if (i < n) {
    const std::uint32_t v =
        (std::uint32_t{data[i]} << 16) | (i + 1 < n ? std::uint32_t{data[i + 1]} << 8 : 0u);
    out += kBase64[(v >> 18) & 63];
    out += kBase64[(v >> 12) & 63];
    out += i + 1 < n ? kBase64[(v >> 6) & 63] : '=';
    out += '=';
  }
}

bool machine_big_endian() {
  const std::uint16_t one = 1;
  unsigned char first = 0;
  std::memcpy(&first, &one, 1);
  return first == 0;
}

template <class T>
void put_le(std::vector<unsigned char>& out, T v) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (machine_big_endian()) std::reverse(b, b + sizeof(T));
  out.insert(out.end(), b, b + sizeof(T));
}

// One data array of the file being written.
struct OutArray {
  std::string type, name;
  int components = 1;
  std::vector<unsigned char> bytes;  // little endian (binary)
  std::string ascii;                 // values (ASCII)
};

// A zlib-compressed array as VTK lays it out (see the top of the file), UInt64 header
// words, base64-encoded: the header, then the blocks.
void append_compressed(std::string& out, const std::vector<unsigned char>& bytes) {
  const std::size_t nb_blocks = (bytes.size() + kVtuBlockSize - 1) / kVtuBlockSize;
  std::vector<unsigned char> header, packed;
  put_le<std::uint64_t>(header, nb_blocks);
  put_le<std::uint64_t>(header, kVtuBlockSize);
  put_le<std::uint64_t>(header, bytes.size() % kVtuBlockSize);
  for (std::size_t b = 0; b < nb_blocks; ++b) {
    const std::size_t begin = b * kVtuBlockSize;
    const std::size_t size = std::min(kVtuBlockSize, bytes.size() - begin);
    auto packed_size = compressBound(static_cast<uLong>(size));
    const std::size_t at = packed.size();
    packed.resize(at + packed_size);
    if (compress2(packed.data() + at, &packed_size, bytes.data() + begin, static_cast<uLong>(size),
                  Z_DEFAULT_COMPRESSION) != Z_OK) {
      throw Error("write_vtu: zlib failed to compress a block");
    }
    packed.resize(at + packed_size);
    put_le<std::uint64_t>(header, packed_size);
  }
  base64_append(out, header.data(), header.size());
  base64_append(out, packed.data(), packed.size());
}

}  // namespace

void write_vtu(std::ostream& out, const double* coords, std::uint32_t nb_points, int dimension,
               const std::vector<VtuCellBlock>& blocks, bool binary,
               const std::vector<VtuCellField>& fields, const std::vector<VtuCellTags>& tags) {
  write_vtu(out, coords, nb_points, dimension, blocks,
            binary ? VtuEncoding::kBase64 : VtuEncoding::kAscii, fields, tags);
}

void write_vtu(std::ostream& out, const double* coords, std::uint32_t nb_points, int dimension,
               const std::vector<VtuCellBlock>& blocks, VtuEncoding encoding,
               const std::vector<VtuCellField>& fields, const std::vector<VtuCellTags>& tags,
               const std::vector<VtuCellTags>& point_tags) {
  const bool binary = encoding != VtuEncoding::kAscii;
  std::size_t nb_cells = 0, nb_indices = 0;
  // Per block its number of indices.
  const auto block_indices = [](const VtuCellBlock& b) {
    return b.vertices_per_cell == 0 ? std::size_t{b.polygon_begin[b.nb_cells]}
                                    : b.nb_cells * static_cast<std::size_t>(b.vertices_per_cell);
  };
  for (const VtuCellBlock& b : blocks) {
    const bool polygons = b.vertices_per_cell == 0 && b.polygon_begin != nullptr;
    if ((b.vertices_per_cell < 2 || b.vertices_per_cell > 4) && !polygons) {
      throw Error("write_vtu: " + std::to_string(b.vertices_per_cell) +
                  " vertices per cell: 2 (lines), 3 (triangles), 4 (tetrahedra), or 0 with "
                  "polygon_begin (polygons)");
    }
    if (polygons && b.polygon_begin[0] != 0) {
      throw Error("write_vtu: polygon_begin must start at 0");
    }
    nb_cells += b.nb_cells;
    nb_indices += block_indices(b);
  }
  const auto dim = static_cast<std::size_t>(dimension);
  const auto check_size = [&](const std::string& name, std::size_t size) {
    if (size != nb_cells) {
      throw Error("write_vtu: cell field '" + name + "' has " + std::to_string(size) +
                  " values for " + std::to_string(nb_cells) + " cells");
    }
  };
  for (const VtuCellField& f : fields) check_size(f.name, f.values.size());
  for (const VtuCellTags& t : tags) check_size(t.name, t.values.size());
  for (const VtuCellTags& t : point_tags) {
    if (t.values.size() != nb_points) {
      throw Error("write_vtu: point array '" + t.name + "' has " + std::to_string(t.values.size()) +
                  " values for " + std::to_string(nb_points) + " points");
    }
  }
  std::vector<OutArray> arrays;
  auto add_doubles = [&](const std::string& type, const std::string& name, int components,
                         std::size_t n, auto value) {
    OutArray a{type, name, components, {}, {}};
    for (std::size_t i = 0; i < n; ++i) {
      const double v = value(i);
      if (binary) {
        put_le<double>(a.bytes, v);
      } else {
        append(a.ascii, v);
        a.ascii += (i + 1) % static_cast<std::size_t>(components) == 0 ? '\n' : ' ';
      }
    }
    arrays.push_back(std::move(a));
  };
  // Int64, UInt8 or Int32 values; `value(i)` returns an std::int64_t.
  auto add_ints = [&](const std::string& type, const std::string& name, std::size_t n, auto value) {
    OutArray a{type, name, 1, {}, {}};
    for (std::size_t i = 0; i < n; ++i) {
      const std::int64_t v = value(i);
      if (!binary) {
        char buf[24];
        a.ascii.append(buf, std::to_chars(buf, buf + sizeof(buf), v).ptr);
        a.ascii += '\n';
      } else if (type == "UInt8") {
        put_le<std::uint8_t>(a.bytes, static_cast<std::uint8_t>(v));
      } else if (type == "Int32") {
        put_le<std::int32_t>(a.bytes, static_cast<std::int32_t>(v));
      } else {
        put_le<std::int64_t>(a.bytes, v);
      }
    }
    arrays.push_back(std::move(a));
  };
  // Cell c is cell c - block_begin[b] of the block b with block_begin[b] <= c < block_begin[b + 1].
  std::vector<std::size_t> block_begin{0}, index_begin{0};
  for (const VtuCellBlock& b : blocks) {
    block_begin.push_back(block_begin.back() + b.nb_cells);
    index_begin.push_back(index_begin.back() + block_indices(b));
  }
  add_doubles("Float64", "Points", 3, 3 * std::size_t{nb_points}, [&](std::size_t i) {
    const std::size_t p = i / 3, c = i % 3;
    return c < dim ? coords[dim * p + c] : 0.0;
  });
  {
    std::size_t b = 0;
    add_ints("Int64", "connectivity", nb_indices, [&](std::size_t i) {
      while (i >= index_begin[b + 1]) ++b;
      return static_cast<std::int64_t>(blocks[b].indices[i - index_begin[b]]);
    });
  }
  // Per cell its number of points and its VTK type (VTK_TETRA 10, VTK_TRIANGLE 5,
  // VTK_LINE 3, VTK_POLYGON 7).
  std::vector<std::int64_t> cell_size(nb_cells);
  std::vector<std::uint8_t> cell_type(nb_cells);
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    const VtuCellBlock& block = blocks[b];
    for (std::size_t c = 0; c < block.nb_cells; ++c) {
      const std::size_t k = block_begin[b] + c;
      if (block.vertices_per_cell == 0) {
        cell_size[k] = std::int64_t{block.polygon_begin[c + 1]} - block.polygon_begin[c];
        cell_type[k] = 7;
      } else {
        cell_size[k] = block.vertices_per_cell;
        cell_type[k] = block.vertices_per_cell == 4 ? 10 : block.vertices_per_cell == 3 ? 5 : 3;
      }
    }
  }
  {
    std::int64_t end = 0;
    add_ints("Int64", "offsets", nb_cells, [&](std::size_t c) { return end += cell_size[c]; });
  }
  add_ints("UInt8", "types", nb_cells, [&](std::size_t c) { return std::int64_t{cell_type[c]}; });
  add_ints("Int64", "cell_id", nb_cells,
           [&](std::size_t c) { return static_cast<std::int64_t>(c); });
  for (const VtuCellField& f : fields) {
    add_doubles("Float64", f.name, 1, nb_cells, [&](std::size_t c) { return f.values[c]; });
  }
  for (const VtuCellTags& t : tags) {
    add_ints("Int32", t.name, nb_cells, [&](std::size_t c) { return std::int64_t{t.values[c]}; });
  }
  const std::size_t first_point_array = arrays.size();  // point data after the cell data
  for (const VtuCellTags& t : point_tags) {
    add_ints("Int32", t.name, nb_points, [&](std::size_t p) { return std::int64_t{t.values[p]}; });
  }

  std::string appended;  // base64, after the '_'
  std::vector<std::size_t> offset(arrays.size(), 0);
  if (binary) {
    for (std::size_t i = 0; i < arrays.size(); ++i) {
      offset[i] = appended.size();
      if (encoding == VtuEncoding::kZlibBase64) {
        append_compressed(appended, arrays[i].bytes);
        continue;
      }
      std::vector<unsigned char> header;
      put_le<std::uint64_t>(header, arrays[i].bytes.size());
      base64_append(appended, header.data(), header.size());
      base64_append(appended, arrays[i].bytes.data(), arrays[i].bytes.size());
    }
  }
  std::string s =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
      "byte_order=\"LittleEndian\" header_type=\"UInt64\"" +
      std::string(encoding == VtuEncoding::kZlibBase64 ? " compressor=\"vtkZLibDataCompressor\""
                                                       : "") +
      ">\n<UnstructuredGrid>\n<Piece "
      "NumberOfPoints=\"" +
      std::to_string(nb_points) + "\" NumberOfCells=\"" + std::to_string(nb_cells) + "\">\n";
  auto data_array = [&](std::size_t i) {
    const OutArray& a = arrays[i];
    s += "<DataArray type=\"" + a.type + "\" Name=\"" + a.name + "\"";
    if (a.components != 1) s += " NumberOfComponents=\"" + std::to_string(a.components) + "\"";
    if (binary) {
      s += " format=\"appended\" offset=\"" + std::to_string(offset[i]) + "\"/>\n";
    } else {
      s += " format=\"ascii\">\n" + a.ascii + "</DataArray>\n";
    }
  };
  s += "<Points>\n";
  data_array(0);
  s += "</Points>\n<Cells>\n";
  for (std::size_t i = 1; i <= 3; ++i) data_array(i);
  s += "</Cells>\n<CellData Scalars=\"cell_id\">\n";
  for (std::size_t i = 4; i < first_point_array; ++i) data_array(i);
  s += "</CellData>\n";
  if (first_point_array < arrays.size()) {
    s += "<PointData>\n";
    for (std::size_t i = first_point_array; i < arrays.size(); ++i) data_array(i);
    s += "</PointData>\n";
  }
  s += "</Piece>\n</UnstructuredGrid>\n";
  if (binary) s += "<AppendedData encoding=\"base64\">\n_" + appended + "\n</AppendedData>\n";
  s += "</VTKFile>\n";
  out.write(s.data(), static_cast<std::streamsize>(s.size()));
}

void write_vtu(std::ostream& out, const double* coords, std::uint32_t nb_points, int dimension,
               const std::vector<std::uint32_t>& cells, int vertices_per_cell, bool binary,
               const std::vector<VtuCellField>& fields) {
  const auto per = static_cast<std::size_t>(vertices_per_cell);
  write_vtu(out, coords, nb_points, dimension,
            {VtuCellBlock{cells.data(), per == 0 ? 0 : cells.size() / per, vertices_per_cell}},
            binary, fields);
}

namespace detail {

namespace {

// The parts of a .vtu file the reader needs: elements with their attributes, parents and
// content ranges. A minimal XML scanner: no entities, no CDATA (VTK writes neither).
struct XmlElement {
  std::string name, parent;
  std::vector<std::pair<std::string, std::string>> attributes;
  std::size_t content_begin = 0, content_end = 0;  // text between the tags
  std::uint32_t line = 1;

  const std::string* attribute(const std::string& key) const {
    for (const auto& [k, v] : attributes) {
      if (k == key) return &v;
    }
    return nullptr;
  }
};

// What the reader does with a VTK cell type given as a number (vtk_cell_types.h); a type
// that is not an integer in [0, 256) is skipped.
vtk::VtkCellKind vtu_cell_kind(double type) {
  if (!(type >= 0 && type < 256) || type != std::floor(type)) return {};
  return vtk::vtk_cell_kind(static_cast<std::uint64_t>(type));
}

class VtuReader {
 public:
  VtuReader(std::string path, std::string text) : path_(std::move(path)), text_(std::move(text)) {}

  TetMeshInput read() {
    scan();
    const XmlElement* file = find("VTKFile");
    if (file == nullptr) fail(1, "not a VTK XML file: no VTKFile element");
    const std::string* type = file->attribute("type");
    if (type == nullptr || *type != "UnstructuredGrid") {
      fail(file->line, "VTKFile type " + (type ? quote(*type) : std::string("(none)")) +
                           ": only UnstructuredGrid is read");
    }
    if (const std::string* compressor = file->attribute("compressor"); compressor != nullptr) {
      if (*compressor != "vtkZLibDataCompressor") {
        fail(file->line, "compressor " + quote(*compressor) +
                             " is not read (vtkZLibDataCompressor, or no compressor)");
      }
      compressed_ = true;
    }
    const std::string* order = file->attribute("byte_order");
    big_endian_ = order != nullptr && *order == "BigEndian";
    const std::string* header = file->attribute("header_type");
    header64_ = header != nullptr && *header == "UInt64";
    std::size_t pieces = 0;
    for (const XmlElement& e : elements_) pieces += e.name == "Piece" ? 1 : 0;
    if (pieces != 1) {
      fail(file->line, std::to_string(pieces) + " Piece elements: exactly one is read");
    }
    const XmlElement* piece = find("Piece");
    const std::uint64_t nb_points = count_attribute(*piece, "NumberOfPoints");
    const std::uint64_t nb_cells = count_attribute(*piece, "NumberOfCells");
    if (nb_points > 0xffffffffull) fail(piece->line, "more than 2^32 - 1 points");

    TetMeshInput mesh;
    mesh.source = path_;
    const XmlElement* points = array_in("Points", nullptr);
    if (points == nullptr) fail(piece->line, "no Points data array");
    mesh.xyz = values(*points, 3 * nb_points, 3);
    for (const double x : mesh.xyz) {
      if (!std::isfinite(x)) fail(points->line, "Points: a coordinate is not finite");
    }
    const XmlElement* conn = array_in("Cells", "connectivity");
    const XmlElement* offsets = array_in("Cells", "offsets");
    const XmlElement* types = array_in("Cells", "types");
    if (conn == nullptr || offsets == nullptr || types == nullptr) {
      // A file cut short inside a DataArray: say so, not that the arrays after it are missing.
      for (const XmlElement& e : elements_) {
        if (e.name == "DataArray" && e.content_end == kOpen) {
          const std::string* name = e.attribute("Name");
          fail(e.line, "DataArray " + (name ? *name : std::string("(no Name)")) + " is not closed");
        }
      }
      fail(piece->line, "Cells needs the data arrays connectivity, offsets and types");
    }
    const std::vector<double> off = values(*offsets, nb_cells, 1);
    // Offsets are read as doubles: checked to be whole numbers in range before they are
    // converted (a negative or huge double converted to an integer is undefined behaviour:
    // fuzz regression vtu_negative_offset.vtu).
    for (std::size_t c = 0; c < off.size(); ++c) {
      if (!(off[c] >= 0 && off[c] <= 0x1p53 && off[c] == std::floor(off[c]))) {
        fail(offsets->line, "offsets: cell " + std::to_string(c) + " ends at " + fmt(off[c]) +
                                ": not an offset (a whole number from 0 to 2^53)");
      }
    }
    const std::vector<double> typ = values(*types, nb_cells, 1);
    const std::uint64_t size = nb_cells == 0 ? 0 : static_cast<std::uint64_t>(off.back());
    const std::vector<double> idx = values(*conn, size, 1);
    // Tags: CellData region (tets) and patch (triangles), else meshio's names for them
    // (kVtkTagNames), read with the cells they tag.
    const auto first_of = [&](const std::size_t* names, std::size_t n) -> const XmlElement* {
      for (std::size_t k = 0; k < n; ++k) {
        if (const XmlElement* a = array_in("CellData", kVtkTagNames[names[k]]); a != nullptr) {
          return a;
        }
      }
      return nullptr;
    };
    const XmlElement* region = first_of(kVtkTetTags, std::size(kVtkTetTags));
    const XmlElement* patch = first_of(kVtkTriangleTags, std::size(kVtkTriangleTags));
    const std::vector<double> region_values =
        region == nullptr ? std::vector<double>{} : values(*region, nb_cells, 1);
    const std::vector<double> patch_values = patch == nullptr  ? std::vector<double>{}
                                             : patch == region ? region_values
                                                               : values(*patch, nb_cells, 1);
    // Volume cells not read (hexahedra, wedges, pyramids, ...): an error once the cells are
    // read.
    OtherVolumes others;
    std::uint64_t begin = 0;
    for (std::size_t c = 0; c < nb_cells; ++c) {
      const auto end = static_cast<std::uint64_t>(off[c]);
      if (end < begin || end > size) {
        fail(offsets->line, "offsets: cell " + std::to_string(c) + " ends at " + fmt(off[c]) +
                                ", not in " + std::to_string(begin) + ".." + std::to_string(size));
      }
      const vtk::VtkCellKind kind = vtu_cell_kind(typ[c]);
      const bool tet = kind.corners == 4, triangle = kind.corners == 3;
      if (kind.other != nullptr) {
        others.add(kind.other, kind.others, types->line,
                   [&] { return "cell " + std::to_string(c) + ", type " + fmt(typ[c]); });
      }
      if (tet || triangle) {
        if (end - begin != kind.points) {
          fail(types->line, "cell " + std::to_string(c) + " of type " + kind.name + " has " +
                                count_of(end - begin, "point") + ", not " +
                                std::to_string(kind.points));
        }
        std::vector<std::uint32_t>& cells = tet ? mesh.tets : mesh.triangles;
        // The corners: the first points (a quadratic cell's mid-edge points are not read).
        for (std::uint64_t k = begin; k < begin + kind.corners; ++k) {
          const double v = idx[static_cast<std::size_t>(k)];
          // Negated: a NaN (from a Float64 connectivity) is out of range too.
          if (!(v >= 0 && v < static_cast<double>(nb_points))) {
            fail(conn->line, "cell " + std::to_string(c) + ": point " + fmt(v) +
                                 " is out of range " +
                                 (nb_points == 0 ? std::string("(the file has no points)")
                                                 : "0.." + std::to_string(nb_points - 1)));
          }
          if (v != std::floor(v)) {
            fail(conn->line, "cell " + std::to_string(c) + ": point " + fmt(v) +
                                 " is not a point index (a whole number)");
          }
          cells.push_back(static_cast<std::uint32_t>(v));
        }
        if (kind.points != kind.corners)
          ++(tet ? mesh.nb_higher_order_tets : mesh.nb_higher_order_triangles);
        if (tet) {
          mesh.tet_line.push_back(conn->line);
          mesh.tet_label.push_back(c);
          if (region != nullptr) mesh.tet_ref.push_back(tag(*region, c, region_values[c]));
        } else if (patch != nullptr) {
          mesh.triangle_ref.push_back(tag(*patch, c, patch_values[c]));
        }
      }
      begin = end;
    }
    for (std::vector<std::int32_t>* ref : {&mesh.tet_ref, &mesh.triangle_ref}) {
      if (std::all_of(ref->begin(), ref->end(), [](std::int32_t r) { return r == 0; })) {
        ref->clear();
      }
    }
    others.check(path_);
    if (mesh.tets.empty()) throw Error(path_ + ": no tetrahedra (cell type 10 or 24)");
    // PointData: the active scalars, else the first array of one component.
    if (const XmlElement* pd = find("PointData"); pd != nullptr) {
      const std::string* active = pd->attribute("Scalars");
      const XmlElement* chosen = active ? array_in("PointData", active->c_str()) : nullptr;
      for (const XmlElement& e : elements_) {
        if (chosen != nullptr) break;
        if (e.name != "DataArray" || e.parent != "PointData") continue;
        const std::string* nc = e.attribute("NumberOfComponents");
        if (nc == nullptr || *nc == "1") chosen = &e;
      }
      if (chosen != nullptr) {
        mesh.point_data = values(*chosen, nb_points, 1);
        const std::string* name = chosen->attribute("Name");
        mesh.point_data_name = name ? *name : std::string();
        mesh.point_data_line = chosen->line;
      }
    }
    mesh.tet_noun = "cell";
    mesh.numbering = "VTK numbering, from 0";
    return mesh;
  }

 private:
  [[noreturn]] void fail(std::uint32_t line, const std::string& what) const {
    throw Error(path_ + ":" + std::to_string(line) + ": " + what);
  }

  // The value of a tag array (region, patch) for cell c: a 32-bit integer.
  std::int32_t tag(const XmlElement& a, std::size_t c, double v) const {
    if (!(v == std::floor(v) && v >= -2147483648.0 && v <= 2147483647.0)) {
      fail(a.line, "DataArray " + *a.attribute("Name") + ": cell " + std::to_string(c) + ": " +
                       fmt(v) + " is not a tag (a 32-bit integer)");
    }
    return static_cast<std::int32_t>(v);
  }

  static std::string fmt(double v) {
    std::string s;
    append(s, v);
    return s;
  }

  std::uint32_t line_at(std::size_t pos) {
    for (; line_pos_ < pos && line_pos_ < text_.size(); ++line_pos_) {
      if (text_[line_pos_] == '\n') ++line_;
    }
    return line_;
  }

  void scan() {
    std::vector<std::string> stack;
    std::size_t pos = 0;
    for (;;) {
      const std::size_t lt = text_.find('<', pos);
      if (lt == std::string::npos) break;
      if (text_.compare(lt, 4, "<!--") == 0) {
        const std::size_t end = text_.find("-->", lt);
        if (end == std::string::npos) fail(line_at(lt), "unterminated comment");
        pos = end + 3;
        continue;
      }
      if (text_.compare(lt, 2, "<?") == 0) {
        const std::size_t end = text_.find("?>", lt);
        if (end == std::string::npos) fail(line_at(lt), "unterminated <?...?>");
        pos = end + 2;
        continue;
      }
      const std::size_t gt = text_.find('>', lt);
      if (gt == std::string::npos) fail(line_at(lt), "unterminated tag");
      if (text_[lt + 1] == '/') {
        const std::string name = trim(text_.substr(lt + 2, gt - lt - 2));
        if (stack.empty() || stack.back() != name) {
          fail(line_at(lt),
               "closing tag </" + name + "> does not match " +
                   (stack.empty() ? std::string("any open element") : "<" + stack.back() + ">"));
        }
        for (auto it = elements_.rbegin(); it != elements_.rend(); ++it) {
          if (it->name == name && it->content_end == kOpen) {
            it->content_end = lt;
            break;
          }
        }
        stack.pop_back();
        pos = gt + 1;
        continue;
      }
      XmlElement e;
      e.line = line_at(lt);
      e.parent = stack.empty() ? "" : stack.back();
      const bool self_closing = text_[gt - 1] == '/';
      parse_tag(std::string_view(text_).substr(lt + 1, gt - lt - 1 - (self_closing ? 1 : 0)), e);
      e.content_begin = gt + 1;
      e.content_end = self_closing ? gt + 1 : kOpen;
      if (e.name == "AppendedData") {
        // Raw data may hold any byte: stop scanning here.
        const std::size_t underscore = text_.find('_', gt + 1);
        if (underscore == std::string::npos) fail(e.line, "AppendedData without '_'");
        const std::string* enc = e.attribute("encoding");
        appended_base64_ = enc == nullptr || *enc == "base64";
        if (enc != nullptr && *enc != "base64" && *enc != "raw") {
          fail(e.line, "AppendedData encoding " + quote(*enc) + ": base64 or raw");
        }
        appended_ = underscore + 1;
        elements_.push_back(std::move(e));
        return;
      }
      if (!self_closing) stack.push_back(e.name);
      elements_.push_back(std::move(e));
      pos = gt + 1;
    }
  }

  static std::string trim(std::string s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
    std::size_t i = 0;
    while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
    return s.substr(i);
  }

  void parse_tag(std::string_view t, XmlElement& e) {
    std::size_t i = 0;
    while (i < t.size() && !std::isspace(static_cast<unsigned char>(t[i]))) ++i;
    e.name = std::string(t.substr(0, i));
    for (;;) {
      while (i < t.size() && std::isspace(static_cast<unsigned char>(t[i]))) ++i;
      if (i >= t.size()) return;
      const std::size_t eq = t.find('=', i);
      if (eq == std::string_view::npos) fail(e.line, "<" + e.name + ">: malformed attribute");
      std::string key = trim(std::string(t.substr(i, eq - i)));
      std::size_t q = eq + 1;
      while (q < t.size() && std::isspace(static_cast<unsigned char>(t[q]))) ++q;
      if (q >= t.size() || (t[q] != '"' && t[q] != '\'')) {
        fail(e.line, "<" + e.name + ">: attribute " + key + " is not quoted");
      }
      const std::size_t close = t.find(t[q], q + 1);
      if (close == std::string_view::npos) {
        fail(e.line, "<" + e.name + ">: attribute " + key + " is not closed");
      }
      e.attributes.emplace_back(std::move(key), std::string(t.substr(q + 1, close - q - 1)));
      i = close + 1;
    }
  }

  const XmlElement* find(const std::string& name) const {
    for (const XmlElement& e : elements_) {
      if (e.name == name) return &e;
    }
    return nullptr;
  }

  // The DataArray in `parent` named `name` (nullptr: the first one).
  const XmlElement* array_in(const std::string& parent, const char* name) const {
    for (const XmlElement& e : elements_) {
      if (e.name != "DataArray" || e.parent != parent) continue;
      const std::string* n = e.attribute("Name");
      if (name == nullptr || (n != nullptr && *n == name)) return &e;
    }
    return nullptr;
  }

  std::uint64_t count_attribute(const XmlElement& e, const char* key) {
    const std::string* v = e.attribute(key);
    if (v == nullptr) fail(e.line, "<" + e.name + "> has no " + key);
    std::uint64_t n = 0;
    const auto r = std::from_chars(v->data(), v->data() + v->size(), n);
    if (r.ec != std::errc() || r.ptr != v->data() + v->size()) {
      fail(e.line, std::string(key) + "=" + quote(*v) + " is not a count");
    }
    return n;
  }

  // A base64 stream over text_[pos, end): whole groups of 4 characters are decoded (a
  // padded group gives 1 or 2 bytes, so separately encoded blocks read as one stream), and
  // bytes of a group beyond what was asked wait for the next read.
  struct Base64Stream {
    std::size_t pos, end;
    std::vector<unsigned char> pending;
  };
  std::vector<unsigned char> base64_read(Base64Stream& in, std::size_t n, std::uint32_t line) {
    std::vector<unsigned char> out;
    out.reserve(n);
    const std::size_t first = std::min(n, in.pending.size());
    out.assign(in.pending.begin(), in.pending.begin() + static_cast<std::ptrdiff_t>(first));
    in.pending.erase(in.pending.begin(), in.pending.begin() + static_cast<std::ptrdiff_t>(first));
    int group[4];
    int k = 0, pad = 0;
    while (out.size() < n && in.pos < in.end) {
      const char c = text_[in.pos++];
      if (std::isspace(static_cast<unsigned char>(c))) continue;
      int v = 0;
      if (c == '=') {
        ++pad;
      } else if (const char* p = std::strchr(kBase64, c); p != nullptr && c != 0) {
        v = static_cast<int>(p - kBase64);
      } else {
        fail(line, "invalid base64 character " + quote(std::string(1, c)));
      }
      group[k++] = v;
      if (k == 4) {
        const std::uint32_t bits = (static_cast<std::uint32_t>(group[0]) << 18) |
                                   (static_cast<std::uint32_t>(group[1]) << 12) |
                                   (static_cast<std::uint32_t>(group[2]) << 6) |
                                   static_cast<std::uint32_t>(group[3]);
        const int bytes = 3 - std::min(pad, 2);
        for (int b = 0; b < bytes; ++b) {
          const auto byte = static_cast<unsigned char>((bits >> (16 - 8 * b)) & 0xff);
          if (out.size() < n) {
            out.push_back(byte);
          } else {
            in.pending.push_back(byte);
          }
        }
        k = 0;
        pad = 0;
      }
    }
    if (out.size() < n) fail(line, "binary data is truncated");
    return out;
  }

  std::uint64_t read_uint(const unsigned char* b, std::size_t size) const {
    std::uint64_t v = 0;
    for (std::size_t i = 0; i < size; ++i) {
      const std::size_t j = big_endian_ ? i : size - 1 - i;
      v = (v << 8) | b[j];
    }
    return v;
  }

  // Where the bytes of a binary array come from: base64 text (inline, or appended with
  // encoding="base64") or raw appended bytes from `raw_pos`.
  struct Source {
    bool base64 = true;
    Base64Stream b64{0, 0, {}};
    std::size_t raw_pos = 0;
  };

  // The next n bytes of `in`, after checking that the file can hold them (before anything
  // is allocated for them).
  std::vector<unsigned char> take(Source& in, std::uint64_t n, const XmlElement& a,
                                  const std::string& name, const char* what) {
    const std::uint64_t left =
        in.base64 ? in.b64.pending.size() + (in.b64.end - std::min(in.b64.pos, in.b64.end)) / 4 * 3
                  : text_.size() - std::min(in.raw_pos, text_.size());
    if (n > left) {
      fail(a.line, "DataArray " + name + ": " + what + " is truncated: " + std::to_string(n) +
                       " bytes needed, at most " + std::to_string(left) + " left");
    }
    if (in.base64) return base64_read(in.b64, static_cast<std::size_t>(n), a.line);
    const auto begin = text_.begin() + static_cast<std::ptrdiff_t>(in.raw_pos);
    in.raw_pos += static_cast<std::size_t>(n);
    return std::vector<unsigned char>(begin, begin + static_cast<std::ptrdiff_t>(n));
  }

  // The `want` bytes of a binary or appended array, after its header: uncompressed, the
  // byte count (at least `want`); compressed, the block table (see the top of the file),
  // the blocks then inflated one by one up to `want` bytes.
  std::vector<unsigned char> array_bytes(const XmlElement& a, const std::string& name,
                                         const std::string& f, std::size_t want) {
    Source in;
    if (f == "binary") {
      in.b64 = {a.content_begin, a.content_end, {}};
    } else if (f == "appended") {
      if (appended_ == 0) fail(a.line, "format=\"appended\" but no AppendedData section");
      const std::uint64_t offset = count_attribute(a, "offset");
      if (offset > text_.size() - appended_) {
        fail(a.line, "DataArray " + name + ": offset " + std::to_string(offset) +
                         " is past the end of the file");
      }
      const std::size_t pos = appended_ + static_cast<std::size_t>(offset);
      in.base64 = appended_base64_;
      in.b64 = {pos, text_.size(), {}};
      in.raw_pos = pos;
    } else {
      fail(a.line, "DataArray " + name + ": unknown format " + quote(f));
    }
    const std::size_t hsize = header64_ ? 8 : 4;
    const auto word = [&](const std::vector<unsigned char>& h, std::size_t i) {
      return read_uint(h.data() + i * hsize, hsize);
    };
    if (!compressed_) {
      const std::uint64_t count = word(take(in, hsize, a, name, "the header"), 0);
      if (count < want) {
        fail(a.line, "DataArray " + name + ": " + std::to_string(count) + " bytes, expected " +
                         std::to_string(want));
      }
      return take(in, want, a, name, "the data");
    }
    const std::uint64_t nb_blocks = word(take(in, hsize, a, name, "the header"), 0);
    if (nb_blocks > text_.size() / hsize) {
      fail(a.line, "DataArray " + name + ": the header announces " + std::to_string(nb_blocks) +
                       " compressed blocks, more than the file can hold");
    }
    const std::vector<unsigned char> h =
        take(in, (2 + nb_blocks) * hsize, a, name, "the compression header");
    const std::uint64_t block_size = word(h, 0), last_size = word(h, 1);
    if (last_size > block_size) {
      fail(a.line, "DataArray " + name + ": the last block has " + std::to_string(last_size) +
                       " bytes, more than the block size " + std::to_string(block_size));
    }
    std::vector<unsigned char> out;
    for (std::uint64_t b = 0; b < nb_blocks && out.size() < want; ++b) {
      const std::uint64_t size = b + 1 == nb_blocks && last_size != 0 ? last_size : block_size;
      const std::uint64_t packed = word(h, 2 + static_cast<std::size_t>(b));
      const std::string block = "block " + std::to_string(b);
      if (size > kZlibMaxRatio * std::min<std::uint64_t>(packed, text_.size())) {
        fail(a.line, "DataArray " + name + ": " + block + " claims " + std::to_string(size) +
                         " bytes from " + std::to_string(packed) +
                         " compressed bytes, more than zlib can inflate");
      }
      const std::vector<unsigned char> z = take(in, packed, a, name, block.c_str());
      std::uint64_t got = 0;
      const int rc = inflate_append(z, size, out, got);
      if (rc != Z_OK || got != size) {
        fail(a.line,
             "DataArray " + name + ": " + block + ": " +
                 (rc == Z_OK ? "inflates to " + std::to_string(got) + " bytes, the header says " +
                                   std::to_string(size)
                  : rc == Z_BUF_ERROR ? "inflates to more than the " + std::to_string(size) +
                                            " bytes the header says"
                                      : std::string("not valid zlib data (") + zError(rc) + ")"));
      }
    }
    if (out.size() < want) {
      fail(a.line, "DataArray " + name + ": " + std::to_string(out.size()) +
                       " bytes once inflated, expected " + std::to_string(want));
    }
    out.resize(want);
    return out;
  }

  // Inflates the zlib stream `z`, which the header says holds `size` bytes, onto the end of
  // `out`; `got` is the number of bytes it gave. Returns what uncompress() would: Z_OK when
  // the stream ended (got may then be below size), Z_BUF_ERROR when it holds more than
  // `size` bytes, Z_DATA_ERROR when it is invalid or incomplete. `out` grows with what
  // actually comes out, by chunks, not by the size claimed: a header may claim up to
  // kZlibMaxRatio times the compressed bytes, which a few bytes of garbage do not justify.
  static int inflate_append(const std::vector<unsigned char>& z, std::uint64_t size,
                            std::vector<unsigned char>& out, std::uint64_t& got) {
    z_stream s{};
    if (inflateInit(&s) != Z_OK) return Z_MEM_ERROR;
    s.next_in = const_cast<Bytef*>(z.data());  // zlib's API is not const-correct
    s.avail_in = static_cast<uInt>(z.size());
    const std::size_t at = out.size();
    std::uint64_t chunk = std::uint64_t{1} << 16;
    int rc = Z_OK;
    got = 0;
    for (;;) {
      unsigned char probe = 0;
      const std::uint64_t step = std::min(chunk, size - got);
      if (step > 0) {
        out.resize(at + static_cast<std::size_t>(got + step));
        s.next_out = out.data() + at + got;
      } else {
        s.next_out = &probe;  // full: one more byte means the stream holds too much
      }
      const uInt room = step > 0 ? static_cast<uInt>(step) : 1u;
      s.avail_out = room;
      rc = inflate(&s, Z_NO_FLUSH);
      const uInt produced = room - s.avail_out;
      if (step == 0 && produced > 0) {
        rc = Z_BUF_ERROR;
        break;
      }
      got += produced;
      if (rc == Z_STREAM_END) {
        rc = Z_OK;
        break;
      }
      if (rc == Z_NEED_DICT || (rc == Z_BUF_ERROR && produced == 0)) {
        rc = Z_DATA_ERROR;  // no progress: the input ended before the stream did
        break;
      }
      if (rc != Z_OK && rc != Z_BUF_ERROR) break;
      chunk = std::min<std::uint64_t>(2 * chunk, std::uint64_t{1} << 26);
    }
    inflateEnd(&s);
    out.resize(at + static_cast<std::size_t>(got));
    return rc;
  }

  // `n` values of a DataArray, as doubles (integers up to 2^53 exactly).
  std::vector<double> values(const XmlElement& a, std::uint64_t n, int components) {
    const std::string* type = a.attribute("type");
    const std::string* format = a.attribute("format");
    const std::string name = a.attribute("Name") ? *a.attribute("Name") : "Points";
    if (type == nullptr) fail(a.line, "DataArray " + name + " has no type");
    // An element left open (no </DataArray> before the end, or before AppendedData) has no
    // end to its content: its inline data would run to the end of the file and past it.
    if (a.content_end == kOpen) fail(a.line, "DataArray " + name + " is not closed");
    if (const std::string* nc = a.attribute("NumberOfComponents");
        nc != nullptr && *nc != std::to_string(components)) {
      fail(a.line, "DataArray " + name + ": NumberOfComponents " + quote(*nc) + ", expected " +
                       std::to_string(components));
    }
    std::size_t size = 0;
    bool floating = false, is_signed = false;
    if (*type == "Float64") {
      size = 8, floating = true;
    } else if (*type == "Float32") {
      size = 4, floating = true;
    } else if (*type == "Int64" || *type == "UInt64") {
      size = 8, is_signed = *type == "Int64";
    } else if (*type == "Int32" || *type == "UInt32") {
      size = 4, is_signed = *type == "Int32";
    } else if (*type == "Int16" || *type == "UInt16") {
      size = 2, is_signed = *type == "Int16";
    } else if (*type == "Int8" || *type == "UInt8") {
      size = 1, is_signed = *type == "Int8";
    } else {
      fail(a.line, "DataArray " + name + ": unknown type " + quote(*type));
    }
    std::vector<double> out;
    out.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(n, text_.size())));
    const std::string f = format ? *format : "ascii";
    if (f == "ascii") {
      Lexer lx(path_, text_.substr(a.content_begin, a.content_end - a.content_begin), 0, a.line);
      for (std::uint64_t i = 0; i < n; ++i) {
        const std::string_view t = lx.next();
        if (t.empty()) {
          fail(a.line, "DataArray " + name + ": expected " + std::to_string(n) + " values, found " +
                           std::to_string(i));
        }
        out.push_back(to_double(lx, t));
      }
      return out;
    }
    if (n > std::numeric_limits<std::size_t>::max() / size) {
      fail(a.line, "DataArray " + name + ": " + std::to_string(n) + " values: too many");
    }
    const std::vector<unsigned char> bytes = array_bytes(a, name, f, n * size);
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint64_t raw = read_uint(bytes.data() + i * size, size);
      if (floating && size == 8) {
        double d;
        std::memcpy(&d, &raw, 8);
        out.push_back(d);
      } else if (floating) {
        const auto r32 = static_cast<std::uint32_t>(raw);
        float x;
        std::memcpy(&x, &r32, 4);
        out.push_back(static_cast<double>(x));
      } else if (is_signed) {
        // to_signed: two's complement without overflow (an Int64 with the sign bit set
        // overflowed the old arithmetic here: fuzz regression vtu_int64_negative.vtu).
        out.push_back(static_cast<double>(to_signed(raw, size)));
      } else {
        out.push_back(static_cast<double>(raw));
      }
    }
    return out;
  }

  static constexpr std::size_t kOpen = static_cast<std::size_t>(-1);
  std::string path_;
  std::string text_;
  std::vector<XmlElement> elements_;
  std::size_t appended_ = 0;  // first byte after the '_' (0: no AppendedData)
  bool appended_base64_ = true;
  bool big_endian_ = false, header64_ = false, compressed_ = false;
  std::size_t line_pos_ = 0;
  std::uint32_t line_ = 1;
};

}  // namespace

TetMeshInput read_vtu_tet_mesh(const std::string& path, std::string text) {
  return VtuReader(path, std::move(text)).read();
}

}  // namespace detail

}  // namespace voroclip
