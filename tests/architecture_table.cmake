# ctest `architecture_table`: the module table in docs/architecture.md (between the markers
# <!-- modules:begin --> and <!-- modules:end -->) must equal the one generated from the CMake
# targets at configure time (TABLE). Regenerate the page's copy with tools/update-docs.sh.
file(READ ${PAGE} page)
file(READ ${TABLE} table)
string(FIND "${page}" "<!-- modules:begin -->\n" a)
string(FIND "${page}" "<!-- modules:end -->" b)
if(a EQUAL -1 OR b EQUAL -1)
  message(FATAL_ERROR "${PAGE}: the markers <!-- modules:begin --> / <!-- modules:end --> are missing")
endif()
math(EXPR a "${a} + 23")
math(EXPR len "${b} - ${a}")
string(SUBSTRING "${page}" ${a} ${len} copy)
if(NOT copy STREQUAL table)
  message(FATAL_ERROR "${PAGE}: the module table differs from the targets' (${TABLE}); run tools/update-docs.sh")
endif()
message(STATUS "the module table of ${PAGE} matches the targets")
