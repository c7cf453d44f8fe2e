// objects.json and the end-of-run table of semantic objects.
#pragma once

#include <filesystem>
#include <vector>

#include "sgslam/semantic/objects.h"

namespace sgslam::app {

// The exported objects (ObjectEstimate::exported), with the map frame's definition;
// candidates: the others too, in a list of their own (semantic.object_candidates).
void WriteObjectsJson(const std::filesystem::path& path, const std::vector<ObjectEstimate>& objects,
                      bool candidates = false);
void PrintObjectTable(const std::vector<ObjectEstimate>& objects);

}  // namespace sgslam::app
