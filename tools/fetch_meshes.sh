#!/usr/bin/env bash
# Obtains CGAL's sample meshes (armadillo.off and ~140 others) from Debian's
# libcgal-demo package: no network beyond the Debian archive.
# Usage: tools/fetch_meshes.sh [CACHE_DIR]   (default: ./cache/meshes)
set -euo pipefail
dest="${1:-$(cd "$(dirname "$0")/.." && pwd)/cache/meshes}"
if [ -f "$dest/armadillo.off" ]; then exit 0; fi
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
cd "$tmp"
if ! apt-get download libcgal-demo >/dev/null 2>&1; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq && apt-get download libcgal-demo >/dev/null 2>&1
fi
dpkg -x libcgal-demo_*.deb x
mkdir -p data "$dest"
tar xzf x/usr/share/doc/libcgal-dev/data.tar.gz -C data
cp data/data/meshes/*.off "$dest/"
echo "locus: $(ls "$dest"/*.off | wc -l) meshes in $dest" >&2
