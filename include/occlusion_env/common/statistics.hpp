// Summary statistics of samples, for the means, medians and percentiles the tools, benchmarks and
// nodes report: written once so that every "median" in a log or a table means the same.
#pragma once

#include <vector>

namespace occlusion_env {

/// The arithmetic mean of `values`. NaN if `values` is empty.
double mean(const std::vector<double>& values);

/// The median of `values`: the middle one, or the mean of the two middle ones if their number is
/// even. NaN if `values` is empty.
double median(std::vector<double> values);

/// The nearest-rank percentile: the value at index round(fraction * (n - 1)) of `values` sorted,
/// `fraction` in [0, 1] (0.975: the 97.5th percentile). NaN if `values` is empty.
double percentile(std::vector<double> values, double fraction);

}  // namespace occlusion_env
