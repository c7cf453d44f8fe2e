#include "sgslam/config/removed_keys.h"

#include <yaml-cpp/yaml.h>

#include <cstdlib>

namespace sgslam {

const std::vector<RemovedConfigKey>& RemovedConfigKeys() {
  // clang-format off
  static const std::vector<RemovedConfigKey> kRemoved = {
      {"dataset.prefetch", "3", "a constant, kPrefetchFrames (apps/run_pipeline.cpp)"},
      {"orb.cell_size", "35", "a constant, FastCellParams::cell_size (features/fast_grid.h)"},
      {"tracking.min_init_points", "500", "a constant, kMinInitPoints (tracking/tracker.cpp; at most half of orb.features)"},
      {"tracking.motion_search_radius", "15", "a constant, kMotionSearchRadius (tracking/tracker.cpp)"},
      {"tracking.local_search_radius", "5", "a constant, kLocalSearchRadius (tracking/tracker.cpp)"},
      {"tracking.descriptor_ratio", "0.7", "a constant, kDescriptorRatio (tracking/tracker.cpp)"},
      {"tracking.min_motion_matches", "20", "a constant, kMinMotionMatches (tracking/tracker.cpp)"},
      {"tracking.min_pose_inliers", "10", "a constant, kMinPoseInliers (tracking/tracker.cpp)"},
      {"tracking.min_local_inliers", "30", "a constant, kMinLocalInliers (tracking/tracker.cpp)"},
      {"tracking.recover_candidates", "30", "a constant, kRecoverCandidates (tracking/tracker.cpp)"},
      {"tracking.keyframe_ref_ratio", "0.75", "a constant, kKeyFrameRefRatio (tracking/keyframe_decision.cpp)"},
      {"tracking.max_frames_between_keyframes", "30", "a constant, kMaxFramesBetweenKeyFrames (tracking/keyframe_decision.cpp)"},
      {"tracking.close_tracked_min", "100", "a constant, kCloseTrackedMin (tracking/keyframe_decision.cpp)"},
      {"tracking.close_untracked_min", "70", "a constant, kCloseUntrackedMin (tracking/keyframe_decision.cpp)"},
      {"tracking.keyframe_min_new_points", "100", "a constant, kKeyFrameMinNewPoints (tracking/keyframe_decision.cpp)"},
      {"tracking.skip_outlier_depth_points", "true", "always so (tracking/keyframe_decision.cpp)"},
      {"tracking.trust_delay", "0.3", "a constant, kTrustDelay (tracking/tracker.cpp); tracking.refinements.trusted_points switches trust off"},
      {"tracking.trust_hits", "2", "a constant, kTrustHits (tracking/tracker.cpp)"},
      {"tracking.trust_min_points", "20", "a constant, kTrustMinPoints (tracking/tracker.cpp)"},
      {"tracking.rejected_match_distance", "50", "a constant, kRejectedMatchDistance (tracking/tracker.cpp); tracking.refinements.rejected_matches switches it off"},
      {"tracking.rolling_shutter_refine", "true", "tracking.refinements.rolling_shutter_refine"},
      {"tracking.rolling_shutter_prior", "1", "a constant, kRollingShutterPrior (tracking/tracker.cpp)"},
      {"tracking.keyframe_velocity_central", "true", "tracking.refinements.keyframe_velocity_central"},
      {"tracking.frame_velocity_central", "true", "tracking.refinements.frame_velocity_central"},
      {"mapping.triangulation_neighbours", "10", "a constant, kTriangulationNeighbours (mapping/new_points.cpp)"},
      {"mapping.fusion_neighbours", "10", "a constant, kFusionNeighbours (mapping/local_mapper.cpp)"},
      {"mapping.ba_first_iterations", "5", "a constant, kLocalBaFirstIterations (mapping/local_ba.cpp)"},
      {"mapping.ba_second_iterations", "10", "a constant, kLocalBaSecondIterations (mapping/local_ba.cpp)"},
      {"mapping.ba_max_local_keyframes", "25", "a constant, kMaxLocalKeyFrames (mapping/local_ba.cpp)"},
      {"mapping.redundant_ratio", "0.9", "a constant, kRedundantRatio (mapping/local_mapper.cpp)"},
      {"mapping.queue_size", "3", "a constant, kMappingQueueSize (system/slam_system.cpp)"},
      {"mapping.busy_frames", "5", "a constant, kMappingBusyFrames (system/slam_system.cpp)"},
      {"detector.nms_threshold", "0.45", "a constant, YoloDecodeParams::nms_threshold (detection/yolo_decode.h)"},
      {"detector.dynamic_min_weight", "3", "a constant, ClassTable::kMinWeight (detection/detector_config.h)"},
      {"dynamic.lk_window", "21", "a constant, kLkWindow (dynamic/flow.cpp)"},
      {"dynamic.lk_levels", "3", "a constant, kLkLevels (dynamic/flow.cpp)"},
      {"dynamic.lk_iterations", "30", "a constant, kLkIterations (dynamic/flow.cpp)"},
      {"dynamic.lk_epsilon", "0.01", "a constant, kLkEpsilon (dynamic/flow.cpp)"},
      {"dynamic.border", "8", "a constant, kBorder (dynamic/flow.cpp)"},
      {"dynamic.patch_radius", "2", "a constant, kPatchRadius (dynamic/flow.cpp)"},
      {"dynamic.max_patch_difference", "20", "a constant, kMaxPatchDifference (dynamic/flow.h)"},
      {"dynamic.ransac_threshold", "1", "a constant, kRansacThreshold (dynamic/algorithm1.cpp)"},
      {"dynamic.ransac_confidence", "0.99", "a constant, kRansacConfidence (dynamic/algorithm1.cpp)"},
      {"dynamic.ransac_iterations", "1000", "a constant, kRansacIterations (dynamic/algorithm1.cpp)"},
      {"dynamic.min_static_pairs", "20", "a constant, kMinStaticPairs (dynamic/algorithm1.cpp)"},
      {"dynamic.max_box_area", "0.7", "a constant, kMaxBoxArea (system/dynamic_stage.cpp); dynamic.refinements.box_area_limit switches it off"},
      {"dynamic.box_depth_band", "0.6", "a constant, kBoxDepthBand (dynamic/refinements.cpp); dynamic.refinements.box_depth_band switches it off"},
      {"dynamic.carry_frames", "8", "a constant, kCarryFrames (system/dynamic_stage.cpp); dynamic.refinements.box_carry switches it off"},
      {"dynamic.carry_iou", "0.3", "a constant, kCarryIou (system/dynamic_stage.cpp)"},
      {"dynamic.carry_min_motion", "0.2", "a constant, kCarryMinMotion (system/dynamic_stage.cpp)"},
      {"dynamic.judge_appearance_pairs", "true", "dynamic.refinements.appearance_pairs"},
      {"dynamic.min_kept_ratio", "0.2", "a constant, kMinKeptRatio (dynamic/algorithm1.h); dynamic.refinements.fallback switches it off"},
      {"dynamic.relax_factor", "2", "a constant, kRelaxFactor (dynamic/algorithm1.h)"},
      {"dynamic.relax_steps", "3", "a constant, kRelaxSteps (dynamic/algorithm1.h)"},
      {"dynamic.undistort_pairs", "true", "dynamic.refinements.undistort_pairs"},
      {"dynamic.first_frame_rejudge", "true", "dynamic.refinements.first_frame_rejudge"},
      {"dynamic.prior_cell", "20", "a constant, kPriorCell (system/dynamic_stage.cpp); dynamic.refinements.prior_cells switches it off"},
      {"dynamic.prior_memory", "5", "a constant, kPriorMemory (system/dynamic_stage.cpp)"},
      {"dynamic.depth_check", "true", "dynamic.refinements.depth_check"},
      {"dynamic.motion_threshold", "2", "a constant, kMotionThreshold (dynamic/motion.cpp)"},
      {"dynamic.motion_iterations", "100", "a constant, kMotionIterations (dynamic/motion.cpp)"},
      {"dynamic.motion_min_inliers", "30", "a constant, kMotionMinInliers (dynamic/motion.h)"},
      {"dynamic.depth_max_share", "0.5", "a constant, kDepthMaxShare (dynamic/depth_check.h)"},
      {"dynamic.depth_tolerance", "0.03", "a constant, kDepthTolerance (dynamic/depth_check.h)"},
      {"dynamic.depth_tolerance_quadratic", "0.006", "a constant, kDepthToleranceQuadratic (dynamic/depth_check.h)"},
      {"dynamic.reprojection_tolerance", "3", "a constant, kReprojectionTolerance (dynamic/depth_check.h)"},
      {"dynamic.reprojection_median_factor", "3", "a constant, kReprojectionMedianFactor (dynamic/depth_check.h)"},
      {"dynamic.confirm_static", "0.33", "a constant, kConfirmStatic (dynamic/depth_check.h)"},
      {"dynamic.depth_check_window", "1", "a constant, kDepthCheckWindow (dynamic/depth_check.h)"},
      {"dynamic.depth_min", "0.2", "a constant, kDepthMin (dynamic/depth_check.h)"},
      {"dynamic.depth_max", "6", "a constant, kDepthMax (dynamic/depth_check.h)"},
      {"semantic.cloud_stride", "3", "a constant, kCloudStride (semantic/semantic_map.cpp)"},
      {"semantic.cloud_edge_radius", "2", "a constant, kDepthEdgeRadius (semantic/cloud.h); semantic.filters.depth_edges switches it off"},
      {"semantic.box_margin", "0.05", "a constant, kBoxMargin (semantic/dynamic_mask.h)"},
      {"semantic.box_window", "2", "a constant, kBoxWindow (semantic/semantic_mapper.cpp); semantic.filters.box_window switches it off"},
      {"semantic.motion_radius", "25", "a constant, kMotionRadius (semantic/dynamic_mask.h)"},
      {"semantic.motion_segments", "true", "semantic.filters.motion_segments"},
      {"semantic.motion_segment_skip_unjudged", "true", "a constant, kSegmentSkipUnjudged (semantic/dynamic_mask.h)"},
      {"semantic.free_space_filter", "true", "semantic.filters.free_space"},
      {"semantic.consistency_filter", "true", "semantic.filters.see_through"},
      {"semantic.consistency_tolerance", "0.05", "a constant, kConsistencyTolerance (semantic/semantic_map.cpp)"},
      {"semantic.consistency_min_votes", "1", "a constant, kConsistencyMinVotes (semantic/semantic_map.cpp)"},
      {"semantic.min_view_support", "3", "a constant, kMinViewSupport (semantic/semantic_map.h); semantic.filters.view_support switches it off"},
      {"semantic.seen_moving_ratio", "3", "a constant, kSeenMovingRatio (semantic/semantic_map.h); semantic.filters.seen_moving switches it off"},
      {"semantic.cloud_border", "32", "a constant, kImageBorder (semantic/semantic_map.h); semantic.filters.image_border switches it off"},
      {"semantic.octomap_hit", "0.7", "a constant, kOctoMapProbHit (semantic/octomap_builder.cpp)"},
      {"semantic.octomap_miss", "0.4", "a constant, kOctoMapProbMiss (semantic/octomap_builder.cpp)"},
      {"semantic.octomap_clamp_min", "0.12", "a constant, kOctoMapClampMin (semantic/octomap_builder.cpp)"},
      {"semantic.octomap_clamp_max", "0.97", "a constant, kOctoMapClampMax (semantic/octomap_builder.cpp)"},
      {"semantic.object_box_shrink", "0.6", "a constant, kObjectBoxShrink (semantic/objects.cpp)"},
      {"semantic.object_depth_band_width", "1", "a constant, kObjectDepthBandWidth (semantic/objects.h)"},
      {"semantic.object_min_points", "30", "a constant, kObjectMinPoints (semantic/objects.h)"},
      {"semantic.object_min_score", "0.3", "a constant, kObjectMinScore (semantic/semantic_map.cpp)"},
      {"semantic.object_merge_iou", "0.1", "a constant, kObjectMergeIou (semantic/objects.cpp)"},
      {"semantic.object_min_observations", "2", "a constant, kObjectMinObservations (semantic/objects.h)"},
      {"semantic.object_background_planes", "3", "a constant, kObjectBackgroundPlanes (semantic/objects.h)"},
  };
  // clang-format on
  return kRemoved;
}

const RemovedConfigKey* FindRemovedConfigKey(const std::string& key) {
  for (const RemovedConfigKey& r : RemovedConfigKeys()) {
    if (key == r.key) return &r;
  }
  return nullptr;
}

namespace {

bool AsNumber(const std::string& text, double& value) {
  if (text.empty()) return false;
  char* end = nullptr;
  value = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size();
}

}  // namespace

bool SameConfigValue(const std::string& a, const std::string& b) {
  double x = 0, y = 0;
  if (AsNumber(a, x) && AsNumber(b, y)) return x == y;
  bool p = false, q = false;
  if (YAML::convert<bool>::decode(YAML::Node(a), p) && YAML::convert<bool>::decode(YAML::Node(b), q)) return p == q;
  return a == b;
}

}  // namespace sgslam
