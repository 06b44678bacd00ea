# The public target names. Component libraries keep their vx_* names in this build and are
# exported as vx::<component> (EXPORT_NAME); build-tree ALIAS targets give the same names here,
# so a project that adds vx with add_subdirectory() links the same names as one that uses
# find_package(vx). vx::vx is everything that was built.

set(VX_COMPONENTS world store render engine)
if(VX_WITH_OPENVDB)
  list(APPEND VX_COMPONENTS vdb)
endif()
foreach(component IN LISTS VX_COMPONENTS)
  set_target_properties(vx_${component} PROPERTIES EXPORT_NAME ${component})
  add_library(vx::${component} ALIAS vx_${component})
  # <vx/vx.h> uses std::span and more: a consumer compiles as C++20 without setting a standard.
  target_compile_features(vx_${component} PUBLIC cxx_std_20)
endforeach()
# Linked PRIVATE by vx_render; exported only because static libraries carry their link deps.
set_target_properties(vx_volk PROPERTIES EXPORT_NAME volk)
set_target_properties(vx_stb_write PROPERTIES EXPORT_NAME stb_write)

# `vx` names the CLI executable in this build, so the umbrella target is vx_all, exported as vx.
add_library(vx_all INTERFACE)
set_target_properties(vx_all PROPERTIES EXPORT_NAME vx)
target_compile_features(vx_all INTERFACE cxx_std_20)
# Installed, vx::vx compiles a game against the facade alone (include/, VxInstall.cmake, and glm,
# which the facade includes): the components are linked only, so their include/vx/internal, where
# "world/chunk.h" and the like live, cannot shadow a game's own headers of those names. vx::world,
# vx::engine... keep it for who links them. In a build tree (add_subdirectory) vx::vx still links
# the components whole, as it always did.
# vdb is an optional component of the installed package (it needs OpenVDB): the installed vx::vx
# gains vx::vdb only when find_package(vx COMPONENTS vdb) asks for it (vxConfig.cmake.in).
target_link_libraries(vx_all INTERFACE $<INSTALL_INTERFACE:glm::glm>)
foreach(component IN LISTS VX_COMPONENTS)
  if(component STREQUAL "vdb")
    target_link_libraries(vx_all INTERFACE $<BUILD_INTERFACE:vx_${component}>)
  else()
    target_link_libraries(vx_all INTERFACE $<BUILD_INTERFACE:vx_${component}>
                                           $<INSTALL_INTERFACE:$<LINK_ONLY:vx_${component}>>)
  endif()
endforeach()
add_library(vx::vx ALIAS vx_all)
set_property(GLOBAL PROPERTY VX_COMPONENTS "${VX_COMPONENTS}")
