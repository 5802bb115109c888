# The complete C and Fortran examples of docs/data-model.md (and its AMR example in C) (its `<!-- file: NAME -->` blocks)
# are extracted at configure time, built with the tree and run against their config (label
# "docs"): the page cannot drift from what compiles and renders.
include(${PROJECT_SOURCE_DIR}/cmake/TesseraDocFiles.cmake)
set(_dm_doc ${PROJECT_SOURCE_DIR}/docs/data-model.md)
set(_dm_dir ${CMAKE_CURRENT_BINARY_DIR}/data_model)
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${_dm_doc})
tessera_doc_files(${_dm_doc} ${_dm_dir} _dm_names)
if(NOT _dm_names STREQUAL "domains_example.yaml;domains_example.c;domains_example.f90;amr_example.c")
  message(FATAL_ERROR "${_dm_doc}: expected the blocks domains_example.yaml, .c, .f90, amr_example.c; found: ${_dm_names}")
endif()

# Each program runs in its own folder holding the config; it must write both steps' PNGs
function(_tessera_data_model_test name exe)
  set(work ${_dm_dir}/run_${name})
  file(MAKE_DIRECTORY ${work})
  configure_file(${_dm_dir}/domains_example.yaml ${work}/domains_example.yaml COPYONLY)
  add_test(NAME docs.data_model_${name}
    COMMAND sh -c "rm -rf out && \"$1\" && test -s out/blocks_000.png && test -s out/blocks_001.png" sh
            $<TARGET_FILE:${exe}>
    WORKING_DIRECTORY ${work})
  set_tests_properties(docs.data_model_${name} PROPERTIES LABELS docs TIMEOUT 120)
endfunction()

if(TARGET tessera_insitu)
  add_executable(tessera_docs_domains_c ${_dm_dir}/domains_example.c)
  target_link_libraries(tessera_docs_domains_c PRIVATE tessera::insitu m)
  _tessera_data_model_test(c tessera_docs_domains_c)
  # The AMR example: two levels of cell data, the same config
  add_executable(tessera_docs_amr_c ${_dm_dir}/amr_example.c)
  target_link_libraries(tessera_docs_amr_c PRIVATE tessera::insitu m)
  _tessera_data_model_test(amr_c tessera_docs_amr_c)
endif()
if(TARGET tessera_fortran)
  add_executable(tessera_docs_domains_fortran ${_dm_dir}/domains_example.f90)
  target_link_libraries(tessera_docs_domains_fortran PRIVATE tessera::fortran)
  target_compile_options(tessera_docs_domains_fortran PRIVATE -std=f2008 -Wall)
  set_target_properties(tessera_docs_domains_fortran PROPERTIES
    Fortran_MODULE_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR}/domains_fortran_mod)
  _tessera_data_model_test(fortran tessera_docs_domains_fortran)
endif()
