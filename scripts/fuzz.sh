#!/usr/bin/env bash
# Runs the libFuzzer targets of fuzz/ (issue 34):
#   scripts/fuzz.sh TARGET SECONDS [libFuzzer options...]   one target, e.g. fuzz_medit 600
#   scripts/fuzz.sh all SECONDS [libFuzzer options...]      every target, FUZZ_JOBS (default
#                                                           2) at a time
#   scripts/fuzz.sh list                                    the targets
# Builds build/fuzz with clang (-DVOROCLIP_FUZZ=ON; only the fuzz targets and what they
# link), gathers the seeds (fuzz/seeds/TARGET, meshes and surfaces written by the library's
# own writers, small files of ../shared/data and of tests/), then fuzzes under nice -n 19
# from the corpus build/fuzz/corpus/TARGET (kept between runs, new inputs go there) and the
# seeds, with:
#   -max_len      per format (below), -timeout=10 (a slower input is a finding),
#   -rss_limit_mb=2048, -malloc_limit_mb=$FUZZ_MALLOC_LIMIT_MB (default 32: no input of
#   max_len bytes may make one allocation of more than that: counts in headers must be
#   checked against the bytes after them), the format's dictionary fuzz/dict/*.dict.
# Findings (crash-*, leak-*, timeout-*, oom-*) go to build/fuzz/artifacts/; reproduce one
# with build/fuzz/fuzz/TARGET FILE. Exit status non-zero when a target found something.
#
# To add a target: fuzz/TARGET.cpp, a voroclip_add_fuzzer() line in fuzz/CMakeLists.txt,
# and a line in the table below (max_len, dictionary or -, seed sources).
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."
root="$PWD"
build="${FUZZ_BUILD_DIR:-$root/build/fuzz}"  # FUZZ_BUILD_DIR: another build directory
shared="$root/../shared/data"

