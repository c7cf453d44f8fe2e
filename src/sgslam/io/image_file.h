// Reading one image file of a frame so that a bad file costs neither memory nor a
// silently wrong frame: the size in a PNG or JPEG header is known before anything
// is decoded, and a file cut short is refused (libjpeg only warns and fills grey).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <opencv2/core.hpp>
#include <span>
#include <string>
#include <vector>

namespace sgslam {

struct ImageHeader {
  const char* format = "";  // "PNG" or "JPEG"
  std::uint32_t width = 0, height = 0;
  // The image's data is whole: a PNG's chunks run to IEND, a JPEG's first scan is
  // followed by EOI. Bytes after the end (a camera's trailer) are allowed.
  bool complete = false;
};

// The header of a PNG or JPEG file held in memory; nullopt for another format or a
// header too short to hold the size.
std::optional<ImageHeader> ReadImageHeader(std::span<const std::uint8_t> bytes);

// The whole file; throws InputError naming it ("<what> <path>: ...") when it is not a
// regular file (a FIFO is refused, not waited on), cannot be read or is larger than
// max_bytes.
std::vector<std::uint8_t> ReadFileBytes(const std::filesystem::path& path, std::uintmax_t max_bytes,
                                        const std::string& what = "image");

// Decodes an image file held in memory (cv::IMREAD_* flags); header is what
// ReadImageHeader gave for these bytes. A PNG or JPEG cut short is refused; every
// failure is an InputError naming the file.
cv::Mat DecodeImageFile(const std::filesystem::path& path, const std::vector<std::uint8_t>& bytes,
                        const std::optional<ImageHeader>& header, int flags);

// The bounds of an image file a user names whose size no camera config gives (a
// mask, a training image): twice an 8K frame's 33 million pixels, and 256 MiB,
// well above such a frame's 66 MB raw at 16 bits (a PNG is hardly more), so every
// real frame fits, while a wrong file, or a header claiming 60000x60000 pixels, is
// stopped before it costs memory.
inline constexpr std::uintmax_t kMaxNamedImageBytes = std::uintmax_t{256} << 20;
inline constexpr std::uint64_t kMaxNamedImagePixels = std::uint64_t{1} << 26;

// An image file a user named (a mask, a training image), read as TumDataset reads
// frames: a regular file of at most max_bytes, a PNG or JPEG header of at most
// max_pixels pixels (checked before decoding), whole. Every error is an InputError
// naming `what` and the path.
cv::Mat ReadImageFile(const std::filesystem::path& path, const std::string& what, int flags, std::uintmax_t max_bytes,
                      std::uint64_t max_pixels);

}  // namespace sgslam
