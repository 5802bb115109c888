# cmake -DBUILD_DIR=<tessera build> -DDOC=docs/fortran.md -DSOURCE_DIR=<tessera source> -DWORK=DIR -DCONFIG_TYPE=Release
#       -DGENERATOR=... -DFortran_COMPILER=... -DC_COMPILER=... -DCXX_COMPILER=...
#       [-DEXE_LINKER_FLAGS=...] -P install_consumer.cmake
# (EXE_LINKER_FLAGS: the build's, e.g. -fsanitize=... of scripts/sanitize.sh, which the
# installed static libraries need at link time.)
# Installs the built Tessera into DIR/prefix, then, against that prefix:
#  1. configures, builds and runs the example project of docs/fortran.md (its blocks marked
#     `<!-- file: NAME -->`: a project(... Fortran) with find_package(Tessera) and
#     tessera::fortran);
#  2. builds section_render.f90 (one process) the same way and requires its images to be
#     byte-identical to the installed tessera-render's (compare_with_cli.cmake).
cmake_minimum_required(VERSION 3.22)
file(REMOVE_RECURSE "${WORK}")

# The example's files, from the fenced block after each `<!-- file: NAME -->`
set(CONSUMER "${WORK}/example")
include("${SOURCE_DIR}/cmake/TesseraDocFiles.cmake")
tessera_doc_files("${DOC}" "${CONSUMER}" names)
if(NOT names STREQUAL "CMakeLists.txt;viz.yaml;sim.f90")
  message(FATAL_ERROR "${DOC}: expected the blocks CMakeLists.txt, viz.yaml, sim.f90; found: ${names}")
endif()

set(RUN_CHECKED_TIMEOUT 250)
include("${CMAKE_CURRENT_LIST_DIR}/run_checked.cmake")

if(NOT CONFIG_TYPE)
  set(CONFIG_TYPE Release)
endif()
run_checked("cmake --install" "${CMAKE_COMMAND}" --install "${BUILD_DIR}" --prefix "${WORK}/prefix"
  --config ${CONFIG_TYPE})
file(GLOB_RECURSE mods "${WORK}/prefix/include/tessera/fortran/*.mod")
if(NOT mods)
  message(FATAL_ERROR "no tessera.mod installed under ${WORK}/prefix/include/tessera/fortran")
endif()
run_checked("configure the consumer" "${CMAKE_COMMAND}" -S "${CONSUMER}" -B "${WORK}/build"
  -G "${GENERATOR}" -DCMAKE_BUILD_TYPE=${CONFIG_TYPE} "-DCMAKE_PREFIX_PATH=${WORK}/prefix"
  "-DCMAKE_Fortran_COMPILER=${Fortran_COMPILER}" "-DCMAKE_C_COMPILER=${C_COMPILER}"
  "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}"
  "-DCMAKE_EXE_LINKER_FLAGS=${EXE_LINKER_FLAGS}")
if(last_output MATCHES "CMake Warning")
  message(FATAL_ERROR "the consumer's configure warned:\n${last_output}")
endif()
run_checked("build the consumer" "${CMAKE_COMMAND}" --build "${WORK}/build" --config ${CONFIG_TYPE})
execute_process(COMMAND "${WORK}/build/sim" WORKING_DIRECTORY "${CONSUMER}"
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 60)
foreach(image sim_000000.exr sim_000005.png sim_000010.exr)
  if(NOT rc EQUAL 0 OR NOT EXISTS "${CONSUMER}/out/${image}")
    message(FATAL_ERROR "the example failed (${rc}) or wrote no out/${image}:\n${out}\n${err}")
  endif()
endforeach()
message(STATUS "the example of ${DOC} built against ${WORK}/prefix and rendered:\n${err}")

# The section program, as a project of its own, against the installed tessera-render
file(WRITE "${WORK}/section/CMakeLists.txt" "cmake_minimum_required(VERSION 3.22)
project(section LANGUAGES Fortran)
find_package(Tessera REQUIRED)
add_executable(section \"${SOURCE_DIR}/tests/fortran/section_render.f90\"
  \"${SOURCE_DIR}/tests/fortran/test_support.f90\" \"${SOURCE_DIR}/miniapp/fortran/heat_parallel_serial.f90\")
target_link_libraries(section PRIVATE tessera::fortran)
")
run_checked("configure the section project" "${CMAKE_COMMAND}" -S "${WORK}/section"
  -B "${WORK}/section-build" -G "${GENERATOR}" -DCMAKE_BUILD_TYPE=${CONFIG_TYPE}
  "-DCMAKE_PREFIX_PATH=${WORK}/prefix" "-DCMAKE_Fortran_COMPILER=${Fortran_COMPILER}"
  "-DCMAKE_C_COMPILER=${C_COMPILER}" "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}"
  "-DCMAKE_EXE_LINKER_FLAGS=${EXE_LINKER_FLAGS}")
run_checked("build the section project" "${CMAKE_COMMAND}" --build "${WORK}/section-build"
  --config ${CONFIG_TYPE})
run_checked("installed section program vs installed tessera-render" "${CMAKE_COMMAND}"
  "-DEXE=${WORK}/section-build/section" "-DRENDER=${WORK}/prefix/bin/tessera-render"
  "-DWORK=${WORK}/section-run" -DNP=1 -P "${CMAKE_CURRENT_LIST_DIR}/compare_with_cli.cmake")
message(STATUS "installed package: section images identical to tessera-render's:\n${last_output}")
