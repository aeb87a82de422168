# One .glsl file as a C++ header (cmake/EmbedGlsl.cmake): cmake -DINPUT= -DOUTPUT= -DIDENTIFIER= -P this.
file(READ ${INPUT} text)
string(FIND "${text}" ")glsl\"" clash)
if(NOT clash EQUAL -1)
  message(FATAL_ERROR "${INPUT} contains the raw string's delimiter )glsl\"")
endif()
file(WRITE ${OUTPUT}.tmp "// Generated from ${INPUT} (cmake/EmbedGlsl.cmake): edit the .glsl file.\n#pragma once\n\nnamespace sightline::glsl {\ninline constexpr char ${IDENTIFIER}[] = R\"glsl(${text})glsl\";\n}\n")
file(RENAME ${OUTPUT}.tmp ${OUTPUT})
