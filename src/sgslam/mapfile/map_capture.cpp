#include "sgslam/mapfile/map_capture.h"

#include <chrono>
#include <cmath>
#include <ctime>
#include <map>
#include <set>

#include "sgslam/common/error.h"

namespace sgslam::mapfile {

namespace {

Pose ToPose(const SE3& T) {
  const Eigen::Quaterniond& q = T.quaternion();
  return {{q.x(), q.y(), q.z(), q.w()}, {T.translation().x(), T.translation().y(), T.translation().z()}};
}

SE3 FromPose(const Pose& p) {
  // Checked to be of unit norm (CheckMapData): kept bit for bit.
  return SE3::FromUnitQuaternion(Eigen::Quaterniond(p.q[3], p.q[0], p.q[1], p.q[2]),
                                 Eigen::Vector3d(p.t[0], p.t[1], p.t[2]));
}

std::string UtcNow() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&now, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

void CaptureFeatures(const Features& f, KeyFrameData& k) {
  const std::size_t n = f.size();
  for (std::size_t i = 0; i < n; ++i) {
    const cv::KeyPoint& p = f.keys[i];
    k.keys.push_back({p.pt.x, p.pt.y, p.size, p.angle, p.response, p.octave});
    k.keys_un.push_back({f.keys_un[i].pt.x, f.keys_un[i].pt.y});
  }
  k.depth = f.depth;
  k.u_right = f.u_right;
  k.descriptors.resize(32 * n);
  for (std::size_t i = 0; i < n; ++i) std::copy(f.descriptor(i), f.descriptor(i) + 32, k.descriptors.begin() + 32 * i);
  k.dynamic = f.dynamic;
  k.unjudged = f.unjudged;
  for (const Detection& d : f.detections) {
    k.detections.push_back({d.class_id, d.class_name, d.score, {d.box.x, d.box.y, d.box.width, d.box.height}, d.carried});
  }
  k.angular_velocity = {f.angular_velocity.x(), f.angular_velocity.y(), f.angular_velocity.z()};
}

KeyFrameData CaptureKeyFrame(const KeyFrame& kf) {
  KeyFrameData k;
  k.id = kf.id;
  k.frame_id = kf.frame_id;
  k.t = kf.t;
  k.T_c_w = ToPose(kf.T_c_w());
  if (kf.bad()) {
    k.culled = true;
    if (const auto& parent = kf.parent_when_culled()) k.parent = parent->id;
    k.T_c_parent = ToPose(kf.T_c_parent());
    return k;
  }
  if (const auto parent = kf.parent()) k.parent = parent->id;
  for (const auto& p : kf.map_points()) k.point_ids.push_back(p && !p->bad() ? p->id : kNoId);
  for (std::uint64_t other : kf.ConnectedIds()) k.connections.emplace_back(other, kf.Weight(other));
  for (const auto& [other, weight] : kf.CovisibleOrder()) k.covisible_order.emplace_back(other, weight);
  for (const auto& other : kf.LoopEdges()) k.loop_edges.push_back(other->id);
  return k;
}

// Observations of keyframes not in `keyframes` (not inserted yet) are left out.
MapPointData CapturePoint(const MapPoint& p, const std::set<std::uint64_t>& keyframes) {
  MapPointData d;
  d.id = p.id;
  d.first_keyframe_id = p.first_keyframe_id;
  d.created_t = p.created_t;
  d.position = {p.position().x(), p.position().y(), p.position().z()};
  const MapPoint::Appearance a = p.appearance();
  d.normal = {a.normal.x(), a.normal.y(), a.normal.z()};
  d.descriptor = a.descriptor;
  d.min_distance = a.min_distance;
  d.max_distance = a.max_distance;
  d.visible = a.visible;
  d.found = a.found;
  for (const auto& [kf_id, obs] : p.observations()) {
    if (keyframes.count(kf_id)) d.observations.emplace_back(kf_id, static_cast<std::uint32_t>(obs.index));
  }
  const auto ref = p.reference_keyframe();
  if (ref && keyframes.count(ref->id)) {
    d.reference = ref->id;
  } else if (!d.observations.empty()) {
    d.reference = d.observations.front().first;
  }
  return d;
}

std::vector<ColoredPointData> ToData(const std::vector<ColoredPoint>& points) {
  std::vector<ColoredPointData> out;
  out.reserve(points.size());
  for (const ColoredPoint& p : points) out.push_back({{p.p.x(), p.p.y(), p.p.z()}, p.rgb});
  return out;
}

ImageData ToData(const cv::Mat& image) {
  ImageData d;
  if (image.empty()) return d;
  d.rows = image.rows;
  d.cols = image.cols;
  d.pixels.reserve(image.total());
  for (int r = 0; r < image.rows; ++r) d.pixels.insert(d.pixels.end(), image.ptr<float>(r), image.ptr<float>(r) + image.cols);
  return d;
}

ObjectData ToData(const ObjectDatabase::Object& o) {
  ObjectData d{o.id, {}, o.views_expected, o.views_seen, o.missing};
  for (const ObjectObservation& obs : o.observations) {
    ObjectObservationData od;
    od.keyframe = obs.keyframe ? obs.keyframe->id : kNoId;
    od.class_id = obs.class_id;
    od.class_name = obs.class_name;
    od.score = obs.score;
    od.box = {obs.box.x, obs.box.y, obs.box.width, obs.box.height};
    od.T_w_c_added = ToPose(obs.T_w_c_added);
    for (const Eigen::Vector3f& p : obs.points_c) od.points_c.push_back({p.x(), p.y(), p.z()});
    od.cut = obs.cut;
    d.observations.push_back(std::move(od));
  }
  return d;
}

using KeyFrameSet = std::map<std::uint64_t, const KeyFrame*>;

// Adds kf, when the map no longer has it (culled), with the culled parents it is placed on.
void Anchor(const KeyFrame* kf, KeyFrameSet& keyframes) {
  for (const KeyFrame* k = kf; k && !keyframes.count(k->id); k = k->parent_when_culled().get()) keyframes[k->id] = k;
}

// The semantic layer, and every keyframe it is anchored to (Anchor).
void CaptureSemantic(const SemanticState& s, KeyFrameSet& keyframes, MapData& d) {
  d.semantic.present = true;
  const auto anchor = [&](const std::shared_ptr<KeyFrame>& kf) { Anchor(kf.get(), keyframes); };
  for (const SemanticState::Cloud& c : s.clouds) {
    anchor(c.keyframe);
    d.semantic.clouds.push_back({c.keyframe->id, ToData(c.points_c), ToData(c.rays_c), ToData(c.depth_pooled),
                                 ToData(c.moving_pooled)});
  }
  for (const ObjectDatabase::Object& o : s.objects) {
    for (const ObjectObservation& obs : o.observations) {
      if (obs.keyframe) anchor(obs.keyframe);
    }
    d.semantic.objects.push_back(ToData(o));
  }
  d.semantic.next_object_id = s.next_object_id;
}

// After the map's lock: the keyframes' features and bags of words (one each per
// keyframe of d, null for culled ones), and only the points captured kept in slots.
void AddImmutableParts(const std::vector<std::shared_ptr<const Features>>& features,
                       const std::vector<std::shared_ptr<const vocab::BowData>>& bows, MapData& d) {
  std::set<std::uint64_t> points;
  for (const MapPointData& p : d.points) points.insert(p.id);
  for (std::size_t i = 0; i < d.keyframes.size(); ++i) {
    KeyFrameData& k = d.keyframes[i];
    for (std::uint64_t& id : k.point_ids) {
      if (id != kNoId && !points.count(id)) id = kNoId;
    }
    if (features[i]) CaptureFeatures(*features[i], k);
    if (bows[i]) {
      k.has_bow = true;
      k.bow_words = bows[i]->words;
      k.bow_nodes = bows[i]->nodes;
    }
  }
}

}  // namespace

MapData CaptureMap(const Map& map, const Settings& settings, std::uint64_t next_frame_id,
                   const SemanticState* semantic) {
  MapData d;
  d.created = UtcNow();
  d.settings = settings;
  // Per captured keyframe (null when culled): immutable once the keyframe is in the
  // map, so copied after the lock is released.
  std::vector<std::shared_ptr<const Features>> features;
  std::vector<std::shared_ptr<const vocab::BowData>> bows;
  {
    std::shared_lock lock(map.mutex());
    KeyFrameSet keyframes;
    for (const auto& [id, kf] : map.keyframes()) keyframes[id] = kf.get();
    std::set<std::uint64_t> live;
    for (const auto& [id, kf] : keyframes) live.insert(id);
    for (std::uint64_t id : live) {
      if (const auto parent = keyframes.at(id)->parent()) Anchor(parent.get(), keyframes);
    }
    if (semantic) CaptureSemantic(*semantic, keyframes, d);
    std::uint64_t next_kf = 0;
    for (const auto& [id, kf] : keyframes) {
      KeyFrameData& k = d.keyframes.emplace_back(CaptureKeyFrame(*kf));
      features.push_back(kf->bad() ? nullptr : kf->features);
      bows.push_back(kf->bad() ? nullptr : kf->bow);
      // Edges to culled keyframes that linger on one side of a covisibility link go.
      const auto gone = [&](const auto& c) { return !live.count(c.first); };
      std::erase_if(k.connections, gone);
      std::erase_if(k.covisible_order, gone);
      std::erase_if(k.loop_edges, [&](std::uint64_t other) { return !live.count(other); });
      next_kf = id + 1;
    }
    std::uint64_t next_point = 0;
    for (const auto& [id, p] : map.map_points()) {
      if (p->bad()) continue;
      MapPointData point = CapturePoint(*p, live);
      if (point.observations.empty()) continue;  // seen only by a keyframe not inserted yet
      d.points.push_back(std::move(point));
      next_point = id + 1;
    }
    // New ids continue after every id the map ever gave (culled entities' too).
    d.next_keyframe_id = std::max(next_kf, map.next_keyframe_id());
    d.next_point_id = std::max(next_point, map.next_point_id());
  }
  AddImmutableParts(features, bows, d);
  // Keyframes made after the request (copied later, on the semantic thread) count too.
  d.next_frame_id = next_frame_id;
  for (const KeyFrameData& k : d.keyframes) d.next_frame_id = std::max(d.next_frame_id, k.frame_id + 1);
  return d;
}

Settings RunSettings(const CameraConfig& camera, double orb_scale_factor, int orb_levels,
                     const std::string& vocabulary_checksum) {
  return {camera, orb_scale_factor, orb_levels, vocabulary_checksum};
}

void CheckCompatible(const Settings& saved, const Settings& run, const std::string& what) {
  const auto fail = [&](const std::string& why) {
    throw InputError("map file " + what + " cannot be used with this run: " + why);
  };
  const auto va = CameraValues(saved.camera), vb = CameraValues(run.camera);
  for (std::size_t i = 0; i < va.size(); ++i) {
    const std::string& name = va[i].first;
    if (name == "fps" || name == "readout" || name == "close_depth") continue;  // how it is run, not the map
    if (std::abs(va[i].second - vb[i].second) > 1e-9 * std::max(1.0, std::abs(vb[i].second))) {
      fail("it was made with camera." + name + " " + std::to_string(va[i].second) + ", this run has " +
           std::to_string(vb[i].second));
    }
  }
  if (saved.orb_levels != run.orb_levels || saved.orb_scale_factor != run.orb_scale_factor) {
    fail("it was made with orb.levels " + std::to_string(saved.orb_levels) + " and orb.scale_factor " +
         std::to_string(saved.orb_scale_factor) + ", this run has " + std::to_string(run.orb_levels) + " and " +
         std::to_string(run.orb_scale_factor));
  }
  if (run.vocabulary_checksum.empty()) fail("loading a map needs place recognition (loop.enabled: true)");
  if (saved.vocabulary_checksum != run.vocabulary_checksum) {
    fail("it was made with another vocabulary (sha256 " + saved.vocabulary_checksum.substr(0, 16) + "..., this run's is " +
         run.vocabulary_checksum.substr(0, 16) + "...; loop.vocabulary)");
  }
}

namespace {

std::shared_ptr<const Features> RestoreFeatures(const KeyFrameData& k, const std::shared_ptr<const Camera>& camera,
                                                const std::shared_ptr<const ScaleLevels>& scale) {
  auto f = std::make_shared<Features>();
  f->camera = camera;
  f->scale = scale;
  f->bounds = UndistortedBounds(*camera);
  const std::size_t n = k.keys.size();
  for (std::size_t i = 0; i < n; ++i) {
    const KeyPointData& p = k.keys[i];
    f->keys.emplace_back(cv::Point2f(p.x, p.y), p.size, p.angle, p.response, p.octave);
    f->keys_un.push_back(f->keys.back());
    f->keys_un.back().pt = cv::Point2f(k.keys_un[i][0], k.keys_un[i][1]);
  }
  f->depth = k.depth;
  f->u_right = k.u_right;
  f->descriptors = cv::Mat(static_cast<int>(n), 32, CV_8U);
  if (n > 0) std::copy(k.descriptors.begin(), k.descriptors.end(), f->descriptors.ptr<std::uint8_t>(0));
  f->grid = FeatureGrid(f->keys_un, f->bounds);
  f->dynamic = k.dynamic;
  f->unjudged = k.unjudged;
  for (const DetectionData& d : k.detections) {
    f->detections.push_back({d.class_id, d.class_name, d.score, cv::Rect2f(d.box[0], d.box[1], d.box[2], d.box[3]), d.carried});
  }
  f->angular_velocity = Eigen::Vector3d(k.angular_velocity[0], k.angular_velocity[1], k.angular_velocity[2]);
  return f;
}

std::vector<ColoredPoint> FromData(const std::vector<ColoredPointData>& points) {
  std::vector<ColoredPoint> out;
  out.reserve(points.size());
  for (const ColoredPointData& p : points) out.push_back({Eigen::Vector3f(p.p[0], p.p[1], p.p[2]), p.rgb});
  return out;
}

cv::Mat FromData(const ImageData& d) {
  if (d.rows == 0 || d.cols == 0) return {};
  cv::Mat m(d.rows, d.cols, CV_32F);
  std::copy(d.pixels.begin(), d.pixels.end(), m.ptr<float>(0));
  return m;
}

ObjectDatabase::Object FromData(const ObjectData& d, const std::map<std::uint64_t, std::shared_ptr<KeyFrame>>& kfs) {
  // The class and the box follow from the observations (ObjectDatabase::Restore).
  ObjectDatabase::Object o;
  o.id = d.id;
  o.views_expected = d.views_expected;
  o.views_seen = d.views_seen;
  o.missing = d.missing;
  for (const ObjectObservationData& od : d.observations) {
    ObjectObservation obs;
    if (od.keyframe != kNoId) obs.keyframe = kfs.at(od.keyframe);
    obs.class_id = od.class_id;
    obs.class_name = od.class_name;
    obs.score = od.score;
    obs.box = cv::Rect2f(od.box[0], od.box[1], od.box[2], od.box[3]);
    obs.T_w_c_added = FromPose(od.T_w_c_added);
    for (const auto& p : od.points_c) obs.points_c.emplace_back(p[0], p[1], p[2]);
    obs.cut = od.cut;
    o.observations.push_back(std::move(obs));
  }
  return o;
}

void RestoreGraph(const MapData& data, const std::map<std::uint64_t, std::shared_ptr<KeyFrame>>& kfs) {
  for (const KeyFrameData& k : data.keyframes) {
    const auto& kf = kfs.at(k.id);
    const auto parent = k.parent == kNoId ? nullptr : kfs.at(k.parent);
    if (k.culled) {
      kf->RestoreCulled(parent, FromPose(k.T_c_parent));
      continue;
    }
    if (parent) kf->SetParent(parent);
    KeyFrame::Edges connections, order;
    for (const auto& [other, weight] : k.connections) connections.emplace_back(kfs.at(other), weight);
    for (const auto& [other, weight] : k.covisible_order) order.emplace_back(kfs.at(other), weight);
    kf->RestoreConnections(connections, order);
    for (std::uint64_t other : k.loop_edges) kf->AddLoopEdge(kfs.at(other));
  }
}

}  // namespace

SemanticState RestoreMap(const MapData& data, Map& map, const std::shared_ptr<const Camera>& camera,
                         const std::shared_ptr<const ScaleLevels>& scale) {
  std::unique_lock lock(map.mutex());
  std::map<std::uint64_t, std::shared_ptr<KeyFrame>> kfs;
  for (const KeyFrameData& k : data.keyframes) {
    auto kf = std::make_shared<KeyFrame>(k.id, k.frame_id, k.t, RestoreFeatures(k, camera, scale), FromPose(k.T_c_w));
    if (k.has_bow) kf->bow = std::make_shared<const vocab::BowData>(vocab::BowData{k.bow_words, k.bow_nodes});
    kfs[k.id] = kf;
    if (!k.culled) map.AddKeyFrame(kf);
  }
  RestoreGraph(data, kfs);
  for (const MapPointData& d : data.points) {
    MapPoint::Appearance a{Eigen::Vector3d(d.normal[0], d.normal[1], d.normal[2]), d.descriptor, d.min_distance,
                           d.max_distance, d.visible, d.found};
    auto p = std::make_shared<MapPoint>(d.id, d.first_keyframe_id, d.created_t,
                                        Eigen::Vector3d(d.position[0], d.position[1], d.position[2]), a);
    for (const auto& [kf_id, index] : d.observations) p->AddObservation(kfs.at(kf_id), index);
    if (d.reference != kNoId) p->RestoreReference(kfs.at(d.reference));
    map.AddMapPoint(p);
  }
  for (const KeyFrameData& k : data.keyframes) {
    for (std::size_t i = 0; i < k.point_ids.size(); ++i) {
      if (k.point_ids[i] != kNoId) kfs.at(k.id)->SetMapPoint(i, map.map_points().at(k.point_ids[i]));
    }
  }
  map.RestoreIds(data.next_keyframe_id, data.next_point_id);

  SemanticState semantic;
  for (const CloudData& c : data.semantic.clouds) {
    semantic.clouds.push_back({kfs.at(c.keyframe), FromData(c.points_c), FromData(c.rays_c), FromData(c.depth_pooled),
                               FromData(c.moving_pooled)});
  }
  for (const ObjectData& o : data.semantic.objects) semantic.objects.push_back(FromData(o, kfs));
  semantic.next_object_id = data.semantic.next_object_id;
  return semantic;
}

}  // namespace sgslam::mapfile
