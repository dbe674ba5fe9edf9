// Order statistics shared by the reports and the evaluations.
#ifndef GROUNDLINE_CORE_STATISTICS_H_
#define GROUNDLINE_CORE_STATISTICS_H_

#include <vector>

namespace groundline::core {

// The median as numpy's np.median: the middle value, or the mean of the two
// middle values of an even count; NaN when there are none.
double Median(std::vector<double> values);

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_STATISTICS_H_
