# ctest api_marks (docs/shipping.md, core/include/locus/export.h): every
# public declaration carries LOCUS_API, the one mark that makes it exported on
# every platform (visibility("default") here, __declspec on Windows, where a
# missing mark is a link error only a Windows host would see), and every C
# function the public headers declare is exported by liblocus.so.
#   cmake -DNM=... -DLIB=.../liblocus.so -DHEADERS="a.h;b.hpp" -P api_marks.cmake
execute_process(COMMAND ${NM} -D --defined-only -C ${LIB} OUTPUT_VARIABLE exported RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${NM} -D ${LIB} failed (${rc})")
endif()
set(bad "")
set(marked 0)
cmake_policy(SET CMP0007 NEW)
list(FILTER HEADERS EXCLUDE REGEX "^$")
foreach(header IN LISTS HEADERS)
  file(READ ${header} text)
  string(REPLACE ";" "@SEMI@" text "${text}")  # CMake lists split at ";"
  # Namespace-scope declarations start in column 0 (members are indented):
  # functions "TYPE name(" and class/struct definitions.
  string(REGEX MATCHALL "\n[A-Za-z_][^\n(\\[{}=@]*[ *&]~?[A-Za-z_][A-Za-z_0-9]*\\(" functions "${text}")
  # A template (header-only, nothing to export) is matched with its template line and skipped.
  string(REGEX MATCHALL "\n(template[^\n]*\n)?(struct|class) [^\n]*" types "${text}")
  foreach(decl IN LISTS functions types)
    string(STRIP "${decl}" decl)
    if(decl MATCHES "^(typedef|using|template|inline|static|constexpr|return|namespace|enum|extern|friend|#)")
      continue()
    endif()
    if(decl MATCHES "^(struct|class) [A-Za-z_0-9]+ *@SEMI@")
      continue()  # a forward declaration
    endif()
    if(NOT decl MATCHES "^(LOCUS_API |(struct|class) LOCUS_API )")
      string(APPEND bad "  ${header}: ${decl}\n")
      continue()
    endif()
    math(EXPR marked "${marked} + 1")
    if(decl MATCHES "^LOCUS_API .*[ *](locus_[a-z_0-9]+)\\($")
      set(name ${CMAKE_MATCH_1})
      string(REGEX MATCH "\n[0-9a-f]* T ${name}\n" found "\n${exported}")
      if(NOT found)
        string(APPEND bad "  ${header}: ${name} is declared but liblocus.so does not export it\n")
      endif()
    endif()
  endforeach()
endforeach()
if(bad)
  message(FATAL_ERROR "public declarations without LOCUS_API or not exported:\n${bad}")
endif()
if(marked LESS 100)
  message(FATAL_ERROR "only ${marked} marked declarations found in ${HEADERS}: the header list is wrong")
endif()
message(STATUS "${marked} public declarations, all marked LOCUS_API; every C function exported")
