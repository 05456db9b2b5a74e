# cmake -DGGK_SOURCE_DIR=<repository> -P cmake/IncludeRulesCheck.cmake
#
# Which way the includes point (engine/README.md, "Who may include whom";
# CONTRIBUTING.md): each room's sources may include the project's headers under
# the prefixes listed for it here, and no others. The ctest entry
# IncludeRules.EveryRoomIncludesWhatItMay fails naming each include that breaks
# them (file:line and the header). A rule changed here changes the whiteboard:
# keep engine/README.md's picture the same.
cmake_minimum_required(VERSION 3.22)

if(NOT GGK_SOURCE_DIR)
  message(FATAL_ERROR "IncludeRulesCheck.cmake: pass -DGGK_SOURCE_DIR=<repository>")
endif()

# room (a folder, or one file) -> the include prefixes it may use besides its own folder.
set(rooms
  kernels
  sims
  engine/hdf5
  engine/job
  engine/tasks
  engine/store
  engine/run
  engine/cli
  engine/main.cpp)
set(allowed_kernels "")
set(allowed_sims "kernels/")
set(allowed_engine/hdf5 "engine/single_quoted.hpp")
set(allowed_engine/job "engine/single_quoted.hpp;kernels/")
set(allowed_engine/tasks "engine/job/;engine/single_quoted.hpp;sims/;kernels/")
# The store knows no task: of tasks/ only the record a task returns and the
# vocabulary it includes (what a task declares of its metrics and datasets).
set(allowed_engine/store
    "engine/job/;engine/hdf5/;engine/single_quoted.hpp;kernels/;engine/tasks/run_record.hpp;engine/tasks/metric_spec.hpp;engine/tasks/dataset_spec.hpp")
set(allowed_engine/run
    "engine/job/;engine/tasks/;engine/store/;engine/hdf5/;engine/single_quoted.hpp;kernels/")
# The commands: the runner, the store's readers, the task list (validate lists
# the tasks) and the embedded Python's version (--version).
set(allowed_engine/cli
    "engine/run/;engine/store/;engine/job/;engine/hdf5/;engine/single_quoted.hpp;engine/tasks/task_list.hpp;engine/tasks/python_env/python_runtime.hpp")
set(allowed_engine/main.cpp "engine/cli/;engine/job/usage_error.hpp;engine/run/address_space.hpp;engine/run/mpi_runner.hpp")

set(broken "")
set(checked 0)
foreach(room IN LISTS rooms)
  if(room MATCHES "\\.cpp$")
    set(files "${room}")
    set(own "")  # a file room has no folder of its own to include from
  else()
    file(GLOB_RECURSE files RELATIVE "${GGK_SOURCE_DIR}" "${GGK_SOURCE_DIR}/${room}/*.cpp"
         "${GGK_SOURCE_DIR}/${room}/*.hpp")
    set(own "${room}/")
  endif()
  set(allowed "${own};${allowed_${room}}")
  string(REPLACE ";" ", " allowed_text "${allowed_${room}}")
  foreach(file IN LISTS files)
    math(EXPR checked "${checked} + 1")
    file(STRINGS "${GGK_SOURCE_DIR}/${file}" lines REGEX "^[ \t]*#[ \t]*include[ \t]*\"")
    foreach(line IN LISTS lines)
      string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]*\"([^\"]*)\".*" "\\1" header "${line}")
      # Only the project's own headers are ruled (a folder of the repository).
      if(NOT header MATCHES "^(engine|kernels|sims)/")
        continue()
      endif()
      set(ok FALSE)
      foreach(prefix IN LISTS allowed)
        if(prefix STREQUAL "")
          continue()
        endif()
        string(FIND "${header}" "${prefix}" at)
        if(at EQUAL 0)
          set(ok TRUE)
          break()
        endif()
      endforeach()
      if(NOT ok)
        list(APPEND broken "${file}: ${header} (${room} may include ${allowed_text})")
      endif()
    endforeach()
  endforeach()
endforeach()

if(broken)
  list(JOIN broken "\n  " text)
  message(FATAL_ERROR "includes against the rooms' rules (engine/README.md, \"Who may include "
                      "whom\"):\n  ${text}")
endif()
list(JOIN rooms ", " rooms_text)
message(STATUS "IncludeRulesCheck: the ${checked} sources of ${rooms_text} include what they may")
