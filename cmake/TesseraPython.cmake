# TESSERA_BUILD_PYTHON: the Python package's extension module (python/, docs/python.md).
# Default ON under scikit-build-core (`pip install .`) and when nanobind is found in the
# Python that CMake uses: Python_EXECUTABLE if given, else the project venv's .venv/bin/python
# (scripts/python_env.sh), so the main build compiles the module against the same libraries
# and the pytest suite runs it from the build tree.
set(_tessera_python_default OFF)
if(NOT DEFINED Python_EXECUTABLE AND EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/.venv/bin/python)
  set(Python_EXECUTABLE ${CMAKE_CURRENT_SOURCE_DIR}/.venv/bin/python CACHE FILEPATH "Python for the tessera package")
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
option(TESSERA_BUILD_PYTHON "Build the Python package's extension module (needs nanobind)" ${_tessera_python_default})
