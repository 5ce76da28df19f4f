// Catch2's main, run in a task arena of VOROCLIP_TEST_THREADS threads when that is set
// (support/threads.h).
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <cstdlib>

#include "support/threads.h"

int main(int argc, char* argv[]) {
  if (std::getenv("VOROCLIP_TEST_THREADS") == nullptr) return Catch::Session().run(argc, argv);
  const std::size_t threads = voroclip_test::test_threads();
  // Both: the limit lets TBB start more workers than cores; the arena gives them slots. A test's
  // own global_control of 1 (the 1-thread side of a comparison) still wins, as the smaller one.
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  tbb::task_arena arena(static_cast<int>(threads));
  return arena.execute([&] { return Catch::Session().run(argc, argv); });
}
