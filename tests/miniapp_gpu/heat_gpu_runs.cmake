# cmake -DEXE=tessera-heat -DCPU_CONFIG=configs/heat.yaml -DGPU_CONFIG=configs/heat_gpu.yaml -DWORK=DIR -DNP=N
#       [-DMPIEXEC=mpiexec] -DPYTHON=python3 -DCOMPARE=compare_heat_runs.py -P heat_gpu_runs.cmake
# tessera-heat --device cuda for 10 steps on 24^3 vertices (under mpiexec -n NP when NP > 1),
# its field simulated and rendered on the GPU, against one CPU process with configs/heat.yaml:
# the images are written, the dumped fields (--dump, float32) agree to float32 rounding and are
# finite, and the PNGs agree within Monte Carlo error (compare_heat_runs.py). Without a CUDA
# device it prints "SKIPPED: " and the reason (the test's SKIP_REGULAR_EXPRESSION).
# The fake clock of tests makes the render budget's plans, and so the samples per pixel, the
# same in both runs (tests/heat_runs.cmake).
cmake_minimum_required(VERSION 3.22)
set(ENV{TESSERA_TEST_CLOCK} "0.05,1e-7")
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}/gpu" "${WORK}/cpu")
set(args --steps 10 --grid 24 24 24)

# The GPU run first: without a device, skip
if(NP GREATER 1)
  set(launch "${MPIEXEC}" -n ${NP})
else()
  set(launch "")
endif()
execute_process(COMMAND ${launch} "${EXE}" ${args} --device cuda --config "${GPU_CONFIG}" --output-dir "${WORK}/gpu"
                        --dump "${WORK}/gpu/field.raw"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 150)
if(NOT rc EQUAL 0 AND err MATCHES "no CUDA device visible")
  string(REGEX MATCH "no CUDA device visible[^\n]*" why "${err}")
  message(STATUS "SKIPPED: tessera-heat --device cuda needs a CUDA device: ${why}")
  return()
endif()
if(NOT rc EQUAL 0 OR err MATCHES "failed")
  message(FATAL_ERROR "tessera-heat --device cuda (${NP} rank(s)) failed (${rc}):\n${out}\n${err}")
endif()
message(STATUS "tessera-heat --device cuda (${NP} rank(s)): ${out}")

# The CPU run: one process, the plain config
execute_process(COMMAND "${EXE}" ${args} --config "${CPU_CONFIG}" --output-dir "${WORK}/cpu" --dump "${WORK}/cpu/field.raw"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 150)
if(NOT rc EQUAL 0 OR err MATCHES "failed")
  message(FATAL_ERROR "tessera-heat (CPU) failed (${rc}):\n${out}\n${err}")
endif()

foreach(image heat_far_000000.exr heat_far_000010.exr heat_close_000010.exr heat_far_000010.png heat_close_000010.png)
  foreach(run gpu cpu)
    if(NOT EXISTS "${WORK}/${run}/${image}")
      message(FATAL_ERROR "the ${run} run wrote no ${WORK}/${run}/${image}")
    endif()
  endforeach()
endforeach()
execute_process(COMMAND "${PYTHON}" "${COMPARE}" "${WORK}/cpu" "${WORK}/gpu" RESULT_VARIABLE rc OUTPUT_VARIABLE out
                ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the GPU run differs from the CPU run:\n${out}\n${err}")
endif()
message(STATUS "${out}")
