// The matcher functions loop closing uses: keyframe-to-keyframe matching through
// the vocabulary's direct index, and the search of a loop's map points in the
// current keyframe at its corrected pose. Keypoints tracking rejected as dynamic
// are never matched (matcher_mapping.cpp says why).
#include <algorithm>
#include <cmath>

#include "sgslam/features/hamming.h"
#include "sgslam/matching/matcher.h"
#include "sgslam/matching/projection.h"

namespace sgslam::matcher {

namespace {
bool IsDynamic(const Features& f, std::size_t i) { return i < f.dynamic.size() && f.dynamic[i] != 0; }
}  // namespace

std::vector<std::shared_ptr<MapPoint>> SearchByBow(const KeyFrame& kf1, const KeyFrame& kf2, double ratio) {
  const Features& f1 = *kf1.features;
  const Features& f2 = *kf2.features;
  std::vector<std::shared_ptr<MapPoint>> matched(f1.size());
  if (!kf1.bow || !kf2.bow) return matched;
  std::vector<std::uint8_t> taken(f2.size(), 0);
  std::vector<float> diffs;
  std::vector<std::size_t> index;
  const auto match_node = [&](const std::vector<std::uint32_t>& a, const std::vector<std::uint32_t>& b) {
    for (const std::uint32_t i : a) {
      const auto& p1 = kf1.map_point(i);
      if (!p1 || p1->bad() || IsDynamic(f1, i)) continue;
      int best = 256, second = 256;
      std::size_t best_j = SIZE_MAX;
      for (const std::uint32_t j : b) {
        const auto& p2 = kf2.map_point(j);
        if (taken[j] || !p2 || p2->bad() || IsDynamic(f2, j)) continue;
        const int d = features::HammingDistance(f1.descriptor(i), f2.descriptor(j));
        if (d < best) {
          second = best, best = d, best_j = j;
        } else if (d < second) {
          second = d;
        }
      }
      if (best_j == SIZE_MAX || best > kThLow || best > ratio * second) continue;
      matched[i] = kf2.map_point(best_j);
      taken[best_j] = 1;
      diffs.push_back(f1.keys[i].angle - f2.keys[best_j].angle);
      index.push_back(i);
    }
  };
  vocab::ForEachShared(kf1.bow->nodes, kf2.bow->nodes,
                       [&](const auto& a, const auto& b) { match_node(a.second, b.second); });
  for (std::size_t k : RotationOutliers(diffs)) matched[index[k]].reset();
  return matched;
}

int SearchByProjection(const KeyFrame& kf, const SE3& T_c_w, const std::vector<std::shared_ptr<MapPoint>>& points,
                       std::vector<std::shared_ptr<MapPoint>>& matched, double th) {
  const Features& f = *kf.features;
  const Eigen::Vector3d center = T_c_w.Inverse().translation();
  std::vector<const MapPoint*> have;
  for (const auto& p : matched) {
    if (p) have.push_back(p.get());
  }
  std::sort(have.begin(), have.end());
  int n = 0;
  for (const auto& p : points) {
    if (!p || p->bad() || std::binary_search(have.begin(), have.end(), p.get())) continue;
    const auto w = ProjectForSearch(*p, T_c_w, center, f, th, /*view_check=*/true);
    if (!w) continue;
    int best = 256;
    std::size_t best_j = SIZE_MAX;
    for (std::size_t j : f.InArea(w->uv.x(), w->uv.y(), w->radius, w->level - 1, w->level)) {
      if (matched[j] || IsDynamic(f, j)) continue;
      const int d = features::HammingDistance(p->descriptor(), f.descriptor(j));
      if (d < best) best = d, best_j = j;
    }
    if (best_j == SIZE_MAX || best > kThLow) continue;
    matched[best_j] = p;
    ++n;
  }
  return n;
}

}  // namespace sgslam::matcher
