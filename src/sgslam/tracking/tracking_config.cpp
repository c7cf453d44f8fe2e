#include "sgslam/tracking/tracking_config.h"

namespace sgslam {

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

}  // namespace sgslam
