// Consistency checks of the map's links, for tests and debugging: every
// observation of a point is mirrored by the keyframe's slot and vice versa, no
// live entity refers to a bad one.
// Caller holds Map::mutex() (shared).
#pragma once

#include <string>
#include <vector>

#include "sgslam/map/map.h"

namespace sgslam {

// Empty when the map is consistent; otherwise one line per problem.
std::vector<std::string> CheckMapConsistency(const Map& map);

}  // namespace sgslam
