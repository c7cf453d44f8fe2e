// Which configuration a run uses, in order of precedence: the file given with
// --config (ResolveConfigPath); else the dataset folder's own sgslam.yaml (sgslam synth writes one);
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

// A --config value: an existing file as it is; a bare name such as "bonn" or
// "tum_fr3.yaml" that is no file here: the config of that name shipped with sgslam
// (<DataDir()>/configs, common/data_dir.h). Throws InputError listing the shipped
// names when there is none of that name.
std::filesystem::path ResolveConfigPath(const std::filesystem::path& config);

RunConfig ResolveRunConfig(const std::optional<std::filesystem::path>& config_file,
                           const std::filesystem::path& dataset_dir);

}  // namespace sgslam
