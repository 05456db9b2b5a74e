# Common settings for every ggk target: C++20, warnings, no floating-point
# contraction, optional sanitizers.
# Kept per target (no global flags), as CONTRIBUTING.md asks.

function(ggk_configure_target target)
  target_compile_features(${target} PUBLIC cxx_std_20)
  set_target_properties(${target} PROPERTIES CXX_EXTENSIONS OFF)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
                                           -Wno-sign-conversion)
  # GCC 12 at -O3 reports false -Wrestrict positives inside std::string's
  # operator+ (GCC bug 105329); the warning says nothing about our code.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    target_compile_options(${target} PRIVATE -Wno-restrict)
  endif()
  # No fused multiply-add anywhere: g++ contracts a * b + c into one rounding
  # whenever the target has FMA (its default for C++ is -ffp-contract=fast), which
  # would make results depend on -march and the AVX2 paths differ from the portable
  # ones (kernels/avx2_dispatch.hpp). Every target of the project (libraries, ggk,
  # tests, benchmarks, fuzzers) comes through here. CONTRIBUTING.md, "Determinism".
  target_compile_options(${target} PRIVATE -ffp-contract=off)
  if(GGK_WARNINGS_AS_ERRORS)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
  if(GGK_SANITIZE)
    target_compile_options(${target} PUBLIC -fsanitize=address,undefined -fno-omit-frame-pointer
                                            -fno-sanitize-recover=undefined)
    target_link_options(${target} PUBLIC -fsanitize=address,undefined)
  endif()
endfunction()

# ggk_add_library(name SOURCES ...): a library target for one top-level folder.
function(ggk_add_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LINK" ${ARGN})
  if(NOT ARG_SOURCES)
    return()
  endif()
  add_library(${name} ${ARG_SOURCES})
  target_include_directories(${name} PUBLIC "${PROJECT_SOURCE_DIR}")
  target_link_libraries(${name} PUBLIC ${ARG_LINK})
  ggk_configure_target(${name})
endfunction()
