#include "sgslam/synth/sequence.h"

#include "sgslam/camera/rolling_shutter.h"
#include "sgslam/common/error.h"
#include "sgslam/synth/presets.h"
#include "sgslam/synth/random.h"

namespace sgslam::synth {

Timestamp FrameTimestamp(int i) {
  const std::int64_t micros = (static_cast<std::int64_t>(i) * 1'000'000 + 15) / 30;
  return kFirstTimestamp + micros * 1000;
}

SynthSequence::SynthSequence(const std::string& preset, std::uint32_t seed, int frames, double readout,
                             DepthNoise depth_noise)
    : scene_(BuildScene(preset, seed)), frames_(frames), readout_(readout), depth_noise_(depth_noise) {
  if (frames <= 0) throw InputError("synth: the number of frames must be positive, got " + std::to_string(frames));
  if (!(readout >= 0 && readout <= 1 / kFps)) {
    throw InputError("synth: the readout time must be between 0 and one frame time (" + std::to_string(1 / kFps) +
                     " s), got " + std::to_string(readout));
  }
  std::uint64_t preset_hash = 0;
  for (char c : preset) preset_hash = Mix64(preset_hash ^ static_cast<unsigned char>(c));
  noise_seed_ = Mix64(seed ^ preset_hash);
}

double SynthSequence::Seconds(int i) const { return ToSeconds(FrameTimestamp(i) - kFirstTimestamp); }

SE3 SynthSequence::CameraPose(int i) const { return scene_.camera.Pose(Seconds(i)); }

SE3 SynthSequence::ObjectPose(int object_id, int i) const {
  if (object_id < 1 || object_id > static_cast<int>(scene_.objects.size())) {
    throw Error("synth: no object with id " + std::to_string(object_id));
  }
  return scene_.objects[object_id - 1].Pose(Seconds(i));
}

Eigen::Vector3d SynthSequence::ObjectVelocity(int object_id, int i) const {
  ObjectPose(object_id, i);  // checks the id
  const SceneObject& o = scene_.objects[object_id - 1];
  return o.motion ? o.motion->path.Velocity(Seconds(i)) : Eigen::Vector3d::Zero();
}

RenderedFrame SynthSequence::Render(int i) const {
  std::vector<SE3> rows;
  if (readout_ > 0) {
    rows.reserve(static_cast<std::size_t>(intrinsics_.height));
    for (int y = 0; y < intrinsics_.height; ++y) {
      // The tracker's model of the timing, for the pixel centres of row y.
      rows.push_back(scene_.camera.Pose(Seconds(i) + RowTimeOffset(y, intrinsics_.height, readout_)));
    }
  }
  RenderedFrame f = RenderFrame(scene_, intrinsics_, CameraPose(i), Seconds(i), i, noise_seed_, rows);
  f.t = FrameTimestamp(i);
  if (depth_noise_ == DepthNoise::kKinect) f.depth_raw = KinectDepthRaw(f, intrinsics_, noise_seed_, kDepthFactor);
  return f;
}

std::vector<Detection> GroundTruthDetections(const RenderedFrame& frame, const Scene& scene, int min_pixels) {
  std::vector<Detection> out;
  for (const VisibleObject& v : frame.visible) {
    if (v.pixels < min_pixels) continue;
    const ObjectInfo& info = scene.objects.at(v.id - 1).info;
    Detection d;
    d.class_id = info.class_id;
    d.class_name = info.class_name;
    d.score = 1.f;
    d.box = cv::Rect2f(static_cast<float>(v.box.x), static_cast<float>(v.box.y), static_cast<float>(v.box.width),
                       static_cast<float>(v.box.height));
    out.push_back(std::move(d));
  }
  return out;
}

}  // namespace sgslam::synth
