#include "sgslam/semantic/semantic_config.h"

namespace sgslam {

void SemanticConfig::Validate(ConfigChecker& c) const {
  c.InRange("queue_size", queue_size, 1, 1000);
  c.Check(keyframe_model.find('/') == std::string::npos, "keyframe_model", keyframe_model,
          "must be empty or a model file stem such as yolo-fastest-1.1-xl (the folder is detector.model_dir)");
  c.InRange("depth_min", depth_min, 0.0, 100.0);
  c.Check(depth_max > depth_min && depth_max <= 100.0, "depth_max", depth_max, "must be > depth_min and <= 100");
  c.InRange("cloud_voxel", cloud_voxel, 0.001, 1.0);
  c.InRange("octomap_resolution", octomap_resolution, 0.005, 1.0);
  // filters: switches only, every value is valid.
}

}  // namespace sgslam
