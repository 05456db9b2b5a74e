# Finds Debian's SuiteSparse 5.x (no CMake config is shipped) and defines the
# imported targets SuiteSparse::CHOLMOD and SuiteSparse::UMFPACK.

find_path(SuiteSparse_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
find_library(SuiteSparse_CHOLMOD_LIBRARY cholmod)
find_library(SuiteSparse_UMFPACK_LIBRARY umfpack)
find_library(SuiteSparse_AMD_LIBRARY amd)
find_library(SuiteSparse_COLAMD_LIBRARY colamd)
find_library(SuiteSparse_CONFIG_LIBRARY suitesparseconfig)

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(SuiteSparse
  REQUIRED_VARS SuiteSparse_INCLUDE_DIR SuiteSparse_CHOLMOD_LIBRARY SuiteSparse_UMFPACK_LIBRARY
                SuiteSparse_AMD_LIBRARY SuiteSparse_COLAMD_LIBRARY SuiteSparse_CONFIG_LIBRARY)

if(SuiteSparse_FOUND AND NOT TARGET SuiteSparse::CHOLMOD)
  add_library(SuiteSparse::config UNKNOWN IMPORTED)
  set_target_properties(SuiteSparse::config PROPERTIES
    IMPORTED_LOCATION "${SuiteSparse_CONFIG_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${SuiteSparse_INCLUDE_DIR}")
  foreach(lib AMD COLAMD CHOLMOD UMFPACK)
    add_library(SuiteSparse::${lib} UNKNOWN IMPORTED)
    set_target_properties(SuiteSparse::${lib} PROPERTIES
      IMPORTED_LOCATION "${SuiteSparse_${lib}_LIBRARY}"
      INTERFACE_LINK_LIBRARIES SuiteSparse::config)
  endforeach()
  set_property(TARGET SuiteSparse::UMFPACK APPEND PROPERTY
    INTERFACE_LINK_LIBRARIES SuiteSparse::CHOLMOD SuiteSparse::AMD)
  set_property(TARGET SuiteSparse::CHOLMOD APPEND PROPERTY
    INTERFACE_LINK_LIBRARIES SuiteSparse::AMD SuiteSparse::COLAMD)
endif()
mark_as_advanced(SuiteSparse_INCLUDE_DIR SuiteSparse_CHOLMOD_LIBRARY SuiteSparse_UMFPACK_LIBRARY
                 SuiteSparse_AMD_LIBRARY SuiteSparse_COLAMD_LIBRARY SuiteSparse_CONFIG_LIBRARY)
