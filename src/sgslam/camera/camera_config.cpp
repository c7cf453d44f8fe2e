#include "sgslam/camera/camera_config.h"

#include <cmath>

namespace sgslam {

void CameraConfig::Validate(ConfigChecker& c) const {
  c.InRange("width", width, 16, 8192);
  c.InRange("height", height, 16, 8192);
  // Positive is not enough: a focal length of 1e-300 px passes it and ends in a crash.
  for (const auto& [key, f] : {std::pair{"fx", fx}, {"fy", fy}}) {
    c.Positive(key, f);
    if (f > 0 && std::isfinite(f)) c.Check(f >= 1 && f <= 1e5, key, f, "must be a focal length in pixels, 1 to 100000");
  }
  c.InRange("cx", cx, 0.0, static_cast<double>(width));
  c.InRange("cy", cy, 0.0, static_cast<double>(height));
  for (const auto& [key, value] : {std::pair{"k1", k1}, {"k2", k2}, {"p1", p1}, {"p2", p2}, {"k3", k3}}) {
    c.Check(std::isfinite(value) && std::abs(value) < 100.0, key, value, "must be a finite distortion coefficient");
  }
  c.InRange("fps", fps, 0.1, 1000.0);
  c.Positive("depth_factor", depth_factor);
  if (depth_factor > 0 && std::isfinite(depth_factor)) {
    c.Check(depth_factor >= 1e-3 && depth_factor <= 1e6, "depth_factor", depth_factor,
            "must be raw depth units per metre, 0.001 to 1000000 (TUM: 5000, millimetres: 1000)");
  }
  c.Positive("baseline_fx", baseline_fx);
  c.Positive("close_depth", close_depth);
  c.InRange("readout", readout, 0.0, 1.0 / fps);
}

}  // namespace sgslam
