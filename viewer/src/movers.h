// The mover tracks in the viewer's messages (movers/mover_tracker.h): a live run's
// with each frame, a finished run's (tracks.txt) with its map, for the page's
// replay of them.
#pragma once

#include <cstddef>
#include <vector>

#include <nlohmann/json.hpp>

#include "message.h"
#include "sgslam/io/trajectory.h"
#include "sgslam/movers/tracks_file.h"
#include "sgslam/system/snapshot.h"

namespace sgslam::viewer {

// The frame message's "movers": per track its id, class, state (StateName),
// position and extent (m, world frame).
nlohmann::json MoversJson(const std::vector<MoverSnapshot>& movers);

// A finished run's tracks as the map message's buffers: per line of tracks.txt
// its frame (the index of the pose in trajectory, which must be sorted, with the
// same timestamp), id, class (an index into the header's "mover_classes"), state
// (TrackState's value: 0 tentative, 1 confirmed, 2 lost), position and extent, by
// frame; and "path_t", the poses' times (s from the first). Lines at a time the
// trajectory has no pose for are left out: returns how many.
std::size_t AddRunTracks(const std::vector<movers::TrackLine>& lines, const Trajectory& trajectory,
                         MessageBuilder& m);

}  // namespace sgslam::viewer
