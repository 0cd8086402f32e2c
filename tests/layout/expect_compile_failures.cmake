# ctest layout_upward_include_fails: builds the layout probes (tests/layout/).
# The two upward probes must fail with "No such file" (clang: "file not found") for the header of the
# floor above; the control probe must build.
foreach(probe kernel_includes_pipeline:locus/pipelines/geodesic/heat_geodesic.hpp pipeline_includes_engine:locus/session.hpp)
  string(REPLACE ":" ";" parts ${probe})
  list(GET parts 0 name)
  list(GET parts 1 header)
  execute_process(COMMAND ${CMAKE_COMMAND} --build ${BUILD_DIR} --target layout_probe_${name}
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(rc EQUAL 0)
    message(FATAL_ERROR "layout probe ${name} compiled: an upward #include of ${header} was allowed")
  endif()
  # gcc: "HEADER: No such file or directory"; clang: "'HEADER' file not found".
  string(FIND "${out}" "${header}: No such file" at)
  string(FIND "${out}" "${header}' file not found" at_clang)
  if(at LESS 0 AND at_clang LESS 0)
    message(FATAL_ERROR "layout probe ${name} failed, but not on the missing ${header}:\n${out}")
  endif()
  message(STATUS "${name}: refused (${header} is not on its floor's include path)")
endforeach()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${BUILD_DIR} --target layout_probe_kernel_includes_kernel
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the control layout probe (a kernel including a kernel) did not compile:\n${out}")
endif()
message(STATUS "control probe compiled")
