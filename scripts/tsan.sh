#!/usr/bin/env bash
# ThreadSanitizer run of the parallel tests (issue 34), stage 7 of scripts/test.sh; also run on
# its own: bash scripts/tsan.sh. build/tsan with clang and -DVOROCLIP_SANITIZE=thread, against
# oneTBB rebuilt with TSan; the test cases tagged [threads] (they compare 1 with N threads) of
# every module with parallel code, at N = 2 and 4. No suppression: the first report fails.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

# Debian's libtbb is not instrumented: TSan would not see its scheduler's hand-offs and would
# report every parallel loop. scripts/tsan_tbb.sh builds Debian's own oneTBB source (libtbb
# alone) with -DTBB_SANITIZE=thread (oneTBB's documented way) into build/tsan/tbb, once.
# Clang: the TBB build and ours must share one TSan runtime. -O1 -g1: line tables for the
# reports' stacks.
bash scripts/tsan_tbb.sh build/tsan
cmake -S . -B build/tsan -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DVOROCLIP_SANITIZE=thread \
  -DTBB_DIR="$PWD/build/tsan/tbb/lib/cmake/TBB" -DVOROCLIP_WITH_CGAL_TESTS=OFF \
  -DVOROCLIP_BUILD_BENCH=OFF -DVOROCLIP_BUILD_APPS=OFF -DVOROCLIP_WERROR=ON
# The test executables of the modules with parallel code: Delaunay 2D/3D; clip 2D, 3D and the
# 3D domains (Surface3, Domain3, the self-intersection search); CVT 2D/3D; mesh2d, tet
# quality, Hausdorff (test_mesh); mesh3d, its extraction and slivers (test_mesh3d).
tsan_delaunay=(delaunay/test_delaunay2 delaunay/test_delaunay3)
tsan_tests=(clip/test_clip clip/test_clip3d clip/test_domain3 cvt/test_cvt mesh/test_mesh
  mesh/test_mesh3d)
SECONDS=0
cmake --build build/tsan -j2 --target "${tsan_delaunay[@]##*/}" "${tsan_tests[@]##*/}"
echo "-- tsan.sh: build in ${SECONDS}s"
# [threads]: every test case that compares 1 with N threads, less [large] (Delaunay3 on
# 150k-300k points: the same parallel passes as the [threads] ones on 20k-30k points, whose
# uniform input already takes a zone pass along the Hilbert curve, at 10 times the cost
# under TSan) and the hidden ones. -w NoTests: a filter that matches nothing fails the run.
tsan_filter='[threads]~[large]~[.]'
# VOROCLIP_TEST_THREADS: the session's arena and the N of every 1-vs-N comparison
# (tests/support/threads.h). halt_on_error + exitcode: the first report fails the stage.
tsan_run() {
  local start=$SECONDS
  VOROCLIP_TEST_THREADS=$1 VOROCLIP_TEST_SCALE=0.3 \
    TSAN_OPTIONS="halt_on_error=1 exitcode=66 second_deadlock_stack=1" \
    "build/tsan/tests/$2" -w NoTests "$tsan_filter"
  echo "-- tsan.sh: $2, $1 threads: $((SECONDS - start))s"
}
# The Delaunay cases build with 1, 2 and 4 threads themselves (tests/delaunay/with_threads.h;
# the strips of Delaunay2 with 1 and VOROCLIP_TEST_THREADS): one session, at 4.
for t in "${tsan_delaunay[@]}"; do tsan_run 4 "$t"; done
for threads in 2 4; do
  for t in "${tsan_tests[@]}"; do tsan_run "$threads" "$t"; done
done

echo "==== tsan.sh: PASSED: the parallel tests at 2 and 4 threads under ThreadSanitizer," \
  "in ${SECONDS}s after the TBB build"
