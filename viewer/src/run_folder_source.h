// What `sgslam view OUTDIR` shows: a finished run's outputs (trajectory.txt,
// keyframes.txt, map_points.ply, cloud.ply, octomap.bt, objects.json, tracks.txt,
// stats.json), read once and encoded once. The dataset's ground truth is shown
// aligned to the trajectory when stats.json names a dataset folder that has one.
#pragma once

#include <filesystem>
#include <string>

#include "server.h"

namespace sgslam::viewer {

class RunFolderSource : public Source {
 public:
  // Throws sgslam::InputError naming the file when the folder has no trajectory.txt,
  // or a file in it is unreadable, malformed, too large or not a regular file (a
  // FIFO is refused, not waited on). A missing optional file (keyframes, map
  // points, cloud, OctoMap, objects, tracks) leaves its layer empty.
  explicit RunFolderSource(const std::filesystem::path& folder);

  std::uint64_t FrameVersion() const override { return 0; }  // no frames: the map only
  std::shared_ptr<const std::string> EncodeFrame() override { return nullptr; }
  std::shared_ptr<const std::string> EncodeMap(const MapRequest& request) override {
    return request.pieces_after < 0 ? whole_ : without_cloud_;
  }
  nlohmann::json Info() const override { return info_; }

  // Points of cloud.ply kept at most (an even subsample), for the page's speed.
  static constexpr std::size_t kMaxCloudPoints = 500'000;

 private:
  nlohmann::json info_;
  std::shared_ptr<const std::string> whole_, without_cloud_;  // the map, with and without its cloud
};

}  // namespace sgslam::viewer
