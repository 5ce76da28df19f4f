// voroclip/core.h — what every module shares: the one error type, the library version,
// and output files that appear whole or not at all.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <stdexcept>
#include <string>
#include <vector>

namespace voroclip {

/// The library's version, "MAJOR.MINOR.PATCH".
const char* version();

/// The single exception type the library throws for bad input or an impossible request.
/// The message names what is wrong and where (file, line, element) so a user can act on it;
/// the library never calls exit() or abort() on user data.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

/// "1 point", "2 points", "0 vertices": a count with its noun, singular for exactly one.
/// `plural` defaults to `singular` + "s".
std::string count_of(std::uint64_t n, const std::string& singular, const std::string& plural = "");

/// Writes a file so that it is either complete or absent: the content goes to a temporary
/// file beside `path`, which is renamed over `path` only after `write` returned and the
/// stream was flushed without error. If `write` throws, or anything fails, the temporary is
/// removed, `path` is left as it was, and an Error naming the file is thrown (the exception
/// thrown by `write` is rethrown unchanged).
void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& write);

/// One file of write_files_atomically: where it goes and what writes its content.
struct FileWriter {
  std::string path;
  std::function<void(std::ostream&)> write;
};

/// Writes files that belong together (TetGen's .node, .ele and .face; a cell table and its
/// neighbour pairs) so that they appear together or not at all: each is written to its
/// temporary beside its path, as write_file_atomically does, and only when every one was
/// written and flushed are they renamed over their paths, in order. If a write fails, every
/// temporary is removed and no path changes; the error is write_file_atomically's. A rename
/// that fails after others succeeded (check_output_path checks what makes it fail, before
/// any work) removes the files already renamed that did not exist before (a file that was
/// replaced cannot be restored) and the remaining temporaries. Two writers with the same
/// path are an Error, thrown before anything is written.
void write_files_atomically(const std::vector<FileWriter>& files);

/// Checks, before any work, that write_file_atomically can create `path`: its directory
/// exists, `path` is not a directory, a temporary file can be created beside it (it is
/// created and removed again: a directory that takes no new files, such as /proc, or a
/// read-only file system fails here, whoever runs the check), and an existing file at
/// `path` can be replaced (not immutable or append-only, chattr +i / +a). Throws Error
/// "cannot write 'path': ..." naming what is wrong. An empty path (no output) passes.
void check_output_path(const std::string& path);

/// True when `a` and `b` name the same file: the same path once made absolute, "." and
/// ".." and symbolic links resolved (files that do not exist yet included), or two names
/// of one existing file (hard links). Empty paths name no file.
bool same_file(const std::string& a, const std::string& b);

/// The contents of a text file as voroclip's readers see them: a gzip-compressed file (it
/// starts with the bytes 1f 8b) or a directory is an Error naming it, a leading UTF-8 byte
/// order mark is dropped, and CR-only line ends (classic Mac OS) become LF.
std::string read_text_file(const std::string& path);

/// Reads points of `dimension` (2 or 3) coordinates, returned packed (x y [z] per point),
/// from either format, recognised by the first non-blank character:
///   - JSON: an array of points, each an array of `dimension` numbers: [[0, 1.5], [2, 3]]
///   - text: one point per line, `dimension` numbers separated by blanks or by commas;
///     empty lines and everything after '#' are ignored. The first line may be a header
///     naming the columns (no number in it, and columns named x, y and, in 3D, z, in any
///     case, maybe quoted): the lines then hold as many fields as the header and the
///     columns x, y (, z) are the point, the others are not read. So the .txt and .csv
///     outputs of cvt2d/cvt3d (`x,y,z`) and the cell tables (`site,x,y,z,volume,...`) read
///     back as sites. Lines end in LF, CRLF or CR; a leading UTF-8 BOM is skipped.
/// Throws Error naming the file and the line (text) or the point (JSON) and what is wrong:
/// a missing file, a value that is not a finite number, a wrong number of coordinates.
std::vector<double> read_points(const std::string& path, int dimension);

/// As read_points(path, dimension), from a stream; `name` stands for the file in messages.
std::vector<double> read_points(std::istream& in, const std::string& name, int dimension);

/// Writes a legacy ASCII VTK unstructured grid (readable by ParaView): the points (z = 0
/// in 2D) and the cells, `vertices_per_cell` point indices each (3: triangles, 4:
/// tetrahedra), with the cell index as cell data "cell_id".
void write_vtk(std::ostream& out, const std::string& title, const double* coords,
               std::uint32_t nb_points, int dimension, const std::vector<std::uint32_t>& cells,
               int vertices_per_cell);

// ---------------------------------------------------------------------------------------
// 2D polygonal domains as read, before validation. The validated domain, with its rings
// oriented and checked exactly, is voroclip::Domain2 (clip.h): validation needs the exact
// predicates, which sit above core.

