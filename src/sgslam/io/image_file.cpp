#include "sgslam/io/image_file.h"

#include <algorithm>
#include <array>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "sgslam/common/error.h"

namespace sgslam {

namespace {

std::uint32_t BigEndian(std::span<const std::uint8_t> b, std::size_t at, int n) {
  std::uint32_t v = 0;
  for (int i = 0; i < n; ++i) v = (v << 8) | b[at + static_cast<std::size_t>(i)];
  return v;
}

// Whether the last `window` bytes hold `marker`.
bool EndsNear(std::span<const std::uint8_t> bytes, std::span<const std::uint8_t> marker, std::size_t window) {
  const std::size_t from = bytes.size() > window ? bytes.size() - window : 0;
  const auto tail = bytes.subspan(from);
  return std::search(tail.begin(), tail.end(), marker.begin(), marker.end()) != tail.end();
}

std::optional<ImageHeader> PngHeader(std::span<const std::uint8_t> b) {
  // signature (8), then the IHDR chunk: length (4), "IHDR", width (4), height (4)
  if (b.size() < 24 || b[12] != 'I' || b[13] != 'H' || b[14] != 'D' || b[15] != 'R') return std::nullopt;
  static constexpr std::array<std::uint8_t, 4> kIend = {'I', 'E', 'N', 'D'};
  return ImageHeader{"PNG", BigEndian(b, 16, 4), BigEndian(b, 20, 4), EndsNear(b, kIend, 64)};
}

bool IsStartOfFrame(std::uint8_t m) { return m >= 0xC0 && m <= 0xCF && m != 0xC4 && m != 0xC8 && m != 0xCC; }

std::optional<ImageHeader> JpegHeader(std::span<const std::uint8_t> b) {
  static constexpr std::array<std::uint8_t, 2> kEoi = {0xFF, 0xD9};
  std::size_t at = 2;  // after SOI
  while (at + 4 <= b.size()) {
    if (b[at] != 0xFF) return std::nullopt;
    const std::uint8_t m = b[at + 1];
    if (m == 0xFF) {  // fill byte
      ++at;
      continue;
    }
    if (m == 0x01 || (m >= 0xD0 && m <= 0xD7)) {  // markers without a segment
      at += 2;
      continue;
    }
    if (m == 0xDA || m == 0xD9) return std::nullopt;  // scan data before any frame header
    const std::size_t length = BigEndian(b, at + 2, 2);
    if (IsStartOfFrame(m)) {
      if (at + 9 > b.size()) return std::nullopt;  // precision (1), height (2), width (2)
      return ImageHeader{"JPEG", BigEndian(b, at + 7, 2), BigEndian(b, at + 5, 2), EndsNear(b, kEoi, 64)};
    }
    if (length < 2) return std::nullopt;
    at += 2 + length;
  }
  return std::nullopt;
}

}  // namespace

std::optional<ImageHeader> ReadImageHeader(std::span<const std::uint8_t> b) {
  static constexpr std::array<std::uint8_t, 8> kPng = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  if (b.size() >= kPng.size() && std::equal(kPng.begin(), kPng.end(), b.begin())) return PngHeader(b);
  if (b.size() >= 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF) return JpegHeader(b);
  return std::nullopt;
}

std::vector<std::uint8_t> ReadFileBytes(const std::filesystem::path& path, std::uintmax_t max_bytes) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) throw InputError("cannot read " + path.string() + ": " + ec.message());
  if (size > max_bytes) {
    throw InputError("file " + path.string() + " is " + std::to_string(size) + " bytes, more than the " +
                     std::to_string(max_bytes) + " an image of this camera can need");
  }
  std::vector<std::uint8_t> bytes(size);
  std::ifstream in(path, std::ios::binary);
  if (!in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size))) {
    throw InputError("cannot read " + path.string());
  }
  return bytes;
}

cv::Mat DecodeImageFile(const std::filesystem::path& path, const std::vector<std::uint8_t>& bytes, int flags) {
  if (const auto header = ReadImageHeader(bytes); header && !header->complete) {
    throw InputError("image " + path.string() + " is cut short (a " + header->format +
                     " file without its end marker)");
  }
  cv::Mat m;
  try {
    m = cv::imdecode(bytes, flags);
  } catch (const cv::Exception& e) {  // OpenCV refusing it (a header claiming 60000x60000 pixels, say)
    throw InputError("cannot read image " + path.string() + ": " + e.err);
  }
  if (m.empty()) throw InputError("cannot read image (corrupt or not an image): " + path.string());
  return m;
}

}  // namespace sgslam
