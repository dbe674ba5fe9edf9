// Test setup shared by the DDS tests: every test runs on the loopback
// configuration (CYCLONEDDS_URI = samples/cyclonedds_loopback.xml, inherited
// by forked helpers) and on a domain id of its own, so that tests run in
// parallel by ctest never meet and nothing leaves the machine.
#ifndef GROUNDLINE_TESTS_IO_DDS_TEST_ENV_H_
#define GROUNDLINE_TESTS_IO_DDS_TEST_ENV_H_

#include <cstdlib>
#include <string>

namespace groundline::io::testing {

// Domain ids used by the tests, one per test executable.
inline constexpr unsigned kGoldenDomainId = 171;
inline constexpr unsigned kLoopbackDomainId = 172;
inline constexpr unsigned kInputsDomainId = 173;

inline void UseLoopbackConfig() {
  const std::string uri = std::string("file://") + GROUNDLINE_DDS_LOOPBACK_XML;
  ::setenv("CYCLONEDDS_URI", uri.c_str(), 1);
}

}  // namespace groundline::io::testing

#endif  // GROUNDLINE_TESTS_IO_DDS_TEST_ENV_H_
