#include "progress.h"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <iostream>

#include "cli.h"

namespace voroclip::cli {

namespace {

// Seconds between "still running" lines (lines mode) and between redraws of the live line's
// clock (bar mode).
constexpr double kLineHeartbeatSeconds = 5;
constexpr double kBarHeartbeatSeconds = 0.25;
// The bar is redrawn at most this often by iteration().
constexpr double kBarRedrawSeconds = 0.1;
constexpr std::size_t kBarCells = 24;

std::string printf_string(const char* format, double x) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, x);
  return buffer;
}

// "4.2 s", "3 min 05 s", "2 h 07 min".
std::string duration_text(double seconds) {
  if (seconds < 60) return printf_string("%.1f s", seconds);
  const auto s = static_cast<long>(std::lround(seconds));
  char buffer[64];
  if (s < 3600) {
    std::snprintf(buffer, sizeof buffer, "%ld min %02ld s", s / 60, s % 60);
  } else {
    std::snprintf(buffer, sizeof buffer, "%ld h %02ld min", s / 3600, (s / 60) % 60);
  }
  return buffer;
}

double seconds_between(std::chrono::steady_clock::time_point a,
                       std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

std::size_t terminal_columns() {
  winsize w{};
  if (ioctl(STDERR_FILENO, TIOCGWINSZ, &w) == 0 && w.ws_col >= 40) return w.ws_col;
  return 100;
}

}  // namespace

Progress::Progress(const GlobalOptions& options) {
  if (options.quiet || options.progress == "none") return;
  out_ = &std::cerr;
  const bool bar =
      options.progress == "bar" || (options.progress == "auto" && isatty(STDERR_FILENO) == 1);
  mode_ = bar ? Mode::kBar : Mode::kLines;
  heartbeat_seconds_ = bar ? kBarHeartbeatSeconds : kLineHeartbeatSeconds;
  heartbeat_ = std::thread([this] { heartbeat_loop(); });
}

Progress::Progress(std::ostream* out, Mode mode, double heartbeat_seconds)
    : out_(out), mode_(out ? mode : Mode::kNone), heartbeat_seconds_(heartbeat_seconds) {
  if (mode_ != Mode::kNone && heartbeat_seconds_ > 0) {
    heartbeat_ = std::thread([this] { heartbeat_loop(); });
  }
}

Progress::~Progress() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (heartbeat_.joinable()) heartbeat_.join();
  if (mode_ == Mode::kNone) return;
  std::lock_guard<std::mutex> lock(mutex_);
  if (std::uncaught_exceptions() > 0) {
    // A failure: its one error line follows; the live line goes, no "done".
    clear_bar_locked();
    out_->flush();
  } else {
    end_phase_locked();
  }
}

void Progress::phase(const std::string& name, std::uint32_t budget) {
  if (mode_ == Mode::kNone) return;
  std::lock_guard<std::mutex> lock(mutex_);
  end_phase_locked();
  name_ = name;
  budget_ = budget;
  iteration_ = 0;
  has_iteration_ = false;
  spoke_ = false;
  energy_ = 0;
  gradient_norm_ = -1;
  phase_start_ = last_output_ = Clock::now();
  // Lines: nothing yet (a phase that fails at once, such as reading a bad file, leaves only
  // its error line); the iterations, the heartbeat and done() say what happens.
  if (mode_ == Mode::kBar) draw_bar_locked(false);
}

void Progress::iteration(std::uint32_t iteration, double energy, double gradient_norm,
                         std::uint32_t line_every) {
  if (mode_ == Mode::kNone) return;
  std::lock_guard<std::mutex> lock(mutex_);
  iteration_ = iteration;
  has_iteration_ = true;
  energy_ = energy;
  gradient_norm_ = gradient_norm;
  const Clock::time_point now = Clock::now();
  if (mode_ == Mode::kBar) {
    if (seconds_between(last_draw_, now) >= kBarRedrawSeconds || iteration == budget_) {
      draw_bar_locked(false);
    }
    return;
  }
  if (line_every == 0 || iteration % line_every == 0 || iteration <= 1) {
    *out_ << "  " << name_ << ' ' << status_locked(false) << std::endl;
    last_output_ = now;
    spoke_ = true;
  }
}

