#include "sgslam/camera/camera_config.h"

#include <cmath>

namespace sgslam {

void CameraConfig::Validate(ConfigChecker& c) const {
  c.InRange("width", width, 16, 8192);
  c.InRange("height", height, 16, 8192);
  c.Positive("fx", fx);
  c.Positive("fy", fy);
  c.InRange("cx", cx, 0.0, static_cast<double>(width));
  c.InRange("cy", cy, 0.0, static_cast<double>(height));
  for (const auto& [key, value] : {std::pair{"k1", k1}, {"k2", k2}, {"p1", p1}, {"p2", p2}, {"k3", k3}}) {
    c.Check(std::isfinite(value) && std::abs(value) < 100.0, key, value, "must be a finite distortion coefficient");
  }
  c.InRange("fps", fps, 0.1, 1000.0);
  c.Positive("depth_factor", depth_factor);
  c.Positive("baseline_fx", baseline_fx);
  c.Positive("close_depth", close_depth);
  c.InRange("readout", readout, 0.0, 1.0 / fps);
}

}  // namespace sgslam
