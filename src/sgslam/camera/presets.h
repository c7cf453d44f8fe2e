// Published calibrations of the dataset families the project reads, so that a
// dataset can run without a config file. configs/*.yaml hold the same values (a
// test keeps them in step).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "sgslam/camera/camera_config.h"

namespace sgslam {

// Names: "tum_fr1", "tum_fr2", "tum_fr3", "bonn".
std::vector<std::string> CameraPresetNames();
std::optional<CameraConfig> CameraPreset(const std::string& name);

// The preset a dataset folder's name implies ("rgbd_dataset_freiburg3_walking_xyz"
// -> tum_fr3, "rgbd_bonn_crowd" -> bonn), if any.
std::optional<std::string> CameraPresetForFolder(const std::filesystem::path& dataset_dir);

}  // namespace sgslam
