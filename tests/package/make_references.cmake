# Included by run_package_test.cmake: runs the `locus` CLI on armadillo with the
# arguments the package programs use for the same pipelines (the C and C++
# programs check every pipeline against the CLI's output),
# writing JSON and mesh files into ${work}/refs, and hands that directory to the
# programs through the environment variable LOCUS_PACKAGE_REFS. The programs
# hard-code the same arguments (tests/package/c/locus_c_demo.c, cli_checks;
# tests/package/cpp/locus_cpp_demo.cc, cli_checks): keep the three in step.
#
# The chapter-2 pipelines (disk parameterization, perfect Laplacian,
# self-supporting surface) need a mesh with a boundary and skinning weights
# cost one full heat solve per vertex (403 s for armadillo's 26k vertices on
# a loaded 2-core machine), so they run on patch.obj: the disk of 5% of
# armadillo's vertices around vertex 0 that `locus param --boundary circle`
# writes (1300 vertices, one boundary loop). The C++ program also runs their
# one-shot forms on quad_grid.off, a polygon disk written here.
set(refs ${work}/refs)
file(MAKE_DIRECTORY ${refs})
set(cli ${LOCUS_BUILD_DIR}/locus)
if(EXISTS ${prefix}/bin/locus)
  set(cli ${prefix}/bin/locus)
endif()

function(cli_reference name)
  execute_process(COMMAND ${cli} ${ARGN} --threads 2 --json WORKING_DIRECTORY ${refs}
                  RESULT_VARIABLE rc OUTPUT_FILE ${refs}/${name}.json ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "reference `locus ${ARGN}` failed (exit ${rc}): ${err}")
  endif()
endfunction()

if(mesh_arg AND EXISTS ${cli})
  set(A ${mesh_arg})
  set(sites 0,1000,5000,9000,13000,20000)
  cli_reference(geodesic geodesic ${A} --source 0 -o geodesic.ply)
  cli_reference(voronoi voronoi ${A} --sites ${sites} -o voronoi.obj)
  cli_reference(voronoi_random voronoi ${A} --random 50 --seed 7 -o voronoi_random.obj)
  cli_reference(nncoords nncoords ${A} --sites ${sites} --point 10,0.2,0.3,0.5)
  cli_reference(adf adf ${A} --vertices 0,7,12345)
  cli_reference(hks hks ${A} --ts 1h2,10h2,100h2 --vertices 0,7,12345)
  cli_reference(heat heat ${A} --source 0,1,2 --target 100,200,25000)
  cli_reference(deform deform ${A} --roi-seed 0 --roi-fraction 0.1 --handle 0 --offset 0.5,1,0 -o deform.ply)
  cli_reference(param_neumann param ${A} --center 0 --fraction 0.1 -o param_neumann.obj)
  cli_reference(param_circle param ${A} --center 0 --fraction 0.1 --boundary circle -o param_circle.obj)
  cli_reference(patch param ${A} --center 0 --fraction 0.05 --boundary circle -o patch.obj)
  cli_reference(param_disk param patch.obj --method perfect -o param_disk.obj)
  cli_reference(skinweights skinweights patch.obj --handles 0,300,900 --exact -o skinweights.ply)
  cli_reference(perfect_laplacian perfect-laplacian patch.obj --iters 20 -o perfect_laplacian.obj)
  cli_reference(selfsupport selfsupport patch.obj --iters 20 -o selfsupport.obj)
  # A polygon disk for the one-shot forms (no Session needed): a 13 x 13-vertex
  # quad grid with integer coordinates, z = i (12 - i) + j (12 - j) (a vault).
  set(grid "OFF\n169 144 0\n")
  foreach(j RANGE 12)
    foreach(i RANGE 12)
      math(EXPR x "10 * ${i}")
      math(EXPR y "10 * ${j}")
      math(EXPR z "${i} * (12 - ${i}) + ${j} * (12 - ${j})")
      string(APPEND grid "${x} ${y} ${z}\n")
    endforeach()
  endforeach()
  foreach(j RANGE 11)
    foreach(i RANGE 11)
      math(EXPR a "13 * ${j} + ${i}")
      math(EXPR b "${a} + 1")
      math(EXPR c "${a} + 14")
      math(EXPR d "${a} + 13")
      string(APPEND grid "4 ${a} ${b} ${c} ${d}\n")
    endforeach()
  endforeach()
  file(WRITE ${refs}/quad_grid.off "${grid}")
  cli_reference(param_quad param quad_grid.off --method perfect -o param_quad.obj)
  cli_reference(perfect_laplacian_quad perfect-laplacian quad_grid.off --iters 20 -o perfect_laplacian_quad.obj)
  cli_reference(selfsupport_quad selfsupport quad_grid.off --iters 20 -o selfsupport_quad.obj)
  set(ENV{LOCUS_PACKAGE_REFS} ${refs})
  message(STATUS "CLI references in ${refs} (from ${cli})")
elseif(mesh_arg)
  message(FATAL_ERROR "no locus CLI at ${cli}: build the locus-cli target before the package test")
endif()
