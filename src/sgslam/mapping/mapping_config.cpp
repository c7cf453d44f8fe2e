#include "sgslam/mapping/mapping_config.h"

namespace sgslam {

void MappingConfig::Validate(ConfigChecker& c) const {
  c.InRange("final_ba_iterations", final_ba_iterations, 0, 1000);
  c.InRange("max_keyframes", max_keyframes, 0, 10000000);
}

}  // namespace sgslam
