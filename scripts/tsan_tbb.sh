#!/usr/bin/env bash
# Builds oneTBB with ThreadSanitizer for the TSan build of voroclip.
#
#   bash scripts/tsan_tbb.sh BUILD_DIR     (scripts/tsan.sh, stage 7 of scripts/test.sh, uses
#                                          build/tsan)
#
# Why: Debian's libtbb.so is not instrumented, so TSan never sees the synchronisation of
# TBB's scheduler (a task spawned by one thread and stolen by another is handed over inside
# the library) and reports every parallel_for body that reads what the spawning thread wrote
# as a race. oneTBB's documented answer is to build the library itself with the sanitizer
# (cmake/README.md of oneTBB, "Sanitizers - configure, build and run": -DTBB_SANITIZE=thread;
# Intel's answer in google/sanitizers#1004 and oneTBB#1290 is the same). There is no
# suppression list that would keep races in our own lambdas visible.
#
# The source is Debian's own onetbb source package, the very version libtbb-dev installs
# (apt-get source, through a private apt configuration under BUILD_DIR: the system's apt
# sources and lists are not touched). Only libtbb is built (no tbbmalloc, tests or hwloc
# binding): voroclip uses nothing else. Installs into BUILD_DIR/tbb, whose
# lib/cmake/TBB is then given to voroclip's configure as TBB_DIR. A second run with the same
# version does nothing.
set -euo pipefail

if [[ $# -ne 1 ]]; then
  echo "usage: bash scripts/tsan_tbb.sh BUILD_DIR" >&2
  exit 2
fi
mkdir -p "$1"
build_dir=$(cd "$1" && pwd)
version=$(dpkg-query -W -f='${Version}' libtbb-dev 2>/dev/null || true)
if [[ -z "$version" ]]; then
  echo "tsan_tbb.sh: libtbb-dev is not installed (run scripts/setup.sh first)" >&2
  exit 1
fi
prefix="$build_dir/tbb"
stamp="$prefix/voroclip-tsan-stamp"
if [[ -f "$stamp" && "$(cat "$stamp")" == "$version" ]]; then
  echo "==> tsan_tbb: oneTBB $version with TSan already in $prefix"
  exit 0
fi

work="$build_dir/tbb-work"
rm -rf "$work" "$prefix"
mkdir -p "$work/apt/lists/partial" "$work/apt/cache/archives/partial" "$work/src"
cat >"$work/apt/sources.list" <<'EOF'
deb-src [signed-by=/usr/share/keyrings/debian-archive-keyring.gpg] http://deb.debian.org/debian bookworm main
deb-src [signed-by=/usr/share/keyrings/debian-archive-keyring.gpg] http://deb.debian.org/debian bookworm-updates main
deb-src [signed-by=/usr/share/keyrings/debian-archive-keyring.gpg] http://deb.debian.org/debian-security bookworm-security main
EOF
# The suites above are Debian 12's, as scripts/setup.sh assumes (one line per suite: on one
# line, a second suite would be read as a component).
apt_options=(-o "Dir::Etc::SourceList=$work/apt/sources.list" -o "Dir::Etc::SourceParts=/nonexistent"
  -o "Dir::State::Lists=$work/apt/lists" -o "Dir::Cache=$work/apt/cache")
echo "==> tsan_tbb: fetching Debian's onetbb $version source"
apt-get "${apt_options[@]}" -qq update
(cd "$work/src" && apt-get "${apt_options[@]}" -qq source --download-only "onetbb=$version")
# --no-check: apt has already checked the files against the signed Sources index (the
# .dsc signature itself would need debian-keyring).
dpkg-source --no-check -x "$work"/src/onetbb_*.dsc "$work/onetbb" >/dev/null

echo "==> tsan_tbb: building libtbb with -fsanitize=thread (${CXX:-clang++})"
# -O1 -g1: line tables for TSan's stacks; TBB_STRICT=OFF: the sanitizer's warnings (GCC's
# -Wtsan on atomic_thread_fence) are not errors in a library we only test with.
CXX="${CXX:-clang++}" CC="${CC:-clang}" cmake -S "$work/onetbb" -B "$work/build" \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
  -DTBB_SANITIZE=thread -DTBB_STRICT=OFF -DTBB_TEST=OFF -DTBB_EXAMPLES=OFF \
  -DTBBMALLOC_BUILD=OFF -DTBB_DISABLE_HWLOC_AUTOMATIC_SEARCH=ON \
  -DCMAKE_INSTALL_PREFIX="$prefix" >"$work/configure.log"
cmake --build "$work/build" -j2 >"$work/build.log"
cmake --install "$work/build" >"$work/install.log"
echo "$version" >"$stamp"
rm -rf "$work"
echo "==> tsan_tbb: installed in $prefix (TBB_DIR=$prefix/lib/cmake/TBB)"
