# Warnings apply to idto's own targets only, never to consumers.
function(idto_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow)
  if(IDTO_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()
