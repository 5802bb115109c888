# The side-by-side of docs/porting-from-ascent.md: its C and Fortran simulations with Tessera's
# adaptors (its `<!-- file: NAME -->` blocks) are extracted at configure time, built with the
# tree and run with its viz.yaml (label "docs"); each must write both renders' PNGs of step 1.
# The C and Fortran programs publish the same data: their images are the same bytes.
# Its table of line counts is checked in CMakeLists.txt (check_porting.py).
include(${PROJECT_SOURCE_DIR}/cmake/TesseraDocFiles.cmake)
set(_pa_doc ${PROJECT_SOURCE_DIR}/docs/porting-from-ascent.md)
set(_pa_dir ${CMAKE_CURRENT_BINARY_DIR}/porting)
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${_pa_doc})
tessera_doc_files(${_pa_doc} ${_pa_dir} _pa_names)
if(NOT _pa_names STREQUAL "viz.yaml;porting_sim.h;porting_sim.c;porting_tessera.c;porting_sim.f90;porting_main.f90;porting_tessera.f90")
  message(FATAL_ERROR "${_pa_doc}: expected the blocks viz.yaml, porting_sim.h, .c, porting_tessera.c, porting_sim.f90, porting_main.f90, porting_tessera.f90; found: ${_pa_names}")
endif()
function(_tessera_porting_test name exe)
  set(work ${_pa_dir}/run_${name})
  file(MAKE_DIRECTORY ${work})
  configure_file(${_pa_dir}/viz.yaml ${work}/viz.yaml COPYONLY)
  add_test(NAME docs.porting_${name}
    COMMAND sh -c "rm -rf out && \"$1\" && test -s out/energy_000001.png && test -s out/speed_000001.png" sh
            $<TARGET_FILE:${exe}>
    WORKING_DIRECTORY ${work})
  set_tests_properties(docs.porting_${name} PROPERTIES LABELS docs TIMEOUT 300 FIXTURES_SETUP porting_${name})
endfunction()
if(TARGET tessera_insitu)
  add_executable(tessera_docs_porting_c ${_pa_dir}/porting_sim.c ${_pa_dir}/porting_tessera.c)
  target_link_libraries(tessera_docs_porting_c PRIVATE tessera::insitu m)
  _tessera_porting_test(c tessera_docs_porting_c)
endif()
if(TARGET tessera_fortran)
  add_executable(tessera_docs_porting_fortran ${_pa_dir}/porting_sim.f90 ${_pa_dir}/porting_main.f90
    ${_pa_dir}/porting_tessera.f90)
  target_link_libraries(tessera_docs_porting_fortran PRIVATE tessera::fortran)
  target_compile_options(tessera_docs_porting_fortran PRIVATE -std=f2008 -Wall)
  set_target_properties(tessera_docs_porting_fortran PROPERTIES
    Fortran_MODULE_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR}/porting_fortran_mod)
  _tessera_porting_test(fortran tessera_docs_porting_fortran)
endif()
if(TARGET tessera_docs_porting_c AND TARGET tessera_docs_porting_fortran)
  add_test(NAME docs.porting_same_images
    COMMAND sh -c "cmp run_c/out/energy_000001.exr run_fortran/out/energy_000001.exr && cmp run_c/out/speed_000001.exr run_fortran/out/speed_000001.exr"
    WORKING_DIRECTORY ${_pa_dir})
  set_tests_properties(docs.porting_same_images PROPERTIES LABELS docs TIMEOUT 60
    FIXTURES_REQUIRED "porting_c;porting_fortran")
endif()
