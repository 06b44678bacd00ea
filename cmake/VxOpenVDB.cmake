# vx_find_openvdb_module_dir(<out-var>): the folder that holds OpenVDB's FindOpenVDB.cmake.
# OpenVDB 10 (Debian) ships no config file, only that module, under lib/<multiarch>/cmake/OpenVDB;
# other layouts use lib/cmake/OpenVDB or lib64/cmake/OpenVDB. Searched under CMAKE_PREFIX_PATH and
# the system prefixes, so no machine's path is written down. Used by the build (world/vdb) and by
# the installed vxConfig.cmake. Empty when not found.
function(vx_find_openvdb_module_dir out)
  set(dirs "")
  foreach(prefix IN LISTS CMAKE_PREFIX_PATH CMAKE_SYSTEM_PREFIX_PATH)
    foreach(lib IN ITEMS lib/${CMAKE_LIBRARY_ARCHITECTURE} lib lib64)
      list(APPEND dirs ${prefix}/${lib}/cmake/OpenVDB)
    endforeach()
  endforeach()
  find_path(VX_OPENVDB_MODULE_DIR FindOpenVDB.cmake PATHS ${dirs} NO_DEFAULT_PATH)
  if(VX_OPENVDB_MODULE_DIR)
    set(${out} ${VX_OPENVDB_MODULE_DIR} PARENT_SCOPE)
  else()
    set(${out} "" PARENT_SCOPE)
  endif()
endfunction()
