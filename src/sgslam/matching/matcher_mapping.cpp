// The matcher functions local mapping uses: fusion of duplicate points and the
// search for new correspondences to triangulate. Keypoints that tracking rejected
// as dynamic (Features::dynamic) are never used: tracking neither matches nor maps
// them, and local mapping must not either (fusing a map point into a moving
// keypoint, or triangulating two of them, puts the mover back into the map).
#include <algorithm>
#include <cmath>

#include "sgslam/features/hamming.h"
#include "sgslam/matching/matcher.h"
#include "sgslam/matching/projection.h"

namespace sgslam::matcher {

namespace {
bool IsDynamic(const Features& f, std::size_t i) { return i < f.dynamic.size() && f.dynamic[i] != 0; }
}  // namespace

int Fuse(const std::shared_ptr<KeyFrame>& keyframe, const std::vector<std::shared_ptr<MapPoint>>& points, Map& map,
         double th) {
  const Features& f = *keyframe->features;
  const Camera& cam = *f.camera;
  const SE3 T_c_w = keyframe->T_c_w();
  const Eigen::Vector3d center = keyframe->center();
  int fused = 0;
  for (const auto& p : points) {
    if (!p || p->bad() || p->IndexIn(keyframe->id) >= 0) continue;
    const auto w = ProjectForSearch(*p, T_c_w, center, f, th, /*view_check=*/true);
    if (!w) continue;
    const Eigen::Vector2d& uv = w->uv;
    const int level = w->level;
    const double r = w->radius;
    const double ur = uv.x() - cam.baseline_fx() / w->depth;
    int best_dist = 256;
    std::size_t best = SIZE_MAX;
    for (std::size_t j : f.InArea(uv.x(), uv.y(), r)) {
      if (IsDynamic(f, j)) continue;
      const int kl = f.keys_un[j].octave;
      if (kl < level - 1 || kl > level) continue;
      const double ex = uv.x() - f.keys_un[j].pt.x, ey = uv.y() - f.keys_un[j].pt.y;
      const double inv_s2 = f.scale->inv_sigma2[static_cast<std::size_t>(kl)];
      if (f.u_right[j] >= 0) {
        const double er = ur - f.u_right[j];
        if ((ex * ex + ey * ey + er * er) * inv_s2 > 7.8) continue;  // chi2 3 dof, 95 %
      } else if ((ex * ex + ey * ey) * inv_s2 > 5.99) {
        continue;  // chi2 2 dof, 95 %
      }
      const int d = features::HammingDistance(p->descriptor(), f.descriptor(j));
      if (d < best_dist) {
        best_dist = d;
        best = j;
      }
    }
    if (best_dist > kThLow) continue;
    if (const auto existing = keyframe->map_point(best); existing && !existing->bad()) {
      // Keep the better-established point.
      if (existing->num_observations() > p->num_observations()) p->ReplaceWith(existing, map);
      else existing->ReplaceWith(p, map);
    } else {
      p->AddObservation(keyframe, best);
      keyframe->SetMapPoint(best, p);
    }
    ++fused;
  }
  return fused;
}

std::vector<std::pair<std::size_t, std::size_t>> SearchForTriangulation(const KeyFrame& kf1, const KeyFrame& kf2,
                                                                         const Eigen::Matrix3d& F_21) {
  const Features& f1 = *kf1.features;
  const Features& f2 = *kf2.features;
  // Epipole of camera 1 in image 2: points next to it give no parallax.
  const Eigen::Vector3d c1_in_2 = kf2.T_c_w() * kf1.center();
  const Eigen::Vector2d epipole = f2.camera->Project(c1_in_2);
  const bool epipole_valid = c1_in_2.z() > 0;

  std::vector<std::size_t> free2;
  for (std::size_t j = 0; j < f2.size(); ++j) {
    if (!kf2.map_point(j) && !IsDynamic(f2, j)) free2.push_back(j);
  }
  std::vector<int> best_for_2(f2.size(), 257);
  std::vector<std::size_t> match_of_2(f2.size(), SIZE_MAX);
  for (std::size_t i = 0; i < f1.size(); ++i) {
    if (kf1.map_point(i) || IsDynamic(f1, i)) continue;
    const cv::Point2f& x1 = f1.keys_un[i].pt;
    const Eigen::Vector3d line = F_21 * Eigen::Vector3d(x1.x, x1.y, 1.0);  // epipolar line in image 2
    const double norm2 = line.x() * line.x() + line.y() * line.y();
    if (norm2 < 1e-12) continue;
    const bool stereo1 = f1.u_right[i] >= 0;
    int best_dist = kThLow + 1;
    std::size_t best = SIZE_MAX;
    for (std::size_t j : free2) {
      const cv::Point2f& x2 = f2.keys_un[j].pt;
      const double num = line.x() * x2.x + line.y() * x2.y + line.z();
      const double sigma2 = f2.scale->sigma2[static_cast<std::size_t>(f2.keys_un[j].octave)];
      if (num * num / norm2 > 3.84 * sigma2) continue;  // chi2 1 dof, 95 %
      const int d = features::HammingDistance(f1.descriptor(i), f2.descriptor(j));
      if (d >= best_dist) continue;
      if (!stereo1 && f2.u_right[j] < 0 && epipole_valid) {
        const double ex = epipole.x() - x2.x, ey = epipole.y() - x2.y;
        if (ex * ex + ey * ey < 100.0 * f2.scale->scale[static_cast<std::size_t>(f2.keys_un[j].octave)]) continue;
      }
      best_dist = d;
      best = j;
    }
    if (best == SIZE_MAX || best_dist >= best_for_2[best]) continue;
    best_for_2[best] = best_dist;
    match_of_2[best] = i;
  }
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  std::vector<float> diffs;
  for (std::size_t j = 0; j < f2.size(); ++j) {
    if (match_of_2[j] == SIZE_MAX) continue;
    pairs.emplace_back(match_of_2[j], j);
    diffs.push_back(f1.keys[match_of_2[j]].angle - f2.keys[j].angle);
  }
  std::vector<std::size_t> drop = RotationOutliers(diffs);
  std::sort(drop.rbegin(), drop.rend());
  for (std::size_t k : drop) pairs.erase(pairs.begin() + static_cast<std::ptrdiff_t>(k));
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

}  // namespace sgslam::matcher
