// The `voroclip predicate NAME COORDS... [--sos I...]` command: evaluates one exact
// predicate of voroclip/predicates.h on points given on the command line.
#include <cstddef>
#include <cstdint>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli.h"
#include "voroclip/predicates.h"

namespace voroclip::cli {
namespace {

struct PredicateShape {
  const char* name;
  std::size_t points;
  std::size_t dimension;
};

constexpr PredicateShape kShapes[] = {
    {"orient2d", 3, 2},
    {"incircle", 4, 2},
    {"orient3d", 4, 3},
    {"insphere", 5, 3},
};

const PredicateShape& find_shape(const std::string& name) {
  for (const PredicateShape& shape : kShapes) {
    if (name == shape.name) return shape;
  }
  throw UsageError("unknown predicate '" + name +
                   "' (expected orient2d, incircle, orient3d or insphere)");
}

Sign evaluate(const std::string& name, const std::vector<const double*>& p) {
  if (name == "orient2d") return orient2d(p[0], p[1], p[2]);
  if (name == "incircle") return incircle(p[0], p[1], p[2], p[3]);
  if (name == "orient3d") return orient3d(p[0], p[1], p[2], p[3]);
  return insphere(p[0], p[1], p[2], p[3], p[4]);
}

Sign evaluate_sos(const std::string& name, const std::vector<const double*>& p,
                  const std::vector<std::uint32_t>& i) {
  if (name == "orient2d") return orient2d_sos(p[0], p[1], p[2], i[0], i[1], i[2]);
  if (name == "incircle") return incircle_sos(p[0], p[1], p[2], p[3], i[0], i[1], i[2], i[3]);
  if (name == "orient3d") return orient3d_sos(p[0], p[1], p[2], p[3], i[0], i[1], i[2], i[3]);
  return insphere_sos(p[0], p[1], p[2], p[3], p[4], i[0], i[1], i[2], i[3], i[4]);
}

}  // namespace

void run_predicate(const PredicateArgs& args, const GlobalOptions& options) {
  const PredicateShape& shape = find_shape(args.name);
  const std::size_t expected = shape.points * shape.dimension;
  if (args.coordinates.size() != expected) {
    throw UsageError(args.name + " takes " + std::to_string(expected) + " coordinates (" +
                     std::to_string(shape.points) + " points in " +
                     std::to_string(shape.dimension) + "D), got " +
                     std::to_string(args.coordinates.size()));
  }
  std::vector<double> coordinates;
  for (std::size_t k = 0; k < expected; ++k) {
    coordinates.push_back(
        parse_finite_double(args.coordinates[k], "coordinate " + std::to_string(k + 1)));
  }
  std::vector<const double*> points;
  for (std::size_t k = 0; k < shape.points; ++k) {
    points.push_back(coordinates.data() + k * shape.dimension);
  }

  Sign sign;
  if (args.sos) {
    if (args.sos_indices.size() != shape.points) {
      throw UsageError("--sos takes " + std::to_string(shape.points) + " indices for " + args.name +
                       " (one per point), got " + std::to_string(args.sos_indices.size()));
    }
    std::vector<std::uint32_t> indices;
    for (const std::string& text : args.sos_indices) {
      const std::uint32_t index = parse_index(text, "--sos index");
      for (const std::uint32_t previous : indices) {
        if (previous == index) {
          throw UsageError("--sos indices must be distinct; " + text + " appears twice");
        }
      }
      indices.push_back(index);
    }
    sign = evaluate_sos(args.name, points, indices);
  } else {
    sign = evaluate(args.name, points);
  }

  const char* word = sign_name(sign);
  if (options.stats_json) {
    nlohmann::ordered_json stats;
    stats["predicate"] = args.name;
    stats["sign"] = static_cast<int>(sign);
    stats["sos"] = args.sos;
    print_stats(stats, options);
    if (std::ostream* human = human_stream(options)) *human << word << "\n";
  } else {
    // The sign is the command's output, not commentary: --quiet does not hide it.
    std::cout << word << "\n";
  }
}

}  // namespace voroclip::cli
