// The paper's Algorithm 1 (dynamic feature rejection) and its ablation modes
// (Sec. IV-C): which current keypoints are static enough to track with.
//   sg         inside a dynamic box of weight w: kept when d * w < eps_std (line 6),
//              elsewhere when d < eps_std (line 10)
//   geometric  d < eps_std for every keypoint
//   semantic   every keypoint inside a dynamic box is rejected
//   none       all kept
// Keypoints without a valid flow pair or F cannot be judged geometrically: in sg a
// keypoint inside a dynamic box is rejected (semantics is the only evidence),
// elsewhere kept, as in geometric mode. A pair that failed only the
// appearance filter is kept out of F but, with config.judge_appearance_pairs, its
// keypoint is rejected outside the boxes when the pair is beyond eps.
// Fallback (release: restore every keypoint when < 10 % survive, person present):
// when fewer than min_kept_ratio of the keypoints are kept, eps_std is relaxed by
// relax_factor up to relax_steps times; if still too few, the rejected keypoints
// with the smallest d * w are restored up to the minimum. The most dynamic-looking
// points therefore never come back, unlike the release. Semantic mode has no d and
// falls back to restoring all, as the release does.
// F is fitted on the pairs whose current keypoint lies outside every dynamic box of
// the current frame's detections (the release tests the previous point against the
// previous frame's boxes). With config.depth_check and a DepthCheckInput, pairs the
// RGB-D check flags are rejected in geometric and sg modes whatever their w (the
// check has its own noise model), and the fallback restores them last; a check
// that flags more than config.depth_max_share of the pairs it could test is
// ignored for the frame (its motion must be wrong). In sg, a keypoint in a dynamic
// box that the check passes within config.confirm_static of both tolerances is
// judged at w = 1 (direct evidence outweighs the box's prior). The check uses the
// motion PnP RANSAC finds on the pairs (motion.h, fitted on the same preferred
// pairs as F).
// Geometry (F, eq. 4, PnP, reprojection) uses undistorted pixels when an undistort
// function is given and config.undistort_pairs; LK and the depth lookups use the
// raw positions.
// The work is split in two so that the flow, which needs no detections, can run
// while the detector works (paper Fig. 1: tracking waits for the boxes only once
// the matches are there): TrackPairs (lines 1-2), then JudgePairs (lines 3-14).
// Thread safety: free functions on const inputs; deterministic for equal inputs.
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "sgslam/detection/detection.h"
#include "sgslam/dynamic/depth_check.h"
#include "sgslam/dynamic/dynamic_config.h"
#include "sgslam/dynamic/flow.h"
#include "sgslam/dynamic/motion.h"
#include "sgslam/dynamic/regions.h"
#include "sgslam/geometry/epipolar.h"

