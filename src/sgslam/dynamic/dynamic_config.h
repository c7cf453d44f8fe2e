// Dynamic feature rejection (paper Sec. III-C/D, Algorithm 1): backward LK flow,
// pair filtering, 7-point RANSAC fundamental matrix, epipolar distance against
// eps_std scaled by the class weight w, a fallback, and an RGB-D check.
// Defaults: the release's LK/RANSAC settings; eps_std, max_patch_difference,
// depth_check, depth_max_share and prior_cell measured on dyn_dev (real TUM
// fr1_rpy frames with composited movers and ground-truth masks, 300 frames,
// Yolo-Fastest boxes), sg mode, share of moving keypoints rejected / of static
// keypoints lost / precision:
//   eps_std 1, patch 12, no RGB-D check (the former defaults): 54.6 / 31.1 / 38.8 %
//   eps_std 3 + RGB-D check (PnP motion):                      63.1 / 26.4 / 46.4 %
//   ... + prior_cell 20, depth_max_share 0.5:                  64.2 / 23.4 / 49.8 %
//   ... + max_patch_difference 20 (16: 67.2 / 23.6, 24: 70.0 / 25.0): 71.4 / 23.4 / 52.5 %
// On the static tum_fr1_rpy (300 frames) sg then rejects 11 % instead of 16.5 %.
// Real fr1 pairs are noisy (fast rotation, blur, rolling shutter): the static
// median epipolar distance is 0.23 px and its 90th percentile 0.9 px, so eps_std 1
// with w = 5 (d < 0.2 px inside person boxes) throws away most static points in
// the boxes. The synthetic presets (tests/dynamic/rejection_test.cpp) are
// noise-free and are tested at eps_std 1.
#pragma once

#include <string>

#include "sgslam/config/checker.h"

