# cmake -DIMUCONV_SOURCE=<tree> -DPARENT=<parent project> -DWORK_ROOT=<dir> [-DGENERATOR=<g>]
#       -P run_subproject.cmake
# Configures parent/ (which add_subdirectory's imuconv) in a fresh directory of its own under
# WORK_ROOT, so parallel runs never share one, and removes it afterwards. The checks are in
# parent/CMakeLists.txt; this script also reads the parent's cache for a forced build type.
foreach(v IMUCONV_SOURCE PARENT WORK_ROOT)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "run_subproject.cmake: -D${v}=... is required")
  endif()
endforeach()

file(MAKE_DIRECTORY ${WORK_ROOT})
foreach(attempt RANGE 20)
  string(RANDOM LENGTH 12 ALPHABET abcdefghijklmnopqrstuvwxyz0123456789 suffix)
  set(work ${WORK_ROOT}/subproject-${suffix})
  if(NOT EXISTS ${work})
    break()
  endif()
endforeach()
if(EXISTS ${work})
  message(FATAL_ERROR "run_subproject.cmake: no free directory name under ${WORK_ROOT}")
endif()
file(MAKE_DIRECTORY ${work})

set(gen_args "")
if(GENERATOR)
  set(gen_args -G ${GENERATOR})
endif()
execute_process(COMMAND ${CMAKE_COMMAND} ${gen_args} -S ${PARENT} -B ${work} -DIMUCONV_SOURCE=${IMUCONV_SOURCE}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
set(cache_build_type "")
if(EXISTS ${work}/CMakeCache.txt)
  file(STRINGS ${work}/CMakeCache.txt cache_build_type REGEX "^CMAKE_BUILD_TYPE:")
endif()
file(REMOVE_RECURSE ${work})

if(NOT rc EQUAL 0)
  message(FATAL_ERROR "configuring a parent project around imuconv failed (exit ${rc}):\n${out}\n${err}")
endif()
if(NOT cache_build_type STREQUAL "" AND NOT cache_build_type MATCHES "^CMAKE_BUILD_TYPE:[A-Z]+=$")
  message(FATAL_ERROR "imuconv forced the parent's cached build type: ${cache_build_type}")
endif()
message(STATUS "subproject_guard: passed")
