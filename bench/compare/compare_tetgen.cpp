// The clipped Voronoi diagram of a volume given by its closed surface, against what a user
// had to do before voroclip took surfaces: tetrahedralize the surface with TetGen (`tetgen
// -pYQ`, the Debian package's program, AGPL: run as a separate process, never linked), read
// its .node/.ele back as the domain and clip. Both in one run, on the same sites.
//
//   compare_tetgen [--threads N] [--repeat R] [--scales 1,10,100] [--models a,b,...]
//
// Per model of ../shared/data/surfaces and site count (bench_table1's counts at x1, times
// each scale), with n sites uniform in the volume (random_points3 on the surface domain,
// fixed seed, drawn once and given to both paths):
//   ours         read_surface + Domain3 (reading and the exact validation), then
//                ClippedVoronoi3::compute(domain, sites, n) (Delaunay included);
//   alternative  `tetgen -pYQ model.off` on the surface written as OFF (write_surface; not
//                timed: a user may have an OFF already), the wall clock of the process
//                (start to exit, its .node/.ele/.face/.edge files written), then
//                read_tet_mesh of its output + Domain3 (the tet mesh validated), then the
//                same compute. -pY keeps the surface as the mesh's boundary, so both
//                domains are the same volume. ../shared/data/tetmeshes was made with
//                -pYq1.5 (gargoyle: -pY); here every model gets -pYQ, the cheapest mesh
//                with that boundary.
// Checks (exit status 1 when one fails): each diagram's total volume equals its domain's
// to 1e-12 relative, the two domains' volumes agree to 1e-12 relative; the largest
// difference of a cell's volume between the two diagrams is printed (relative to the
// domain's volume).
// Figures are medians of R runs (each column on its own; the runs of both paths
// interleaved). TetGen runs on one thread, our compute on N (default: all cores).
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <tbb/global_control.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "voroclip/clip.h"
#include "voroclip/core.h"
#include "voroclip/cvt.h"

extern char** environ;  // NOLINT: POSIX, for posix_spawn

namespace {

constexpr std::uint64_t kSeed = 20261122;
constexpr double kTolerance = 1e-12;

// bench_table1's kModels at x1, for the models that have a surface file.
struct Model {
  const char* name;
  const char* file;
  std::uint32_t sites;
};
const Model kModels[] = {{"bunny", "bunny.obj", 2000},
                         {"elk", "elk.off", 2000},
                         {"fandisk", "fandisk.obj", 3000},
                         {"homer", "homer.obj", 10000},
                         {"rocker-arm", "rocker-arm.obj", 3000},
                         {"skull_low_resolution", "skull_low_resolution.obj", 3000},
                         {"sphere", "sphere.obj", 1000},
                         {"gargoyle", "gargoyle.off", 10000}};

using Clock = std::chrono::steady_clock;
double seconds(Clock::time_point from, Clock::time_point to) {
  return std::chrono::duration<double>(to - from).count();
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string x; std::getline(in, x, ',');) out.push_back(x);
  return out;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// Runs args[0] (a path) with args[1..], its standard output and error to `log`; waits for
// it. Returns its exit status, or -1 when it did not start or did not exit normally.
int run_process(const std::vector<std::string>& args, const std::string& log) {
  std::vector<std::string> owned = args;
  std::vector<char*> argv;
  for (std::string& a : owned) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  pid_t pid = 0;
  const int started = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (started != 0) return -1;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return -1;
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string last_line(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line)) {
    if (!line.empty()) last = line;
  }
  return last;
}

struct Row {
  std::vector<double> validate, clip, total;                      // ours
  std::vector<double> tetgen, tet_validate, tet_clip, tet_total;  // the alternative
  std::vector<double> alternative;
};

}  // namespace

