// Map files (mapfile/map_file.h, with CheckMapData), then their restoration into an
// empty map as `sgslam run --load-map` does (mapfile/map_capture.h), which relies on
// what CheckMapData lets through. The header holds the payload's size and SHA-256,
// which a mutation almost never keeps right: each input is read as it is (the
// header checks), then with its size and checksum made to agree (the decoding and
// the content checks), the reading that counts as the input's outcome.
#include <cstring>

#include "fuzz_support.h"
#include "sgslam/common/sha256.h"
#include "sgslam/features/orb_config.h"
#include "sgslam/features/pyramid.h"
#include "sgslam/map/map.h"
#include "sgslam/mapfile/map_capture.h"
#include "sgslam/mapfile/map_file.h"

namespace {

namespace mf = sgslam::mapfile;

constexpr std::size_t kHeaderBytes = 8 + 4 + 8 + 32;
constexpr std::size_t kSizeAt = 8 + 4;
constexpr std::size_t kChecksumAt = 8 + 4 + 8;

// The input with the payload size and checksum of what follows its header.
std::string Consistent(std::string_view in) {
  std::string out(in);
  if (out.size() < kHeaderBytes) return out;
  const std::uint64_t size = out.size() - kHeaderBytes;
  std::memcpy(out.data() + kSizeAt, &size, sizeof size);
  const std::string hex = sgslam::Sha256Hex(in.substr(kHeaderBytes));
  for (std::size_t i = 0; i < 32; ++i) out[kChecksumAt + i] = static_cast<char>(std::stoi(hex.substr(2 * i, 2), nullptr, 16));
  return out;
}

void Load(const std::filesystem::path& path) {
  static const sgslam::CameraConfig camera_config;
  static const sgslam::OrbConfig orb;
  static const auto camera = std::make_shared<const sgslam::Camera>(camera_config);
  static const auto scale =
      std::make_shared<const sgslam::features::ScaleLevels>(sgslam::features::MakeScaleLevels(orb.scale_factor, orb.levels));
  const mf::MapData data = mf::ReadMapFile(path);
  // The vocabulary is the run's own business here: any the map names is the run's.
  const std::string vocabulary = data.settings.vocabulary_checksum.empty() ? "none" : data.settings.vocabulary_checksum;
  mf::CheckCompatible(data.settings, mf::RunSettings(camera_config, orb.scale_factor, orb.levels, vocabulary),
                      path.string());
  sgslam::Map map;
  const sgslam::SemanticState semantic = mf::RestoreMap(data, map, camera, scale);
  FUZZ_CHECK(map.map_points().size() == data.points.size() && semantic.clouds.size() == data.semantic.clouds.size());
  FUZZ_CHECK(!mf::Describe(data).empty());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace sgslam;
  const std::string_view in = fuzz::Bytes(data, size);
  fuzz::Parse([&] { Load(fuzz::WriteScratch("raw.map", in)); });
  fuzz::Parse([&] { Load(fuzz::WriteScratch("consistent.map", Consistent(in))); });
  return 0;
}
