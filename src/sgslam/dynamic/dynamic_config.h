// Dynamic feature rejection (paper Sec. III-C/D, Algorithm 1): backward LK flow,
// pair filtering, 7-point RANSAC fundamental matrix, epipolar distance against
// eps_std scaled by the class weight w, a fallback, and an RGB-D check. The LK and
// RANSAC defaults are the released code's; the others were measured on real fr1
// frames with composited movers (docs/results-archive.md; docs/algorithm1.md per refinement). The synthetic presets of the
// tests are noise-free and use eps_std 1.
#pragma once

#include <string>

#include "sgslam/common/config_checker.h"

namespace sgslam {

struct DynamicConfig {
  std::string mode = "sg";  // none | semantic | geometric | sg (paper Sec. IV-C ablation)
  // px, epipolar distance threshold eps_std (Algorithm 1 lines 6, 10). Real fr1 pairs
  // are noisy (fast rotation, blur, rolling shutter): at 1 px with w = 5 most static
  // points inside person boxes would be rejected.
  double eps_std = 3.0;
  // Lucas-Kanade flow (Algorithm 1 line 1), the release's settings.
  int lk_window = 21;        // px, side of the square LK window
  int lk_levels = 3;         // pyramid levels above the full image (OpenCV maxLevel)
  int lk_iterations = 30;    // per level
  double lk_epsilon = 0.01;  // px, LK stops when the update is smaller
  // Pair filters (Algorithm 1 line 2, after DS-SLAM).
  double border = 8.0;                 // px, pairs closer than this to an image edge (either image) are dropped
  int patch_radius = 2;                // px, appearance patch is (2r+1)^2 around both points
  double max_patch_difference = 20.0;  // intensity, zero-mean mean absolute patch difference limit
  // Fundamental matrix (Algorithm 1 line 3).
  double ransac_threshold = 1.0;    // px, OpenCV's symmetric epipolar distance
  double ransac_confidence = 0.99;  // probability
  int ransac_iterations = 1000;     // at most (OpenCV's default)
  int min_static_pairs = 20;        // pairs outside dynamic boxes needed to fit F on them alone
  // Share of the image above which a box takes no part in the rejection (1: all
  // do): a box that large is most likely a false detection, and it has no outside
  // to contrast with.
  double max_box_area = 0.7;
  // m, sg: keypoints this far behind the object's depth in a dynamic box are its
  // background and keep w = 1 (regions.h); 0: off. A real body is up to this deep.
  double box_depth_band = 0.6;
  // sg: a moving-object box the detector misses in the next frames is carried
  // (shifted by the flow) for up to carry_frames frames (box_carry.h); 0: off. A
  // fresh detection of its class with IoU >= carry_iou replaces it. Only boxes
  // with at least carry_min_motion of their keypoints showing motion of their own
  // are carried.
  int carry_frames = 8;
  double carry_iou = 0.3;
  double carry_min_motion = 0.2;
  // A keypoint whose backward flow converged but whose patches differ (line 2's
  // appearance filter) is rejected outside the boxes when that pair is beyond
  // eps_std: the flow may be off, but a static point rarely lands far from its line.
  bool judge_appearance_pairs = true;
  // Geometry on undistorted pixels: LK runs on the raw images, the pairs are then
  // undistorted before F, eq. (4) and the RGB-D check.
  bool undistort_pairs = true;
  // sg: the first frame has no flow, so its boxes alone judge it; with this its
  // keypoints are judged again once the second frame is there, and those a false
  // box rejected join the first keyframe (Tracker::ConfirmStaticInFirstKeyFrame).
  bool first_frame_rejudge = true;
  // px; pairs whose previous point lies in a cell of this size where the previous
  // frames rejected most keypoints are left out of the F and PnP fits, so that a
  // large textured mover cannot carry them; 0: off. Algorithm 1 itself does not use it.
  int prior_cell = 20;
  // Frames a rejected keypoint keeps its cell out of the fits while its flow-tracked
  // successors are kept: a slow mover can pass eq. (4) in a frame where it moves
  // along its epipolar line.
  int prior_memory = 5;
  // Fallback when too few keypoints survive (safer than the release's "restore all").
  double min_kept_ratio = 0.2;  // share of keypoints that must be kept
  double relax_factor = 2.0;    // eps_std is multiplied by this per relaxation step
  int relax_steps = 3;          // relaxation steps before keeping the most static-looking keypoints
  // RGB-D consistency check (depth_check.h): catches motion along epipolar lines,
  // eq. (4)'s blind spot. Its camera motion is a PnP RANSAC on the pairs (motion.h).
  bool depth_check = true;
  double motion_threshold = 2.0;             // px, PnP RANSAC inlier threshold
  int motion_iterations = 100;               // PnP RANSAC iterations at most
  int motion_min_inliers = 30;               // fewer inliers: no motion, the RGB-D check is skipped
  double depth_max_share = 0.5;              // the check flags more of the checked pairs: distrusted, ignored
  double depth_tolerance = 0.03;             // m, depth error allowed at any range
  double depth_tolerance_quadratic = 0.006;  // 1/m, plus this times depth^2 (Kinect-like noise)
  double reprojection_tolerance = 3.0;       // px, reprojection error allowed; 0: depth only
  // sg: the reprojection tolerance is at least this times the frame's median
  // residual (fast turns move every static point off together); 0: off. Geometric
  // mode keeps the fixed tolerance, since there movers can fill half the frame.
  double reprojection_median_factor = 3;
  // sg: a keypoint in a dynamic box whose RGB-D check passes within this share of
  // both tolerances is judged at w = 1: direct evidence of a static point outweighs
  // the box's prior weight; 0: off.
  double confirm_static = 0.33;
  // px, half-size of the window of previous depths the RGB-D check lifts a point
  // with; a point next to a depth edge lifted with the other surface's depth lands
  // pixels off. 0: the pixel itself.
  int depth_check_window = 1;
  double depth_min = 0.2;  // m, valid depth range
  double depth_max = 6.0;  // m

  template <class V>
  void Visit(V&& v) {
    v("mode", mode, "none | semantic | geometric | sg");
    v("eps_std", eps_std, "px, epipolar distance threshold");
    v("lk_window", lk_window, "px, LK window side");
    v("lk_levels", lk_levels, "LK pyramid levels above the image");
    v("lk_iterations", lk_iterations, "LK iterations per level");
    v("lk_epsilon", lk_epsilon, "px, LK convergence");
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
    v("judge_appearance_pairs", judge_appearance_pairs, "reject keypoints whose appearance-failed pair is beyond eps_std");
    v("min_kept_ratio", min_kept_ratio, "share of keypoints kept at least (fallback)");
    v("relax_factor", relax_factor, "eps_std factor per fallback step");
    v("relax_steps", relax_steps, "fallback relaxation steps");
    v("undistort_pairs", undistort_pairs, "undistort flow pairs before F and eq. 4");
    v("first_frame_rejudge", first_frame_rejudge, "sg: judge the first frame's box-rejected keypoints again with the second frame's flow");
    v("prior_cell", prior_cell, "px, cells of the previous frame's rejections left out of the fits; 0: off");
    v("prior_memory", prior_memory, "frames a rejection keeps its cell out of the fits (1: the previous frame only)");
    v("depth_check", depth_check, "RGB-D motion check");
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
  }
  void Validate(ConfigChecker& c) const;
};

}  // namespace sgslam
