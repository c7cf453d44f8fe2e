#include "sgslam/matching/matcher.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "sgslam/features/hamming.h"
#include "sgslam/matching/projection.h"

namespace sgslam::matcher {

namespace {

constexpr int kHistLength = 30;

double RadiusByViewingCos(double view_cos) { return view_cos > 0.998 ? 2.5 : 4.0; }

// The rejected-keypoint pass of the projection searches: on, and something to match.
bool SecondPass(const Frame& current, int rejected_distance) {
  return rejected_distance > 0 &&
         std::any_of(current.rejected.begin(), current.rejected.end(), [](std::uint8_t r) { return r != 0; });
}

struct Best {
  int dist = 256, second = 256, level = -1, second_level = -1;
  std::size_t index = SIZE_MAX;
  void Offer(int d, std::size_t i, int lvl) {
    if (d < dist) {
      second = dist;
      second_level = level;
      dist = d;
      level = lvl;
      index = i;
    } else if (d < second) {
      second = d;
      second_level = lvl;
    }
  }
};

// Unmatches the frame keypoints matched[k] whose angle change diffs[k] RotationOutliers
// rejects; returns how many.
int DropRotationOutliers(Frame& current, const std::vector<float>& diffs, const std::vector<std::size_t>& matched) {
  const std::vector<std::size_t> drop = RotationOutliers(diffs);
  for (std::size_t k : drop) current.map_points[matched[k]].reset();
  return static_cast<int>(drop.size());
}

}  // namespace

std::vector<std::size_t> RotationOutliers(const std::vector<float>& angle_diffs) {
  std::array<std::vector<std::size_t>, kHistLength> hist;
  for (std::size_t i = 0; i < angle_diffs.size(); ++i) {
    float rot = angle_diffs[i];
    if (rot < 0) rot += 360.0f;
    int bin = static_cast<int>(std::lround(rot * kHistLength / 360.0f));
    if (bin == kHistLength) bin = 0;
    hist[static_cast<std::size_t>(bin)].push_back(i);
  }
  // The three largest bins; the 2nd and 3rd only if at least 10 % of the first.
  std::array<int, 3> top = {-1, -1, -1};
  std::array<std::size_t, 3> size = {0, 0, 0};
  for (int b = 0; b < kHistLength; ++b) {
    const std::size_t s = hist[static_cast<std::size_t>(b)].size();
    if (s > size[0]) {
      top = {b, top[0], top[1]};
      size = {s, size[0], size[1]};
    } else if (s > size[1]) {
      top = {top[0], b, top[1]};
      size = {size[0], s, size[1]};
    } else if (s > size[2]) {
      top[2] = b;
      size[2] = s;
    }
  }
  if (size[1] < 0.1 * size[0]) top[1] = top[2] = -1;
  else if (size[2] < 0.1 * size[0]) top[2] = -1;
  std::vector<std::size_t> drop;
  for (int b = 0; b < kHistLength; ++b) {
    if (b == top[0] || b == top[1] || b == top[2]) continue;
    const auto& v = hist[static_cast<std::size_t>(b)];
    drop.insert(drop.end(), v.begin(), v.end());
  }
  return drop;
}

int SearchByProjection(Frame& current, const Frame& last, double radius_px, int rejected_distance) {
  const Features& cf = *current.features;
  const Features& lf = *last.features;
  const Camera& cam = *cf.camera;
  const Eigen::Vector3d t_l_c = last.T_c_w * current.center();  // current centre in the last camera
  const double baseline = cam.baseline_fx() / cam.fx();
  const bool forward = t_l_c.z() > baseline, backward = -t_l_c.z() > baseline;

  std::vector<float> diffs;
  std::vector<std::size_t> matched;
  std::vector<std::uint8_t> found(last.map_points.size(), 0);
  int n = 0;
  for (const bool rejected_pass : {false, true}) {
    if (rejected_pass && !SecondPass(current, rejected_distance)) break;
    for (std::size_t i = 0; i < last.map_points.size(); ++i) {
      const auto& p = last.map_points[i];
      if (!p || last.outlier[i] || p->bad() || found[i]) continue;
      if (rejected_pass && !p->track.trusted) continue;
      const Eigen::Vector3d p_c = current.T_c_w * p->position();
      if (p_c.z() <= 0) continue;
      const Eigen::Vector2d uv = cam.Project(p_c);
      if (!cf.bounds.Contains(uv.x(), uv.y())) continue;
      const int last_level = lf.keys_un[i].octave;
      // Moving forward, the point looks bigger: search at finer-or-equal scale
      // levels above the last one, and conversely (ORB-SLAM2).
      const double r = radius_px * cf.scale->scale[static_cast<std::size_t>(last_level)];
      const auto candidates = forward    ? cf.InArea(uv.x(), uv.y(), r, last_level)
                              : backward ? cf.InArea(uv.x(), uv.y(), r, 0, last_level)
                                         : cf.InArea(uv.x(), uv.y(), r, last_level - 1, last_level + 1);
      const double ur = uv.x() - cam.baseline_fx() / p_c.z();
      Best best;
      for (std::size_t j : candidates) {
        if (current.map_points[j] || (current.rejected[j] != 0) != rejected_pass) continue;
        if (cf.u_right[j] > 0 && std::abs(ur - cf.u_right[j]) > r) continue;
        best.Offer(features::HammingDistance(p->descriptor(), cf.descriptor(j)), j, cf.keys_un[j].octave);
      }
      if (best.dist > (rejected_pass ? rejected_distance : kThHigh)) continue;
      current.map_points[best.index] = p;
      found[i] = 1;
      diffs.push_back(lf.keys[i].angle - cf.keys[best.index].angle);
      matched.push_back(best.index);
      ++n;
    }
  }
  return n - DropRotationOutliers(current, diffs, matched);
}

int SearchByProjection(Frame& current, const KeyFrame& keyframe, double radius_px, int max_distance) {
  const Features& cf = *current.features;
  const Features& kf = *keyframe.features;
  const Eigen::Vector3d center = current.center();
  std::vector<const MapPoint*> have;
  for (const auto& p : current.map_points) {
    if (p) have.push_back(p.get());
  }
  std::sort(have.begin(), have.end());
  std::vector<float> diffs;
  std::vector<std::size_t> matched;
  int n = 0;
  for (std::size_t i = 0; i < keyframe.map_points().size(); ++i) {
    const auto& p = keyframe.map_point(i);
    if (!p || p->bad() || std::binary_search(have.begin(), have.end(), p.get())) continue;
    const auto w = ProjectForSearch(*p, current.T_c_w, center, cf, radius_px, /*view_check=*/false);
    if (!w) continue;
    Best best;
    for (std::size_t j : cf.InArea(w->uv.x(), w->uv.y(), w->radius, w->level - 1, w->level + 1)) {
      if (current.map_points[j] || current.rejected[j]) continue;
      best.Offer(features::HammingDistance(p->descriptor(), cf.descriptor(j)), j, cf.keys_un[j].octave);
    }
    if (best.index == SIZE_MAX || best.dist > max_distance) continue;
    current.map_points[best.index] = p;
    diffs.push_back(kf.keys[i].angle - cf.keys[best.index].angle);
    matched.push_back(best.index);
    ++n;
  }
  return n - DropRotationOutliers(current, diffs, matched);
}

int SearchLocalPoints(Frame& current, const std::vector<std::shared_ptr<MapPoint>>& points, double th,
                      int rejected_distance) {
  const Features& cf = *current.features;
  std::vector<std::uint8_t> found(points.size(), 0);
  int n = 0;
  for (const bool rejected_pass : {false, true}) {
    if (rejected_pass && !SecondPass(current, rejected_distance)) break;
    for (std::size_t k = 0; k < points.size(); ++k) {
      const auto& p = points[k];
      if (!p->track.in_view || p->bad() || p->track.last_frame_seen == current.id || found[k]) continue;
      if (rejected_pass && !p->track.trusted) continue;
      const int level = p->track.predicted_level;
      const double r = th * RadiusByViewingCos(p->track.view_cos) * cf.scale->scale[static_cast<std::size_t>(level)];
      Best best;
      for (std::size_t j : cf.InArea(p->track.u, p->track.v, r, level - 1, level)) {
        if ((current.rejected[j] != 0) != rejected_pass) continue;
        if (const auto& q = current.map_points[j]; q && q->num_observations() > 0) continue;
        if (cf.u_right[j] > 0 && std::abs(p->track.u_right - cf.u_right[j]) > r) continue;
        best.Offer(features::HammingDistance(p->descriptor(), cf.descriptor(j)), j, cf.keys_un[j].octave);
      }
      if (best.dist > (rejected_pass ? rejected_distance : kThHigh)) continue;
      // Ambiguous at the same level: the best must clearly beat the second.
      if (best.level == best.second_level && best.dist > 0.8 * best.second) continue;
      current.map_points[best.index] = p;
      found[k] = 1;
      ++n;
    }
  }
  return n;
}

namespace {

// The keyframe's mapped keypoints matched to the frame's kept keypoints that
// candidates(i) lists for keypoint i: best distance below kThLow and below ratio
// times the second best, the closest claim on each frame keypoint, then rotation
// consistency. Sets current.map_points; returns the matches.
template <typename Candidates>
int MatchKeyFrameToFrame(const KeyFrame& keyframe, Frame& current, double ratio, Candidates candidates) {
  const Features& kf = *keyframe.features;
  const Features& cf = *current.features;
  std::vector<int> best_for_current(cf.size(), 257);
  std::vector<std::size_t> source(cf.size(), SIZE_MAX);
  candidates([&](std::size_t i, const auto& js) {
    const auto& p = keyframe.map_point(i);
    if (!p || p->bad()) return;
    Best best;
    for (const std::size_t j : js) {
      if (current.rejected[j]) continue;
      best.Offer(features::HammingDistance(kf.descriptor(i), cf.descriptor(j)), j, 0);
    }
    if (best.index == SIZE_MAX || best.dist > kThLow || best.dist > ratio * best.second) return;
    if (best.dist >= best_for_current[best.index]) return;  // keep the closest claim
    best_for_current[best.index] = best.dist;
    source[best.index] = i;
  });
  std::vector<float> diffs;
  std::vector<std::size_t> matched;
  int n = 0;
  for (std::size_t j = 0; j < cf.size(); ++j) {
    if (source[j] == SIZE_MAX) continue;
    current.map_points[j] = keyframe.map_point(source[j]);
    diffs.push_back(kf.keys[source[j]].angle - cf.keys[j].angle);
    matched.push_back(j);
    ++n;
  }
  return n - DropRotationOutliers(current, diffs, matched);
}

// 0, 1, ..., n - 1 without storing them.
struct Indices {
  std::size_t n;
  struct It {
    std::size_t i;
    std::size_t operator*() const { return i; }
    It& operator++() { return ++i, *this; }
    bool operator!=(const It& o) const { return i != o.i; }
  };
  It begin() const { return {0}; }
  It end() const { return {n}; }
};

}  // namespace

int SearchByDescriptor(const KeyFrame& keyframe, Frame& current, double ratio) {
  const Indices all{current.features->size()};
  return MatchKeyFrameToFrame(keyframe, current, ratio, [&](const auto& visit) {
    for (std::size_t i = 0; i < keyframe.features->size(); ++i) visit(i, all);
  });
}

int SearchByBow(const KeyFrame& keyframe, Frame& current, const vocab::FeatureVector& current_nodes, double ratio) {
  if (!keyframe.bow) return 0;
  const vocab::FeatureVector& kf_nodes = keyframe.bow->nodes;
  return MatchKeyFrameToFrame(keyframe, current, ratio, [&](const auto& visit) {
    vocab::ForEachShared(kf_nodes, current_nodes, [&](const auto& a, const auto& b) {
      for (const std::uint32_t k : a.second) visit(k, b.second);
    });
  });
}

}  // namespace sgslam::matcher