namespace sgslam::dynamic {

enum class Mode : std::uint8_t { kNone, kSemantic, kGeometric, kSg };
Mode ParseMode(const std::string& name);  // throws ConfigError for an unknown name

enum class Why : std::uint8_t {
  kStatic,     // kept: passed the test of its mode
  kUnjudged,   // kept: no valid pair or no F, outside dynamic boxes
  kFallback,   // kept: restored by the fallback
  kGeometry,   // rejected: d * w >= eps (Algorithm 1 lines 6, 10)
  kSemantics,  // rejected: inside a dynamic box with no geometric evidence (semantic mode, or no pair)
  kDepth,      // rejected: RGB-D check (depth_check.h)
};

struct KeypointVerdict {
  bool kept = true;
  Why why = Why::kStatic;
  double distance = std::nan("");  // px, eq. (4); NaN without a valid pair and F
  // px, eq. (4) of a pair whose flow converged but whose patches differ (kAppearance);
  // NaN otherwise. With config.judge_appearance_pairs such a keypoint outside the
  // boxes is rejected when it is beyond eps: the flow may be off, but a static point
  // it leads astray rarely lands far from its epipolar line.
  double loose_distance = std::nan("");
  double weight = 1.0;             // largest w of the dynamic boxes holding the keypoint; 1 outside
  PairStatus pair = PairStatus::kFlowFailed;
  cv::Point2f prev;  // px, flow position in the previous image (pair == kOk)
};

struct RejectionTiming {  // ms
  double flow = 0, fundamental = 0, depth = 0, decide = 0, total = 0;
};

// Raw px -> undistorted px, in place (Camera::Undistort).
using UndistortPointsFn = std::function<void(std::vector<cv::Point2f>&)>;

// Algorithm 1 lines 1-2 for every current keypoint, with undistorted copies.
struct PairSet {
  std::vector<cv::Point2f> cur;      // raw keypoint positions
  FlowPairs flow;                    // raw previous positions and pair status
  std::vector<cv::Point2f> prev_un;  // undistorted flow.prev (= raw without undistortion)
  std::vector<cv::Point2f> cur_un;   // undistorted cur
  double ms = 0;                     // flow and undistortion
};

// Which cells of the previous image the previous frame found mostly dynamic
// (config.prior_cell); empty: no prior.
struct DynamicPrior {
  int cell = 0;  // px
  cv::Mat dynamic;  // CV_8U, one per cell: frames it stays dynamic (most of its keypoints rejected, or
                    // their predecessors within prior_memory frames); 0 = static
  bool Dynamic(cv::Point2f p) const { return Memory(p) > 0; }
  int Memory(cv::Point2f p) const;  // frames the cell at p stays dynamic; 0: static or no prior
};

struct RejectionResult {
  std::vector<KeypointVerdict> keypoints;  // one per input keypoint, same order
  int kept = 0, rejected_geometry = 0, rejected_semantics = 0, rejected_depth = 0;
  int in_dynamic_boxes = 0;  // keypoints with w > 1
  int valid_pairs = 0;       // flow pairs that passed line 2
  std::optional<geometry::FundamentalEstimate> fundamental;
  std::optional<MotionEstimate> motion;  // PnP motion of the RGB-D check
  bool depth_ignored = false;            // the check flagged more than config.depth_max_share: ignored
  double eps_used = 0;  // px, eps_std after fallback relaxation
  int relax_steps = 0;  // fallback relaxation steps taken
  int restored = 0;     // keypoints kept by the fallback ranking (or by restore-all)
  RejectionTiming ms;
};

PairSet TrackPairs(const FlowFrame& prev, const FlowFrame& cur, const std::vector<cv::KeyPoint>& keys,
                   const DynamicConfig& config, const UndistortPointsFn& undistort = {});

// depth: the RGB-D check's inputs, used when config.depth_check (null: skipped);
// its T_cur_prev is replaced by the PnP estimate (no estimate: no check). prior:
// config.prior_cell's map of the previous frame.
RejectionResult JudgePairs(const PairSet& pairs, const std::vector<cv::KeyPoint>& keys,
                           const std::vector<Detection>& detections, const WeightFn& weight,
                           const DynamicConfig& config, const DepthCheckInput* depth = nullptr,
                           const DynamicPrior* prior = nullptr);

// The prior for the next frame from this frame's verdicts: a cell is dynamic when
// most of its keypoints are; a rejected keypoint counts for `memory` frames, passed
// on through its successors' flow pairs (previous: the prior this frame used).
DynamicPrior MakeDynamicPrior(const std::vector<cv::KeyPoint>& keys, const RejectionResult& result, cv::Size image,
                              int cell, const DynamicPrior* previous = nullptr, int memory = 1);

// TrackPairs then JudgePairs.
RejectionResult RejectDynamicFeatures(const FlowFrame& prev, const FlowFrame& cur,
                                      const std::vector<cv::KeyPoint>& keys, const std::vector<Detection>& detections,
                                      const WeightFn& weight, const DynamicConfig& config,
                                      const DepthCheckInput* depth = nullptr, const UndistortPointsFn& undistort = {});

inline RejectionResult RejectDynamicFeatures(const cv::Mat& prev_gray, const cv::Mat& cur_gray,
                                             const std::vector<cv::KeyPoint>& keys,
                                             const std::vector<Detection>& detections, const WeightFn& weight,
                                             const DynamicConfig& config) {
  return RejectDynamicFeatures(FlowFrame{prev_gray, {}}, FlowFrame{cur_gray, {}}, keys, detections, weight, config);
}

}  // namespace sgslam::dynamic
