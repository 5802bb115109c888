# The side-by-side of docs/porting-from-ascent.md: its C and Fortran simulations with Tessera's
# adaptors, built and run with its viz.yaml (doc_examples.cmake); each must write both renders'
# PNGs of step 1. The C and Fortran programs publish the same data: their images are the same
# bytes. Its table of line counts is checked in CMakeLists.txt (check_porting.py).
include(${CMAKE_CURRENT_LIST_DIR}/doc_examples.cmake)
set(_pa_dir ${CMAKE_CURRENT_BINARY_DIR}/porting)
tessera_doc_examples(${PROJECT_SOURCE_DIR}/docs/porting-from-ascent.md ${_pa_dir}
  "viz.yaml;porting_sim.h;porting_sim.c;porting_tessera.c;porting_sim.f90;porting_main.f90;porting_tessera.f90")
tessera_doc_example_program(tessera_docs_porting_c C ${_pa_dir}/porting_sim.c ${_pa_dir}/porting_tessera.c)
tessera_doc_example_program(tessera_docs_porting_fortran Fortran ${_pa_dir}/porting_sim.f90
  ${_pa_dir}/porting_main.f90 ${_pa_dir}/porting_tessera.f90)
foreach(_pa_name c fortran)
  tessera_doc_example_test(NAME docs.porting_${_pa_name} PROGRAM tessera_docs_porting_${_pa_name}
    WORK ${_pa_dir}/run_${_pa_name} CONFIG ${_pa_dir}/viz.yaml TIMEOUT 300
    OUTPUTS out/energy_000001.png out/speed_000001.png FIXTURE porting_${_pa_name})
endforeach()
if(TARGET tessera_docs_porting_c AND TARGET tessera_docs_porting_fortran)
  add_test(NAME docs.porting_same_images
    COMMAND sh -c "cmp run_c/out/energy_000001.exr run_fortran/out/energy_000001.exr && cmp run_c/out/speed_000001.exr run_fortran/out/speed_000001.exr"
    WORKING_DIRECTORY ${_pa_dir})
  set_tests_properties(docs.porting_same_images PROPERTIES LABELS docs TIMEOUT 60
    FIXTURES_REQUIRED "porting_c;porting_fortran")
endif()