void Progress::note(const std::string& text) {
  if (mode_ == Mode::kNone) return;
  std::lock_guard<std::mutex> lock(mutex_);
  clear_bar_locked();
  *out_ << "  " << text << std::endl;
  last_output_ = Clock::now();
  spoke_ = true;
  if (mode_ == Mode::kBar && !name_.empty()) draw_bar_locked(false);
}

void Progress::done() {
  if (mode_ == Mode::kNone) return;
  std::lock_guard<std::mutex> lock(mutex_);
  end_phase_locked();
}

void Progress::end_phase_locked() {
  if (name_.empty()) return;
  if (mode_ == Mode::kBar) {
    draw_bar_locked(true);
    *out_ << std::endl;
    bar_width_ = 0;
  } else if (spoke_) {
    *out_ << name_ << ": " << duration_text(seconds_between(phase_start_, Clock::now()));
    if (has_iteration_) {
      *out_ << ", " << iteration_ << (iteration_ == 1 ? " iteration" : " iterations");
    }
    *out_ << std::endl;
  }
  name_.clear();
}

std::string Progress::status_locked(bool with_eta) const {
  std::string s;
  if (has_iteration_) {
    s += "iteration " + std::to_string(iteration_);
    if (budget_ > 0) s += "/" + std::to_string(budget_);
    s += "  energy " + printf_string("%.9g", energy_);
    if (gradient_norm_ >= 0) s += "  |g| " + printf_string("%.3e", gradient_norm_);
    s += "  ";
  }
  const double elapsed = seconds_between(phase_start_, Clock::now());
  s += duration_text(elapsed);
  if (with_eta && budget_ > 0 && has_iteration_ && iteration_ > 0 && iteration_ < budget_) {
    s += "  ETA " + duration_text(elapsed / iteration_ * (budget_ - iteration_));
  }
  return s;
}

void Progress::draw_bar_locked(bool final) {
  std::string line = name_ + " ";
  if (budget_ > 0) {
    const std::uint32_t it = std::min(iteration_, budget_);
    const auto filled = static_cast<std::size_t>(static_cast<double>(kBarCells) * it /
                                                 static_cast<double>(budget_));
    line += "[" + std::string(filled, '#') + std::string(kBarCells - filled, '.') + "] ";
  }
  line += status_locked(!final);
  const std::size_t columns = out_ == &std::cerr ? terminal_columns() : 200;
  if (line.size() >= columns) line.resize(columns - 1);
  // Pad over what the previous drawing left.
  const std::size_t width = line.size();
  if (width < bar_width_) line += std::string(bar_width_ - width, ' ');
  *out_ << '\r' << line << std::flush;
  bar_width_ = width;
  last_draw_ = last_output_ = Clock::now();
}

void Progress::clear_bar_locked() {
  if (mode_ != Mode::kBar || bar_width_ == 0) return;
  *out_ << '\r' << std::string(bar_width_, ' ') << '\r';
  bar_width_ = 0;
}

void Progress::heartbeat_loop() {
  std::unique_lock<std::mutex> lock(mutex_);
  // Woken often enough that a silent phase gets its line at most 0.5 s late.
  const auto poll = std::chrono::duration<double>(std::min(heartbeat_seconds_, 0.5));
  while (!stop_) {
    wake_.wait_for(lock, poll);
    if (stop_) break;
    if (name_.empty()) continue;
    const Clock::time_point now = Clock::now();
    if (seconds_between(last_output_, now) < heartbeat_seconds_) continue;
    if (mode_ == Mode::kBar) {
      draw_bar_locked(false);
    } else {
      *out_ << "  " << name_ << ": still running, "
            << duration_text(seconds_between(phase_start_, now)) << std::endl;
      last_output_ = now;
      spoke_ = true;
    }
  }
}

}  // namespace voroclip::cli
