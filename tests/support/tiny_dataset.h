// Small TUM-layout datasets written on the fly, for reader and command-line tests.
#pragma once

#include <filesystem>

#include "sgslam/common/time.h"

#include "sgslam/config/config.h"

namespace sgslam::test {

// The camera of the tiny datasets: 64x48, pinhole, no distortion.
CameraConfig TinyCamera();

// Writes n frames (rgb/, depth/ PNGs at 2 m depth, rgb.txt, depth.txt, and a
// sgslam.yaml with TinyCamera) a period apart (default 30 Hz) into dir. Depth
// stamps lag RGB by 5 ms (a fifth of the period when that is shorter).
void WriteTinyDataset(const std::filesystem::path& dir, int n, Timestamp period = kNsPerSecond / 30);

}  // namespace sgslam::test
