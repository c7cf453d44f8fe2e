#include "sgslam/mapping/mapping_config.h"

namespace sgslam {

void MappingConfig::Validate(ConfigChecker& c) const {
  c.InRange("triangulation_neighbours", triangulation_neighbours, 0, 100);
  c.InRange("fusion_neighbours", fusion_neighbours, 0, 100);
  c.InRange("ba_first_iterations", ba_first_iterations, 0, 1000);
  c.InRange("ba_second_iterations", ba_second_iterations, 0, 1000);
  c.InRange("ba_max_local_keyframes", ba_max_local_keyframes, 2, 10000);
  c.InRange("redundant_ratio", redundant_ratio, 0.5, 1.0);
  c.InRange("queue_size", queue_size, 1, 100);
  c.InRange("busy_frames", busy_frames, 0, 1000);
  c.InRange("final_ba_iterations", final_ba_iterations, 0, 1000);
  c.InRange("max_keyframes", max_keyframes, 0, 10000000);
}

}  // namespace sgslam
