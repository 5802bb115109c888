# The README's two commands in either order give the whole suite: a build directory first
# configured without the venv (the demo command) builds the Python module once the venv is
# there (the test command), while a value set by hand stays. Run with cmake -P:
#   -DSOURCE=<repo> -DVENV=<a venv with nanobind> -DWORK=<scratch dir>
# Exits 77 (skipped) without such a venv.
if(NOT EXISTS ${VENV}/bin/python)
  message("python_option: no venv at ${VENV}: skipped")
  cmake_language(EXIT 77)
endif()
execute_process(COMMAND ${VENV}/bin/python -m nanobind --cmake_dir RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
if(NOT rc EQUAL 0)
  message("python_option: the venv has no nanobind: skipped")
  cmake_language(EXIT 77)
endif()

function(configure dir)
  execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE}/tests/layout/python_option -B ${dir}
                          -DTESSERA_SOURCE_DIR=${SOURCE} ${ARGN}
                  OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "configure failed:\n${out}\n${err}")
  endif()
  string(REGEX MATCH "probe: TESSERA_BUILD_PYTHON=([A-Za-z0-9]*)" _ "${out}")
  set(value ${CMAKE_MATCH_1} PARENT_SCOPE)
endfunction()

function(expect what got want)
  if(NOT got STREQUAL want)
    message(FATAL_ERROR "python_option: ${what}: TESSERA_BUILD_PYTHON=${got}, expected ${want}")
  endif()
  message("python_option: ${what}: ${got}")
endfunction()

file(REMOVE_RECURSE ${WORK})
# 1. No venv yet (the demo first), then the venv (the test command): the module is built
configure(${WORK}/a -DTESSERA_VENV_DIR=${WORK}/no-venv)
expect("first configure, no venv" "${value}" OFF)
configure(${WORK}/a -DTESSERA_VENV_DIR=${VENV})
expect("same directory, venv now there" "${value}" ON)
configure(${WORK}/a)
expect("configured again" "${value}" ON)
# 2. OFF set by hand where the default is ON stays OFF on every later configure
configure(${WORK}/b -DTESSERA_VENV_DIR=${VENV} -DTESSERA_BUILD_PYTHON=OFF)
expect("set OFF by hand" "${value}" OFF)
configure(${WORK}/b -DTESSERA_VENV_DIR=${VENV})
expect("set OFF by hand, configured again" "${value}" OFF)
file(REMOVE_RECURSE ${WORK})
message("python_option: 5 configures, 0 failed")
