# Runs the scene generator into OUT_DIR and compares every .gltf and .bin it writes, byte for byte, with the
# one committed under SCENES_DIR; a committed .gltf or .bin that the generator no longer writes fails too.
#   cmake -DMAKE_SCENES=<fly_make_scenes> -DOUT_DIR=<temporary dir> -DSCENES_DIR=<repo>/scenes
#         -P check_scenes.cmake
cmake_minimum_required(VERSION 3.25)
foreach(var MAKE_SCENES OUT_DIR SCENES_DIR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "check_scenes.cmake: -D${var}=... is required")
  endif()
endforeach()

file(REMOVE_RECURSE "${OUT_DIR}")
execute_process(COMMAND "${MAKE_SCENES}" "${OUT_DIR}" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "fly_make_scenes failed (${rc})")
endif()

file(GLOB_RECURSE generated RELATIVE "${OUT_DIR}" "${OUT_DIR}/*")
file(GLOB_RECURSE committed RELATIVE "${SCENES_DIR}" "${SCENES_DIR}/*.gltf" "${SCENES_DIR}/*.bin")
set(problems "")
foreach(f IN LISTS generated)
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files "${OUT_DIR}/${f}" "${SCENES_DIR}/${f}"
                  RESULT_VARIABLE differs OUTPUT_QUIET ERROR_QUIET)
  if(NOT differs EQUAL 0)
    string(APPEND problems "\n  scenes/${f} differs from what the generator writes (or is missing)")
  endif()
endforeach()
foreach(f IN LISTS committed)
  if(NOT f IN_LIST generated)
    string(APPEND problems "\n  scenes/${f} is not written by the generator")
  endif()
endforeach()
if(problems)
  message(FATAL_ERROR "The committed scenes are out of date:${problems}\n"
                      "Run scripts/make-scenes and commit scenes/ (the new files are in ${OUT_DIR}).")
endif()
list(LENGTH generated n)
message(STATUS "${n} scene files up to date")
