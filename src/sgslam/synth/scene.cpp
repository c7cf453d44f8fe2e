#include "sgslam/synth/scene.h"

namespace sgslam::synth {

SceneObject& Scene::AddObject(ObjectInfo info, std::vector<Quad> quads, std::optional<WalkerMotion> motion) {
  info.id = static_cast<int>(objects.size()) + 1;
  info.dynamic = motion.has_value();
  for (Quad& q : quads) q.object = info.id;
  Eigen::Vector3d min, max;
  Bounds(quads, min, max);
  info.size = max - min;
  info.centroid = motion ? Eigen::Vector3d::Zero() : Eigen::Vector3d(0.5 * (min + max));
  objects.push_back(SceneObject{std::move(info), std::move(quads), std::move(motion)});
  return objects.back();
}

std::vector<Quad> Scene::SurfacesAt(double t) const {
  std::vector<Quad> out = static_quads;
  for (const SceneObject& o : objects) {
    if (!o.motion) {
      out.insert(out.end(), o.quads.begin(), o.quads.end());
      continue;
    }
    const SE3 T_w_o = o.Pose(t);
    for (const Quad& q : o.quads) out.push_back(Transformed(T_w_o, q));
  }
  return out;
}

}  // namespace sgslam::synth
