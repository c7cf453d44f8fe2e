#include "foxglove_channels.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "sgslam/semantic/object_json.h"
#include "sgslam/common/data_dir.h"
#include "sgslam/common/error.h"

namespace sgslam::app::foxglove {

namespace {

using nlohmann::json;

// The per-frame statistics' own schema (the only type that is not Foxglove's).
constexpr const char* kFrameStatsSchema = R"json({
 "title": "sgslam.FrameStats",
 "description": "One frame of an sgslam run: tracking state, time and dynamic feature rejection",
 "type": "object",
 "properties": {
  "timestamp": {"type": "object", "title": "time", "properties": {"sec": {"type": "integer", "minimum": 0}, "nsec": {"type": "integer", "minimum": 0, "maximum": 999999999}}},
  "index": {"type": "integer", "minimum": 0, "description": "Frame number in the sequence"},
  "state": {"type": "string", "description": "Tracking state: ok, odometry, lost or not_initialized (docs/tracking-states.md)"},
  "frame_ms": {"type": "number", "description": "The frame's time on the tracking thread, ms"},
  "kept": {"type": "integer", "minimum": 0, "description": "Keypoints kept as static"},
  "rejected": {"type": "integer", "minimum": 0, "description": "Keypoints rejected as dynamic"},
  "unjudged": {"type": "integer", "minimum": 0, "description": "Keypoints kept without a test"},
  "detections": {"type": "integer", "minimum": 0, "description": "Boxes of this frame, carried ones included"},
  "movers": {"type": "integer", "minimum": 0, "description": "Mover tracks after this frame"},
  "keyframe": {"type": "boolean", "description": "A keyframe was made of this frame"}
 },
 "required": ["timestamp", "index", "state", "frame_ms", "kept", "rejected", "unjudged", "detections", "movers", "keyframe"]
})json";

constexpr const char* kMap = "map";
constexpr const char* kCamera = "camera";

json Time(Timestamp t) {
  if (t < 0) t = 0;  // Foxglove's times are unsigned
  return {{"sec", t / kNsPerSecond}, {"nsec", t % kNsPerSecond}};
}
// A number the schemas' "number" takes: JSON has no NaN or infinity (a degenerate
// extent, say), which would become null.
double Finite(double v) { return std::isfinite(v) ? v : 0.0; }
json Vec3(const Eigen::Vector3d& v) { return {{"x", Finite(v.x())}, {"y", Finite(v.y())}, {"z", Finite(v.z())}}; }
json Quat(const Eigen::Quaterniond& q) {
  if (!q.coeffs().allFinite()) return {{"x", 0.0}, {"y", 0.0}, {"z", 0.0}, {"w", 1.0}};
  return {{"x", q.x()}, {"y", q.y()}, {"z", q.z()}, {"w", q.w()}};
}
json Pose(const SE3& T) { return {{"position", Vec3(T.translation())}, {"orientation", Quat(T.quaternion())}}; }
json Pose(const Eigen::Vector3d& p) { return {{"position", Vec3(p)}, {"orientation", Quat(Eigen::Quaterniond::Identity())}}; }
json Rgba(float r, float g, float b, float a = 1.f) { return {{"r", r}, {"g", g}, {"b", b}, {"a", a}}; }
// Image positions to 0.1 px, path points to 1 mm: shorter JSON, nothing a display shows lost.
double Round(double v, double unit) { return std::isfinite(v) ? std::round(v / unit) * unit : 0.0; }
json Point2(float x, float y) { return {{"x", Round(x, 0.1)}, {"y", Round(y, 0.1)}}; }
json Vec3mm(const Eigen::Vector3d& v) { return {{"x", Round(v.x(), 1e-3)}, {"y", Round(v.y(), 1e-3)}, {"z", Round(v.z(), 1e-3)}}; }

