# cmake -DGGK_SOURCE_DIR=<repository> -P cmake/SourceListCheck.cmake
#
# The source lists are written by hand, a list per folder's CMakeLists.txt
# (CONTRIBUTING.md, "Source lists"): CMake's own advice against globbing sources
# is that a new file is not seen until CMake is re-run. What a hand list can do
# wrong is forget a file: a source never compiled, a test never run. This check
# (the ctest entry SourceLists.EveryFileIsListed) fails naming each C++ source
# (.cpp) of the compiled folders that no CMakeLists.txt at or above its folder
# names by its path relative to that CMakeLists.txt's folder.
cmake_minimum_required(VERSION 3.22)

if(NOT GGK_SOURCE_DIR)
  message(FATAL_ERROR "SourceListCheck.cmake: pass -DGGK_SOURCE_DIR=<repository>")
endif()

set(compiled_folders bench engine fuzz kernels python/module sims tests)
set(unlisted "")
set(checked 0)
foreach(folder IN LISTS compiled_folders)
  file(GLOB_RECURSE sources RELATIVE "${GGK_SOURCE_DIR}" "${GGK_SOURCE_DIR}/${folder}/*.cpp")
  foreach(source IN LISTS sources)
    math(EXPR checked "${checked} + 1")
    set(listed FALSE)
    get_filename_component(directory "${source}" DIRECTORY)
    # Walk up from the source's folder to the repository's root.
    while(TRUE)
      set(lists_file "${GGK_SOURCE_DIR}/${directory}/CMakeLists.txt")
      if(directory STREQUAL "")
        set(lists_file "${GGK_SOURCE_DIR}/CMakeLists.txt")
      endif()
      if(EXISTS "${lists_file}")
        if(directory STREQUAL "")
          set(relative "${source}")
        else()
          file(RELATIVE_PATH relative "${GGK_SOURCE_DIR}/${directory}" "${GGK_SOURCE_DIR}/${source}")
        endif()
        file(READ "${lists_file}" text)
        # The name as a word of the list: after white space, '(' or '"' (or a
        # ${...}/ prefix), and ending there.
        string(REGEX REPLACE "([][+.*?^$(){}|\\\\])" "\\\\\\1" pattern "${relative}")
        if(text MATCHES "(^|[ \t\r\n(\"/])${pattern}([ \t\r\n)\"]|$)")
          set(listed TRUE)
          break()
        endif()
      endif()
      if(directory STREQUAL "")
        break()
      endif()
      get_filename_component(directory "${directory}" DIRECTORY)
    endwhile()
    if(NOT listed)
      list(APPEND unlisted "${source}")
    endif()
  endforeach()
endforeach()

if(unlisted)
  list(JOIN unlisted "\n  " text)
  message(FATAL_ERROR "no CMakeLists.txt lists these sources (add each to its folder's list; "
                      "CONTRIBUTING.md, \"Source lists\"):\n  ${text}")
endif()
message(STATUS "SourceListCheck: all ${checked} C++ sources are listed")
