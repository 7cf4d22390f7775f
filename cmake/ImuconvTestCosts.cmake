# imuconv_seed_test_costs(<tree>)
# Gives a fresh build tree ctest's record of how long the long tests take, so that `ctest -j2`
# starts them first. ctest orders tests by their cost (Testing/Temporary/CTestCostData.txt,
# written after every run) and, on a tree that has never run, in the order they are listed: a
# 280 s test listed late, or the five 60 s fuzzers listed last, then finish alone on one core
# while the other is idle. The seed is cmake/test-costs/<tree>.txt (release, sanitized,
# aarch64): each test that took 2 s or more in the last full run of that tree, one line
# "name runs seconds" in ctest's own format. It is copied only into a tree that has no record:
# after its first run ctest keeps its own, measured there. A name the seed lists that no longer
# exists is ignored by ctest; a new long test only runs in listed order until it is added.
function(imuconv_seed_test_costs tree)
  set(seed ${PROJECT_SOURCE_DIR}/cmake/test-costs/${tree}.txt)
  set(record ${PROJECT_BINARY_DIR}/Testing/Temporary/CTestCostData.txt)
  if(EXISTS ${seed} AND NOT EXISTS ${record})
    file(READ ${seed} costs)
    # ctest's file ends its cost lines with "---", then the tests that failed last time (none).
    file(WRITE ${record} "${costs}---\n")
  endif()
endfunction()
