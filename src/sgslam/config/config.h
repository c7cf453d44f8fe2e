// Configuration: one plain struct per module with in-class defaults and the unit of
// each field in its comment. Each struct lists its fields once in Visit(), which
// the YAML loader, the printer and the unknown-key check all use, and checks its
// values in Validate(), which runs before any thread starts.
#pragma once

#include <string>

#include "sgslam/config/checker.h"
#include "sgslam/detection/detector_config.h"
#include "sgslam/dynamic/dynamic_config.h"
#include "sgslam/semantic/semantic_config.h"

namespace sgslam {

// Pinhole camera with radial-tangential distortion, and the RGB-D depth encoding.
// Defaults: TUM freiburg1 (Kinect), as published with the TUM RGB-D benchmark.
struct CameraConfig {
  int width = 640;               // px
  int height = 480;              // px
  double fx = 517.306408;        // px
  double fy = 516.469215;        // px
  double cx = 318.643040;        // px
  double cy = 255.313989;        // px
  double k1 = 0.262383;          // radial distortion (OpenCV model)
  double k2 = -0.953104;         // radial distortion
  double p1 = -0.005358;         // tangential distortion
  double p2 = 0.002628;          // tangential distortion
  double k3 = 1.163314;          // radial distortion
  double fps = 30.0;             // Hz, frame rate of the sensor
  double depth_factor = 5000.0;  // raw depth units per metre (TUM and Bonn: 5000)
  double baseline_fx = 40.0;     // px*m, virtual stereo baseline times fx (ORB-SLAM2 "bf"), for u_r = u - bf/d
  double close_depth = 40.0;     // baselines; points closer than close_depth * bf / fx are "close" (ThDepth)
  // s, rolling-shutter readout, first row to last (camera/rolling_shutter.h); 0: a
  // global shutter. The tum_fr1 preset sets the Kinect's, measured on fr1_rpy.
  double readout = 0.0;

  template <class V>
  void Visit(V&& v) {
    v("width", width, "px");
    v("height", height, "px");
    v("fx", fx, "px");
    v("fy", fy, "px");
    v("cx", cx, "px");
    v("cy", cy, "px");
    v("k1", k1, "radial distortion");
    v("k2", k2, "radial distortion");
    v("p1", p1, "tangential distortion");
    v("p2", p2, "tangential distortion");
    v("k3", k3, "radial distortion");
    v("fps", fps, "Hz");
    v("depth_factor", depth_factor, "raw depth units per metre");
    v("baseline_fx", baseline_fx, "px*m, virtual stereo baseline times fx");
    v("close_depth", close_depth, "baselines, near/far limit of depth points");
    v("readout", readout, "s, rolling-shutter readout time, top row to bottom row; 0: global shutter");
  }
  void Validate(ConfigChecker& c) const;
};

// Reading datasets.
struct DatasetConfig {
  double max_time_difference = 0.02;  // s, RGB-depth association window (TUM associate.py default)
  int prefetch = 3;                   // frames read ahead of the consumer
  double min_median_depth = 0.1;      // m, a first frame whose median depth is below: wrong depth_factor
  double max_median_depth = 20.0;     // m, ... above: wrong depth_factor

  template <class V>
  void Visit(V&& v) {
    v("max_time_difference", max_time_difference, "s, RGB-depth association window");
    v("prefetch", prefetch, "frames read ahead");
    v("min_median_depth", min_median_depth, "m, depth-scale sanity check");
    v("max_median_depth", max_median_depth, "m, depth-scale sanity check");
  }
  void Validate(ConfigChecker& c) const;
};

// ORB features (ORB-SLAM2's settings for 640x480 RGB-D).
struct OrbConfig {
  int features = 1000;           // keypoints per frame, spread over levels and image cells
  double scale_factor = 1.2;     // ratio between pyramid levels
  int levels = 8;                // pyramid levels
  int fast_threshold = 20;       // intensity, FAST threshold tried first in each cell
  int fast_min_threshold = 7;    // intensity, fallback for cells where the first finds nothing
  int cell_size = 35;            // px, FAST is run per cell of this size
  // Threads of the extraction (levels split between them, same output). 0: 2
  // when parallel, no detector thread runs and the machine has more than two
  // cores, else 1 (on two cores local mapping or the detector, paper Fig. 1,
  // has the second one; measured: no gain there).
  int threads = 0;

