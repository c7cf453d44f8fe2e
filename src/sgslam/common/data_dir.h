// Where the files that ship with sgslam (detector models, camera configs) are
// found at run time: relative to the running executable, never through a path
// fixed at build time, so a moved build tree or an installed prefix both work.
//   installed:   <prefix>/bin/sgslam         -> <prefix>/share/sgslam
//   build tree:  build/sgslam, build/tests/x -> build/share/sgslam (copied there by CMake)
#pragma once

#include <filesystem>
#include <optional>

namespace sgslam {

// The folder of the running executable (/proc/self/exe); nullopt if unknown.
std::optional<std::filesystem::path> ExecutableDir();

// The first of <exe dir>/share/sgslam and <exe dir>/../share/sgslam that exists.
std::optional<std::filesystem::path> DataDir();

}  // namespace sgslam
