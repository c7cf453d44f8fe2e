// Point clouds as binary little-endian PLY (x y z as float, optional red green
// blue as uchar), readable by MeshLab, CloudCompare, Open3D and PCL.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

#include <Eigen/Core>

namespace sgslam {

using Rgb = std::array<std::uint8_t, 3>;

// colours: empty, or one per point. Written atomically; throws InputError.
void WritePly(const std::filesystem::path& path, const std::vector<Eigen::Vector3d>& points,
              const std::vector<Rgb>& colours = {});

// Reads what WritePly writes (tests, tools, sgslam view): a regular file of at most
// 1 GiB whose header is checked against its size before anything is allocated.
// Throws InputError naming the file on anything else.
std::vector<Eigen::Vector3d> ReadPlyPoints(const std::filesystem::path& path, std::vector<Rgb>* colours = nullptr);

}  // namespace sgslam
