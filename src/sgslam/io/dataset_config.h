// Reading datasets (tum_dataset.h).
#pragma once

#include "sgslam/common/config_checker.h"

namespace sgslam {

struct DatasetConfig {
  double max_time_difference = 0.02;  // s, RGB-depth association window (TUM associate.py default)
  double min_median_depth = 0.3;      // m, a first frame whose median depth is below: wrong depth_factor
  double max_median_depth = 10.0;     // m, ... above: wrong depth_factor

  template <class V>
  void Visit(V&& v) {
    v("max_time_difference", max_time_difference, "s, RGB-depth association window");
    v("min_median_depth", min_median_depth, "m, a first frame's median depth below: wrong depth_factor, refused");
    v("max_median_depth", max_median_depth, "m, a first frame's median depth above: wrong depth_factor, refused");
  }
  void Validate(ConfigChecker& c) const;
};

}  // namespace sgslam
