// The content checks of a map file's payload, apart from its encoding (map_file.cpp
// decodes the payload, then calls CheckMapData before anything is returned).
#pragma once

#include <string>

#include "sgslam/mapfile/map_data.h"

namespace sgslam::mapfile {

// Every reference resolves (keyframes, points, keypoint indices, parents), every
// per-keypoint array has one entry per keypoint, every number is finite and every
// keypoint within 1e6 px of 0; throws InputError (FailMapFile's form) naming `what`
// and the first problem.
void CheckMapData(const MapData& data, const std::string& what);

// The one form of a map file's refusals, the reader's and the checks' alike, so
// that every message names the file the same way: InputError "map file <what>: <why>".
[[noreturn]] void FailMapFile(const std::string& what, const std::string& why);

}  // namespace sgslam::mapfile
