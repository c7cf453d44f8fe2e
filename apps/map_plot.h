// A top view of the semantic map for a quick look without other tools: the static
// cloud seen from above (the map frame's x-z plane: the first camera's y axis points
// down), the objects' boxes with their class, and the camera path.
#pragma once

#include <filesystem>
#include <vector>

#include "sgslam/io/ply.h"
#include "sgslam/io/trajectory.h"
#include "sgslam/semantic/objects.h"

namespace sgslam::app {

// Written atomically; throws InputError naming the file.
void WriteTopView(const std::filesystem::path& path, const std::vector<Eigen::Vector3d>& cloud,
                  const std::vector<Rgb>& colours, const std::vector<ObjectEstimate>& objects,
                  const Trajectory& trajectory);

}  // namespace sgslam::app
