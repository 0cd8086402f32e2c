# ctest entry `package` (CMakeLists.txt, install block): installs the build in
# LOCUS_BUILD_DIR to a scratch prefix, configures and builds tests/package/c (a
# C99 project that includes only locus/locus.h) and tests/package/cpp (C++17,
# locus/session.hpp) against it with find_package(locus), and runs both. The C
# program reads LOCUS_MESH (armadillo, from tools/fetch_meshes.sh); without it
# both programs run their generated-mesh checks only and the test reports
# LOCUS_PACKAGE_SKIPPED (ctest: skipped).
cmake_minimum_required(VERSION 3.22)
foreach(var LOCUS_BUILD_DIR LOCUS_PACKAGE_SOURCE LOCUS_MESH LOCUS_GENERATOR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "run_package_test.cmake: -D${var}=... is required")
  endif()
endforeach()

set(work ${LOCUS_BUILD_DIR}/package-test)
file(REMOVE_RECURSE ${work})
file(MAKE_DIRECTORY ${work})
set(prefix ${work}/prefix)

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message(STATUS "$ ${ARGN}\n${out}${err}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (exit ${rc}): ${ARGN}")
  endif()
endfunction()

run(${CMAKE_COMMAND} --install ${LOCUS_BUILD_DIR} --prefix ${prefix})
foreach(header locus/locus.h locus/session.hpp locus/error.hpp)
  if(NOT EXISTS ${prefix}/include/${header})
    message(FATAL_ERROR "the install did not place include/${header}")
  endif()
endforeach()

set(mesh_arg "")
if(EXISTS ${LOCUS_MESH})
  set(mesh_arg ${LOCUS_MESH})
else()
  message(STATUS "${LOCUS_MESH} is absent (run tools/fetch_meshes.sh): generated meshes only")
endif()
# The CLI's outputs the programs compare every pipeline with (LOCUS_PACKAGE_REFS).
include(${CMAKE_CURRENT_LIST_DIR}/make_references.cmake)

foreach(lang c cpp)
  set(compilers "")
  if(LOCUS_C_COMPILER)
    list(APPEND compilers -DCMAKE_C_COMPILER=${LOCUS_C_COMPILER})
  endif()
  if(LOCUS_CXX_COMPILER)
    list(APPEND compilers -DCMAKE_CXX_COMPILER=${LOCUS_CXX_COMPILER})
  endif()
  # Only this prefix and the system: nothing from the locus build tree leaks in.
  run(${CMAKE_COMMAND} -S ${LOCUS_PACKAGE_SOURCE}/${lang} -B ${work}/build-${lang} -G ${LOCUS_GENERATOR}
      -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF ${compilers})
  run(${CMAKE_COMMAND} --build ${work}/build-${lang} -j2)
  run(${work}/build-${lang}/locus_${lang}_demo ${mesh_arg})
endforeach()

if(NOT mesh_arg)
  message("LOCUS_PACKAGE_SKIPPED: the armadillo part needs tools/fetch_meshes.sh")
endif()
