# Rewrites liblocus.a as one relocatable object whose internal symbols are local
# (run after the archive is built: CMakeLists.txt, POST_BUILD of locus_static).
#   cmake -DAR=ar -DLD=ld -DOBJCOPY=objcopy -DREADELF=readelf -DLIB=liblocus.a -DWORK=dir -P localize_static.cmake
#
# Why: the sources are compiled with hidden visibility, which keeps the shared
# library's exports to the API but means nothing to a static link: a host that
# defines METIS_NodeND (or links its own METIS) would meet locus' copy and fail
# with "multiple definition". `ld -r` joins every object so internal references
# are resolved inside one object; then every strong, hidden, defined symbol is
# made local. Weak symbols are left alone (inline and template code in COMDAT
# groups: they cannot clash, and the linker deduplicates groups by name).
foreach(var AR LD OBJCOPY READELF LIB WORK)
  if(NOT ${var})
    message(FATAL_ERROR "localize_static.cmake: -D${var}=... is required")
  endif()
endforeach()

file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
set(joined ${WORK}/locus.o)
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "localize_static.cmake: ${ARGN} failed (${rc}): ${err}")
  endif()
endfunction()

run(${LD} -r --whole-archive ${LIB} -o ${joined})
execute_process(COMMAND ${READELF} -sW ${joined} OUTPUT_VARIABLE table RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "localize_static.cmake: ${READELF} -sW ${joined} failed (${rc})")
endif()
# Lines: "Num: Value Size Type Bind Vis Ndx Name"; keep GLOBAL + HIDDEN + defined.
string(REGEX MATCHALL "[^\n]* GLOBAL +HIDDEN +[0-9]+ [^\n]+" hidden "${table}")
set(names "")
set(count 0)
foreach(line IN LISTS hidden)
  string(REGEX REPLACE "^.* GLOBAL +HIDDEN +[0-9]+ " "" name "${line}")
  string(APPEND names "${name}\n")
  math(EXPR count "${count} + 1")
endforeach()
file(WRITE ${WORK}/localize.txt "${names}")
run(${OBJCOPY} --localize-symbols=${WORK}/localize.txt ${joined})
file(REMOVE ${LIB})
run(${AR} qcs ${LIB} ${joined})
message(STATUS "liblocus.a: ${count} internal symbols made local")
