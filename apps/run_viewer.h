// `sgslam run --viewer`: the live web viewer (viewer/) during a run. Without the
// viewer built in (SGSLAM_VIEWER=OFF), asking for it is an error, not ignored.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sgslam/io/trajectory.h"
#include "sgslam/system/slam_system.h"

namespace sgslam::app {

class RunViewer {
 public:
  // Starts serving (snapshots enabled on the system, which must outlive this) and
  // prints the address. Throws sgslam::Error when it cannot.
  // truth: the dataset's ground truth (sorted, unique stamps), or empty.
  // origins: pages elsewhere allowed to connect (--viewer-origin; server.h's
  // ServerOptions::allowed_origins).
  RunViewer(SlamSystem& system, const std::string& address, int port, nlohmann::json info, Trajectory truth,
            std::vector<std::string> origins);
  ~RunViewer();
  RunViewer(const RunViewer&) = delete;
  RunViewer& operator=(const RunViewer&) = delete;

  // After each frame (the run's thread).
  void AddFrame(const FrameReport& report);
  // Before each frame: waits while the page has the run paused; a stop signal ends
  // the wait (StopSignals::Received() then tells).
  void WaitWhilePaused();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// For the command line's check of --viewer-origin and view --origin: why text is
// not an origin (http://HOST[:PORT] or https://HOST[:PORT]), or empty when it is.
std::string ViewerOriginError(const std::string& text);

}  // namespace sgslam::app
