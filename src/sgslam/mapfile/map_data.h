// A saved map as plain data (no pointers, no locks): what `--save-map` writes and
// `--load-map` reads (map_file.h), captured from and restored into a live system
// (map_capture.h). Entities refer to each other by id. Every struct compares
// field by field, so a round trip can be checked whole.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "sgslam/camera/camera_config.h"
#include "sgslam/features/orb_config.h"

namespace sgslam::mapfile {

inline constexpr std::uint64_t kNoId = std::numeric_limits<std::uint64_t>::max();

struct Pose {  // T_c_w (or T_c_parent): unit quaternion x, y, z, w and translation
  std::array<double, 4> q{0, 0, 0, 1};
  std::array<double, 3> t{0, 0, 0};
  bool operator==(const Pose&) const = default;
};

struct KeyPointData {  // cv::KeyPoint
  float x = 0, y = 0, size = 0, angle = 0, response = 0;
  std::int32_t octave = 0;
  bool operator==(const KeyPointData&) const = default;
};

struct DetectionData {
  std::int32_t class_id = -1;
  std::string class_name;
  float score = 0;
  std::array<float, 4> box{};  // x, y, width, height (px)
  std::int32_t carried = 0;
  bool operator==(const DetectionData&) const = default;
};

struct ImageData {  // a CV_32F image; empty: none
  std::int32_t rows = 0, cols = 0;
  std::vector<float> pixels;
  bool operator==(const ImageData&) const = default;
};

struct KeyFrameData {
  std::uint64_t id = 0, frame_id = 0;
  std::int64_t t = 0;  // ns
  Pose T_c_w;
  // A culled keyframe is kept only when the semantic layer is anchored to it: no
  // features then, and its pose follows parent (kNoId: its own T_c_w).
  bool culled = false;
  std::uint64_t parent = kNoId;  // the spanning tree's parent, or the parent when culled
  Pose T_c_parent;               // culled only

  // Features (map/features.h), one entry per keypoint.
  std::vector<KeyPointData> keys;
  std::vector<std::array<float, 2>> keys_un;
  std::vector<float> depth, u_right;
  std::vector<std::uint8_t> descriptors;  // 32 bytes a keypoint
  std::vector<std::uint8_t> dynamic, unjudged;
  std::vector<DetectionData> detections;
  std::array<double, 3> angular_velocity{};

  bool has_bow = false;
  std::vector<std::pair<std::uint32_t, float>> bow_words;
  std::vector<std::pair<std::uint32_t, std::vector<std::uint32_t>>> bow_nodes;

  std::vector<std::uint64_t> point_ids;  // per keypoint, kNoId where none
  std::vector<std::pair<std::uint64_t, std::int32_t>> connections;  // covisibility: keyframe, weight
  std::vector<std::pair<std::uint64_t, std::int32_t>> covisible_order;  // KeyFrame::CovisibleOrder()
  std::vector<std::uint64_t> loop_edges;
  bool operator==(const KeyFrameData&) const = default;
};

struct MapPointData {
  std::uint64_t id = 0, first_keyframe_id = 0;
  std::int64_t created_t = 0;
  std::array<double, 3> position{}, normal{};
  std::array<std::uint8_t, 32> descriptor{};
  double min_distance = 0, max_distance = 0;
  std::int32_t visible = 1, found = 1;
  std::uint64_t reference = kNoId;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> observations;  // keyframe, keypoint index
  bool operator==(const MapPointData&) const = default;
};

struct ColoredPointData {
  std::array<float, 3> p{};
  std::array<std::uint8_t, 3> rgb{};
  bool operator==(const ColoredPointData&) const = default;
};

struct CloudData {  // semantic/semantic_mapper.h SemanticState::Cloud
  std::uint64_t keyframe = 0;
  std::vector<ColoredPointData> points_c, rays_c;
  ImageData depth_pooled, moving_pooled;
  bool operator==(const CloudData&) const = default;
};

struct ObjectObservationData {  // semantic/objects.h
  std::uint64_t keyframe = kNoId;
  std::int32_t class_id = -1;
  std::string class_name;
  float score = 0;
  std::array<float, 4> box{};
  Pose T_w_c_added;
  std::vector<std::array<float, 3>> points_c;
  bool cut = false;
  bool operator==(const ObjectObservationData&) const = default;
};

struct ObjectData {  // its class and box follow from the observations (ObjectDatabase::Restore)
  std::int32_t id = 0;
  std::vector<ObjectObservationData> observations;
  std::int32_t views_expected = 0, views_seen = 0, missing = 0;  // since format version 2
  bool operator==(const ObjectData&) const = default;
};

struct SemanticData {
  bool present = false;  // the run had the semantic thread (semantic.enabled)
  std::vector<CloudData> clouds;
  std::vector<ObjectData> objects;
  std::int32_t next_object_id = 1;
  bool operator==(const SemanticData&) const = default;
};

// What must match between the map and the run that loads it.
struct Settings {
  CameraConfig camera;
  double orb_scale_factor = 0;
  std::int32_t orb_levels = 0;
  std::string vocabulary_checksum;  // empty: saved without place recognition
};

struct MapData {
  std::string created;  // UTC, ISO 8601 (informative: not part of a round trip's comparison)
  Settings settings;
  std::uint64_t next_keyframe_id = 0, next_point_id = 0, next_frame_id = 0;
  std::vector<KeyFrameData> keyframes;  // by id
  std::vector<MapPointData> points;     // by id
  SemanticData semantic;
};

// The same content (every field but `created`).
bool SameContent(const MapData& a, const MapData& b);

// The camera's values by key, in CameraConfig::Visit's order (for comparing two).
std::vector<std::pair<std::string, double>> CameraValues(CameraConfig camera);

}  // namespace sgslam::mapfile
