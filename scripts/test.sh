#!/usr/bin/env bash
# The whole test suite, as CI runs it (.ci/run calls this script verbatim):
#   1. dependencies          bash scripts/setup.sh --deps-only
#   2. formatting            clang-format --dry-run --Werror on every .h/.cpp
#   3. Release build         build/test, warnings as errors, benchmarks and the Python
#                            package built; full ctest
#   4. Python tests          pytest python/tests against build/test's package and CLI
#   5. ASan + UBSan build    build/asan, without the CGAL tests and the benchmarks; ctest
#                            without the install test
#   6. libFuzzer smoke       build/fuzz with clang (the fuzz targets and what they link
#                            only), every target of fuzz/ for FUZZ_CI_SECONDS (default 10)
#                            from its seeds, two at a time (scripts/fuzz.sh all): whole
#                            stage <= 5 minutes
#   7. ThreadSanitizer       scripts/tsan.sh: build/tsan with clang against oneTBB rebuilt
#                            with TSan (scripts/tsan_tbb.sh, once), the test cases tagged
#                            [threads] of the parallel modules at 2 and 4 threads
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

stage "1/7 dependencies (scripts/setup.sh --deps-only)"
bash scripts/setup.sh --deps-only

stage "2/7 clang-format check"
dirs=()
for d in core predicates delaunay clip cvt mesh apps bench tests python fuzz; do
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

stage "3/7 Release build (build/test, -DVOROCLIP_WERROR=ON) and ctest"
cmake -S . -B build/test -DCMAKE_BUILD_TYPE=Release -DVOROCLIP_WERROR=ON \
  -DVOROCLIP_BUILD_PYTHON=ON -DPython_EXECUTABLE=/usr/bin/python3
cmake --build build/test -j2
ctest --test-dir build/test --output-on-failure -j2

stage "4/7 Python tests (pytest python/tests on build/test/python)"
# Debian's /usr/bin/python3: the `python3` first on PATH may not see Debian's numpy, scipy,
# meshio and pytest. The tests run the examples and compare with build/test's CLI.
PYTHONPATH="$PWD/build/test/python" VOROCLIP_CLI="$PWD/build/test/bin/voroclip" \
  MPLBACKEND=Agg /usr/bin/python3 -m pytest -q -p no:cacheprovider python/tests

stage "5/7 ASan+UBSan build (build/asan) and ctest without the install test"
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

stage "6/7 fuzz: libFuzzer targets (build/fuzz, clang) for ${FUZZ_CI_SECONDS:-10}s each"
# A smoke run, not a campaign (scripts/fuzz.sh TARGET SECONDS runs long ones): each target
# builds, its seeds and corpus load without a finding, and it fuzzes briefly. The corpus
# of earlier runs in build/fuzz/corpus is kept and grows.
# -seed=1: the same inputs in every CI run, as far as the time bound allows.
bash scripts/fuzz.sh all "${FUZZ_CI_SECONDS:-10}" -seed=1

stage "7/7 ThreadSanitizer build (build/tsan) and the parallel tests at 2 and 4 threads"
# 389 s CPU from scratch (oneTBB 25 s, our build about 235 s, the 14 runs about 130 s): about
# 4.5 minutes on an idle two-core machine (scripts/tsan.sh says what it runs and why).
bash scripts/tsan.sh

echo
echo "==== test.sh: PASSED: format (${#files[@]} files), Release build + ctest, pytest," \
  "ASan/UBSan build + ctest, libFuzzer smoke, TSan at 2 and 4 threads, in ${SECONDS}s"
