# run_checked(WHAT COMMAND...): runs COMMAND (script mode; within RUN_CHECKED_TIMEOUT seconds,
# default 100) and stops with a fatal error naming WHAT, the exit status and the output when it
# fails; else sets last_output to its output (stdout then stderr) in the caller's scope.
# Included by compare_with_cli.cmake and install_consumer.cmake.
if(NOT RUN_CHECKED_TIMEOUT)
  set(RUN_CHECKED_TIMEOUT 100)
endif()
function(run_checked what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err
                  TIMEOUT ${RUN_CHECKED_TIMEOUT})
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}\n${err}")
  endif()
  set(last_output "${out}${err}" PARENT_SCOPE)
endfunction()
