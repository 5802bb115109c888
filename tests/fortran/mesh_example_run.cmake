# cmake -DEXE=mesh_example -DCONFIG=mesh_example.yaml -DWORK=DIR -DPYTHON=python3 -DCHECK=png_not_flat.py
#       -P mesh_example_run.cmake
# Runs a mesh example (mesh_example.c or .f90) in WORK with CONFIG; then: every render wrote its
# EXR and PNG, the shell published as a curvilinear grid and as unstructured hexes gave the same
# EXR bytes, and the shell's and the tets' PNGs are pictures, not flat (CHECK).
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
execute_process(COMMAND ${EXE} ${CONFIG} WORKING_DIRECTORY ${WORK} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${EXE} ${CONFIG} failed (${rc})")
endif()
foreach(dir shell hexes tets)
  foreach(ext exr png)
    if(NOT EXISTS ${WORK}/${dir}/f_000000.${ext})
      message(FATAL_ERROR "${dir}/f_000000.${ext} was not written")
    endif()
  endforeach()
endforeach()
file(SHA256 ${WORK}/shell/f_000000.exr shell)
file(SHA256 ${WORK}/hexes/f_000000.exr hexes)
if(NOT shell STREQUAL hexes)
  message(FATAL_ERROR "the shell as a curvilinear grid and as unstructured hexes: different images")
endif()
execute_process(COMMAND ${PYTHON} ${CHECK} ${WORK}/shell/f_000000.png ${WORK}/tets/f_000000.png
  RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "a flat image (above)")
endif()
message(STATUS "curvilinear = hexes bit for bit; shell and tets are pictures")
