// Which variant of the build a test executable is, and the groundline
// executable of that variant. The test objects are compiled once and linked
// twice (cmake/GroundlineTargets.cmake): <name> against the plain libraries,
// <name>_san against their AddressSanitizer + UndefinedBehaviorSanitizer
// twins, so the variant is a fact of the link, asked at run time.
#ifndef GROUNDLINE_TESTS_SUPPORT_TOOLS_UNDER_TEST_H_
#define GROUNDLINE_TESTS_SUPPORT_TOOLS_UNDER_TEST_H_

#include <gtest/gtest.h>

// Defined by the AddressSanitizer runtime, which only the sanitized test
// executables link; a weak reference is null in the others.
extern "C" void __asan_init() __attribute__((weak));  // NOLINT(bugprone-reserved-identifier)

namespace groundline::testing {

// True in a test executable linked against the sanitizer twins. Tests that
// take minutes instrumented run shorter or skip on it.
inline bool Sanitized() { return &__asan_init != nullptr; }

// The groundline executable to run: the sanitizer twin (tools/san/groundline)
// from a sanitized test, the plain one otherwise. A test that runs it is
// declared RUNS_CLI in its CMakeLists, which builds it first.
inline const char* GroundlineCli() {
  return Sanitized() ? GROUNDLINE_CLI_SANITIZED : GROUNDLINE_CLI_PLAIN;
}

}  // namespace groundline::testing

#endif  // GROUNDLINE_TESTS_SUPPORT_TOOLS_UNDER_TEST_H_
