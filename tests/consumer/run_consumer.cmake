# Installs imuconv into a scratch prefix, then configures, builds and runs tests/consumer/project
# against the installed package (the fmt-style consumer test).
include(${CMAKE_CURRENT_LIST_DIR}/run_step.cmake)
file(REMOVE_RECURSE ${WORK})
run_step("install" ${CMAKE_COMMAND} --install ${BUILD} --prefix ${WORK}/prefix)
run_step("consumer configure" ${CMAKE_COMMAND} -S ${SRC} -B ${WORK}/build -DCMAKE_BUILD_TYPE=Release
         -DCMAKE_PREFIX_PATH=${WORK}/prefix)
run_step("consumer build" ${CMAKE_COMMAND} --build ${WORK}/build)
run_step("consumer run" ${WORK}/build/consumer)
# imuconv::ceres through the package, when it was installed with it.
if(EXISTS ${WORK}/prefix/include/imuconv/ceres/state_manifold.h)
  if(NOT EXISTS ${WORK}/build/consumer_ceres)
    message(FATAL_ERROR "the package installed imuconv::ceres's headers but not its target")
  endif()
  run_step("consumer_ceres run" ${WORK}/build/consumer_ceres)
endif()

# The user's tool does not need Google Benchmark at run time (imuconv-bench does).
execute_process(COMMAND readelf -d ${WORK}/prefix/bin/imuconv OUTPUT_VARIABLE dyn RESULT_VARIABLE rc)
if(rc OR NOT dyn MATCHES "NEEDED")
  message(FATAL_ERROR "readelf -d on the installed imuconv failed")
endif()
if(dyn MATCHES "libbenchmark")
  message(FATAL_ERROR "the installed imuconv needs Google Benchmark at run time:\n${dyn}")
endif()
if(NOT EXISTS ${WORK}/prefix/bin/imuconv-bench)
  message(FATAL_ERROR "imuconv-bench is not installed beside imuconv")
endif()

# The same package without CMake: compiler flags from the installed imuconv.pc only.
file(GLOB_RECURSE pc_files ${WORK}/prefix/imuconv.pc)
list(LENGTH pc_files n_pc)
if(NOT n_pc EQUAL 1)
  message(FATAL_ERROR "expected one installed imuconv.pc, found: ${pc_files}")
endif()
get_filename_component(pc_dir ${pc_files} DIRECTORY)
run_step("pkg-config --cflags --libs imuconv"
         ${CMAKE_COMMAND} -E env PKG_CONFIG_PATH=${pc_dir} pkg-config --cflags --libs imuconv)
string(STRIP "${out}" pc_flags)
separate_arguments(pc_flags UNIX_COMMAND "${pc_flags}")
run_step("compiling with pkg-config's flags (${pc_flags})"
         c++ ${SRC}/../pkgconfig_main.cpp ${pc_flags} -o ${WORK}/pc_consumer)
run_step("the pkg-config consumer" ${CMAKE_COMMAND} -E env LD_LIBRARY_PATH=${pc_dir}/.. ${WORK}/pc_consumer)

# The installed Python module (when built): it imports from the prefix alone and its Registry
# loads the installed plugins, not the build tree's.
if(PYTHON)
  run_step("the installed Python module"
           ${CMAKE_COMMAND} -E env PYTHONPATH=${WORK}/prefix/${PYTHON_DIR} IMUCONV_PLUGIN_PATH=
           ${PYTHON} -c "import imuconv, os, sys
r = imuconv.Registry()
files = {p['file'] for p in r.plugins() if p['file'] != 'built-in'}
assert imuconv.__file__.startswith(sys.argv[1]), imuconv.__file__
assert files and all(f.startswith(sys.argv[1]) for f in files), files
assert 'euler' in r.ids('propagator'), r.ids('propagator')
print('installed module:', imuconv.__file__, len(files), 'plugins')" ${WORK}/prefix)
  message(STATUS "${out}")
endif()
