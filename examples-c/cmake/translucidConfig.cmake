# CMake package config for translucid: install as <prefix>/lib/cmake/translucid/translucidConfig.cmake
# (with include/translucid.h in <prefix>/include and libtranslucid_ffi in <prefix>/lib), then
#   find_package(translucid CONFIG REQUIRED)
#   target_link_libraries(my_engine PRIVATE translucid::translucid)
# Set translucid_USE_STATIC=ON before find_package to link libtranslucid_ffi.a instead.
# translucid.h includes <vulkan/vulkan.h>: the Vulkan headers come with the target.
include(CMakeFindDependencyMacro)
find_dependency(Vulkan)

get_filename_component(_translucid_prefix "${CMAKE_CURRENT_LIST_DIR}/../../.." ABSOLUTE)

if(translucid_USE_STATIC)
    find_library(translucid_LIBRARY NAMES libtranslucid_ffi.a
                 PATHS "${_translucid_prefix}/lib" NO_DEFAULT_PATH)
    set(_translucid_kind STATIC)
else()
    find_library(translucid_LIBRARY NAMES translucid_ffi
                 PATHS "${_translucid_prefix}/lib" NO_DEFAULT_PATH)
    set(_translucid_kind SHARED)
endif()
find_path(translucid_INCLUDE_DIR translucid.h
          PATHS "${_translucid_prefix}/include" NO_DEFAULT_PATH)

if(translucid_LIBRARY AND translucid_INCLUDE_DIR AND NOT TARGET translucid::translucid)
    add_library(translucid::translucid ${_translucid_kind} IMPORTED)
    set_target_properties(translucid::translucid PROPERTIES
        IMPORTED_LOCATION "${translucid_LIBRARY}"
        INTERFACE_INCLUDE_DIRECTORIES "${translucid_INCLUDE_DIR}"
        INTERFACE_LINK_LIBRARIES Vulkan::Headers)
    if(translucid_USE_STATIC)
        set_property(TARGET translucid::translucid APPEND PROPERTY
                     INTERFACE_LINK_LIBRARIES m dl pthread)
    endif()
endif()

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(translucid REQUIRED_VARS translucid_LIBRARY translucid_INCLUDE_DIR)
