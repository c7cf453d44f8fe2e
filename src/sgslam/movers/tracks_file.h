// tracks.txt: the mover tracks of a run, one line per track per tracked frame, in
// the frame of trajectory.txt:
//   timestamp id class x y z vx vy vz sx sy sz state
// centroid (m), velocity (m/s), extent along the map axes (m), state tentative,
// confirmed or lost; lines starting with '#' are comments.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "sgslam/common/time.h"
#include "sgslam/movers/mover_tracker.h"

namespace sgslam::movers {

struct TrackLine {
  Timestamp t = 0;
  int id = 0;
  std::string class_name;  // a COCO name, or "unknown"
  Eigen::Vector3d position = Eigen::Vector3d::Zero(), velocity = Eigen::Vector3d::Zero(),
                  extent = Eigen::Vector3d::Zero();
  TrackState state = TrackState::kTentative;
};

// Atomically (io/atomic_write.h).
void WriteTracksFile(const std::filesystem::path& path, const std::vector<TrackLine>& lines);
// Throws InputError / ParseError naming the file and line for a missing file or a bad line.
std::vector<TrackLine> ReadTracksFile(const std::filesystem::path& path);

}  // namespace sgslam::movers
