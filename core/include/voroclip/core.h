// voroclip/core.h — what every module shares: the one error type, the library version,
// and output files that appear whole or not at all.
#pragma once

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

/// Writes a file so that it is either complete or absent: the content goes to a temporary
/// file beside `path`, which is renamed over `path` only after `write` returned and the
/// stream was flushed without error. If `write` throws, or anything fails, the temporary is
/// removed, `path` is left as it was, and an Error naming the file is thrown (the exception
/// thrown by `write` is rethrown unchanged).
void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& write);

/// Reads points of `dimension` (2 or 3) coordinates, returned packed (x y [z] per point),
/// from either format, recognised by the first non-blank character:
///   - JSON: an array of points, each an array of `dimension` numbers: [[0, 1.5], [2, 3]]
///   - text: one point per line, `dimension` numbers separated by blanks; empty lines and
///     everything after '#' are ignored.
/// Throws Error naming the file and the line (text) or the point (JSON) and what is wrong:
/// a missing file, a value that is not a finite number, a wrong number of coordinates.
std::vector<double> read_points(const std::string& path, int dimension);

/// Writes a legacy ASCII VTK unstructured grid (readable by ParaView): the points (z = 0
/// in 2D) and the cells, `vertices_per_cell` point indices each (3: triangles, 4:
/// tetrahedra), with the cell index as cell data "cell_id".
void write_vtk(std::ostream& out, const std::string& title, const double* coords,
               std::uint32_t nb_points, int dimension, const std::vector<std::uint32_t>& cells,
               int vertices_per_cell);

}  // namespace voroclip
