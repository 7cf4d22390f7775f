# What the consumer scripts (run_consumer.cmake, run_custom_convention.cmake) do with each step
# of theirs that runs a program: run it, and stop the test at the first that fails, saying which
# step it was, its exit code and all it printed (a package test failing on another machine has
# only its log to go on).
#
# run_step(WHAT COMMAND...): runs COMMAND; on a non-zero exit (or one that could not start),
# FATAL_ERROR "WHAT failed (CODE)" with its standard output and error. Otherwise sets `out` in
# the caller's scope to its standard output. COMMAND is a CMake list: an argument holding a ';'
# would be split (none of the scripts' commands has one).
function(run_step what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(rc)
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}\n${err}")
  endif()
  set(out "${out}" PARENT_SCOPE)
endfunction()