// A scene entity with every list the schema asks for, empty.
json Entity(Timestamp t, const std::string& id) {
  json e = {{"timestamp", Time(t)}, {"frame_id", kMap}, {"id", id}, {"lifetime", Time(0)}, {"frame_locked", false},
            {"metadata", json::array()}};
  for (const char* list : {"arrows", "cubes", "spheres", "cylinders", "lines", "triangles", "texts", "models"}) {
    e[list] = json::array();
  }
  return e;
}
json Label(const Eigen::Vector3d& at, const std::string& text, const json& colour, double size) {
  return {{"pose", Pose(at)}, {"billboard", true}, {"font_size", size}, {"scale_invariant", true}, {"color", colour},
          {"text", text}};
}
// A scene update that replaces everything before it on its channel.
json SceneUpdate(Timestamp t, json entities) {
  return {{"deletions", json::array({{{"timestamp", Time(t)}, {"type", 1}, {"id", ""}}})},
          {"entities", std::move(entities)}};
}

// A packed cloud: x y z float32, then with colours red green blue alpha uint8.
json PointCloud(Timestamp t, const std::vector<float>& xyz, const std::vector<Rgb>* colours) {
  const std::size_t n = xyz.size() / 3;
  const std::size_t stride = colours ? 16 : 12;
  std::vector<std::uint8_t> data(n * stride);
  for (std::size_t i = 0; i < n; ++i) {
    std::memcpy(&data[i * stride], &xyz[3 * i], 12);  // little-endian floats, as the host's
    if (colours) {
      const Rgb& c = (*colours)[i];
      data[i * stride + 12] = c[0], data[i * stride + 13] = c[1], data[i * stride + 14] = c[2], data[i * stride + 15] = 255;
    }
  }
  json fields = json::array();
  for (const auto& [name, offset] : {std::pair{"x", 0}, {"y", 4}, {"z", 8}}) {
    fields.push_back({{"name", name}, {"offset", offset}, {"type", 7}});  // FLOAT32
  }
  if (colours) {
    for (const auto& [name, offset] : {std::pair{"red", 12}, {"green", 13}, {"blue", 14}, {"alpha", 15}}) {
      fields.push_back({{"name", name}, {"offset", offset}, {"type", 1}});  // UINT8
    }
  }
  return {{"timestamp", Time(t)}, {"frame_id", kMap}, {"pose", Pose(SE3())}, {"point_stride", stride},
          {"fields", std::move(fields)}, {"data", Base64(data.data(), data.size())}};
}

// Text that is not UTF-8 (a class name from a user's detections file) replaced, not thrown on.
void Add(std::vector<Message>& out, Channel c, Timestamp t, const json& j) {
  out.push_back({c, t, j.dump(-1, ' ', false, json::error_handler_t::replace)});
}

}  // namespace

const std::array<ChannelInfo, kChannels>& Channels() {
  static const std::array<ChannelInfo, kChannels> channels = {{
      {Channel::kTransform, "/tf", "foxglove.FrameTransform"},
      {Channel::kPose, "/camera/pose", "foxglove.PoseInFrame"},
      {Channel::kImage, "/camera/image", "foxglove.CompressedImage"},
      {Channel::kCalibration, "/camera/calibration", "foxglove.CameraCalibration"},
      {Channel::kAnnotations, "/camera/annotations", "foxglove.ImageAnnotations"},
      {Channel::kMovers, "/movers", "foxglove.SceneUpdate"},
      {Channel::kStats, "/stats", "sgslam.FrameStats"},
      {Channel::kTrajectory, "/map/trajectory", "foxglove.PosesInFrame"},
      {Channel::kMapPoints, "/map/points", "foxglove.PointCloud"},
      {Channel::kCloud, "/map/cloud", "foxglove.PointCloud"},
      {Channel::kObjects, "/map/objects", "foxglove.SceneUpdate"},
  }};
  return channels;
}

std::string SchemaText(const std::string& schema) {
  if (schema == "sgslam.FrameStats") return kFrameStatsSchema;
  const auto dir = DataDir();
  if (!dir) throw InputError("the folder of sgslam's data files (share/sgslam) was not found beside the executable");
  const auto path = *dir / "foxglove" / "schemas" / (schema + ".json");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot read the Foxglove schema " + path.string() + " (shipped with sgslam)");
  return {std::istreambuf_iterator<char>(in), {}};
}

