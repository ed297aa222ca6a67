# fixed.standalone_headers: fixed/ includes nothing from reference/ (issue 29).
#   cmake -DFIXED_DIR=<src>/fixed -DCXX=<compiler> -DINCLUDE_DIRS=<a|b|...> -P standalone_headers.cmake
# Fails when
#   1. an include directory of lockstep::fixed (INCLUDE_DIRS, the target's
#      INTERFACE_INCLUDE_DIRECTORIES at build time) lies outside fixed/;
#   2. a CMake file under fixed/ names reference/ outside a comment;
#   3. a header or source under fixed/ does not compile (syntax only) with
#      fixed/include as the one project include directory, i.e. it includes a
#      header that lives elsewhere (reference/include, compare/include, ...).
if(NOT FIXED_DIR OR NOT CXX)
  message(FATAL_ERROR "usage: cmake -DFIXED_DIR=... -DCXX=... [-DINCLUDE_DIRS=a|b] -P standalone_headers.cmake")
endif()
get_filename_component(FIXED_DIR "${FIXED_DIR}" REALPATH)
set(failures "")

# 1. The target's include directories.
if(INCLUDE_DIRS)
  string(REPLACE "|" ";" dirs "${INCLUDE_DIRS}")
  foreach(d IN LISTS dirs)
    if(d STREQUAL "")
      continue()
    endif()
    get_filename_component(real "${d}" REALPATH)
    cmake_path(IS_PREFIX FIXED_DIR "${real}" NORMALIZE inside)
    if(NOT inside)
      list(APPEND failures "lockstep::fixed has the include directory ${d}, outside ${FIXED_DIR}")
    endif()
  endforeach()
endif()

# 2. CMake files under fixed/.
file(GLOB_RECURSE cmake_files "${FIXED_DIR}/CMakeLists.txt" "${FIXED_DIR}/*.cmake")
foreach(f IN LISTS cmake_files)
  file(STRINGS "${f}" lines)
  foreach(line IN LISTS lines)
    string(REGEX REPLACE "#.*$" "" code "${line}")
    if(code MATCHES "reference")
      list(APPEND failures "${f} names reference/: ${line}")
    endif()
  endforeach()
endforeach()

# 3. Every header and source, compiled with fixed/include alone.
file(GLOB_RECURSE sources "${FIXED_DIR}/*.hpp" "${FIXED_DIR}/*.cpp")
list(SORT sources)
if(NOT sources)
  list(APPEND failures "no headers or sources found under ${FIXED_DIR}")
endif()
foreach(f IN LISTS sources)
  execute_process(
    COMMAND "${CXX}" -std=c++20 -fsyntax-only -x c++ -I "${FIXED_DIR}/include" "${f}"
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    list(APPEND failures "${f} does not compile with only fixed/include on the include path:\n${err}")
  else()
    message(STATUS "ok: ${f}")
  endif()
endforeach()

if(failures)
  list(JOIN failures "\n" text)
  message(FATAL_ERROR "fixed/ is not standalone:\n${text}")
endif()
list(LENGTH sources n)
message(STATUS "fixed/ is standalone: ${n} files compile with only fixed/include")
