// Keypoints Algorithm 1 could not judge (no valid flow pair: LK failed, or the two
// patches differ too much) are kept outside dynamic boxes. On dyn_dev a quarter of
// the keypoints on the unknown moving box have no pair, against 8 % of the static
// keypoints outside boxes: occlusion edges and appearance change are themselves a
// sign of motion. Such a keypoint is taken as moving when most of the judged
// keypoints around it were rejected (dynamic.unjudged_radius, unjudged_share).
// Thread safety: a free function on const inputs.
#pragma once

#include <cstddef>
#include <vector>

#include <opencv2/core/types.hpp>

#include "sgslam/dynamic/rejection.h"

namespace sgslam::dynamic {

// Indices of the kept, unjudged keypoints (Why::kUnjudged) with at least min_judged
// judged neighbours within radius px of which more than share were rejected by
// geometry or depth.
std::vector<std::size_t> UnjudgedAmongMovers(const std::vector<cv::KeyPoint>& keys,
                                             const std::vector<KeypointVerdict>& verdicts, double radius,
                                             double share, int min_judged);

}  // namespace sgslam::dynamic
