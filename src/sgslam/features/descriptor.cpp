#include "sgslam/features/descriptor.h"

#include "sgslam/features/fast_grid.h"

namespace sgslam::features {

cv::Ptr<cv::ORB> MakeRotatedBrief() {
  // Only nlevels, edgeThreshold, WTA_K and patchSize matter for compute();
  // the detector settings are left at OpenCV's defaults.
  return cv::ORB::create(/*nfeatures=*/500, /*scaleFactor=*/1.2f, /*nlevels=*/1, /*edgeThreshold=*/0,
                         /*firstLevel=*/0, /*WTA_K=*/2, cv::ORB::FAST_SCORE, /*patchSize=*/kPatchSize,
                         /*fastThreshold=*/20);
}

void ComputeDescriptorsInOrder(const cv::Ptr<cv::Feature2D>& orb, const cv::Mat& image,
                               std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors) {
  std::vector<int> class_ids(keypoints.size());
  std::vector<cv::KeyPoint> work = keypoints;
  for (size_t i = 0; i < work.size(); ++i) {
    class_ids[i] = work[i].class_id;
    work[i].class_id = static_cast<int>(i);
  }
  cv::Mat raw;
  if (!work.empty()) orb->compute(image, work, raw);

  // row_of[i]: the row of raw that describes input keypoint i, or -1 if dropped.
  std::vector<int> row_of(keypoints.size(), -1);
  for (size_t r = 0; r < work.size(); ++r) {
    const int i = work[r].class_id;
    if (i >= 0 && static_cast<size_t>(i) < row_of.size()) row_of[static_cast<size_t>(i)] = static_cast<int>(r);
  }

  std::vector<cv::KeyPoint> kept;
  kept.reserve(keypoints.size());
  cv::Mat out(static_cast<int>(work.size()), raw.empty() ? kDescriptorBytes : raw.cols,
              raw.empty() ? CV_8U : raw.type());
  for (size_t i = 0; i < keypoints.size(); ++i) {
    if (row_of[i] < 0) continue;
    raw.row(row_of[i]).copyTo(out.row(static_cast<int>(kept.size())));
    kept.push_back(keypoints[i]);
    kept.back().class_id = class_ids[i];
  }
  keypoints.swap(kept);
  descriptors = out;
}

}  // namespace sgslam::features
