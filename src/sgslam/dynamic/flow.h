// Algorithm 1 lines 1-2: the current keypoints are tracked backwards into the
// previous image with pyramidal Lucas-Kanade flow, then pairs whose flow failed,
// that touch the image border or whose patches differ too much in appearance
// (DS-SLAM's check, which the release skips) are removed. The LK settings, the
// border and the patch size are constants of flow.cpp (the release's, DS-SLAM's).
// Thread safety: free functions on const inputs.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

namespace sgslam::dynamic {

// An 8-bit grey image and, optionally, its LK pyramid from BuildFlowPyramid. The
// current frame's pyramid is the next frame's previous one: keep it to save a build.
struct FlowFrame {
  cv::Mat gray;                  // CV_8UC1
  std::vector<cv::Mat> pyramid;  // empty: built inside calcOpticalFlowPyrLK
};

// cv::buildOpticalFlowPyramid with TrackBackward's window and levels, with
// derivatives (LK needs them for its first image, the current one).
std::vector<cv::Mat> BuildFlowPyramid(const cv::Mat& gray);

enum class PairStatus : std::uint8_t { kOk, kFlowFailed, kBorder, kAppearance };

struct FlowPairs {
  std::vector<cv::Point2f> prev;   // px, position in the previous image, per current keypoint
  std::vector<PairStatus> status;  // per current keypoint
  int valid = 0;                   // pairs with status kOk
};

// intensity, line 2's appearance filter: a pair whose zero-mean mean absolute patch
// difference exceeds this is dropped. Measured on one dyn_dev sg run (12 before:
// more moving keypoints rejected at about the same static loss; docs/algorithm1.md).
constexpr double kMaxPatchDifference = 20.0;

// What the tests vary; the pipeline runs at the defaults.
struct FlowParams {
  double max_patch_difference = kMaxPatchDifference;  // intensity
};

// cur_points: keypoint positions in the current image (px, as detected).
FlowPairs TrackBackward(const FlowFrame& prev, const FlowFrame& cur, const std::vector<cv::Point2f>& cur_points,
                        const FlowParams& params = {});

// Zero-mean mean absolute difference of the (2r+1)^2 patches around a (in image_a)
// and b (in image_b), sampled bilinearly; both patches must lie inside their images.
double PatchDifference(const cv::Mat& image_a, cv::Point2f a, const cv::Mat& image_b, cv::Point2f b, int radius);

}  // namespace sgslam::dynamic
