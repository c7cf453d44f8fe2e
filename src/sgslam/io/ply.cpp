#include "sgslam/io/ply.h"

#include <bit>
#include <cstring>
#include <algorithm>
#include <charconv>
#include <sstream>
#include <string>

#include "sgslam/common/error.h"
#include "sgslam/common/regular_file.h"
#include "sgslam/io/atomic_write.h"

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

namespace {

// A header is a dozen short lines; other tools add comments, not kilobytes.
constexpr std::size_t kMaxHeaderBytes = 64 * 1024;
// 70 million coloured points: a run's cloud is a few million at most (a voxel
// grid of the static scene). Beyond it is the wrong file, refused before reading.
constexpr std::uint64_t kMaxPlyBytes = std::uint64_t{1} << 30;
// Points converted per read: the body is never held whole besides the result.
constexpr std::size_t kPointsPerPiece = 1 << 16;

struct PlyLayout {
  std::uint64_t count = 0;
  bool rgb = false;
  std::size_t header_bytes = 0;
  std::size_t stride() const { return rgb ? 15 : 12; }
};

// The header of what WritePly writes: binary little-endian, one vertex element of
// float x y z and optionally uchar red green blue.
PlyLayout ReadPlyHeader(const RegularFile& file) {
  const std::string head = file.Read(0, static_cast<std::size_t>(std::min<std::uint64_t>(kMaxHeaderBytes, file.size())));
  const std::size_t end = head.find("\nend_header\n");
  if (head.rfind("ply\n", 0) != 0 || end == std::string::npos) file.Fail("not a PLY file (no ply ... end_header header)");
  PlyLayout layout;
  layout.header_bytes = end + std::string_view("\nend_header\n").size();
  std::istringstream lines(head.substr(0, end));
  std::string line, types;
  bool binary = false, vertex = false;
  while (std::getline(lines, line)) {
    std::istringstream s(line);
    std::string word, a, b;
    s >> word >> a >> b;
    if (word == "format") binary = a == "binary_little_endian";
    if (word == "property") types += a + " ";
    if (word != "element") continue;
    if (vertex || a != "vertex") file.Fail("unsupported PLY layout (one element, vertex, expected; got '" + line + "')");
    vertex = true;
    const auto [ptr, ec] = std::from_chars(b.data(), b.data() + b.size(), layout.count);
    if (ec != std::errc() || ptr != b.data() + b.size()) file.Fail("bad vertex count '" + b + "' in its header");
  }
  layout.rgb = types == "float float float uchar uchar uchar ";
  if (!binary || !vertex || (!layout.rgb && types != "float float float ")) {
    file.Fail("unsupported PLY layout (binary little-endian float x y z, optionally uchar red green blue, expected)");
  }
  return layout;
}

}  // namespace

std::vector<Eigen::Vector3d> ReadPlyPoints(const std::filesystem::path& path, std::vector<Rgb>* colours) {
  const RegularFile file(path, "PLY file");
  file.CheckSize(kMaxPlyBytes);
  const PlyLayout layout = ReadPlyHeader(file);
  // Before anything is allocated: a header claiming 150 million points in a
  // 220-byte file is refused here, not after 1.8 GB.
  const std::uint64_t body = file.size() - layout.header_bytes;
  if (layout.count > body / layout.stride() || layout.count * layout.stride() != body) {
    file.Fail("its header claims " + std::to_string(layout.count) + " points (" +
              (layout.count > body / layout.stride() ? "more than" : std::to_string(layout.count * layout.stride())) +
              " bytes), the file holds " + std::to_string(body) + " bytes after its header (cut short or padded)");
  }
  const auto count = static_cast<std::size_t>(layout.count);
  const std::size_t stride = layout.stride();
  std::vector<Eigen::Vector3d> points(count);
  if (colours) colours->assign(layout.rgb ? count : 0, Rgb{});
  std::string piece;
  for (std::size_t first = 0; first < count; first += kPointsPerPiece) {
    const std::size_t n = std::min(kPointsPerPiece, count - first);
    piece.resize(n * stride);
    file.ReadInto(layout.header_bytes + first * stride, piece);
    for (std::size_t i = 0; i < n; ++i) {
      float xyz[3];
      std::memcpy(xyz, piece.data() + i * stride, 12);
      points[first + i] = {xyz[0], xyz[1], xyz[2]};
      if (colours && layout.rgb) std::memcpy((*colours)[first + i].data(), piece.data() + i * stride + 12, 3);
    }
  }
  return points;
}

}  // namespace sgslam
