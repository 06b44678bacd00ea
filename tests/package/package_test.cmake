# Run by ctest (tests/package/CMakeLists.txt) as `cmake -P`. Inputs: VX_BUILD_DIR, VX_SOURCE_DIR,
# VX_CONSUMER_DIR, VX_GENERATOR, VX_BUILD_TYPE, VX_WITH_OPENVDB. Fails (FATAL_ERROR) on the first step that fails.
cmake_minimum_required(VERSION 3.25)

function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}\n${err}")
  endif()
  set(run_output "${out}" PARENT_SCOPE)
  set(run_log "${out}${err}" PARENT_SCOPE) # message() without a mode goes to stderr.
endfunction()

# A fresh directory in the system's temporary folder: outside the source and build trees.
if(DEFINED ENV{TMPDIR} AND IS_DIRECTORY "$ENV{TMPDIR}")
  set(tmp_root "$ENV{TMPDIR}")
else()
  set(tmp_root /tmp)
endif()
string(RANDOM LENGTH 8 suffix)
set(work "${tmp_root}/vx-package-test-${suffix}")
file(REMOVE_RECURSE "${work}")
file(MAKE_DIRECTORY "${work}")
set(prefix "${work}/prefix")

run("cmake --install" ${CMAKE_COMMAND} --install "${VX_BUILD_DIR}" --prefix "${prefix}")

# The package must not point back into this machine's trees: the build tree may be deleted.
file(GLOB_RECURSE installed_text "${prefix}/*.cmake" "${prefix}/*.h" "${prefix}/*.hpp")
foreach(f IN LISTS installed_text)
  file(READ "${f}" text)
  foreach(tree IN ITEMS "${VX_BUILD_DIR}" "${VX_SOURCE_DIR}")
    string(FIND "${text}" "${tree}" at)
    if(NOT at EQUAL -1)
      message(FATAL_ERROR "${f} names ${tree}")
    endif()
  endforeach()
endforeach()
# Installed headers compile without headers the package does not provide: a consumer has no
# libpq include path (pg_wire.h, which needs it, was installed once).
foreach(f IN LISTS installed_text)
  file(READ "${f}" text)
  if(text MATCHES "#include <libpq-fe.h>")
    message(FATAL_ERROR "${f} includes <libpq-fe.h>, which the package's consumers do not have")
  endif()
endforeach()
foreach(f IN ITEMS lib/cmake/vx/vxConfig.cmake lib/cmake/vx/vxConfigVersion.cmake lib/cmake/vx/vxTargets.cmake)
  if(NOT EXISTS "${prefix}/${f}")
    # GNUInstallDirs may choose lib64 or lib/<multiarch>: look for it anywhere under the prefix.
    get_filename_component(name "${f}" NAME)
    file(GLOB_RECURSE found "${prefix}/*/${name}")
    if(NOT found)
      message(FATAL_ERROR "not installed: ${name}")
    endif()
  endif()
endforeach()

if(NOT VX_BUILD_TYPE)
  set(VX_BUILD_TYPE Release)
endif()
# The clock in seconds, for the log (never a pass/fail criterion: machines differ).
function(now out)
  string(TIMESTAMP t "%s")
  set(${out} ${t} PARENT_SCOPE)
endfunction()

# 1. The newcomer's consumer: find_package(vx) and vx::vx only, no standard of its own, the
# first program of docs/embedding.md beside a game-like check. No OpenVDB may show up: not in its
# configure (Debian's FindOpenVDB prints "COMPONENT = openvdb" and Imath warnings), not linked.
file(COPY "${VX_CONSUMER_DIR}/" DESTINATION "${work}/consumer")
file(COPY "${VX_SOURCE_DIR}/docs/examples/first_program.cpp" DESTINATION "${work}/consumer")
run("consumer configure" ${CMAKE_COMMAND} -S "${work}/consumer" -B "${work}/build" -G "${VX_GENERATOR}"
    -DCMAKE_BUILD_TYPE=${VX_BUILD_TYPE} "-DCMAKE_PREFIX_PATH=${prefix}" -DCMAKE_EXPORT_COMPILE_COMMANDS=ON)