  template <class V>
  void Visit(V&& v) {
    v("features", features, "keypoints per frame");
    v("scale_factor", scale_factor, "ratio between pyramid levels");
    v("levels", levels, "pyramid levels");
    v("fast_threshold", fast_threshold, "intensity, FAST threshold");
    v("fast_min_threshold", fast_min_threshold, "intensity, FAST fallback threshold");
    v("cell_size", cell_size, "px, FAST cell size");
    v("threads", threads, "extraction threads, 1 or 2; 0: 2 when parallel without a detector on more than 2 cores");
  }
  void Validate(ConfigChecker& c) const;
};

// Tracking (ORB-SLAM2's RGB-D settings unless a comment says otherwise).
struct TrackingConfig {
  int min_init_points = 500;           // keypoints with depth needed to start the map (at most half of orb.features)
  double motion_search_radius = 15.0;  // px at level 0, constant-velocity projection search
  double local_search_radius = 5.0;    // factor, local-map projection search (ORB-SLAM2: 3; 5 measured better on fr1_rpy, whose rolling shutter shifts rows by pixels under fast rotation)
  double descriptor_ratio = 0.7;       // best/second-best ratio, reference keyframe matching
  int min_motion_matches = 20;         // matches needed to trust the motion model
  int min_pose_inliers = 10;           // inliers after pose optimisation (motion / reference)
  int min_local_inliers = 30;          // inliers after local-map tracking
  int recover_candidates = 30;         // keyframes tried per frame while lost (newest 5, then nearest)
  double keyframe_ref_ratio = 0.75;    // new keyframe when tracked points fall below this share of the reference's
  int max_frames_between_keyframes = 30;  // frames; 0: the camera's fps
  int close_tracked_min = 100;         // need a keyframe when fewer close points are tracked ...
  int close_untracked_min = 70;        // ... and at least this many close points are not
  int keyframe_min_new_points = 100;   // points created per keyframe beyond the close range
  bool skip_outlier_depth_points = true;  // no new keyframe point from a pose-outlier keypoint (dynamic modes only)
  // Map points earn the right to set the pose (tracking/trusted_pose.h): a point
  // is trusted once it has matched as a pose inlier trust_hits times at least
  // trust_delay after its keyframe made it; the first keyframe's points are trusted.
  // A frame's pose is fitted to its trusted matches, then every match that agrees
  // joins. A mover is caught by the time it has moved, whatever its image motion
  // in two frames: dyn_dev's unknown box (0.35 m/s, mostly along the view) passes
  // every two-frame test, its points entered the map at each keyframe and set the
  // pose over 100 matches to 28 static. Panels of 5 ORB budgets (900-1100,
  // --sequential), median without -> with (trust_delay 0.3, hits 2, min 20):
  //   dyn_dev sg 0.129 -> 0.041 m; none 0.315 -> 0.128; ground-truth masks 0.080 -> 0.037;
  //   fr1_rpy 300 frames (static) 0.0273 -> 0.0303 (spread 0.020-0.035 -> 0.030-0.033);
  //   fr1_rpy 694 frames 0.0215 -> 0.0223 (spread 0.017-0.026 -> 0.022-0.025).
  // 0.5 s let the box back in before enough points were trusted (sg 0.126 m);
  // 0.2 s gave 0.040 m. 0: off (ORB-SLAM2: every match sets the pose).
  double trust_delay = 0.3;  // s
  int trust_hits = 2;        // late inlier matches that make a point trusted
  int trust_min_points = 20;  // trusted matches a frame needs to be fitted to them first; fewer: all matches
  // A keypoint that dynamic rejection condemned may still match a trusted map point
  // (one that has stayed put in the map) that no kept keypoint matched, in the
  // projection searches, when their descriptors differ by at most this many bits;
  // the match then counts like any other. The two-frame tests condemn static
  // keypoints whose LK flow went wrong in blur (most of fr1_rpy's 10 %); a point
  // that matched where the map put it for trust_delay is static. Rejected keypoints
  // still never make map points. 0: rejected keypoints are never matched (the paper).
  // Ten-budget panels, sequential, fr1_rpy sg / dyn_dev sg: 0 -> 0.0094 / 0.0159 m;
  // 50 -> 0.0091 / 0.0159; 65 -> 0.0092 / 0.0160; 80 -> 0.0086 / 0.0171; 100 (every
  // match) -> 0.0089 / 0.0176: loose matches let movers' keypoints in. README
  // "Rejected keypoints matched to trusted points".
  int rejected_match_distance = 50;
  // With a rolling-shutter camera (camera.readout > 0), keypoints are first
  // corrected with the predicted angular velocity; this fits the frame's angular
  // velocity together with its pose, corrects them again and fits the pose once more.
  bool rolling_shutter_refine = true;
  double rolling_shutter_prior = 1.0;  // rad/s, sigma of the refined velocity around the predicted one
  // With a rolling shutter, a new keyframe goes to local mapping one frame late:
  // when the next frame is tracked, the keyframe's keypoints are corrected again
  // with the central difference of the poses on either side (no lag; the fitted
  // velocity lags by ~1.5 frames), its depth points move with them and the next
  // frame is fitted again (Tracker::KeyFramesWait); the map's first keyframe takes
  // the velocity of the step to the next frame (it had none). Panels of 5 ORB budgets,
  // sequential, off -> on: fr1_rpy none 0.0099 -> 0.0091 m, dyn_dev sg 0.0183 ->
  // 0.0176 (budgets 925-1125: 0.0114 -> 0.0097, 0.0198 -> 0.0161). README "Rolling shutter".
  bool keyframe_velocity_central = true;
  // The same for every frame, for the exported trajectory: when frame n+1 is
  // tracked, frame n's keypoints are corrected with the central difference of the
  // poses of frames n-1 and n+1 and frame n is fitted again to its matches;
  // trajectory.txt takes that pose, trajectory_online.txt and tracking keep the
  // live one (Tracker::RefinePrevious). Panels of 5 ORB budgets, sequential, off
  // -> on: fr1_rpy none 0.0091 -> 0.0082 m, sg 0.0109 -> 0.0095, dyn_dev sg 0.0171
  // -> 0.0159; no gain on the rendered shutter of synth --readout, where the fitted
  // velocity is already good. README "Rolling shutter".
  bool frame_velocity_central = true;

