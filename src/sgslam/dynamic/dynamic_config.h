// Dynamic feature rejection (paper Sec. III-C/D, Algorithm 1): backward LK flow,
// pair filtering, 7-point RANSAC fundamental matrix, epipolar distance against
// eps_std scaled by the class weight w, a fallback, and an optional RGB-D check.
// Defaults: the release's LK/RANSAC settings; eps_std, the patch limit and
// refine_fundamental measured on the synthetic walkers/degenerate/static presets
// with ground-truth masks (tests/dynamic/rejection_test.cpp prints the tables):
// eps_std 1.0 with w = 5 rejects 95 % of walker keypoints and loses 7 % of static
// ones, most of them background inside person boxes (40 pairs, seed 1).
#pragma once

#include <string>

#include "sgslam/config/checker.h"

namespace sgslam {

struct DynamicConfig {
  std::string mode = "sg";  // none | semantic | geometric | sg (paper Sec. IV-C ablation)
  double eps_std = 1.0;     // px, epipolar distance threshold eps_std (Algorithm 1 lines 6, 10)
  // Lucas-Kanade flow (Algorithm 1 line 1), the release's settings.
  int lk_window = 21;         // px, side of the square LK window
  int lk_levels = 3;          // pyramid levels above the full image (OpenCV maxLevel)
  int lk_iterations = 30;     // per level
  double lk_epsilon = 0.01;   // px, LK stops when the update is smaller
  double lk_max_error = 0.0;  // intensity, LK mean absolute window error above which a pair fails; 0: off
  // Pair filters (Algorithm 1 line 2, after DS-SLAM).
  double border = 8.0;   // px, pairs closer than this to an image edge (either image) are dropped
  int patch_radius = 2;  // px, appearance patch is (2r+1)^2 around both points
  double max_patch_difference = 12.0;  // intensity, zero-mean mean absolute patch difference limit
  // Fundamental matrix (Algorithm 1 line 3).
  double ransac_threshold = 1.0;    // px, OpenCV's symmetric epipolar distance
  double ransac_confidence = 0.99;  // probability
  int ransac_iterations = 1000;     // at most (OpenCV's default)
  int min_static_pairs = 20;        // pairs outside dynamic boxes needed to fit F on them alone
  bool refine_fundamental = false;  // 8-point refit on the RANSAC inliers (measured worse, see epipolar.h)
  bool reject_unmatched = false;    // true: the paper's literal rule, a keypoint without a pair is never kept
  // Fallback when too few keypoints survive (safer than the release's "restore all").
  double min_kept_ratio = 0.2;  // share of keypoints that must be kept
  double relax_factor = 2.0;    // eps_std is multiplied by this per relaxation step
  int relax_steps = 3;          // relaxation steps before keeping the most static-looking keypoints
  // RGB-D consistency check (depth_check.h): catches motion along epipolar lines.
  bool depth_check = false;                  // needs both depth images and the pose T_cur_prev
  double depth_tolerance = 0.03;             // m, depth error allowed at any range
  double depth_tolerance_quadratic = 0.006;  // 1/m, plus this times depth^2 (Kinect-like noise)
  double reprojection_tolerance = 3.0;       // px, reprojection error allowed; 0: depth only
  double depth_min = 0.2;                    // m, valid depth range
  double depth_max = 6.0;                    // m

  template <class V>
  void Visit(V&& v) {
    v("mode", mode, "none | semantic | geometric | sg");
    v("eps_std", eps_std, "px, epipolar distance threshold");
    v("lk_window", lk_window, "px, LK window side");
    v("lk_levels", lk_levels, "LK pyramid levels above the image");
    v("lk_iterations", lk_iterations, "LK iterations per level");
    v("lk_epsilon", lk_epsilon, "px, LK convergence");
    v("lk_max_error", lk_max_error, "intensity, LK window error limit; 0: off");
    v("border", border, "px, image border excluded");
    v("patch_radius", patch_radius, "px, appearance patch radius");
    v("max_patch_difference", max_patch_difference, "intensity, mean absolute patch difference");
    v("ransac_threshold", ransac_threshold, "px, RANSAC epipolar threshold");
    v("ransac_confidence", ransac_confidence, "probability");
    v("ransac_iterations", ransac_iterations, "RANSAC iterations at most");
    v("min_static_pairs", min_static_pairs, "pairs outside dynamic boxes to fit F on them");
    v("refine_fundamental", refine_fundamental, "8-point refit on RANSAC inliers");
    v("reject_unmatched", reject_unmatched, "reject keypoints without a valid flow pair");
    v("min_kept_ratio", min_kept_ratio, "share of keypoints kept at least (fallback)");
    v("relax_factor", relax_factor, "eps_std factor per fallback step");
    v("relax_steps", relax_steps, "fallback relaxation steps");
    v("depth_check", depth_check, "RGB-D motion check");
    v("depth_tolerance", depth_tolerance, "m, depth error allowed");
    v("depth_tolerance_quadratic", depth_tolerance_quadratic, "1/m, extra tolerance times depth^2");
    v("reprojection_tolerance", reprojection_tolerance, "px, reprojection error allowed; 0: off");
    v("depth_min", depth_min, "m, valid depth range");
    v("depth_max", depth_max, "m, valid depth range");
  }
  void Validate(ConfigChecker& c) const;
};

}  // namespace sgslam
