// The one YAML loader and writer of the configuration (config.h).
#pragma once

#include <filesystem>
#include <string>

#include "sgslam/config/config.h"

namespace sgslam {

// Applies the values of a YAML file onto `config` (keys the file omits keep their
// values). Unknown sections and keys are warned about; a value of the wrong type
// throws ConfigError naming the file, line and key. A missing or unparsable file
// throws ConfigError naming the file.
void LoadConfigFile(const std::filesystem::path& file, Config& config);

// Whether a config file has a top-level section `name` (false when it cannot be
// read: LoadConfigFile reports that).
bool ConfigFileHasSection(const std::filesystem::path& file, const std::string& name);

// The effective configuration as YAML, each key with its unit as a comment.
std::string ConfigToYaml(const Config& config);

}  // namespace sgslam
