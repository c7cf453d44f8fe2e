// Writes the seeds of the fuzz corpus that the project's own writers make: small
// valid map and vocabulary files, a few near-valid ones (cut short, another
// version), and the default configuration as the printer writes it. Deterministic,
// so the committed files can be made again byte for byte.
//   fuzz_make_seeds CORPUS_DIR   (writes into CORPUS_DIR/map, vocabulary and config)
#include <cstdio>
#include <filesystem>
#include <random>

#include "sgslam/common/sha256.h"
#include "sgslam/config/yaml_io.h"
#include "sgslam/features/orb_config.h"
#include "sgslam/io/atomic_write.h"
#include "sgslam/mapfile/map_capture.h"
#include "sgslam/mapfile/map_file.h"
#include "sgslam/vocab/training.h"

namespace {

namespace fs = std::filesystem;
namespace mf = sgslam::mapfile;

mf::KeyFrameData KeyFrame(std::uint64_t id, std::vector<std::uint64_t> point_ids) {
  mf::KeyFrameData k;
  k.id = id;
  k.frame_id = 10 * id;
  k.t = static_cast<std::int64_t>(id) * 333'333'333;
  k.T_c_w.t = {0.1 * static_cast<double>(id), 0, 0};
  for (std::size_t i = 0; i < point_ids.size(); ++i) {
    const float x = 100.0f + 50.0f * static_cast<float>(i), y = 120.0f + 7.0f * static_cast<float>(id);
    k.keys.push_back({x, y, 31.0f, 45.0f * static_cast<float>(i), 0.01f, static_cast<std::int32_t>(i % 8)});
    k.keys_un.push_back({x + 0.5f, y - 0.5f});
    k.depth.push_back(1.5f + 0.1f * static_cast<float>(i));
    k.u_right.push_back(x - 20.0f);
    k.dynamic.push_back(i == 1 ? 1 : 0);
    for (int b = 0; b < 32; ++b) k.descriptors.push_back(static_cast<std::uint8_t>(id * 31 + i * 7 + b));
  }
  k.point_ids = std::move(point_ids);
  k.detections.push_back({0, "person", 0.9f, {90, 100, 60, 120}, 0});
  k.has_bow = true;
  k.bow_words = {{2, 0.25f}, {5, 0.75f}};
  k.bow_nodes = {{1, {0, 1}}, {3, {2}}};
  return k;
}

mf::SemanticData Semantic() {
  mf::SemanticData s;
  s.present = true;
  mf::CloudData c;
  c.keyframe = 2;
  c.points_c = {{{0.1f, 0.2f, 1.5f}, {200, 100, 50}}, {{-0.3f, 0.1f, 2.0f}, {10, 20, 30}}};
  c.rays_c = {{{0.0f, 0.0f, 3.0f}, {0, 0, 0}}};
  c.depth_pooled = {2, 2, {1.0f, 1.5f, 0.0f, 2.0f}};
  s.clouds.push_back(c);
  mf::ObjectData o;
  o.id = 1;
  o.views_expected = 2;
  o.views_seen = 1;
  o.observations.push_back({0, 56, "chair", 0.8f, {200, 150, 80, 90}, {}, {{0.0f, 0.1f, 1.2f}}, false});
  s.objects.push_back(o);
  s.next_object_id = 2;
  return s;
}

// Two keyframes sharing points, a culled one anchoring the semantic layer.
mf::MapData SmallMap() {
  mf::MapData d;
  d.created = "2026-01-01T00:00:00Z";
  d.settings = mf::RunSettings(sgslam::CameraConfig{}, sgslam::OrbConfig{}.scale_factor, sgslam::OrbConfig{}.levels,
                               sgslam::Sha256Hex("vocabulary"));
  d.next_keyframe_id = 3;
  d.next_point_id = 4;
  d.next_frame_id = 30;
  d.keyframes = {KeyFrame(0, {0, 1, mf::kNoId}), KeyFrame(1, {0, 1, 3})};
  d.keyframes[0].connections = d.keyframes[0].covisible_order = {{1, 2}};
  d.keyframes[1].connections = d.keyframes[1].covisible_order = {{0, 2}};
  d.keyframes[1].parent = 0;
  d.keyframes[1].loop_edges = {0};
  mf::KeyFrameData culled;
  culled.id = 2;
  culled.culled = true;
  culled.parent = 1;
  culled.T_c_parent.t = {0, 0.05, 0};
  d.keyframes.push_back(culled);
  for (const std::uint64_t id : {0, 1, 3}) {
    mf::MapPointData p;
    p.id = id;
    p.position = {0.1 * static_cast<double>(id), 0.2, 1.5};
    p.normal = {0, 0, -1};
    p.min_distance = 0.5;
    p.max_distance = 4.0;
    p.reference = id == 3 ? 1 : 0;
    const std::uint32_t index = id == 3 ? 2 : static_cast<std::uint32_t>(id);
    if (id != 3) p.observations.emplace_back(0, index);
    p.observations.emplace_back(1, index);
    d.points.push_back(p);
  }
  d.semantic = Semantic();
  return d;
}

// One keyframe without features, nothing else.
mf::MapData MinimalMap() {
  mf::MapData d = SmallMap();
  d.keyframes = {mf::KeyFrameData{}};
  d.points.clear();
  d.semantic = {};
  return d;
}

sgslam::vocab::Vocabulary SmallVocabulary(int branching, int levels) {
  std::mt19937_64 rng(7);
  std::vector<cv::Mat> images;
  for (int i = 0; i < 4; ++i) {
    cv::Mat d(40, sgslam::vocab::kDescriptorBytes, CV_8U);
    for (int r = 0; r < d.rows; ++r) {
      for (int c = 0; c < d.cols; ++c) d.at<std::uint8_t>(r, c) = static_cast<std::uint8_t>(rng());
    }
    images.push_back(d);
  }
  sgslam::vocab::TrainingOptions o;
  o.branching = branching;
  o.levels = levels;
  return sgslam::vocab::TrainVocabulary(images, o);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s CORPUS_DIR\n", argv[0]);
    return 2;
  }
  const fs::path map = fs::path(argv[1]) / "map", vocabulary = fs::path(argv[1]) / "vocabulary";
  fs::create_directories(map);
  fs::create_directories(vocabulary);
  const std::string small = mf::Encode(SmallMap());
  sgslam::WriteFileAtomically(map / "valid-small.map", small);
  sgslam::WriteFileAtomically(map / "valid-minimal.map", mf::Encode(MinimalMap()));
  sgslam::WriteFileAtomically(map / "truncated.map", small.substr(0, small.size() / 2));
  // A version this sgslam does not read yet. (valid-version-1.map, the small map as
  // format version 1 wrote it, is kept as it is: version 1 files must still load.)
  std::string other_version = small;
  other_version[8] = static_cast<char>(mf::kFormatVersion + 1);
  sgslam::WriteFileAtomically(map / ("version-" + std::to_string(mf::kFormatVersion + 1) + ".map"), other_version);
  const std::string k3l2 = SmallVocabulary(3, 2).Serialize();
  sgslam::WriteFileAtomically(vocabulary / "valid-k3-l2.vocab", k3l2);
  sgslam::WriteFileAtomically(vocabulary / "valid-k2-l3.vocab", SmallVocabulary(2, 3).Serialize());
  sgslam::WriteFileAtomically(vocabulary / "truncated.vocab", k3l2.substr(0, k3l2.size() - 100));
  fs::create_directories(fs::path(argv[1]) / "config");
  sgslam::WriteFileAtomically(fs::path(argv[1]) / "config" / "valid-defaults.yaml", sgslam::ConfigToYaml(sgslam::Config{}));
  std::printf("wrote the map, vocabulary and default configuration seeds in %s\n", argv[1]);
  return 0;
}
