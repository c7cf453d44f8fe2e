// `sgslam run --foxglove[=PORT]` and `sgslam view OUTDIR --foxglove`: the channels
// of foxglove_channels.h served live over Foxglove's WebSocket protocol
// (viewer/src/foxglove_server.h; docs/foxglove.md). Without the viewer built in
// (SGSLAM_VIEWER=OFF), asking for it is an error, not ignored.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "sgslam/camera/camera_config.h"
#include "sgslam/system/slam_system.h"

#include "foxglove_channels.h"

namespace sgslam::app {

inline constexpr int kDefaultFoxglovePort = 8765;  // Foxglove's own default

class RunFoxglove {
 public:
  // Listens (InputError naming the address when it cannot), prints the address,
  // turns the system's snapshots on and starts the thread that makes the messages.
  // The system must outlive this.
  RunFoxglove(SlamSystem& system, const std::string& address, int port, const CameraConfig& camera);
  ~RunFoxglove();
  RunFoxglove(const RunFoxglove&) = delete;
  RunFoxglove& operator=(const RunFoxglove&) = delete;

  // The run's thread, after each frame: the frame just processed is handed over
  // (the newest wins: a frame not yet sent is replaced, never waited for).
  void AddFrame();
  // After the system's Finish(): the final map, kept for clients that connect later.
  void Finish();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// `sgslam view OUTDIR --foxglove`: a finished run's map, trajectory, objects and
// cloud, served until a stop signal.
class ViewFoxglove {
 public:
  ViewFoxglove(const MapSnapshot& map, Timestamp t, const std::string& address, int port, const CameraConfig& camera);
  ~ViewFoxglove();
  ViewFoxglove(const ViewFoxglove&) = delete;
  ViewFoxglove& operator=(const ViewFoxglove&) = delete;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sgslam::app
