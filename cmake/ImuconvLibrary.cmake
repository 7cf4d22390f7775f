# imuconv_shared_library(<target> <export name> <source>...)
# One of the package's public shared libraries: <target> built from the sources, its alias
# imuconv::<export name> (the name consumers link, also in the export set), the file name
# lib<target>.so versioned with the project, its include/ folder of public headers for the build
# and the install, IMUCONV_BUILDING_LIBRARY (export.h: the library's own side of IMUCONV_API)
# and its installation (imuconv_install_library). What it links and any further definitions
# stay with the caller.
function(imuconv_shared_library target export_name)
  add_library(${target} SHARED ${ARGN})
  add_library(imuconv::${export_name} ALIAS ${target})
  set_target_properties(${target} PROPERTIES OUTPUT_NAME ${target} EXPORT_NAME ${export_name}
    VERSION ${PROJECT_VERSION} SOVERSION ${PROJECT_VERSION_MAJOR})
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_compile_definitions(${target} PRIVATE IMUCONV_BUILDING_LIBRARY)
  imuconv_install_library(${target})
endfunction()
