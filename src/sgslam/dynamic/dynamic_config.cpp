#include "sgslam/dynamic/dynamic_config.h"

namespace sgslam {

void DynamicConfig::Validate(ConfigChecker& c) const {
  c.Check(mode == "none" || mode == "semantic" || mode == "geometric" || mode == "sg", "mode", mode,
          "must be none, semantic, geometric or sg");
  c.InRange("eps_std", eps_std, 1e-3, 100.0);
  c.Check(lk_window >= 5 && lk_window <= 101 && lk_window % 2 == 1, "lk_window", lk_window,
          "must be odd and in [5, 101]");
  c.InRange("lk_levels", lk_levels, 0, 8);
  c.InRange("lk_iterations", lk_iterations, 1, 1000);
  c.InRange("lk_epsilon", lk_epsilon, 1e-6, 1.0);
  c.InRange("border", border, 0.0, 200.0);
  c.InRange("patch_radius", patch_radius, 0, 10);
  c.InRange("max_patch_difference", max_patch_difference, 0.0, 255.0);
  c.InRange("ransac_threshold", ransac_threshold, 0.01, 50.0);
  c.InRange("ransac_confidence", ransac_confidence, 0.5, 0.999999);
  c.InRange("ransac_iterations", ransac_iterations, 10, 100000);
  c.InRange("min_static_pairs", min_static_pairs, 15, 100000);  // OpenCV's RANSAC needs 15 pairs
  c.InRange("max_box_area", max_box_area, 0.0, 1.0);
  c.InRange("box_depth_band", box_depth_band, 0.0, 10.0);
  c.InRange("carry_frames", carry_frames, 0, 30);
  c.InRange("carry_iou", carry_iou, 0.0, 1.0);
  c.InRange("carry_min_motion", carry_min_motion, 0.0, 1.0);
  c.InRange("min_kept_ratio", min_kept_ratio, 0.0, 1.0);
  c.InRange("relax_factor", relax_factor, 1.0, 10.0);
  c.InRange("relax_steps", relax_steps, 0, 20);
  c.InRange("prior_cell", prior_cell, 0, 640);
  c.InRange("prior_memory", prior_memory, 1, 255);
  c.InRange("depth_check_window", depth_check_window, 0, 5);
  c.InRange("confirm_static", confirm_static, 0.0, 1.0);
  c.InRange("motion_threshold", motion_threshold, 0.1, 50.0);
  c.InRange("motion_iterations", motion_iterations, 10, 100000);
  c.InRange("motion_min_inliers", motion_min_inliers, 6, 100000);
  c.InRange("depth_max_share", depth_max_share, 0.0, 1.0);
  c.InRange("depth_tolerance", depth_tolerance, 0.0, 10.0);
  c.InRange("depth_tolerance_quadratic", depth_tolerance_quadratic, 0.0, 1.0);
  c.InRange("reprojection_tolerance", reprojection_tolerance, 0.0, 1000.0);
  c.InRange("reprojection_median_factor", reprojection_median_factor, 0.0, 100.0);
  c.Positive("depth_min", depth_min);
  c.Check(depth_max > depth_min, "depth_max", depth_max, "must be > depth_min");
}

}  // namespace sgslam
