// SG-SLAM's dynamic feature rejection (paper Sec. III-C and III-D), Algorithm 1:
// which keypoints of the current frame are static enough to track with.
//
//   1   P1 = CalcOpticalFlowPyrLK(F2, F1, P2)       backward flow     TrackPairs
//   2   remove pairs at the edges or too different  pair filters      TrackPairs
//   3   F = FindFundamentalMat(P2, P1, 7-point RANSAC)                JudgePairs
//   4   for each pair (p1, p2):
//         d = |p2^T F p1| / sqrt(X^2 + Y^2), (X Y Z)^T = F p1         eq. (2), (4)
//   5-6   in a dynamic object's box: static when d * w < eps_std      w: the class's prior, 1..5
//   10    elsewhere:                 static when d     < eps_std
//
// Notation: P1/p1 the previous frame's points, P2/p2 the current frame's
// keypoints, F = F_cur_prev (p2^T F p1 = 0, eq. 3), d the offset distance of
// eq. (4) in px, w the prior dynamic weight of the box holding p2 (the largest of
// the boxes holding it; 1 outside), eps_std the standard empirical threshold.
// The paper's ablation (Sec. IV-C) gives the other modes: geometric (w = 1 for
// every keypoint), semantic (every keypoint in a dynamic box rejected, no flow)
// and none.
//
// Lines 1-2 need no boxes, so they run while the detector works on the same frame
// (paper Fig. 1): TrackPairs, then JudgePairs once the boxes are there.
//
// The code departs from the paper where measurements showed it must; each
// departure is a named step of refinements.h, called from JudgePairs in the order
// listed there, with its reason and measured effect in docs/algorithm1.md. Those
// that can be switched off are DynamicConfig::refinements. The constants of the
// steps are named beside their use; those the unit tests vary are Algorithm1Params.
// Thread safety: free functions on const inputs; deterministic for equal inputs.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
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
const char* ModeName(Mode mode);

enum class Why : std::uint8_t {
  kStatic,     // kept: passed the test of its mode (lines 6, 10)
  kUnjudged,   // kept: no valid pair or no F, outside dynamic boxes (refinements.h)
  kFallback,   // kept: restored by the fallback (refinements.h)
  kGeometry,   // rejected: d * w >= eps_std (lines 6, 10)
  kSemantics,  // rejected: in a dynamic box with no geometric evidence (semantic mode, or no pair)
  kDepth,      // rejected: the RGB-D check (refinements.h, depth_check.h)
};

struct KeypointVerdict {
  bool kept = true;
  Why why = Why::kStatic;
  double distance = std::nan("");  // d, px, eq. (4); NaN without a valid pair and F
  // d of a pair whose flow converged but whose patches differ (PairStatus::kAppearance);
  // NaN otherwise (refinements.h, JudgeAppearancePairs).
  double loose_distance = std::nan("");
  double weight = 1.0;  // w: the largest of the dynamic boxes holding the keypoint; 1 outside
  PairStatus pair = PairStatus::kFlowFailed;
  cv::Point2f prev;  // p1, px, in the previous image (pair == kOk)
};

// R7, the fallback (refinements.h): fewer than ceil(min_kept_ratio * keypoints)
// kept: eps_std is multiplied by relax_factor up to relax_steps times, then the most
// static-looking rejected keypoints are restored (RestoreMostStatic; semantic mode
// restores all). DynamicConfig::refinements.fallback false: none of it.
// Not measured on their own (docs/algorithm1.md, R7).
constexpr double kMinKeptRatio = 0.2;  // share of keypoints kept at least; at 0.1 dyn_dev's map started on 102 points
constexpr double kRelaxFactor = 2.0;   // eps_std factor per relaxation step: doubling, so that few steps are needed
constexpr int kRelaxSteps = 3;         // relaxation steps, eps_std up to 8x (24 px) before restoring by rank

struct FallbackParams {
  double min_kept_ratio = kMinKeptRatio;
  double relax_factor = kRelaxFactor;
  int relax_steps = kRelaxSteps;
};

