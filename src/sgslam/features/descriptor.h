// Rotated BRIEF (rBRIEF) descriptors through OpenCV's ORB, so the learned
// 256-pair sampling pattern is OpenCV's. OpenCV's ORB::compute with given
// keypoints may drop keypoints (those within edgeThreshold of the border) and
// regroups them by octave, so rows are matched back to keypoints by an index
// carried in class_id rather than trusting the order.
#pragma once

#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>
#include <vector>

namespace sgslam::features {

inline constexpr int kDescriptorBytes = 32;

// OpenCV ORB set up to describe keypoints given in the coordinates of the image
// passed to compute(): one level (keypoints must have octave 0), 31x31 patch,
// no border filter (our keypoints are already kEdgeThreshold px inside).
// compute() blurs the image with a 7x7, sigma 2 Gaussian before sampling, as
// ORB-SLAM2 does, and keeps each keypoint's angle.
cv::Ptr<cv::ORB> MakeRotatedBrief();

// Computes descriptors of `keypoints` on `image` with `orb`, then puts the
// result back into the input order: on return keypoints[i] matches
// descriptors.row(i), keypoints OpenCV dropped are removed (order of the rest
// kept) and every other field, class_id included, is as given.
// descriptors: CV_8U, kDescriptorBytes columns, keypoints.size() rows.
void ComputeDescriptorsInOrder(const cv::Ptr<cv::Feature2D>& orb, const cv::Mat& image,
                               std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors);

}  // namespace sgslam::features
