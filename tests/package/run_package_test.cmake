# ctest entry `package` (CMakeLists.txt, install block): installs the build in
# LOCUS_BUILD_DIR to a scratch prefix, then builds and runs against it:
#   * tests/package/c (a C99 project that includes only locus/locus.h) and
#     tests/package/cpp (C++17, locus/session.hpp), with find_package(locus),
#     linked to the shared library and again to the static one;
#   * the C program again, compiled by hand with the flags of `pkg-config locus`
#     (shared) and of `pkg-config --static locus` (liblocus.a);
#   * tests/package/metis_clash (a host defining its own METIS_NodeND), against both;
# and checks that bin/locus runs, that the shared builds load liblocus.so and
# the static ones do not. The programs read LOCUS_MESH (armadillo, from
# tools/fetch_meshes.sh) in the shared build (once is enough: the static build
# runs the same code); without it they run their generated-mesh checks only
# and the test reports LOCUS_PACKAGE_SKIPPED (ctest: skipped).
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
foreach(header locus/locus.h locus/session.hpp locus/error.hpp locus/version.h locus/export.h locus/view.hpp)
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

set(compilers "")
if(LOCUS_C_COMPILER)
  list(APPEND compilers -DCMAKE_C_COMPILER=${LOCUS_C_COMPILER})
endif()
if(LOCUS_CXX_COMPILER)
  list(APPEND compilers -DCMAKE_CXX_COMPILER=${LOCUS_CXX_COMPILER})
endif()
find_program(READELF readelf)
# Does the program load liblocus.so (DT_NEEDED)?
function(check_linkage exe want_shared)
  if(NOT READELF)
    return()
  endif()
  execute_process(COMMAND ${READELF} -d ${exe} OUTPUT_VARIABLE dyn)
  string(FIND "${dyn}" "liblocus.so" at)
  if(want_shared AND at LESS 0)
    message(FATAL_ERROR "${exe} was to link liblocus.so but does not load it")
  elseif(NOT want_shared AND NOT at LESS 0)
    message(FATAL_ERROR "${exe} was to link liblocus.a but loads liblocus.so")
  endif()
endfunction()

foreach(kind shared static)
  foreach(lang c cpp)
    set(build ${work}/build-${lang}-${kind})
    # Only this prefix and the system: nothing from the locus build tree leaks in.
    run(${CMAKE_COMMAND} -S ${LOCUS_PACKAGE_SOURCE}/${lang} -B ${build} -G ${LOCUS_GENERATOR}
        -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF
        -DLOCUS_TARGET=locus::locus_${kind} ${compilers})
    run(${CMAKE_COMMAND} --build ${build} -j2)
    if(kind STREQUAL "shared")
      check_linkage(${build}/locus_${lang}_demo TRUE)
      run(${build}/locus_${lang}_demo ${mesh_arg})
    else()
      check_linkage(${build}/locus_${lang}_demo FALSE)
      run(${build}/locus_${lang}_demo)
    endif()
  endforeach()
endforeach()

# A host with its own METIS_NodeND and gk_malloc links against each library and
# runs (locus keeps its own METIS: cmake/localize_static.cmake).
foreach(kind shared static)
  set(build ${work}/build-metis-clash-${kind})
  run(${CMAKE_COMMAND} -S ${LOCUS_PACKAGE_SOURCE}/metis_clash -B ${build} -G ${LOCUS_GENERATOR}
      -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF
      -DLOCUS_TARGET=locus::locus_${kind} ${compilers})
  run(${CMAKE_COMMAND} --build ${build} -j2)
  if(kind STREQUAL "shared")
    check_linkage(${build}/locus_metis_clash TRUE)
  else()
    check_linkage(${build}/locus_metis_clash FALSE)
  endif()
  run(${build}/locus_metis_clash)
endforeach()