string(TOLOWER "${run_log}" configure_log)
if(configure_log MATCHES "openvdb|imath")
  message(FATAL_ERROR "find_package(vx) without COMPONENTS vdb mentions OpenVDB:\n${run_log}")
endif()
# vx::vx compiles a game against the facade alone: no include/vx/internal on the command lines of
# its sources (written at configure), where vx's "world/chunk.h" and the like would shadow the
# game's own (vx_shadow has such headers, and builds only if its own are found). The consumer of
# vx::world has it.
file(READ "${work}/build/compile_commands.json" compile_commands)
string(JSON n_commands LENGTH "${compile_commands}")
set(checked "")
math(EXPR last "${n_commands} - 1")
foreach(i RANGE ${last})
  string(JSON file GET "${compile_commands}" ${i} file)
  string(JSON command GET "${compile_commands}" ${i} command)
  get_filename_component(name "${file}" NAME)
  string(FIND "${command}" "vx/internal" at)
  if(name MATCHES "^(main|first_program|shadow)\\.cpp$" AND NOT at EQUAL -1)
    message(FATAL_ERROR "${name} links vx::vx and compiles with vx/internal on its include path:\n${command}")
  endif()
  if(name STREQUAL "advanced.cpp" AND at EQUAL -1)
    message(FATAL_ERROR "advanced.cpp links vx::world and compiles without vx/internal:\n${command}")
  endif()
  list(APPEND checked ${name})
endforeach()
foreach(name IN ITEMS main.cpp first_program.cpp shadow.cpp advanced.cpp)
  if(NOT name IN_LIST checked)
    message(FATAL_ERROR "compile_commands.json has no command for ${name}")
  endif()
endforeach()
run("consumer build" ${CMAKE_COMMAND} --build "${work}/build")
find_program(readelf readelf)
if(readelf)
  run("readelf" ${readelf} -d "${work}/build/first_program")
  if(run_output MATCHES "openvdb")
    message(FATAL_ERROR "first_program links OpenVDB:\n${run_output}")
  endif()
endif()
foreach(program IN ITEMS vx_consumer vx_shadow vx_advanced)
  run("${program} run" "${work}/build/${program}" "${work}/world.db")
  message(STATUS "${run_output}")
  if(NOT run_output MATCHES "${program}: ok")
    message(FATAL_ERROR "${program} printed no '${program}: ok':\n${run_output}")
  endif()
endforeach()
# The documented program writes my_world.db and my_world.png where it runs.
file(MAKE_DIRECTORY "${work}/first")
now(t0)
execute_process(COMMAND "${work}/build/first_program" WORKING_DIRECTORY "${work}/first"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
now(t1)
math(EXPR seconds "${t1} - ${t0}")
if(NOT rc EQUAL 0 OR NOT EXISTS "${work}/first/my_world.png")
  message(FATAL_ERROR "docs/examples/first_program failed (${rc}):\n${out}\n${err}")
endif()
message(STATUS "first_program (docs/embedding.md) ran in ${seconds} s: ${out}")

# 2. A consumer of the vdb component (when vx was built with OpenVDB).
if(VX_WITH_OPENVDB)
  file(COPY "${VX_SOURCE_DIR}/tests/package/vdb_consumer/" DESTINATION "${work}/vdb_consumer")
  run("vdb consumer configure" ${CMAKE_COMMAND} -S "${work}/vdb_consumer" -B "${work}/vdb_build"
      -G "${VX_GENERATOR}" -DCMAKE_BUILD_TYPE=${VX_BUILD_TYPE} "-DCMAKE_PREFIX_PATH=${prefix}")
  run("vdb consumer build" ${CMAKE_COMMAND} --build "${work}/vdb_build")
  run("vdb consumer run" "${work}/vdb_build/vx_vdb_consumer" "${work}/world.vdb")
  message(STATUS "${run_output}")
  if(NOT run_output MATCHES "vx_vdb_consumer: ok")
    message(FATAL_ERROR "vdb consumer printed no 'vx_vdb_consumer: ok':\n${run_output}")
  endif()
endif()
file(REMOVE_RECURSE "${work}")