/// Rings of a polygonal domain as given by a file or a generator. Ring r has the vertices
/// [ring_begin[r], ring_begin[r + 1]) of `xy` (packed x y), in the file's order and
/// orientation, a repeated closing point and repeated consecutive points included.
struct PolygonRings {
  /// Where the rings came from (a file name, or the generator), for error messages.
  std::string source;
  std::vector<double> xy;
  /// nb_rings + 1 offsets into the points (so ring_begin.front() == 0).
  std::vector<std::uint32_t> ring_begin;
  /// Per ring: the polygon it belongs to when the format says so (JSON: a polygon is an
  /// array of rings, its ring 0 the outer boundary, the others its holes), or -1 for every
  /// ring when roles follow from nesting (.poly: a ring inside an odd number of other rings
  /// bounds a hole).
  std::vector<std::int32_t> ring_polygon;
  /// Per ring: the line of the file where it starts (1-based; 0 when not from a text file).
  std::vector<std::uint32_t> ring_line;
  /// .poly hole markers (packed x y): each must lie in a hole of the domain.
  std::vector<double> hole_points;
  /// .poly (Triangle's rule: a region is a hole only where a hole marker is): each ring that
  /// nesting makes a hole must hold a marker. Triangle meshes an unmarked one, its ring an
  /// inner boundary, which voroclip does not take, so Domain2 refuses it.
  bool holes_need_markers = false;
  /// Optional, for messages (empty when the format has nothing to say): per point, its own
  /// number in the file (.poly: the vertex number as written, so that a ring assembled from
  /// segments is reported with the user's numbering; otherwise a point is named by its
  /// position in its ring), and per hole marker, the line of the file where it stands.
  std::vector<std::uint32_t> point_number;
  std::vector<std::uint32_t> hole_line;
  /// .poly with segment markers: per point, the marker of the segment from it to the next
  /// point of its ring, as written (empty otherwise).
  std::vector<std::int32_t> segment_marker;
  /// .poly regional attributes: points (packed x y) and their attribute.
  std::vector<double> region_points, region_attributes;
  /// Optional, for messages (.poly; empty otherwise): per point, the number and the line of
  /// the segment from it to the next point of its ring; per hole marker, its own number;
  /// per regional attribute, its own number and line. The file's own numbers, as written.
  std::vector<std::int64_t> segment_number, hole_number, region_number;
  std::vector<std::uint32_t> segment_line, region_line;

  std::uint32_t nb_rings() const {
    return ring_begin.empty() ? 0u : static_cast<std::uint32_t>(ring_begin.size() - 1);
  }
};

/// Reads a polygonal domain, by extension (in any letter case):
///   .json  an array of rings (one polygon: ring 0 outer, the others holes) or an array of
///          polygons, each an array of rings (ring_polygon numbers them); a ring is an array
///          of [x, y]. The form is recognised by the nesting depth. Orientation is free; the
///          closing point may be repeated. (The format of shared/data/polygons.)
///   .poly  Triangle's format (https://www.cs.cmu.edu/~quake/triangle.poly.html): vertices
///          (numbered from 0 or 1, as the first one says, then consecutively), segments,
///          hole markers, then optionally regional attributes. Segments are chained into
///          closed rings, each starting at the first segment not yet used, in its direction;
///          every vertex used must end exactly two segments, unused vertices are ignored.
///          Roles follow from nesting (ring_polygon = -1); point_number keeps the vertex
///          numbers and hole_line the marker lines (segment_number/segment_line,
///          hole_number, region_number/region_line the other items' own numbers and lines,
///          for messages); segment markers go to
///          segment_marker, regional attributes to region_points/region_attributes (vertex
///          attributes and markers, and maximum areas, are read and ignored); '#' starts a
///          comment. A vertex count of 0 (vertices in a
///          separate .node file) is not supported.
/// Throws Error naming the file, the line (or JSON ring/point) and what is wrong: a missing
/// file, a value that is not a finite number, a wrong number of fields, a truncated file, a
/// vertex index out of range, segments that do not form closed rings.
PolygonRings read_polygon(const std::string& path);

/// As read_polygon(path), from a stream: `name` stands for the file, in messages and in
/// `source`, and its extension (.json or .poly) tells the format.
PolygonRings read_polygon(std::istream& in, const std::string& name);

/// An annulus centred at the origin: outer radius r_outer, inner r_inner, each circle a
/// regular polygon with `segments` vertices, the first at angle 0; the outer ring runs
/// counter-clockwise, the inner one clockwise, as one polygon. Source "annulus(r_inner,
/// r_outer, segments)". Throws Error unless 0 < r_inner < r_outer (finite), segments >= 3.
PolygonRings annulus_rings(double r_inner, double r_outer, std::uint32_t segments);

/// The unit square [0, 1]^2 with a k x k grid of square holes of side `hole_fraction` / k
/// each centred in its grid cell (0 < hole_fraction < 1, k <= 4096), as one polygon: the
/// square counter-clockwise, then the holes clockwise, row after row. Area 1 - fraction^2
/// (1 when k = 0). Source "square_with_holes(k, hole_fraction)".
PolygonRings square_with_holes(std::uint32_t k, double hole_fraction);

// ---------------------------------------------------------------------------------------
// Tetrahedral meshes as read, before validation (validated: voroclip::Domain3, clip.h).

