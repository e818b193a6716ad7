# Which optional parts this tree builds, said once at the end of configuration.
#
# A part that an option switches off is a choice. A part whose option asks for it but whose
# packages are missing is left out with a STATUS line, so that a user's build still works,
# except when the environment has FRNN_STRICT=1 (CI sets it): then it is an error, so that no
# part, and none of its tests, can vanish without anyone noticing.
function(frnn_part_built name)
  set_property(GLOBAL APPEND PROPERTY FRNN_PARTS "${name}: built")
endfunction()

function(frnn_part_off name option)
  set_property(GLOBAL APPEND PROPERTY FRNN_PARTS "${name}: off (${option})")
endfunction()

function(frnn_part_missing name why)
  if("$ENV{FRNN_STRICT}" STREQUAL "1")
    message(FATAL_ERROR "frnn: ${name} cannot be built: ${why}. FRNN_STRICT=1 requires every "
                        "part this tree enables; install what is missing (scripts/setup) or "
                        "switch the part off with its option.")
  endif()
  message(STATUS "frnn: ${name} left out: ${why}")
  set_property(GLOBAL APPEND PROPERTY FRNN_PARTS "${name}: LEFT OUT (${why})")
endfunction()

function(frnn_print_parts)
  get_property(parts GLOBAL PROPERTY FRNN_PARTS)
  set(strict "")
  if("$ENV{FRNN_STRICT}" STREQUAL "1")
    set(strict " (FRNN_STRICT=1)")
  endif()
  message(STATUS "frnn ${PROJECT_VERSION}, the parts of this tree${strict}:")
  foreach(part IN LISTS parts)
    message(STATUS "  ${part}")
  endforeach()
endfunction()
