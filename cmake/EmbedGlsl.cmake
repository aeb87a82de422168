# GLSL kept as .glsl files (read, highlighted and diffed as GLSL) and compiled into the code:
# sightline_embed_glsl(<target> <file>...) turns each file, at build time, into the header
# <target's binary dir>/glsl/<file name>.h, which holds the text as
#     namespace sightline::glsl { inline constexpr char <identifier>[] = ...; }
# the identifier being the file's name with every character that is not a letter, a digit or an
# underscore made an underscore ("bitmask_exact.frag" -> bitmask_exact_frag). Sources include it
# as "glsl/<file name>.h". Editing a .glsl file rebuilds what includes it.
set(SIGHTLINE_EMBED_GLSL_SCRIPT ${CMAKE_CURRENT_LIST_DIR}/EmbedGlslFile.cmake)

function(sightline_embed_glsl target)
  foreach(file IN LISTS ARGN)
    get_filename_component(name ${file} NAME)
    string(MAKE_C_IDENTIFIER ${name} identifier)
    set(input ${CMAKE_CURRENT_SOURCE_DIR}/${file})
    set(output ${CMAKE_CURRENT_BINARY_DIR}/glsl/${name}.h)
    add_custom_command(OUTPUT ${output}
      COMMAND ${CMAKE_COMMAND} -DINPUT=${input} -DOUTPUT=${output} -DIDENTIFIER=${identifier} -P ${SIGHTLINE_EMBED_GLSL_SCRIPT}
      DEPENDS ${input} ${SIGHTLINE_EMBED_GLSL_SCRIPT}
      COMMENT "Embedding ${file}"
      VERBATIM)
    target_sources(${target} PRIVATE ${output})
  endforeach()
  target_include_directories(${target} PRIVATE ${CMAKE_CURRENT_BINARY_DIR})
endfunction()
