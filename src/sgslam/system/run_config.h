// Which configuration a run uses, in order of precedence: the file given with
// --config; else the dataset folder's own sgslam.yaml (sgslam synth writes one);
// else the camera preset the folder name implies (freiburg1/2/3, bonn); else the
// TUM fr1 defaults, with a warning. A --config file without a camera section goes
// on top of the folder's sgslam.yaml when that has one (its camera and the rest),
// else on top of the folder name's camera preset. The result is validated before
// it is returned.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "sgslam/config/config.h"

namespace sgslam {

struct RunConfig {
  Config config;
  std::string source;  // where the values came from, for logs and errors
};

RunConfig ResolveRunConfig(const std::optional<std::filesystem::path>& config_file,
                           const std::filesystem::path& dataset_dir);

}  // namespace sgslam
