#!/usr/bin/env bash
# Fetches and unpacks the METIS sources that locus compiles into itself.
#
#   bash tools/fetch_metis.sh [DEST]     (default cache/deps/metis-<version>)
#
# Why locus compiles METIS: Debian's libmetis.so draws its random numbers from
# the C library's rand()/srand(), one generator for the whole process, shared
# with the host program. locus compiles the same sources with rand/srand
# renamed (cmake/metis.cmake) so that METIS draws from a generator of the
# calling thread and the host's rand() sequence is never touched.
#
# The sources are Debian's own source package of the pinned version (the one
# whose binary locus used before, so the orderings stay bit-identical), fetched
# with apt-get source through a private apt state directory (the system's apt
# configuration is untouched, as in tools/tsan.sh), checked against pinned
# SHA-256 sums, and unpacked by dpkg-source (which applies Debian's patches).
# Idempotent: prints nothing and touches nothing when DEST is already complete.
# CMake runs it at configure time when its cache is missing; tools/setup.sh
# runs it too, so a machine set up once builds offline.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

version=5.1.0.dfsg-7
declare -A sha256=(
  [metis_5.1.0.dfsg.orig.tar.xz]=c50a88b92b01fa3972c5c92cf50117f126c62589b8f793657c7d865c59c23615
  [metis_5.1.0.dfsg-7.debian.tar.xz]=5d7c0b63501c4825945c6ddfec575c61ab383e518160e942bde7e8dd0861f8bd
)
dest=${1:-$root/cache/deps/metis-$version}
case "$dest" in /*) ;; *) dest="$root/$dest" ;; esac
stamp="metis $version"
[ -f "$dest/libmetis/ometis.c" ] && [ "$(cat "$dest/.locus-stamp" 2>/dev/null)" = "$stamp" ] && exit 0

die() {
  cat >&2 <<EOF
tools/fetch_metis.sh: $1
locus compiles METIS $version from Debian's source package (apt-get source metis=$version).
It needs network access to a Debian archive that still carries that version
(bookworm, or snapshot.debian.org) and dpkg-dev. Alternatively unpack the
source package yourself (dpkg-source -x metis_$version.dsc DIR) and configure
with -DLOCUS_METIS_SOURCE_DIR=DIR.
EOF
  exit 1
}
command -v apt-get >/dev/null || die "apt-get not found"
command -v dpkg-source >/dev/null || die "dpkg-source not found (apt-get install dpkg-dev)"

echo "tools/fetch_metis.sh: fetching Debian's metis $version source package into $dest" >&2
work="$dest.tmp.$$"
trap 'rm -rf "$work"' EXIT
rm -rf "$work"
mkdir -p "$work/src"
# Source entries for the archives this machine already uses (deb -> deb-src),
# plus bookworm's (the release that carries the pinned version) if absent.
. "$root/tools/private_apt_sources.sh"
private_apt_sources "$work"
if ! grep -rqsE '(^|[[:space:]])bookworm([[:space:]]|$)' "$work/apt/sources.list" "$work/apt/sources.list.d"; then
  echo "deb-src [signed-by=/usr/share/keyrings/debian-archive-keyring.gpg] http://deb.debian.org/debian bookworm main" \
    >> "$work/apt/sources.list"
fi
apt-get "${apt_opts[@]}" -qq update >"$work/apt.log" 2>&1 || { cat "$work/apt.log" >&2; die "apt-get update failed"; }
(cd "$work/src" && apt-get "${apt_opts[@]}" -qq source --download-only "metis=$version") >>"$work/apt.log" 2>&1 ||
  { cat "$work/apt.log" >&2; die "apt-get source metis=$version failed"; }
for f in "${!sha256[@]}"; do
  [ -f "$work/src/$f" ] || die "$f missing from the source package"
  echo "${sha256[$f]}  $work/src/$f" | sha256sum -c --quiet - || die "$f: SHA-256 differs from the pinned sum"
done
# apt checked the files against the signed Sources index; dpkg-source's own
# signature check of the .dsc needs debian-keyring and only warns without it.
(cd "$work/src" && dpkg-source -x "metis_$version.dsc" tree) >"$work/unpack.log" 2>&1 ||
  { cat "$work/unpack.log" >&2; die "dpkg-source -x failed"; }
echo "$stamp" > "$work/src/tree/.locus-stamp"
rm -rf "$dest"
mkdir -p "$(dirname "$dest")"
mv "$work/src/tree" "$dest"
echo "tools/fetch_metis.sh: METIS sources in $dest" >&2
