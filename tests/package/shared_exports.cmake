# ctest shared_exports (docs/shipping.md): liblocus.so exports the public API
# and nothing else: every dynamic symbol it defines is a locus_* C function or
# belongs to the C++ API in namespace locus (functions, typeinfo, vtables),
# and the C API and Session are among them. Kernels, METIS, Eigen/TBB/std
# template instantiations stay hidden (export.h, -fvisibility=hidden).
#   cmake -DNM=... -DLIB=.../liblocus.so -P shared_exports.cmake
execute_process(COMMAND ${NM} -D --defined-only -C ${LIB} OUTPUT_VARIABLE out RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${NM} -D ${LIB} failed (${rc})")
endif()
string(REPLACE "\n" ";" lines "${out}")
set(bad "")
set(count 0)
foreach(line IN LISTS lines)
  if(NOT line MATCHES "^[0-9a-f]* [A-Za-z] (.*)$")
    continue()
  endif()
  set(sym "${CMAKE_MATCH_1}")
  math(EXPR count "${count} + 1")
  if(sym MATCHES "^locus_[a-z_0-9]+$" OR sym MATCHES "^(typeinfo for |typeinfo name for |vtable for )?locus::")
    continue()
  endif()
  # A std:: or other function taking locus types (e.g. a std::function call operator) is a leak too.
  string(APPEND bad "  ${sym}\n")
endforeach()
if(bad)
  message(FATAL_ERROR "${LIB} exports symbols outside the public API:\n${bad}")
endif()
foreach(want "locus_session_create" "locus_last_error_copy" "locus::Session::Session(locus::Mesh)" "typeinfo for locus::Error" "locus::read_mesh(")
  string(FIND "${out}" "${want}" at)
  if(at LESS 0)
    message(FATAL_ERROR "${LIB} does not export ${want}")
  endif()
endforeach()
message(STATUS "${LIB}: ${count} exported symbols, all locus_* or locus::")