/// A tetrahedral mesh as given by a file: vertices (packed x y z), tets (4 vertex indices
/// each, 0-based, in the file's order and orientation), and, for boundary conditions and
/// materials, the triangles the file lists and the tags of tets and triangles.
///
/// Tags. A tag is a 32-bit integer, 0 meaning "untagged": Medit refs, TetGen region
/// attributes and face markers, Gmsh physical tags, the cell data `region` and `patch` of
/// VTK files (or meshio's `gmsh:physical` and `medit:ref`). A tag vector is either empty (every tag
/// 0: readers return it empty when the file has no tags or only zeros) or holds one tag per tet /
/// triangle.
struct TetMeshInput {
  /// Where it came from (a file name), for error messages.
  std::string source;
  std::vector<double> xyz;
  std::vector<std::uint32_t> tets;
  /// Per tet: the line of the file where it is defined (1-based; 0 when not known).
  std::vector<std::uint32_t> tet_line;
  /// Per tet: its region tag (empty: all 0).
  std::vector<std::int32_t> tet_ref;
  /// Triangles the file lists (boundary or interface faces, or any other): 3 vertex indices
  /// each, 0-based, in the file's order and orientation, all of them, whether or not they
  /// are faces of tets (except Medit's: the reader requires each to be a tet face).
  std::vector<std::uint32_t> triangles;
  /// Per triangle: its tag, the surface patch it belongs to (empty: all 0).
  std::vector<std::int32_t> triangle_ref;

  /// The name of a tag (Gmsh's $PhysicalNames): `dimension` 3 names a region (tet_ref), 2
  /// a patch (triangle_ref); other dimensions are kept as read.
  struct TagName {
    int dimension = 3;
    std::int32_t tag = 0;
    std::string name;
    bool operator==(const TagName& o) const {
      return dimension == o.dimension && tag == o.tag && name == o.name;
    }
  };
  /// Tag names in the file's order. Only Gmsh files carry them: the other formats neither
  /// write nor read names. Writers invent no default names (Gmsh and meshio do without:
  /// an unnamed physical group is a group all the same).
  std::vector<TagName> tag_names;

  /// How the file numbers its tets and vertices, so that messages (Domain3's) name them
  /// with the file's own numbers: tet t is "<tet_noun> <tet_label[t]>", vertex v is
  /// vertex_label[v] (Gmsh node tags), or v + vertex_base when vertex_label is empty;
  /// `numbering` says which for the messages ("Medit numbering, from 1"). The readers set
  /// them; a mesh built in code may leave them empty: "tet t" and vertex v, from 0.
  std::string tet_noun;                  // "tetrahedron", "element" (Gmsh), "cell" (VTK)
  std::vector<std::uint64_t> tet_label;  // per tet (empty: t)
  std::uint64_t vertex_base = 0;
  std::vector<std::uint64_t> vertex_label;  // per vertex (empty: v + vertex_base)
  std::string numbering;                    // empty: "numbered from 0"

  /// Elements of second order or higher read by their corners: Gmsh's 10-node (type 11)
  /// and higher tetrahedra (29..33) and 6-node (type 9) and higher triangles (20..25), VTK's
  /// quadratic tetra (24) and triangle (22), TetGen's 10-node tetrahedra, Medit's
  /// TetrahedraP2. They are tets and triangles with straight edges on those corners; their
  /// other nodes (mid-edge, ...) are vertices of no tet. 0 for a linear mesh.
  std::uint64_t nb_higher_order_tets = 0, nb_higher_order_triangles = 0;

  /// One scalar per vertex, from a .vtu's PointData (the array its Scalars attribute names,
  /// else its first array of one component); empty for the other formats and without one.
  /// point_data_name is the array's Name, point_data_line the line of its DataArray.
  std::vector<double> point_data;
  std::string point_data_name;
  std::uint32_t point_data_line = 0;

  std::uint32_t nb_vertices() const { return static_cast<std::uint32_t>(xyz.size() / 3); }
  std::uint32_t nb_tets() const { return static_cast<std::uint32_t>(tets.size() / 4); }
  std::uint32_t nb_triangles() const { return static_cast<std::uint32_t>(triangles.size() / 3); }
};

