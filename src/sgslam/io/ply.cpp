#include "sgslam/io/ply.h"

#include <bit>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "sgslam/common/error.h"
#include "sgslam/io/text_file.h"

namespace sgslam {

static_assert(std::endian::native == std::endian::little, "PLY output assumes a little-endian host");

void WritePly(const std::filesystem::path& path, const std::vector<Eigen::Vector3d>& points,
              const std::vector<Rgb>& colours) {
  if (!colours.empty() && colours.size() != points.size()) {
    throw Error("WritePly: " + std::to_string(colours.size()) + " colours for " + std::to_string(points.size()) +
                " points");
  }
  const bool rgb = !colours.empty();
  std::string out = "ply\nformat binary_little_endian 1.0\ncomment written by sgslam\nelement vertex " +
                    std::to_string(points.size()) + "\nproperty float x\nproperty float y\nproperty float z\n";
  if (rgb) out += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  out += "end_header\n";
  const std::size_t stride = 12 + (rgb ? 3 : 0);
  const std::size_t header = out.size();
  out.resize(header + stride * points.size());
  char* dst = out.data() + header;
  for (std::size_t i = 0; i < points.size(); ++i, dst += stride) {
    const float xyz[3] = {static_cast<float>(points[i].x()), static_cast<float>(points[i].y()),
                          static_cast<float>(points[i].z())};
    std::memcpy(dst, xyz, 12);
    if (rgb) std::memcpy(dst + 12, colours[i].data(), 3);
  }
  WriteFileAtomically(path, out);
}

std::vector<Eigen::Vector3d> ReadPlyPoints(const std::filesystem::path& path, std::vector<Rgb>* colours) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot open PLY file: " + path.string());
  std::string line;
  std::size_t count = 0;
  int properties = 0;
  bool binary = false;
  while (std::getline(in, line) && line != "end_header") {
    std::istringstream s(line);
    std::string word, kind;
    s >> word;
    if (word == "format") binary = line.find("binary_little_endian") != std::string::npos;
    if (word == "element") s >> kind >> count;
    if (word == "property") ++properties;
  }
  if (!binary || (properties != 3 && properties != 6)) throw InputError("unsupported PLY layout: " + path.string());
  const std::size_t stride = properties == 6 ? 15 : 12;
  std::vector<char> data(stride * count);
  if (!in.read(data.data(), static_cast<std::streamsize>(data.size()))) throw InputError("truncated PLY: " + path.string());
  std::vector<Eigen::Vector3d> points(count);
  if (colours) colours->assign(properties == 6 ? count : 0, Rgb{});
  for (std::size_t i = 0; i < count; ++i) {
    float xyz[3];
    std::memcpy(xyz, data.data() + i * stride, 12);
    points[i] = {xyz[0], xyz[1], xyz[2]};
    if (colours && properties == 6) std::memcpy((*colours)[i].data(), data.data() + i * stride + 12, 3);
  }
  return points;
}

}  // namespace sgslam
