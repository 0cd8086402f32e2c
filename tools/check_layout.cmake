# Checks the include graph of the library against the floors (README "Layout"):
#
#   cmake -DLOCUS_SOURCE_DIR=<checkout> -P tools/check_layout.cmake
#
# core -> kernels -> io, pipelines -> engine -> tools, tests, python. A file may
# include the headers of its own floor and of the floors below it; a pipeline
# may include the headers of its own application folder (pipelines/*/<app>/)
# but not another application's. Files in tools/, tests/ and python/ may include
# anything. Prints every offending line and fails (ctest entry layout_includes);
# the build itself enforces the same rule through include paths (ctest entry
# layout_upward_include_fails).
cmake_minimum_required(VERSION 3.22)
if(NOT LOCUS_SOURCE_DIR)
  get_filename_component(LOCUS_SOURCE_DIR "${CMAKE_CURRENT_LIST_DIR}/.." ABSOLUTE)
endif()

set(core_headers "locus/error.hpp;locus/mesh.hpp;locus/sparse_matrix.hpp;locus/run_context.hpp;locus/view.hpp;locus/export.h;locus/version.h;locus/mesh_view.hpp;locus/mesh_info.hpp")

# Is include NAME (from a file of FLOOR, application APP) allowed? Sets OUT.
function(allowed floor app name dir out)
  set(ok FALSE)
  if(name IN_LIST core_headers OR name MATCHES "^locus/core/")
    set(ok TRUE)  # core: every floor
  elseif(name MATCHES "^locus/kernels/")
    if(NOT floor STREQUAL "core")
      set(ok TRUE)
    endif()
  elseif(name MATCHES "^locus/io/" OR name STREQUAL "locus/mesh_io.hpp" OR name STREQUAL "factor_cache_generated.h")
    if(floor STREQUAL "io" OR floor STREQUAL "engine")
      set(ok TRUE)
    endif()
  elseif(name MATCHES "^locus/pipelines/([a-z_]+)/")
    set(target_app "${CMAKE_MATCH_1}")
    if(floor STREQUAL "engine" OR (floor STREQUAL "pipelines" AND target_app STREQUAL app))
      set(ok TRUE)
    endif()
  elseif(name STREQUAL "locus/session.hpp" OR name STREQUAL "locus/locus.h" OR name STREQUAL "locus/locus_commands.h"
         OR name MATCHES "^locus/engine/")
    if(floor STREQUAL "engine")
      set(ok TRUE)
    endif()
  elseif(NOT name MATCHES "/" AND EXISTS "${dir}/${name}")
    set(ok TRUE)  # a private header beside the file
  endif()
  set(${out} ${ok} PARENT_SCOPE)
endfunction()

set(bad 0)
set(checked 0)
foreach(floor core kernels io pipelines engine)
  file(GLOB_RECURSE files "${LOCUS_SOURCE_DIR}/${floor}/*.hpp" "${LOCUS_SOURCE_DIR}/${floor}/*.cpp" "${LOCUS_SOURCE_DIR}/${floor}/*.h")
  foreach(f IN LISTS files)
    file(RELATIVE_PATH rel "${LOCUS_SOURCE_DIR}" "${f}")
    set(app "")
    if(floor STREQUAL "pipelines")
      if(rel MATCHES "^pipelines/(include/locus/pipelines|src)/([a-z_]+)/")
        set(app "${CMAKE_MATCH_2}")
      else()
        message("${rel}: a pipeline must live in an application folder (pipelines/src/<app>/, pipelines/include/locus/pipelines/<app>/)")
        math(EXPR bad "${bad} + 1")
      endif()
    endif()
    get_filename_component(dir "${f}" DIRECTORY)
    file(STRINGS "${f}" lines REGEX "^[ \t]*#[ \t]*include[ \t]*[\"<]")
    foreach(line IN LISTS lines)
      if(line MATCHES "#[ \t]*include[ \t]*\"([^\"]+)\"")
        set(name "${CMAKE_MATCH_1}")
      elseif(line MATCHES "#[ \t]*include[ \t]*<(locus/[^>]+)>")
        set(name "${CMAKE_MATCH_1}")  # a system-style include of a locus header is checked too
      else()
        continue()
      endif()
      math(EXPR checked "${checked} + 1")
      allowed("${floor}" "${app}" "${name}" "${dir}" ok)
      if(NOT ok)
        message("${rel}: #include \"${name}\" runs against the floors (${floor} may include only itself and the floors below it)")
        math(EXPR bad "${bad} + 1")
      endif()
    endforeach()
  endforeach()
endforeach()
# The CLI is a client of the engine (Session, the requests of engine/include/
# locus/engine/), like the C API and Python: no file of tools/cli includes a
# pipelines header.
file(GLOB cli_files "${LOCUS_SOURCE_DIR}/tools/cli/*.cpp" "${LOCUS_SOURCE_DIR}/tools/cli/*.hpp")
foreach(f IN LISTS cli_files)
  get_filename_component(base "${f}" NAME)
  file(STRINGS "${f}" lines REGEX "^[ \t]*#[ \t]*include[ \t]*[\"<]locus/pipelines/")
  foreach(line IN LISTS lines)
    message("tools/cli/${base}: ${line}: the CLI reaches the pipelines through the engine (locus/session.hpp)")
    math(EXPR bad "${bad} + 1")
  endforeach()
endforeach()
if(checked EQUAL 0)
  message(FATAL_ERROR "check_layout: no includes found under ${LOCUS_SOURCE_DIR}")
endif()
if(bad GREATER 0)
  message(FATAL_ERROR "check_layout: ${bad} include(s) against the layout (of ${checked} checked)")
endif()
message(STATUS "check_layout: ${checked} includes follow the floors")
