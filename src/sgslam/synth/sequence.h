// A synthetic RGB-D sequence in memory: the scene of a preset and seed, the frame
// timestamps (30 Hz), exact camera and object poses, and rendering of any frame on
// its own. Tests use this directly; writer.h saves it in the TUM layout.
// Thread safety: const methods may be called from several threads at once.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "sgslam/common/se3.h"
#include "sgslam/common/time.h"
#include "sgslam/detection/detection.h"
#include "sgslam/synth/depth_noise.h"
#include "sgslam/synth/renderer.h"
#include "sgslam/synth/scene.h"

namespace sgslam::synth {

constexpr Timestamp kFirstTimestamp = 1'700'000'000 * kNsPerSecond;
constexpr double kFps = 30.0;
constexpr int kMinDetectionPixels = 150;  // smaller visible parts get no detection

// 1700000000 s + i / 30 s, rounded to whole microseconds so that text files (6
// decimals) hold it exactly.
Timestamp FrameTimestamp(int i);

class SynthSequence {
 public:
  // Throws InputError for an unknown preset, frames <= 0 or a readout outside
  // [0, 1 / kFps]. readout > 0: a rolling shutter, row v exposed at the frame's
  // time + (v / height - 1/2) * readout (camera/rolling_shutter.h's model, with the
  // camera's translation as well); the ground truth is the middle row's pose.
  // depth_noise: the sensor model of the rendered frames' depth_raw (depth stays exact).
  SynthSequence(const std::string& preset, std::uint32_t seed, int frames, double readout = 0,
                DepthNoise depth_noise = DepthNoise::kNone);

  int size() const { return frames_; }
  const Scene& scene() const { return scene_; }
  const Intrinsics& intrinsics() const { return intrinsics_; }
  const std::vector<SceneObject>& objects() const { return scene_.objects; }

  Timestamp timestamp(int i) const { return FrameTimestamp(i); }
  double readout() const { return readout_; }  // s
  DepthNoise depth_noise() const { return depth_noise_; }
  double Seconds(int i) const;                        // time of frame i since the first frame
  SE3 CameraPose(int i) const;                        // T_w_c
  SE3 ObjectPose(int object_id, int i) const;         // T_w_o (identity for static objects)
  Eigen::Vector3d ObjectVelocity(int object_id, int i) const;  // m/s, world, of the object's origin

  RenderedFrame Render(int i) const;

 private:
  Scene scene_;
  Intrinsics intrinsics_;
  int frames_ = 0;
  double readout_ = 0;
  DepthNoise depth_noise_ = DepthNoise::kNone;
  std::uint64_t noise_seed_ = 0;
};

// One detection (score 1) per labelled object with at least min_pixels visible pixels:
// the bounding rectangle of those pixels.
std::vector<Detection> GroundTruthDetections(const RenderedFrame& frame, const Scene& scene,
                                             int min_pixels = kMinDetectionPixels);

}  // namespace sgslam::synth
