#include "sgslam/eval/stats.h"

#include "sgslam/common/stats.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace sgslam::eval {

ErrorStats ComputeStats(const std::vector<double>& values) {
  if (values.empty()) throw std::invalid_argument("statistics of an empty sequence");
  ErrorStats s;
  s.count = values.size();
  const double n = static_cast<double>(values.size());
  double sum = 0, sum_sq = 0;
  for (double v : values) {
    sum += v;
    sum_sq += v * v;
  }
  s.mean = sum / n;
  s.rmse = std::sqrt(sum_sq / n);
  // Two-pass variance, as numpy does, instead of sum_sq/n - mean^2 which cancels
  // catastrophically when the errors are nearly constant.
  double var = 0;
  for (double v : values) var += (v - s.mean) * (v - s.mean);
  s.std = std::sqrt(var / n);
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  s.min = *lo;
  s.max = *hi;
  s.median = sgslam::Median(values);
  return s;
}

}  // namespace sgslam::eval