/// Reads a tetrahedral mesh, by extension (case-insensitive):
///   .mesh          Medit (INRIA) ASCII: keywords case-insensitive, '#' comments; the
///                  Vertices (x y z ref), Triangles (3 indices from 1, ref) and Tetrahedra
///                  (4 indices from 1, ref) sections, refs as tags (a triangle that
///                  repeats a vertex or is no tet's face is an error: its ref would
///                  tag nothing); other sections (Edges,
///                  Corners, Normals, ...) are read past by their counts;
///                  MeshVersionFormatted 1 to 4, Dimension 3;
///   .node / .ele   TetGen: either file may be given, the other is found beside it (same
///                  name, other extension); nodes numbered from 0 or 1 (the first node
///                  decides); 4 or 10 nodes per tetrahedron (10: the first 4 are used); the
///                  first tetrahedron attribute, an integer, is its region tag (further
///                  attributes and node markers are read and ignored); the triangles and
///                  their boundary markers come from the .face file beside them, when there
///                  is one; `source` is the .ele file;
///   .msh           Gmsh ASCII or binary, format 2.x (2.2) or 4.1: $Nodes and $Elements (4-node
///                  tetrahedra, element type 4, and 3-node triangles, type 2; other element
///                  types are skipped), node tags in any order and with gaps; the tag of an
///                  element is its physical tag (2.2: its first tag; 4.1: the first physical
///                  tag of its entity in $Entities, or $PartitionedEntities in a
///                  partitioned mesh, 0 when the entity has none or is not listed);
///                  $PhysicalNames gives tag_names; other sections are read past;
///                  binary files (file-type 1) in either byte order (the int 1 after the
///                  version line tells), 4.1 with a data-size (size_t) of 4 or 8; in them,
///                  elements of other types are read past by their type's node count, so
///                  types unknown to Gmsh 4.8 are rejected;
///   .vtk           legacy VTK ASCII or BINARY (big endian, of the types the lines name; no
///                  string or bit arrays), DATASET UNSTRUCTURED_GRID: POINTS, CELLS (classic or
///                  VTK 5.1 OFFSETS/CONNECTIVITY layout), CELL_TYPES; cells of type 10
///                  (VTK_TETRA) and 5 (VTK_TRIANGLE) are kept, others skipped; tags from
///                  CELL_DATA arrays (SCALARS or FIELD arrays of one component, integers):
///                  the tets' from `region`, else `gmsh:physical`, else `medit:ref`, the
///                  triangles' from `patch`, else `gmsh:physical`, else `medit:ref` (meshio
///                  names so the tags of a .msh or .mesh it converts); other data
///                  (`gmsh:geometrical`, ...) is read past;
///   .vtu           VTK XML UnstructuredGrid, one Piece: Points and the Cells arrays
///                  connectivity, offsets, types (tetra and triangle cells kept), CellData
///                  tags as for .vtk, each ascii, binary (inline base64) or
///                  appended (base64 or raw), UInt32 or UInt64 headers, either byte order,
///                  uncompressed or zlib-compressed (compressor="vtkZLibDataCompressor";
///                  LZ4 and LZMA are rejected); tet_line is the line of the connectivity
///                  array; PointData: one scalar array into point_data (see there).
/// Binary Medit files (.meshb) are rejected. Vertices keep the file's order (Gmsh: the
/// order of $Nodes), tetrahedra and triangles the file's order and orientation; tet_line is
/// 0 in binary .msh and .vtk files.
/// Throws Error "file:line: what" (or "file: what" for the whole file and in binary .msh
/// and .vtk files, naming the section, the element or the cell) for a missing file,
/// an unknown extension, format or version, a truncated section (which section, expected
/// and found counts), a value that is not a number or not finite, a tag that is not a
/// 32-bit integer, a vertex index out of range (naming the element as the file numbers
/// it: Medit's 1-based tetrahedron or triangle number, TetGen's tetrahedron or face number,
/// Gmsh's element tag, VTK's 0-based cell index), no tetrahedra; in binary data, a count or
/// a size that the bytes after it cannot hold (checked before anything is allocated), a
/// compressed block that does not inflate to the size its header gives.
TetMeshInput read_tet_mesh(const std::string& path);

/// As read_tet_mesh(path), from the bytes of a stream (read to its end): `name` stands
/// for the file, in messages and in `source`, and its extension tells the format (.mesh,
/// .msh, .vtk, .vtu). A TetGen mesh is several files: read_tetgen_mesh.
TetMeshInput read_tet_mesh(std::istream& in, const std::string& name);

/// A TetGen mesh from the streams of its .node and .ele files and, when `face` is not
/// nullptr, its .face file; `base` names them ("base.node", ...) in messages.
TetMeshInput read_tetgen_mesh(std::istream& node, std::istream& ele, std::istream* face,
                              const std::string& base);

/// Tetrahedral mesh file formats that write_tet_mesh can write. Every format keeps the
/// triangles and the tags; only Gmsh keeps tag_names.
enum class TetMeshFormat {
  kMedit,   // .mesh, MeshVersionFormatted 2, numbered from 1: Vertices (ref 0), Triangles
            // (when there are triangles) and Tetrahedra, refs the tags
  kTetGen,  // .node + .ele + .face (all written, whichever extension `path` has, and
            // all or none: write_files_atomically), numbered from 1; .ele has one region attribute
            // when tet_ref is not empty, .face the triangles (maybe none), with markers when
            // triangle_ref is not empty
  kGmsh22,  // .msh ASCII 2.2, node tags 1..n, element tags: tets 1..nt, then triangles;
            // each element's tags: physical = its tag, elementary = its entity (as 4.1)
  kGmsh41,  // .msh ASCII 4.1: one surface entity per distinct triangle tag and one volume
            // entity per distinct tet tag (increasing tags, entity tags from 1), each in
            // the physical group of its tag; all nodes in volume entity 1; tets (element
            // tags 1..nt) then triangles, one element block per run of equal tags
  kVtk,     // legacy ASCII .vtk: tets (VTK_TETRA) then triangles (VTK_TRIANGLE), cell
            // data "cell_id", "region" (when tet_ref is not empty), "patch" (when
            // triangle_ref is not empty)
  kVtu,     // VTK XML .vtu, binary: base64-encoded appended data (write_vtu), cells and
            // cell data as kVtk ("region"/"patch" Int32)
  kVtuAscii,       // VTK XML .vtu, ASCII data arrays (write_vtu), as kVtu
  kGmsh41Binary,   // .msh binary 4.1 (file-type 1, little endian, size_t of 8 bytes): as
                   // kGmsh41, $PhysicalNames in ASCII as Gmsh writes it
  kVtuCompressed,  // VTK XML .vtu, zlib-compressed appended data (VtuEncoding::kZlibBase64,
                   // compressor="vtkZLibDataCompressor"), as kVtu
};