std::optional<bool> MapPacer::Take(const MapSnapshot& map, Timestamp t, bool final, bool cloud_wanted) {
  map_t_ = t;
  const bool pieces_changed = map.cloud.size() != pieces_;
  if (!final && any_ && map.keyframes.size() == keyframes_ && !pieces_changed) return std::nullopt;
  const bool cloud = cloud_wanted && (final || (pieces_changed && ToSeconds(t - cloud_t_) >= kCloudPeriod));
  any_ = true;
  keyframes_ = map.keyframes.size();
  if (cloud) cloud_t_ = t;
  if (cloud || !cloud_wanted) pieces_ = map.cloud.size();  // a cloud nobody takes is no change to send the map for
  return cloud;
}

std::string Base64(const std::uint8_t* data, std::size_t size) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 3 <= size; i += 3) {
    const std::uint32_t v = (data[i] << 16) | (data[i + 1] << 8) | data[i + 2];
    for (int k = 18; k >= 0; k -= 6) out.push_back(kAlphabet[(v >> k) & 63]);
  }
  if (const std::size_t rest = size - i; rest > 0) {
    const std::uint32_t v = (data[i] << 16) | (rest == 2 ? data[i + 1] << 8 : 0);
    out.push_back(kAlphabet[(v >> 18) & 63]);
    out.push_back(kAlphabet[(v >> 12) & 63]);
    out.push_back(rest == 2 ? kAlphabet[(v >> 6) & 63] : '=');
    out.push_back('=');
  }
  return out;
}

Encoder::Encoder(const CameraConfig& camera, int jpeg_quality) : jpeg_quality_(jpeg_quality) {
  const CameraConfig& c = camera;
  const std::string calibration = json{{"frame_id", kCamera},
                                       {"width", c.width},
                                       {"height", c.height},
                                       {"distortion_model", "plumb_bob"},
                                       {"D", {c.k1, c.k2, c.p1, c.p2, c.k3}},
                                       {"K", {c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1}},
                                       {"R", {1, 0, 0, 0, 1, 0, 0, 0, 1}},
                                       {"P", {c.fx, 0, c.cx, 0, 0, c.fy, c.cy, 0, 0, 0, 1, 0}}}
                                      .dump();
  calibration_ = calibration.substr(1);  // after its opening brace: each frame's message puts its time first
}

