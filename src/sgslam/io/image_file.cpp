#include "sgslam/io/image_file.h"

#include <algorithm>
#include <array>
#include <opencv2/imgcodecs.hpp>

#include "sgslam/common/error.h"
#include "sgslam/common/regular_file.h"

namespace sgslam {

namespace {

std::uint32_t BigEndian(std::span<const std::uint8_t> b, std::size_t at, int n) {
  std::uint32_t v = 0;
  for (int i = 0; i < n; ++i) v = (v << 8) | b[at + static_cast<std::size_t>(i)];
  return v;
}

// Whether a PNG's chunks (length, type, data, CRC) run whole from the signature to
// IEND; data after IEND is allowed.
bool PngChunksComplete(std::span<const std::uint8_t> b) {
  std::size_t at = 8;
  while (at + 12 <= b.size()) {
    const std::size_t length = BigEndian(b, at, 4);
    if (b[at + 4] == 'I' && b[at + 5] == 'E' && b[at + 6] == 'N' && b[at + 7] == 'D') return true;
    if (length > b.size() - at - 12) return false;
    at += 12 + length;
  }
  return false;
}

std::optional<ImageHeader> PngHeader(std::span<const std::uint8_t> b) {
  // signature (8), then the IHDR chunk: length (4), "IHDR", width (4), height (4)
  if (b.size() < 24 || b[12] != 'I' || b[13] != 'H' || b[14] != 'D' || b[15] != 'R') return std::nullopt;
  return ImageHeader{"PNG", BigEndian(b, 16, 4), BigEndian(b, 20, 4), PngChunksComplete(b)};
}

bool IsStartOfFrame(std::uint8_t m) { return m >= 0xC0 && m <= 0xCF && m != 0xC4 && m != 0xC8 && m != 0xCC; }

// Walks a JPEG's segments to its first scan. Entropy-coded data never holds FF D9
// (an FF there is followed by 00 or a restart marker), so the image is whole when an
// EOI follows its first scan; data after it (a camera's trailer) is allowed.
std::optional<ImageHeader> JpegHeader(std::span<const std::uint8_t> b) {
  static constexpr std::array<std::uint8_t, 2> kEoi = {0xFF, 0xD9};
  std::optional<ImageHeader> header;
  std::size_t at = 2;  // after SOI
  while (at + 4 <= b.size() && b[at] == 0xFF) {
    const std::uint8_t m = b[at + 1];
    if (m == 0xFF || m == 0x01 || (m >= 0xD0 && m <= 0xD7)) {  // fill byte, markers without a segment
      at += m == 0xFF ? 1 : 2;
      continue;
    }
    if (m == 0xD9) break;  // the end before any scan
    if (IsStartOfFrame(m) && at + 9 <= b.size()) {  // length (2), precision (1), height (2), width (2)
      header = ImageHeader{"JPEG", BigEndian(b, at + 7, 2), BigEndian(b, at + 5, 2), false};
    }
    if (m == 0xDA) {
      if (header) header->complete = std::search(b.begin() + static_cast<std::ptrdiff_t>(at), b.end(), kEoi.begin(),
                                                 kEoi.end()) != b.end();
      break;
    }
    const std::size_t length = BigEndian(b, at + 2, 2);
    if (length < 2) break;
    at += 2 + length;
  }
  return header;
}

}  // namespace

std::optional<ImageHeader> ReadImageHeader(std::span<const std::uint8_t> b) {
  static constexpr std::array<std::uint8_t, 8> kPng = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  if (b.size() >= kPng.size() && std::equal(kPng.begin(), kPng.end(), b.begin())) return PngHeader(b);
  if (b.size() >= 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF) return JpegHeader(b);
  return std::nullopt;
}

std::vector<std::uint8_t> ReadFileBytes(const std::filesystem::path& path, std::uintmax_t max_bytes,
                                        const std::string& what) {
  const RegularFile file(path, what);
  if (file.size() > max_bytes) {
    file.Fail(std::to_string(file.size()) + " bytes, more than the " + std::to_string(max_bytes) +
              " an image of this camera can need");
  }
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(file.size()));
  file.ReadInto(0, std::span<char>(reinterpret_cast<char*>(bytes.data()), bytes.size()));
  return bytes;
}

cv::Mat DecodeImageFile(const std::filesystem::path& path, const std::vector<std::uint8_t>& bytes,
                        const std::optional<ImageHeader>& header, int flags) {
  if (header && !header->complete) {
    throw InputError("image " + path.string() + " is cut short (a " + header->format +
                     " file without its end marker)");
  }
  cv::Mat m;
  try {
    m = cv::imdecode(bytes, flags);
  } catch (const cv::Exception& e) {  // OpenCV refusing it (a header claiming 60000x60000 pixels, say)
    throw InputError("cannot read image " + path.string() + ": " + e.err);
  } catch (const std::exception& e) {  // a format whose header is not read here, claiming more than memory holds
    throw InputError("cannot read image " + path.string() + ": " + e.what());
  }
  if (m.empty()) throw InputError("cannot read image (corrupt or not an image): " + path.string());
  return m;
}

cv::Mat ReadImageFile(const std::filesystem::path& path, const std::string& what, int flags, std::uintmax_t max_bytes,
                      std::uint64_t max_pixels) {
  const std::vector<std::uint8_t> bytes = ReadFileBytes(path, max_bytes, what);
  const std::optional<ImageHeader> header = ReadImageHeader(bytes);
  if (header && std::uint64_t{header->width} * header->height > max_pixels) {
    throw InputError(what + " " + path.string() + ": its " + header->format + " header claims " +
                     std::to_string(header->width) + "x" + std::to_string(header->height) + " pixels, more than the " +
                     std::to_string(max_pixels) + " such an image can have");
  }
  return DecodeImageFile(path, bytes, header, flags);
}

}  // namespace sgslam
