// Order statistics and distribution quantiles shared by the reports, the
// evaluations and the estimators' gates.
#ifndef GROUNDLINE_CORE_STATISTICS_H_
#define GROUNDLINE_CORE_STATISTICS_H_

#include <vector>

namespace groundline::core {

// The median as numpy's np.median: the middle value, or the mean of the two
// middle values of an even count; NaN when there are none.
double Median(std::vector<double> values);

// The standard normal quantile: z with P(Z <= z) = p, p in (0, 1) (Acklam's
// rational approximation, relative error < 1.2e-9); NaN outside (0, 1).
double NormalQuantile(double p);

// The chi-square quantile of dof >= 1 degrees of freedom at probability p in
// (0, 1): exact for 1 dof (z((1+p)/2)^2) and 2 dof (-2 ln(1-p)); from 3 dof
// on the Wilson-Hilferty cube-root approximation, within -0.5 % and +4 % for p
// in [0.9, 0.9999] (+3.5 % at 3 dof and 0.9999, less with more dof).
// NaN for dof < 1 or p outside (0, 1).
double ChiSquareQuantile(int dof, double p);

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_STATISTICS_H_
