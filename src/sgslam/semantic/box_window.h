// The dynamic-object boxes of the frames around a keyframe, moved into its image.
// A CPU detector misses a person in some frames and finds it in the next; with
// semantic.filters.box_window the kBoxWindow frames on each side of a keyframe
// (semantic_mapper.cpp) lend it their boxes for the static-map mask (paper
// Sec. III-E leaves dynamic objects out of the cloud and the OctoMap).
// Tracking is untouched: it uses its own frame's boxes only (Algorithm 1).
//
// A box is carried to the keyframe as the plane at its median depth: its corners
// are back-projected there with the frame's tracked pose and projected with the
// keyframe's, and it grows by a few px per frame of distance for the object's own
// motion.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "sgslam/common/se3.h"
#include "sgslam/detection/detection.h"

namespace sgslam {

class Camera;

struct FrameBoxes {
  std::uint64_t frame_id = 0;
  SE3 T_c_w;                     // the tracked pose of the frame
  std::vector<Detection> boxes;  // its dynamic-class detections (raw image pixels)
  std::vector<double> depth;     // m, median depth inside each box; 0: none, the box is not carried
};

// Median of the valid depths on a grid of `step` px over the inner `inner` share of
// the box (its middle, where the object rather than the background is); 0 if none.
double BoxMedianDepth(const cv::Mat& depth_raw, double depth_factor, const cv::Rect2f& box, double inner = 0.6,
                      int step = 4);

struct CarriedBox {
  cv::Rect2f box;     // raw image pixels of the keyframe
  double depth = 0;   // m, the box's plane centre in the keyframe's camera
};

// `from`'s boxes as seen from the pose T_c_w_to (the keyframe's tracked pose),
// clipped to the image; boxes that leave it or whose plane falls behind the camera
// are left out, and so are boxes over max_area of the image (a detector's
// whole-view false positive would wipe out a keyframe). growth_px: added on each side.
std::vector<CarriedBox> CarryBoxes(const FrameBoxes& from, const SE3& T_c_w_to, const Camera& camera,
                                   cv::Size image, double growth_px, double max_area);

// Marks (255) the pixels of each carried box whose depth lies within band m of the
// box's: the moving object, not the background seen around it.
void MaskCarriedBoxes(const std::vector<CarriedBox>& boxes, const cv::Mat& depth_raw, double depth_factor,
                      double band, cv::Mat& mask);

}  // namespace sgslam
