# The layering of DESIGN.md §1, checked on every include line (run by ctest as `Layering`):
#   app -> ui -> report, project -> lighting, plugins -> visibility (and data/ beside them).
# A library may include only the libraries below it; nothing outside app/ includes app/;
# visibility/, lighting/ and project/ include no Qt. Usage: cmake -DROOT=<source dir> -P CheckLayering.cmake
cmake_minimum_required(VERSION 3.25)
if(NOT ROOT)
  message(FATAL_ERROR "pass -DROOT=<source dir>")
endif()

# What each library's files may not include, by the first folder of the include's path.
set(forbidden_visibility lighting plugins project report ui app bench cli)
set(forbidden_lighting plugins project report ui app bench cli)
set(forbidden_plugins lighting project report ui app bench cli)
set(forbidden_project report ui app bench cli)
set(forbidden_report project ui app bench cli)
set(forbidden_data ui app bench cli report)
set(forbidden_ui app bench cli)
set(no_qt visibility lighting project plugins)

set(failures "")
foreach(library visibility lighting plugins project report data ui)
  file(GLOB_RECURSE files "${ROOT}/${library}/*.h" "${ROOT}/${library}/*.cpp")
  foreach(file ${files})
    file(STRINGS "${file}" includes REGEX "^[ \t]*#[ \t]*include[ \t]*[<\"]")
    file(RELATIVE_PATH shown "${ROOT}" "${file}")
    foreach(line ${includes})
      string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]*[<\"]([^>\"]*)[>\"].*" "\\1" path "${line}")
      string(REGEX MATCH "^[^/]+" first "${path}")
      if(path MATCHES "/" AND first IN_LIST forbidden_${library})
        list(APPEND failures "${shown}: includes ${path} (${library}/ may not include ${first}/)")
      endif()
      if(library IN_LIST no_qt AND path MATCHES "^Q[A-Za-z]*$|^Qt[A-Za-z]*/")
        list(APPEND failures "${shown}: includes Qt (${path}); ${library}/ knows no Qt")
      endif()
    endforeach()
  endforeach()
endforeach()

if(failures)
  list(JOIN failures "\n" text)
  message(FATAL_ERROR "layering broken (DESIGN.md §1):\n${text}")
endif()
message(STATUS "layering holds")
