// Boxes of moving objects carried over the frames where the detector misses them.
// A small CPU detector often loses a person it found a few frames earlier; without
// a box those keypoints face only the epipolar test, and the semantic map takes
// their depth in. So a dynamic-class box that finds no detection of its
// class (IoU >= min_iou) in the next frames is kept for up to `frames` frames,
// shifted by the median backward flow of the keypoints that lie in it, then dropped.
// Only boxes that showed motion are carried (Remember): a detector's false
// positives and people standing still then stay where they were found.
// Only dynamic classes (ClassTable::is_dynamic) are carried: a chair missed for a
// frame is simply static there.
// Thread safety: none; one instance per tracking thread.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core/types.hpp>

#include "sgslam/detection/detection.h"
#include "sgslam/dynamic/flow.h"

namespace sgslam::dynamic {

class BoxCarrier {
 public:
  // frames: how long a missed box lives (0: off); min_iou: a fresh detection of the
  // same class overlapping a carried box this much replaces it.
  BoxCarrier(int frames, double min_iou, std::function<bool(const std::string&)> is_dynamic)
      : frames_(frames), min_iou_(min_iou), is_dynamic_(std::move(is_dynamic)) {}

  // fresh: this frame's detections. cur / flow: the current keypoints (raw px) and
  // their backward flow into the previous image (may be empty: no shift). Returns
  // the remembered boxes that no fresh detection replaces, moved into this frame,
  // each with carried > 0 (the frames since its object was last detected).
  std::vector<Detection> Carry(const std::vector<Detection>& fresh, const std::vector<cv::Point2f>& cur,
                               const FlowPairs& flow, cv::Size image);

  // The boxes of this frame (fresh and carried) to carry into the next frames:
  // those of dynamic classes whose moving[i] is true. Forgets the rest.
  void Remember(const std::vector<Detection>& boxes, const std::vector<bool>& moving);

 private:
  int frames_;
  double min_iou_;
  std::function<bool(const std::string&)> is_dynamic_;
  std::vector<Detection> boxes_;  // in the last frame's pixels
};

// A box of the previous frame moved into this one by the median backward flow of
// the keypoints whose previous position lies in it (unmoved with fewer than 5 such
// pairs) and cut to the image; nothing once less than a third of it is in view.
std::optional<cv::Rect2f> FollowBox(const cv::Rect2f& box, const std::vector<cv::Point2f>& cur, const FlowPairs& flow,
                                    cv::Size image);

// Intersection over union of two boxes (0 when either is empty).
double BoxIou(const cv::Rect2f& a, const cv::Rect2f& b);

}  // namespace sgslam::dynamic
