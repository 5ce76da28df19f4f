// Point files: JSON arrays of points, or text with one point per line.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <limits>
#include <nlohmann/json.hpp>
#include <ostream>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "text_lexer.h"
#include "voroclip/core.h"

namespace voroclip {

namespace {

std::vector<double> read_json_points(const std::string& text, const std::string& path,
                                     int dimension) {
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {  // a syntax error, or a number overflow
    throw Error(path + ": not valid JSON: " + e.what());
  }
  if (!doc.is_array()) throw Error(path + ": expected a JSON array of points");
  std::vector<double> out;
  out.reserve(doc.size() * static_cast<std::size_t>(dimension));
  for (std::size_t i = 0; i < doc.size(); ++i) {
    const auto& p = doc[i];
    if (!p.is_array() || p.size() != static_cast<std::size_t>(dimension)) {
      throw Error(path + ": point " + std::to_string(i) + " (from 0) is not an array of " +
                  std::to_string(dimension) + " numbers");
    }
    for (const auto& x : p) {
      if (!x.is_number()) {
        throw Error(path + ": point " + std::to_string(i) +
                    " (from 0) has a coordinate that is not a number");
      }
      const double v = x.get<double>();
      if (!std::isfinite(v)) {
        throw Error(path + ": point " + std::to_string(i) +
                    " (from 0) has a non-finite coordinate");
      }
      out.push_back(v);
    }
  }
  return out;
}

// The fields of a line: separated by commas when it holds one (CSV; blanks around a field
// are dropped), else by blanks.
std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> out;
  const auto blank = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  if (line.find(',') != std::string_view::npos) {
    for (std::size_t begin = 0;;) {
      const std::size_t comma = std::min(line.find(',', begin), line.size());
      std::string_view f = line.substr(begin, comma - begin);
      while (!f.empty() && blank(f.front())) f.remove_prefix(1);
      while (!f.empty() && blank(f.back())) f.remove_suffix(1);
      out.push_back(f);
      if (comma == line.size()) break;
      begin = comma + 1;
    }
    return out;
  }
  for (std::size_t i = 0; i < line.size();) {
    while (i < line.size() && blank(line[i])) ++i;
    const std::size_t begin = i;
    while (i < line.size() && !blank(line[i])) ++i;
    if (i > begin) out.push_back(line.substr(begin, i - begin));
  }
  return out;
}

// A header line names the columns: the first line that holds anything, when none of its
// fields is a number and it names the columns x and y (and z in 3D), as the .csv outputs
// of cvt2d/cvt3d (x,y,z) and the cell tables (site,x,y,z,volume,...) do. Names may be
// quoted ("x") and are compared case-insensitively. Sets `column` to the field index of
// each coordinate; false when the line is not such a header.
bool read_header(const std::vector<std::string_view>& fields, int dimension,
                 const std::string& where, std::size_t column[3]) {
  std::size_t found[3] = {SIZE_MAX, SIZE_MAX, SIZE_MAX};
  for (std::size_t i = 0; i < fields.size(); ++i) {
    std::string_view f = fields[i];
    double v = 0;
    const auto r = std::from_chars(f.data(), f.data() + f.size(), v);
    if (!f.empty() && (r.ec == std::errc() || r.ec == std::errc::result_out_of_range)) {
      return false;  // a number: a line of data
    }
    if (f.size() >= 2 && f.front() == '"' && f.back() == '"') f = f.substr(1, f.size() - 2);
    const std::string name = detail::lower(f);
    for (int k = 0; k < 3; ++k) {
      if (name.size() == 1 && name[0] == "xyz"[k] && found[k] == SIZE_MAX) found[k] = i;
    }
  }
  if (found[0] == SIZE_MAX || found[1] == SIZE_MAX) return false;
  if (dimension == 2 && found[2] != SIZE_MAX) {
    throw Error(where + "the header names a column z: 3D points, 2D expected");
  }
  if (dimension == 3 && found[2] == SIZE_MAX) {
    throw Error(where + "the header names no column z: 2D points, 3D expected");
  }
  std::copy(found, found + 3, column);
  return true;
}

// One point per line: `dimension` numbers separated by blanks or by commas, '#' comments,
// empty lines ignored; or, after a header line naming the columns (read_header), the
// columns x, y (, z) of lines of as many fields as the header (a CSV table). Lines end in
// LF, CRLF or CR.
std::vector<double> read_text_points(const std::string& text, const std::string& path,
                                     int dimension) {
  std::vector<double> out;
  const auto dim = static_cast<std::size_t>(dimension);
  bool first = true;
  std::size_t nb_columns = 0;  // 0: no header
  std::size_t column[3] = {0, 1, 2};
  std::size_t pos = 0;
  for (std::size_t number = 1; pos < text.size(); ++number) {
    std::size_t eol = text.find_first_of("\r\n", pos);
    if (eol == std::string::npos) eol = text.size();
    std::string_view line = std::string_view(text).substr(pos, eol - pos);
    pos = eol + (text.compare(eol, 2, "\r\n") == 0 ? 2 : 1);
    line = line.substr(0, line.find('#'));
    const std::vector<std::string_view> fields = split_fields(line);
    if (fields.empty()) continue;
    const std::string where = path + ":" + std::to_string(number) + ": ";
    if (first) {
      first = false;
      if (read_header(fields, dimension, where, column)) {
        nb_columns = fields.size();
        continue;
      }
    }
    if (nb_columns != 0 && fields.size() != nb_columns) {
      throw Error(where + "expected " + std::to_string(nb_columns) +
                  " fields, as the header names, found " + std::to_string(fields.size()));
    }
    if (nb_columns == 0 && fields.size() > dim) {
      throw Error(where + "more than " + std::to_string(dimension) + " coordinates");
    }
    if (nb_columns == 0 && fields.size() < dim) {
      throw Error(where + "expected " + std::to_string(dimension) + " coordinates, found " +
                  std::to_string(fields.size()));
    }
    for (std::size_t k = 0; k < dim; ++k) {
      const std::string_view f = fields[column[k]];
      if (f.empty()) {
        throw Error(where + "field " + std::to_string(column[k] + 1) + " is empty");
      }
      std::string_view s = f;
      if (s.size() > 1 && s[0] == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
      double v = 0;
      // Hexadecimal floats (0x1p-2) as strtod reads them, which from_chars does not.
      if (s.size() > 2 && (s.substr(0, 2) == "0x" || s.substr(0, 3) == "-0x")) {
        const std::string str(s);
        char* end = nullptr;
        v = std::strtod(str.c_str(), &end);
        if (end != str.c_str() + str.size()) {
          throw Error(where + detail::quote(f) + " is not a number");
        }
      } else {
        const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
        if (r.ec == std::errc::result_out_of_range) {
          throw Error(where + detail::quote(f) + " is out of the range of a double");
        }
        if (r.ec != std::errc() || r.ptr != s.data() + s.size()) {
          throw Error(where + detail::quote(f) + " is not a number");
        }
      }
      if (!std::isfinite(v)) throw Error(where + detail::quote(f) + " is not a finite number");
      out.push_back(v);
    }
  }
  return out;
}

}  // namespace

std::string read_text_file(const std::string& path) {
  std::string text = detail::read_whole_file(path);
  detail::prepare_input(path, text);
  return text;
}

std::vector<double> read_points(const std::string& path, int dimension) {
  if (dimension != 2 && dimension != 3) {
    throw Error("read_points: dimension must be 2 or 3, got " + std::to_string(dimension));
  }
  detail::check_not_directory(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open the file");
  return read_points(in, path, dimension);
}

std::vector<double> read_points(std::istream& in, const std::string& path, int dimension) {
  if (dimension != 2 && dimension != 3) {
    throw Error("read_points: dimension must be 2 or 3, got " + std::to_string(dimension));
  }
  std::string text = detail::read_whole_stream(in, path);
  detail::prepare_input(path, text);
  const std::size_t first = text.find_first_not_of(" \t\r\n\v\f");
  if (first == std::string::npos) throw Error(path + ": the file holds no points");
  // '{': a JSON object (a cell table written as .json) is reported as not an array.
  return text[first] == '[' || text[first] == '{' ? read_json_points(text, path, dimension)
                                                  : read_text_points(text, path, dimension);
}

void write_vtk(std::ostream& out, const std::string& title, const double* coords,
               std::uint32_t nb_points, int dimension, const std::vector<std::uint32_t>& cells,
               int vertices_per_cell) {
  const auto dim = static_cast<std::size_t>(dimension);
  const auto per = static_cast<std::size_t>(vertices_per_cell);
  const std::size_t nb_cells = cells.size() / per;
  out.imbue(std::locale::classic());
  out << "# vtk DataFile Version 3.0\n" << title << "\nASCII\nDATASET UNSTRUCTURED_GRID\n";
  out << "POINTS " << nb_points << " double\n" << std::setprecision(17);
  for (std::size_t i = 0; i < nb_points; ++i) {
    out << coords[dim * i] << ' ' << coords[dim * i + 1] << ' '
        << (dimension == 3 ? coords[dim * i + 2] : 0.0) << '\n';
  }
  out << "CELLS " << nb_cells << ' ' << nb_cells * (per + 1) << '\n';
  for (std::size_t c = 0; c < nb_cells; ++c) {
    out << per;
    for (std::size_t k = 0; k < per; ++k) out << ' ' << cells[c * per + k];
    out << '\n';
  }
  const int type = vertices_per_cell == 4 ? 10 : 5;  // VTK_TETRA, VTK_TRIANGLE
  out << "CELL_TYPES " << nb_cells << '\n';
  for (std::size_t c = 0; c < nb_cells; ++c) out << type << '\n';
  out << "CELL_DATA " << nb_cells << "\nSCALARS cell_id int 1\nLOOKUP_TABLE default\n";
  for (std::size_t c = 0; c < nb_cells; ++c) out << c << '\n';
}

}  // namespace voroclip
