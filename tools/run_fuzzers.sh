#!/usr/bin/env bash
# Builds the libFuzzer targets (tools/fuzz/fuzz_*.cpp) with clang into
# build-fuzz/ and runs each one for MINUTES minutes (default 1), one after the
# other, under `nice -n 10`. Each target starts from a working corpus
# build-fuzz/corpus/<target>/ seeded from tests/fuzz_corpus/<name>/ (<name> =
# the target without "fuzz_", e.g. load_factor, cli_options, c_api) or, for the
# readers, tests/fuzz_corpus/<format>/ (fuzz_read_ply -> ply).
# Prints the number of executed inputs per target and exits non-zero if any
# target produced a crash / leak / timeout / out-of-memory file.
#
#   tools/run_fuzzers.sh [MINUTES] [TARGET ...]     e.g. tools/run_fuzzers.sh 10 fuzz_read_ply
# LOCUS_FUZZ_BUILD=DIR uses another build directory (default build-fuzz).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
minutes="${1:-1}"
shift || true
build="${LOCUS_FUZZ_BUILD:-$here/build-fuzz}"

cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DLOCUS_BUILD_FUZZERS=ON -DLOCUS_BUILD_TESTS=OFF -DLOCUS_BUILD_TOOLS=OFF >/dev/null

if [ "$#" -gt 0 ]; then targets=("$@"); else
  targets=()
  for src in "$here"/tools/fuzz/fuzz_*.cpp; do targets+=("$(basename "$src" .cpp)"); done
fi
nice -n 10 cmake --build "$build" -j2 --target "${targets[@]}"

status=0
seconds=$(( minutes * 60 ))
for t in "${targets[@]}"; do
  fmt="${t##*_}"                                  # fuzz_read_ply -> ply
  name="${t#fuzz_}"                               # fuzz_load_factor -> load_factor
  seeds="$here/tests/fuzz_corpus/$name"
  [ -d "$seeds" ] || seeds="$here/tests/fuzz_corpus/$fmt"
  corpus="$build/corpus/$t"
  artifacts="$build/artifacts/$t"
  mkdir -p "$corpus" "$artifacts"
  if [ -d "$seeds" ]; then cp -n "$seeds"/* "$corpus"/ 2>/dev/null || true; fi
  # Inputs per target: argument lists are short; factor caches and meshes are files.
  case "$t" in
    fuzz_cli_options) max_len=512 ;;
    fuzz_c_api) max_len=4096 ;;
    *) max_len=16384 ;;
  esac
  dict=()
  if [ -f "$here/tools/fuzz/$name.dict" ]; then dict=(-dict="$here/tools/fuzz/$name.dict");
  elif [ -f "$here/tools/fuzz/$fmt.dict" ]; then dict=(-dict="$here/tools/fuzz/$fmt.dict"); fi
  log="$build/$t.log"
  echo "== $t: ${minutes} min, corpus $corpus, log $log"
  set +e
  nice -n 10 "$build/$t" "$corpus" "${dict[@]}" -max_total_time="$seconds" -rss_limit_mb=1024 -timeout=10 \
    -max_len="$max_len" -print_final_stats=1 -artifact_prefix="$artifacts/" >"$log" 2>&1
  rc=$?
  set -e
  grep -E "^#[0-9]+ +DONE|stat::number_of_executed_units" "$log" | sed "s/^/   $t: /" || true
  found=$(find "$artifacts" -type f \( -name 'crash-*' -o -name 'leak-*' -o -name 'timeout-*' -o -name 'oom-*' \) | wc -l)
  if [ "$rc" -ne 0 ] || [ "$found" -ne 0 ]; then
    echo "   $t: FAILED (exit $rc, $found finding file(s) in $artifacts)"; status=1
  else
    echo "   $t: ok, no findings"
  fi
done
exit $status