/// Writes a tetrahedral mesh (all vertices, used or not, the tets and triangles in order
/// and orientation, their tags) so that read_tet_mesh reads back the same coordinates
/// (shortest round-trip decimals), tets, triangles and tags (a tag vector of zeros reads
/// back empty), and, from Gmsh files, tag_names. In the files, a tet's region is 0 on
/// triangles and a triangle's patch 0 on tets (VTK cell data), and tag 0 means no tag;
/// in Gmsh files, when any tag is not 0, entities of tag 0 are in physical group 0 (so
/// that readers such as meshio see one physical tag per element), otherwise no entity has
/// a physical group. The file appears whole or not at all (write_file_atomically).
/// Throws Error naming the file for an index out of range, a tag vector of the wrong size,
/// a write failure, and, in Gmsh formats, a negative tag or a tag name that Gmsh cannot
/// hold (a tag not above 0, a name with '"' or a line break).
void write_tet_mesh(const std::string& path, const TetMeshInput& mesh, TetMeshFormat format);

/// As above, the format chosen by the extension: .mesh, .node/.ele, .msh (4.1), .vtk, .vtu
/// (binary).
void write_tet_mesh(const std::string& path, const TetMeshInput& mesh);

/// The files write_tet_mesh(path, mesh, format) writes: `path`, or for TetGen the .node,
/// .ele and .face beside it (whichever of them `path` names), so that a caller can check
/// every one of them (check_output_path) before any work.
std::vector<std::string> tet_mesh_files(const std::string& path, TetMeshFormat format);

/// A named per-cell scalar of a .vtu file (one value per cell, written as Float64).
struct VtuCellField {
  std::string name;
  std::vector<double> values;
};

/// A named per-cell integer of a .vtu file (one value per cell, written as Int32): tags.
struct VtuCellTags {
  std::string name;
  std::vector<std::int32_t> values;
};

/// Cells of one kind for write_vtu: `nb_cells` cells of `vertices_per_cell` point indices
/// each (2: line segments, 3: triangles, 4: tetrahedra) at `indices`; or, with vertices_per_cell 0,
/// polygons (VTK_POLYGON): cell c has the indices [polygon_begin[c], polygon_begin[c + 1]) of
/// `indices` (polygon_begin: nb_cells + 1 offsets, the first 0).
struct VtuCellBlock {
  const std::uint32_t* indices = nullptr;
  std::size_t nb_cells = 0;
  int vertices_per_cell = 4;
  const std::uint32_t* polygon_begin = nullptr;
};

/// How write_vtu stores its data arrays.
enum class VtuEncoding {
  kAscii,       // in place, shortest round-trip decimals
  kBase64,      // appended, base64: per array its byte count, then its bytes, each
                // base64-encoded on its own, as VTK's reader expects
  kZlibBase64,  // appended, base64, compressor="vtkZLibDataCompressor" (meshio's and
                // ParaView's usual output): per array a header (number of blocks, block
                // size 32768, size of the last block, compressed size of each block), then
                // the blocks, each one zlib stream
};

/// Writes a VTK XML unstructured grid (version 1.0, UInt64 headers, little endian): the
/// points (z = 0 when dimension is 2), the cells of `blocks` one block after the other
/// (VTK_LINE for 2 vertices, VTK_TRIANGLE for 3, VTK_TETRA for 4), the cell index (counted
/// across blocks) as cell data "cell_id", then `fields` (Float64) and `tags` (Int32), and
/// `point_tags` (Int32, one value per point, as point data), the arrays stored as
/// `encoding` says. Coordinates are Float64 and indices Int64 in every encoding, so a file
/// read back gives the same doubles. Throws Error when a field or tag array does not have
/// one value per cell, or a point array one per point.
void write_vtu(std::ostream& out, const double* coords, std::uint32_t nb_points, int dimension,
               const std::vector<VtuCellBlock>& blocks, VtuEncoding encoding,
               const std::vector<VtuCellField>& fields = {},
               const std::vector<VtuCellTags>& tags = {},
               const std::vector<VtuCellTags>& point_tags = {});

/// write_tet_mesh(path, mesh, format) with, in the .vtu formats, `fields` after "cell_id"
/// (one value per tet, then per triangle; mesh3d's q1_min_dihedral_deg, mesh.h
/// tet_quality_fields); Error for another format with fields.
void write_tet_mesh(const std::string& path, const TetMeshInput& mesh, TetMeshFormat format,
                    const std::vector<VtuCellField>& fields);

/// As above: `binary` is VtuEncoding::kBase64, otherwise kAscii.
void write_vtu(std::ostream& out, const double* coords, std::uint32_t nb_points, int dimension,
               const std::vector<VtuCellBlock>& blocks, bool binary,
               const std::vector<VtuCellField>& fields = {},
               const std::vector<VtuCellTags>& tags = {});

/// As above, with cells of one kind: `cells` holds `vertices_per_cell` (3: triangles, 4:
/// tetrahedra) point indices per cell.
void write_vtu(std::ostream& out, const double* coords, std::uint32_t nb_points, int dimension,
               const std::vector<std::uint32_t>& cells, int vertices_per_cell, bool binary,
               const std::vector<VtuCellField>& fields = {});

// ---------------------------------------------------------------------------------------
// Triangle surfaces: files, the boundary of a tet mesh, closest-point queries and sharp
// feature lines (surface_io.cpp, surface_tree.cpp, feature_lines.cpp).