namespace sgslam {

struct DynamicConfig {
  std::string mode = "sg";  // none | semantic | geometric | sg (paper Sec. IV-C ablation)
  // Evaluation only: a folder with mask.txt + mask/*.png (sgslam synth, dyn_dev).
  // Its ground-truth masks replace the mode's verdicts: exactly the keypoints on
  // moving pixels are rejected. It measures what perfect rejection would give the
  // rest of the system (with --mode none, no detector or flow runs). Empty: off.
  std::string truth_masks;
  double eps_std = 3.0;     // px, epipolar distance threshold eps_std (Algorithm 1 lines 6, 10)
  // Lucas-Kanade flow (Algorithm 1 line 1), the release's settings.
  int lk_window = 21;         // px, side of the square LK window
  int lk_levels = 3;          // pyramid levels above the full image (OpenCV maxLevel)
  int lk_iterations = 30;     // per level
  double lk_epsilon = 0.01;   // px, LK stops when the update is smaller
  double lk_max_error = 0.0;  // intensity, LK mean absolute window error above which a pair fails; 0: off
  // Off by default; a speed option. LK starts where the tracker's motion model
  // puts a static keypoint in the previous image (flow_guess.h) instead of at the
  // keypoint itself, and then needs fewer levels: the pyramid only has to reach
  // the prediction's error and a mover's own motion, not the whole image motion. A
  // probe of lk_probe keypoints (a stride over all) is tracked first with lk_levels
  // from the keypoints themselves; their median offset from the prediction moves
  // every start, for when the motion model is off (a jerk of the hand-held camera).
  // Without a prediction (the first frames, after a loss) LK runs with lk_levels.
  // Measured (2026-12-03), sg, sequential panels of ten ORB budgets (900-1125),
  // ATE median (min - max); parallel runs, median frame / rejection ms:
  //   off:                      dyn_dev 0.0192 m (0.0168 - 0.0224), fr1_rpy 0.0112 (0.0097 - 0.0131);
  //                             24.8 / 13.1 ms, 83.9 % moving rejected, 18.6 % static lost
  //   on, 1 level, probe 40:    dyn_dev 0.0203 (0.0167 - 0.0267), fr1_rpy 0.0122 (0.0111 - 0.0173);
  //                             22.6 / 9.6 ms, 84.1 %, 17.5 %
  //   on, 1 level, no probe:    5 budgets: dyn_dev 0.0210 with 11 lost frames (the blurred 113-117)
  //   on, 2 levels, probe 40:   5 budgets: dyn_dev 0.0196 (0.0193 - 0.0224)
  // A 3.5 ms faster rejection for a 5-9 % higher ATE median: a start at the motion
  // model's guess pulls LK in blurred texture towards that guess, and the pairs
  // then confirm the model rather than measure it.
  bool lk_predict = false;
  // px; > 0: a keypoint outside the dynamic boxes that eq. (4) or the RGB-D check
  // rejects is tracked forward again from its flow position; landing farther
  // than this from itself, its pair is unreliable and it is kept untested. dyn_dev
  // sg (moving rejected / static lost): off 83.9 / 18.6 %, 1 px 79.1 / 15.0 %, 3 px
  // 79.9 / 16.1 %; ATE panels at 1 px no better (README), so off.
  double forward_check = 0.0;
  int lk_levels_predicted = 1;
  int lk_probe = 40;
  // Pair filters (Algorithm 1 line 2, after DS-SLAM).
  double border = 8.0;   // px, pairs closer than this to an image edge (either image) are dropped
  int patch_radius = 2;  // px, appearance patch is (2r+1)^2 around both points
  double max_patch_difference = 20.0;  // intensity, zero-mean mean absolute patch difference limit (fr1 blur)
  // Fundamental matrix (Algorithm 1 line 3).
  double ransac_threshold = 1.0;    // px, OpenCV's symmetric epipolar distance
  double ransac_confidence = 0.99;  // probability
  int ransac_iterations = 1000;     // at most (OpenCV's default)
  int min_static_pairs = 20;        // pairs outside dynamic boxes needed to fit F on them alone
  // Share of the image above which a box takes no part in the rejection (1: all do).
  // Yolo-Fastest's whole-view false positives on dyn_dev (a "person" over 83 % of
  // frame 67, a "cat" over half of frame 53) throw out the static background and
  // leave the F fit to the unknown moving box; a box that large has no outside to
  // contrast with anyway. Measured on dyn_dev sg: sequential ATE 0.0927 m at 0.7
  // against 0.1302 at 1 (0.6: 0.092 m with 8 frames lost; 0.5: 0.110 m); parallel, 16
  // runs: 0.047-0.137 m, median 0.094, against 0.119-0.144 (median 0.133, 4 runs).
  // fr1_rpy sg sequential: 0.0204 m against 0.0202.
  double max_box_area = 0.7;
  // sg: keypoints measured this far (m) behind the object's depth in a dynamic box
  // are its background and keep w = 1 (regions.h, KeypointWeightsWithDepth); 0: off.
  // A box frames its background, which Algorithm 1 then holds to d < eps / w. dyn_dev
  // sg panels (5 ORB budgets, sequential), median ATE / static keypoints lost:
  // off 0.0407 m / 24.2 %; 0.3 m 0.0365 / 20.1 %; 0.45 m 0.0386 / 20.9 %; 0.6 m
  // 0.0371 / 21.2 % (moving keypoints rejected 69.5-70.7 % in all). 0.6 m since a
  // real body is deeper than dyn_dev's flat cut-outs: an arm or a back up to 0.6 m
  // behind the nearest quarter of the box's middle stays part of the person.
  double box_depth_band = 0.6;
  // sg: a moving-object box the detector misses in the next frames is carried
  // (shifted by the flow) for up to this many frames (box_carry.h); 0: off. A fresh
  // detection of its class with IoU >= carry_iou replaces it. Only boxes with at
  // least carry_min_motion of their keypoints beyond eps_std (unweighted) or flagged
  // by the RGB-D check are carried; semantic mode has no such evidence and carries
  // none (carrying all its boxes left 78 of dyn_dev's 300 frames tracked).
  // dyn_dev sg panels (scripts/ate_panel.sh, 5 ORB budgets, sequential), medians of
  // ATE / moving keypoints rejected / static lost / cloud on movers / OctoMap path
  // cells occupied: off 0.0357 m / 68.9 % / 20.5 % / 0.85 % / 104; 3 frames 0.0369 /
  // 72.8 / 21.9 / 0.57 / 66; 5 frames 0.0350 / 74.3 / 22.0 / 0.51 / 74; 8 frames
  // 0.0368 / 75.3 / 22.3 / 0.46 / 47. fr1_rpy (static) sg: off 0.0204 m, 5 frames
  // 0.0223, 8 frames 0.0223 (8 with carry_min_motion 0.3: 0.0226); none 0.0223.
  int carry_frames = 8;
  double carry_iou = 0.3;
  double carry_min_motion = 0.2;
  bool refine_fundamental = false;  // 8-point refit on the RANSAC inliers (measured worse, see epipolar.h)
  bool reject_unmatched = false;    // true: the paper's literal rule, a keypoint without a pair is never kept
  // A keypoint whose backward flow converged but whose patches differ (line 2's
  // appearance filter) is rejected outside the boxes when that pair is beyond
  // eps_std. On dyn_dev (sg, per-keypoint dump against the masks) the appearance
  // filter left 7.4k moving and 8.0k static keypoints untested and kept; 3.6k and
  // 2.7k of them are beyond 3 px. Panels (5 ORB budgets, sequential), median ATE /
  // moving rejected / static lost / cloud on movers / OctoMap path cells: off
  // 0.0371 m / 78.0 % / 18.7 % / 0.42 % / 40; on 0.0364 / 82.3 / 20.1 / 0.40 / 50;
  // fr1_rpy (static) sg on 0.0219 m (none 0.0223).
  bool judge_appearance_pairs = true;
  // Geometry on undistorted pixels: LK runs on the raw images, the pairs are then
  // undistorted (Camera::Undistort) before F, eq. (4) and the RGB-D check.
  bool undistort_pairs = true;
  // With a rolling-shutter camera (camera.readout > 0): the pairs are moved to their
  // frames' middle-row cameras before F and the RGB-D check, the previous frame's
  // with the tracker's velocity and the current one's with a velocity fitted to the
  // pairs (rolling_pairs.h); that fit is then the check's motion. Off: it fits the
  // pairs better but did not help. On fr1_rpy (sg, budget 1000) the median PnP
  // residual of fast frames fell 2-4x (1.4 -> 0.4 px) and 91.2 % of the keypoints
  // were kept instead of 89.8 %; what the check still flags are wrong LK flows
  // (10-260 px off). dyn_dev sg (moving rejected / static lost): 84.5 / 19.2 %
  // against 83.9 / 18.6 %. Sequential panels over ten ORB budgets (900-1125), ATE
  // median: fr1_rpy 0.0094 m (0.0077 - 0.0143) against 0.0094; dyn_dev 0.0173 m
  // (0.0161 - 0.0188) against 0.0159 (2026-12-03).
  bool rolling_shutter_pairs = false;
  // sg: the first frame has no flow, so its boxes alone judge it; a false box there
  // (fr1_rpy: a "person" over half of frame 0) kept its keypoints out of the first
  // keyframe for good, and frame 1 was lost in every run. With this, Algorithm 1
  // runs on the first frame's keypoints again once frame 1 is there (as the other
  // image); those the boxes rejected and it keeps join the map before frame 1 is
  // tracked (Tracker::ConfirmStaticInFirstKeyFrame). fr1_rpy sg: 156 of 595 back,
  // frame 1 tracked in all ten panel runs, ATE ten-budget median 0.0094 m either
  // way (worst 0.0111 against 0.0133); dyn_dev unchanged (its frame 0 keeps all).
  bool first_frame_rejudge = true;
  // Temporal prior for the model fits (F and PnP): pairs whose previous point lies
  // in a cell of this size where the previous frame rejected most keypoints are
  // left out of the fit (a large textured moving object can otherwise carry F).
  // 0: off. The decision itself (Algorithm 1) does not use it.
  int prior_cell = 20;  // px
  // Frames a rejected keypoint keeps its cell out of the fits when its flow-tracked
  // successors are kept (1: the previous frame's verdicts only). A slow mover can
  // pass eq. (4) in a frame where its motion runs along the epipolar lines; the
  // next frame's PnP of the RGB-D check then locked on it and flagged the static
  // background (dyn_dev frames 59-67: 150-267 static keypoints a frame flagged,
  // 10-37 of the box's 400). Remembered, the box stays out of the fits through
  // that frame. dyn_dev sg panels (5 ORB budgets, sequential, with confirm_static
  // 0.33), median ATE / moving rejected / static lost / cloud on movers / OctoMap
  // path cells: 1: 0.0343 m / 74.0 % / 19.1 % / 0.51 % / 52; 3: 0.0365 / 75.9 /
  // 18.5 / 0.35 / 42; 5: 0.0371 / 78.0 / 18.7 / 0.42 / 40; 8: 0.0359 / 78.6 / 18.5 /
  // 0.39 / 35 (but 9 frames lost in the panel against 3 at 5).
  int prior_memory = 5;  // frames
  // Fallback when too few keypoints survive (safer than the release's "restore all").
  double min_kept_ratio = 0.2;  // share of keypoints that must be kept
  double relax_factor = 2.0;    // eps_std is multiplied by this per relaxation step
  int relax_steps = 3;          // relaxation steps before keeping the most static-looking keypoints
  // RGB-D consistency check (depth_check.h): catches motion along epipolar lines.
  bool depth_check = true;                   // needs both depth images and a motion (depth_motion)
  std::string depth_motion = "pnp";          // pnp: PnP RANSAC on the pairs (motion.h) | tracker: motion model
  double motion_threshold = 2.0;             // px, PnP RANSAC inlier threshold
  int motion_iterations = 100;               // PnP RANSAC iterations at most
  int motion_min_inliers = 30;               // fewer inliers: no motion, the RGB-D check is skipped
  double depth_max_share = 0.5;              // the check flags more of the checked pairs: distrusted, ignored
  double depth_tolerance = 0.03;             // m, depth error allowed at any range
  double depth_tolerance_quadratic = 0.006;  // 1/m, plus this times depth^2 (Kinect-like noise)
  double reprojection_tolerance = 3.0;       // px, reprojection error allowed; 0: depth only
  // sg: the reprojection tolerance is at least this times the frame's median residual
  // (depth_check.h); 0: off. Geometric mode keeps the fixed tolerance: there movers
  // fill up to half of a dyn_dev frame and lift the median (panel 0.147 m against 0.043). On the static fr1_rpy the fixed 3 px flagged 16k of the
  // first 300 frames' 300k keypoints, mostly in fast turns. sg panels (5 ORB
  // budgets, sequential), median ATE, off -> 3: fr1_rpy 694 frames 0.0233 -> 0.0204 m
  // (none 0.0223), its first 300 0.0320 -> 0.0265, dyn_dev 0.0371 -> 0.0357 (moving
  // keypoints rejected 70.7 -> 68.9 %, static lost 21.2 -> 20.5 %). 2: 0.0312 and
  // 0.0400 m; 5: dyn_dev 0.0381 m, 66.1 % rejected.
  double reprojection_median_factor = 3;
  // sg: a keypoint in a dynamic box whose RGB-D check passes within this share of
  // both tolerances is judged at w = 1 (d < eps_std): direct evidence of a static
  // point outweighs the box's prior weight; 0: off. On dyn_dev (sg, per-keypoint
  // dump against the masks) the box weight alone rejected 11.3k static and 5.6k
  // moving keypoints that the unweighted test and the RGB-D check passed; within a
  // half of the tolerances 8.8k / 2.9k, a third 6.5k / 1.2k, a quarter 4.9k / 0.7k.
  // Panels (as prior_memory, memory 1), median ATE / moving rejected / static lost:
  // off 0.0368 m / 75.3 % / 22.3 %; 0.33: 0.0343 / 74.0 / 19.1; 0.25: 0.0376 / 74.3 / 19.9.
  double confirm_static = 0.33;
  // px, half-size of the window of previous depths the RGB-D check lifts a point
  // with (depth_check.h); 0: the pixel itself. A static point next to a depth edge
  // (or under fr1's depth-to-colour offset) lifted with the other surface's depth
  // lands pixels off. dyn_dev sg panels (5 ORB budgets, sequential), median ATE /
  // moving rejected / static lost / cloud on movers / OctoMap path cells: 0:
  // 0.0364 m / 82.3 % / 20.1 % / 0.40 % / 50; 1: 0.0357 / 83.9 / 19.0 / 0.33 / 48.
  // fr1_rpy sg: 0.0219 m (0.0194 - 0.0234) at 0, 0.0225 (0.0214 - 0.0255) at 1;
  // none 0.0223.
  int depth_check_window = 1;
  double depth_min = 0.2;                    // m, valid depth range
  double depth_max = 6.0;                    // m
  // On top of Algorithm 1, off by default: measured on dyn_dev (sg, sequential,
  // Yolo-Fastest) none of them lowered the ATE (0.1305 m without them):
  //   track_check                    recall 76.1 %, static loss 30.1 %, ATE 0.158-0.177 m
  //   track_check + track_motion     73.9 / 28.5 %, ATE 0.183-0.198 m
  //   track_rescue (+ track_motion)  68.4 / 23.3 %, ATE 0.197 m
  //   unjudged_radius 20             77.3 / 26.5 %, ATE 0.167 m
  // (ATE on this sequence swings by +-0.03 m with any change; see track_memory.h for
  // why the tracks lose where the box dominates the view).
  // Multi-frame check (track_memory.h): keypoint tracks whose anchor, moved by the
  // frame-to-frame motion, no longer projects onto them are rejected.
  bool track_check = false;
  double track_radius = 2.0;     // px at pyramid level 0, keypoint-to-flow association radius
  int track_min_age = 3;         // frames a track must span before it is judged
  int track_max_age = 10;        // frames after which a static track is re-anchored
  double track_tolerance = 3.0;  // px, residual allowed at any age
  double track_growth = 1.0;     // px, plus this times sqrt(age) (chained motion noise)
  bool track_rescue = false;            // geometry-rejected keypoints in dynamic boxes with a static track are kept
  double track_rescue_tolerance = 3.0;  // px, the track's residual at most for that
  bool track_motion = false;         // the frame-to-frame motion from the anchors, also for the RGB-D check
  double track_fit_threshold = 3.0;  // px, its PnP RANSAC inlier threshold
  // Unjudged keypoints (no valid flow pair) among rejected neighbours (neighbours.h).
  double unjudged_radius = 0.0;  // px, neighbourhood; 0: off
  double unjudged_share = 0.5;   // share of the judged neighbours rejected above which it is rejected

