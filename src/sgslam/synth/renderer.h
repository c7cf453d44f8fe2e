// Renders one frame of a synthetic scene: ray-cast depth and visible surfaces,
// procedural textures with a fixed Lambertian light, a light Gaussian blur (sigma
// 0.6 px, like camera optics) and small deterministic Gaussian noise (sigma 1.5).
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "sgslam/common/se3.h"
#include "sgslam/common/time.h"
#include "sgslam/synth/raycast.h"
#include "sgslam/synth/scene.h"

namespace sgslam::synth {

struct VisibleObject {
  int id = 0;      // ObjectInfo::id
  int pixels = 0;  // visible pixel count
  cv::Rect box;    // bounding rectangle of its visible pixels
};

struct RenderedFrame {
  int index = 0;
  Timestamp t = 0;
  SE3 T_w_c;
  cv::Mat bgr;           // CV_8UC3
  cv::Mat depth;         // CV_32F, m: camera z of the surface hit by the pixel centre's ray; 0 = none
  cv::Mat depth_raw;     // CV_16U, the depth PNG's: round(depth * 5000) or a sensor's (depth_noise.h); 0 = none
  cv::Mat object_id;     // CV_32S, labelled object id, 0 on unlabelled surfaces
  cv::Mat surface;       // CV_32S, index into `surfaces`, -1 = none
  cv::Mat dynamic_mask;  // CV_8U, 255 where the visible surface belongs to a moving object
  std::vector<Quad> surfaces;          // world frame at this frame's time
  std::vector<VisibleObject> visible;  // by increasing id
  double dynamic_fraction = 0;         // share of mask pixels
};

constexpr double kDepthFactor = 5000.0;  // raw depth units per metre (TUM)

// Renders the scene at time t_seconds seen from T_w_c; the noise depends only on
// noise_seed and frame_index, so frames can render in any order or in parallel.
// T_w_c_rows, when given (K.height poses): a rolling shutter, row y seen from
// T_w_c_rows[y] (depth is z in that row's camera); the scene's moving objects stay
// at t_seconds, and T_w_c is what the frame reports as its pose.
RenderedFrame RenderFrame(const Scene& scene, const Intrinsics& K, const SE3& T_w_c, double t_seconds,
                          int frame_index, std::uint64_t noise_seed, const std::vector<SE3>& T_w_c_rows = {});

}  // namespace sgslam::synth
