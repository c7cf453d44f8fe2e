// What sgslam publishes to Foxglove (docs/foxglove.md): the channels, their
// schemas (Foxglove's own types, JSON-encoded, with the JSON Schemas shipped in
// foxglove/schemas), and the messages made from a run's snapshots
// (system/snapshot.h). Frames of reference: "map" (the first camera's frame, the
// map's) and "camera" (the optical frame: x right, y down, z forward).
#pragma once

#include <array>
#include <bitset>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "sgslam/camera/camera_config.h"
#include "sgslam/common/time.h"
#include "sgslam/system/mover_trails.h"
#include "sgslam/system/snapshot.h"

namespace sgslam::app::foxglove {

enum class Channel : std::uint8_t {
  kTransform,    // /tf                foxglove.FrameTransform: map -> camera, each tracked frame
  kPose,         // /camera/pose       foxglove.PoseInFrame, each tracked frame
  kImage,        // /camera/image      foxglove.CompressedImage (JPEG), each frame
  kCalibration,  // /camera/calibration foxglove.CameraCalibration, each frame
  kAnnotations,  // /camera/annotations foxglove.ImageAnnotations: kept and rejected keypoints, boxes
  kMovers,       // /movers            foxglove.SceneUpdate: the mover tracks' boxes, labels, trails
  kStats,        // /stats             sgslam.FrameStats: state, frame time, kept and rejected
  kTrajectory,   // /map/trajectory    foxglove.PosesInFrame: the keyframes' poses
  kMapPoints,    // /map/points        foxglove.PointCloud: the sparse map
  kCloud,        // /map/cloud         foxglove.PointCloud: the static dense cloud, coloured
  kObjects,      // /map/objects       foxglove.SceneUpdate: the objects' boxes and labels
};
inline constexpr std::size_t kChannels = 11;

struct ChannelInfo {
  Channel channel;
  const char* topic;
  const char* schema;
};
const std::array<ChannelInfo, kChannels>& Channels();
inline const ChannelInfo& Info(Channel c) { return Channels()[static_cast<std::size_t>(c)]; }

// A channel's JSON Schema: foxglove.* read from the shipped foxglove/schemas
// (data_dir.h), sgslam.FrameStats built in. Throws InputError naming what is missing.
std::string SchemaText(const std::string& schema);

struct Message {
  Channel channel;
  Timestamp t;  // the frame's (ns): the log time
  std::string json;
};

class Encoder {
 public:
  // jpeg_quality: 0-100, the image channel's.
  explicit Encoder(const CameraConfig& camera, int jpeg_quality = 80);

  using Wanted = std::bitset<kChannels>;  // by Channel: the messages to make
  static Wanted All() { return Wanted().set(); }

  // A frame's messages on the wanted channels, appended to out. Remembers the mover
  // tracks' trails.
  void Frame(const FrameSnapshot& f, std::vector<Message>& out, const Wanted& wanted = All());
  // The map's at time t on the wanted channels: trajectory, points, objects, and the
  // cloud when `cloud` (the largest, so the caller spaces them out).
  void Map(const MapSnapshot& m, Timestamp t, bool cloud, std::vector<Message>& out, const Wanted& wanted = All()) const;

  // Points of the dense cloud a message holds at most (an even subsample beyond).
  static constexpr std::size_t kMaxCloudPoints = 300'000;

 private:
  int jpeg_quality_;
  std::string calibration_;  // the camera's calibration message but its time: it never changes
  MoverTrails trails_;
};

// When a stream of frames (a recording, a live connection) sends the map's messages:
// at most every kMapPeriod of the sequence and only when the map changed (a keyframe,
// the semantic thread's cloud), the cloud at most every kCloudPeriod; everything at
// the end. One thread's.
class MapPacer {
 public:
  static constexpr double kMapPeriod = 1.0;    // s of the sequence between the map's messages
  static constexpr double kCloudPeriod = 5.0;  // ... and the dense cloud's

  // Whether the map is due after a frame at time t.
  bool Due(Timestamp t) const { return !any_ || ToSeconds(t - map_t_) >= kMapPeriod; }
  // The map taken at time t when due, or at the end (final): nothing to send
  // (nullopt, it has not changed), or send it, with the cloud (true) or without.
  // cloud_wanted: false when nobody takes the cloud.
  std::optional<bool> Take(const MapSnapshot& map, Timestamp t, bool final, bool cloud_wanted = true);

 private:
  Timestamp map_t_ = 0, cloud_t_ = 0;
  bool any_ = false;
  std::size_t keyframes_ = 0, pieces_ = 0;  // of the map sent last; pieces_: of its cloud
};

// Standard base64 (RFC 4648), as JSON carries Foxglove's bytes fields.
std::string Base64(const std::uint8_t* data, std::size_t size);

}  // namespace sgslam::app::foxglove
