#!/usr/bin/env bash
# ThreadSanitizer job: the parallel kernels and pipelines under TSan.
#
#   bash tools/tsan.sh [BUILD_DIR]        (default build-tsan; CI runs it from .ci/run)
#
# TSan only sees the happens-before edges of code it instrumented. Debian's
# libtbb.so is not instrumented, so every oneTBB task spawn/wait looks like a
# race (hundreds of false reports inside task_group). This script therefore
# builds oneTBB itself with -fsanitize=thread from Debian's own source package
# of the installed libtbb-dev version (same headers, same ABI), into
# BUILD_DIR/_tbb/prefix, and builds locus-tests against it. Idempotent: the TBB
# build is cached under BUILD_DIR (a stamp names the version and flags) and
# only redone when the installed version changes.
#
# Test subset (fits ~20 minutes on 2 shared cores, build included): the
# ordering, symbolic analysis, factorization, solve, selected-inversion and
# factor-update kernels, and the
# pipelines that run threads or parallel loops: CVT (flow graph), the remesh
# optimization's colour-class sweeps, heat
# geodesic and log map (concurrent queries), heat Voronoi, ADF, and the
# Session's concurrent queries. OpenBLAS stays single-threaded
# (OPENBLAS_NUM_THREADS=1): locus never runs threaded BLAS (STYLE.md habit 4),
# and OpenBLAS's own thread pool is not instrumented.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
B=${1:-build-tsan}
case "$B" in /*) ;; *) B="$root/$B" ;; esac
export DEBIAN_FRONTEND=noninteractive
t0=$SECONDS
say() { echo "== tools/tsan.sh: $1 ($((SECONDS - t0)) s)"; }

# ---- 1. oneTBB with TSan, from the Debian source package of the installed version ----
tbb_dir="$B/_tbb"
prefix="$tbb_dir/prefix"
version=$(dpkg-query -W -f='${source:Version}' libtbb-dev)
srcpkg=$(dpkg-query -W -f='${source:Package}' libtbb-dev)
# clang, for oneTBB and locus alike (one TSan runtime in the process; tools/clang_tree.sh).
. "$root/tools/clang_tree.sh"
cc_id="$(clang -dumpversion 2>/dev/null || echo unknown)"
stamp="$srcpkg $version tsan clang-$cc_id nohwloc"
if [ -f "$prefix/lib/cmake/TBB/TBBConfig.cmake" ] && [ "$(cat "$prefix/.locus-stamp" 2>/dev/null)" = "$stamp" ]; then
  say "instrumented oneTBB cached ($stamp)"
else
  say "building oneTBB $version with -fsanitize=thread"
  rm -rf "$tbb_dir"
  mkdir -p "$tbb_dir/src"
  # Source entries for the archives this machine already uses (deb -> deb-src),
  # in a private apt state directory: the system's apt configuration is untouched.
  . "$root/tools/private_apt_sources.sh"
  private_apt_sources "$tbb_dir"
  apt-get "${apt_opts[@]}" -qq update
  (cd "$tbb_dir/src" && apt-get "${apt_opts[@]}" -qq source --download-only "$srcpkg=$version")
  dsc=$(ls "$tbb_dir"/src/*.dsc)
  # apt checked the files against the signed Sources index; dpkg-source's own
  # signature check of the .dsc needs debian-keyring and only warns without it.
  (cd "$tbb_dir/src" && dpkg-source -x "$dsc" tree >"$tbb_dir/unpack.log" 2>&1) || { cat "$tbb_dir/unpack.log"; exit 1; }
  # Only the tbb library (no tests, examples, tbbmalloc, Python or tbbbind): the
  # tests link TBB::tbb only. Without the hwloc switch, a machine with
  # libhwloc-dev configures tbbbind, which the install step then looks for and
  # fails (CI, stop 31). IPO is off under TSan in oneTBB's CMake already.
  cmake -S "$tbb_dir/src/tree" -B "$tbb_dir/build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "${clang_cmake_compilers[@]}" \
    -DTBB_SANITIZE=thread -DTBB_TEST=OFF -DTBB_EXAMPLES=OFF -DTBB4PY_BUILD=OFF -DTBBMALLOC_BUILD=OFF \
    -DTBB_STRICT=OFF -DTBB_DISABLE_HWLOC_AUTOMATIC_SEARCH=ON -DCMAKE_INSTALL_PREFIX="$prefix" -DCMAKE_INSTALL_LIBDIR=lib >"$tbb_dir/configure.log" 2>&1 ||
    { tail -40 "$tbb_dir/configure.log"; exit 1; }
  cmake --build "$tbb_dir/build" -j2 --target tbb >"$tbb_dir/build.log" 2>&1 || { tail -40 "$tbb_dir/build.log"; exit 1; }
  cmake --install "$tbb_dir/build" >"$tbb_dir/install.log" 2>&1 || { tail -40 "$tbb_dir/install.log"; exit 1; }
  echo "$stamp" > "$prefix/.locus-stamp"
  say "oneTBB installed in $prefix"
fi

# ---- 2. locus-tests with TSan, against that oneTBB ----
say "building locus-tests (TSan)"
# Only the test files the groups below run are compiled (keep the two lists in step).
tests="/tests/(kernels/(order/|mesh/nearest_seed_buckets|symbolic/symbolic_factor|factor/(supernodal_factor|memory_budget)|solve/(solve_|selected_inversion)"
tests="$tests|update/factor_update)|pipelines/(voronoi/(cvt_lloyd|cvt_remesh|heat_voronoi|skinning_|remesh_features|remesh_quality|remesh_flips)|geodesic/(heat_geodesic|logmap)\\.cpp"
tests="$tests|heat/adf\\.cpp)|engine/(session|c_api|session_pipelines)\\.cpp)"
clang_tree "$B"
cmake -S "$root" -B "$B" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLOCUS_SANITIZE=thread "${clang_cmake_compilers[@]}" \
  -DTBB_DIR="$prefix/lib/cmake/TBB" -DLOCUS_BUILD_TOOLS=OFF -DLOCUS_WITH_CHOLMOD_BENCH=ON \
  "-DLOCUS_TEST_FILTER=$tests" >"$B/locus-configure.log"
quiet_build "$B" locus-build.log locus-tests
# The binary must load the instrumented library (CMake's build RPATH points at
# the prefix); a system libtbb here would bring the false reports back.
tbb_loaded=$(ldd "$B/locus-tests" | awk '/libtbb\.so/ {print $3}')
case "$tbb_loaded" in
  "$prefix"/lib/*) say "locus-tests loads $tbb_loaded" ;;
  *) echo "tools/tsan.sh: locus-tests loads '$tbb_loaded', not the instrumented oneTBB in $prefix/lib" >&2; exit 1 ;;
esac

# ---- 3. The parallel subset ----
export OPENBLAS_NUM_THREADS=1
# Every report is printed; a run with any report exits 66.
opts="halt_on_error=0 second_deadlock_stack=1 history_size=4 exitcode=66"
[ -f "$root/tools/tsan.supp" ] && opts="$opts suppressions=$root/tools/tsan.supp"
export TSAN_OPTIONS="$opts ${TSAN_OPTIONS:-}"
status=0
run() {  # run NAME DOCTEST-ARGS...: one group of test cases
  local name=$1; shift
  local s=$SECONDS
  local log="$B/group.log"
  if "$B/locus-tests" --test-suite-exclude=stress "$@" 2>&1 | tee "$log" && [ "${PIPESTATUS[0]}" = 0 ]; then
    # A filter that matches no test case passes silently: a group must run one.
    if grep -qE "test cases: +0 " "$log"; then
      say "$name ran no test case (its files are not in the TSan build, or its patterns match nothing)"
      status=1
    else
      say "$name passed in $((SECONDS - s)) s"
    fi
  else
    say "$name FAILED"
    status=1
  fi
}
run "ordering (nested dissection task tree at 1/2/3/8 threads, per-thread METIS random numbers, parallel contraction blocks)" --source-file='*tests/kernels/order/*'
run "symbolic analysis (subtree pieces, chunked scatters, assembly map; 1/2/3/8 threads)" --source-file='*tests/kernels/*/symbolic_factor*'
run "factorization" --source-file='*tests/kernels/*/supernodal_factor*'
run "solves" --source-file='*tests/kernels/*/solve_*'
run "selected inversion" --source-file='*tests/kernels/*/selected_inversion*'
run "factor update" --source-file='*tests/kernels/*/factor_update*'
run "memory budget" --source-file='*tests/kernels/*/memory_budget*'
run "CVT (flow graph)" --source-file='*tests/pipelines/*/cvt_lloyd*'
run "graph-metric labels (a bucket's offers in parallel, applied in queue order)" --source-file='*tests/kernels/mesh/nearest_seed_buckets*'
run "remesh optimization (parallel colour-class sweeps), with features; the Hausdorff search" --test-case='cvt remesh: sphere*,remesh optimization:*,cvt remesh with features*,remesh quality: the Hausdorff*'
run "heat geodesic and log map threads" --test-case='*queries from several threads*,*log map: angles from the batched*'
run "ADF and heat Voronoi threads" --test-case='*adf: results do not depend on the thread count*,*heat voronoi: localized*'
# The cases that compare 1 and 2 threads; the others check numbers the Release and ASan stages check.
run "skinning weights (exact rows 8 per batch in parallel, refinement rounds)" \
  --test-case='skinning weights: per-vertex*,sampled skinning weights: refinement deterministic*,sampled skinning weights: properties*'
run "Session and C API concurrency" --test-case='*session: concurrent queries*,*c api: progress callback*,*session pipelines from several threads*'
say "done"
exit $status
