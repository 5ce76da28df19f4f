// clip/src/clip_poll.h — the progress/cancel hook of the clipped diagrams
// (Clip2Options::progress, Clip3Options::progress; ClipProgress in clip.h).
//
// The callback runs only on the thread that called compute(): at the start of each phase,
// and from inside the phases' parallel loops between chunks of cells, when that thread
// finishes a chunk and kInterval has passed since its last call. So it needs no locking,
// and a Python binding can check for signals there (they are delivered to the main thread
// only). Once it returns false every chunk not yet started returns at once, and the loop's
// caller throws Error("<what>: cancelled") (check()). Without a callback a chunk costs one
// test of an empty std::function. Chunks skip work only after a cancel: a run that is not
// cancelled computes exactly what it computes without the hook.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <thread>

#include "voroclip/clip.h"

namespace voroclip::detail {

class ClipPoll {
 public:
  using Callback = std::function<bool(const ClipProgress&)>;
  ClipPoll(const Callback& callback, const char* what)
      : callback_(callback),
        what_(what),
        caller_(std::this_thread::get_id()),
        start_(Clock::now()),
        last_(start_) {}

  // The start of a phase of `total` items: calls the callback; throws when it says stop.
  void phase(const char* name, std::uint64_t total) {
    if (!callback_) return;
    phase_ = name;
    total_ = total;
    done_.store(0, std::memory_order_relaxed);
    call();
    check();
  }
  // From a parallel loop, after a chunk of `count` items: false once cancelled (the
  // remaining chunks then return at once).
  bool chunk(std::uint64_t count) {
    if (!callback_) return true;
    if (stop_.load(std::memory_order_relaxed)) return false;
    done_.fetch_add(count, std::memory_order_relaxed);
    if (std::this_thread::get_id() == caller_ && Clock::now() - last_ >= kInterval) call();
    return !stop_.load(std::memory_order_relaxed);
  }
  // At the start of a chunk: false once cancelled.
  bool running() const { return !callback_ || !stop_.load(std::memory_order_relaxed); }
  // After a parallel loop: throws Error("<what>: cancelled") once cancelled.
  void check() const {
    if (!running()) throw Error(std::string(what_) + ": cancelled");
  }

 private:
  using Clock = std::chrono::steady_clock;
  static constexpr std::chrono::milliseconds kInterval{50};
  void call() {
    last_ = Clock::now();
    ClipProgress p;
    p.phase = phase_;
    p.done = done_.load(std::memory_order_relaxed);
    p.total = total_;
    p.seconds = std::chrono::duration<double>(last_ - start_).count();
    if (!callback_(p)) stop_.store(true, std::memory_order_relaxed);
  }
  const Callback& callback_;
  const char* what_;
  std::thread::id caller_;
  Clock::time_point start_, last_;  // last_: only the caller's thread touches it
  const char* phase_ = "";
  std::uint64_t total_ = 0;
  std::atomic<std::uint64_t> done_{0};
  std::atomic<bool> stop_{false};
};

}  // namespace voroclip::detail