  template <class V>
  void Visit(V&& v) {
    v("min_init_points", min_init_points, "keypoints with depth to start the map");
    v("motion_search_radius", motion_search_radius, "px, motion-model search radius");
    v("local_search_radius", local_search_radius, "factor, local-map search radius");
    v("descriptor_ratio", descriptor_ratio, "best/second ratio, reference keyframe matching");
    v("min_motion_matches", min_motion_matches, "matches to trust the motion model");
    v("min_pose_inliers", min_pose_inliers, "inliers after pose optimisation");
    v("min_local_inliers", min_local_inliers, "inliers after local-map tracking");
    v("recover_candidates", recover_candidates, "keyframes tried per frame while lost");
    v("keyframe_ref_ratio", keyframe_ref_ratio, "tracked share of the reference keyframe's points");
    v("max_frames_between_keyframes", max_frames_between_keyframes, "frames between keyframes at most");
    v("close_tracked_min", close_tracked_min, "close points tracked, keyframe rule");
    v("close_untracked_min", close_untracked_min, "close points untracked, keyframe rule");
    v("keyframe_min_new_points", keyframe_min_new_points, "points created per keyframe");
    v("skip_outlier_depth_points", skip_outlier_depth_points, "no keyframe point from a pose-outlier keypoint");
    v("trust_delay", trust_delay, "s, age at which a map point's inlier matches start to earn it trust; 0: off");
    v("trust_hits", trust_hits, "late inlier matches that make a map point trusted");
    v("trust_min_points", trust_min_points, "trusted matches needed to fit a frame's pose to them first");
    v("rejected_match_distance", rejected_match_distance, "bits; rejected keypoints may match trusted map points no kept keypoint matched within it; 0: never");
    v("rolling_shutter_refine", rolling_shutter_refine, "fit the frame's angular velocity with its pose and correct the keypoints again");
    v("rolling_shutter_prior", rolling_shutter_prior, "rad/s, sigma of the fitted angular velocity around the predicted one");
    v("keyframe_velocity_central", keyframe_velocity_central, "correct a keyframe one frame later with the velocity of the frames around it");
    v("frame_velocity_central", frame_velocity_central, "fit every frame again one frame later with the velocity of the frames around it (exported trajectory)");
  }
  void Validate(ConfigChecker& c) const;
};

// Local mapping.
struct MappingConfig {
  int triangulation_neighbours = 10;  // covisible keyframes searched for new points
  int fusion_neighbours = 10;         // covisible keyframes (and theirs) for duplicate fusion
  int ba_first_iterations = 5;        // local BA, with robust kernel
  int ba_second_iterations = 10;      // local BA, after removing outliers
  // free keyframes of local BA: the new one and its best covisibles. The Schur
  // complement grows with their square, and in a small scene every keyframe is
  // covisible with every other (fr1_rpy: up to 63 free).
  int ba_max_local_keyframes = 25;
  double redundant_ratio = 0.9;       // a keyframe is culled when this share of its points is seen thrice elsewhere
  int queue_size = 3;                 // keyframes waiting for local mapping, beyond which tracking waits
  // frames after a keyframe during which local mapping counts as busy for the
  // keyframe decision (ORB-SLAM2's "idle" rule). --sequential steps the mapper
  // at once, so it always waits this long (an always-idle mapper would take a
  // keyframe on nearly every frame). In parallel, mapping busy beyond this long
  // (a local BA of 150-250 ms) no longer blocks a keyframe: the new keyframe
  // interrupts the BA, as ORB-SLAM2's InterruptBA does. Otherwise parallel runs
  // made 55-60 keyframes on fr1_rpy against 77 sequential, and lost accuracy.
  int busy_frames = 5;
  // One bundle adjustment of the whole map when the sequence ends (what ORB-SLAM2
  // runs after a loop closure), iterations per stage; 0: off. fr1_rpy --mode none
  // --sequential, ORB budgets 900-1100: ATE median 0.0232 -> 0.0215 m, no budget
  // worse, 0.65 s at the end; 20 iterations gave the same as 10. dyn_dev sg:
  // median 0.1274 -> 0.1294 m (within noise). Only trajectory.txt and the maps
  // see it; trajectory_online.txt is what tracking output at the time.
  // Fusing every map point into every keyframe before it (a loop closure's fusion
  // without the loop) gave 0.0255 / 0.0233 m against 0.0260 / 0.0230 at budgets
  // 900 / 950: not done.
  int final_ba_iterations = 10;

