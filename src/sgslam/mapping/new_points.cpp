// Triangulation of new map points between a new keyframe and its covisible
// keyframes (ORB-SLAM2's CreateNewMapPoints, RGB-D variant: depth is used where
// it gives more parallax than the two rays).
#include <cmath>
#include <mutex>
#include <shared_mutex>

#include "sgslam/matching/matcher.h"
#include "sgslam/mapping/local_mapper.h"
#include "sgslam/geometry/epipolar.h"
#include "sgslam/geometry/triangulation.h"

namespace sgslam {

namespace {

constexpr std::size_t kTriangulationNeighbours = 10;  // covisible keyframes searched for new points (ORB-SLAM2)

struct Candidate {
  std::shared_ptr<KeyFrame> kf2;
  std::size_t i1, i2;
  Eigen::Vector3d p_w;
};

// Reprojection test of p_w in keyframe kf at keypoint i (chi2 at 95 %).
bool Reprojects(const KeyFrame& kf, std::size_t i, const Eigen::Vector3d& p_w) {
  const Features& f = *kf.features;
  const Eigen::Vector3d p_c = kf.T_c_w() * p_w;
  if (p_c.z() <= 0) return false;
  const Eigen::Vector2d uv = f.camera->Project(p_c);
  const double inv_s2 = f.scale->inv_sigma2[static_cast<std::size_t>(f.keys_un[i].octave)];
  const double ex = uv.x() - f.keys_un[i].pt.x, ey = uv.y() - f.keys_un[i].pt.y;
  if (f.u_right[i] < 0) return (ex * ex + ey * ey) * inv_s2 <= 5.991;
  const double er = uv.x() - f.camera->baseline_fx() / p_c.z() - f.u_right[i];
  return (ex * ex + ey * ey + er * er) * inv_s2 <= 7.8;
}

}  // namespace

int LocalMapper::CreateNewMapPoints(const std::shared_ptr<KeyFrame>& kf) {
  std::vector<Candidate> candidates;
  {
    std::shared_lock lock(map_.mutex());
    const Features& f1 = *kf->features;
    const Camera& cam = *f1.camera;
    const geometry::Pinhole K{cam.fx(), cam.fy(), cam.cx(), cam.cy()};
    const double baseline = cam.baseline_fx() / cam.fx();
    const SE3 T_1w = kf->T_c_w();
    const Eigen::Matrix3d R_w1 = kf->T_w_c().rotation();
    const double ratio_factor = 1.5 * f1.scale->factor;
    for (const auto& kf2 : kf->Covisibles(kTriangulationNeighbours)) {
      if ((kf2->center() - kf->center()).norm() < baseline) continue;  // depth beats this parallax
      const Features& f2 = *kf2->features;
      const SE3 T_2w = kf2->T_c_w();
      const Eigen::Matrix3d R_w2 = kf2->T_w_c().rotation();
      for (const auto& [i1, i2] : matcher::SearchForTriangulation(*kf, *kf2, geometry::FundamentalMatrix(T_2w * T_1w.Inverse(), K))) {
        const Eigen::Vector3d x1((f1.keys_un[i1].pt.x - cam.cx()) / cam.fx(), (f1.keys_un[i1].pt.y - cam.cy()) / cam.fy(), 1);
        const Eigen::Vector3d x2((f2.keys_un[i2].pt.x - cam.cx()) / cam.fx(), (f2.keys_un[i2].pt.y - cam.cy()) / cam.fy(), 1);
        const Eigen::Vector3d ray1 = R_w1 * x1, ray2 = R_w2 * x2;
        const double cos_rays = ray1.dot(ray2) / (ray1.norm() * ray2.norm());
        const bool stereo1 = f1.depth[i1] > 0, stereo2 = f2.depth[i2] > 0;
        const double cos_stereo1 = stereo1 ? std::cos(2 * std::atan2(baseline / 2, f1.depth[i1])) : 2.0;
        const double cos_stereo2 = stereo2 ? std::cos(2 * std::atan2(baseline / 2, f2.depth[i2])) : 2.0;
        const double cos_stereo = std::min(cos_stereo1, cos_stereo2);
        Eigen::Vector3d p_w;
        if (cos_rays < cos_stereo && cos_rays > 0 && (stereo1 || stereo2 || cos_rays < 0.9998)) {
          const auto t = geometry::Triangulate(x1, x2, T_1w, T_2w);
          if (!t) continue;
          p_w = *t;
        } else if (stereo1 && cos_stereo1 < cos_stereo2) {
          p_w = kf->T_w_c() * f1.Unproject(i1);
        } else if (stereo2 && cos_stereo2 < cos_stereo1) {
          p_w = kf2->T_w_c() * f2.Unproject(i2);
        } else {
          continue;  // no parallax
        }
        if (!Reprojects(*kf, i1, p_w) || !Reprojects(*kf2, i2, p_w)) continue;
        // Scale consistency: the distance ratio must agree with the level ratio.
        const double d1 = (p_w - kf->center()).norm(), d2 = (p_w - kf2->center()).norm();
        if (d1 <= 0 || d2 <= 0) continue;
        const double ratio_dist = d2 / d1;
        const double ratio_octave = f1.scale->scale[static_cast<std::size_t>(f1.keys_un[i1].octave)] /
                                    f2.scale->scale[static_cast<std::size_t>(f2.keys_un[i2].octave)];
        if (ratio_dist * ratio_factor < ratio_octave || ratio_dist > ratio_octave * ratio_factor) continue;
        candidates.push_back({kf2, i1, i2, p_w});
      }
    }
  }
  std::unique_lock lock(map_.mutex());
  int created = 0;
  for (const auto& c : candidates) {
    // Another neighbour (or fusion) may have taken a slot since the search.
    if (kf->map_point(c.i1) || c.kf2->map_point(c.i2) || c.kf2->bad()) continue;
    auto p = std::make_shared<MapPoint>(map_.NewMapPointId(), c.p_w, kf);
    p->AddObservation(kf, c.i1);
    p->AddObservation(c.kf2, c.i2);
    kf->SetMapPoint(c.i1, p);
    c.kf2->SetMapPoint(c.i2, p);
    p->UpdateDescriptor();
    p->UpdateNormalAndDepth();
    map_.AddMapPoint(p);
    recent_points_.push_back(p);
    ++created;
  }
  return created;
}

}  // namespace sgslam
