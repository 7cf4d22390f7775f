# examples/custom_convention against the installed package only: install imuconv into a
# scratch prefix, build the example (a new state convention, a new integrator, a checker),
# then with IMUCONV_PLUGIN_PATH naming the example's plugins:
#   1. the installed `imuconv plugins` lists both;
#   2. check_conventions: conversions against every built-in convention (central differences,
#      round trips) and the integrator's convergence;
#   3. the installed `imuconv run` runs the example's pipeline, which uses both, and its output
#      names the user's plugin files and writes covariances in the user's convention;
#   4. the installed Python module's Registry loads and converts with them (when built).
file(REMOVE_RECURSE ${WORK})
include(${CMAKE_CURRENT_LIST_DIR}/run_step.cmake)
# Every step with the example's plugins on the plugin path.
function(run what)
  run_step("${what}" ${CMAKE_COMMAND} -E env IMUCONV_PLUGIN_PATH=${WORK}/build/plugins ${ARGN})
  set(out "${out}" PARENT_SCOPE)
endfunction()

run("install" ${CMAKE_COMMAND} --install ${BUILD} --prefix ${WORK}/prefix)
run("configuring the example" ${CMAKE_COMMAND} -S ${EXAMPLE} -B ${WORK}/build -DCMAKE_BUILD_TYPE=Release
    -DCMAKE_PREFIX_PATH=${WORK}/prefix)
run("building the example" ${CMAKE_COMMAND} --build ${WORK}/build)

run("imuconv plugins" ${WORK}/prefix/bin/imuconv plugins --json)
foreach(id euler_angles midpoint_substeps)
  if(NOT out MATCHES "\"id\": *\"${id}\"")
    message(FATAL_ERROR "the installed imuconv plugins does not list ${id}:\n${out}")
  endif()
endforeach()

run("check_conventions" ${WORK}/build/check_conventions)
message(STATUS "${out}")

run("imuconv run" ${WORK}/prefix/bin/imuconv run ${EXAMPLE}/pipeline.json -o ${WORK}/pipeline.out.json)
file(READ ${WORK}/pipeline.out.json doc)
string(JSON n_plugins LENGTH "${doc}" plugins)
set(found "")
math(EXPR last "${n_plugins} - 1")
foreach(i RANGE ${last})
  string(JSON id GET "${doc}" plugins ${i} id)
  string(JSON file GET "${doc}" plugins ${i} file)
  if(id MATCHES "^(euler_angles|midpoint_substeps)$" AND file MATCHES "^${WORK}/build/plugins/")
    list(APPEND found ${id})
  endif()
endforeach()
list(LENGTH found n_found)
if(NOT n_found EQUAL 2)
  message(FATAL_ERROR "the pipeline's output does not name both user plugins from ${WORK}/build/plugins: ${found}")
endif()
string(JSON conv GET "${doc}" tasks 1 steps 0 cov convention)
string(JSON first_block GET "${doc}" tasks 1 steps 0 cov blocks 1)
if(NOT conv STREQUAL "euler_angles" OR NOT first_block STREQUAL "v")
  message(FATAL_ERROR "the propagated covariance is not in euler_angles' chart and order: ${conv}, block 1 ${first_block}")
endif()

if(PYTHON)
  run("the Python module" ${CMAKE_COMMAND} -E env PYTHONPATH=${WORK}/prefix/${PYTHON_DIR} ${PYTHON} -c "
import numpy as np, imuconv
r = imuconv.Registry()
assert 'euler_angles' in r.ids('state_convention') and 'midpoint_substeps' in r.ids('propagator'), r.plugins()
x = imuconv.State(p=[1, 2, 3], q_wxyz=[0.9, 0.1, -0.3, 0.2] / np.linalg.norm([0.9, 0.1, -0.3, 0.2]), v=[0.5, 0, 0])
for other in r.ids('state_convention'):
    e = np.abs(r.conversion('euler_angles', other, x) @ r.conversion(other, 'euler_angles', x) - np.eye(15)).max()
    assert e < 1e-8, (other, e)
print('python: euler_angles round trips with', len(r.ids('state_convention')) - 1, 'conventions')")
  message(STATUS "${out}")
endif()
