#include "sgslam/mapfile/map_check.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <set>
#include <vector>

#include "sgslam/common/error.h"

namespace sgslam::mapfile {

void FailMapFile(const std::string& what, const std::string& why) { throw InputError("map file " + what + ": " + why); }

namespace {

bool Finite(const Pose& p) {
  const double n = std::sqrt(p.q[0] * p.q[0] + p.q[1] * p.q[1] + p.q[2] * p.q[2] + p.q[3] * p.q[3]);
  return std::all_of(p.t.begin(), p.t.end(), [](double v) { return std::isfinite(v); }) && std::abs(n - 1) < 1e-6;
}

template <typename C>
bool AllFinite(const C& c) {
  return std::all_of(c.begin(), c.end(), [](auto v) { return std::isfinite(v); });
}

// A keypoint's coordinate (px) within 1e6 of 0, and so finite: far beyond any
// image, and far inside int's range, to which the feature grid casts its cell.
bool PixelInRange(float v) { return std::abs(v) <= 1e6f; }

// The checks of one keyframe's own arrays; "" when they are consistent.
std::string CheckKeyFrameArrays(const KeyFrameData& k, int levels) {
  const std::size_t n = k.keys.size();
  if (!Finite(k.T_c_w) || !Finite(k.T_c_parent)) return "a pose is not finite or not a rotation";
  if (k.culled) return n == 0 ? "" : "a culled keyframe with keypoints";
  if (k.keys_un.size() != n || k.depth.size() != n || k.u_right.size() != n || k.point_ids.size() != n ||
      k.descriptors.size() != 32 * n || (!k.dynamic.empty() && k.dynamic.size() != n) ||
      (!k.unjudged.empty() && k.unjudged.size() != n)) {
    return "per-keypoint arrays of different lengths";
  }
  for (std::size_t i = 0; i < n; ++i) {
    const KeyPointData& p = k.keys[i];
    // Matching bins the angle (0-360 degrees) and indexes the pyramid by octave.
    if (!PixelInRange(p.x) || !PixelInRange(p.y) || !PixelInRange(k.keys_un[i][0]) || !PixelInRange(k.keys_un[i][1]) ||
        p.octave < 0 || p.octave >= levels || !(p.angle >= 0 && p.angle < 360) || !std::isfinite(p.size) ||
        !std::isfinite(p.response)) {
      return "keypoint " + std::to_string(i) + " is out of range";
    }
  }
  if (!AllFinite(k.depth) || !AllFinite(k.u_right) || !AllFinite(k.angular_velocity)) return "a depth is not finite";
  for (const auto& [node, indices] : k.bow_nodes) {
    if (std::any_of(indices.begin(), indices.end(), [&](std::uint32_t i) { return i >= n; })) {
      return "a bag-of-words entry names a keypoint it does not have";
    }
  }
  return "";
}

void CheckKeyFrames(const MapData& d, const std::string& what, std::map<std::uint64_t, const KeyFrameData*>& kfs) {
  for (const KeyFrameData& k : d.keyframes) {
    if (k.id >= d.next_keyframe_id || !kfs.emplace(k.id, &k).second) FailMapFile(what, "keyframe id " + std::to_string(k.id) + " repeated or out of range");
    if (const std::string why = CheckKeyFrameArrays(k, d.settings.orb_levels); !why.empty()) {
      FailMapFile(what, "keyframe " + std::to_string(k.id) + ": " + why);
    }
  }
  // Parent chains end (PlacedT_c_w and the spanning tree walk them).
  std::map<std::uint64_t, int> state;  // 1: being walked, 2: ends
  for (const KeyFrameData& k : d.keyframes) {
    std::vector<std::uint64_t> chain;
    for (std::uint64_t id = k.id; id != kNoId && kfs.count(id) && state[id] != 2; id = kfs.at(id)->parent) {
      if (state[id] == 1) FailMapFile(what, "keyframe " + std::to_string(id) + " is its own ancestor");
      state[id] = 1;
      chain.push_back(id);
    }
    for (std::uint64_t id : chain) state[id] = 2;
  }
  std::set<std::uint64_t> point_ids;
  for (const MapPointData& p : d.points) point_ids.insert(p.id);
  for (const KeyFrameData& k : d.keyframes) {
    const auto live = [&](std::uint64_t id) { return kfs.count(id) && !kfs.at(id)->culled; };
    const auto fail = [&](const std::string& which, std::uint64_t id) {
      FailMapFile(what, "keyframe " + std::to_string(k.id) + " refers to " + which + " " + std::to_string(id) +
                     ", which the map does not have");
    };
    if (k.parent != kNoId && (!kfs.count(k.parent) || k.parent == k.id)) fail("parent keyframe", k.parent);
    for (const auto& [other, weight] : k.connections) {
      if (!live(other) || other == k.id) fail("covisible keyframe", other);
    }
    for (const auto& [other, weight] : k.covisible_order) {
      if (!live(other) || other == k.id) fail("covisible keyframe", other);
    }
    for (std::uint64_t other : k.loop_edges) {
      if (!live(other) || other == k.id) fail("loop keyframe", other);
    }
    for (std::uint64_t p : k.point_ids) {
      if (p != kNoId && !point_ids.count(p)) fail("map point", p);
    }
  }
}

void CheckPoints(const MapData& d, const std::string& what, const std::map<std::uint64_t, const KeyFrameData*>& kfs) {
  std::uint64_t last = 0;
  for (std::size_t i = 0; i < d.points.size(); ++i) {
    const MapPointData& p = d.points[i];
    const std::string name = "map point " + std::to_string(p.id);
    if (p.id >= d.next_point_id || (i > 0 && p.id <= last)) FailMapFile(what, name + ": id repeated, unordered or out of range");
    last = p.id;
    if (!AllFinite(p.position) || !AllFinite(p.normal) || !std::isfinite(p.min_distance) || !std::isfinite(p.max_distance)) {
      FailMapFile(what, name + ": not finite");
    }
    if (p.observations.empty() || (p.reference != kNoId && !kfs.count(p.reference))) FailMapFile(what, name + ": no observation, or an unknown reference");
    for (std::size_t k = 1; k < p.observations.size(); ++k) {
      if (p.observations[k].first <= p.observations[k - 1].first) FailMapFile(what, name + ": observations repeated or unordered");
    }
    for (const auto& [kf, index] : p.observations) {
      const auto it = kfs.find(kf);
      if (it == kfs.end() || it->second->culled || index >= it->second->point_ids.size() ||
          it->second->point_ids[index] != p.id) {
        FailMapFile(what, name + ": an observation does not match its keyframe");
      }
    }
  }
}

void CheckSemantic(const MapData& d, const std::string& what, const std::map<std::uint64_t, const KeyFrameData*>& kfs) {
  const auto image_ok = [](const ImageData& i) {
    return i.rows >= 0 && i.cols >= 0 && i.pixels.size() == static_cast<std::size_t>(i.rows) * i.cols &&
           AllFinite(i.pixels);
  };
  const auto points_ok = [](const std::vector<ColoredPointData>& points) {
    return std::all_of(points.begin(), points.end(), [](const ColoredPointData& p) { return AllFinite(p.p); });
  };
  for (const CloudData& c : d.semantic.clouds) {
    // The movers' depth is none or one per pooled depth pixel (the filters index both alike).
    const bool moving_ok = c.moving_pooled.pixels.empty() || (c.moving_pooled.rows == c.depth_pooled.rows &&
                                                              c.moving_pooled.cols == c.depth_pooled.cols);
    if (!kfs.count(c.keyframe) || !image_ok(c.depth_pooled) || !image_ok(c.moving_pooled) || !moving_ok ||
        !points_ok(c.points_c) || !points_ok(c.rays_c)) {
      FailMapFile(what, "the cloud of keyframe " + std::to_string(c.keyframe) + " is inconsistent");
    }
  }
  for (const ObjectData& o : d.semantic.objects) {
    bool ok = !o.observations.empty() && o.views_seen >= 0 && o.views_expected >= o.views_seen && o.missing >= 0;
    for (const ObjectObservationData& obs : o.observations) {
      ok = ok && (obs.keyframe == kNoId || kfs.count(obs.keyframe)) && Finite(obs.T_w_c_added) && AllFinite(obs.box) &&
           std::isfinite(obs.score) &&
           std::all_of(obs.points_c.begin(), obs.points_c.end(), [](const auto& p) { return AllFinite(p); });
    }
    if (!ok) FailMapFile(what, "object " + std::to_string(o.id) +
                                   " is inconsistent (no view, an unknown keyframe, a count or a value out of range)");
  }
}

}  // namespace

void CheckMapData(const MapData& d, const std::string& what) {
  if (d.settings.orb_levels <= 0 || d.settings.orb_levels > 32 || !(d.settings.orb_scale_factor > 1)) {
    FailMapFile(what, "ORB settings out of range");
  }
  // Ids continue after these: far from wrapping around.
  constexpr std::uint64_t kMaxId = std::uint64_t{1} << 62;
  if (d.next_keyframe_id > kMaxId || d.next_point_id > kMaxId || d.next_frame_id > kMaxId ||
      d.semantic.next_object_id < 1) {
    FailMapFile(what, "id counters out of range");
  }
  if (std::none_of(d.keyframes.begin(), d.keyframes.end(), [](const KeyFrameData& k) { return !k.culled; })) {
    FailMapFile(what, "the map holds no keyframe");
  }
  std::map<std::uint64_t, const KeyFrameData*> kfs;
  CheckKeyFrames(d, what, kfs);
  CheckPoints(d, what, kfs);
  CheckSemantic(d, what, kfs);
}

}  // namespace sgslam::mapfile