int main(int argc, char** argv) {
  int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  int repeat = 3;
  std::vector<std::string> scales = {"1", "10", "100"}, models;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    const bool has_value = a + 1 < argc;
    if (arg == "--threads" && has_value) {
      threads = std::max(1, std::atoi(argv[++a]));
    } else if (arg == "--repeat" && has_value) {
      repeat = std::max(1, std::atoi(argv[++a]));
    } else if (arg == "--scales" && has_value) {
      scales = split(argv[++a]);
    } else if (arg == "--models" && has_value) {
      models = split(argv[++a]);
    } else {
      std::fprintf(stderr,
                   "usage: compare_tetgen [--threads N] [--repeat R] [--scales 1,10,100] "
                   "[--models a,b,...]\n");
      return 2;
    }
  }
  for (const std::string& m : models) {
    if (std::none_of(std::begin(kModels), std::end(kModels),
                     [&](const Model& k) { return m == k.name; })) {
      std::fprintf(stderr, "compare_tetgen: no model '%s'\n", m.c_str());
      return 2;
    }
  }
  const tbb::global_control control(tbb::global_control::max_allowed_parallelism,
                                    static_cast<std::size_t>(threads));

  namespace fs = std::filesystem;
  std::string tmp = (fs::temp_directory_path() / "compare_tetgen.XXXXXX").string();
  if (mkdtemp(tmp.data()) == nullptr) {
    std::fprintf(stderr, "compare_tetgen: cannot create a directory %s\n", tmp.c_str());
    return 1;
  }
  const fs::path dir(tmp);

  std::printf(
      "ours: %d thread(s); TetGen (%s -pYQ, one thread) + read/validate its mesh + clip on "
      "%d thread(s); median of %d run(s), seconds\n\n",
      threads, VOROCLIP_TETGEN, threads, repeat);
  std::printf(
      "| model | triangles | tets | sites | ours: validate | clip | total | tetgen | tet path: "
      "read+validate | clip | total | alternative total | alternative / ours | max cell "
      "diff |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  std::fflush(stdout);
  bool ok = true;
  try {
    for (const Model& m : kModels) {
      if (!models.empty() && std::find(models.begin(), models.end(), m.name) == models.end()) {
        continue;
      }
      const std::string path = std::string(VOROCLIP_SHARED_DATA_DIR) + "/surfaces/" + m.file;
      const voroclip::TriangleSurface input = voroclip::read_surface(path);
      const voroclip::Domain3 reference(input);
      const fs::path off = dir / (std::string(m.name) + ".off");
      voroclip::write_surface(off.string(), input, voroclip::SurfaceFormat::kOff);
      // TetGen writes model.1.node, .ele, .face, .edge, .smesh beside its input.
      const fs::path out = dir / (std::string(m.name) + ".1");
      const std::string log = (dir / (std::string(m.name) + ".log")).string();
      for (const std::string& sc : scales) {
        const auto n = static_cast<std::uint32_t>(m.sites * std::atof(sc.c_str()));
        const std::vector<double> sites = voroclip::random_points3(reference, n, kSeed);
        Row row;
        voroclip::ClippedVoronoi3 ours, alt;
        std::uint32_t nb_tets = 0;
        double domain_volume = 0, tet_domain_volume = 0;
        int failed = 0;  // TetGen's exit status when it failed
        for (int r = 0; r < repeat && failed == 0; ++r) {
          const auto t0 = Clock::now();
          const voroclip::Domain3 domain(voroclip::read_surface(path));
          const auto t1 = Clock::now();
          ours.compute(domain, sites.data(), n);
          const auto t2 = Clock::now();
          row.validate.push_back(seconds(t0, t1));
          row.clip.push_back(seconds(t1, t2));
          row.total.push_back(seconds(t0, t2));
          domain_volume = domain.volume();

          for (const char* ext : {".node", ".ele", ".face", ".edge", ".smesh"}) {
            fs::remove(out.string() + ext);
          }
          const auto t3 = Clock::now();
          const int status = run_process({VOROCLIP_TETGEN, "-pYQ", off.string()}, log);
          const auto t4 = Clock::now();
          if (status != 0 || !fs::exists(out.string() + ".ele")) {
            failed = status == 0 ? -1 : status;
            break;
          }
          const voroclip::Domain3 tets(voroclip::read_tet_mesh(out.string() + ".ele"));
          const auto t5 = Clock::now();
          alt.compute(tets, sites.data(), n);
          const auto t6 = Clock::now();
          row.tetgen.push_back(seconds(t3, t4));
          row.tet_validate.push_back(seconds(t4, t5));
          row.tet_clip.push_back(seconds(t5, t6));
          row.tet_total.push_back(seconds(t4, t6));
          row.alternative.push_back(seconds(t3, t6));
          nb_tets = tets.nb_tets();
          tet_domain_volume = tets.volume();

          const double err = std::fabs(ours.total_volume() - domain_volume) / domain_volume;
          const double err_tets =
              std::fabs(alt.total_volume() - tet_domain_volume) / tet_domain_volume;
          const double err_domains = std::fabs(tet_domain_volume - domain_volume) / domain_volume;
          if (!(err <= kTolerance && err_tets <= kTolerance && err_domains <= kTolerance)) {
            std::fprintf(stderr,
                         "%s, %u sites: volume error: surface %.3g, tets %.3g, domains %.3g\n",
                         m.name, n, err, err_tets, err_domains);
            ok = false;
          }
        }
        if (failed != 0) {
          std::fprintf(stderr, "%s: tetgen -pYQ failed (exit status %d): %s\n", m.name, failed,
                       last_line(log).c_str());
          std::printf("| %s | %u | - | %u | | | | tetgen failed (%d) | | | | | | |\n", m.name,
                      reference.surface().nb_triangles(), n, failed);
          std::fflush(stdout);
          ok = false;
          break;  // it fails alike for every site count
        }
        double max_diff = 0;
        for (std::uint32_t i = 0; i < n; ++i) {
          max_diff = std::max(max_diff, std::fabs(ours.volume(i) - alt.volume(i)));
        }
        std::printf(
            "| %s | %u | %u | %u | %.4f | %.4f | %.4f | %.4f | %.4f | %.4f | %.4f | %.4f | "
            "%.2f | %.1e |\n",
            m.name, reference.surface().nb_triangles(), nb_tets, n, median(row.validate),
            median(row.clip), median(row.total), median(row.tetgen), median(row.tet_validate),
            median(row.tet_clip), median(row.tet_total), median(row.alternative),
            median(row.alternative) / median(row.total), max_diff / domain_volume);
        std::fflush(stdout);
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "compare_tetgen: %s\n", e.what());
    ok = false;
  }
  std::error_code ignored;
  fs::remove_all(dir, ignored);
  return ok ? 0 : 1;
}
