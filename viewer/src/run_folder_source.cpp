#include "run_folder_source.h"

#include <algorithm>
#include <fstream>

#include <octomap/OcTree.h>
#include <spdlog/spdlog.h>

#include "message.h"
#include "truth.h"
#include "sgslam/common/error.h"
#include "sgslam/eval/evaluate.h"
#include "sgslam/io/ply.h"
#include "sgslam/io/trajectory.h"

namespace sgslam::viewer {

namespace fs = std::filesystem;

namespace {

void Push(std::vector<float>& out, const Eigen::Vector3d& p) {
  out.insert(out.end(), {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())});
}

nlohmann::json ReadJson(const fs::path& p) {
  std::ifstream in(p);
  nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded()) throw InputError(p.string() + ": not valid JSON");
  return j;
}

// The dataset's ground truth (stats.json names its folder), aligned to the run.
std::vector<float> TruthOf(const nlohmann::json& stats, const Trajectory& trajectory) {
  if (!stats.contains("dataset") || !stats["dataset"].is_string()) return {};
  const fs::path gt_path = fs::path(stats["dataset"].get<std::string>()) / "groundtruth.txt";
  std::error_code ec;
  if (!fs::is_regular_file(gt_path, ec)) return {};
  try {
    return AlignedTruth(eval::UniqueStamps(ReadTumTrajectory(gt_path)), trajectory);
  } catch (const Error& e) {
    spdlog::warn("view: no ground truth shown: {}", e.what());
    return {};
  }
}

// The OctoMap's occupied leaves: centre and side, 4 floats each.
std::vector<float> OccupiedCells(const fs::path& path) {
  std::vector<float> out;
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return out;
  octomap::OcTree tree(0.05);
  if (!tree.readBinary(path.string())) {
    spdlog::warn("view: {} is not a readable OctoMap; not shown", path.string());
    return out;
  }
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) {
    if (!tree.isNodeOccupied(*it)) continue;
    const octomap::point3d c = it.getCoordinate();
    out.insert(out.end(), {c.x(), c.y(), c.z(), static_cast<float>(it.getSize())});
  }
  return out;
}

// The keyframes' poses (ids: their order in keyframes.txt), when the file is there.
void AddKeyFrames(const fs::path& path, MessageBuilder& m) {
  std::vector<std::uint32_t> ids;
  std::vector<float> poses;
  std::error_code ec;
  if (fs::is_regular_file(path, ec)) {
    for (const StampedPose& k : ReadTumTrajectory(path)) {
      ids.push_back(static_cast<std::uint32_t>(ids.size()));
      const std::vector<float> T = ColumnMajor(k.T_w_c);
      poses.insert(poses.end(), T.begin(), T.end());
    }
  }
  m.Add("keyframe_ids", ids);
  m.Add("keyframe_poses", poses);
}

// objects.json's objects (semantic/object_json.h's form, as the live page gets them).
nlohmann::json ObjectsOf(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return nlohmann::json::array();
  nlohmann::json objects = ReadJson(path).value("objects", nlohmann::json::array());
  if (!objects.is_array()) throw InputError(path.string() + ": 'objects' is not a list");
  const auto three_numbers = [](const nlohmann::json& v) {
    return v.is_array() && v.size() == 3 && std::all_of(v.begin(), v.end(), [](const auto& x) { return x.is_number(); });
  };
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const nlohmann::json& o = objects[i];
    if (!o.is_object() || !o.contains("class") || !o["class"].is_string() || !o.contains("confidence") ||
        !o["confidence"].is_number() || !o.contains("centroid") || !three_numbers(o["centroid"]) ||
        !o.contains("size") || !three_numbers(o["size"])) {
      throw InputError(path.string() + ": object " + std::to_string(i + 1) +
                       " lacks a class, confidence, centroid or size as sgslam run writes them");
    }
  }
  return objects;
}

// cloud.ply, an even subsample of at most RunFolderSource::kMaxCloudPoints points.
void ReadCloud(const fs::path& path, std::vector<float>& xyz, std::vector<std::uint8_t>& rgb) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return;
  std::vector<Rgb> colours;
  const std::vector<Eigen::Vector3d> cloud = ReadPlyPoints(path, &colours);
  const std::size_t max = RunFolderSource::kMaxCloudPoints;
  const std::size_t step = std::max<std::size_t>(1, (cloud.size() + max - 1) / max);
  for (std::size_t i = 0; i < cloud.size(); i += step) {
    Push(xyz, cloud[i]);
    const Rgb c = colours.empty() ? Rgb{200, 200, 200} : colours[i];
    rgb.insert(rgb.end(), c.begin(), c.end());
  }
}

}  // namespace

RunFolderSource::RunFolderSource(const fs::path& folder) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) throw InputError("view: " + folder.string() + " is not a folder");
  if (!fs::is_regular_file(folder / "trajectory.txt", ec)) {
    throw InputError("view: " + folder.string() + " has no trajectory.txt (is it the --out folder of sgslam run?)");
  }
  const Trajectory trajectory = ReadTumTrajectory(folder / "trajectory.txt");
  const nlohmann::json stats =
      fs::is_regular_file(folder / "stats.json", ec) ? ReadJson(folder / "stats.json") : nlohmann::json::object();
  info_ = {{"live", false},
           {"dataset", stats.contains("dataset") ? fs::path(stats["dataset"].get<std::string>()).filename().string()
                                                 : folder.filename().string()},
           {"mode", stats.value("mode", "")},
           {"frames", stats.value("frames", trajectory.size())},
           {"pausable", false}};

  MessageBuilder m("map");
  std::vector<float> path;
  for (const StampedPose& p : trajectory) Push(path, p.T_w_c.translation());
  m.Add("path", path);
  AddKeyFrames(folder / "keyframes.txt", m);
  std::vector<float> points;
  if (fs::is_regular_file(folder / "map_points.ply", ec)) {
    for (const Eigen::Vector3d& p : ReadPlyPoints(folder / "map_points.ply")) Push(points, p);
  }
  m.Add("points", points);
  m.Add("truth", TruthOf(stats, trajectory));
  m.Add("cells", OccupiedCells(folder / "octomap.bt"));
  m.header()["objects"] = ObjectsOf(folder / "objects.json");
  // The cloud is one piece (id 0) at the world's origin.
  m.Add("piece_ids", std::vector<std::uint32_t>{0});
  m.Add("piece_poses", ColumnMajor(SE3()));
  MessageBuilder without = m;
  std::vector<float> xyz;
  std::vector<std::uint8_t> rgb;
  ReadCloud(folder / "cloud.ply", xyz, rgb);
  const auto n = static_cast<std::uint32_t>(xyz.size() / 3);
  m.Add("new_piece_ids", std::vector<std::uint32_t>{0});
  m.Add("new_piece_counts", std::vector<std::uint32_t>{n});
  m.Add("new_piece_xyz", xyz);
  m.Add("new_piece_rgb", rgb);
  without.Add("new_piece_ids", std::vector<std::uint32_t>{});
  without.Add("new_piece_counts", std::vector<std::uint32_t>{});
  without.Add("new_piece_xyz", std::vector<float>{});
  without.Add("new_piece_rgb", std::vector<std::uint8_t>{});
  whole_ = m.Finish();
  without_cloud_ = without.Finish();
}

}  // namespace sgslam::viewer