void Encoder::Frame(const FrameSnapshot& f, std::vector<Message>& out, const Wanted& wanted) {
  const Timestamp t = f.t;
  const auto want = [&](Channel c) { return wanted.test(static_cast<std::size_t>(c)); };
  if (f.T_w_c && want(Channel::kTransform)) {
    Add(out, Channel::kTransform, t,
        {{"timestamp", Time(t)}, {"parent_frame_id", kMap}, {"child_frame_id", kCamera},
         {"translation", Vec3(f.T_w_c->translation())}, {"rotation", Quat(f.T_w_c->quaternion())}});
  }
  if (f.T_w_c && want(Channel::kPose)) {
    Add(out, Channel::kPose, t, {{"timestamp", Time(t)}, {"frame_id", kMap}, {"pose", Pose(*f.T_w_c)}});
  }
  if (!f.bgr.empty() && want(Channel::kImage)) {
    std::vector<std::uint8_t> jpeg;
    cv::imencode(".jpg", f.bgr, jpeg, {cv::IMWRITE_JPEG_QUALITY, jpeg_quality_});
    Add(out, Channel::kImage, t,
        {{"timestamp", Time(t)}, {"frame_id", kCamera}, {"data", Base64(jpeg.data(), jpeg.size())}, {"format", "jpeg"}});
  }
  if (want(Channel::kCalibration)) {
    out.push_back({Channel::kCalibration, t, R"({"timestamp":)" + Time(t).dump() + "," + calibration_});
  }

  // The keypoints by verdict (kept green, rejected red, unjudged grey), the boxes
  // with their class and score (carried ones, of missed moving objects, yellow).
  std::array<json, 3> groups = {json::array(), json::array(), json::array()};
  std::array<int, 3> counts{};
  const bool annotate = want(Channel::kAnnotations);
  for (std::size_t i = 0; i < f.keypoints.size(); ++i) {
    constexpr std::uint8_t kUnjudged = FrameSnapshot::kUnjudged;
    const std::uint8_t label = i < f.labels.size() ? f.labels[i] : kUnjudged;
    const std::size_t g = std::min(label, kUnjudged);
    if (annotate) groups[g].push_back(Point2(f.keypoints[i].x, f.keypoints[i].y));
    ++counts[g];
  }
  const std::array<json, 3> colours = {Rgba(0.2f, 0.9f, 0.3f), Rgba(1.f, 0.2f, 0.2f), Rgba(0.7f, 0.7f, 0.7f)};
  json points = json::array(), texts = json::array();
  for (std::size_t g = 0; g < 3; ++g) {
    if (groups[g].empty()) continue;
    points.push_back({{"timestamp", Time(t)}, {"type", 1}, {"points", std::move(groups[g])}, {"outline_color", colours[g]},
                      {"outline_colors", json::array()}, {"fill_color", colours[g]}, {"thickness", 4}});
  }
  for (const Detection& d : f.detections) {
    if (!annotate) break;
    const json colour = d.carried > 0 ? Rgba(1.f, 0.9f, 0.2f) : Rgba(1.f, 0.55f, 0.1f);
    const cv::Rect2f& b = d.box;
    points.push_back({{"timestamp", Time(t)},
                      {"type", 2},  // LINE_LOOP
                      {"points", {Point2(b.x, b.y), Point2(b.x + b.width, b.y), Point2(b.x + b.width, b.y + b.height),
                                  Point2(b.x, b.y + b.height)}},
                      {"outline_color", colour},
                      {"outline_colors", json::array()},
                      {"fill_color", Rgba(0, 0, 0, 0)},
                      {"thickness", 2}});
    texts.push_back({{"timestamp", Time(t)},
                     {"position", Point2(b.x + 2, b.y + 14)},
                     {"text", d.carried > 0 ? fmt::format("{} (carried)", d.class_name)
                                            : fmt::format("{} {:.2f}", d.class_name, d.score)},
                     {"font_size", 14},
                     {"text_color", colour},
                     {"background_color", Rgba(0, 0, 0, 0.6f)}});
  }
  if (annotate) {
    Add(out, Channel::kAnnotations, t,
        {{"circles", json::array()}, {"points", std::move(points)}, {"texts", std::move(texts)}});
  }

  // The confirmed and lost mover tracks (tentative ones are new, or people sitting still).
  if (f.T_w_c) trails_.Update(f.movers, t);
  json movers = json::array();
  for (const MoverSnapshot& m : f.movers) {
    if (!want(Channel::kMovers)) break;
    if (m.state == movers::TrackState::kTentative) continue;
    const bool lost = m.state == movers::TrackState::kLost;
    const auto [r, g, b, a] = TrackColour(m.id, lost);
    json e = Entity(t, fmt::format("mover/{}", m.id));
    e["cubes"].push_back({{"pose", Pose(m.position)}, {"size", Vec3(m.extent)}, {"color", Rgba(r, g, b, 0.3f * a)}});
    // Above the box: up is -y in the map frame (the first camera's).
    const Eigen::Vector3d above = m.position - Eigen::Vector3d(0, m.extent.y() / 2 + 0.1, 0);
    e["texts"].push_back(
        Label(above, fmt::format("{} {}{}", m.id, m.class_name, lost ? " (lost)" : ""), Rgba(r, g, b, a), 14));
    if (const MoverTrails::Trail* trail = trails_.Of(m.id); trail && trail->size() > 1) {
      json path = json::array();
      for (const auto& [when, p] : *trail) path.push_back(Vec3mm(p));
      e["lines"].push_back({{"type", 0},  // LINE_STRIP
                            {"pose", Pose(SE3())},
                            {"thickness", 3},
                            {"scale_invariant", true},
                            {"points", std::move(path)},
                            {"color", Rgba(r, g, b, a)},
                            {"colors", json::array()},
                            {"indices", json::array()}});
    }
    movers.push_back(std::move(e));
  }
  if (want(Channel::kMovers)) Add(out, Channel::kMovers, t, SceneUpdate(t, std::move(movers)));

  if (want(Channel::kStats)) {
    Add(out, Channel::kStats, t,
        {{"timestamp", Time(t)},
         {"index", f.index},
         {"state", ToString(f.state)},
         {"frame_ms", f.frame_ms},
         {"kept", counts[FrameSnapshot::kKept]},
         {"rejected", counts[FrameSnapshot::kRejected]},
         {"unjudged", counts[FrameSnapshot::kUnjudged]},
         {"detections", f.detections.size()},
         {"movers", f.movers.size()},
         {"keyframe", f.keyframe}});
  }
}

