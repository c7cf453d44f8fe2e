#include "run_folder_source.h"

#include <algorithm>

#include <spdlog/spdlog.h>

#include "message.h"
#include "movers.h"
#include "run_folder_files.h"
#include "truth.h"
#include "sgslam/common/error.h"
#include "sgslam/common/regular_file.h"
#include "sgslam/eval/evaluate.h"
#include "sgslam/io/ply.h"
#include "sgslam/io/trajectory.h"
#include "sgslam/movers/tracks_file.h"

namespace sgslam::viewer {

namespace fs = std::filesystem;

namespace {

void Push(std::vector<float>& out, const Eigen::Vector3d& p) {
  out.insert(out.end(), {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())});
}

// The dataset's ground truth (stats.json names its folder), aligned to the run. It
// is the dataset's, not the run's: a problem with it costs the line, not the view.
std::vector<float> TruthOf(const RunStatsInfo& stats, const Trajectory& trajectory) {
  if (stats.dataset.empty()) return {};
  try {
    const auto gt_path = OptionalRegularFile(fs::path(stats.dataset) / "groundtruth.txt", "ground truth");
    if (!gt_path) return {};
    return AlignedTruth(eval::UniqueStamps(ReadTumTrajectory(*gt_path)), trajectory);
  } catch (const Error& e) {
    spdlog::warn("view: no ground truth shown: {}", e.what());
    return {};
  }
}

// The keyframes' poses (ids: their order in keyframes.txt), when the file is there.
void AddKeyFrames(const fs::path& path, MessageBuilder& m) {
  std::vector<std::uint32_t> ids;
  std::vector<float> poses;
  if (OptionalRegularFile(path, "keyframe trajectory")) {
    for (const StampedPose& k : ReadTumTrajectory(path)) {
      ids.push_back(static_cast<std::uint32_t>(ids.size()));
      const std::vector<float> T = ColumnMajor(k.T_w_c);
      poses.insert(poses.end(), T.begin(), T.end());
    }
  }
  m.Add("keyframe_ids", ids);
  m.Add("keyframe_poses", poses);
}

// cloud.ply, an even subsample of at most RunFolderSource::kMaxCloudPoints points.
void ReadCloud(const fs::path& path, std::vector<float>& xyz, std::vector<std::uint8_t>& rgb) {
  if (!OptionalRegularFile(path, "cloud")) return;
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

// The files' fields are checked where they are read (run_folder_files.h); the JSON
// library can still refuse a name that is not UTF-8 (a folder's) when encoding.
RunFolderSource::RunFolderSource(const fs::path& folder) try {
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) throw InputError("view: " + folder.string() + " is not a folder");
  if (!OptionalRegularFile(folder / "trajectory.txt", "trajectory")) {
    throw InputError("view: " + folder.string() + " has no trajectory.txt (is it the --out folder of sgslam run?)");
  }
  const Trajectory trajectory = ReadTumTrajectory(folder / "trajectory.txt");
  const RunStatsInfo stats = OptionalRegularFile(folder / "stats.json", "run output")
                                 ? ReadRunStats(folder / "stats.json")
                                 : RunStatsInfo{};
  info_ = {{"live", false},
           {"dataset", stats.dataset.empty() ? folder.filename().string() : fs::path(stats.dataset).filename().string()},
           {"mode", stats.mode},
           {"frames", stats.frames.value_or(trajectory.size())},
           {"pausable", false}};
  (void)info_.dump();  // encoded for every page later, where a throw would name nothing

  MessageBuilder m("map");
  std::vector<float> path;
  for (const StampedPose& p : trajectory) Push(path, p.T_w_c.translation());
  m.Add("path", path);
  AddKeyFrames(folder / "keyframes.txt", m);
  std::vector<float> points;
  if (OptionalRegularFile(folder / "map_points.ply", "map points")) {
    for (const Eigen::Vector3d& p : ReadPlyPoints(folder / "map_points.ply")) Push(points, p);
  }
  m.Add("points", points);
  m.Add("truth", TruthOf(stats, trajectory));
  const fs::path octomap = folder / "octomap.bt", objects = folder / "objects.json";
  m.Add("cells", OptionalRegularFile(octomap, "OctoMap") ? ReadOccupiedCells(octomap) : std::vector<float>{});
  m.header()["objects"] =
      OptionalRegularFile(objects, "run output") ? ReadRunObjects(objects) : nlohmann::json::array();
  if (const fs::path tracks = folder / "tracks.txt"; OptionalRegularFile(tracks, "run output")) {
    if (const std::size_t left_out = AddRunTracks(movers::ReadTracksFile(tracks), trajectory, m)) {
      spdlog::warn("view: {}: {} lines at times trajectory.txt has no pose for are not shown (another run's file?)",
                   tracks.string(), left_out);
    }
  }
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
} catch (const nlohmann::json::exception& e) {
  throw InputError("view: " + folder.string() + ": " + e.what());
}

}  // namespace sgslam::viewer
