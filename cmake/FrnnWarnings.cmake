# frnn_warnings(target): the project's warning set, applied per target (never globally).
function(frnn_warnings target)
  target_compile_options(${target} PRIVATE
    $<$<CXX_COMPILER_ID:GNU,Clang>:-Wall -Wextra -Wpedantic -Wshadow -Wno-unknown-pragmas>)
endfunction()
