// The files of a finished run that `sgslam view` reads besides the trajectories and
// clouds (io/): stats.json, objects.json and octomap.bt. Each is a regular file of a
// bounded size, checked before it is used, and every problem is an InputError
// naming the file (and the field): never a library's exception without a name.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace sgslam::viewer {

// What the page shows from stats.json; a field that is absent is empty.
struct RunStatsInfo {
  std::string dataset;  // the dataset folder the run read
  std::string mode;
  std::optional<std::uint64_t> frames;
};

// stats.json: an object whose dataset and mode, when present, are strings and
// whose frames is a count.
RunStatsInfo ReadRunStats(const std::filesystem::path& path);

// objects.json's objects (semantic/object_json.h's form): an object whose
// "objects" is a list of objects with a class, a confidence, a centroid and a size.
nlohmann::json ReadRunObjects(const std::filesystem::path& path);

// A binary OctoMap (.bt) as written by octomap's writeBinary: its header and node
// tree are checked here (the tree has the header's node count, ends with the file,
// is no deeper than OctoMap's 16 levels and has at most kMaxOctoMapNodes nodes)
// before OctoMap reads it, since OctoMap's own reader trusts both. Returns the
// occupied leaves: centre and side, 4 floats each.
std::vector<float> ReadOccupiedCells(const std::filesystem::path& path);

// 8 million nodes: a 5 cm OctoMap of a whole floor of a building has about a
// million; OctoMap holds 20-80 bytes a node.
inline constexpr std::uint64_t kMaxOctoMapNodes = std::uint64_t{1} << 23;

}  // namespace sgslam::viewer
