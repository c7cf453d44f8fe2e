#include "run_folder_files.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <octomap/OcTree.h>

#include "sgslam/common/error.h"
#include "sgslam/common/regular_file.h"

namespace sgslam::viewer {

namespace fs = std::filesystem;

namespace {

// stats.json is a few KB; objects.json 1-2 KB an object. Far beyond is the wrong file.
constexpr std::uint64_t kMaxStatsBytes = 16 << 20;
constexpr std::uint64_t kMaxObjectsBytes = 256 << 20;

// The file's JSON, which must be an object, as sgslam run writes it.
nlohmann::json ReadJsonObject(const fs::path& path, std::uint64_t max_bytes) {
  const nlohmann::json j = nlohmann::json::parse(ReadRegularFile(path, "run output", max_bytes), nullptr, false);
  if (j.is_discarded()) throw InputError(path.string() + ": not valid JSON");
  if (!j.is_object()) {
    throw InputError(path.string() + ": a JSON " + j.type_name() + ", not the object sgslam run writes");
  }
  return j;
}

// Throws naming the file and field when j has `key` and it is not of the kind `is` tests.
void CheckField(const fs::path& path, const nlohmann::json& j, const char* key, bool (*is)(const nlohmann::json&),
                const char* kind) {
  if (j.contains(key) && !is(j[key])) {
    throw InputError(path.string() + ": '" + key + "' must be " + kind + ", got a JSON " + j[key].type_name());
  }
}

bool ThreeNumbers(const nlohmann::json& v) {
  return v.is_array() && v.size() == 3 && std::all_of(v.begin(), v.end(), [](const auto& x) { return x.is_number(); });
}

}  // namespace

RunStatsInfo ReadRunStats(const fs::path& path) {
  const nlohmann::json stats = ReadJsonObject(path, kMaxStatsBytes);
  CheckField(path, stats, "dataset", [](const nlohmann::json& v) { return v.is_string(); }, "a string (a folder)");
  CheckField(path, stats, "mode", [](const nlohmann::json& v) { return v.is_string(); }, "a string");
  CheckField(path, stats, "frames", [](const nlohmann::json& v) { return v.is_number_unsigned(); }, "a count");
  RunStatsInfo info;
  if (stats.contains("dataset")) info.dataset = stats["dataset"].get<std::string>();
  if (stats.contains("mode")) info.mode = stats["mode"].get<std::string>();
  if (stats.contains("frames")) info.frames = stats["frames"].get<std::uint64_t>();
  return info;
}

nlohmann::json ReadRunObjects(const fs::path& path) {
  const nlohmann::json file = ReadJsonObject(path, kMaxObjectsBytes);
  CheckField(path, file, "objects", [](const nlohmann::json& v) { return v.is_array(); }, "a list");
  nlohmann::json objects = file.value("objects", nlohmann::json::array());
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const nlohmann::json& o = objects[i];
    if (!o.is_object() || !o.contains("class") || !o["class"].is_string() || !o.contains("confidence") ||
        !o["confidence"].is_number() || !o.contains("centroid") || !ThreeNumbers(o["centroid"]) ||
        !o.contains("size") || !ThreeNumbers(o["size"])) {
      throw InputError(path.string() + ": object " + std::to_string(i + 1) +
                       " lacks a class, confidence, centroid or size as sgslam run writes them");
    }
  }
  return objects;
}

