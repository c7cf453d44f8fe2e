// The depth sensor of the synthetic sequences: exact (none) or Kinect-like
// (kinect), what a structured-light camera with a 7.5 cm baseline does to depth:
//   - axial noise sigma_z = 1.2 mm + 1.9 mm/m^2 (z - 0.4 m)^2 plus a grazing-angle
//     term 0.1 mm/sqrt(z) theta^2 / (pi/2 - theta)^2 (Nguyen, Izadi & Lovell 2012,
//     "Modeling Kinect sensor noise for improved 3D reconstruction and tracking");
//   - disparity quantised to 1/8 px at f = 580 px, b = 7.5 cm: steps of z^2 / 348 m,
//     3 mm at 1 m and 4.6 cm at 4 m (Khoshelham & Elberink 2012, "Accuracy and
//     resolution of Kinect depth data for indoor mapping applications");
//   - no depth outside 0.5-5 m, at incidence beyond 80 degrees, and in the
//     projector's shadow left of nearer surfaces (width f b (1/z_near - 1/z_far) px).
// Deterministic: the noise is a hash of the seed, frame and pixel.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>

#include "sgslam/synth/raycast.h"

namespace sgslam::synth {

struct RenderedFrame;

enum class DepthNoise { kNone, kKinect };

// "none" or "kinect"; throws InputError naming the value otherwise.
DepthNoise ParseDepthNoise(const std::string& name);
const char* DepthNoiseName(DepthNoise noise);

// Standard deviation (m) of the Kinect's depth at z (m) and incidence angle theta
// (rad, from the surface normal), before quantisation.
double KinectDepthSigma(double z, double theta);

// The raw depth image (CV_16U, m * depth_factor, 0 = none) a Kinect would give
// of the frame's exact depth, surfaces and pose.
cv::Mat KinectDepthRaw(const RenderedFrame& frame, const Intrinsics& K, std::uint64_t seed, double depth_factor);

}  // namespace sgslam::synth
