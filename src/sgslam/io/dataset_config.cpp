#include "sgslam/io/dataset_config.h"

namespace sgslam {

void DatasetConfig::Validate(ConfigChecker& c) const {
  c.InRange("max_time_difference", max_time_difference, 1e-6, 1.0);
  c.Positive("min_median_depth", min_median_depth);
  c.Check(max_median_depth > min_median_depth, "max_median_depth", max_median_depth, "must be > min_median_depth");
}

}  // namespace sgslam