namespace {

constexpr std::string_view kOctoMapFirstLine = "# Octomap OcTree binary file";
// The header is a few short lines; comments may be added, not kilobytes of them.
constexpr std::size_t kMaxOctoMapHeader = 64 * 1024;
// Every inner node takes two bytes, so no tree within kMaxOctoMapNodes is larger.
constexpr std::uint64_t kMaxOctoMapBytes = kMaxOctoMapHeader + 2 * kMaxOctoMapNodes;
constexpr int kOctoMapDepth = 16;  // OctoMap's: leaves at most 16 levels below the root

struct OctoMapHeader {
  double resolution = 0;
  std::uint64_t nodes = 0;
  std::size_t body = 0;  // where the node tree starts
};

// "key value" lines after the first, up to the line "data"; '#' lines are comments.
OctoMapHeader ParseOctoMapHeader(const RegularFile& file, std::string_view text) {
  const std::string_view head = text.substr(0, kMaxOctoMapHeader);
  if (head.rfind(kOctoMapFirstLine, 0) != 0) file.Fail("not a binary OctoMap (no '# Octomap OcTree binary file' line)");
  OctoMapHeader h;
  bool has_resolution = false, has_size = false;
  for (std::size_t at = head.find('\n'); at != std::string_view::npos && h.body == 0;) {
    const std::size_t end = head.find('\n', at + 1);
    if (end == std::string_view::npos) break;
    std::istringstream line(std::string(head.substr(at + 1, end - at - 1)));
    std::string key;
    line >> key;
    if (key == "data") h.body = end + 1;
    if (key == "res") has_resolution = static_cast<bool>(line >> h.resolution);
    if (key == "size") has_size = static_cast<bool>(line >> h.nodes);
    at = end;
  }
  if (h.body == 0) file.Fail("no 'data' line ends its header (a damaged binary OctoMap)");
  // A resolution outside 0.1 mm - 1 km is no map's, and 0 or NaN breaks OctoMap's keys.
  if (!has_resolution || !(h.resolution >= 1e-4 && h.resolution <= 1e3)) file.Fail("no resolution in 1e-4..1e3 m in its header");
  if (!has_size) file.Fail("no node count ('size') in its header");
  return h;
}

// Walks the node tree (two bytes a node with children: two bits a child, 01 or 10
// a leaf, 11 a child with children, written depth first) without building it.
std::uint64_t CountOctoMapNodes(const RegularFile& file, std::string_view text, std::size_t at) {
  std::vector<int> pending = {1};  // per level: nodes whose children are still to be read
  std::uint64_t nodes = 1;
  while (!pending.empty()) {
    if (pending.back() == 0) {
      pending.pop_back();
      continue;
    }
    --pending.back();
    if (at + 2 > text.size()) file.Fail("its node tree is cut short after " + std::to_string(nodes) + " nodes");
    int inner = 0;
    for (int child = 0; child < 8; ++child) {
      const int bits = (static_cast<unsigned char>(text[at + child / 4]) >> (2 * (child % 4))) & 3;
      nodes += bits != 0;
      inner += bits == 3;
    }
    at += 2;
    if (nodes > kMaxOctoMapNodes) file.Fail("more than " + std::to_string(kMaxOctoMapNodes) + " nodes");
    if (inner > 0 && static_cast<int>(pending.size()) >= kOctoMapDepth) {
      file.Fail("its node tree is deeper than OctoMap's " + std::to_string(kOctoMapDepth) + " levels (damaged)");
    }
    if (inner > 0) pending.push_back(inner);
  }
  if (at != text.size()) file.Fail(std::to_string(text.size() - at) + " bytes after its node tree (damaged)");
  return nodes;
}

}  // namespace

std::vector<float> ReadOccupiedCells(const fs::path& path) {
  const RegularFile file(path, "OctoMap");
  const std::string text = file.ReadAll(kMaxOctoMapBytes);
  const OctoMapHeader h = ParseOctoMapHeader(file, text);
  if (h.nodes == 0 && h.body == text.size()) return {};  // an empty tree
  if (const std::uint64_t n = CountOctoMapNodes(file, text, h.body); n != h.nodes) {
    file.Fail("its header says " + std::to_string(h.nodes) + " nodes, its tree has " + std::to_string(n));
  }
  octomap::OcTree tree(h.resolution);
  std::istringstream in(text);
  if (!tree.readBinary(in)) file.Fail("OctoMap cannot read it");
  std::vector<float> out;
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) {
    if (!tree.isNodeOccupied(*it)) continue;
    const octomap::point3d c = it.getCoordinate();
    out.insert(out.end(), {c.x(), c.y(), c.z(), static_cast<float>(it.getSize())});
  }
  return out;
}

}  // namespace sgslam::viewer
