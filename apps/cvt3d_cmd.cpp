// voroclip cvt3d: the centroidal Voronoi tessellation of sites in a volume (a closed
// surface or a tet mesh), by L-BFGS or Lloyd (optimize_cvt3), with the user's density;
// the final sites (.txt, .csv) or cells (.vtu, .json, .obj) out. Mirrors cvt2d.
#include "cvt3d_cmd.h"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdint>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "progress.h"
#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/cvt.h"

namespace voroclip::cli {

namespace {

// Each coordinate in the shortest decimal that reads back to its bits.
void write_sites3(std::ostream& out, const std::vector<double>& sites, bool csv) {
  if (csv) out << "x,y,z\n";
  const char sep = csv ? ',' : ' ';
  for (std::size_t i = 0; i < sites.size() / 3; ++i) {
    out << format_double(sites[3 * i]) << sep << format_double(sites[3 * i + 1]) << sep
        << format_double(sites[3 * i + 2]) << '\n';
  }
}

}  // namespace

CLI::App* add_cvt3d_command(CLI::App& app, Cvt3dArgs& args, const std::string& domain_help,
                            const std::string& reorient_help) {
  CLI::App* cmd = app.add_subcommand(
      "cvt3d",
      "Centroidal Voronoi tessellation of a volume (L-BFGS or Lloyd; Yan et al. 2011, eq. 1-2), "
      "from given or random sites, with an optional density");
  cmd->add_option("DOMAIN", args.domain, domain_help)->required()->type_name("");
  cmd->add_flag("--reorient", args.reorient, reorient_help);
  cmd->add_option("--sites", args.sites,
                  "Site file: one 'x y z' per line ('#' comments) or a JSON array [[x,y,z],...]")
      ->type_name("FILE");
  cmd->add_option("--random", args.random,
                  "Use N random sites in the volume (uniform; with a --density or "
                  "--density-file (any format), drawn with density rho^(3/5), the CVT's)")
      ->type_name("N");
  cmd->add_option("--seed", args.seed, "Seed of --random (default 1)")->type_name("S");
  cmd->add_option("--method", args.method, "lbfgs (default) or lloyd")->type_name("NAME");
  cmd->add_option("--iterations", args.iterations,
                  "Iteration budget (default 1000, as cvt2d's: enough for L-BFGS to "
                  "reach the default tolerance on the shared models from random sites)")
      ->type_name("N");
  cmd->add_option("--tolerance", args.tolerance,
                  "Stop when |gradient| <= tolerance * initial |gradient| (default 1e-4)")
      ->type_name("T");
  cmd->add_option("-o,--output", args.output,
                  "Write the final sites (.txt: 'x y z' lines; .csv) or cells (.vtu: every "
                  "cell's faces; .json: per cell site, volume, centroid, energy; .obj: the "
                  "restricted surface)")
      ->type_name("FILE");
  add_density_options(cmd, args.density, 3, false);
  return cmd;
}

void run_cvt3d(const Cvt3dArgs& args, const GlobalOptions& options) {
  const std::string ext = lower_extension(args.output);
  if (!args.output.empty() && ext != ".txt" && ext != ".csv" && ext != ".vtu" && ext != ".json" &&
      ext != ".obj") {
    throw UsageError(
        "-o: the output must end in .txt or .csv (the sites), .vtu, .json or .obj (the cells), "
        "got '" +
        args.output + "'");
  }
  check_outputs({{"-o", args.output}});
  if (args.method != "lbfgs" && args.method != "lloyd") {
    throw UsageError("--method: expected lbfgs or lloyd, got '" + args.method + "'");
  }
  if (!(args.tolerance >= 0) || !std::isfinite(args.tolerance)) {
    throw UsageError("--tolerance: expected a finite number >= 0");
  }
  if (args.sites.empty() == !args.random_set) {
    throw UsageError("give exactly one of --sites FILE and --random N");
  }
  if (args.random_set && args.random < 1) throw UsageError("--random: needs at least 1 site");
  const Domain3 domain = load_domain3(args.domain, args.reorient, options);
  Cvt3Options o;
  o.clip.density = make_density3(args.density, domain);
  std::vector<double> sites;
  if (args.random_set) {
    // A CVT of density rho has about rho^(d/(d+2)) sites per unit volume: start there.
    Density3 draw;
    // Whatever the density's file format: a .sol's is drawn from as a .vtu's is.
    if (!o.clip.density.is_constant()) {
      const Density3 rho = pointwise_density3(o.clip.density, domain);
      draw = Density3::function(
          [rho](double x, double y, double z) { return std::pow(rho.callback(x, y, z), 0.6); });
    }
    sites = random_points3(domain, args.random, args.seed, draw);
  } else {
    sites = read_points(args.sites, 3);
    if (sites.empty()) throw Error(args.sites + ": needs at least 1 site");
  }
  const auto n = static_cast<std::uint32_t>(sites.size() / 3);
  o.method = args.method == "lloyd" ? CvtMethod::kLloyd : CvtMethod::kLbfgs;
  o.max_iterations = args.iterations;
  o.gradient_tolerance = args.tolerance;
  std::ostream* human = human_stream(options);
  Progress progress(options);
  progress.phase("CVT (" + args.method + ")", args.iterations);
  o.progress = [&](const CvtProgress& p) {
    progress.iteration(p.iteration, p.energy, p.gradient_norm);
    return true;
  };
  const Cvt3Result r = optimize_cvt3(domain, sites, o);
  if (!args.output.empty()) {
    progress.phase("writing");
    if (ext == ".txt" || ext == ".csv") {
      write_file_atomically(args.output,
                            [&](std::ostream& out) { write_sites3(out, sites, ext == ".csv"); });
    } else {
      ClippedVoronoi3 cv;
      Clip3Options co = o.clip;
      co.keep_surface = ext == ".obj";
      co.keep_geometry = ext == ".vtu" || ext == ".json";
      cv.compute(domain, sites.data(), n, co);
      const FileWriter file = cells3_file(args.output, "cvt3d", sites, cv);
      write_file_atomically(file.path, file.write);
    }
  }
  progress.done();
  if (options.stats_json) {
    print_stats(nlohmann::json{{"sites", n},
                               {"method", args.method},
                               {"density", args.density.describe()},
                               {"domain_volume", domain.volume()},
                               {"iterations", r.iterations},
                               {"evaluations", r.evaluations},
                               {"energy", r.energy},
                               {"gradient_norm", r.gradient_norm},
                               {"initial_gradient_norm", r.initial_gradient_norm},
                               {"converged", r.converged},
                               {"stop", cvt_stop_name(r.stop)},
                               {"seconds", r.seconds}},
                options);
  }
  if (human) {
    *human << "CVT (" << args.method << "): " << count_of(n, "site") << " in " << domain.source()
           << ", " << count_of(r.iterations, "iteration") << ", "
           << count_of(r.evaluations, "diagram") << ", energy " << std::setprecision(12) << r.energy
           << ", |g|/|g0| " << std::setprecision(3)
           << (r.initial_gradient_norm > 0 ? r.gradient_norm / r.initial_gradient_norm : 0)
           << "; stopped: " << cvt_stop_name(r.stop) << ", " << r.seconds << " s\n";
    if (!args.output.empty()) *human << "Written to " << args.output << '\n';
  }
}

}  // namespace voroclip::cli
