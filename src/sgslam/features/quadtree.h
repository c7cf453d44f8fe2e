// Even spatial distribution of keypoints (ORB-SLAM2's DistributeOctTree idea):
// the best `target` FAST responses cluster on the most textured object, which
// makes pose estimation ill-conditioned and, in dynamic scenes, lets one moving
// person own the frame. Instead the region is split like a quadtree until there
// are `target` cells, and each cell keeps its strongest corner.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace sgslam::features {

// Returns at most `target` of `keypoints` (all of them when there are fewer),
// one per quadtree leaf, each the leaf's highest response; ties go to the
// earlier keypoint, so the result is deterministic. `region` must contain every
// keypoint; its root nodes are roughly square (round(width / height) of them).
std::vector<cv::KeyPoint> DistributeQuadtree(const std::vector<cv::KeyPoint>& keypoints, const cv::Rect2f& region,
                                             int target);

}  // namespace sgslam::features
