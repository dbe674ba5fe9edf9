# Helpers that give every groundline target the same shape and flags.

function(groundline_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic)
  if(GROUNDLINE_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# Sanitizer twins (GROUNDLINE_SANITIZER_TWINS): every library, the CLI, the
# test fixtures and the fuzz smoke drivers are also built as <target>_san,
# instrumented with AddressSanitizer + UndefinedBehaviorSanitizer at -O1 with
# assertions on, in the same tree as the plain build. Each test executable's
# objects (uninstrumented, -O0) are compiled once and linked twice: <name>
# against the plain libraries, <name>_san against the twins and the
# sanitizer runtimes, so an error in the product is caught wherever a test
# calls it. One tree instead of a second build of everything halves the test
# code's share of CI's compile time.
#
# UBSan runs without its null and alignment checks: they instrument every
# pointer and reference in the Eigen and Ceres templates, which doubled the
# compile time of the heaviest sources (a calibration unity batch: 85 s with
# them, 43 s without, 28 s unsanitized). A null dereference is still caught
# by ASan (SEGV on unknown address 0x0), and the misalignment that matters
# here, a fixed-size vectorizable Eigen type, is asserted by Eigen itself in
# the twins (assertions on). Every other UBSan check (overflow, shift, bounds,
# vptr, object-size, enum, bool, float-cast...) stays on. -O1, as the
# AddressSanitizer documentation advises: the suite ran in 281 s instead of
# 630 s at -O0 (2 cores, 2026-12-01).
set(GROUNDLINE_SANITIZER_FLAGS -fsanitize=address,undefined -fno-sanitize=alignment,null
    -fno-omit-frame-pointer -fno-sanitize-recover=undefined)

# Makes <target> a sanitizer twin: instrumented, -O1, assertions on, and
# "GROUNDLINE_SANITIZED" defined (the LeakSanitizer suppressions are compiled
# in on it). Whatever links it links the sanitizer runtimes.
function(groundline_sanitize target)
  target_compile_options(${target} PRIVATE ${GROUNDLINE_SANITIZER_FLAGS} -O1 -UNDEBUG)
  target_compile_definitions(${target} PRIVATE GROUNDLINE_SANITIZED=1)
  get_target_property(type ${target} TYPE)
  if(type STREQUAL "EXECUTABLE")
    target_link_options(${target} PRIVATE -fsanitize=address,undefined)
  else()
    target_link_options(${target} INTERFACE -fsanitize=address,undefined)
  endif()
  # GCC 12's -Wmaybe-uninitialized gives false positives inside libstdc++
  # (std::regex, std::function) once the sanitizers instrument optimized
  # code; the plain build keeps the warning, and ASan/UBSan check the real thing.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    target_compile_options(${target} PRIVATE -Wno-maybe-uninitialized)
  endif()
endfunction()

# groundline_twin_deps(<out> <dep>...): the twins' dependencies, each
# groundline::<m> as groundline::<m>_san and each local target that has a
# twin as <target>_san; outside libraries as they are.
function(groundline_twin_deps out)
  set(result "")
  foreach(dep IN LISTS ARGN)
    if(dep MATCHES "^groundline::(.+)$")
      list(APPEND result groundline::${CMAKE_MATCH_1}_san)
    elseif(TARGET ${dep}_san)
      list(APPEND result ${dep}_san)
    else()
      list(APPEND result ${dep})
    endif()
  endforeach()
  set(${out} ${result} PARENT_SCOPE)
endfunction()

# groundline_add_library(<module> SOURCES ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# Defines groundline_<module> (alias groundline::<module>) with public headers in
# <module>/include and private headers in <module>/src, and its twin
# groundline_<module>_san (groundline::<module>_san) when the twins are built.
function(groundline_add_library module)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  set(variants "")
  if(GROUNDLINE_SANITIZER_TWINS)
    set(variants _san)
  endif()
  foreach(variant "" ${variants})
    set(target groundline_${module}${variant})
    add_library(${target} STATIC ${ARG_SOURCES})
    add_library(groundline::${module}${variant} ALIAS ${target})
    target_include_directories(${target}
      PUBLIC $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
      PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src)
    if(variant STREQUAL "")
      target_link_libraries(${target} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
    else()
      groundline_twin_deps(public ${ARG_PUBLIC_DEPS})
      groundline_twin_deps(private ${ARG_PRIVATE_DEPS})
      target_link_libraries(${target} PUBLIC ${public} PRIVATE ${private})
      groundline_sanitize(${target})
    endif()
    set_target_properties(${target} PROPERTIES POSITION_INDEPENDENT_CODE ON)
    groundline_set_warnings(${target})
  endforeach()
endfunction()

# Every test batch parses GoogleTest, Eigen and much of the standard library
# again; the test objects share one precompiled header of them (the first
# test compiles it, the others reuse it). The release build's test objects
# took 417 s of CPU with it against 530 s without (2 cores, 2026-12-06).
# OpenCV stays out: not every test target links it.
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

# The environment of every sanitized test process: a leak or an error ends it
# with a report and a failure.
set(GROUNDLINE_SANITIZER_TEST_ENVIRONMENT
    "ASAN_OPTIONS=detect_leaks=1:abort_on_error=1"
    "UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1")

# groundline_register_test(<ctest name> <executable> <cost> <label> <shards> [ENV...])
# One ctest entry, or <shards> entries that share the executable's tests out
# with GoogleTest's sharding.
function(groundline_register_test test executable cost label shards)
  set(environment ${ARGN})
  if(NOT shards OR shards LESS 2)
    add_test(NAME ${test} COMMAND ${executable})
    set_tests_properties(${test} PROPERTIES ENVIRONMENT "${environment}" COST ${cost}
                         LABELS ${label})
  else()
    math(EXPR last "${shards} - 1")
    foreach(shard RANGE ${last})
      add_test(NAME ${test}.shard${shard} COMMAND ${executable})
      set_tests_properties(${test}.shard${shard} PROPERTIES
        ENVIRONMENT "${environment};GTEST_TOTAL_SHARDS=${shards};GTEST_SHARD_INDEX=${shard}"
        COST ${cost} LABELS ${label})
    endforeach()
  endif()
endfunction()

# groundline_add_test(<name> [LONG] [RUNS_CLI] [OPTIMIZED] [SHARDS n] SOURCES ...
#                     [DEPS ...] [DEFINITIONS ...] [INCLUDES ...])
# One GoogleTest executable <name>: one ctest entry that runs all its tests in
# one process, or n entries (SHARDS n, GoogleTest's sharding) that share them
# out. With the sanitizer twins, also <name>_san, the same objects linked
# against the twins, whose ctest entries are asan.<name>[.shardK] (label
# "sanitized"; the plain ones have the label "plain"). To run one test, run
# the executable with --gtest_filter=Suite.Name.
# RUNS_CLI: the tests run the groundline executable (testing::GroundlineCli()
# in tests/support/tools_under_test.h names the one of the test's variant).
# DEFINITIONS and INCLUDES: compile definitions and private include
# directories of the test sources.
#
# Test code compiles at -O0 and uninstrumented in every variant: what the
# tests time and exercise is the libraries (built -O2, and -O1 instrumented in
# the twins). Optimizing the gtest and Eigen templates of the test code itself
# took over half of the release build's compile time, and instrumenting them
# a third of their compile time under the sanitizers (a localization_tests
# batch: 57 s against 36 s of CPU, 2026-12-06). A fixture that computes much
# (a rendered floor, a synthetic drive) goes in a small library of its own,
# which keeps the build's optimization level and has a twin.
#
# OPTIMIZED: the test objects compile at -O1 (without the shared PCH, which
# is -O0). The linker keeps one copy of each out-of-line template, the first
# it meets, and a test's objects come before the libraries: Eigen's matrix
# products instantiated by unoptimized test code then run unoptimized inside
# the libraries too. Where the tests drive much dense algebra that costs more
# than the compile time (2 cores, 2026-12-07, plain / sanitized shards summed:
# calibration_tests 44 / 179 s with -O0 test objects, 14 / 60 s with -O1;
# localization_tests 28 / 110 s against 9 / 96 s; for 5-9 s more compile
# CPU each). The service and relocalization tests gained nothing.
function(groundline_add_test name)
  cmake_parse_arguments(ARG "LONG;RUNS_CLI;OPTIMIZED" "SHARDS" "SOURCES;DEPS;DEFINITIONS;INCLUDES"
                        ${ARGN})
  set(objects ${name}_objects)
  add_library(${objects} OBJECT ${ARG_SOURCES})
  target_link_libraries(${objects} PRIVATE ${ARG_DEPS} groundline_test_support)
  target_compile_definitions(${objects} PRIVATE ${ARG_DEFINITIONS})
  target_include_directories(${objects} PRIVATE ${ARG_INCLUDES})
  if(ARG_OPTIMIZED)
    target_compile_options(${objects} PRIVATE -O1)
  else()
    target_compile_options(${objects} PRIVATE -O0)
    groundline_use_test_pch(${objects})
  endif()
  groundline_set_warnings(${objects})
  # Unoptimized code has no cost that grows faster than the batch, while
  # every batch parses GoogleTest, Eigen and OpenCV again: test sources
  # compile in batches twice the libraries'.
  math(EXPR batch "2 * ${GROUNDLINE_UNITY_BATCH}")
  set_target_properties(${objects} PROPERTIES UNITY_BUILD_BATCH_SIZE ${batch})

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

  add_executable(${name} $<TARGET_OBJECTS:${objects}>)
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} groundline_test_support GTest::gtest_main)
  if(ARG_RUNS_CLI)
    add_dependencies(${name} groundline)
  endif()
  groundline_register_test(${name} ${name} ${cost} plain "${ARG_SHARDS}"
                           "GROUNDLINE_TEST_TMPDIR=${CMAKE_CURRENT_BINARY_DIR}/tmp")
  if(GROUNDLINE_SANITIZER_TWINS)
    groundline_twin_deps(deps ${ARG_DEPS} groundline_test_support)
    add_executable(${name}_san $<TARGET_OBJECTS:${objects}>)
    target_link_libraries(${name}_san PRIVATE ${deps} GTest::gtest_main)
    target_link_options(${name}_san PRIVATE -fsanitize=address,undefined)
    if(ARG_RUNS_CLI)
      add_dependencies(${name}_san groundline_san)
    endif()
    groundline_register_test(asan.${name} ${name}_san ${cost} sanitized "${ARG_SHARDS}"
                             "GROUNDLINE_TEST_TMPDIR=${CMAKE_CURRENT_BINARY_DIR}/tmp-asan"
                             ${GROUNDLINE_SANITIZER_TEST_ENVIRONMENT})
  endif()
endfunction()

# groundline_add_test_library(<name> SOURCES ... DEPS ...)
# A test fixture that computes much (a rendered floor, a synthetic drive):
# a static library at the build's optimization level, with its twin
# <name>_san when the sanitizer twins are built. DEPS are public.
function(groundline_add_test_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_library(${name} STATIC ${ARG_SOURCES})
  target_link_libraries(${name} PUBLIC ${ARG_DEPS})
  groundline_set_warnings(${name})
  if(GROUNDLINE_SANITIZER_TWINS)
    add_library(${name}_san STATIC ${ARG_SOURCES})
    groundline_twin_deps(deps ${ARG_DEPS})
    target_link_libraries(${name}_san PUBLIC ${deps})
    groundline_set_warnings(${name}_san)
    groundline_sanitize(${name}_san)
  endif()
endfunction()

# groundline_test_needs(<test> <target>...): the test's executables (both
# variants) run these targets' programs, which the test's build builds first.
function(groundline_test_needs test)
  add_dependencies(${test} ${ARGN})
  if(TARGET ${test}_san)
    add_dependencies(${test}_san ${ARGN})
  endif()
endfunction()
