# TESSERA_BUILD_PYTHON: the Python package's extension module (python/, docs/python.md).
# Default ON under scikit-build-core (`pip install .`) and when nanobind is found in the
# Python that CMake uses: Python_EXECUTABLE if given, else the project venv's python
# (TESSERA_VENV_DIR, default .venv/, made by scripts/python_env.sh), so the main build compiles
# the module against the same libraries and the pytest suite runs it from the build tree.
#
# The default is decided again at every configure, and an option the user never moved off its
# default follows it: a build directory first configured before the venv existed (the README's
# demo command, then its test command) builds the module once the venv is there, instead of
# keeping the OFF it cached the first time. A value the user set to other than the default
# of its configure (-DTESSERA_BUILD_PYTHON=OFF where nanobind is found) stays as set.
if(NOT DEFINED TESSERA_VENV_DIR)
  set(TESSERA_VENV_DIR ${CMAKE_CURRENT_SOURCE_DIR}/.venv)
endif()
set(_tessera_python_default OFF)
if(NOT DEFINED Python_EXECUTABLE AND EXISTS ${TESSERA_VENV_DIR}/bin/python)
  set(Python_EXECUTABLE ${TESSERA_VENV_DIR}/bin/python CACHE FILEPATH "Python for the tessera package")
endif()
if(SKBUILD)
  set(_tessera_python_default ON)
elseif(DEFINED Python_EXECUTABLE)
  execute_process(COMMAND ${Python_EXECUTABLE} -m nanobind --cmake_dir
    OUTPUT_VARIABLE _tessera_nanobind_dir OUTPUT_STRIP_TRAILING_WHITESPACE
    RESULT_VARIABLE _tessera_nanobind_rc ERROR_QUIET)
  if(_tessera_nanobind_rc EQUAL 0 AND EXISTS "${_tessera_nanobind_dir}")
    set(_tessera_python_default ON)
  endif()
endif()
if(DEFINED CACHE{TESSERA_BUILD_PYTHON} AND DEFINED CACHE{_TESSERA_BUILD_PYTHON_DEFAULT})
  if(TESSERA_BUILD_PYTHON STREQUAL _TESSERA_BUILD_PYTHON_DEFAULT AND
     NOT TESSERA_BUILD_PYTHON STREQUAL _tessera_python_default)
    message(STATUS "TESSERA_BUILD_PYTHON: default now ${_tessera_python_default} (was ${TESSERA_BUILD_PYTHON}, "
                   "never set by hand): following it")
    set(TESSERA_BUILD_PYTHON ${_tessera_python_default} CACHE BOOL
        "Build the Python package's extension module (needs nanobind)" FORCE)
  endif()
endif()
option(TESSERA_BUILD_PYTHON "Build the Python package's extension module (needs nanobind)" ${_tessera_python_default})
set(_TESSERA_BUILD_PYTHON_DEFAULT ${_tessera_python_default} CACHE INTERNAL "the default of the last configure")
