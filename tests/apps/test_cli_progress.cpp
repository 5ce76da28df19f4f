// Progress (apps/progress.h) and the command line's messages: progress on stderr only, per
// line or as a live bar, silenced by -q; unknown commands; the help's wording.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <sstream>
#include <string>
#include <thread>

#include "cli_run.h"
#include "progress.h"

using voroclip::cli::Progress;

namespace {

const std::string kData = VOROCLIP_SHARED_DATA_DIR;

std::size_t count_lines(const std::string& s) {
  return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n'));
}

}  // namespace

TEST_CASE("Progress in lines: iterations, notes, phases ended with their time", "[apps]") {
  std::ostringstream out;
  {
    Progress p(&out, Progress::Mode::kLines, 0);
    p.phase("reading");
    CHECK(out.str().empty());  // a phase says nothing until it has news or ends
    p.phase("CVT", 20);
    for (std::uint32_t i = 1; i <= 20; ++i) p.iteration(i, 1.0 / i, 0.5 / i, 10);
    p.note("something happened");
    p.done();
    p.phase("writing");
  }  // the destructor ends the last phase
  const std::string s = out.str();
  CHECK(s.find('\r') == std::string::npos);
  CHECK(!contains(s, "reading"));  // silent phases print nothing, not even their end
  // Iterations 1, 10 and 20 (every 10th, and the first).
  CHECK(contains(s, "  CVT iteration 1/20  energy 1  |g| 5.000e-01"));
  CHECK(contains(s, "  CVT iteration 10/20  energy 0.1  |g| 5.000e-02"));
  CHECK(contains(s, "  CVT iteration 20/20"));
  CHECK(!contains(s, "iteration 2/20"));
  CHECK(contains(s, "  something happened\n"));
  CHECK(contains(s, "CVT: "));
  CHECK(contains(s, ", 20 iterations\n"));
  CHECK(!contains(s, "writing"));
  CHECK(count_lines(s) == 5);
}

TEST_CASE("Progress in lines: a silent phase gets a heartbeat line", "[apps]") {
  std::ostringstream out;
  {
    Progress p(&out, Progress::Mode::kLines, 0.01);
    p.phase("clipping");
    // The heartbeat thread wakes every 10 ms; a line is due after 10 ms without news.
    for (int k = 0; k < 200 && !contains(out.str(), "still running"); ++k) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }
  CHECK(contains(out.str(), "  clipping: still running, "));
  CHECK(contains(out.str(), "\nclipping: "));  // having spoken, the phase says when it ends
}

TEST_CASE("Progress as a bar: redrawn in place, a bar and an ETA, one line per phase", "[apps]") {
  std::ostringstream out;
  {
    Progress p(&out, Progress::Mode::kBar, 0);
    p.phase("constrained CVT", 4);
    for (std::uint32_t i = 1; i <= 4; ++i) p.iteration(i, 2.0, 0.25);
    p.done();
  }
  const std::string s = out.str();
  CHECK(s.rfind("\rconstrained CVT [", 0) == 0);
  CHECK(contains(s, "[########################] iteration 4/4"));
  CHECK(contains(s, "|g| 2.500e-01"));
  CHECK(count_lines(s) == 1);  // the finished phase stays as one line
}

TEST_CASE("Progress with an exception in flight: the bar is cleared, no 'done'", "[apps]") {
  std::ostringstream out;
  try {
    Progress p(&out, Progress::Mode::kBar, 0);
    p.phase("reading");
    throw std::runtime_error("bad file");
  } catch (const std::runtime_error&) {
  }
  CHECK(count_lines(out.str()) == 0);
  const std::string s = out.str();
  CHECK(s.find_last_not_of(" \r") < s.rfind('\r'));  // ends with a blank redraw
}

