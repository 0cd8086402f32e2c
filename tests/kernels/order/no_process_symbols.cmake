# ctest metis_no_process_symbols: the library objects (liblocus_objects.a, the
# archive of the objects liblocus.a is made of) neither define nor call rand(),
# srand(), signal() or raise().
#   cmake -DNM=... -DLIB=.../liblocus.a -P no_process_symbols.cmake
# Defining rand/srand would take the C library's generator over for the whole
# process (and silently stop working in a shared object with hidden symbols);
# calling them would advance the host program's sequence; signal() would
# replace the host's handlers. METIS is compiled with all four renamed
# (cmake/metis.cmake) to locus_metis_*, defined in kernels/src/order/.
execute_process(COMMAND ${NM} -g ${LIB} OUTPUT_VARIABLE out RESULT_VARIABLE rc ERROR_QUIET)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${NM} -g ${LIB} failed (${rc})")
endif()
string(REGEX MATCHALL "[^\n]* [A-Za-z] (s?rand|signal|__sysv_signal|bsd_signal|sigaction|raise)\n" hits "${out}")
if(hits)
  message(FATAL_ERROR "liblocus.a defines or calls rand/srand/signal/raise:\n${hits}")
endif()
foreach(sym locus_metis_rand locus_metis_srand locus_metis_signal locus_metis_raise)
  if(NOT out MATCHES " T ${sym}\n")
    message(FATAL_ERROR "${sym} (what METIS' call was renamed to) is not defined in ${LIB}")
  endif()
endforeach()
message(STATUS "liblocus.a: no rand/srand/signal/raise; METIS calls locus_metis_*")
