// Small measurement helpers shared by the run outputs (localize, serve).
#ifndef GROUNDLINE_CORE_RUN_TIMING_H_
#define GROUNDLINE_CORE_RUN_TIMING_H_

#include <chrono>
#include <vector>

namespace groundline::core {

// Wall-clock seconds from start to now (steady clock).
inline double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// CPU seconds of the calling thread (CLOCK_THREAD_CPUTIME_ID): its own work,
// without the time it waited for a core on a loaded machine.
double ThreadCpuSeconds();

// The q-quantile (0..1) of the values, nearest rank; 0 for none.
double Percentile(std::vector<double> values, double q);

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_RUN_TIMING_H_
