# Helpers that give every groundline target the same shape and flags.

function(groundline_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic)
  # GCC 12's -Wmaybe-uninitialized gives false positives inside libstdc++
  # (std::regex, std::function) once the sanitizers instrument optimized code;
  # the release build keeps the warning, and ASan/UBSan check the real thing.
  if(GROUNDLINE_SANITIZE AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    target_compile_options(${target} PRIVATE -Wno-maybe-uninitialized)
  endif()
  if(GROUNDLINE_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# groundline_add_library(<module> SOURCES ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# Defines groundline_<module> (alias groundline::<module>) with public headers in
# <module>/include and private headers in <module>/src.
function(groundline_add_library module)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  set(target groundline_${module})
  add_library(${target} STATIC ${ARG_SOURCES})
  add_library(groundline::${module} ALIAS ${target})
  target_include_directories(${target}
    PUBLIC $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src)
  target_link_libraries(${target} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  set_target_properties(${target} PROPERTIES POSITION_INDEPENDENT_CODE ON)
  groundline_set_warnings(${target})
endfunction()

# Every test batch parses GoogleTest, Eigen and much of the standard library
# again; the test executables built at -O0 share one precompiled header of
# them (the first such target compiles it, the others reuse it: a
# precompiled header is valid only with the same flags, so targets optimized
# under the sanitizers parse the headers as before). The release build's test
# objects took 417 s of CPU with it against 530 s without (2 cores,
# 2026-12-06). OpenCV stays out: not every test target links it.
set(GROUNDLINE_TEST_PCH ON CACHE BOOL
    "Test executables share a precompiled header of GoogleTest, Eigen and the standard library")
function(groundline_use_test_pch target)
  if(NOT GROUNDLINE_TEST_PCH)
    return()
  endif()
  get_property(owner GLOBAL PROPERTY GROUNDLINE_TEST_PCH_OWNER)
  if(owner)
    target_precompile_headers(${target} REUSE_FROM ${owner})
  else()
    target_precompile_headers(${target} PRIVATE
      <gtest/gtest.h> <Eigen/Core> <Eigen/Geometry>
      <algorithm> <cmath> <filesystem> <fstream> <numbers> <random> <string> <vector>)
    set_property(GLOBAL PROPERTY GROUNDLINE_TEST_PCH_OWNER ${target})
  endif()
endfunction()

# groundline_add_test(<name> [LONG] [OPTIMIZED_UNDER_SANITIZERS] [SHARDS n] SOURCES ...
#                     [DEPS ...])
# One GoogleTest executable: one ctest entry that runs all its tests in one
# process, or n entries (SHARDS n, GoogleTest's sharding) that share them out.
# To run one test, run the executable with --gtest_filter=Suite.Name.
# Test code compiles at -O0 in every build: what the tests time and exercise
# is the libraries (built -O2 in release, -O1 under the sanitizers), and
# optimizing the gtest and Eigen templates of the test code itself took over
# half of the release build's compile time. A fixture that computes much
# (a rendered floor, a synthetic drive) goes in a small library of its own,
# which keeps the build's optimization level.
function(groundline_add_test name)
  cmake_parse_arguments(ARG "LONG;OPTIMIZED_UNDER_SANITIZERS" "SHARDS" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} groundline_test_support GTest::gtest_main)
  groundline_set_warnings(${name})
  # Half the compile time (a unity batch of core tests under the
  # sanitizers: 32 s at -O0 against 60 s at -O1 of CPU).
  # OPTIMIZED_UNDER_SANITIZERS: the tests run much Eigen code of their own,
  # which unoptimized and instrumented is slow (calibration_tests under
  # ASan+UBSan: 202 s at -O0 against 61 s at -O1); release keeps -O0.
  if(NOT (GROUNDLINE_SANITIZE AND ARG_OPTIMIZED_UNDER_SANITIZERS))
    target_compile_options(${name} PRIVATE -O0)
  endif()
  # Under the sanitizers the product's libraries are instrumented and the test
  # code itself is not: what the sanitizers are there to check is the product,
  # and instrumenting the test sources (GoogleTest's and Eigen's templates
  # above all) took a third of their compile time (a localization_tests batch:
  # 57 s against 36 s of CPU, 2026-12-06). The runtime is linked into every
  # executable, so a library's error is still caught wherever a test calls it.
  if(GROUNDLINE_SANITIZE)
    target_compile_options(${name} PRIVATE -fno-sanitize=all)
  endif()
  if(NOT (GROUNDLINE_SANITIZE AND ARG_OPTIMIZED_UNDER_SANITIZERS))
    groundline_use_test_pch(${name})
  endif()
  # Unoptimized code has no cost that grows faster than the batch, while
  # every batch parses GoogleTest, Eigen and OpenCV again: test sources
  # compile in batches twice the libraries'.
  math(EXPR batch "2 * ${GROUNDLINE_UNITY_BATCH}")
  set_target_properties(${name} PROPERTIES UNITY_BUILD_BATCH_SIZE ${batch})
  # LONG: the executable holds tests of a minute or more (end-to-end runs).
  # ctest starts tests of a higher COST first; without it a fresh build
  # directory (CI's) has no timings yet and runs them in declaration order,
  # and a long test started last leaves a core idle while it finishes.
  set(cost 0)
  if(ARG_LONG)
    set(cost 1000)
  endif()
  # A test process, not a test, is the unit ctest runs: a test binary that
  # links OpenCV, Ceres and the rest takes ~0.25 s of CPU to start (0.1-0.7 s
  # under ASan+UBSan, most of it in the kernel for the shadow memory); with
  # one process per test the release suite took 268 s on 2 cores, with one
  # per executable 207 s. An executable whose tests take most of a minute in
  # all is split into SHARDS so that `ctest -j 2` keeps both cores busy to
  # its end. An executable of more sources holds more tests: it starts
  # earlier.
  list(LENGTH ARG_SOURCES sources)
  math(EXPR cost "${cost} + 10 * ${sources}")
  set(environment "GROUNDLINE_TEST_TMPDIR=${CMAKE_CURRENT_BINARY_DIR}/tmp")
  if(NOT ARG_SHARDS OR ARG_SHARDS LESS 2)
    add_test(NAME ${name} COMMAND ${name})
    set_tests_properties(${name} PROPERTIES ENVIRONMENT "${environment}" COST ${cost})
  else()
    math(EXPR last "${ARG_SHARDS} - 1")
    foreach(shard RANGE ${last})
      add_test(NAME ${name}.shard${shard} COMMAND ${name})
      set_tests_properties(${name}.shard${shard} PROPERTIES
        ENVIRONMENT "${environment};GTEST_TOTAL_SHARDS=${ARG_SHARDS};GTEST_SHARD_INDEX=${shard}"
        COST ${cost})
    endforeach()
  endif()
endfunction()
