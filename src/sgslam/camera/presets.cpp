#include "sgslam/camera/presets.h"

#include <algorithm>
#include <cctype>

namespace sgslam {

namespace {

CameraConfig Make(double fx, double fy, double cx, double cy, double k1, double k2, double p1, double p2, double k3) {
  CameraConfig c;
  c.fx = fx;
  c.fy = fy;
  c.cx = cx;
  c.cy = cy;
  c.k1 = k1;
  c.k2 = k2;
  c.p1 = p1;
  c.p2 = p2;
  c.k3 = k3;
  return c;  // 640x480, 30 Hz, depth factor 5000, bf 40, close depth 40: as ORB-SLAM2's TUM settings
}

}  // namespace

std::vector<std::string> CameraPresetNames() { return {"tum_fr1", "tum_fr2", "tum_fr3", "bonn"}; }

std::optional<CameraConfig> CameraPreset(const std::string& name) {
  // TUM RGB-D: https://cvg.cit.tum.de/data/datasets/rgbd-dataset/file_formats (ROS default
  // calibration for fr3, whose images are already undistorted).
  if (name == "tum_fr1") {
    CameraConfig c = Make(517.306408, 516.469215, 318.643040, 255.313989, 0.262383, -0.953104, -0.005358, 0.002628, 1.163314);
    // The Kinect's colour camera has a rolling shutter whose readout takes nearly a
    // frame time (docs/rolling-shutter.md). fr2 and fr3 are left at 0: no data here
    // to measure them on.
    c.readout = 0.03;
    return c;
  }
  if (name == "tum_fr2") return Make(520.908620, 521.007327, 325.141442, 249.701764, 0.231222, -0.784899, -0.003257, -0.000105, 0.917205);
  if (name == "tum_fr3") return Make(535.4, 539.2, 320.1, 247.6, 0, 0, 0, 0, 0);
  // Bonn RGB-D Dynamic: https://www.ipb.uni-bonn.de/data/rgbd-dynamic-dataset/
  if (name == "bonn") return Make(542.822841, 542.576870, 315.593520, 237.756098, 0.039903, -0.099343, -0.000730, -0.000144, 0.0);
  return std::nullopt;
}

std::optional<std::string> CameraPresetForFolder(const std::filesystem::path& dataset_dir) {
  std::string name = dataset_dir.filename().string();
  if (name.empty()) name = dataset_dir.parent_path().filename().string();
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return std::tolower(c); });
  if (name.find("bonn") != std::string::npos) return "bonn";
  for (const char* n : {"1", "2", "3"}) {
    if (name.find(std::string("freiburg") + n) != std::string::npos || name.find(std::string("fr") + n) != std::string::npos) {
      return std::string("tum_fr") + n;
    }
  }
  return std::nullopt;
}

}  // namespace sgslam
