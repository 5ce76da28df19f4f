// The progress printer every long command of the voroclip tool uses (clip2d, clip3d, cvt2d,
// mesh2d, mesh3d, quality, ...): human progress on stderr, never on stdout (which carries
// the report, or the --stats json object).
//
// Two renderings of the same calls:
//   - lines (stderr is not a terminal, or --progress lines): one line per event, flushed
//     at once, so that a log file grows as the work goes on; a phase that has nothing to
//     say (short) prints nothing;
//   - bar (stderr is a terminal, or --progress bar): one live line per phase, redrawn in
//     place ('\r'), with a bar when the phase's iteration budget is known, the iteration,
//     energy, |g|, the elapsed time and an estimate of the time left (ETA, from the mean
//     time per iteration and the budget: an upper bound when the run converges early);
//     the finished phase stays as one line.
// In both, a phase without news for `heartbeat_seconds` gets a line saying it is still
// running (lines) or its clock redrawn (bar), from a background thread, so that a phase the
// library reports nothing from (a clipped diagram of 10^6 sites) still shows life. The
// printer only writes text: it changes nothing in what is computed.
//
// With -q/--quiet nothing is printed. All methods are safe to call from one thread (the
// command's); the heartbeat thread shares the stream under a mutex.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <iosfwd>
#include <mutex>
#include <string>
#include <thread>

namespace voroclip::cli {

struct GlobalOptions;

class Progress {
 public:
  enum class Mode { kNone, kLines, kBar };

  /// From the global options: kNone with --quiet, else --progress (auto: kBar when stderr
  /// is a terminal, kLines otherwise), on std::cerr.
  explicit Progress(const GlobalOptions& options);
  /// On any stream (tests), with the heartbeat period in seconds (0: none).
  Progress(std::ostream* out, Mode mode, double heartbeat_seconds);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  Mode mode() const { return mode_; }

  /// Starts a phase (ends the previous one): `name` as shown ("constrained CVT"),
  /// `budget` its iteration budget when known (0: unknown; no bar, no ETA).
  void phase(const std::string& name, std::uint32_t budget = 0);
  /// An iteration of the current phase with the energy and the gradient norm (a negative
  /// value: not shown). In line mode every `line_every`-th iteration is printed (and the
  /// first); the bar is redrawn at most 10 times a second.
  void iteration(std::uint32_t iteration, double energy, double gradient_norm = -1,
                 std::uint32_t line_every = 1);
  /// A line of news inside the current phase ("topology round 2: ..."): printed as a line
  /// in both modes (above the bar).
  void note(const std::string& text);
  /// Ends the current phase: "name: 1.2 s, 30 iterations" (lines; only after the phase
  /// printed something, so that a short run, or one failing on its input, prints no
  /// progress at all), the bar's last state (bar).
  void done();

 private:
  using Clock = std::chrono::steady_clock;
  void heartbeat_loop();
  void draw_bar_locked(bool final);
  void clear_bar_locked();
  void end_phase_locked();
  std::string status_locked(bool with_eta) const;

  std::ostream* out_ = nullptr;
  Mode mode_ = Mode::kNone;
  double heartbeat_seconds_ = 0;

  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::thread heartbeat_;

  // The current phase (empty name: none).
  std::string name_;
  std::uint32_t budget_ = 0;
  std::uint32_t iteration_ = 0;
  bool has_iteration_ = false;
  bool spoke_ = false;  // lines: the phase printed something (then done() closes it)
  double energy_ = 0, gradient_norm_ = -1;
  Clock::time_point phase_start_, last_output_, last_draw_;
  std::size_t bar_width_ = 0;  // characters of the live line on screen (bar mode)
};

}  // namespace voroclip::cli
