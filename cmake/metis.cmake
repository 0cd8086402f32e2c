# METIS compiled into locus, with a private random generator.
#
# Debian's libmetis.so draws from the C library's rand()/srand(): one generator
# for the whole process, shared with the host program. locus used to define
# rand()/srand() itself to redirect METIS' draws, which took the symbols over
# for the whole process and stops working once locus is a shared object with
# hidden symbols. Instead the same sources are compiled here with rand/srand
# renamed to locus_metis_rand/locus_metis_srand (defined in
# kernels/src/order/metis_random.cpp, one generator per thread): nothing else in
# the process is affected, and the host's rand() sequence is never touched.
# GKlib's signal()/raise() (process-wide handlers around every METIS call) are
# renamed the same way, to functions that touch no process state.
#
# Sources: Debian's metis source package (tools/fetch_metis.sh, run here when
# the unpacked tree is missing; pinned version and SHA-256). Flags: those of
# Debian's build where they can change results (-O3 from GKlib's CMake, C99,
# -fno-strict-aliasing, NDEBUG/NDEBUG2, the shipped metis.h with 32-bit idx_t
# and real_t) and nothing that could: no -march, -ffp-contract=off (no FMA
# contraction whatever the compiler's default), no sanitizers (as before: the
# system library was not instrumented either). Every symbol is hidden, so a
# host that links Debian's libmetis too (CHOLMOD does) keeps its own METIS.
#
# Sets METIS_INCLUDE_DIR (the package's metis.h) and the object library
# locus_metis, whose objects are part of the static library locus. METIS_LIBRARY
# is empty: there is no external METIS to link any more. Compile cost: ~14 s of
# CPU per build tree (61 C files), shared through ccache when present.
set(LOCUS_METIS_VERSION 5.1.0.dfsg-7)
set(LOCUS_METIS_SOURCE_DIR "${PROJECT_SOURCE_DIR}/cache/deps/metis-${LOCUS_METIS_VERSION}" CACHE PATH
  "Unpacked Debian metis ${LOCUS_METIS_VERSION} source package (fetched there by tools/fetch_metis.sh when missing)")
execute_process(COMMAND bash ${PROJECT_SOURCE_DIR}/tools/fetch_metis.sh ${LOCUS_METIS_SOURCE_DIR}
  RESULT_VARIABLE _locus_metis_rc)
if(NOT _locus_metis_rc EQUAL 0 OR NOT EXISTS ${LOCUS_METIS_SOURCE_DIR}/libmetis/ometis.c)
  message(FATAL_ERROR "METIS sources unavailable in ${LOCUS_METIS_SOURCE_DIR} (see the message of "
    "tools/fetch_metis.sh above). locus compiles Debian's metis ${LOCUS_METIS_VERSION} source package; "
    "run 'bash tools/fetch_metis.sh' with network access, or point -DLOCUS_METIS_SOURCE_DIR at an "
    "unpacked copy (dpkg-source -x metis_${LOCUS_METIS_VERSION}.dsc DIR).")
endif()

file(GLOB _locus_metis_sources ${LOCUS_METIS_SOURCE_DIR}/GKlib/*.c ${LOCUS_METIS_SOURCE_DIR}/libmetis/*.c)
# metis_trap.c: METIS_ComputeVertexSeparator inside GKlib's error trap (it says why).
add_library(locus_metis OBJECT ${_locus_metis_sources} ${PROJECT_SOURCE_DIR}/kernels/src/order/metis_trap.c)
target_include_directories(locus_metis PRIVATE
  ${LOCUS_METIS_SOURCE_DIR}/GKlib ${LOCUS_METIS_SOURCE_DIR}/include ${LOCUS_METIS_SOURCE_DIR}/libmetis)
# rand/srand: kernels/src/order/metis_random.cpp. signal/raise: GKlib's error
# handling installs process-wide signal handlers (kernels/src/order/metis_signals.cpp
# says why and what replaces them); _DEFAULT_SOURCE lets the rename reach them
# (in strict C99 glibc's <signal.h> binds signal() to __sysv_signal by asm
# label). The object code is otherwise identical with and without it (checked
# by comparing the disassembly of every object).
# malloc/calloc/realloc/free: kernels/src/order/metis_memory.cpp (the host's
# allocator, and a cancel point at every allocation: metis_call.hpp); the
# printf family: dropped (METIS' error paths print to stderr).
set(_locus_metis_memory
  "malloc=locus_metis_malloc;calloc=locus_metis_calloc;realloc=locus_metis_realloc;free=locus_metis_free;fprintf=locus_metis_fprintf;vfprintf=locus_metis_vfprintf;printf=locus_metis_printf;fflush=locus_metis_fflush")
set(_locus_metis_renames
  "rand=locus_metis_rand;srand=locus_metis_srand;_DEFAULT_SOURCE;signal=locus_metis_signal;raise=locus_metis_raise;${_locus_metis_memory}")
# Replaces what the directory would hand down (-march, sanitizers, fuzzer
# instrumentation); -O3 comes last so it wins over the build type's level.
set_target_properties(locus_metis PROPERTIES
  C_VISIBILITY_PRESET hidden
  POSITION_INDEPENDENT_CODE ON
  COMPILE_DEFINITIONS "LINUX;_FILE_OFFSET_BITS=64;NDEBUG;NDEBUG2;HAVE_EXECINFO_H;HAVE_GETLINE;${_locus_metis_renames}"
  COMPILE_OPTIONS "-std=c99;-fno-strict-aliasing;-ffp-contract=off;-fno-fast-math;-w;-O3")
set(METIS_INCLUDE_DIR ${LOCUS_METIS_SOURCE_DIR}/include)
set(METIS_LIBRARY "")

if(LOCUS_BUILD_TESTS)
  enable_testing()
  add_test(NAME metis_no_process_symbols COMMAND ${CMAKE_COMMAND} -DNM=${CMAKE_NM} -DLIB=$<TARGET_FILE:locus_objects>
    -P ${PROJECT_SOURCE_DIR}/tests/kernels/order/no_process_symbols.cmake)
endif()
