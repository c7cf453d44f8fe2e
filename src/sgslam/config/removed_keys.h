// Keys earlier versions read and this one does not: most were constants of the
// authors' or ORB-SLAM2's code, or switches of experiments, and are now named
// constants beside their use (issue #48). Each keeps its last value here, so that
// a file written for an earlier version (a config_used.yaml) still loads when it
// holds that value (the run does what it asked), and is refused when it asks for
// another, which this version cannot do. docs/configuration.md lists them.
#pragma once

#include <string>
#include <vector>

namespace sgslam {

struct RemovedConfigKey {
  const char* key;         // section.key as it was
  const char* last_value;  // its default when it was removed, as YAML
  const char* now;         // where the value lives now, or the key that replaced it
};

const std::vector<RemovedConfigKey>& RemovedConfigKeys();

// The entry of `key` (section.key), or null.
const RemovedConfigKey* FindRemovedConfigKey(const std::string& key);

// Whether two YAML scalars are the same value: numbers by value (3 and 3.0), booleans
// by truth (true, True, yes), anything else by text.
bool SameConfigValue(const std::string& a, const std::string& b);

}  // namespace sgslam