TEST_CASE("cvt2d: progress on stderr only, per line, as a bar, or none", "[apps]") {
  const std::string domain = kData + "/polygons/valid/issue35.json";
  const std::vector<std::string> args = {"cvt2d", domain, "--random", "100", "--iterations", "12"};
  std::vector<std::string> lines = args;
  lines.insert(lines.begin(), {"--progress", "lines"});
  const Run l = run_cli(lines);
  REQUIRE(l.status == 0);
  CHECK(contains(l.err, "CVT (lbfgs) iteration 1/12  energy "));
  CHECK(contains(l.err, "|g| "));
  CHECK(l.err.find('\r') == std::string::npos);
  CHECK(!contains(l.out, "iteration 1/"));  // the report on stdout, the progress not
  CHECK(contains(l.out, "CVT (lbfgs): "));

  std::vector<std::string> bar = args;
  bar.insert(bar.begin(), {"--progress", "bar"});
  const Run b = run_cli(bar);
  REQUIRE(b.status == 0);
  CHECK(contains(b.err, "\rCVT (lbfgs) ["));
  CHECK(contains(b.out, "CVT (lbfgs): "));

  std::vector<std::string> quiet = args;
  quiet.insert(quiet.begin(), "-q");
  const std::string sites = temp_path(".txt");
  quiet.insert(quiet.end(), {"-o", sites});
  const Run q = run_cli(quiet);
  REQUIRE(q.status == 0);
  CHECK(q.err.empty());
  CHECK(q.out.empty());
  CHECK(exists(sites));  // quiet, but the work is done
  std::remove(sites.c_str());

  std::vector<std::string> none = args;
  none.insert(none.begin(), {"--progress", "none"});
  const Run n = run_cli(none);
  REQUIRE(n.status == 0);
  CHECK(n.err.empty());
  CHECK(contains(n.out, "CVT (lbfgs): "));
}

TEST_CASE("an unknown or missing command lists the commands", "[apps]") {
  const Run unknown = run_cli({"clip4d", "x"});
  CHECK(unknown.status == 2);
  check_one_error_line(unknown);
  CHECK(contains(unknown.err, "unknown command 'clip4d'"));
  for (const char* command : {"clip2d", "clip3d", "cvt2d", "mesh2d", "mesh3d", "quality"}) {
    CHECK(contains(unknown.err, command));
  }
  const Run global = run_cli({"--threads", "2", "mesh4d"});
  CHECK(global.status == 2);
  CHECK(contains(global.err, "unknown command 'mesh4d'"));
  const Run none = run_cli({"--threads", "2"});
  CHECK(none.status == 2);
  check_one_error_line(none);
  CHECK(contains(none.err, "no command given; the commands are: "));
  // A real command with a bad global option keeps its own message.
  const Run bad = run_cli({"--threads", "0", "demo"});
  CHECK(bad.status == 2);
  CHECK(contains(bad.err, "--threads"));
  CHECK(!contains(bad.err, "unknown command"));
}

TEST_CASE("help text: no CLI11 artefacts", "[apps]") {
  const Run top = run_cli({"--help"});
  CHECK(!contains(top.out, "json:{json}"));
  CHECK(contains(top.out, "--progress"));
  for (const char* command : {"clip2d", "clip3d", "mesh2d", "mesh3d", "cvt2d", "cvt3d", "quality",
                              "check-surface", "delaunay2d", "delaunay3d", "predicate", "demo"}) {
    INFO(command);
    const Run h = run_cli({command, "--help"});
    CHECK(h.status == 0);
    CHECK(h.out == run_cli({"help", command}).out);
    CHECK(!contains(h.out, "FILE FILE"));
    CHECK(!contains(h.out, "DOMAIN DOMAIN"));
    CHECK(!contains(h.out, "MESH MESH"));
    CHECK(!contains(h.out, "REQUIRED"));
  }
  const Run clip = run_cli({"clip2d", "--help"});
  CHECK(contains(clip.out, "site,x,y,area,centroid_x,centroid_y,energy,boundary,neighbors"));
  CHECK(contains(clip.out, "--neighbors"));
}

TEST_CASE("voroclip help COMMAND prints that command's help", "[apps]") {
  const Run clip = run_cli({"help", "clip3d"});
  CHECK(clip.status == 0);
  CHECK(clip.out == run_cli({"clip3d", "--help"}).out);
  CHECK(contains(clip.out, "--neighbors"));
  const Run top = run_cli({"help"});
  CHECK(top.status == 0);
  CHECK(contains(top.out, "mesh3d"));
  const Run bad = run_cli({"help", "clip4d"});
  CHECK(bad.status == 2);
  check_one_error_line(bad);
  CHECK(contains(bad.err, "unknown command 'clip4d'; the commands are: "));
}
