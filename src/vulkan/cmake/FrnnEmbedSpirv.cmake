# frnn_embed_spirv(<target> SOURCE <file.comp> SYMBOL <c_name> [DEFINES <NAME=VALUE>...]
#                  [INCLUDE_DIRS <dir>...])
#
# Compiles a GLSL compute shader to SPIR-V with glslc at build time and adds to <target> a
# generated C++ file defining
#     extern const std::uint32_t <c_name>[];  extern const std::size_t <c_name>_words;
# in namespace frnn::spirv. Include dependencies are tracked through glslc's depfile.
# Uses FRNN_GLSLC, the glslc executable (found on the PATH when not set).
set(FRNN_EMBED_SPIRV_SCRIPT ${CMAKE_CURRENT_LIST_DIR}/spirv_to_cpp.cmake)
if(NOT FRNN_GLSLC)
  find_program(FRNN_GLSLC glslc)
endif()

function(frnn_embed_spirv target)
  cmake_parse_arguments(ARG "" "SOURCE;SYMBOL" "DEFINES;INCLUDE_DIRS" ${ARGN})
  if(NOT ARG_SOURCE OR NOT ARG_SYMBOL)
    message(FATAL_ERROR "frnn_embed_spirv: SOURCE and SYMBOL are required")
  endif()
  if(NOT FRNN_GLSLC)
    message(FATAL_ERROR "frnn_embed_spirv: glslc not found (Debian package glslc)")
  endif()
  get_filename_component(source ${ARG_SOURCE} ABSOLUTE)
  set(dir ${CMAKE_CURRENT_BINARY_DIR}/spirv)
  set(spv ${dir}/${ARG_SYMBOL}.spv)
  set(cpp ${dir}/${ARG_SYMBOL}.cpp)
  set(flags -fshader-stage=compute --target-env=vulkan1.1 -O)
  foreach(d IN LISTS ARG_DEFINES)
    list(APPEND flags -D${d})
  endforeach()
  foreach(i IN LISTS ARG_INCLUDE_DIRS)
    list(APPEND flags -I${i})
  endforeach()
  add_custom_command(OUTPUT ${spv}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${dir}
    COMMAND ${FRNN_GLSLC} ${flags} -MD -MF ${spv}.d -o ${spv} ${source}
    DEPENDS ${source}
    DEPFILE ${spv}.d
    COMMENT "glslc ${ARG_SYMBOL}"
    VERBATIM)
  add_custom_command(OUTPUT ${cpp}
    COMMAND ${CMAKE_COMMAND} -DINPUT=${spv} -DOUTPUT=${cpp} -DSYMBOL=${ARG_SYMBOL}
            -P ${FRNN_EMBED_SPIRV_SCRIPT}
    DEPENDS ${spv} ${FRNN_EMBED_SPIRV_SCRIPT}
    VERBATIM)
  target_sources(${target} PRIVATE ${cpp})
endfunction()
