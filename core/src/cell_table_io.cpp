// Tables of the cells of a clipped Voronoi diagram (core.h, "Tables of the cells"): CSV and
// JSON writers. The values come from clip.h (cell_table, cell_neighbors); this file only
// formats them.
#include <charconv>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "voroclip/core.h"

namespace voroclip {

namespace {

// Shortest decimal text that reads back as the same double, independent of the locale.
void put(std::ostream& out, double x) {
  char buffer[64];
  const std::to_chars_result r = std::to_chars(buffer, buffer + sizeof buffer, x);
  out.write(buffer, r.ptr - buffer);
}

void check_sizes(const CellTable& t) {
  const std::size_t n = t.measure.size(), d = static_cast<std::size_t>(t.dimension);
  if ((t.dimension != 2 && t.dimension != 3) || t.sites.size() != d * n ||
      t.centroids.size() != d * n || t.energy.size() != n || t.boundary.size() != n ||
      (!t.nb_neighbors.empty() && t.nb_neighbors.size() != n) ||
      (!t.surface_area.empty() && t.surface_area.size() != n)) {
    throw Error("write_cell_table: the columns do not have one value per cell");
  }
}

void check_sizes(const NeighborTable& t) {
  if ((t.dimension != 2 && t.dimension != 3) || t.pairs.size() != 2 * t.measure.size()) {
    throw Error("write_neighbor_table: the columns do not have one value per pair");
  }
}

}  // namespace

void write_cell_table_csv(std::ostream& out, const CellTable& table) {
  check_sizes(table);
  const bool three = table.dimension == 3;
  out << (three ? "site,x,y,z,volume,centroid_x,centroid_y,centroid_z,energy,boundary"
                : "site,x,y,area,centroid_x,centroid_y,energy,boundary");
  if (!table.nb_neighbors.empty()) out << ",neighbors";
  if (!table.surface_area.empty()) out << ",surface_area";
  out << '\n';
  const std::size_t d = three ? 3 : 2;
  for (std::uint32_t i = 0; i < table.nb_cells(); ++i) {
    out << i;
    for (std::size_t k = 0; k < d; ++k) {
      out << ',';
      put(out, table.sites[d * i + k]);
    }
    out << ',';
    put(out, table.measure[i]);
    for (std::size_t k = 0; k < d; ++k) {
      out << ',';
      put(out, table.centroids[d * i + k]);
    }
    out << ',';
    put(out, table.energy[i]);
    out << ',' << (table.boundary[i] != 0 ? 1 : 0);
    if (!table.nb_neighbors.empty()) out << ',' << table.nb_neighbors[i];
    if (!table.surface_area.empty()) {
      out << ',';
      put(out, table.surface_area[i]);
    }
    out << '\n';
  }
}

void write_neighbor_table_csv(std::ostream& out, const NeighborTable& table) {
  check_sizes(table);
  out << (table.dimension == 3 ? "site_a,site_b,area\n" : "site_a,site_b,length\n");
  for (std::uint32_t r = 0; r < table.nb_pairs(); ++r) {
    out << table.pairs[2 * std::size_t{r}] << ',' << table.pairs[2 * std::size_t{r} + 1] << ',';
    put(out, table.measure[r]);
    out << '\n';
  }
}

void write_neighbor_table_json(std::ostream& out, const NeighborTable& table) {
  check_sizes(table);
  const char* measure = table.dimension == 3 ? "area" : "length";
  nlohmann::json rows = nlohmann::json::array();
  for (std::uint32_t r = 0; r < table.nb_pairs(); ++r) {
    rows.push_back({{"site_a", table.pairs[2 * std::size_t{r}]},
                    {"site_b", table.pairs[2 * std::size_t{r} + 1]},
                    {measure, table.measure[r]}});
  }
  out << nlohmann::json{{"neighbors", std::move(rows)}}.dump(1) << '\n';
}

}  // namespace voroclip