// The values of Algorithm 1's steps that the unit tests vary to check their math;
// every run (DynamicStage) uses the defaults, the named constants.
struct Algorithm1Params {
  FlowParams flow;          // line 2's appearance limit (flow.h)
  DepthCheckParams depth;   // R5, the RGB-D check (depth_check.h)
  FallbackParams fallback;  // R7
};

struct RejectionTiming {  // ms
  double flow = 0, fundamental = 0, depth = 0, decide = 0, total = 0;
};

// Raw px -> undistorted px, in place (Camera::Undistort).
using UndistortPointsFn = std::function<void(std::vector<cv::Point2f>&)>;

// Lines 1-2 for every current keypoint, with undistorted copies for the geometry.
struct PairSet {
  std::vector<cv::Point2f> cur;      // P2, raw keypoint positions
  FlowPairs flow;                    // P1 (raw) and each pair's status
  std::vector<cv::Point2f> prev_un;  // undistorted flow.prev (= raw without undistortion)
  std::vector<cv::Point2f> cur_un;   // undistorted cur
  double ms = 0;                     // flow and undistortion
};

struct RejectionResult {
  std::vector<KeypointVerdict> keypoints;  // one per input keypoint, same order
  int kept = 0, rejected_geometry = 0, rejected_semantics = 0, rejected_depth = 0;
  int in_dynamic_boxes = 0;  // keypoints with w > 1
  int valid_pairs = 0;       // flow pairs that passed line 2
  std::optional<geometry::FundamentalEstimate> fundamental;
  std::optional<MotionEstimate> motion;  // PnP motion of the RGB-D check
  bool depth_ignored = false;            // the check flagged more than DepthCheckParams::max_share: ignored
  double eps_used = 0;  // px, eps_std after the fallback's relaxation
  int relax_steps = 0;  // fallback relaxation steps taken
  int restored = 0;     // keypoints kept by the fallback ranking (or by restore-all)
  RejectionTiming ms;
};

struct DynamicPrior;  // refinements.h

// Lines 1-2. undistort: applied to both ends of every pair when
// config.refinements.undistort_pairs (R1).
PairSet TrackPairs(const FlowFrame& prev, const FlowFrame& cur, const std::vector<cv::KeyPoint>& keys,
                   const DynamicConfig& config, const UndistortPointsFn& undistort = {},
                   const FlowParams& flow = {});

// Lines 3-14 in `mode` (config.mode is not read). depth: the RGB-D check's
// inputs, used when config.refinements.depth_check (null: skipped); its T_cur_prev
// is replaced by the PnP estimate (no estimate: no check). prior: the previous
// frames' rejections (R3, config.refinements.prior_cells; null: none).
RejectionResult JudgePairs(Mode mode, const PairSet& pairs, const std::vector<cv::KeyPoint>& keys,
                           const std::vector<Detection>& detections, const WeightFn& weight,
                           const DynamicConfig& config, const DepthCheckInput* depth = nullptr,
                           const DynamicPrior* prior = nullptr, const Algorithm1Params& params = {});

// Lines 1-14 in config.mode: TrackPairs (geometric and sg) then JudgePairs.
RejectionResult RejectDynamicFeatures(const FlowFrame& prev, const FlowFrame& cur,
                                      const std::vector<cv::KeyPoint>& keys, const std::vector<Detection>& detections,
                                      const WeightFn& weight, const DynamicConfig& config,
                                      const DepthCheckInput* depth = nullptr, const UndistortPointsFn& undistort = {},
                                      const Algorithm1Params& params = {});

inline RejectionResult RejectDynamicFeatures(const cv::Mat& prev_gray, const cv::Mat& cur_gray,
                                             const std::vector<cv::KeyPoint>& keys,
                                             const std::vector<Detection>& detections, const WeightFn& weight,
                                             const DynamicConfig& config, const Algorithm1Params& params = {}) {
  return RejectDynamicFeatures(FlowFrame{prev_gray, {}}, FlowFrame{cur_gray, {}}, keys, detections, weight, config,
                               nullptr, {}, params);
}

}  // namespace sgslam::dynamic
