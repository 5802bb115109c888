# cmake -DBUILD_DIR=<tessera build> -DCONSUMER=consumer -DWORK=DIR -DCONFIG_TYPE=Release
#       -DGENERATOR=... -DFortran_COMPILER=... -DC_COMPILER=... -DCXX_COMPILER=...
#       -P install_consumer.cmake
# Installs the built Tessera into DIR/prefix, then configures, builds and runs consumer/ (a
# project(... Fortran) with find_package(Tessera) and tessera::fortran) against that prefix.
cmake_minimum_required(VERSION 3.22)
file(REMOVE_RECURSE "${WORK}")

function(run_checked what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err
                  TIMEOUT 250)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}\n${err}")
  endif()
  set(last_output "${out}${err}" PARENT_SCOPE)
endfunction()

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
  "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}")
if(last_output MATCHES "CMake Warning")
  message(FATAL_ERROR "the consumer's configure warned:\n${last_output}")
endif()
run_checked("build the consumer" "${CMAKE_COMMAND}" --build "${WORK}/build" --config ${CONFIG_TYPE})
file(MAKE_DIRECTORY "${WORK}/run")
execute_process(COMMAND "${WORK}/build/tessera_consumer" WORKING_DIRECTORY "${WORK}/run"
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 60)
if(NOT rc EQUAL 0 OR NOT EXISTS "${WORK}/run/out/consumer_000002.exr")
  message(FATAL_ERROR "the consumer failed (${rc}) or wrote no image:\n${out}\n${err}")
endif()
message(STATUS "${out}")
