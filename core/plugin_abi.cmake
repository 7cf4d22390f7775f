# imuconv::plugin_abi: what a plugin needs to export itself (plugin_abi.h and Boost.DLL's
# alias macros), as its own small INTERFACE target, so that Boost is a dependency of the
# plugins and the registry only, not of everything that links imuconv::core.
add_library(imuconv_plugin_abi INTERFACE)
add_library(imuconv::plugin_abi ALIAS imuconv_plugin_abi)
set_target_properties(imuconv_plugin_abi PROPERTIES EXPORT_NAME plugin_abi)
target_link_libraries(imuconv_plugin_abi INTERFACE imuconv::core Boost::headers)
target_compile_definitions(imuconv_plugin_abi INTERFACE BOOST_DLL_USE_STD_FS)
if(IMUCONV_INSTALL)
  install(TARGETS imuconv_plugin_abi EXPORT imuconvTargets)
endif()
