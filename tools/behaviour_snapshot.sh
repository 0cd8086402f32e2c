#!/usr/bin/env bash
# Runs a fixed set of locus commands and keeps their JSON and output files, so
# two builds can be compared byte for byte (a refactoring must not change what
# the tool computes):
#
#   bash tools/behaviour_snapshot.sh BUILD_DIR OUT_DIR        # run one build
#   bash tools/behaviour_snapshot.sh --compare DIR_A DIR_B    # diff two snapshots
#   SNAP_ONLY=REGEX bash tools/behaviour_snapshot.sh ...      # only the matching commands, keeping the rest
#
# Inputs: cache/meshes/armadillo.off (tools/fetch_meshes.sh) and a polygon mesh
# (cache/meshes/cube_quad.off, and a generated quad grid). Wall-clock fields are taken out of the JSON
# (keys ending in _s or _s_all, "timings", "seconds", speedups and iter_ratio,
# peak RSS, "version" and "load", which describe the run, not the result; the
# output and temporary paths are replaced by OUT and TMP); everything
# else, and every output file, must be identical. --threads 2 everywhere.
set -euo pipefail
cd "$(dirname "$0")/.."

if [ "${1:-}" = "--compare" ]; then
  a=$2 b=$3
  if diff -r "$a" "$b" >/dev/null; then
    echo "behaviour_snapshot: identical ($(ls "$a" | wc -l) files)"
    exit 0
  fi
  diff -r "$a" "$b" | head -40
  echo "behaviour_snapshot: DIFFERENT" >&2
  exit 1
fi

B=${1:?usage: behaviour_snapshot.sh BUILD_DIR OUT_DIR}
OUT=${2:?usage: behaviour_snapshot.sh BUILD_DIR OUT_DIR}
L="$B/locus"
A=cache/meshes/armadillo.off
Q=cache/meshes/cube_quad.off
G=$(mktemp -d)/quad_grid.off  # a 13x13-vertex quad grid with a bump: a polygon disk
trap 'rm -rf "$(dirname "$G")"' EXIT
awk 'BEGIN { n = 13; print "OFF"; print n*n, (n-1)*(n-1), 0
  for (j = 0; j < n; j++) for (i = 0; i < n; i++) { x = i / (n-1) - 0.5; y = j / (n-1) - 0.5
    printf "%.6f %.6f %.6f\n", x, y, 0.2 * exp(-8 * (x*x + y*y)) + 0.01 * ((i * 7 + j * 3) % 5) / 5 }
  for (j = 0; j < n-1; j++) for (i = 0; i < n-1; i++) { v = j*n + i; print 4, v, v+1, v+n+1, v+n } }' > "$G"
[ -x "$L" ] || { echo "no $L" >&2; exit 2; }
[ -f "$A" ] || { echo "no $A (run tools/fetch_meshes.sh)" >&2; exit 2; }
[ -z "${SNAP_ONLY:-}" ] && rm -rf "$OUT"; mkdir -p "$OUT"

# Drops run-dependent keys from a JSON object (one line on stdin).
strip_json() {
  python3 -c '
import json, sys
RUN = {"timings", "seconds", "version", "load", "peak_rss_mb", "rss_mb", "progress_calls", "iter_ratio"}
OUT, TMP = sys.argv[1], sys.argv[2]
def timing(k):
    return k in RUN or k.endswith(("_s", "_ms", "_s_all")) or k.startswith(("timing", "speedup"))
def clean(x):
    if isinstance(x, dict):
        return {k: clean(v) for k, v in x.items() if not timing(k)}
    if isinstance(x, list):
        return [clean(v) for v in x]
    if isinstance(x, str):
        return x.replace(OUT, "OUT").replace(TMP, "TMP")
    return x
print(json.dumps(clean(json.load(sys.stdin)), indent=1, sort_keys=True))' "$OUT" "$(dirname "$G")"
}

run() {  # run NAME EXT ARGS...: locus ARGS --json -o OUT/NAME.EXT
  local name=$1 ext=$2; shift 2
  [[ "$name" =~ ${SNAP_ONLY:-.} ]] || return 0
  local o=()
  [ "$ext" != "-" ] && o=(-o "$OUT/$name.$ext")
  if "$L" "$@" --threads 2 --json "${o[@]}" > "$OUT/$name.raw.json" 2> "$OUT/$name.stderr"; then
    strip_json < "$OUT/$name.raw.json" > "$OUT/$name.json"
  else
    echo "exit $?" > "$OUT/$name.json"
  fi
  rm -f "$OUT/$name.raw.json" "$OUT/$name.stderr"
  echo "  $name"
}

echo "behaviour_snapshot: $L -> $OUT"
run factor - factor "$A" --operator heat
run factor_lap - factor "$A" --operator laplacian
run geodesic ply geodesic "$A" --source 0
run geodesic_local ply geodesic "$A" --source 100 --fraction 0.1
run logmap ply logmap "$A" --center 0 --fraction 0.06
run logmap_dem ply logmap "$A" --center 100 --fraction 0.05 --method dem
run cvt ply cvt "$A" --sites 200 --iters 5
run voronoi ply voronoi "$A" --random 50
run deform ply deform "$A" --roi-seed 0 --roi-fraction 0.1 --handle 0 --offset 0.01,0.02,0
run param_patch ply param "$A" --center 0 --fraction 0.1
run param_circle ply param "$A" --center 0 --fraction 0.1 --boundary circle
run adf ply adf "$A" --all
run hks ply hks "$A" --ts 1h2,10h2,100h2 --all
run heat - heat "$A" --source 0,1,2 --target 100,200
run nncoords - nncoords "$A" --sites 0,100,200,300,400,500 --point 10,0.2,0.3,0.5
run skinweights ply skinweights cache/meshes/elephant.off --handles 0,100,200
run perfect_laplacian_quad obj perfect-laplacian "$Q"
run info_quad - info "$Q"
run param_quad obj param "$G"
run selfsupport_quad obj selfsupport "$G"
run perfect_laplacian_grid obj perfect-laplacian "$G"
echo "behaviour_snapshot: $(ls "$OUT" | wc -l) files"
