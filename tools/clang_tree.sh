# Sourced by .ci/run and tools/tsan.sh: the sanitizer build trees are clang's
# (docs/testing.md: ~40 % less CPU per instrumented compile than gcc).
#
#   clang_tree DIR                 # CMake keeps a tree's first compiler: a tree
#                                  # configured with another one starts over
#   quiet_build DIR LOG TARGET...  # the build's lines go to DIR/LOG, their tail
#                                  # on failure (CI shows only the log's tail)
clang_cmake_compilers=(-DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++)
clang_tree() {
  if [ -f "$1/CMakeCache.txt" ] && ! grep -q "^CMAKE_CXX_COMPILER:[A-Z]*=.*clang++" "$1/CMakeCache.txt"; then
    rm -rf "$1/CMakeCache.txt" "$1/CMakeFiles"
  fi
}
quiet_build() {
  local dir=$1 log=$2; shift 2
  cmake --build "$dir" -j2 --target "$@" >"$dir/$log" 2>&1 ||
    { tail -60 "$dir/$log"; echo "== the build of $* in $dir failed" >&2; return 1; }
}