/// A triangle surface as read (or built): vertices packed x y z, triangles as 3 vertex
/// indices each (0-based), in the file's order and orientation.
struct TriangleSurface {
  /// Where it came from (a file name, or what built it), for messages.
  std::string source;
  std::vector<double> xyz;
  std::vector<std::uint32_t> triangles;
  /// Per triangle: the line of the file where its face is defined (1-based; 0 for binary
  /// files and built surfaces). A polygon fan-triangulated into k triangles gives k equal
  /// entries.
  std::vector<std::uint32_t> triangle_line;
  /// For messages, how the file numbers its elements: per triangle, the number of its face
  /// as the file counts faces (OBJ from 1, OFF, PLY and STL from 0; a polygon split into k
  /// triangles gives k equal entries; empty for built surfaces: triangles are then named by
  /// their index from 0), and the number the file gives its first vertex (OBJ 1, else 0).
  std::vector<std::uint32_t> triangle_face;
  std::uint32_t vertex_base = 0;

  std::uint32_t nb_vertices() const { return static_cast<std::uint32_t>(xyz.size() / 3); }
  std::uint32_t nb_triangles() const { return static_cast<std::uint32_t>(triangles.size() / 3); }
};

/// Reads a triangle surface, by extension (case-insensitive):
///   .obj  Wavefront: `v x y z [w] [r g b]` and `f` with 3 or more corners, each `v`,
///         `v/t`, `v//n` or `v/t/n`, 1-based or negative (relative to the last vertex read);
///         every other statement (vn, vt, g, o, s, usemtl, mtllib, l, p...) is ignored;
///         `\` at the end of a line continues it; '#' comments;
///   .off  OFF, COFF, NOFF, CNOFF (Geomview): the counts, the vertices (x y z, then colours
///         or normals, ignored), the faces (`k i0 .. ik-1`, then an optional colour); '#'
///         comments; vertices numbered from 0;
///   .stl  binary (80-byte header, count, 50 bytes per triangle; recognised by the size
///         84 + 50 n, whatever the header says) or ASCII (`solid` ... `facet normal` ...
///         `outer loop` 3 x `vertex x y z` `endloop` `endfacet` ... `endsolid`); STL has no
///         shared vertices: vertices with equal coordinates are merged (the first one's
///         index is kept, in order of appearance); facet normals are ignored;
///   .ply  ASCII, binary_little_endian or binary_big_endian 1.0: the `vertex` element's x,
///         y, z properties (any numeric type) and the `face` element's list property
///         `vertex_indices` (or `vertex_index`); other properties and elements are read
///         past (their types are known from the header).
/// Polygons with k > 3 corners become the fan (c0, ci, ci+1), i = 1 .. k - 2. Vertices keep
/// the file's order (STL: order of first appearance), unused vertices included.
/// Throws Error "file:line: what" (binary files: "file: face N: what") for a missing file,
/// an unknown extension, a bad header, a value that is not a (finite) number, a truncated
/// file (what was expected, what was found), a face with fewer than 3 corners or a vertex
/// index out of range (naming the face as the file numbers it, from 1 in OBJ and from 0 in
/// OFF/PLY, and the index as written), no triangles. Degenerate triangles (repeated or
/// collinear vertices) are kept: a reader does not judge geometry.
TriangleSurface read_surface(const std::string& path);

/// As read_surface(path), from the bytes of a stream (read to its end): `name` stands for
/// the file, in messages and in `source`, and its extension tells the format.
TriangleSurface read_surface(std::istream& in, const std::string& name);

/// Triangle surface formats that write_surface can write.
enum class SurfaceFormat {
  kObj,        // v / f lines, 1-based
  kOff,        // OFF, counts then vertices and faces
  kStlAscii,   // solid / facet normal / outer loop, normals from the triangles
  kStlBinary,  // 80-byte header; coordinates rounded to float32 (the format's type)
  kPlyAscii,   // ply / format ascii 1.0, vertex x y z double, face list uchar int
  kPlyBinary,  // ply / format binary_little_endian 1.0, same properties
};

/// Writes a surface so that read_surface reads back the same triangles and the same
/// coordinates (shortest round-trip decimals in the text formats, exact doubles in binary
/// PLY; float32 in binary STL). STL has no vertex indices: reading back merges equal
/// coordinates, so unused and duplicate vertices do not survive. The file appears whole or
/// not at all. Throws Error naming the file for an index out of range or a write failure.
void write_surface(const std::string& path, const TriangleSurface& surface, SurfaceFormat format);

/// As above, the format chosen by the extension: .obj, .off, .stl (binary), .ply (binary).
void write_surface(const std::string& path, const TriangleSurface& surface);

/// The boundary of a tet mesh: the facets that belong to exactly one tet (compared as
/// vertex sets), in the order (tet, facet), facet k opposite tet vertex k, with the mesh's
/// vertex array (unused vertices included). Facet k of tet (v0, v1, v2, v3) is written
/// (v1, v2, v3), (v0, v3, v2), (v0, v1, v3), (v0, v2, v1) for k = 0..3: outward by the
/// right-hand rule when the tet has det(v1 - v0, v2 - v0, v3 - v0) > 0 (TetGen's and the
/// shared data's orientation), inward for tets oriented the other way. Facets shared by
/// three or more tets are not boundary; triangle_line is the tet's line. O(n log n).
TriangleSurface tet_mesh_boundary(const TetMeshInput& mesh);

