#!/usr/bin/env bash
# Installs every Debian package locus needs to build, test and benchmark.
# Idempotent: when everything is present it prints nothing and does not touch apt.
# Then fetches the METIS sources locus compiles into itself (tools/fetch_metis.sh,
# Debian's source package; silent when cached), so later builds need no network.
set -euo pipefail
PKGS=(
  build-essential cmake ninja-build pkg-config
  dpkg-dev                           # dpkg-source: unpacks Debian's metis source package
  libtbb-dev libeigen3-dev libopenblas-dev liblapacke-dev
  libxsimd-dev libflatbuffers-dev flatbuffers-compiler doctest-dev
  libcli11-dev nlohmann-json3-dev libstb-dev
  libassimp-dev                      # asset formats (glTF, FBX, Collada, STL, 3MF, ...) behind read_mesh
  libsuitesparse-dev                 # AMD, CAMD (BSD-3): orderings; CHOLMOD (GPL): test/benchmark peer only
  clang libclang-rt-14-dev           # libFuzzer + sanitizer runtimes
  qemu-user                          # ctest dispatch_paths: runs the build on CPUs without AVX2/AVX-512
  python3-dev pybind11-dev python3-numpy python3-pytest  # the Python module (python/) and its tests
  python3-tqdm mypy                  # the Python tests' progress-bar and stub checks
  blender                            # the add-on's ctest runs in Debian's Blender (skipped without it)
)
# `tools/setup.sh --bench-peers` also installs the peers only benchmarks use
# (CGAL's Heat_method_3 for locus-bench-cgal, GPL; SCOTCH for locus-bench-scotch,
# CeCILL-C; never linked into locus) and scipy for the remesh table's
# independent scorer (tools/remesh_score.py).
# Not by default: CI and the tests do not need them, and Boost is large.
# assimp-testmodels (real exports, ~100 MB) is not installed either: tests/io/read_assimp.cpp
# reads a few of them when present and skips that case otherwise.
if [ "${1:-}" = "--bench-peers" ]; then
  PKGS+=(libcgal-dev libscotch-dev python3-scipy)
fi
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  echo "locus setup: installing ${missing[*]}" >&2
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
bash "$(dirname "$0")/fetch_metis.sh"
