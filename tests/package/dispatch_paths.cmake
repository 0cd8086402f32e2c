# ctest dispatch_paths (docs/shipping.md): the default build is for x86-64-v2,
# and its small dense factor kernels also have AVX2 and AVX-512 versions
# chosen at load time (kernels/include/locus/kernels/factor/dense_small.hpp).
# Every version must give the same bits: the factor of one mesh, saved by
# `locus factor --save`, is compared byte for byte between this machine and
# emulated CPUs without AVX (Nehalem) and without AVX-512 (Haswell), with
# OpenBLAS pinned to one kernel set (its own CPU dispatch changes last bits,
# docs/shipping.md). Skipped without qemu-x86_64 (Debian qemu-user) or the mesh.
#   cmake -DLOCUS=build/locus -DMESH=... -DWORK=dir -P dispatch_paths.cmake
find_program(QEMU qemu-x86_64)
if(NOT QEMU OR NOT EXISTS ${MESH})
  message("LOCUS_DISPATCH_SKIPPED: needs qemu-x86_64 (apt-get install qemu-user) and ${MESH}")
  return()
endif()
file(MAKE_DIRECTORY ${WORK})
set(ENV{OPENBLAS_CORETYPE} NEHALEM)
foreach(cpu native Nehalem Haswell)
  if(cpu STREQUAL "native")
    set(cmd ${LOCUS})
  else()
    set(cmd ${QEMU} -cpu ${cpu} ${LOCUS})
  endif()
  execute_process(COMMAND ${cmd} factor ${MESH} --save ${WORK}/${cpu}.locus RESULT_VARIABLE rc
    OUTPUT_QUIET ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "locus factor on ${cpu} failed (${rc}): ${err}")
  endif()
endforeach()
foreach(cpu Nehalem Haswell)
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${WORK}/native.locus ${WORK}/${cpu}.locus RESULT_VARIABLE same)
  if(NOT same EQUAL 0)
    message(FATAL_ERROR "the factor computed on ${cpu} differs from this machine's")
  endif()
endforeach()
message(STATUS "factors identical on this CPU, Nehalem and Haswell")
