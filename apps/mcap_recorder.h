// `sgslam run --mcap FILE`: the run recorded as an MCAP file for Foxglove
// (docs/foxglove.md), written as it goes on a thread of its own: each frame's
// messages (foxglove_channels.h) and, at most every second of the sequence, the
// map's (the dense cloud every five); the final map and the file's summary at the
// end, on every stop.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>

#include "sgslam/camera/camera_config.h"
#include "sgslam/common/bounded_queue.h"
#include "sgslam/io/mcap_writer.h"
#include "sgslam/system/slam_system.h"

#include "foxglove_channels.h"

namespace sgslam::app {

class McapRecorder {
 public:
  // Opens the file (InputError naming it when it cannot), writes the schemas and
  // channels, turns the system's snapshots on and starts the writing thread. The
  // system must outlive the recorder. live: frames come from a camera (the ROS node,
  // run --realtime), so a frame that finds kQueuedFrames waiting is dropped from the
  // recording (counted) rather than holding tracking up.
  McapRecorder(const std::filesystem::path& file, SlamSystem& system, const CameraConfig& camera, bool live = false);
  // Without Finish() (a run that failed before it had frames to save): the file is
  // abandoned, an earlier one of its name kept.
  ~McapRecorder();
  McapRecorder(const McapRecorder&) = delete;
  McapRecorder& operator=(const McapRecorder&) = delete;

  // The run's thread, after each frame: queues the frame just processed. Not live,
  // it waits while kQueuedFrames wait already: the file keeps every frame.
  void AddFrame();
  // After the system's Finish(): the frames queued, the final map, the summary.
  // Empty when the file was written in full, else why not. A frame whose messages
  // could not be made is left out (logged), not the recording.
  std::string Finish();

  static constexpr std::size_t kQueuedFrames = 16;

 private:
  void Run();
  void Write(const std::vector<foxglove::Message>& messages);
  void WriteMap(Timestamp t, bool final);

  const SlamSystem& system_;
  mcap::Writer writer_;
  foxglove::Encoder encoder_;
  std::array<std::uint16_t, foxglove::kChannels> channel_ids_{};
  BoundedQueue<std::shared_ptr<const FrameSnapshot>> frames_;
  std::thread thread_;
  bool finished_ = false;
  std::string error_;  // the file's failure (the writing thread's, read after it ended)
  std::size_t skipped_ = 0;  // frames whose messages could not be made (the writing thread's)
  // The writing thread's: the last frame's time, and when the map goes.
  Timestamp last_t_ = 0;
  bool any_frame_ = false;
  foxglove::MapPacer map_pacer_;
};

}  // namespace sgslam::app
