#include "sgslam/map/map_check.h"

namespace sgslam {

std::vector<std::string> CheckMapConsistency(const Map& map) {
  std::vector<std::string> problems;
  const auto say = [&](const std::string& s) {
    if (problems.size() < 50) problems.push_back(s);
  };
  for (const auto& [id, kf] : map.keyframes()) {
    if (kf->bad()) say("keyframe " + std::to_string(id) + " is bad but in the map");
    for (std::size_t i = 0; i < kf->map_points().size(); ++i) {
      const auto& p = kf->map_point(i);
      if (!p) continue;
      if (p->bad()) say("keyframe " + std::to_string(id) + " slot " + std::to_string(i) + " holds a bad point");
      else if (p->IndexIn(id) != static_cast<int>(i))
        say("point " + std::to_string(p->id) + " in keyframe " + std::to_string(id) + " slot " + std::to_string(i) +
            " lacks the matching observation");
      else if (!map.map_points().count(p->id))
        say("point " + std::to_string(p->id) + " seen by keyframe " + std::to_string(id) + " is not in the map");
    }
  }
  for (const auto& [id, p] : map.map_points()) {
    if (p->bad()) say("point " + std::to_string(id) + " is bad but in the map");
    if (p->observations().empty()) say("point " + std::to_string(id) + " has no observation");
    for (const auto& [kf_id, obs] : p->observations()) {
      const auto kf = obs.keyframe.lock();
      if (!kf || kf->bad()) {
        say("point " + std::to_string(id) + " observed by missing or bad keyframe " + std::to_string(kf_id));
      } else if (kf->map_point(obs.index) != p) {
        say("point " + std::to_string(id) + " observation in keyframe " + std::to_string(kf_id) + " slot " +
            std::to_string(obs.index) + " is not mirrored");
      }
    }
  }
  return problems;
}

}  // namespace sgslam
