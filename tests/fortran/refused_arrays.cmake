# cmake -DEXE=tessera_fortran_refused_arrays -DWORK=DIR [-DVALGRIND=valgrind] -P refused_arrays.cmake
# Runs the program in a fresh WORK (under valgrind when VALGRIND is given: any invalid read or
# write, or use of an uninitialised value, fails the run; leaks are not counted) and requires
# the library's log lines (stderr, "tessera: ...") of the refused calls to name the module's
# fault, never a secondary complaint about the empty call that stands in for them.
cmake_minimum_required(VERSION 3.22)
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
set(cmd "${EXE}")
if(VALGRIND)
  set(cmd "${VALGRIND}" --error-exitcode=99 --errors-for-leak-kinds=none --leak-check=no
      --track-origins=yes "${EXE}")
endif()
execute_process(COMMAND ${cmd} WORKING_DIRECTORY "${WORK}" RESULT_VARIABLE rc OUTPUT_VARIABLE out
                ERROR_VARIABLE err TIMEOUT 280)
message("${out}${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "refused_arrays failed (exit ${rc}; 99: valgrind found an error)")
endif()
# The log names each refused mesh's fault at its step; nothing blames the stand-in call
foreach(line "step 1: mesh%refinement has 1 ratio" "step 3: mesh: the coordinates of axis 1 \\(i\\)"
             "step 6: fields\\(1\\) 't': dims\\(3\\) = 7" "step 8: domains\\(1\\)%fields\\(1\\) 't': dtype")
  if(NOT err MATCHES "tessera: render 'r' at ${line}")
    message(FATAL_ERROR "no log line \"tessera: render 'r' at ${line}...\"")
  endif()
endforeach()
foreach(wrong "no rank passed a domain" "mesh is NULL" "ranks disagree" "field list is invalid" "descriptor is NULL")
  if(err MATCHES "${wrong}")
    message(FATAL_ERROR "a log line blames the stand-in call (\"${wrong}\")")
  endif()
endforeach()
