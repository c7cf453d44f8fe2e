#include "sgslam/eval/track_score.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include <opencv2/imgcodecs.hpp>

#include "sgslam/common/error.h"
#include "sgslam/common/regular_file.h"
#include "sgslam/common/stats.h"
#include "sgslam/eval/ate.h"
#include "sgslam/eval/evaluate.h"
#include "sgslam/eval/mask_score.h"
#include "sgslam/io/image_file.h"
#include "sgslam/io/text_file.h"

namespace sgslam::eval {

namespace fs = std::filesystem;

namespace {

constexpr Timestamp kSameFrame = 1'000'000;    // ns: a truth line within 1 ms is the frame's
constexpr Timestamp kPoseWindow = 20'000'000;  // ns: ground-truth poses interpolated across at most this gap
constexpr int kRayStep = 2;                    // px: every second mask pixel in each direction is used

MoverTruth ReadMoversFile(const fs::path& path, const CameraConfig& camera) {
  MoverTruth truth;
  truth.source = path.string();
  truth.image_pixels = camera.width * camera.height;
  ForEachDataLine(path, [&](int line, const std::vector<std::string_view>& tok) {
    if (tok.size() != 7) throw ParseError(path.string(), line, "expected 'timestamp id class visible_px cx cy cz'");
    const auto t = ParseTimestamp(tok[0]);
    if (!t) throw ParseError(path.string(), line, "bad timestamp '" + std::string(tok[0]) + "'");
    TrueMover m;
    m.id = static_cast<int>(ParseNumber(tok[1], path, line, "id"));
    m.class_name = std::string(tok[2]);
    m.pixels = static_cast<int>(ParseNumber(tok[3], path, line, "visible_px"));
    for (int a = 0; a < 3; ++a) m.centroid[a] = ParseNumber(tok[4 + a], path, line, "centroid");
    truth.frames[*t].push_back(m);
  });
  return truth;
}

// A mover's shape in its own frame (the generator's dynamic_objects.txt header).
struct Shape {
  std::string class_name;
  bool quad = true;                                    // a person's quad in the x-z plane; else a box
  double width = 0, height = 0, bottom = 0;            // quad
  Eigen::Vector3d size = Eigen::Vector3d::Zero();      // box, centred above the origin
};

std::map<std::string, std::string> KeyValues(const std::string& text) {
  std::map<std::string, std::string> kv;
  std::istringstream in(text);
  std::string word;
  while (in >> word) {
    const auto eq = word.find('=');
    if (eq != std::string::npos) kv[word.substr(0, eq)] = word.substr(eq + 1);
  }
  return kv;
}

// m: how far from its vertical axis a point of the shape can be (a quad turns
// about it; the box spins), plus the depth noise.
constexpr double kSlack = 0.15;
double Reach(const Shape& s) { return (s.quad ? 0.5 * s.width : 0.5 * s.size.head<2>().norm()) + kSlack; }

std::optional<SE3> PoseAt(const Trajectory& gt, Timestamp t) {
  const auto it = std::lower_bound(gt.begin(), gt.end(), t, [](const auto& p, Timestamp x) { return p.t < x; });
  if (it != gt.end() && it->t == t) return it->T_w_c;
  if (it == gt.begin() || it == gt.end()) return std::nullopt;
  const auto& a = *(it - 1);
  const auto& b = *it;
  if (b.t - a.t > kPoseWindow) return std::nullopt;
  const double s = static_cast<double>(t - a.t) / static_cast<double>(b.t - a.t);
  return SE3(a.T_w_c.quaternion().slerp(s, b.T_w_c.quaternion()),
             (1 - s) * a.T_w_c.translation() + s * b.T_w_c.translation());
}

MoverTruth ComputeFromPoses(const fs::path& dir, const CameraConfig& camera) {
  const fs::path path = dir / "dynamic_objects.txt";
  MoverTruth truth;
  truth.source = path.string();
  truth.image_pixels = camera.width * camera.height;
  std::map<int, Shape> shapes;
  std::map<Timestamp, std::map<int, Eigen::Vector3d>> positions;  // world; the orientations are not used
  ForEachTextLine(path, "dynamic objects", [&](int line, std::string_view text) {
    if (text.rfind("# object ", 0) == 0 && text.size() > 9 && std::isdigit(static_cast<unsigned char>(text[9]))) {
      const std::string rest(text.substr(9));
      const int id = std::atoi(rest.c_str());
      const auto kv = KeyValues(rest);
      Shape s;
      s.class_name = kv.count("class") ? kv.at("class") : "unknown";
      try {
        if (kv.count("box_size")) {
          s.quad = false;
          std::istringstream in(kv.at("box_size"));
          char comma = 0;
          in >> s.size.x() >> comma >> s.size.y() >> comma >> s.size.z();
          if (!in) throw ParseError(path.string(), line, "bad box_size");
        } else {
          s.width = std::stod(kv.at("width_m"));
          s.height = std::stod(kv.at("height_m"));
          s.bottom = kv.count("bottom_offset") ? std::stod(kv.at("bottom_offset")) : 0.0;
        }
      } catch (const std::logic_error&) {
        throw ParseError(path.string(), line, "an object line needs width_m and height_m, or box_size");
      }
      shapes[id] = s;
    }
  });
  ForEachDataLine(path, [&](int line, const std::vector<std::string_view>& tok) {
    if (tok.size() != 9) throw ParseError(path.string(), line, "expected 'timestamp id tx ty tz qx qy qz qw'");
    const auto t = ParseTimestamp(tok[0]);
    if (!t) throw ParseError(path.string(), line, "bad timestamp '" + std::string(tok[0]) + "'");
    const int id = static_cast<int>(ParseNumber(tok[1], path, line, "id"));
    if (!shapes.count(id)) throw ParseError(path.string(), line, "object " + std::to_string(id) + " has no '# object' line");
    Eigen::Vector3d& p = positions[*t][id];
    for (int a = 0; a < 3; ++a) p[a] = ParseNumber(tok[2 + a], path, line, "position");
  });
  const Trajectory gt = UniqueStamps(ReadTumTrajectory(dir / "groundtruth.txt"));
  const MaskIndex masks(dir);
  std::map<Timestamp, fs::path> depth_files;  // by RGB time
  ForEachDataLine(dir / "associations.txt", [&](int line, const std::vector<std::string_view>& tok) {
    const auto t = tok.size() >= 4 ? ParseTimestamp(tok[0]) : std::nullopt;
    if (!t) throw ParseError((dir / "associations.txt").string(), line, "expected 'timestamp rgb timestamp depth'");
    depth_files[*t] = dir / std::string(tok[3]);
  });
  for (const auto& [t, objects] : positions) {
    const auto depth_file = depth_files.find(t);
    if (depth_file == depth_files.end()) continue;  // not a frame of the sequence
    const std::optional<SE3> T_w_c = PoseAt(gt, t);
    const std::optional<cv::Mat> mask = masks.Load(t);
    if (!T_w_c || !mask) continue;
    std::vector<TrueMover>& frame = truth.frames[t];
    const cv::Mat depth = ReadImageFile(depth_file->second, "depth image", cv::IMREAD_UNCHANGED, kMaxNamedImageBytes,
                                        kMaxNamedImagePixels);
    if (depth.type() != CV_16U || depth.size() != mask->size()) {
      throw InputError("depth image " + depth_file->second.string() + ": not 16-bit or not the mask's size");
    }
    std::map<int, TrueMover> seen;
    for (int v = 0; v < mask->rows; v += kRayStep) {
      for (int u = 0; u < mask->cols; u += kRayStep) {
        const double z = depth.at<std::uint16_t>(v, u) / camera.depth_factor;
        if (mask->at<std::uint8_t>(v, u) == 0 || z <= 0) continue;
        const Eigen::Vector3d p = *T_w_c * Eigen::Vector3d((u - camera.cx) / camera.fx * z, (v - camera.cy) / camera.fy * z, z);
        int best = -1;
        double best_d = 1e30;
        for (const auto& [id, o] : objects) {
          const Shape& shape = shapes[id];
          const double d = (p - o).head<2>().norm();
          const double top = shape.quad ? shape.bottom + shape.height : shape.size.z();
          if (d < Reach(shape) && p.z() > o.z() - kSlack && p.z() < o.z() + top + kSlack && d < best_d) best_d = d, best = id;
        }
        if (best < 0) continue;
        TrueMover& m = seen[best];
        m.centroid += p;
        m.pixels += kRayStep * kRayStep;
      }
    }
    for (auto& [id, m] : seen) {
      m.id = id;
      m.class_name = shapes[id].class_name;
      m.centroid /= m.pixels / (kRayStep * kRayStep);
      frame.push_back(m);
    }
  }
  return truth;
}

}  // namespace

std::optional<MoverTruth> LoadMoverTruth(const fs::path& dir, const CameraConfig& camera) {
  if (OptionalRegularFile(dir / "movers.txt", "true movers")) return ReadMoversFile(dir / "movers.txt", camera);
  if (OptionalRegularFile(dir / "dynamic_objects.txt", "dynamic objects") &&
      OptionalRegularFile(dir / "groundtruth.txt", "ground truth") && OptionalRegularFile(dir / "mask.txt", "mask list")) {
    return ComputeFromPoses(dir, camera);
  }
  return std::nullopt;
}

TrackScore ScoreTracks(const MoverTruth& truth, const std::vector<movers::TrackLine>& tracks, const Trajectory& est,
                       const Trajectory& gt, const TrackScoreOptions& options) {
  TrackScore score;
  const Trajectory est_u = UniqueStamps(est), gt_u = UniqueStamps(gt);
  const SE3 T_gt_est = ComputeAte(gt_u, est_u, kPoseWindow).T_gt_est;
  std::map<Timestamp, std::vector<const movers::TrackLine*>> by_frame;
  for (const movers::TrackLine& l : tracks) {
    if (l.state == movers::TrackState::kConfirmed) by_frame[l.t].push_back(&l);
  }
  std::map<int, MoverScore> movers;
  std::map<int, int> last_track;                     // mover -> the track that last covered it
  std::map<int, std::pair<int, int>> track_frames;   // confirmed track -> (frames, frames covering a mover)
  std::vector<double> errors;
  const double min_pixels = options.min_visible * truth.image_pixels;
  for (const auto& pose : est_u) {
    const auto it = truth.frames.lower_bound(pose.t - kSameFrame);
    if (it == truth.frames.end() || it->first > pose.t + kSameFrame) continue;
    ++score.frames;
    const std::vector<TrueMover>& visible = it->second;
    const auto f = by_frame.find(pose.t);
    static const std::vector<const movers::TrackLine*> kNone;
    const std::vector<const movers::TrackLine*>& live = f == by_frame.end() ? kNone : f->second;
    struct Pair {
      double d;
      std::size_t track, mover;
    };
    std::vector<Pair> pairs;
    for (std::size_t k = 0; k < live.size(); ++k) {
      ++track_frames[live[k]->id].first;
      const Eigen::Vector3d p = T_gt_est * live[k]->position;
      for (std::size_t j = 0; j < visible.size(); ++j) {
        const double d = (p - visible[j].centroid).norm();
        if (d < options.match_gate) pairs.push_back({d, k, j});
      }
    }
    // CLEAR MOT's rule: a mover keeps the track that covered it last while that track
    // stays within the gate; the rest go nearest pair first.
    std::sort(pairs.begin(), pairs.end(), [&](const Pair& a, const Pair& b) {
      const auto kept = [&](const Pair& p) {
        const auto last = last_track.find(visible[p.mover].id);
        return last != last_track.end() && last->second == live[p.track]->id;
      };
      if (kept(a) != kept(b)) return kept(a);
      return a.d < b.d;
    });
    std::vector<bool> track_used(live.size(), false), mover_used(visible.size(), false);
    std::vector<int> cover(visible.size(), 0);
    for (const Pair& p : pairs) {
      if (track_used[p.track] || mover_used[p.mover]) continue;
      track_used[p.track] = mover_used[p.mover] = true;
      cover[p.mover] = live[p.track]->id;
      ++track_frames[live[p.track]->id].second;
      errors.push_back(p.d);
    }
    for (std::size_t j = 0; j < visible.size(); ++j) {
      MoverScore& m = movers[visible[j].id];
      m.id = visible[j].id;
      m.class_name = visible[j].class_name;
      if (visible[j].pixels >= min_pixels) {
        ++m.frames_visible;
        m.frames_covered += cover[j] != 0 ? 1 : 0;
      }
      if (cover[j] != 0) {
        auto last = last_track.find(m.id);
        if (last != last_track.end() && last->second != cover[j]) ++m.id_switches;
        last_track[m.id] = cover[j];
      }
    }
  }
  int visible_total = 0, covered_total = 0;
  score.min_coverage = 1;
  for (const auto& [id, m] : movers) {
    score.movers.push_back(m);
    visible_total += m.frames_visible;
    covered_total += m.frames_covered;
    if (m.frames_visible > 0) score.min_coverage = std::min(score.min_coverage, double(m.frames_covered) / m.frames_visible);
    score.max_id_switches = std::max(score.max_id_switches, m.id_switches);
  }
  score.coverage = visible_total > 0 ? double(covered_total) / visible_total : 0.0;
  for (const auto& [id, fc] : track_frames) score.false_tracks += 2 * fc.second < fc.first ? 1 : 0;
  score.false_per_100_frames = score.frames > 0 ? 100.0 * score.false_tracks / score.frames : 0.0;
  score.matches = static_cast<int>(errors.size());
  score.median_centroid_error = Median(errors);
  return score;
}

nlohmann::json ToJson(const TrackScore& s, const TrackScoreOptions& options) {
  nlohmann::json movers = nlohmann::json::array();
  for (const MoverScore& m : s.movers) {
    movers.push_back({{"id", m.id},
                      {"class", m.class_name},
                      {"frames_visible", m.frames_visible},
                      {"frames_covered", m.frames_covered},
                      {"coverage", m.frames_visible > 0 ? double(m.frames_covered) / m.frames_visible : 0.0},
                      {"id_switches", m.id_switches}});
  }
  return {{"frames", s.frames},
          {"match_gate_m", options.match_gate},
          {"min_visible", options.min_visible},
          {"coverage", s.coverage},
          {"min_coverage", s.min_coverage},
          {"max_id_switches", s.max_id_switches},
          {"false_tracks", s.false_tracks},
          {"false_per_100_frames", s.false_per_100_frames},
          {"median_centroid_error_m", s.median_centroid_error},
          {"matches", s.matches},
          {"movers", movers}};
}

}  // namespace sgslam::eval
