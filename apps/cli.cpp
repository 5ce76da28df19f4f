#include "cli.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <limits>
#include <numeric>
#include <system_error>
#include <utility>

#include <sys/resource.h>
#include <unistd.h>

#include "progress.h"

namespace voroclip::cli {

std::string no_encoding_message(const std::string& flag, const std::string& ext) {
  // OBJ, SVG, CSV, JSON and plain text have no binary or compressed form in their own
  // specifications (a gzipped file is another file type, .obj.gz, that few readers open).
  const std::string what =
      ext.empty() ? std::string("no output file is given")
                  : ext +
                        " is a text format with no binary or compressed variant in its "
                        "specification; gzip the file if its size matters";
  return flag + ": only a .vtu output (-o FILE.vtu) is written in binary or compressed (" + what +
         ")";
}

std::string cli_message(const std::string& what) {
  // What the library tells a caller of its API, and what says the same on the command line.
  static const std::pair<const char*, const char*> kNames[] = {
      {"Surface3Options::reorient, --reorient", "--reorient"},
      {"ClippedVoronoi3::compute(domain, sites, n) takes them", "clip3d takes them"},
      // The library's bounds on an implied vertex count (mesh2d.cpp, mesh3d.cpp), with what
      // to change on the command line (check_vertex_count's advice).
      {"mesh2d: the edge length asks for about ",
       "mesh2d: the edge length or sizing asks for about "},
      {" vertices; at most 10^9",
       " vertices; at most 10^9, the most mesh2d makes: give a larger --edge-length or --sizing"},
      {" vertices; at most 2e9",
       " vertices; at most 2e9, the most mesh3d makes: give a larger "
       "--sizing (or --vertices N)"},
  };
  std::string text = what;
  for (const auto& [api, cli] : kNames) {
    const std::string from = api;
    for (std::size_t at = text.find(from); at != std::string::npos;
         at = text.find(from, at + std::strlen(cli))) {
      text.replace(at, from.size(), cli);
    }
  }
  return text;
}

std::string error_line(const std::string& what) {
  std::string line = cli_message(what);
  for (char& c : line) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  while (!line.empty() && line.back() == ' ') line.pop_back();
  return line;
}

namespace {
bool g_stats_printed = false;  // one JSON object per run, success or failure
}  // namespace

void print_stats(const nlohmann::ordered_json& stats, const GlobalOptions& options) {
  nlohmann::ordered_json j = {{"command", options.command}, {"ok", true}};
  for (const auto& [key, value] : stats.items()) j[key] = value;
  std::cout << j.dump() << '\n';
  g_stats_printed = true;
}

void print_failure_stats(const std::string& command, const std::string& what,
                         const nlohmann::ordered_json& fields) {
  nlohmann::ordered_json j;
  j["command"] =
      command.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(command);
  j["ok"] = false;
  j["error"] = error_line(what);
  for (const auto& [key, value] : fields.items()) j[key] = value;
  std::cout << j.dump() << '\n';
  g_stats_printed = true;
}

bool stats_printed() { return g_stats_printed; }

void check_vertex_count(const std::string& command, const std::string& what, double count,
                        double bytes_per_vertex, const std::string& advice) {
  const auto integer = [](double x) {
    char text[64];  // %.0f: a whole number even beyond 64 bits
    std::snprintf(text, sizeof text, "%.0f", x);
    return std::string(text);
  };
  const auto fail = [&](double most, const std::string& where) {
    throw Error(command + ": " + what + " asks for about " + integer(count) +
                " vertices; at most " + integer(most) + " fit " + where + ": " + advice);
  };
  constexpr double kMaxCount = 4294967295.0;  // 2^32 - 1: indices 0 .. 2^32 - 2, one kNone
  if (!(count <= kMaxCount)) fail(kMaxCount, "32-bit vertex indices");
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  double memory = pages > 0 && page > 0 ? static_cast<double>(pages) * static_cast<double>(page)
                                        : std::numeric_limits<double>::infinity();
  std::string where = "in this machine's memory";
  rlimit limit{};
  if (getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY &&
      static_cast<double>(limit.rlim_cur) < memory) {
    memory = static_cast<double>(limit.rlim_cur);
    where = "in the address space allowed (ulimit -v)";
  }
  if (count * bytes_per_vertex > memory) {
    char detail[96];
    std::snprintf(detail, sizeof detail, " (%.3g GB at about %.0f bytes per vertex)", memory / 1e9,
                  bytes_per_vertex);
    fail(std::floor(memory / bytes_per_vertex), where + detail);
  }
}

bool note_implied_vertices(const std::string& command, const std::string& what, double count,
                           double bytes_per_vertex, const std::string& advice, Progress& progress,
                           std::string& refused) {
  try {
    check_vertex_count(command, what, count, bytes_per_vertex, advice);
  } catch (const Error& e) {
    refused = e.what();
    return false;
  }
  const double unit = std::max(1.0, std::pow(10.0, std::floor(std::log10(count)) - 2));
  progress.note(command + ": about " +
                std::to_string(static_cast<std::uint64_t>(std::round(count / unit) * unit)) +
                " vertices for this size");
  return true;
}

std::ostream* human_stream(const GlobalOptions& options) {
  if (options.quiet) return nullptr;
  return options.stats_json ? &std::cerr : &std::cout;
}

double parse_finite_double(const std::string& text, const std::string& what) {
  const auto fail = [&](const std::string& why) {
    return UsageError("invalid " + what + " '" + text + "': " + why);
  };
  // std::from_chars is locale-independent but takes neither a '+' sign nor the "0x"
  // prefix, so both are handled here.
  const char* first = text.data();
  const char* const last = text.data() + text.size();
  bool negative = false;
  if (first != last && (*first == '+' || *first == '-')) {
    negative = *first == '-';
    ++first;
  }
  std::chars_format format = std::chars_format::general;
  if (last - first > 2 && first[0] == '0' && (first[1] == 'x' || first[1] == 'X')) {
    format = std::chars_format::hex;
    first += 2;
  }
  if (first == last || *first == '+' || *first == '-') {
    throw fail("not a number");
  }
  double value = 0;
  const std::from_chars_result r = std::from_chars(first, last, value, format);
  if (r.ec == std::errc::result_out_of_range) {
    throw fail("out of the range of double (overflow or underflow)");
  }
  if (r.ec != std::errc() || r.ptr == first) throw fail("not a number");
  if (r.ptr != last) throw fail("unexpected text '" + std::string(r.ptr, last) + "'");
  if (!std::isfinite(value)) throw fail("NaN and infinities are not allowed");
  return negative ? -value : value;
}

std::uint32_t parse_index(const std::string& text, const std::string& what) {
  std::uint32_t value = 0;
  const char* const last = text.data() + text.size();
  const std::from_chars_result r = std::from_chars(text.data(), last, value);
  if (text.empty() || r.ec != std::errc() || r.ptr != last) {
    throw UsageError("invalid " + what + " '" + text +
                     "': expected an integer from 0 to 4294967295");
  }
  return value;
}

const char* sign_name(Sign s) {
  return s == Sign::positive ? "positive" : (s == Sign::negative ? "negative" : "zero");
}

std::string format_double(double x) {
  char buffer[64];
  const std::to_chars_result r = std::to_chars(buffer, buffer + sizeof buffer, x);
  return std::string(buffer, r.ptr);
}

std::string lower_extension(const std::string& path) {
  const std::size_t slash = path.find_last_of("/\\");
  const std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

std::string input_extension(const std::string& path) {
  const std::string ext = lower_extension(path);
  return ext == ".gz" ? lower_extension(path.substr(0, path.size() - 3)) : ext;
}

void check_outputs(const std::vector<OutputOption>& outputs) {
  for (std::size_t k = 0; k < outputs.size(); ++k) {
    for (std::size_t j = 0; j < k; ++j) {
      if (same_file(outputs[j].path, outputs[k].path)) {
        const std::string both =
            outputs[j].path == outputs[k].path
                ? "'" + outputs[k].path + "'"
                : "'" + outputs[j].path + "' and '" + outputs[k].path + "' (the same file)";
        throw UsageError(outputs[j].option + " and " + outputs[k].option + " both name " + both +
                         ": one would overwrite the other; give them different files");
      }
    }
  }
  for (const OutputOption& o : outputs) check_output_path(o.path);
}

std::vector<std::uint32_t> repeated_sites(const std::vector<double>& sites, int dimension) {
  const auto d = static_cast<std::size_t>(dimension);
  std::vector<std::uint32_t> order(sites.size() / d);
  std::iota(order.begin(), order.end(), 0u);
  const auto less = [&](std::uint32_t a, std::uint32_t b) {
    for (std::size_t k = 0; k < d; ++k) {
      if (sites[d * a + k] != sites[d * b + k]) return sites[d * a + k] < sites[d * b + k];
    }
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  std::vector<std::uint32_t> repeated;
  for (std::size_t k = 1; k < order.size(); ++k) {
    if (std::equal(&sites[d * order[k]], &sites[d * order[k]] + d, &sites[d * order[k - 1]])) {
      repeated.push_back(order[k]);  // the runs are in input order: all but the first repeat
    }
  }
  std::sort(repeated.begin(), repeated.end());
  return repeated;
}

void report_sites(const std::string& source, const std::vector<std::uint32_t>& outside,
                  const std::vector<std::uint32_t>& repeated, bool strict, Progress& progress) {
  const auto list = [](const std::vector<std::uint32_t>& v) {
    constexpr std::size_t kShown = 5;
    std::string text;
    for (std::size_t k = 0; k < v.size() && k < kShown; ++k) {
      text += (k == 0 ? "" : ", ") + std::to_string(v[k]);
    }
    return text + (v.size() > kShown ? ", ..." : "");
  };
  std::string message;
  if (!outside.empty()) {
    message += count_of(outside.size(), "site") + " outside the domain " + source + " (" +
               (outside.size() == 1 ? "index " : "indices ") + list(outside) +
               ", from 0 in input order)";
  }
  if (!repeated.empty()) {
    message += (message.empty() ? "" : "; ") + count_of(repeated.size(), "site") +
               (repeated.size() == 1 ? " repeats" : " repeat") + " an earlier site (" +
               (repeated.size() == 1 ? "index " : "indices ") + list(repeated) +
               ", from 0 in input order; " +
               (repeated.size() == 1 ? "its cell is" : "their cells are") + " empty)";
  }
  if (message.empty()) return;
  if (strict) throw Error(message + " (--strict)");
  progress.done();
  std::cout.flush();
  std::cerr << "voroclip: warning: " << message << "; --strict makes this an error" << std::endl;
}

}  // namespace voroclip::cli
