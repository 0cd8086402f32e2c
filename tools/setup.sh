#!/usr/bin/env bash
# Installs every Debian package locus needs to build, test and benchmark.
# Idempotent: when everything is present it prints nothing and does not touch apt.
set -euo pipefail
PKGS=(
  build-essential cmake ninja-build pkg-config
  libtbb-dev libeigen3-dev libmetis-dev libopenblas-dev liblapacke-dev
  libxsimd-dev libflatbuffers-dev flatbuffers-compiler doctest-dev
  libcli11-dev nlohmann-json3-dev libstb-dev
  libsuitesparse-dev                 # CHOLMOD: test/benchmark peer only
  clang libclang-rt-14-dev           # libFuzzer + sanitizer runtimes
)
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
echo "locus setup: installing ${missing[*]}" >&2
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
