// The thread count of the tests, shared by every test executable (tests/support/).
//
// VOROCLIP_TEST_THREADS=N (N >= 1) makes catch_main.cpp run the whole session in a task arena
// of N threads (N may exceed the cores: the ThreadSanitizer stage of scripts/test.sh runs at 2
// and at 4 on two cores), and every "same bits with 1 and N threads" test compares 1 with N.
// Unset, N is 2 and the session runs in TBB's default arena (one thread per core).
// Every test case that compares 1 with N threads carries the tag [threads] (and [large] when
// it needs 10^5 points or more): scripts/tsan.sh runs "[threads]~[large]~[.]" under TSan.
#pragma once

#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace voroclip_test {

// N: VOROCLIP_TEST_THREADS, or 2 when unset. A value that is not a whole number from 1 to 256
// stops the run with a message (a typo must not silently test something else).
inline std::size_t test_threads() {
  const char* s = std::getenv("VOROCLIP_TEST_THREADS");
  if (s == nullptr) return 2;
  char* end = nullptr;
  const long n = std::strtol(s, &end, 10);
  if (end == s || *end != '\0' || n < 1 || n > 256) {
    std::fprintf(stderr, "VOROCLIP_TEST_THREADS='%s': expected a whole number from 1 to 256\n", s);
    std::exit(2);
  }
  return static_cast<std::size_t>(n);
}

}  // namespace voroclip_test
