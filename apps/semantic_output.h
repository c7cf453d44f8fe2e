// objects.json and the end-of-run table of semantic objects.
#pragma once

#include <filesystem>
#include <vector>

#include "sgslam/semantic/objects.h"

namespace sgslam::app {

// Exported objects only (ObjectEstimate::exported), with the map frame's definition.
void WriteObjectsJson(const std::filesystem::path& path, const std::vector<ObjectEstimate>& objects);
void PrintObjectTable(const std::vector<ObjectEstimate>& objects);

}  // namespace sgslam::app
