// The one YAML loader and writer of the configuration (config.h).
#pragma once

#include <filesystem>
#include <string>

#include "sgslam/config/config.h"

namespace sgslam {

// A sub-section of a section (dynamic.refinements): a struct that lists its own
// keys with Visit(), as a section does.
template <class T>
concept ConfigSubsection = requires(T& t) { t.Visit([](const char*, auto&, const char*) {}); };

// The top-level entry of a config file that turns its unknown keys from errors into
// warnings: `unknown_keys: warn` (default: error).
inline constexpr const char* kUnknownKeysDirective = "unknown_keys";

// Applies the values of a YAML file onto `config` (keys the file omits keep their
// values). Unknown sections and keys throw ConfigError listing each with its file
// and line (and the nearest known name), unless the file says `unknown_keys: warn`;
// a value of the wrong type throws ConfigError naming the file, line and key. A
// missing or unparsable file, one that is not a regular file (a FIFO is refused,
// not waited on) or is over 1 MiB, and a key given twice in one map (at any depth)
// throw ConfigError naming the file (and both lines of the key).
void LoadConfigFile(const std::filesystem::path& file, Config& config);

// Whether a config file has a top-level section `name`; throws as LoadConfigFile
// does when the file cannot be read or parsed, or repeats a key.
bool ConfigFileHasSection(const std::filesystem::path& file, const std::string& name);

// The effective configuration as YAML, each key with its unit as a comment.
std::string ConfigToYaml(const Config& config);

// A value as it appears in YAML (int, double, bool, string, or a name: number table
// in flow style); doubles in the shortest text that reads back to the same value.
template <class T>
std::string ConfigValueText(const T& value);

}  // namespace sgslam
