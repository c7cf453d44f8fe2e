// What a display draws of the mover tracks besides their boxes (the ROS node's
// markers, the Foxglove channels): each track's recent path and its colour.
#pragma once

#include <array>
#include <deque>
#include <map>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "sgslam/common/time.h"
#include "sgslam/system/snapshot.h"

namespace sgslam {

// Each mover track's recent positions, for its trail: the last kSeconds of them,
// forgotten with the track.
class MoverTrails {
 public:
  static constexpr double kSeconds = 3.0;
  using Trail = std::deque<std::pair<Timestamp, Eigen::Vector3d>>;

  // The tracks of a tracked frame at time t (every state: a tentative track's path
  // is there when it is confirmed). A frame without a pose has no tracks and is not
  // given: it would forget them all.
  void Update(const std::vector<MoverSnapshot>& movers, Timestamp t);
  // Oldest first; null for a track not seen.
  const Trail* Of(int id) const;

 private:
  std::map<int, Trail> trails_;
};

// A track's colour, RGBA in [0, 1]: hues a golden ratio of the circle apart from one
// id to the next (tracks born together differ most), none in the band of the
// objects' blue; a lost track's dimmer.
std::array<float, 4> TrackColour(int id, bool lost);

}  // namespace sgslam
