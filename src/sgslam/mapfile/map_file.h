// The map file (`sgslam run --save-map / --load-map`, `sgslam map info`):
//
//   bytes 0-7    magic "SGMAP\0\0\0"
//   bytes 8-11   format version (uint32, little-endian)
//   bytes 12-19  payload size (uint64)
//   bytes 20-51  SHA-256 of the payload
//   then         the payload: MapData (map_data.h) in cereal's portable binary archive
//
// Written atomically (io/text_file.h). Reading checks the size, magic, version and
// checksum before it decodes anything, then the content's own consistency
// (CheckMapData, map_check.h), so a truncated, corrupt, other-version or
// inconsistent file is an InputError naming the file and the reason, and nothing
// half-read is returned.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "sgslam/mapfile/map_data.h"

namespace sgslam::mapfile {

// 2: objects keep the views' counts (ObjectData::views_expected, views_seen, missing)
// and no longer their class and box (derived from their observations).
inline constexpr std::uint32_t kFormatVersion = 2;
inline constexpr std::uint32_t kOldestFormatVersion = 1;  // still read
inline constexpr std::string_view kFileMagic{"SGMAP\0\0\0", 8};  // the first bytes of every map file

// The file's bytes (header and payload).
std::string Encode(const MapData& data);
// what: the file name, for errors. Throws InputError.
MapData Decode(const std::string& bytes, const std::string& what);

void WriteMapFile(const std::filesystem::path& path, const MapData& data);
MapData ReadMapFile(const std::filesystem::path& path);

// A few lines for `sgslam map info`: version, date, camera, keyframes, points,
// objects, the area covered.
std::string Describe(const MapData& data);

}  // namespace sgslam::mapfile
