#!/usr/bin/env bash
# The whole test suite, as CI runs it (.ci/run calls this script verbatim):
#   1. dependencies          bash scripts/setup.sh --deps-only
#   2. formatting            clang-format --dry-run --Werror on every .h/.cpp
#   3. Release build         build/test, warnings as errors, benchmarks and the Python
#                            package built; full ctest
#   4. Python tests          pytest python/tests against build/test's package and CLI
#   5. ASan + UBSan build    build/asan, without the CGAL tests and the benchmarks; ctest
#                            without the install test
#   6. ThreadSanitizer       build/tsan (clang, oneTBB rebuilt with TSan by
#                            scripts/tsan_tbb.sh): the parallel tests at 2 and 4 threads
# Stops at the first failure with a non-zero exit status.
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."

stage_name="start"
stage() {
  stage_name="$1"
  echo
  echo "==== test.sh: $1"
}
trap 'echo "==== test.sh: FAILED in stage: $stage_name" >&2' ERR

stage "1/6 dependencies (scripts/setup.sh --deps-only)"
bash scripts/setup.sh --deps-only

stage "2/6 clang-format check"
dirs=()
for d in core predicates delaunay clip cvt mesh apps bench tests python; do
  if [[ -d "$d" ]]; then dirs+=("$d"); fi
done
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  # Tracked files plus new ones not ignored, so a local run also checks unstaged work.
  mapfile -t listed < <(git ls-files --cached --others --exclude-standard -- "${dirs[@]}")
else
  mapfile -t listed < <(find "${dirs[@]}" -type f | sort)
fi
files=()
for f in "${listed[@]}"; do
  if [[ "$f" =~ \.(h|cpp)$ && -f "$f" ]]; then files+=("$f"); fi
done
echo "checking ${#files[@]} files against .clang-format ($(clang-format --version))"
clang-format --dry-run --Werror "${files[@]}"

stage "3/6 Release build (build/test, -DVOROCLIP_WERROR=ON) and ctest"
cmake -S . -B build/test -DCMAKE_BUILD_TYPE=Release -DVOROCLIP_WERROR=ON \
  -DVOROCLIP_BUILD_PYTHON=ON -DPython_EXECUTABLE=/usr/bin/python3
cmake --build build/test -j2
ctest --test-dir build/test --output-on-failure -j2

stage "4/6 Python tests (pytest python/tests on build/test/python)"
# Debian's /usr/bin/python3: the `python3` first on PATH may not see Debian's numpy, scipy,
# meshio and pytest. The tests run the examples and compare with build/test's CLI.
PYTHONPATH="$PWD/build/test/python" VOROCLIP_CLI="$PWD/build/test/bin/voroclip" \
  MPLBACKEND=Agg /usr/bin/python3 -m pytest -q -p no:cacheprovider python/tests

stage "5/6 ASan+UBSan build (build/asan) and ctest without the install test"
# -O1 -g1 (line tables, enough for the sanitizers' stack traces): test_clip3d.cpp compiles
# in 27 s instead of 71 s with RelWithDebInfo's -O2 -g (2.0 GHz EPYC host), and this stage's
# build was 18 of the suite's 30 minutes there.
cmake -S . -B build/asan -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
  -DVOROCLIP_SANITIZE=address,undefined -DVOROCLIP_WITH_CGAL_TESTS=OFF \
  -DVOROCLIP_BUILD_BENCH=OFF -DVOROCLIP_WERROR=ON
cmake --build build/asan -j2
# Random-input counts at 30% under the sanitizers (VOROCLIP_TEST_SCALE, see
# tests/predicates/exact_oracle.h): same code paths, a third of the time.
VOROCLIP_TEST_SCALE=0.3 UBSAN_OPTIONS=print_stacktrace=1 ctest --test-dir build/asan --output-on-failure -j2 -E install

stage "6/6 ThreadSanitizer build (build/tsan) and the parallel tests at 2 and 4 threads"
# Debian's libtbb is not instrumented: TSan would not see its scheduler's hand-offs and would
# report every parallel loop. scripts/tsan_tbb.sh builds Debian's own oneTBB source with
# -DTBB_SANITIZE=thread (oneTBB's documented way) into build/tsan/tbb, once. No suppression.
# Clang: the TBB build and ours must share one TSan runtime. Only the test executables of
# the parallel modules are built.
bash scripts/tsan_tbb.sh build/tsan
cmake -S . -B build/tsan -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DVOROCLIP_SANITIZE=thread \
  -DTBB_DIR="$PWD/build/tsan/tbb/lib/cmake/TBB" -DVOROCLIP_WITH_CGAL_TESTS=OFF \
  -DVOROCLIP_BUILD_BENCH=OFF -DVOROCLIP_BUILD_APPS=OFF -DVOROCLIP_WERROR=ON
tsan_delaunay=(delaunay/test_delaunay2 delaunay/test_delaunay3)
tsan_tests=(clip/test_clip clip/test_clip3d cvt/test_cvt mesh/test_mesh mesh/test_mesh3d)
cmake --build build/tsan -j2 --target "${tsan_delaunay[@]##*/}" "${tsan_tests[@]##*/}"
# The test cases that run the parallel code against one thread (names with "thread", tags
# [parallel] and [threads]), less the Delaunay3 ones on 200k-300k points (minutes under
# TSan; the 1, 2, 4-thread case and the presorted one cover the same passes on fewer points).
# VOROCLIP_TEST_THREADS: the session's arena and the N of every 1-vs-N comparison
# (tests/support/threads.h). halt_on_error + exitcode: the first report fails the stage.
tsan_filter='*thread*,[parallel],[threads],~*Hilbert curve*,~*300k points*,~*AVX2*,~*slot limit*,~*no round of*'
# The Delaunay cases build with 1, 2 and 4 threads themselves (tests/delaunay/with_threads.h):
# one session, at 4.
tsan_run() {
  echo "-- $2, $1 threads"
  VOROCLIP_TEST_THREADS=$1 VOROCLIP_TEST_SCALE=0.3 \
    TSAN_OPTIONS="halt_on_error=1 exitcode=66 second_deadlock_stack=1" \
    "build/tsan/tests/$2" "$tsan_filter"
}
for t in "${tsan_delaunay[@]}"; do tsan_run 4 "$t"; done
for threads in 2 4; do
  for t in "${tsan_tests[@]}"; do tsan_run "$threads" "$t"; done
done

echo
echo "==== test.sh: PASSED: format (${#files[@]} files), Release build + ctest, pytest," \
  "ASan/UBSan build + ctest, TSan build + parallel tests at 2 and 4 threads, in ${SECONDS}s"
