#include "sgslam/semantic/semantic_config.h"

#include "sgslam/semantic/objects.h"

namespace sgslam {

void SemanticConfig::Validate(ConfigChecker& c) const {
  c.InRange("queue_size", queue_size, 1, 1000);
  c.Check(keyframe_model.find('/') == std::string::npos, "keyframe_model", keyframe_model,
          "must be empty or a model file stem such as yolo-fastest-1.1-xl (the folder is detector.model_dir)");
  c.InRange("depth_min", depth_min, 0.0, 100.0);
  c.Check(depth_max > depth_min && depth_max <= 100.0, "depth_max", depth_max, "must be > depth_min and <= 100");
  c.InRange("cloud_stride", cloud_stride, 1, 64);
  c.InRange("cloud_voxel", cloud_voxel, 0.001, 1.0);
  c.InRange("cloud_edge_radius", cloud_edge_radius, 0, 50);
  c.InRange("box_margin", box_margin, 0.0, 1.0);
  c.InRange("box_window", box_window, 0, 30);
  c.InRange("motion_radius", motion_radius, 0, 200);
  c.InRange("consistency_tolerance", consistency_tolerance, 0.0, 10.0);
  c.InRange("consistency_min_votes", consistency_min_votes, 1, 1000);
  c.InRange("min_view_support", min_view_support, 1, 1000);
  c.InRange("seen_moving_ratio", seen_moving_ratio, 0.0, 1000.0);
  c.InRange("cloud_border", cloud_border, 0, 1000);
  c.InRange("octomap_resolution", octomap_resolution, 0.005, 1.0);
  c.Check(octomap_hit > 0.5 && octomap_hit < 1.0, "octomap_hit", octomap_hit, "must be in (0.5, 1)");
  c.Check(octomap_miss > 0.0 && octomap_miss < 0.5, "octomap_miss", octomap_miss, "must be in (0, 0.5)");
  c.Check(octomap_clamp_min > 0.0 && octomap_clamp_min < 0.5, "octomap_clamp_min", octomap_clamp_min,
          "must be in (0, 0.5)");
  c.Check(octomap_clamp_max > 0.5 && octomap_clamp_max < 1.0, "octomap_clamp_max", octomap_clamp_max,
          "must be in (0.5, 1)");
  c.Check(object_box_shrink > 0.0 && object_box_shrink <= 1.0, "object_box_shrink", object_box_shrink,
          "must be in (0, 1]");
  c.InRange("object_depth_band_width", object_depth_band_width, 0.0, 10.0);
  c.InRange("object_min_points", object_min_points, 3, kObjectMaxPoints);
  c.InRange("object_min_score", object_min_score, 0.0, 1.0);
  c.InRange("object_merge_iou", object_merge_iou, 0.0, 1.0);
  c.InRange("object_min_observations", object_min_observations, 1, 1000);
  c.InRange("object_background_planes", object_background_planes, 0, 5);
}

}  // namespace sgslam
