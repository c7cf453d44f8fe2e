// Where the code departs from the paper's Algorithm 1 (algorithm1.h), in the order
// the steps apply. Each was added because a measurement showed the paper's rule
// failing; docs/algorithm1.md gives each one's reason and measured effect. The
// switch of a step is config `dynamic.refinements.<name>` (DynamicConfig); its sizes
// are named constants, given here with the file that holds them.
//
// In JudgePairs (this file):
//   R1 undistorted pairs      F, eq. (4) and the RGB-D check on undistorted pixels;
//                             LK and depth lookups on the raw ones (switch
//                             undistort_pairs; TrackPairs, undistort_table.h)
//   R2 box depth band         a keypoint well behind its box's object is the
//                             background the box frames: w = 1 (switch
//                             box_depth_band; kBoxDepthBand, refinements.cpp)
//   R3 what F is fitted on    (a) pairs outside fresh dynamic boxes (the authors'
//                             release; kMinStaticPairs, algorithm1.cpp), (b) outside
//                             cells where the previous frames rejected most
//                             keypoints (switch prior_cells; kPriorCell, kPriorMemory,
//                             system/dynamic_stage.cpp)
//   R4 appearance pairs       a keypoint whose flow converged but whose patches
//                             differ is rejected outside the boxes when beyond eps_std
//                             (switch appearance_pairs)
//   R5 RGB-D check            motion along the epipolar line, eq. (4)'s blind spot,
//                             from depth and a PnP motion; a point it confirms static
//                             is judged at w = 1 (switch depth_check; the tolerances,
//                             kDepthMaxShare and kConfirmStatic in depth_check.h, the
//                             PnP in motion.h / motion.cpp)
//   R6 keypoints without d    no pair or no F: rejected in a dynamic box (sg),
//                             kept elsewhere (always on)
//   R7 fallback               too few kept: eps_std relaxed, then the most
//                             static-looking restored (switch fallback; kMinKeptRatio,
//                             kRelaxFactor, kRelaxSteps, algorithm1.h)
// In the dynamic stage (system/dynamic_stage.h), around JudgePairs:
//   R8 box area limit         a box over most of the image takes no part (switch
//                             box_area_limit; kMaxBoxArea, system/dynamic_stage.cpp)
//   R9 detector stride        between detector frames the last boxes follow the flow
//                             (detector.stride)
//   R10 box carry             a mover's box the detector misses is carried a few
//                             frames; carried boxes weigh keypoints but do not take
//                             pairs out of the fits (switch box_carry; kCarryFrames,
//                             kCarryIou, kCarryMinMotion, system/dynamic_stage.cpp;
//                             box_carry.h)
//   R11 first frame           judged by its boxes alone, then again with the second
//                             frame's flow (switch first_frame_rejudge)
//   R12 track footprints      in a frame the detector did not see, a mover track's
//                             predicted box (switch track_footprints;
//                             movers/mover_tracker.h, kUnknownMoverWeight)
// In tracking (tracking/): trusted map points hold the pose against fresh movers
// (tracking.trust_*), and a rolling shutter is corrected (camera.readout).
// Thread safety: free functions on const inputs.
#pragma once

#include <vector>

#include "sgslam/dynamic/algorithm1.h"

namespace sgslam::dynamic {

// R2 and R10: w per keypoint (Algorithm 1 line 6), and the w the fits of R3 use.
// R2 (depth given, sg, config.refinements.box_depth_band): kBoxDepthBand.
struct KeypointWeighting {
  std::vector<double> w;
  std::vector<double> w_fresh;  // without the carried boxes (R10); empty when the frame has none
  const std::vector<double>& fit() const { return w_fresh.empty() ? w : w_fresh; }
};
KeypointWeighting WeighKeypoints(Mode mode, const std::vector<cv::KeyPoint>& keys,
                                 const std::vector<Detection>& detections, const WeightFn& weight,
                                 const DynamicConfig& config, const DepthCheckInput* depth);

// R3: which cells of the previous image the previous frames found mostly dynamic;
// empty: no prior.
struct DynamicPrior {
  int cell = 0;  // px
  cv::Mat dynamic;  // CV_8U, one per cell: frames it stays dynamic (most of its keypoints rejected, or
                    // their predecessors within `memory` frames, MakeDynamicPrior); 0 = static
  bool Dynamic(cv::Point2f p) const { return Memory(p) > 0; }
  int Memory(cv::Point2f p) const;  // frames the cell at p stays dynamic; 0: static or no prior
};

// R3: the prior for the next frame from this frame's verdicts: a cell is dynamic
// when most of its keypoints are; a rejected keypoint counts for `memory` frames,
// passed on through its successors' flow pairs (previous: the prior this frame used).
DynamicPrior MakeDynamicPrior(const std::vector<cv::KeyPoint>& keys, const RejectionResult& result, cv::Size image,
                              int cell, const DynamicPrior* previous = nullptr, int memory = 1);

// R3: the valid pairs (line 2) F may be fitted on: in sg outside fresh dynamic
// boxes, in every mode outside the prior's dynamic cells.
std::vector<bool> PairsForTheFit(Mode mode, const PairSet& pairs, const std::vector<bool>& valid,
                                 const KeypointWeighting& w, const DynamicPrior* prior);

// R4: eq. (4) for the pairs line 2 dropped for their appearance alone.
void MeasureAppearancePairs(const PairSet& pairs, const Eigen::Matrix3d& F, std::vector<KeypointVerdict>& verdicts);

// R5 (config.refinements.depth_check; depth null: off): the RGB-D check with the
// PnP motion of the pairs in `fit` (into r.motion): moved[i] where it flags pair i,
// confirmed[i] where (sg) it passes within params.confirm_static of both
// tolerances. A check that flags more than params.max_share of what it tested is
// ignored (r.depth_ignored).
struct DepthEvidence {
  std::vector<bool> moved, confirmed;
};
DepthEvidence CheckPairDepths(Mode mode, const PairSet& pairs, const std::vector<bool>& valid,
                              const std::vector<bool>& fit, const DepthCheckInput* depth, const DynamicConfig& config,
                              const DepthCheckParams& params, RejectionResult& r);

// R4 (config.refinements.appearance_pairs) and R6: the verdict on a keypoint without d.
void JudgeWithoutDistance(Mode mode, double eps, const DynamicConfig& config, KeypointVerdict& v);

// R7: restores the `missing` rejected keypoints that look most static: finite
// d * w first (smallest first), then those without a test, depth-flagged ones
// last. Returns how many.
int RestoreMostStatic(Mode mode, int missing, std::vector<KeypointVerdict>& verdicts);

}  // namespace sgslam::dynamic
