# cmake -DEXE=tessera-heat[-fortran] -DCONFIG=configs/heat.yaml -DWORK=DIR -DNP=N [-DMPIEXEC=mpiexec]
#       [-DARGS="a;b"] [-DSECOND_ARGS="c;d"] -P heat_runs.cmake
# Runs a heat miniapp (tessera-heat or the Fortran example) for 10 steps on 24^3 vertices as
# one process with ARGS; with NP > 1 also under mpiexec -n NP with ARGS and SECOND_ARGS (e.g.
# --domains-per-rank 3: the same data cut into other blocks), and requires the images of both
# runs to be byte-identical (each vertex's value, and the image, do not depend on the cut).
# configs/heat.yaml has a render budget: the fake clock of tests makes its plans, and so the
# images, the same in every run and for any number of ranks (10 steps of 0.05 s pay for
# steps 0 and 10).
cmake_minimum_required(VERSION 3.22)
set(ENV{TESSERA_TEST_CLOCK} "0.05,1e-7")
file(REMOVE_RECURSE "${WORK}")
get_filename_component(name "${EXE}" NAME)
set(args --config "${CONFIG}" --steps 10 --grid 24 24 24 ${ARGS})

function(run_checked what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err
                  TIMEOUT 150)
  if(NOT rc EQUAL 0 OR err MATCHES "failed")
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}\n${err}")
  endif()
  message(STATUS "${what}: ${out}")
endfunction()

run_checked("${name} ${ARGS}" "${EXE}" ${args} --output-dir "${WORK}/one")
set(images heat_far_000000.exr heat_far_000010.exr heat_close_000010.exr heat_close_000010.png)
foreach(image IN LISTS images)
  if(NOT EXISTS "${WORK}/one/${image}")
    message(FATAL_ERROR "${name} wrote no ${WORK}/one/${image}")
  endif()
endforeach()
if(NP GREATER 1)
  run_checked("mpiexec -n ${NP} ${name} ${ARGS} ${SECOND_ARGS}" "${MPIEXEC}" -n ${NP} "${EXE}" ${args}
    ${SECOND_ARGS} --output-dir "${WORK}/np${NP}")
  foreach(image IN LISTS images)
    execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files "${WORK}/one/${image}"
      "${WORK}/np${NP}/${image}" RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "${image}: -n ${NP} ${SECOND_ARGS} differs from one process")
    endif()
  endforeach()
  message(STATUS "-n ${NP} images identical to one process: ${images}")
endif()
