// Point files: JSON arrays of points, or text with one point per line.
#include <cctype>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <nlohmann/json.hpp>
#include <ostream>
#include <sstream>
#include <string>

#include "text_lexer.h"
#include "voroclip/core.h"

namespace voroclip {

namespace {

std::vector<double> read_json_points(std::istream& in, const std::string& path, int dimension) {
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(in);
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

std::vector<double> read_text_points(std::istream& in, const std::string& path, int dimension) {
  std::vector<double> out;
  std::string line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    const std::size_t hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream fields(line);
    fields.imbue(std::locale::classic());
    std::string field;
    int count = 0;
    while (fields >> field) {
      const std::string where = path + ":" + std::to_string(number) + ": ";
      if (count == dimension) {
        throw Error(where + "more than " + std::to_string(dimension) + " coordinates");
      }
      std::size_t used = 0;
      double v = 0;
      try {
        v = std::stod(field, &used);
      } catch (const std::exception&) {
        throw Error(where + "'" + field + "' is not a number");
      }
      if (used != field.size()) throw Error(where + "'" + field + "' is not a number");
      if (!std::isfinite(v)) throw Error(where + "'" + field + "' is not a finite number");
      out.push_back(v);
      ++count;
    }
    if (count != 0 && count != dimension) {
      throw Error(path + ":" + std::to_string(number) + ": expected " + std::to_string(dimension) +
                  " coordinates, found " + std::to_string(count));
    }
  }
  if (in.bad()) throw Error(path + ": read error");
  return out;
}

}  // namespace

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
  char first = 0;
  while (in.get(first) && std::isspace(static_cast<unsigned char>(first))) {
  }
  if (!in) throw Error(path + ": the file holds no points");
  in.unget();
  return first == '[' ? read_json_points(in, path, dimension)
                      : read_text_points(in, path, dimension);
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
