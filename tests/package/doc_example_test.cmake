# Run by ctest as `cmake -P` with VX_SOURCE_DIR: the program docs/embedding.md shows under "A
# complete program" is docs/examples/first_program.cpp, character for character (the package test
# builds and runs that file, so the doc shows code that works).
cmake_minimum_required(VERSION 3.25)
file(READ "${VX_SOURCE_DIR}/docs/embedding.md" doc)
file(READ "${VX_SOURCE_DIR}/docs/examples/first_program.cpp" program)
string(FIND "${doc}" "## A complete program" section)
if(section EQUAL -1)
  message(FATAL_ERROR "docs/embedding.md has no '## A complete program' section")
endif()
string(SUBSTRING "${doc}" ${section} -1 doc)
string(FIND "${doc}" "```cpp\n" open)
if(open EQUAL -1)
  message(FATAL_ERROR "docs/embedding.md: no ```cpp block under 'A complete program'")
endif()
math(EXPR open "${open} + 7")
string(SUBSTRING "${doc}" ${open} -1 doc)
string(FIND "${doc}" "```" close)
string(SUBSTRING "${doc}" 0 ${close} shown)
if(NOT shown STREQUAL program)
  message(FATAL_ERROR "docs/embedding.md's first program differs from docs/examples/first_program.cpp: "
                      "copy the file into the doc")
endif()
