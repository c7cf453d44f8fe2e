// ORB features (ORB-SLAM2's settings for 640x480 RGB-D).
#pragma once

#include "sgslam/common/config_checker.h"

namespace sgslam {

struct OrbConfig {
  int features = 1000;         // keypoints per frame, spread over levels and image cells
  double scale_factor = 1.2;   // ratio between pyramid levels
  int levels = 8;              // pyramid levels
  int fast_threshold = 20;     // intensity, FAST threshold tried first in each cell
  int fast_min_threshold = 7;  // intensity, fallback for cells where the first finds nothing
  // Threads of the extraction (levels split between them, same output). 0: 2 when
  // parallel, no detector thread runs and the machine has more than two cores,
  // else 1: on two cores local mapping or the detector (paper Fig. 1) has the
  // second one.
  int threads = 0;

  template <class V>
  void Visit(V&& v) {
    v("features", features, "keypoints per frame");
    v("scale_factor", scale_factor, "ratio between pyramid levels");
    v("levels", levels, "pyramid levels");
    v("fast_threshold", fast_threshold, "intensity, FAST threshold");
    v("fast_min_threshold", fast_min_threshold, "intensity, FAST fallback threshold");
    v("threads", threads, "extraction threads, 1 or 2; 0: 2 when parallel without a detector on more than 2 cores");
  }
  void Validate(ConfigChecker& c) const;
};

}  // namespace sgslam
