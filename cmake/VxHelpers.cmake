# Shared build settings for vx targets. Third-party code never sees these flags.

function(vx_apply_settings target)
  set_property(TARGET ${target} PROPERTY VX_TARGET ON) # vx_assign_pchs() picks these.
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wshadow)
  if(VX_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
  if(VX_SANITIZE)
    target_compile_options(${target} PRIVATE -fsanitize=${VX_SANITIZE} -fno-omit-frame-pointer
                                             -fno-sanitize-recover=all)
    target_link_options(${target} PRIVATE -fsanitize=${VX_SANITIZE})
  endif()
endfunction()

# vx_add_library(name SOURCES...): a static library with vx warnings applied PRIVATE.
function(vx_add_library name)
  add_library(${name} STATIC ${ARGN})
  vx_apply_settings(${name})
endfunction()

function(vx_add_executable name)
  add_executable(${name} ${ARGN})
  vx_apply_settings(${name})
endfunction()

# Precompiled headers (option VX_PCH). Standard and third-party headers only, never ours: each
# set is compiled once, by an object library of its own with the flags of every vx target, and
# the targets reuse it (REUSE_FROM; -Winvalid-pch, an error under VX_WERROR, says if one cannot).
# A file that forgets one of these #includes still compiles with them: -DVX_PCH=OFF finds it.
set(VX_PCH_STD_HEADERS
  <algorithm> <array> <atomic> <chrono> <cmath> <cstdint> <cstdio> <cstdlib> <cstring>
  <filesystem> <functional> <map> <memory> <mutex> <optional> <random> <set> <span> <string>
  <string_view> <thread> <unordered_map> <unordered_set> <utility> <vector> <glm/glm.hpp>)

# vx_add_pch(name HEADERS <header>... [LINK <target>...]): the object library `name` that compiles
# these headers into a precompiled header; LINK gives it their include folders and definitions.
function(vx_add_pch name)
  cmake_parse_arguments(arg "" "" "HEADERS;LINK" ${ARGN})
  if(NOT VX_PCH)
    return()
  endif()
  set(stub ${CMAKE_CURRENT_BINARY_DIR}/${name}.cpp)
  file(CONFIGURE OUTPUT ${stub} CONTENT "// Built for its precompiled header (cmake/VxHelpers.cmake).\n")
  add_library(${name} OBJECT ${stub})
  vx_apply_settings(${name})
  target_link_libraries(${name} PRIVATE ${arg_LINK})
  target_precompile_headers(${name} PRIVATE ${arg_HEADERS})
endfunction()

# vx_use_pch(pch target...): these targets compile with the precompiled header of vx_add_pch(pch).
function(vx_use_pch pch)
  if(VX_PCH)
    foreach(target IN LISTS ARGN)
      target_precompile_headers(${target} REUSE_FROM ${pch})
    endforeach()
  endif()
endfunction()

# vx_assign_pchs(): every vx target below the top folder that has no precompiled header of its own
# reuses vx_pch_tests if it links GoogleTest, else vx_pch_std. Called once, after the last target.
function(vx_assign_pchs)
  if(NOT VX_PCH)
    return()
  endif()
  set(dirs ${PROJECT_SOURCE_DIR})
  while(dirs)
    list(POP_FRONT dirs dir)
    get_property(subdirs DIRECTORY ${dir} PROPERTY SUBDIRECTORIES)
    list(APPEND dirs ${subdirs})
    get_property(targets DIRECTORY ${dir} PROPERTY BUILDSYSTEM_TARGETS)
    foreach(target IN LISTS targets)
      get_target_property(is_vx ${target} VX_TARGET)
      get_target_property(own ${target} PRECOMPILE_HEADERS)
      if(NOT is_vx OR own)
        continue()
      endif()
      get_target_property(libs ${target} LINK_LIBRARIES)
      if(TARGET vx_pch_tests AND libs MATCHES "GTest::")
        vx_use_pch(vx_pch_tests ${target})
      else()
        vx_use_pch(vx_pch_std ${target})
      endif()
    endforeach()
  endwhile()
endfunction()