  template <class V>
  void Visit(V&& v) {
    v("mode", mode, "none | semantic | geometric | sg");
    v("truth_masks", truth_masks, "evaluation: folder of ground-truth masks that replace the verdicts; empty: off");
    v("eps_std", eps_std, "px, epipolar distance threshold");
    v("lk_window", lk_window, "px, LK window side");
    v("lk_levels", lk_levels, "LK pyramid levels above the image");
    v("lk_iterations", lk_iterations, "LK iterations per level");
    v("lk_epsilon", lk_epsilon, "px, LK convergence");
    v("lk_max_error", lk_max_error, "intensity, LK window error limit; 0: off");
    v("lk_predict", lk_predict, "LK starts at the motion model's prediction");
    v("forward_check", forward_check, "px, forward-backward limit for rejected keypoints outside boxes; 0: off");
    v("lk_probe", lk_probe, "keypoints tracked with the full pyramid to correct the prediction; 0: off");
    v("lk_levels_predicted", lk_levels_predicted, "LK pyramid levels above the image when LK starts at a prediction");
    v("border", border, "px, image border excluded");
    v("patch_radius", patch_radius, "px, appearance patch radius");
    v("max_patch_difference", max_patch_difference, "intensity, mean absolute patch difference");
    v("ransac_threshold", ransac_threshold, "px, RANSAC epipolar threshold");
    v("ransac_confidence", ransac_confidence, "probability");
    v("ransac_iterations", ransac_iterations, "RANSAC iterations at most");
    v("min_static_pairs", min_static_pairs, "pairs outside dynamic boxes to fit F on them");
    v("max_box_area", max_box_area, "image share above which a detection takes no part in the rejection");
    v("box_depth_band", box_depth_band, "m, sg: keypoints this far behind a dynamic box's object keep w = 1; 0: off");
    v("carry_frames", carry_frames, "frames a missed moving-object box is carried over; 0: off");
    v("carry_iou", carry_iou, "IoU of a fresh detection that replaces a carried box");
    v("carry_min_motion", carry_min_motion, "share of a box's keypoints showing motion for it to be carried");
    v("refine_fundamental", refine_fundamental, "8-point refit on RANSAC inliers");
    v("reject_unmatched", reject_unmatched, "reject keypoints without a valid flow pair");
    v("judge_appearance_pairs", judge_appearance_pairs, "reject keypoints whose appearance-failed pair is beyond eps_std");
    v("min_kept_ratio", min_kept_ratio, "share of keypoints kept at least (fallback)");
    v("relax_factor", relax_factor, "eps_std factor per fallback step");
    v("relax_steps", relax_steps, "fallback relaxation steps");
    v("undistort_pairs", undistort_pairs, "undistort flow pairs before F and eq. 4");
    v("rolling_shutter_pairs", rolling_shutter_pairs, "move flow pairs to their middle-row cameras (rolling shutter)");
    v("first_frame_rejudge", first_frame_rejudge, "sg: judge the first frame's box-rejected keypoints again with the second frame's flow");
    v("prior_cell", prior_cell, "px, cells of the previous frame's rejections left out of the fits; 0: off");
    v("prior_memory", prior_memory, "frames a rejection keeps its cell out of the fits (1: the previous frame only)");
    v("depth_check", depth_check, "RGB-D motion check");
    v("depth_motion", depth_motion, "pnp | tracker: camera motion of the RGB-D check");
    v("motion_threshold", motion_threshold, "px, PnP RANSAC inlier threshold");
    v("motion_iterations", motion_iterations, "PnP RANSAC iterations at most");
    v("motion_min_inliers", motion_min_inliers, "PnP inliers needed for the RGB-D check");
    v("depth_max_share", depth_max_share, "share of checked pairs above which the RGB-D check is ignored");
    v("depth_tolerance", depth_tolerance, "m, depth error allowed");
    v("depth_tolerance_quadratic", depth_tolerance_quadratic, "1/m, extra tolerance times depth^2");
    v("reprojection_tolerance", reprojection_tolerance, "px, reprojection error allowed; 0: off");
    v("confirm_static", confirm_static, "sg: share of the RGB-D tolerances within which a keypoint in a dynamic box is judged at w = 1; 0: off");
    v("reprojection_median_factor", reprojection_median_factor, "reprojection tolerance at least this times the frame's median residual; 0: off");
    v("depth_check_window", depth_check_window, "px, half-size of the previous-depth window of the RGB-D check; 0: the pixel");
    v("depth_min", depth_min, "m, valid depth range");
    v("depth_max", depth_max, "m, valid depth range");
    v("track_check", track_check, "multi-frame anchor check of keypoint tracks");
    v("track_radius", track_radius, "px, track association radius at level 0");
    v("track_min_age", track_min_age, "frames a track spans before it is judged");
    v("track_max_age", track_max_age, "frames before a static track is re-anchored");
    v("track_tolerance", track_tolerance, "px, track residual allowed");
    v("track_growth", track_growth, "px, extra residual allowed times sqrt(age)");
    v("track_rescue", track_rescue, "keep geometry-rejected keypoints in dynamic boxes whose track stayed static");
    v("track_rescue_tolerance", track_rescue_tolerance, "px, track residual at most for that");
    v("track_motion", track_motion, "frame-to-frame motion from the track anchors (also for the RGB-D check)");
    v("track_fit_threshold", track_fit_threshold, "px, PnP RANSAC threshold of that motion");
    v("unjudged_radius", unjudged_radius, "px, unjudged keypoints among rejected neighbours are rejected; 0: off");
    v("unjudged_share", unjudged_share, "share of rejected judged neighbours for that");
  }
  void Validate(ConfigChecker& c) const;
};

}  // namespace sgslam