/// Closest points on a triangle surface, for snapping and re-projecting points onto it.
///
/// A bounding-volume hierarchy over the triangles (binned surface-area heuristic, leaves of
/// up to 2 triangles, their corners copied in leaf order), built once in O(n log n). A query visits
/// the nearer child first and skips every box farther than the best distance so far. Distances are
/// computed in double precision by the region test of the point against the triangle's vertices and
/// edges, then its plane: a few ulps of relative error, no epsilon; a triangle of zero area counts
/// as its three edges. The answer is the pair (squared distance, triangle index) that is smallest
/// in lexicographic order, so it does not depend on the traversal or on the hint: ties (a closest
/// point on an edge or vertex shared by several triangles) go to the lowest triangle index. Queries
/// are const and thread-safe.
class SurfaceTree {
 public:
  static constexpr std::uint32_t kNone = 0xffffffffu;

  /// Where the closest point lies on its triangle.
  enum class Feature : std::uint8_t {
    kFace,    // inside the triangle
    kEdge,    // on edge `index` (opposite corner `index`, from corner index+1 to index+2)
    kVertex,  // at corner `index`
  };

  struct Closest {
    double point[3] = {0, 0, 0};
    double distance2 = 0;  // squared distance from the query point
    std::uint32_t triangle = kNone;
    Feature feature = Feature::kFace;
    std::uint8_t index = 0;
    /// The unit pseudo-normal at the point (Baerentzen and Aanaes 2005): the triangle's
    /// normal inside it, the normalised sum of the normals of the triangles sharing the
    /// edge on an edge, the angle-weighted mean of the normals around the vertex at a
    /// vertex. Orientation by the right-hand rule of the triangles, so outward for an
    /// outward surface; the sign of dot(query - point, normal) tells the side then. Zero
    /// only where every triangle around is degenerate.
    double normal[3] = {0, 0, 0};
  };

  SurfaceTree() = default;
  /// Copies what it needs from `surface` (which may then go away). Throws Error for an
  /// index out of range or a non-finite coordinate of a used vertex; an empty surface
  /// gives a tree whose queries return triangle == kNone.
  explicit SurfaceTree(const TriangleSurface& surface);

  /// The closest point of the surface to p (triangle == kNone for a non-finite p, or when
  /// the squared distance overflows).
  Closest closest(const double* p) const { return closest(p, kNone); }
  /// The same answer, usually faster when `hint` is a triangle near the answer (the
  /// previous answer for a point that moved a little): its distance bounds the search.
  Closest closest(const double* p, std::uint32_t hint) const;

  std::uint32_t nb_triangles() const { return static_cast<std::uint32_t>(leaf_triangle_.size()); }
  /// The unit normal of triangle t (input index) by the right-hand rule, zero if degenerate.
  const double* triangle_normal(std::uint32_t t) const { return &face_normal_[3 * std::size_t{t}]; }
  /// Bounding box of the triangles' corners (zeros for an empty surface).
  const double* bbox_lo() const { return bbox_; }
  const double* bbox_hi() const { return bbox_ + 3; }

 private:
  struct Node {
    double lo[3], hi[3];
    // Leaf: triangles [first, first + count) in leaf order; inner: children first and
    // first + 1, count == 0.
    std::uint32_t first, count;
  };
  std::vector<Node> nodes_;
  std::vector<double> corners_;               // 9 per triangle, leaf order
  std::vector<std::uint32_t> leaf_triangle_;  // leaf order -> input index
  std::vector<std::uint32_t> leaf_of_;        // input index -> leaf order
  std::vector<std::uint32_t> triangles_;      // 3 per triangle, input order
  std::vector<double> face_normal_;           // 3 per triangle, input order
  std::vector<double> edge_normal_;           // 9 per triangle, input order: edge e's normal
  std::vector<double> vertex_normal_;         // 3 per surface vertex
  double bbox_[6] = {0, 0, 0, 0, 0, 0};
};

/// Sharp feature lines of a triangle surface, for meshing with crisp edges and corners.
///
/// An edge is sharp when the angle between the normals of its two triangles exceeds
/// `feature_angle_deg` (i.e. its dihedral angle is below 180 - feature_angle_deg); an edge
/// not shared by exactly two triangles (a border or a non-manifold edge) is always a
/// feature; an edge of a zero-area triangle (no normal) shared by two triangles is not. Corners are
/// the vertices where a number of feature edges other than 0 and 2 meet. Feature edges are chained
/// into lines: each line runs from a corner to a corner (possibly the same) through vertices with
/// exactly two feature edges; feature edges left over form closed loops (first vertex == last
/// vertex, closed). Lines start at corners in increasing vertex order, along their edges in
/// increasing order of the other vertex; loops start at their lowest vertex, towards its lower
/// neighbour.
struct FeatureLines {
  /// Vertices (surface indices) of line l: line_vertices[line_begin[l] .. line_begin[l+1]).
  std::vector<std::uint32_t> line_begin{0};
  std::vector<std::uint32_t> line_vertices;
  /// Per line: 1 for a closed loop without corner (its last vertex repeats its first).
  std::vector<std::uint8_t> line_closed;
  /// Corner vertices, increasing.
  std::vector<std::uint32_t> corners;
  std::uint32_t nb_feature_edges = 0;

