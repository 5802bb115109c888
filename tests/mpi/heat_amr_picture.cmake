# cmake -DEXE=tessera-heat -DMPIEXEC=mpiexec -DPYTHON=python3 -DSOURCE_DIR=<repo> -DWORK=DIR
#       -P heat_amr_picture.cmake
# docs/images/heat_amr.png is what scripts/make_doc_images.sh's command makes: tessera-heat
# --amr --levels 3 with configs/heat_amr.yaml, 32^3 vertices, 40 steps, 2 ranks; its image of
# step 40 has the committed picture's pixels exactly (decoded by png_pixels_equal.py, so that
# another zlib does not matter).
cmake_minimum_required(VERSION 3.22)
file(REMOVE_RECURSE "${WORK}")
execute_process(COMMAND "${MPIEXEC}" -n 2 "${EXE}" --config "${SOURCE_DIR}/configs/heat_amr.yaml" --amr --levels 3
  --steps 40 --grid 32 32 32 --output-dir "${WORK}"
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 150)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "tessera-heat --amr failed (${rc}):\n${out}\n${err}")
endif()
execute_process(COMMAND "${PYTHON}" "${SOURCE_DIR}/tests/mpi/png_pixels_equal.py" "${SOURCE_DIR}/docs/images/heat_amr.png"
  "${WORK}/heat_amr_000040.png" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "docs/images/heat_amr.png is not what its command makes: ${out}${err}")
endif()
message(STATUS "docs/images/heat_amr.png: the same pixels as tessera-heat --amr makes")
