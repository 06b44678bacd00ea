# Shared build settings for vx targets. Third-party code never sees these flags.

function(vx_apply_settings target)
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
