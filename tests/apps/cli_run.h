// Running the built `voroclip` binary (VOROCLIP_CLI_PATH) from a test: its exit status,
// standard output and standard error.
#pragma once

#include <catch2/catch.hpp>

#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <string>
#include <vector>

namespace {

struct Run {
  int status = -1;  // exit status, or -1 when the process did not exit normally
  std::string out;
  std::string err;
};

std::string shell_quote(const std::string& s) {
  std::string quoted = "'";
  for (const char c : s) {
    if (c == '\'') {
      quoted += "'\\''";
    } else {
      quoted += c;
    }
  }
  return quoted + "'";
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool exists(const std::string& path) { return access(path.c_str(), F_OK) == 0; }

// `shell_prefix`, when given, runs before the command in its shell (e.g. "ulimit -v N &&").
Run run_cli(const std::vector<std::string>& args, const std::string& shell_prefix = "") {
  char err_path[] = "test_cli_stderr_XXXXXX";
  const int fd = mkstemp(err_path);
  REQUIRE(fd >= 0);
  close(fd);
  std::string command =
      shell_prefix + (shell_prefix.empty() ? "" : " ") + shell_quote(VOROCLIP_CLI_PATH);
  for (const std::string& a : args) command += " " + shell_quote(a);
  command += " 2>" + shell_quote(err_path);

  Run run;
  FILE* pipe = popen(command.c_str(), "r");
  REQUIRE(pipe != nullptr);
  char buffer[4096];
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) run.out.append(buffer, n);
  const int status = pclose(pipe);
  run.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.err = slurp(err_path);
  std::remove(err_path);
  // Shown with the next assertion, which is usually the one about this run.
  UNSCOPED_INFO("command: " << command << "\nstatus: " << run.status << "\nstdout: " << run.out
                            << "\nstderr: " << run.err);
  return run;
}

Run run_cli(std::initializer_list<std::string> args) {
  return run_cli(std::vector<std::string>(args));
}

// A failure prints exactly one line "voroclip: error: ..." on stderr and nothing on stdout.
void check_one_error_line(const Run& run) {
  INFO("stderr: " << run.err);
  CHECK(run.err.rfind("voroclip: error: ", 0) == 0);
  CHECK(std::count(run.err.begin(), run.err.end(), '\n') == 1);
  CHECK(run.err.back() == '\n');
  CHECK(run.out.empty());
}

bool contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

// A fresh file name in the working directory ending in `suffix` (no file is left there).
inline std::string temp_path(const std::string& suffix) {
  char name[] = "test_cli_XXXXXX";
  const int fd = mkstemp(name);
  REQUIRE(fd >= 0);
  close(fd);
  std::remove(name);
  return std::string(name) + suffix;
}

}  // namespace
