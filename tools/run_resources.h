// CPU time and peak memory of this process, for the run summaries.
#ifndef GROUNDLINE_TOOLS_RUN_RESOURCES_H_
#define GROUNDLINE_TOOLS_RUN_RESOURCES_H_

#include <sys/resource.h>

namespace groundline::tools {

// User + system CPU seconds used so far.
inline double ProcessCpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

// Peak resident set size [MiB] (ru_maxrss is in KiB on Linux).
inline double ProcessPeakRssMb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

}  // namespace groundline::tools

#endif  // GROUNDLINE_TOOLS_RUN_RESOURCES_H_
