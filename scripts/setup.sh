#!/usr/bin/env bash
# Installs the Debian packages voroclip needs, then configures and builds build/release.
#
#   bash scripts/setup.sh              packages + Release build (build/release/bin/voroclip
#                                      and the Python package in build/release/python)
#   bash scripts/setup.sh --deps-only  packages only (scripts/test.sh uses this)
#
# apt is skipped entirely when every package is already installed. Installing needs root:
# the script uses sudo when it is not run as root.
set -euo pipefail

packages=(
  build-essential cmake git
  libeigen3-dev libtbb-dev libcli11-dev nlohmann-json3-dev liblbfgspp-dev zlib1g-dev libmuparser-dev
  catch2 libbenchmark-dev libcgal-dev libgmp-dev libmpfr-dev voro++-dev
  clang-format
  # The TSan stage of scripts/test.sh and the fuzz targets: clang with its sanitizer runtimes
  # and libFuzzer; dpkg-dev for scripts/tsan_tbb.sh's `apt-get source`.
  clang libclang-rt-dev dpkg-dev
  python3-meshio python3-gmsh
  # The Python package (python/): pybind11 and numpy to build it, pytest, scipy and
  # matplotlib for its tests and examples, pip and setuptools for `pip install .`.
  python3-dev pybind11-dev python3-pybind11 python3-numpy python3-pytest python3-scipy
  python3-matplotlib python3-setuptools python3-pip
)

deps_only=0
for arg in "$@"; do
  case "$arg" in
    --deps-only) deps_only=1 ;;
    -h | --help)
      sed -n '2,8p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'
      exit 0
      ;;
    *)
      echo "setup.sh: unknown argument '$arg' (expected --deps-only)" >&2
      exit 2
      ;;
  esac
done

cd "$(dirname "${BASH_SOURCE[0]}")/.."

if ! command -v dpkg-query >/dev/null 2>&1; then
  echo "setup.sh: dpkg-query not found; this script installs Debian packages (Debian 12" \
    "or a derivative). Install the equivalents of: ${packages[*]}" >&2
  exit 1
fi

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  if [[ "$status" != "install ok installed" ]]; then
    missing+=("$p")
  fi
done

if [[ ${#missing[@]} -eq 0 ]]; then
  echo "==> setup: all ${#packages[@]} Debian packages are installed; skipping apt-get"
else
  if [[ $(id -u) -eq 0 ]]; then
    as_root=()
  elif command -v sudo >/dev/null 2>&1; then
    as_root=(sudo)
  else
    echo "setup.sh: missing packages (${missing[*]}) and not root, and sudo is not" \
      "available; run this script as root" >&2
    exit 1
  fi
  echo "==> setup: installing ${#missing[@]} missing package(s): ${missing[*]}"
  echo "==> setup: apt-get update"
  "${as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update
  echo "==> setup: apt-get install"
  "${as_root[@]}" env DEBIAN_FRONTEND=noninteractive \
    apt-get install -y --no-install-recommends "${missing[@]}"
fi

if [[ $deps_only -eq 1 ]]; then
  echo "==> setup: dependencies ready (--deps-only: not building)"
  exit 0
fi

# The library, the command-line tool and the Python package; scripts/test.sh builds the
# tests and benchmarks in build trees of its own. The Python package is built for Debian's
# /usr/bin/python3 (the one its pybind11 and numpy belong to), whatever python3 is first on
# PATH.
echo "==> setup: configuring build/release (Release, library, CLI and Python package)"
cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release -DVOROCLIP_BUILD_TESTS=OFF \
  -DVOROCLIP_BUILD_BENCH=OFF -DVOROCLIP_BUILD_PYTHON=ON -DPython_EXECUTABLE=/usr/bin/python3
echo "==> setup: building (cmake --build build/release -j2)"
cmake --build build/release -j2
echo "==> setup: done; the tool is build/release/bin/voroclip, the Python package" \
  "build/release/python/voroclip (PYTHONPATH=build/release/python /usr/bin/python3)"