void Encoder::Map(const MapSnapshot& m, Timestamp t, bool cloud, std::vector<Message>& out, const Wanted& wanted) const {
  const auto want = [&](Channel c) { return wanted.test(static_cast<std::size_t>(c)); };
  if (want(Channel::kTrajectory)) {
    json poses = json::array();
    for (const KeyFramePose& k : m.keyframes) poses.push_back(Pose(k.T_w_c));
    Add(out, Channel::kTrajectory, t, {{"timestamp", Time(t)}, {"frame_id", kMap}, {"poses", std::move(poses)}});
  }
  std::vector<float> xyz;
  if (want(Channel::kMapPoints)) {
    xyz.reserve(3 * m.points.size());
    for (const Eigen::Vector3d& p : m.points) {
      for (int k = 0; k < 3; ++k) xyz.push_back(static_cast<float>(p[k]));
    }
    Add(out, Channel::kMapPoints, t, PointCloud(t, xyz, nullptr));
  }
  if (cloud && !m.cloud.empty() && want(Channel::kCloud)) {
    std::size_t total = 0;
    for (const CloudPiece& piece : m.cloud) total += piece.points_c ? piece.points_c->size() : 0;
    const std::size_t step = (total + kMaxCloudPoints - 1) / kMaxCloudPoints;  // an even subsample beyond the cap
    xyz.clear();
    std::vector<Rgb> colours;
    std::size_t seen = 0;
    for (const CloudPiece& piece : m.cloud) {
      if (!piece.points_c) continue;
      const Eigen::Matrix3f R = piece.T_w_c.rotation().cast<float>();
      const Eigen::Vector3f tr = piece.T_w_c.translation().cast<float>();
      for (const ColoredPoint& p : *piece.points_c) {
        if (seen++ % step != 0) continue;
        const Eigen::Vector3f w = R * p.p + tr;
        xyz.insert(xyz.end(), {w.x(), w.y(), w.z()});
        colours.push_back(p.rgb);
      }
    }
    Add(out, Channel::kCloud, t, PointCloud(t, xyz, &colours));
  }

  if (!want(Channel::kObjects)) return;
  json objects = json::array();
  for (const ObjectEstimate& o : m.objects) {
    if (!o.exported) continue;
    json e = Entity(t, fmt::format("object/{}", o.id));
    e["cubes"].push_back({{"pose", Pose(o.centroid)}, {"size", Vec3(o.size)}, {"color", Rgba(0.3f, 0.64f, 1.f, 0.25f)}});
    const Eigen::Vector3d above = o.centroid - Eigen::Vector3d(0, o.size.y() / 2 + 0.05, 0);
    e["texts"].push_back(Label(above, ObjectLabel(o), Rgba(1, 1, 1), 12));
    objects.push_back(std::move(e));
  }
  Add(out, Channel::kObjects, t, SceneUpdate(t, std::move(objects)));
}

}  // namespace sgslam::app::foxglove
