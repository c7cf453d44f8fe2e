// The map file: a saved map loads into a new system and saves again to the same
// content, field by field; a damaged or inconsistent file is refused with its
// reason; a map made with another camera or vocabulary is refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "sgslam/common/error.h"
#include "sgslam/common/sha256.h"
#include "sgslam/io/frame_stream.h"
#include "sgslam/mapfile/map_capture.h"
#include "sgslam/mapfile/map_file.h"
#include "sgslam/synth/writer.h"
#include "sgslam/system/run_config.h"
#include "sgslam/system/slam_system.h"
#include "support/shared_folder.h"
#include "support/test_support.h"

namespace sgslam::mapfile {
namespace {

namespace fs = std::filesystem;

// The objects preset (file detections: objects in the semantic map), mapped once
// for all the tests of this file (test::SharedFolder).
struct Fixture {
  fs::path seq, map;
  RunConfig rc;
  Fixture() {
    const fs::path dir = test::SharedFolder("objects-mapped", [](const fs::path& out) {
      synth::SynthOptions o;
      o.preset = "objects";
      o.frames = 90;
      synth::GenerateSequence(o, out / "objects");
      const RunConfig config = ResolveRunConfig(std::nullopt, out / "objects");
      const TumDataset dataset(out / "objects", config.config.dataset);
      SlamSystem system(config.config, /*sequential=*/true, MakeDetector(config.config.detector, out / "objects"));
      FrameStream stream(dataset, config.config.camera, 2);
      while (auto frame = stream.Next()) system.Process(*frame);
      system.Finish();
      if (!system.SaveMap(out / "objects.map") || system.maps_saved() != 1) {
        throw std::runtime_error("the map of the objects preset was not saved");
      }
    });
    seq = dir / "objects";
    map = dir / "objects.map";
    rc = ResolveRunConfig(std::nullopt, seq);
  }
};

const Fixture& Mapped() {
  static const Fixture f;
  return f;
}

std::string ReadBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The InputError message of Decode(bytes), or "" when it decodes.
std::string DecodeError(const std::string& bytes) {
  try {
    Decode(bytes, "test.map");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(MapFile, TheSavedMapHoldsEveryLayer) {
  const MapData d = ReadMapFile(Mapped().map);
  ASSERT_GT(d.keyframes.size(), 3u);
  EXPECT_GT(d.points.size(), 300u);
  EXPECT_TRUE(d.semantic.present);
  EXPECT_FALSE(d.semantic.clouds.empty());
  EXPECT_FALSE(d.semantic.objects.empty());
  const KeyFrameData& k = d.keyframes.back();
  EXPECT_TRUE(k.has_bow);
  EXPECT_FALSE(k.connections.empty());
  EXPECT_EQ(k.descriptors.size(), 32 * k.keys.size());
  EXPECT_FALSE(d.settings.vocabulary_checksum.empty());
  EXPECT_NE(Describe(d).find("keyframes"), std::string::npos);
}

TEST(MapFile, LoadThenSaveGivesTheSameContent) {
  const Fixture& f = Mapped();
  const MapData first = ReadMapFile(f.map);
  SlamSystem system(f.rc.config, /*sequential=*/true, MakeDetector(f.rc.config.detector, f.seq));
  system.LoadMap(first, f.map.string());
  const test::TempDir dir;
  const fs::path again = dir / "again.map";
  ASSERT_TRUE(system.SaveMap(again));
  MapData second = ReadMapFile(again);
  // Field by field, for a failure that says where.
  EXPECT_TRUE(first.settings.vocabulary_checksum == second.settings.vocabulary_checksum);
  EXPECT_EQ(first.next_keyframe_id, second.next_keyframe_id);
  EXPECT_EQ(first.next_point_id, second.next_point_id);
  EXPECT_EQ(first.next_frame_id, second.next_frame_id);
  ASSERT_EQ(first.keyframes.size(), second.keyframes.size());
  for (std::size_t i = 0; i < first.keyframes.size(); ++i) {
    EXPECT_TRUE(first.keyframes[i] == second.keyframes[i]) << "keyframe " << first.keyframes[i].id;
  }
  ASSERT_EQ(first.points.size(), second.points.size());
  for (std::size_t i = 0; i < first.points.size(); ++i) {
    EXPECT_TRUE(first.points[i] == second.points[i]) << "map point " << first.points[i].id;
  }
  EXPECT_TRUE(first.semantic.clouds == second.semantic.clouds);
  EXPECT_TRUE(first.semantic.objects == second.semantic.objects);
  EXPECT_TRUE(SameContent(first, second));
  // And byte for byte, but for the date.
  second.created = first.created;
  EXPECT_EQ(Encode(first), Encode(second));
}

TEST(MapFile, DamagedFilesAreRefusedWithTheirReason) {
  const std::string good = ReadBytes(Mapped().map);
  ASSERT_EQ(DecodeError(good), "");
  for (std::size_t size : {std::size_t{0}, std::size_t{7}, std::size_t{30}, std::size_t{52}, good.size() / 3,
                           good.size() - 1}) {
    const std::string why = DecodeError(good.substr(0, size));
    EXPECT_TRUE(why.find("too short") != std::string::npos || why.find("truncated") != std::string::npos)
        << size << ": " << why;
    EXPECT_NE(why.find("test.map"), std::string::npos) << why;
  }
  for (std::size_t at : {std::size_t{60}, good.size() / 2, good.size() - 1}) {
    std::string flipped = good;
    flipped[at] = static_cast<char>(flipped[at] ^ 0x10);
    EXPECT_NE(DecodeError(flipped).find("checksum mismatch"), std::string::npos) << at;
  }
  std::string magic = good;
  magic[0] = 'X';
  EXPECT_NE(DecodeError(magic).find("wrong magic"), std::string::npos);
  std::string version = good;
  const std::uint32_t newer = kFormatVersion + 1;
  std::memcpy(version.data() + 8, &newer, sizeof newer);
  EXPECT_NE(DecodeError(version).find("format version " + std::to_string(newer)), std::string::npos)
      << DecodeError(version);
  std::string padded = good + "x";
  EXPECT_NE(DecodeError(padded).find("truncated or padded"), std::string::npos);
}

TEST(MapFile, InconsistentContentIsRefusedEvenWithAGoodChecksum) {
  const MapData good = ReadMapFile(Mapped().map);
  MapData d = good;
  d.points.front().observations.front().second = 1'000'000;  // no such keypoint
  EXPECT_NE(DecodeError(Encode(d)).find("does not match its keyframe"), std::string::npos);
  d = good;
  d.keyframes[1].parent = d.keyframes[2].id;
  d.keyframes[2].parent = d.keyframes[1].id;
  EXPECT_NE(DecodeError(Encode(d)).find("its own ancestor"), std::string::npos);
  d = good;
  d.keyframes.back().depth.pop_back();
  EXPECT_NE(DecodeError(Encode(d)).find("different lengths"), std::string::npos);
  d = good;
  d.points.back().position[1] = std::nan("");
  EXPECT_NE(DecodeError(Encode(d)).find("not finite"), std::string::npos);
  d = good;
  d.keyframes.back().keys.front().octave = 99;
  EXPECT_NE(DecodeError(Encode(d)).find("out of range"), std::string::npos);
  d = good;
  d.semantic.clouds.front().keyframe = 123456;
  EXPECT_NE(DecodeError(Encode(d)).find("cloud"), std::string::npos);
  d = good;
  d.keyframes.back().keys.front().angle = 1000;  // matching bins the angle
  EXPECT_NE(DecodeError(Encode(d)).find("out of range"), std::string::npos);
  d = good;
  d.semantic.clouds.front().moving_pooled = {2, 2, {0, 0, 0, 0}};  // not the pooled depth's size
  EXPECT_NE(DecodeError(Encode(d)).find("cloud"), std::string::npos);
  d = good;
  d.semantic.clouds.back().points_c.front().p[0] = INFINITY;
  EXPECT_NE(DecodeError(Encode(d)).find("cloud"), std::string::npos);
  d = good;
  d.points.front().observations.push_back(d.points.front().observations.front());
  EXPECT_NE(DecodeError(Encode(d)).find("repeated"), std::string::npos);
  d = good;
  for (KeyFrameData& k : d.keyframes) k.culled = true, k.keys.clear();
  EXPECT_NE(DecodeError(Encode(d)).find("no keyframe"), std::string::npos);
  ASSERT_FALSE(good.semantic.objects.empty());
  d = good;
  d.semantic.objects.front().views_seen = d.semantic.objects.front().views_expected + 1;  // seen more than in view
  EXPECT_NE(DecodeError(Encode(d)).find("object"), std::string::npos);
  d = good;
  d.semantic.objects.front().observations.clear();
  EXPECT_NE(DecodeError(Encode(d)).find("object"), std::string::npos);
  d = good;
  d.semantic.objects.front().observations.front().score = std::nanf("");
  EXPECT_NE(DecodeError(Encode(d)).find("object"), std::string::npos);
}

// A map file around `payload`, with its size and checksum (the checksum is no
// defence against a crafted file: anyone can compute one).
std::string FileOf(const std::string& payload) {
  std::string file = "SGMAP";
  file.append(3, '\0');
  const std::uint32_t version = kFormatVersion;
  const std::uint64_t size = payload.size();
  file.append(reinterpret_cast<const char*>(&version), sizeof version);
  file.append(reinterpret_cast<const char*>(&size), sizeof size);
  const std::string hex = Sha256Hex(payload);
  for (std::size_t i = 0; i < 32; ++i) file += static_cast<char>(std::stoi(hex.substr(2 * i, 2), nullptr, 16));
  return file + payload;
}

// The fuzz corpus's small map (fuzz_make_seeds): keyframe 0 has keypoints, and the
// semantic layer is present. Cheaper than the mapped sequence for a test of one field.
MapData SmallMap() { return ReadMapFile(test::SourceDir() / "fuzz/corpus/map/valid-small.map"); }

// An undistorted keypoint at -4e27 px passed as finite, and the feature grid cast its
// cell to int (undefined behaviour, reported by UBSan in RestoreMap). Found by the
// map fuzz target.
TEST(MapFile, AKeypointFarOutsideAnyImageIsRefused) {
  const MapData good = SmallMap();
  ASSERT_FALSE(good.keyframes.front().keys.empty());
  for (const float v : {-4e27f, 2e6f}) {
    MapData d = good;
    d.keyframes.front().keys_un.front()[1] = v;
    EXPECT_NE(DecodeError(Encode(d)).find("keypoint 0 is out of range"), std::string::npos) << v;
    d = good;
    d.keyframes.front().keys.front().x = v;
    EXPECT_NE(DecodeError(Encode(d)).find("keypoint 0 is out of range"), std::string::npos) << v;
  }
}

// A count no file could hold is refused before anything is allocated for it.
TEST(MapFile, AHugeCountIsRefusedNotAllocated) {
  std::string payload(1, '\x01');  // the portable archive's byte order flag
  const std::uint64_t huge = std::uint64_t{1} << 60;  // the length of MapData::created
  payload.append(reinterpret_cast<const char*>(&huge), sizeof huge);
  payload += std::string(64, 'x');
  const std::string file = FileOf(payload);
  EXPECT_NE(DecodeError(file).find("cannot decode"), std::string::npos) << DecodeError(file);
}

// A true/false byte of 255 was copied into a bool: undefined behaviour, which UBSan
// reported in Describe (`sgslam map info`). Found by the map fuzz target.
TEST(MapFile, ATrueFalseByteOtherThanZeroOrOneIsRefused) {
  MapData d = SmallMap();
  ASSERT_TRUE(d.semantic.present);
  const std::string with = Encode(d).substr(52);
  d.semantic.present = false;
  const std::string without = Encode(d).substr(52);
  ASSERT_EQ(with.size(), without.size());
  const auto at = static_cast<std::size_t>(std::mismatch(with.begin(), with.end(), without.begin()).first - with.begin());
  ASSERT_LT(at, with.size());
  std::string payload = with;
  payload[at] = '\xff';
  const std::string why = DecodeError(FileOf(payload));
  EXPECT_NE(why.find("cannot decode"), std::string::npos) << why;
  EXPECT_NE(why.find("true/false byte of value 255"), std::string::npos) << why;
}

TEST(MapFile, AMapOfAnotherCameraOrVocabularyIsRefused) {
  const MapData saved = ReadMapFile(Mapped().map);
  Settings run = saved.settings;
  EXPECT_NO_THROW(CheckCompatible(saved.settings, run, "m.map"));
  run.camera.fps = 15;  // how the camera is run, not what the map is
  EXPECT_NO_THROW(CheckCompatible(saved.settings, run, "m.map"));
  const auto error = [&](const Settings& r) {
    try {
      CheckCompatible(saved.settings, r, "m.map");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  run = saved.settings;
  run.camera.fx += 1;
  EXPECT_NE(error(run).find("camera.fx"), std::string::npos) << error(run);
  run = saved.settings;
  run.camera.depth_factor = 1000;
  EXPECT_NE(error(run).find("camera.depth_factor"), std::string::npos);
  run = saved.settings;
  run.orb_levels = 4;
  EXPECT_NE(error(run).find("orb.levels"), std::string::npos);
  run = saved.settings;
  run.vocabulary_checksum = std::string(64, '0');
  EXPECT_NE(error(run).find("another vocabulary"), std::string::npos);
  run.vocabulary_checksum.clear();
  EXPECT_NE(error(run).find("loop.enabled"), std::string::npos);
}

}  // namespace
}  // namespace sgslam::mapfile