  template <class V>
  void Visit(V&& v) {
    v("triangulation_neighbours", triangulation_neighbours, "keyframes searched for new points");
    v("fusion_neighbours", fusion_neighbours, "keyframes searched for duplicates");
    v("ba_first_iterations", ba_first_iterations, "local BA iterations with robust kernel");
    v("ba_second_iterations", ba_second_iterations, "local BA iterations after outlier removal");
    v("ba_max_local_keyframes", ba_max_local_keyframes, "free keyframes in local BA, best covisibles first");
    v("redundant_ratio", redundant_ratio, "share of points seen elsewhere to cull a keyframe");
    v("queue_size", queue_size, "keyframes queued for local mapping");
    v("busy_frames", busy_frames, "frames after a keyframe that mapping counts as busy; later keyframes interrupt its BA");
    v("final_ba_iterations", final_ba_iterations, "global BA iterations per stage when the sequence ends; 0: off");
  }
  void Validate(ConfigChecker& c) const;
};

struct Config {
  CameraConfig camera;
  DatasetConfig dataset;
  OrbConfig orb;
  TrackingConfig tracking;
  MappingConfig mapping;
  DetectorConfig detector;
  DynamicConfig dynamic;
  SemanticConfig semantic;

  template <class V>
  void VisitSections(V&& v) {
    v("camera", camera);
    v("dataset", dataset);
    v("orb", orb);
    v("tracking", tracking);
    v("mapping", mapping);
    v("detector", detector);
    v("dynamic", dynamic);
    v("semantic", semantic);
  }
  template <class V>
  void VisitSections(V&& v) const {
    const_cast<Config*>(this)->VisitSections(v);  // the visitors never write through const
  }

  // Throws ConfigError naming `source` and every bad key with its value.
  void Validate(const std::string& source) const;
};

}  // namespace sgslam