  std::uint32_t nb_lines() const { return static_cast<std::uint32_t>(line_closed.size()); }
};

/// The angle between the normals above which an edge is sharp, by default: 40 degrees
/// (a dihedral angle below 140 degrees). On fandisk it keeps every crease of the part and
/// nothing of its smooth faces (see the tests).
constexpr double kDefaultFeatureAngleDeg = 40.0;

/// Extracts the feature lines of `surface` (see FeatureLines). O(n log n). With
/// `triangle_tag` (one per triangle, or empty), an edge between two triangles of different
/// tags is a feature edge too, however flat: the borders of tagged patches (boundary
/// conditions) become lines that a mesh keeps.
FeatureLines extract_feature_lines(const TriangleSurface& surface,
                                   double feature_angle_deg = kDefaultFeatureAngleDeg,
                                   const std::vector<std::int32_t>& triangle_tag = {});

/// Closest points on feature lines, and their arclength parametrisation. A hierarchy of
/// boxes over each line's segments; thread-safe const queries; ties go to the lowest
/// (line, segment).
class FeatureTree {
 public:
  struct Closest {
    double point[3] = {0, 0, 0};
    double distance2 = 0;
    std::uint32_t line = SurfaceTree::kNone;
    std::uint32_t segment = 0;      // between the line's vertices segment and segment + 1
    double t = 0;                   // in [0, 1] along the segment
    double arclength = 0;           // from the line's first vertex
    double tangent[3] = {0, 0, 0};  // unit, along the line's direction (zero: empty segment)
  };

  FeatureTree() = default;
  FeatureTree(const TriangleSurface& surface, const FeatureLines& lines);

  /// The closest point on any line (line == kNone when there is none) / on line `line`.
  Closest closest(const double* p) const;
  Closest closest(const double* p, std::uint32_t line) const;

  std::uint32_t nb_lines() const { return static_cast<std::uint32_t>(line_node_.size()); }
  bool closed(std::uint32_t line) const { return closed_[line] != 0; }
  double length(std::uint32_t line) const { return arclength_[point_begin_[line + 1] - 1]; }
  /// The point at arclength s on a line (clamped to [0, length]; wrapped for a closed
  /// line) and, optionally, the unit tangent there.
  void eval(std::uint32_t line, double s, double* xyz, double* tangent = nullptr) const;

 private:
  struct Node {
    double lo[3], hi[3];
    std::uint32_t first, count;  // as SurfaceTree::Node, over segments
  };
  Closest closest_on(const double* p, std::uint32_t line, double best2) const;
  std::vector<double> points_;                 // 3 per line vertex, lines one after another
  std::vector<double> arclength_;              // per line vertex
  std::vector<std::uint32_t> point_begin_{0};  // per line + 1
  std::vector<std::uint8_t> closed_;
  std::vector<Node> nodes_;
  std::vector<std::uint32_t> line_node_;  // root node of each line's tree
  std::vector<std::uint32_t> segments_;   // leaf order -> segment (global first point index)
};

// ---------------------------------------------------------------------------------------
// Tables of the cells of a clipped Voronoi diagram (cell_table_io.cpp), as clip2d and
// clip3d write them (-o cells.csv, --neighbors pairs.csv); clip.h fills them (cell_table,
// cell_neighbors). The columns, by name (2D | 3D), in order:
//   cells      site (the cell's index = the site's, 0-based, in input order), x, y[, z]
//              (the site), area | volume, centroid_x, centroid_y[, centroid_z] (mass
//              centroid; the site for an empty cell), energy (the CVT energy term
//              ∫rho |x - site|^2 over the cell), boundary (1 when the cell meets the domain's
//              boundary, else 0), neighbors (the number of cells it shares an edge | a face
//              with), and in 3D surface_area (its area on the domain's boundary);
//   neighbors  site_a, site_b (site_a < site_b: each pair once), length | area (of the
//              boundary the two cells share, on their bisector).
// Numbers are written as the shortest decimals that read back as the same doubles.

struct CellTable {
  int dimension = 2;
  std::vector<double> sites;      // `dimension` values per cell
  std::vector<double> measure;    // area (2D) or volume (3D)
  std::vector<double> centroids;  // `dimension` values per cell
  std::vector<double> energy;
  std::vector<std::uint8_t> boundary;
  std::vector<std::uint32_t> nb_neighbors;  // empty: the column is not written
  std::vector<double> surface_area;         // 3D; empty: the column is not written
  std::uint32_t nb_cells() const { return static_cast<std::uint32_t>(measure.size()); }
};

struct NeighborTable {
  int dimension = 2;
  std::vector<std::uint32_t> pairs;  // site_a, site_b per row, site_a < site_b, sorted
  std::vector<double> measure;       // per row: length (2D) or area (3D)
  std::uint32_t nb_pairs() const { return static_cast<std::uint32_t>(measure.size()); }
};

/// CSV with a header line, one row per cell, columns as above.
void write_cell_table_csv(std::ostream& out, const CellTable& table);
/// CSV with a header line, one row per pair.
void write_neighbor_table_csv(std::ostream& out, const NeighborTable& table);
/// JSON: {"neighbors": [{"site_a": 0, "site_b": 3, "length": 0.25}, ...]} ("area" in 3D).
void write_neighbor_table_json(std::ostream& out, const NeighborTable& table);

}  // namespace voroclip
