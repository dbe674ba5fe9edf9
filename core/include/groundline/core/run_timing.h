// Small measurement helpers shared by the run outputs (localize, serve).
#ifndef GROUNDLINE_CORE_RUN_TIMING_H_
#define GROUNDLINE_CORE_RUN_TIMING_H_

#include <vector>

namespace groundline::core {

// CPU seconds of the calling thread (CLOCK_THREAD_CPUTIME_ID): its own work,
// without the time it waited for a core on a loaded machine.
double ThreadCpuSeconds();

// The q-quantile (0..1) of the values, nearest rank; 0 for none.
double Percentile(std::vector<double> values, double q);

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_RUN_TIMING_H_
