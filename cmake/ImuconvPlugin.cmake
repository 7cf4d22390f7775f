# imuconv_add_plugin(<id> <source>...)
# Builds one imuconv plugin as a MODULE library named imuconv_plugin_<id>.so, with hidden
# visibility (only the Boost.DLL aliases are exported). Inside the imuconv build it lands in
# the build tree's plugin directory; in a consumer project, next to its other outputs.
function(imuconv_add_plugin id)
  set(target imuconv_plugin_${id})
  add_library(${target} MODULE ${ARGN})
  target_link_libraries(${target} PRIVATE imuconv::plugin_abi)
  set_target_properties(${target} PROPERTIES
    PREFIX ""
    OUTPUT_NAME imuconv_plugin_${id}
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON)
  if(DEFINED IMUCONV_PLUGIN_BUILD_DIR)
    set_target_properties(${target} PROPERTIES LIBRARY_OUTPUT_DIRECTORY ${IMUCONV_PLUGIN_BUILD_DIR})
    if(IMUCONV_INSTALL)
      install(TARGETS ${target} LIBRARY DESTINATION ${IMUCONV_PLUGIN_INSTALL_DIR})
    endif()
  endif()
endfunction()