# target  max_len  dictionary  seeds from ../shared/data and tests/ (globs, files <= 200 kB)
table="
fuzz_medit     65536 medit   tetmeshes/*.mesh tests/*.mesh
fuzz_tetgen    65536 tetgen  -
fuzz_gmsh      65536 gmsh    tests/*.msh
fuzz_vtk       65536 vtk     tests/*.vtk
fuzz_vtu       65536 vtu     tests/*.vtu
fuzz_surface   65536 surface surfaces/*.obj surfaces/*.off surfaces/*.stl surfaces/*.ply tests/*.obj tests/*.off tests/*.stl tests/*.ply
fuzz_polygon   65536 polygon polygons/valid/*.json polygons/degenerate/*.json tests/*.poly tests/*.json
fuzz_points    16384 points  -
fuzz_surface3  4096  -       -
fuzz_domain2   4096  -       -
fuzz_sites     1024  -       -
fuzz_density_sol 16384 density_sol -
fuzz_density_vtu 16384 density_vtu -
fuzz_density_vtk 16384 density_vtk -
"

targets() { awk 'NF { print $1 }' <<<"$table"; }
field() { awk -v t="$1" -v f="$2" '$1 == t { print $f }' <<<"$table"; }
seed_globs() { awk -v t="$1" '$1 == t { for (i = 4; i <= NF; ++i) print $i }' <<<"$table"; }

usage() {
  echo "usage: scripts/fuzz.sh TARGET|all SECONDS [libFuzzer options...] | list" >&2
  echo "targets: $(targets | tr '\n' ' ')" >&2
  exit 2
}

[[ $# -ge 1 ]] || usage
if [[ "$1" == list ]]; then
  targets
  exit 0
fi
[[ $# -ge 2 && "$2" =~ ^[0-9]+$ ]] || usage
what="$1"
seconds="$2"
shift 2
if [[ "$what" == all ]]; then
  mapfile -t run < <(targets)
elif targets | grep -qx -- "$what"; then
  run=("$what")
else
  usage
fi

# ---- Build (only what the targets link).
if [[ ! -f "$build/CMakeCache.txt" ]]; then
  # -O1 -g1: fast to build, line tables for the reports.
  cmake -S "$root" -B "$build" -DCMAKE_CXX_COMPILER="${FUZZ_CXX:-clang++}" \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" \
    -DVOROCLIP_FUZZ=ON -DVOROCLIP_BUILD_TESTS=OFF -DVOROCLIP_BUILD_APPS=OFF \
    -DVOROCLIP_BUILD_BENCH=OFF -DVOROCLIP_BUILD_PYTHON=OFF -DVOROCLIP_WITH_CGAL_TESTS=OFF \
    ${FUZZ_CMAKE_ARGS:-} >/dev/null
fi
if [[ -z "${FUZZ_NO_BUILD:-}" ]]; then  # FUZZ_NO_BUILD=1: run what is built
  cmake --build "$build" -j"${FUZZ_BUILD_JOBS:-2}" --target "${run[@]}" fuzz_write_seeds
fi

# ---- Seeds: build/fuzz/seeds/TARGET, rebuilt on every run (cheap).
mkdir -p "$build/seeds" "$build/corpus" "$build/artifacts"
for t in "${run[@]}"; do
  rm -rf "$build/seeds/$t"
done
# The writers' files, in a directory of this run's own (runs of other targets may be going).
writers=$(mktemp -d "$build/seeds/writers.XXXXXX")
trap 'rm -rf "$writers"' EXIT
"$build/fuzz/fuzz_write_seeds" "$writers"
for t in "${run[@]}"; do
  mkdir -p "$build/seeds/$t"
  if [[ -d "$writers/$t" ]]; then cp "$writers/$t"/* "$build/seeds/$t/"; fi
  if [[ -d "$root/fuzz/seeds/$t" ]]; then cp "$root/fuzz/seeds/$t"/* "$build/seeds/$t/"; fi
  while read -r glob; do
    [[ -n "$glob" && "$glob" != - ]] || continue
    if [[ "$glob" == tests/* ]]; then
      # The tests' own input files, anywhere under tests/.
      files=$(find "$root/tests" -type f -name "${glob#tests/}" -size -200k)
    elif [[ -d "$shared" ]]; then
      files=$(find "$shared" -type f -path "$shared/$glob" -size -200k)
    else
      files=""
    fi
    for f in $files; do cp "$f" "$build/seeds/$t/$(basename "$(dirname "$f")")_$(basename "$f")"; done
  done < <(seed_globs "$t")
done

# ---- Fuzz: FUZZ_JOBS targets at a time (default 2, the machine's cores), each one a single
# libFuzzer process with its own log; the reports are printed in the table's order.
fuzz_one() {
  local t="$1" exe="$build/fuzz/$1" corpus="$build/corpus/$1" max_len dict
  shift
  max_len=$(field "$t" 2)
  dict=$(field "$t" 3)
  local opts=(-max_len="$max_len" -timeout=10 -rss_limit_mb=2048
    -malloc_limit_mb="${FUZZ_MALLOC_LIMIT_MB:-32}" -artifact_prefix="$build/artifacts/$t-"
    -print_final_stats=1)
  if [[ "$dict" != - ]]; then opts+=(-dict="$root/fuzz/dict/$dict.dict"); fi
  # The corpus first (new inputs go there), then the seeds: each one runs once at the start,
  # so a seed that is a finding stops the run.
  nice -n 19 "$exe" "${opts[@]}" -max_total_time="$seconds" "$@" "$corpus" \
    "$build/seeds/$t" >"$build/$t.log" 2>&1
}

jobs_max="${FUZZ_JOBS:-2}"
[[ "$jobs_max" =~ ^[1-9][0-9]*$ ]] || { echo "fuzz.sh: FUZZ_JOBS must be >= 1" >&2; exit 2; }
declare -A pid_of
for t in "${run[@]}"; do
  mkdir -p "$build/corpus/$t"
  echo "==== fuzz.sh: $t for ${seconds}s ($(ls "$build/seeds/$t" | wc -l) seeds, corpus" \
    "$(ls "$build/corpus/$t" | wc -l) inputs)"
  while (($(jobs -rp | wc -l) >= jobs_max)); do wait -n || true; done
  fuzz_one "$t" "$@" &
  pid_of[$t]=$!
done

status=0
for t in "${run[@]}"; do
  echo -n "---- $t: "
  if ! wait "${pid_of[$t]}"; then
    echo "FINDING"
    echo "fuzz.sh: $t: FINDING (log $build/$t.log, artifacts $build/artifacts/$t-*)" >&2
    grep -a -A30 "==ERROR\|SUMMARY\|voroclip fuzz:\|runtime error" "$build/$t.log" | head -60 >&2 || true
    status=1
  fi
  grep -a "^stat::\|^#.*DONE" "$build/$t.log" | tr '\n' ' ' || true
  echo
done
exit $status
