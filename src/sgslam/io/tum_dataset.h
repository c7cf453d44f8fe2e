// A dataset in the TUM RGB-D layout (also used by the Bonn RGB-D Dynamic dataset):
// rgb.txt and depth.txt ("timestamp path" lines), an optional associations.txt
// ("t_rgb rgb t_depth depth", as ORB-SLAM2's rgbd_tum reads), optional
// groundtruth.txt. Opening reads only the lists; images are read per frame.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "sgslam/common/time.h"
#include "sgslam/camera/camera_config.h"
#include "sgslam/io/dataset_config.h"
#include "sgslam/io/trajectory.h"

namespace sgslam {

struct FrameRecord {
  Timestamp t_rgb = 0, t_depth = 0;
  std::filesystem::path rgb, depth;  // absolute
  std::string listed_at;             // "rgb.txt:57", for error messages
};

// One RGB-D pair as read from disk: BGR 8-bit and raw 16-bit depth.
struct RgbdImages {
  std::size_t index = 0;
  Timestamp t = 0;  // the RGB timestamp names the frame
  cv::Mat bgr;      // CV_8UC3
  cv::Mat depth;    // CV_16UC1, raw units (camera.depth_factor per metre)
};

class TumDataset {
 public:
  // Throws InputError naming the folder or file: missing folder or list file,
  // malformed line or a time rgb.txt or depth.txt lists twice (file:line), empty
  // sequence; an associations.txt, rgb.txt, depth.txt or groundtruth.txt that is
  // not a regular file (a FIFO, a folder: refused, never waited on or skipped).
  TumDataset(const std::filesystem::path& dir, const DatasetConfig& config);

  const std::filesystem::path& dir() const { return dir_; }
  std::string name() const;
  const std::vector<FrameRecord>& frames() const { return frames_; }
  std::size_t size() const { return frames_.size(); }
  bool associations_from_file() const { return associations_from_file_; }

  // groundtruth.txt when the folder has one (looked at on opening).
  const std::optional<std::filesystem::path>& groundtruth_path() const { return groundtruth_; }

  // Reads and checks frame i: files exist and decode, depth is 16-bit single
  // channel, RGB and depth sizes agree with each other and with the camera.
  RgbdImages Load(std::size_t i, const CameraConfig& camera) const;

 private:
  std::filesystem::path dir_;
  std::vector<FrameRecord> frames_;
  bool associations_from_file_ = false;
  std::optional<std::filesystem::path> groundtruth_;
};

// "; with camera.depth_factor = F (millimetres) it would be X m" for the common
// factor F (1000 or 5000) that brings `metres`, measured with `factor`, into
// [lo, hi]; empty when none does. The hint of the depth-scale checks (this one and
// detection/people_scale.h).
std::string DepthFactorHint(double metres, double factor, double lo, double hi);

// Checks the depth scale on one frame: a median valid depth outside the configured
// range (dataset.min/max_median_depth) means depth_factor is wrong for this data:
// throws InputError naming both and the factor that would fit. A median outside
// 0.5-6 m, where RGB-D cameras see rooms, returns a warning.
std::optional<std::string> CheckDepthScale(const RgbdImages& frame, const FrameRecord& record, const CameraConfig& camera,
                     const DatasetConfig& dataset);

}  // namespace sgslam
