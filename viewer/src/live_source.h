// What a running `sgslam run --viewer` shows: the system's snapshots
// (system/snapshot.h), encoded for the page on the viewer's thread, and the
// page's pause and step.
#pragma once

#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "pause.h"
#include "server.h"
#include "sgslam/io/trajectory.h"
#include "sgslam/system/slam_system.h"

namespace sgslam::viewer {

class LiveSource : public Source {
 public:
  // info: what the page says of the run (dataset, mode, frames, ...); truth: the
  // dataset's ground truth (sorted, unique stamps) or empty, drawn aligned to the
  // keyframes.
  LiveSource(const SlamSystem& system, nlohmann::json info, Trajectory truth = {})
      : system_(system), info_(std::move(info)), truth_(std::move(truth)) {}

  // The run's thread, after each frame: remembers the frame's place and counts, and
  // tells the server (set_server) that a new frame is there. Cheap, never blocks.
  void AddFrame(const FrameReport& report);
  void set_server(Server* server) { server_ = server; }

  PauseControl& pause() { return pause_; }

  std::uint64_t FrameVersion() const override;
  std::shared_ptr<const std::string> EncodeFrame() override;
  std::shared_ptr<const std::string> EncodeMap(const MapRequest& request) override;
  nlohmann::json Info() const override;  // info, and whether the run is paused
  bool Control(const std::string& what, std::uint64_t page) override;  // pause.h's rules
  void PageClosed(std::uint64_t page) override;

  // Points a keyframe's cloud piece keeps at most (an even subsample): the page
  // draws 700 keyframes in 490k points.
  static constexpr std::size_t kMaxPiecePoints = 700;

 private:
  const SlamSystem& system_;
  const nlohmann::json info_;
  const Trajectory truth_;
  Server* server_ = nullptr;
  PauseControl pause_;
  // The viewer's thread only: the OctoMap cells last seen, and their version.
  std::shared_ptr<const std::vector<Eigen::Vector4f>> cells_;
  std::uint64_t cells_version_ = 0;

  mutable std::mutex mutex_;  // the fields below: written by the run's thread, read by the viewer's
  std::uint64_t version_ = 0;
  std::vector<float> path_;            // m, world: every tracked frame's position as tracked
  std::deque<double> arrivals_;        // s, steady clock: the last frames' arrival, for fps
  int keyframes_ = 0, map_points_ = 0, kept_ = 0, rejected_ = 0;
  TrackState last_state_ = TrackState::kNotInitialized;
  std::optional<std::size_t> relocalised_at_;  // the last frame that found the track again
  static constexpr std::size_t kShowRelocalisedFrames = 45;
};

}  // namespace sgslam::viewer
