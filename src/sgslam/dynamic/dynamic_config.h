// Dynamic feature rejection (paper Sec. III-C/D, Algorithm 1): backward LK flow,
// pair filtering, 7-point RANSAC fundamental matrix, epipolar distance against
// eps_std scaled by the class weight w, and the refinements R1-R11 of
// docs/algorithm1.md (dynamic/refinements.h). A user sets the ablation mode and
// eps_std, and may switch a refinement off (`refinements`). Every other value is a
// named constant beside its use, with its unit and reason; the LK and RANSAC ones
// are the release's, the others were measured on real fr1 frames with composited
// movers (docs/results-archive.md; docs/algorithm1.md per refinement):
//   lines 1-2: kLk*, kBorder, kPatchRadius (flow.cpp), kMaxPatchDifference (flow.h)
//   line 3:    kRansac*, kMinStaticPairs (algorithm1.cpp)
//   R2:        kBoxDepthBand (refinements.cpp)
//   R5:        kDepth*, kReprojection*, kConfirmStatic (depth_check.h), kMotion* (motion.h, motion.cpp)
//   R7:        kMinKeptRatio, kRelaxFactor, kRelaxSteps (algorithm1.h)
//   R3, R8, R10: kPriorCell, kPriorMemory, kMaxBoxArea, kCarry* (system/dynamic_stage.cpp)
// The synthetic presets of the tests are noise-free and use eps_std 1.
#pragma once

#include <string>

#include "sgslam/common/config_checker.h"

namespace sgslam {

// The refinements of Algorithm 1 that can be switched off (docs/algorithm1.md; R6
// and R9 have no switch here). All on by default; off leaves that step out
// (docs/algorithm1.md gives the paper's rule for each).
struct DynamicRefinements {
  // R1: LK runs on the raw images, then both ends of every pair are undistorted
  // before F, eq. (4) and the RGB-D check. Off: the raw pixels (the paper).
  bool undistort_pairs = true;
  // R2, sg with depth: a keypoint more than kBoxDepthBand (0.6 m) behind its dynamic
  // box's object is the background the box frames and keeps w = 1. Off: every
  // keypoint in the box has the box's w (the paper).
  bool box_depth_band = true;
  // R3 (b), geometric and sg: pairs in kPriorCell (20 px) cells where the previous
  // kPriorMemory (5) frames rejected most keypoints stay out of the F and PnP fits.
  // Off: no prior; F is still fitted outside fresh dynamic boxes in sg (R3 a).
  bool prior_cells = true;
  // R4: a keypoint whose pair failed only the appearance filter is rejected outside
  // the boxes when its d >= eps_std. Off: such keypoints are kept untested (R6).
  bool appearance_pairs = true;
  // R5: the RGB-D check (PnP motion, depth and reprojection errors), eq. (4)'s blind
  // spot; in sg a point it confirms static is judged at w = 1. Off: eq. (4) alone.
  bool depth_check = true;
  // R7: fewer than kMinKeptRatio (20 %) kept: eps_std relaxed, then the most
  // static-looking restored (semantic: all restored). Off: no minimum.
  bool fallback = true;
  // R8: a box over kMaxBoxArea (70 %) of the image takes no part. Off: every box.
  bool box_area_limit = true;
  // R10, sg: a moving-object box the detector misses is carried, moved by the flow,
  // for up to kCarryFrames (8) frames. Off: only the frame's own detections.
  bool box_carry = true;
  // R11, sg with a detector: the first frame, judged by its boxes alone, is judged
  // again with the second frame's flow; static keypoints join the first keyframe.
  // Off: the boxes' verdict stands.
  bool first_frame_rejudge = true;
  // R12, geometric and sg: a confirmed mover track (movers/mover_tracker.h) whose
  // mover no fresh box holds gives Algorithm 1 its predicted box, with its class's w.
  // Off: the tracks are kept and written, not used for the rejection.
  bool track_footprints = true;

  template <class V>
  void Visit(V&& v) {
    v("undistort_pairs", undistort_pairs, "R1: F, eq. 4 and the RGB-D check on undistorted flow pairs");
    v("box_depth_band", box_depth_band, "R2, sg: keypoints over 0.6 m behind a dynamic box's object are its background, w = 1");
    v("prior_cells", prior_cells, "R3: 20 px cells where the last 5 frames rejected most keypoints stay out of the F and PnP fits");
    v("appearance_pairs", appearance_pairs, "R4: a keypoint whose pair failed only the appearance filter is rejected beyond eps_std");
    v("depth_check", depth_check, "R5: the RGB-D check (PnP motion, depth and reprojection errors) against motion along epipolar lines");
    v("fallback", fallback, "R7: under 20 % kept, eps_std is relaxed, then the most static-looking restored (semantic: all)");
    v("box_area_limit", box_area_limit, "R8: a box over 70 % of the image takes no part in the rejection");
    v("box_carry", box_carry, "R10, sg: a moving box the detector misses is carried up to 8 frames with the flow");
    v("first_frame_rejudge", first_frame_rejudge, "R11, sg: the first frame, judged by its boxes alone, is judged again with the second");
    v("track_footprints", track_footprints, "R12: a mover track's predicted box takes the place of a box the detector did not give");
  }
};

struct DynamicConfig {
  std::string mode = "sg";  // none | semantic | geometric | sg (paper Sec. IV-C ablation)
  // px, epipolar distance threshold eps_std (Algorithm 1 lines 6, 10). Real fr1 pairs
  // are noisy (fast rotation, blur, rolling shutter): at 1 px with w = 5 most static
  // points inside person boxes would be rejected.
  double eps_std = 3.0;
  DynamicRefinements refinements;

  template <class V>
  void Visit(V&& v) {
    v("mode", mode, "none | semantic | geometric | sg");
    v("eps_std", eps_std, "px, epipolar distance threshold");
    v("refinements", refinements, "the refinements of Algorithm 1 (docs/algorithm1.md), each switchable");
  }
  void Validate(ConfigChecker& c) const;
};

}  // namespace sgslam
