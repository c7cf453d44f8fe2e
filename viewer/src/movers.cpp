#include "movers.h"

#include <algorithm>
#include <cstdint>
#include <map>
#include <string>

namespace sgslam::viewer {

namespace {

nlohmann::json Vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

void Push(std::vector<float>& out, const Eigen::Vector3d& v) {
  out.insert(out.end(), {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())});
}

}  // namespace

nlohmann::json MoversJson(const std::vector<MoverSnapshot>& movers) {
  nlohmann::json out = nlohmann::json::array();
  for (const MoverSnapshot& m : movers) {
    out.push_back({{"id", m.id},
                   {"class", m.class_name},
                   {"state", movers::StateName(m.state)},
                   {"position", Vec(m.position)},
                   {"extent", Vec(m.extent)}});
  }
  return out;
}

std::size_t AddRunTracks(const std::vector<movers::TrackLine>& lines, const Trajectory& trajectory,
                         MessageBuilder& m) {
  std::vector<float> times;
  times.reserve(trajectory.size());
  for (const StampedPose& p : trajectory) times.push_back(static_cast<float>(ToSeconds(p.t - trajectory.front().t)));
  // Each line's frame: tracks.txt and trajectory.txt write the same stamps (a
  // tracked frame's), so the match is exact.
  std::vector<std::pair<std::uint32_t, const movers::TrackLine*>> matched;
  matched.reserve(lines.size());
  for (const movers::TrackLine& l : lines) {
    const auto at = std::lower_bound(trajectory.begin(), trajectory.end(), l.t,
                                     [](const StampedPose& p, Timestamp t) { return p.t < t; });
    if (at == trajectory.end() || at->t != l.t) continue;
    matched.emplace_back(static_cast<std::uint32_t>(at - trajectory.begin()), &l);
  }
  std::stable_sort(matched.begin(), matched.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::map<std::string, std::uint32_t> class_index;
  nlohmann::json classes = nlohmann::json::array();
  std::vector<std::uint32_t> frame, id, cls;
  std::vector<std::uint8_t> state;
  std::vector<float> position, extent;
  for (const auto& [f, l] : matched) {
    const auto [it, added] = class_index.emplace(l->class_name, static_cast<std::uint32_t>(classes.size()));
    if (added) classes.push_back(l->class_name);
    frame.push_back(f);
    id.push_back(static_cast<std::uint32_t>(l->id));
    cls.push_back(it->second);
    state.push_back(static_cast<std::uint8_t>(l->state));
    Push(position, l->position);
    Push(extent, l->extent);
  }
  m.header()["mover_classes"] = std::move(classes);
  m.Add("path_t", times);
  m.Add("mover_frame", frame);
  m.Add("mover_id", id);
  m.Add("mover_class", cls);
  m.Add("mover_state", state);
  m.Add("mover_position", position);
  m.Add("mover_extent", extent);
  return lines.size() - matched.size();
}

}  // namespace sgslam::viewer