# pkg-config: the C program built by hand with `pkg-config --cflags --libs locus` (the shared library).
find_program(PKG_CONFIG pkg-config)
file(GLOB_RECURSE pc_files ${prefix}/*/locus.pc)
if(NOT pc_files)
  message(FATAL_ERROR "the install did not place locus.pc")
endif()
list(GET pc_files 0 pc_file)
get_filename_component(pc_dir ${pc_file} DIRECTORY)
if(PKG_CONFIG)
  set(ENV{PKG_CONFIG_PATH} ${pc_dir})
  execute_process(COMMAND ${PKG_CONFIG} --modversion locus OUTPUT_VARIABLE pc_version OUTPUT_STRIP_TRAILING_WHITESPACE
    RESULT_VARIABLE rc)
  execute_process(COMMAND ${PKG_CONFIG} --cflags --libs locus OUTPUT_VARIABLE pc_flags OUTPUT_STRIP_TRAILING_WHITESPACE)
  if(NOT rc EQUAL 0 OR NOT pc_flags MATCHES "-llocus")
    message(FATAL_ERROR "pkg-config locus failed: '${pc_version}' '${pc_flags}'")
  endif()
  separate_arguments(pc_flags UNIX_COMMAND "${pc_flags}")
  set(cc ${LOCUS_C_COMPILER})
  if(NOT cc)
    set(cc cc)
  endif()
  get_filename_component(libdir ${pc_dir} DIRECTORY)
  run(${cc} -std=c99 -Wall -Wextra -pedantic -Werror "-DLOCUS_PACKAGE_VERSION=\"${pc_version}\""
      ${LOCUS_PACKAGE_SOURCE}/c/locus_c_demo.c ${pc_flags} -lm -Wl,-rpath,${libdir} -o ${work}/locus_c_demo_pkgconfig)
  check_linkage(${work}/locus_c_demo_pkgconfig TRUE)
  run(${work}/locus_c_demo_pkgconfig)
  # `pkg-config --static`: the same program against liblocus.a, with nothing but those flags.
  execute_process(COMMAND ${PKG_CONFIG} --static --cflags --libs locus OUTPUT_VARIABLE pc_static
    OUTPUT_STRIP_TRAILING_WHITESPACE)
  string(REPLACE "-llocus" "-l:liblocus.a" pc_static "${pc_static}")
  separate_arguments(pc_static UNIX_COMMAND "${pc_static}")
  run(${cc} -std=c99 -Wall -Wextra -pedantic -Werror "-DLOCUS_PACKAGE_VERSION=\"${pc_version}\""
      ${LOCUS_PACKAGE_SOURCE}/c/locus_c_demo.c ${pc_static} -o ${work}/locus_c_demo_pkgconfig_static)
  check_linkage(${work}/locus_c_demo_pkgconfig_static FALSE)
  run(${work}/locus_c_demo_pkgconfig_static)
else()
  message(STATUS "pkg-config not found: the pkg-config build is not checked (apt-get install pkgconf)")
endif()

# The Python package (LOCUS_PYTHON: the interpreter the module was built for; empty
# when -DLOCUS_BUILD_PYTHON=OFF): `import locus` from the prefix's site-packages
# alone, and one query through it.
if(LOCUS_PYTHON)
  set(site ${prefix}/${LOCUS_PYTHON_DIR})
  if(NOT EXISTS ${site}/locus/__init__.py)
    message(FATAL_ERROR "the install did not place the Python package in ${site}/locus")
  endif()
  set(ENV{PYTHONPATH} ${site})
  run(${LOCUS_PYTHON} -c "import locus, numpy as np\n\
assert locus.__file__.startswith('${site}/'), locus.__file__\n\
V = np.array([[0, 0, 1], [1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0], [0, 0, -1]], float)\n\
F = np.array([[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 1], [5, 2, 1], [5, 3, 2], [5, 4, 3], [5, 1, 4]])\n\
d = locus.Session(V, F).geodesic_distance(0)\n\
assert d[0] == 0 and d[5] > d[1] > 0, d\n\
print('import locus', locus.__version__, 'from', locus.__file__)")
  unset(ENV{PYTHONPATH})
endif()

# The command-line tool is installed beside the libraries.
if(EXISTS ${LOCUS_BUILD_DIR}/locus)
  if(NOT EXISTS ${prefix}/bin/locus)
    message(FATAL_ERROR "the install did not place bin/locus")
  endif()
  run(${prefix}/bin/locus --help)
endif()

if(NOT mesh_arg)
  message("LOCUS_PACKAGE_SKIPPED: the armadillo part needs tools/fetch_meshes.sh")
endif()

# The README's embedding examples (the code block after each "<!-- example: NAME -->"),
# compiled and linked against the shared library with pkg-config's flags.
get_filename_component(readme ${LOCUS_PACKAGE_SOURCE}/../../README.md ABSOLUTE)
file(READ ${readme} text)
set(examples 0)
while(TRUE)
  string(FIND "${text}" "<!-- example: " at)
  if(at LESS 0)
    break()
  endif()
  math(EXPR at "${at} + 14")
  string(SUBSTRING "${text}" ${at} -1 text)
  string(FIND "${text}" " -->" e)
  string(SUBSTRING "${text}" 0 ${e} name)
  string(FIND "${text}" "```" fence)
  string(SUBSTRING "${text}" ${fence} -1 text)
  string(FIND "${text}" "\n" nl)
  math(EXPR nl "${nl} + 1")
  string(SUBSTRING "${text}" ${nl} -1 text)
  string(FIND "${text}" "\n```" close)
  string(SUBSTRING "${text}" 0 ${close} code)
  string(SUBSTRING "${text}" ${close} -1 text)
  file(WRITE ${work}/examples/${name} "${code}\n")
  math(EXPR examples "${examples} + 1")
  if(NOT PKG_CONFIG)
    continue()
  endif()
  if(name MATCHES "\\.c$")
    set(std -std=c99)
  else()
    set(std -std=c++17)
  endif()
  set(cc ${LOCUS_C_COMPILER})
  if(name MATCHES "\\.cc$")
    set(cc ${LOCUS_CXX_COMPILER})
    if(NOT cc)
      set(cc c++)
    endif()
  endif()
  run(${cc} ${std} -Wall -Wextra -pedantic -Werror ${work}/examples/${name} ${pc_flags} -lm -Wl,-rpath,${libdir}
      -o ${work}/examples/${name}.out)
endwhile()
if(examples LESS 4)
  message(FATAL_ERROR "found ${examples} README examples (<!-- example: NAME -->), expected at least 4")
endif()
message(STATUS "${examples} README examples compiled")
