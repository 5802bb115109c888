# cmake -DEXE=tessera-heat-shell -DCONFIG=heat_shell.yaml -DWORK=DIR -DMPIEXEC=mpiexec
#       -DRANKS=1,2,3 [-DPYTHON=python3 -DSOURCE_DIR=<repo>] -P heat_shell_runs.cmake
# Without PYTHON: runs tessera-heat-shell for 20 steps on 12 x 48 x 16 vertices under mpiexec
# with each rank count of RANKS and requires every image (EXR and PNG, steps 0 and 20) of each
# run to be byte-identical to the first run's: the ranks cut the shell's angles into other
# curvilinear blocks (the last one across the seam), and the image does not depend on the cut.
# With PYTHON: the picture of docs/miniapp.md instead: the documented command (2 ranks,
# configs/heat_shell.yaml, 60 steps on the default grid) makes docs/images/heat_shell.png's
# pixels exactly (decoded by png_pixels_equal.py, so that another zlib does not matter).
cmake_minimum_required(VERSION 3.22)
file(REMOVE_RECURSE "${WORK}")

function(run_checked what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 150)
  if(NOT rc EQUAL 0 OR err MATCHES "failed")
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}\n${err}")
  endif()
  message(STATUS "${what}: ${out}")
endfunction()

if(PYTHON)
  run_checked("mpiexec -n 2 tessera-heat-shell --steps 60" "${MPIEXEC}" -n 2 "${EXE}" --config
    "${SOURCE_DIR}/configs/heat_shell.yaml" --steps 60 --output-dir "${WORK}")
  execute_process(COMMAND "${PYTHON}" "${SOURCE_DIR}/tests/mpi/png_pixels_equal.py"
    "${SOURCE_DIR}/docs/images/heat_shell.png" "${WORK}/heat_shell_000060.png"
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "docs/images/heat_shell.png is not what its command makes: ${out}${err}")
  endif()
  message(STATUS "docs/images/heat_shell.png: the same pixels as its command makes")
  return()
endif()

set(images heat_shell_000000.exr heat_shell_000000.png heat_shell_000020.exr heat_shell_000020.png)
string(REPLACE "," ";" RANKS "${RANKS}")
list(GET RANKS 0 first)
foreach(np IN LISTS RANKS)
  run_checked("mpiexec -n ${np} tessera-heat-shell" "${MPIEXEC}" -n ${np} "${EXE}" --config "${CONFIG}" --steps 20
    --grid 12 48 16 --output-dir "${WORK}/np${np}")
  foreach(image IN LISTS images)
    if(NOT EXISTS "${WORK}/np${np}/${image}")
      message(FATAL_ERROR "tessera-heat-shell -n ${np} wrote no ${WORK}/np${np}/${image}")
    endif()
    execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files "${WORK}/np${first}/${image}"
      "${WORK}/np${np}/${image}" RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "${image}: -n ${np} differs from -n ${first}")
    endif()
  endforeach()
endforeach()
message(STATUS "-n ${RANKS}: images byte-identical: ${images}")
