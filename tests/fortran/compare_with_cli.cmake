# cmake -DEXE=tessera_fortran_section -DRENDER=tessera-render -DWORK=DIR -DNP=N [-DMPIEXEC=mpiexec]
#       -P compare_with_cli.cmake
# Runs the Fortran section program (one process; and with NP > 1 also under mpiexec -n NP),
# renders its raw files with tessera-render, and requires every image the module wrote to be
# byte-for-byte the CLI's image of the same render (and the NP-rank images the one-rank ones).
# Fails too when the CLI saw no real collision (an empty view would compare equal trivially).
cmake_minimum_required(VERSION 3.22)
file(REMOVE_RECURSE "${WORK}")

include("${CMAKE_CURRENT_LIST_DIR}/run_checked.cmake")

function(expect_same a b)
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files "${a}" "${b}" RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "not byte-identical: ${a} vs ${b}")
  endif()
  message(STATUS "identical: ${a} = ${b}")
endfunction()

# The module's images: one process, and NP ranks
file(MAKE_DIRECTORY "${WORK}/one")
run_checked("section program (one process)" "${EXE}" "${WORK}/one")
if(NP GREATER 1)
  file(MAKE_DIRECTORY "${WORK}/np${NP}")
  run_checked("section program (-n ${NP})" "${MPIEXEC}" -n ${NP} "${EXE}" "${WORK}/np${NP}")
endif()

# The CLI on the raw files of the same values, and the comparisons
foreach(pair f64:scene64 f32:scene32 f64s:scene64)
  string(REPLACE ":" ";" pair "${pair}")
  list(GET pair 0 render)
  list(GET pair 1 scene)
  set(cli "${WORK}/cli_${render}.exr")
  run_checked("tessera-render --render ${render}" "${RENDER}" "${WORK}/one/${scene}.yaml"
    --render ${render} -o "${cli}" --stats "${WORK}/cli_${render}.json" --quiet)
  file(READ "${WORK}/cli_${render}.json" stats)
  string(JSON hits GET "${stats}" real_collisions)
  if(NOT hits GREATER 0)
    message(FATAL_ERROR "render ${render}: no real collision in the CLI render; the test scene shows nothing")
  endif()
  expect_same("${WORK}/one/adapter/${render}.exr" "${cli}")
  if(NP GREATER 1)
    expect_same("${WORK}/np${NP}/adapter/${render}.exr" "${cli}")
  endif()
endforeach()
