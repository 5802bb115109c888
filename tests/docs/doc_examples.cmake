# The complete programs of a page of docs/ (its `<!-- file: NAME -->` blocks) are extracted at
# configure time, built with the tree and run in a folder of their own that holds the page's
# config (label "docs"): the page cannot drift from what compiles and renders. Shared by
# data_model_examples.cmake and porting_examples.cmake.
include_guard(GLOBAL)
include(${PROJECT_SOURCE_DIR}/cmake/TesseraDocFiles.cmake)

# tessera_doc_examples(DOC OUTDIR EXPECTED): writes DOC's blocks to OUTDIR; a configure error
# unless their names are the list EXPECTED, in order. DOC's changes reconfigure.
function(tessera_doc_examples doc outdir expected)
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${doc})
  tessera_doc_files(${doc} ${outdir} names)
  if(NOT names STREQUAL expected)
    string(REPLACE ";" ", " expected "${expected}")
    string(REPLACE ";" ", " names "${names}")
    message(FATAL_ERROR "${doc}: expected the blocks ${expected}; found: ${names}")
  endif()
endfunction()

# tessera_doc_example_program(TARGET LANG SOURCES...): the program TARGET from extracted
# SOURCES, on tessera::insitu (LANG C) or tessera::fortran (LANG Fortran); no target when that
# library is not built.
function(tessera_doc_example_program target lang)
  if(lang STREQUAL "C" AND TARGET tessera_insitu)
    add_executable(${target} ${ARGN})
    target_link_libraries(${target} PRIVATE tessera::insitu m)
  elseif(lang STREQUAL "Fortran" AND TARGET tessera_fortran)
    add_executable(${target} ${ARGN})
    target_link_libraries(${target} PRIVATE tessera::fortran)
    target_compile_options(${target} PRIVATE -std=f2008 -Wall)
    set_target_properties(${target} PROPERTIES Fortran_MODULE_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR}/${target}_mod)
  endif()
endfunction()

# tessera_doc_example_test(NAME test PROGRAM target WORK dir CONFIG file TIMEOUT s
#                          OUTPUTS files... [FIXTURE name]): the test runs PROGRAM in WORK, which
# holds a copy of CONFIG, after removing out/ there; each of OUTPUTS (relative to WORK) must then
# be a file that is not empty. FIXTURE: the test sets up that fixture. Nothing without PROGRAM.
function(tessera_doc_example_test)
  cmake_parse_arguments(PARSE_ARGV 0 arg "" "NAME;PROGRAM;WORK;CONFIG;TIMEOUT;FIXTURE" "OUTPUTS")
  if(NOT TARGET ${arg_PROGRAM})
    return()
  endif()
  file(MAKE_DIRECTORY ${arg_WORK})
  get_filename_component(config_name ${arg_CONFIG} NAME)
  configure_file(${arg_CONFIG} ${arg_WORK}/${config_name} COPYONLY)
  set(script "rm -rf out && \"$1\"")
  foreach(output IN LISTS arg_OUTPUTS)
    string(APPEND script " && test -s ${output}")
  endforeach()
  add_test(NAME ${arg_NAME} COMMAND sh -c "${script}" sh $<TARGET_FILE:${arg_PROGRAM}>
    WORKING_DIRECTORY ${arg_WORK})
  set_tests_properties(${arg_NAME} PROPERTIES LABELS docs TIMEOUT ${arg_TIMEOUT})
  if(arg_FIXTURE)
    set_tests_properties(${arg_NAME} PROPERTIES FIXTURES_SETUP ${arg_FIXTURE})
  endif()
endfunction()
