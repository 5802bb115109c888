# The complete C and Fortran examples of docs/data-model.md (and its AMR example in C), built and
# run against the page's config (doc_examples.cmake); each must write both steps' PNGs.
include(${CMAKE_CURRENT_LIST_DIR}/doc_examples.cmake)
set(_dm_dir ${CMAKE_CURRENT_BINARY_DIR}/data_model)
tessera_doc_examples(${PROJECT_SOURCE_DIR}/docs/data-model.md ${_dm_dir}
  "mesh_example.yaml;mesh_example.c;domains_example.yaml;domains_example.c;domains_example.f90;amr_example.c")
tessera_doc_example_program(tessera_docs_domains_c C ${_dm_dir}/domains_example.c)
# The AMR example: two levels of cell data, the same config
tessera_doc_example_program(tessera_docs_amr_c C ${_dm_dir}/amr_example.c)
tessera_doc_example_program(tessera_docs_domains_fortran Fortran ${_dm_dir}/domains_example.f90)
foreach(_dm c:tessera_docs_domains_c amr_c:tessera_docs_amr_c fortran:tessera_docs_domains_fortran)
  string(REPLACE ":" ";" _dm ${_dm})
  list(GET _dm 0 _dm_name)
  list(GET _dm 1 _dm_exe)
  tessera_doc_example_test(NAME docs.data_model_${_dm_name} PROGRAM ${_dm_exe} WORK ${_dm_dir}/run_${_dm_name}
    CONFIG ${_dm_dir}/domains_example.yaml TIMEOUT 120 OUTPUTS out/blocks_000.png out/blocks_001.png)
endforeach()
# Curvilinear and unstructured domains: its own config
tessera_doc_example_program(tessera_docs_mesh_c C ${_dm_dir}/mesh_example.c)
tessera_doc_example_test(NAME docs.data_model_mesh PROGRAM tessera_docs_mesh_c WORK ${_dm_dir}/run_mesh
  CONFIG ${_dm_dir}/mesh_example.yaml TIMEOUT 120 OUTPUTS out/shell_000.png out/shell_001.png)
