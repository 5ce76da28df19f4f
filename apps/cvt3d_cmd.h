// voroclip cvt3d: the centroidal Voronoi tessellation of N sites in a volume (the paper's
// central computation, sec. 4 and eq. 1-2), from given or random sites.
#pragma once

#include <cstdint>
#include <string>

#include "cli.h"
#include "density_options.h"

namespace CLI {
class App;
}

namespace voroclip::cli {

struct Cvt3dArgs {
  std::string domain;  // closed surface or tet mesh (read_domain3)
  bool reorient = false;
  std::string sites;  // site file; empty with --random
  std::uint32_t random = 0;
  bool random_set = false;
  std::uint64_t seed = 1;
  std::string method = "lbfgs";
  std::uint32_t iterations = 1000;
  double tolerance = 1e-4;
  std::string output;  // .txt / .csv sites, .vtu / .json / .obj cells; empty: no file
  DensityArgs density;
};

/// Declares the cvt3d command and its options on `app`.
CLI::App* add_cvt3d_command(CLI::App& app, Cvt3dArgs& args, const std::string& domain_help,
                            const std::string& reorient_help);

void run_cvt3d(const Cvt3dArgs& args, const GlobalOptions& options);

}  // namespace voroclip::cli
