#include "sgslam/io/trajectory.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "sgslam/common/error.h"
#include "sgslam/io/atomic_write.h"
#include "sgslam/io/text_file.h"

namespace sgslam {

Trajectory ReadTumTrajectory(const std::filesystem::path& path) {
  Trajectory out;
  ForEachDataLine(path, [&](int line, const std::vector<std::string_view>& tok) {
    if (tok.size() != 8) {
      throw ParseError(path.string(), line,
                       "expected 8 fields 'timestamp tx ty tz qx qy qz qw', got " + std::to_string(tok.size()));
    }
    const auto t = ParseTimestamp(tok[0]);
    if (!t) throw ParseError(path.string(), line, "bad timestamp '" + std::string(tok[0]) + "'");
    double v[7];
    static const char* kNames[7] = {"tx", "ty", "tz", "qx", "qy", "qz", "qw"};
    for (int i = 0; i < 7; ++i) v[i] = ParseNumber(tok[i + 1], path, line, kNames[i]);
    const Eigen::Quaterniond q(v[6], v[3], v[4], v[5]);
    const double norm = q.norm();
    if (norm < 1e-6) throw ParseError(path.string(), line, "quaternion has zero norm");
    // Components beyond ~1e154 overflow the norm, and normalising by it would give zero.
    if (!std::isfinite(norm)) throw ParseError(path.string(), line, "quaternion too large to normalise");
    out.push_back({*t, SE3(q, Eigen::Vector3d(v[0], v[1], v[2]))});
  });
  std::stable_sort(out.begin(), out.end(), [](const StampedPose& a, const StampedPose& b) { return a.t < b.t; });
  return out;
}

void WriteTumTrajectory(const std::filesystem::path& path, const Trajectory& trajectory) {
  std::string text = "# timestamp tx ty tz qx qy qz qw (T_w_c)\n";
  char buf[256];
  for (const StampedPose& p : trajectory) {
    const Eigen::Vector3d& t = p.T_w_c.translation();
    const Eigen::Quaterniond& q = p.T_w_c.quaternion();
    std::snprintf(buf, sizeof buf, " %.9g %.9g %.9g %.9g %.9g %.9g %.9g\n", t.x(), t.y(), t.z(), q.x(), q.y(),
                  q.z(), q.w());
    text += FormatTimestamp(p.t);
    text += buf;
  }
  WriteFileAtomically(path, text);
}

}  // namespace sgslam
