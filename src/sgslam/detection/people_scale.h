// The depth scale checked against something that does not depend on it: the size
// of the people the detector finds. A box inside the image is not always a whole
// person (a desk or a chair hides the legs: on dyn_dev, at the right scale, people
// of 1.7 m measure 0.30-0.59 m), so the bounds are wide: among enough people, the
// tallest is above 0.4 m (a head and shoulders) and the shortest below 2.5 m. With
// millimetres read with TUM's 5000 a standing person measures 0.34 m; this catches
// what the first frame's median depth cannot (a deep room read 5x too near still
// looks like a room).
#pragma once

#include <opencv2/core/mat.hpp>
#include <optional>
#include <string>
#include <vector>

#include "sgslam/camera/camera_config.h"
#include "sgslam/detection/detection.h"

namespace sgslam {

// One person's height in metres from its box and the depth image: the box's
// height in pixels at the depth of the person (the near quartile of the valid
// depths in the box's middle half of columns: the person is in front of what the
// box also covers). Nothing for a box cut by the top or bottom of the image, a
// carried box, or one with too little depth.
std::optional<double> PersonHeight(const cv::Mat& depth, const Detection& d, const CameraConfig& camera);

class PeopleScaleCheck {
 public:
  static constexpr int kPeopleNeeded = 15;
  static constexpr double kMinTallest = 0.4, kMaxShortest = 2.5;  // m

  // Measures the people among one frame's detections, until kPeopleNeeded are;
  // then, once, returns a warning when the tallest is below kMinTallest or the
  // shortest above kMaxShortest, naming the depth factor that would fit.
  std::optional<std::string> Add(const cv::Mat& depth, const std::vector<Detection>& detections,
                                 const CameraConfig& camera);

  int measured() const { return static_cast<int>(heights_.size()); }
  // The median height of the people measured so far.
  std::optional<double> median_height() const;
  std::optional<double> tallest() const;

 private:
  std::vector<double> heights_;
  bool judged_ = false;
};

}  // namespace sgslam
