// Summary statistics of an error sequence, with numpy's conventions so the numbers
// match the TUM benchmark scripts: the median of an even count is the mean of the
// two middle values, and std is the population standard deviation (ddof = 0).
#pragma once

#include <cstddef>
#include <vector>

namespace sgslam::eval {

struct ErrorStats {
  double rmse = 0;
  double mean = 0;
  double median = 0;
  double std = 0;  // population standard deviation
  double min = 0;
  double max = 0;
  std::size_t count = 0;
};

// All fields of ErrorStats; the median is sgslam::Median (numpy's). Throws
// std::invalid_argument for an empty sequence.
ErrorStats ComputeStats(const std::vector<double>& values);

}  // namespace sgslam::eval
