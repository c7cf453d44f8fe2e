#include "sgslam/system/mover_trails.h"

#include <algorithm>
#include <cmath>

namespace sgslam {

void MoverTrails::Update(const std::vector<MoverSnapshot>& movers, Timestamp t) {
  std::map<int, Trail> kept;
  for (const MoverSnapshot& m : movers) {
    Trail& trail = kept[m.id];
    if (auto it = trails_.find(m.id); it != trails_.end()) trail = std::move(it->second);
    trail.emplace_back(t, m.position);
    while (t - trail.front().first > FromSeconds(kSeconds)) trail.pop_front();
  }
  trails_ = std::move(kept);
}

const MoverTrails::Trail* MoverTrails::Of(int id) const {
  const auto it = trails_.find(id);
  return it == trails_.end() ? nullptr : &it->second;
}

std::array<float, 4> TrackColour(int id, bool lost) {
  const double turn = std::fmod(id * 0.6180339887, 1.0);
  const double hue = std::fmod(0.72 + 0.8 * turn, 1.0) * 6;  // in sextants from red: 3.1-4.3 (blue) left out
  const double s = 0.8, v = lost ? 0.5 : 1.0;
  const auto channel = [&](double n) {
    const double k = std::fmod(n + hue, 6.0);
    return static_cast<float>(v - v * s * std::max(0.0, std::min({k, 4 - k, 1.0})));
  };
  return {channel(5), channel(3), channel(1), lost ? 0.6f : 1.f};
}

}  // namespace sgslam
