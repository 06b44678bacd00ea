# `cmake --install` and the vx CMake package: static libraries, headers, vxConfig.cmake,
# vxConfigVersion.cmake and the exported targets, so that
#   find_package(vx CONFIG REQUIRED [COMPONENTS world engine render ...])
#   target_link_libraries(app PRIVATE vx::vx)     # or vx::world, vx::engine, vx::render, ...
# works from any prefix. Installed files name no path of this machine: targets use
# $<INSTALL_INTERFACE:...> and dependencies are found again by vxConfig.cmake.
#
# Include paths: vx::vx gives include/ alone, for <vx/vx.h> (the facade includes only glm and
# vx/*.h); it links the components but takes none of their include paths ($<LINK_ONLY:...>,
# VxTargets.cmake), so a game's own "world/chunk.h" is never shadowed by vx's. vx::world,
# vx::store, vx::render, vx::engine and vx::vdb, for who uses the internals, give
# include/vx/internal as well.
#
# Layout under the prefix:
#   include/vx/...           the facade (<vx/vx.h>, when the source tree has include/vx)
#   include/vx/internal/...  the headers of the component libraries, by their source paths
#                            ("world/world.h", "engine/job_system.h", "render/renderer.h"):
#                            on the include path of the component targets only
#   lib/libvx_*.a            the static libraries
#   lib/cmake/vx/            the package files
#   bin/vx                   the CLI (when built)
include(CMakePackageConfigHelpers)

set(VX_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/vx)
set(VX_INTERNAL_INCLUDEDIR ${CMAKE_INSTALL_INCLUDEDIR}/vx/internal)
get_property(VX_COMPONENTS GLOBAL PROPERTY VX_COMPONENTS)

# The internal headers include <vx/result.h> and the like: every component gives include/ too.
foreach(component IN LISTS VX_COMPONENTS)
  target_include_directories(vx_${component} PUBLIC $<INSTALL_INTERFACE:${VX_INTERNAL_INCLUDEDIR}>
                                                    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
endforeach()
# <vx/vx.h> (implemented by vx_engine), and nothing else: the components are linked only.
target_include_directories(vx_all INTERFACE $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)

# vx_vdb goes to its own export set (vxVdbTargets.cmake), loaded only for COMPONENTS vdb: it
# names OpenVDB::openvdb, which only that component finds.
set(VX_INSTALL_TARGETS vx_volk vx_stb_write vx_all)
foreach(component IN LISTS VX_COMPONENTS)
  if(NOT component STREQUAL "vdb")
    list(APPEND VX_INSTALL_TARGETS vx_${component})
  endif()
endforeach()
install(TARGETS ${VX_INSTALL_TARGETS} EXPORT vxTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
if(VX_WITH_OPENVDB)
  install(TARGETS vx_vdb EXPORT vxVdbTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
endif()
if(VX_BUILD_TOOLS)
  install(TARGETS vx RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()

# Headers. The facade directory as a whole; the component headers by source path. Left out: the
# test oracles and measurement code (vx_mesh_reference and vx_vdb_reference are not installed), the Vulkan-facing internals of render/ (only
# renderer.h and device_probe.h are its interface), vdb/ unless vx_vdb was built.
if(EXISTS ${PROJECT_SOURCE_DIR}/include/vx)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/vx DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
          FILES_MATCHING PATTERN "*.h" PATTERN "*.hpp")
endif()
set(vdb_exclude "")
if(NOT VX_WITH_OPENVDB)
  set(vdb_exclude PATTERN vdb EXCLUDE)
endif()
install(DIRECTORY ${PROJECT_SOURCE_DIR}/world DESTINATION ${VX_INTERNAL_INCLUDEDIR}
        FILES_MATCHING PATTERN "*.h"
        PATTERN reference_meshers.h EXCLUDE PATTERN vdb_accuracy.h EXCLUDE PATTERN vdb_analytic.h EXCLUDE
        PATTERN pg_wire.h EXCLUDE # libpq's types: the PostgreSQL store's .cpp files only.
        ${vdb_exclude})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/engine DESTINATION ${VX_INTERNAL_INCLUDEDIR}
        FILES_MATCHING PATTERN "*.h")
install(FILES ${PROJECT_SOURCE_DIR}/render/renderer.h ${PROJECT_SOURCE_DIR}/render/device_probe.h
        DESTINATION ${VX_INTERNAL_INCLUDEDIR}/render)

# The package.
install(EXPORT vxTargets NAMESPACE vx:: FILE vxTargets.cmake DESTINATION ${VX_INSTALL_CMAKEDIR})
if(VX_WITH_OPENVDB)
  install(EXPORT vxVdbTargets NAMESPACE vx:: FILE vxVdbTargets.cmake DESTINATION ${VX_INSTALL_CMAKEDIR})
endif()
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/vxConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/vxConfig.cmake
                              INSTALL_DESTINATION ${VX_INSTALL_CMAKEDIR}
                              NO_SET_AND_CHECK_MACRO)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/vxConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMajorVersion)
install(FILES ${PROJECT_BINARY_DIR}/vxConfig.cmake ${PROJECT_BINARY_DIR}/vxConfigVersion.cmake
              ${PROJECT_SOURCE_DIR}/cmake/VxOpenVDB.cmake
        DESTINATION ${VX_INSTALL_CMAKEDIR})
