// One 2-D object detection of a frame, as the detector thread produces it and as
// detections files (io/detections_file.h) store it. Class ids are COCO ids in the
// order of coco.names (0 person, 56 chair, ...).
#pragma once

#include <opencv2/core/types.hpp>
#include <string>

namespace sgslam {

struct Detection {
  int class_id = -1;
  std::string class_name;
  float score = 0.f;
  cv::Rect2f box;  // px; x, y: top-left corner, the box covers [x, x + width) x [y, y + height)
  int carried = 0;  // 0: found in this frame; n: a missed moving object's box carried n frames (dynamic/box_carry.h)
};

}  // namespace sgslam
