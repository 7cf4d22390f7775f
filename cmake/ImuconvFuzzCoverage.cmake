# imuconv_fuzz_coverage(<target>...)
# Compiles every library the given targets link, directly or through other libraries, with
# libFuzzer's coverage instrumentation (-fsanitize=fuzzer-no-link), and nothing else: the fuzz
# executables (tests/fuzz) need the edges of the readers they reach to steer their inputs, but
# the test executables, the command line and the plugins (loaded at run time, numeric code whose
# branches do not depend on the input's structure) gain nothing from it and compiled about 15 %
# slower with it. Call it after the libraries are defined (tests/ is added after them).
# Imported targets (Eigen, Boost, GoogleTest) are left alone: they are not compiled here.
function(imuconv_fuzz_coverage)
  set(pending ${ARGN})
  set(seen "")
  while(pending)
    list(POP_FRONT pending item)
    # $<LINK_ONLY:x> (a static library's private dependencies) names x all the same.
    string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" item "${item}")
    if(NOT TARGET "${item}")
      continue()
    endif()
    get_target_property(aliased "${item}" ALIASED_TARGET)
    if(aliased)
      set(item "${aliased}")
    endif()
    if(item IN_LIST seen)
      continue()
    endif()
    list(APPEND seen "${item}")
    get_target_property(imported "${item}" IMPORTED)
    if(imported)
      continue()
    endif()
    get_target_property(type "${item}" TYPE)
    if(type MATCHES "^(STATIC|SHARED|OBJECT)_LIBRARY$")
      target_compile_options("${item}" PRIVATE -fsanitize=fuzzer-no-link)
    endif()
    foreach(property LINK_LIBRARIES INTERFACE_LINK_LIBRARIES)
      get_target_property(deps "${item}" ${property})
      if(deps)
        list(APPEND pending ${deps})
      endif()
    endforeach()
  endwhile()
endfunction()
