# Project targets call envshadow_target_defaults(); third-party code (glad, ImGui backends) does not.
function(envshadow_target_defaults target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor)
  if(ENVSHADOW_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
  if(ENVSHADOW_SANITIZE AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    # GCC's instrumentation makes -Wmaybe-uninitialized report false positives (in libstdc++'s
    # <regex>, for one); GCC's manual says as much for -fsanitize=address.
    target_compile_options(${target} PRIVATE -Wno-maybe-uninitialized)
  endif()
endfunction()

if(ENVSHADOW_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()
