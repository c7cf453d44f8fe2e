#include "sgslam/features/orb_config.h"

namespace sgslam {

void OrbConfig::Validate(ConfigChecker& c) const {
  c.InRange("features", features, 50, 20000);
  c.InRange("scale_factor", scale_factor, 1.01, 2.0);
  c.InRange("levels", levels, 1, 16);
  c.InRange("fast_threshold", fast_threshold, 1, 254);
  c.InRange("fast_min_threshold", fast_min_threshold, 1, 254);
  c.Check(fast_min_threshold <= fast_threshold, "fast_min_threshold", fast_min_threshold, "must be <= fast_threshold");
  c.InRange("threads", threads, 0, 2);
}

}  // namespace sgslam
