#include "sgslam/config/config.h"

#include <cmath>

#include "sgslam/common/error.h"

namespace sgslam {

void CameraConfig::Validate(ConfigChecker& c) const {
  c.InRange("width", width, 16, 8192);
  c.InRange("height", height, 16, 8192);
  c.Positive("fx", fx);
  c.Positive("fy", fy);
  c.InRange("cx", cx, 0.0, static_cast<double>(width));
  c.InRange("cy", cy, 0.0, static_cast<double>(height));
  for (const auto& [key, value] : {std::pair{"k1", k1}, {"k2", k2}, {"p1", p1}, {"p2", p2}, {"k3", k3}}) {
    c.Check(std::isfinite(value) && std::abs(value) < 100.0, key, value, "must be a finite distortion coefficient");
  }
  c.InRange("fps", fps, 0.1, 1000.0);
  c.Positive("depth_factor", depth_factor);
  c.Positive("baseline_fx", baseline_fx);
  c.Positive("close_depth", close_depth);
  c.InRange("readout", readout, 0.0, 1.0 / fps);
}

void DatasetConfig::Validate(ConfigChecker& c) const {
  c.InRange("max_time_difference", max_time_difference, 1e-6, 1.0);
  c.InRange("prefetch", prefetch, 1, 64);
  c.Positive("min_median_depth", min_median_depth);
  c.Check(max_median_depth > min_median_depth, "max_median_depth", max_median_depth, "must be > min_median_depth");
}

void OrbConfig::Validate(ConfigChecker& c) const {
  c.InRange("features", features, 50, 20000);
  c.InRange("scale_factor", scale_factor, 1.01, 2.0);
  c.InRange("levels", levels, 1, 16);
  c.InRange("fast_threshold", fast_threshold, 1, 254);
  c.InRange("fast_min_threshold", fast_min_threshold, 1, 254);
  c.Check(fast_min_threshold <= fast_threshold, "fast_min_threshold", fast_min_threshold, "must be <= fast_threshold");
  c.InRange("cell_size", cell_size, 10, 200);
  c.InRange("threads", threads, 0, 2);
}

void TrackingConfig::Validate(ConfigChecker& c) const {
  c.InRange("min_init_points", min_init_points, 10, 100000);
  c.InRange("motion_search_radius", motion_search_radius, 1.0, 200.0);
  c.InRange("local_search_radius", local_search_radius, 0.5, 50.0);
  c.InRange("descriptor_ratio", descriptor_ratio, 0.1, 1.0);
  c.InRange("min_motion_matches", min_motion_matches, 4, 10000);
  c.InRange("min_pose_inliers", min_pose_inliers, 4, 10000);
  c.InRange("min_local_inliers", min_local_inliers, 4, 10000);
  c.InRange("recover_candidates", recover_candidates, 1, 100000);
  c.InRange("keyframe_ref_ratio", keyframe_ref_ratio, 0.05, 1.0);
  c.InRange("max_frames_between_keyframes", max_frames_between_keyframes, 0, 10000);
  c.InRange("close_tracked_min", close_tracked_min, 0, 100000);
  c.InRange("close_untracked_min", close_untracked_min, 0, 100000);
  c.InRange("keyframe_min_new_points", keyframe_min_new_points, 0, 100000);
  c.InRange("trust_delay", trust_delay, 0.0, 60.0);
  c.InRange("trust_hits", trust_hits, 1, 1000);
  c.InRange("trust_min_points", trust_min_points, 3, 100000);
  c.InRange("rejected_match_distance", rejected_match_distance, 0, 256);
  c.InRange("rolling_shutter_prior", rolling_shutter_prior, 1e-3, 100.0);
}

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
}

void Config::Validate(const std::string& source) const {
  ConfigChecker checker("");
  VisitSections([&](const char* name, const auto& section) {
    checker.SetSection(name);
    section.Validate(checker);
  });
  if (checker.problems().empty()) return;
  std::string message = "invalid configuration (" + source + "):";
  for (const auto& p : checker.problems()) message += "\n  " + p;
  throw ConfigError(message);
}

}  // namespace sgslam
