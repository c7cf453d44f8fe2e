#include "sgslam/synth/writer.h"

#include <algorithm>
#include <atomic>
#include <charconv>
#include <chrono>
#include <exception>
#include <map>
#include <mutex>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <thread>
#include <vector>

#include "sgslam/common/error.h"
#include "sgslam/common/regular_file.h"
#include "sgslam/detection/detections_file.h"
#include "sgslam/io/atomic_write.h"
#include "sgslam/io/trajectory.h"
#include "sgslam/synth/presets.h"
#include "sgslam/synth/sequence.h"

namespace sgslam::synth {

namespace fs = std::filesystem;

namespace {

// A time in s as the command line and sgslam.yaml take it back (no rounding).
std::string FormatSeconds(double s) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof(buf), s);  // the shortest that reads back exactly
  return std::string(buf, r.ptr);
}

// A moving object's visible part in one frame (movers.txt).
struct VisibleMover {
  int id = 0;
  int pixels = 0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // m, world: mean of its visible surface points
};

struct FrameResult {
  SE3 T_w_c;
  std::vector<Detection> detections;
  double dynamic_fraction = 0;
  std::vector<VisibleMover> movers;
};

// The visible part of each moving object: the mean world point of its pixels.
std::vector<VisibleMover> VisibleMovers(const RenderedFrame& f, const SynthSequence& seq) {
  std::vector<VisibleMover> out;
  const Intrinsics& K = seq.intrinsics();
  for (const SceneObject& o : seq.objects()) {
    if (!o.info.dynamic) continue;
    VisibleMover m;
    m.id = o.info.id;
    for (int v = 0; v < f.object_id.rows; ++v) {
      for (int u = 0; u < f.object_id.cols; ++u) {
        const float z = f.depth.at<float>(v, u);
        if (f.object_id.at<int>(v, u) != m.id || z <= 0) continue;
        m.centroid += f.T_w_c * Eigen::Vector3d((u - K.cx) / K.fx * z, (v - K.cy) / K.fy * z, z);
        ++m.pixels;
      }
    }
    if (m.pixels == 0) continue;
    m.centroid /= m.pixels;
    out.push_back(m);
  }
  return out;
}

constexpr char kMoversHeader[] =
    "# moving objects' visible parts (sgslam synth), world frame = groundtruth.txt's\n"
    "# timestamp id class visible_px cx cy cz   (centroid: mean of the visible surface points, m)\n";

constexpr char kCameraYamlHeader[] = "# camera of the synthetic sequence written by sgslam synth\n";

// --force replaces what synth wrote before, never a dataset of the same layout
// that synth did not write (a user's own rgb.txt, groundtruth.txt, images).
void CheckOutputFolder(const fs::path& out, bool force) {
  std::error_code ec;
  if (!fs::exists(out, ec)) return;
  if (!fs::is_directory(out, ec)) throw InputError("synth: output path exists and is not a folder: " + out.string());
  if (fs::is_empty(out, ec)) return;
  if (!force) {
    throw InputError("synth: output folder is not empty: " + out.string() +
                     " (use --force to replace the files sgslam synth writes there)");
  }
  if (WrittenBySynth(out)) return;
  for (const char* name : {"rgb.txt", "depth.txt", "mask.txt", "associations.txt", "groundtruth.txt", "detections.txt",
                           "objects_gt.json", "movers.txt", "sgslam.yaml", "rgb", "depth", "mask"}) {
    if (fs::exists(out / name, ec)) {
      throw InputError("synth --force: " + (out / name).string() + " was not written by sgslam synth (" +
                       (out / "sgslam.yaml").string() + " is not synth's); choose another folder");
    }
  }
}

// Fast PNG settings: writing dominates the run time. Huffman-only coding suits the
// noisy colour images (faster and smaller than deflate level 1); depth and masks
// compress well with level 1.
void WritePng(const fs::path& path, const cv::Mat& image) {
  const int strategy = image.channels() == 3 ? cv::IMWRITE_PNG_STRATEGY_HUFFMAN_ONLY : cv::IMWRITE_PNG_STRATEGY_DEFAULT;
  bool ok = false;
  try {
    ok = cv::imwrite(path.string(), image, {cv::IMWRITE_PNG_COMPRESSION, 1, cv::IMWRITE_PNG_STRATEGY, strategy});
  } catch (const cv::Exception& e) {
    throw InputError("cannot write image " + path.string() + ": " + e.what());
  }
  if (!ok) throw InputError("cannot write image: " + path.string());
}

FrameResult RenderAndSave(const SynthSequence& seq, int i, const fs::path& out) {
  const RenderedFrame f = seq.Render(i);
  const std::string name = FormatTimestamp(f.t) + ".png";
  WritePng(out / "rgb" / name, f.bgr);
  WritePng(out / "depth" / name, f.depth_raw);
  WritePng(out / "mask" / name, f.dynamic_mask);
  return {f.T_w_c, GroundTruthDetections(f, seq.scene()), f.dynamic_fraction, VisibleMovers(f, seq)};
}

// Renders every frame on `threads` workers pulling frame numbers from a counter, or
// until *stop; returns how many frames from the first were rendered (all of them
// without a stop).
int RenderAll(const SynthSequence& seq, const fs::path& out, int threads, const std::atomic<bool>* stop,
              std::vector<FrameResult>& results) {
  results.assign(seq.size(), {});
  std::vector<char> done(seq.size(), 0);
  std::atomic<int> next{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  const auto work = [&] {
    for (int i = next++; i < seq.size(); i = next++) {
      if (stop && *stop) break;
      try {
        results[i] = RenderAndSave(seq, i, out);
        done[i] = 1;  // each worker writes its own frames' entries; read after the join
      } catch (...) {
        const std::lock_guard lock(failure_mutex);
        if (!failure) failure = std::current_exception();
        next = seq.size();  // stop the others early
      }
    }
  };
  std::vector<std::thread> workers;
  for (int w = 0; w < std::max(threads, 1); ++w) workers.emplace_back(work);
  for (std::thread& t : workers) t.join();
  if (failure) std::rethrow_exception(failure);
  return static_cast<int>(std::find(done.begin(), done.end(), 0) - done.begin());
}

std::string ImageList(const SynthSequence& seq, int frames, const char* title, const char* folder,
                      const std::string& source) {
  std::string text = std::string("# ") + title + "\n# file: '" + source + "'\n# timestamp filename\n";
  for (int i = 0; i < frames; ++i) {
    const std::string t = FormatTimestamp(seq.timestamp(i));
    text += t + " " + folder + "/" + t + ".png\n";
  }
  return text;
}

std::string ObjectsJson(const SynthSequence& seq, int frames) {
  nlohmann::json objects = nlohmann::json::array();
  for (const SceneObject& o : seq.objects()) {
    const ObjectInfo& info = o.info;
    nlohmann::json j = {{"id", info.id}, {"class", info.class_name}, {"class_id", info.class_id},
                        {"dynamic", info.dynamic}};
    if (!info.dynamic) j["centroid"] = {info.centroid.x(), info.centroid.y(), info.centroid.z()};
    j["size"] = {info.size.x(), info.size.y(), info.size.z()};
    objects.push_back(j);
  }
  const nlohmann::json root = {{"preset", seq.scene().preset}, {"seed", seq.scene().seed},
                               {"frames", frames}, {"objects", objects}};
  return root.dump(2) + "\n";
}

// The command that writes the same images: the sensor options whenever they are
// not a global shutter and exact depth, or not the preset's defaults.
std::string SourceCommand(const SynthSequence& seq) {
  const PresetDefaults d = DefaultsOf(seq.scene().preset);
  std::string command = "sgslam synth --preset " + seq.scene().preset + " --seed " + std::to_string(seq.scene().seed);
  if (seq.readout() > 0 || seq.readout() != d.readout) command += " --readout " + FormatSeconds(seq.readout());
  if (seq.depth_noise() != DepthNoise::kNone || seq.depth_noise() != d.depth_noise) {
    command += std::string(" --depth-noise ") + DepthNoiseName(seq.depth_noise());
  }
  return command;
}

// The list files of the first `frames` frames.
void WriteLists(const SynthSequence& seq, const std::vector<FrameResult>& results, int frames, const fs::path& out) {
  const std::string source = SourceCommand(seq);
  WriteFileAtomically(out / "rgb.txt", ImageList(seq, frames, "color images", "rgb", source));
  WriteFileAtomically(out / "depth.txt", ImageList(seq, frames, "depth maps", "depth", source));
  WriteFileAtomically(out / "mask.txt", ImageList(seq, frames, "dynamic masks (255: moving object)", "mask", source));
  std::string associations;
  Trajectory groundtruth;
  std::vector<FrameDetections> detections;
  for (int i = 0; i < frames; ++i) {
    const std::string t = FormatTimestamp(seq.timestamp(i));
    associations += t + " rgb/" + t + ".png " + t + " depth/" + t + ".png\n";
    groundtruth.push_back({seq.timestamp(i), results[i].T_w_c});
    detections.emplace_back(seq.timestamp(i), results[i].detections);
  }
  WriteFileAtomically(out / "associations.txt", associations);
  WriteTumTrajectory(out / "groundtruth.txt", groundtruth);
  WriteDetectionsFile(out / "detections.txt", detections);
  WriteFileAtomically(out / "objects_gt.json", ObjectsJson(seq, frames));
  std::string movers = std::string(kMoversHeader);
  std::map<int, std::string> classes;
  for (const SceneObject& o : seq.objects()) classes[o.info.id] = o.info.class_name;
  for (int i = 0; i < frames; ++i) {
    for (const VisibleMover& m : results[i].movers) {
      char buf[160];
      std::snprintf(buf, sizeof buf, " %d %s %d %.4f %.4f %.4f\n", m.id, classes[m.id].c_str(),
                    m.pixels, m.centroid.x(), m.centroid.y(), m.centroid.z());
      movers += FormatTimestamp(seq.timestamp(i)) + buf;
    }
  }
  WriteFileAtomically(out / "movers.txt", movers);
}

}  // namespace

std::string CameraYaml(double readout) {
  const std::string shutter = "  readout: " + FormatSeconds(readout) +
                              (readout > 0 ? "  # s, rendered with a rolling shutter\n" : "  # rendered with a global shutter\n");
  return std::string(kCameraYamlHeader) +
         "camera:\n"
         "  width: 640\n"
         "  height: 480\n"
         "  fx: 525.0\n"
         "  fy: 525.0\n"
         "  cx: 319.5\n"
         "  cy: 239.5\n"
         "  k1: 0.0\n"
         "  k2: 0.0\n"
         "  p1: 0.0\n"
         "  p2: 0.0\n"
         "  k3: 0.0\n"
         "  fps: 30.0\n"
         "  depth_factor: 5000.0\n"
         + shutter +
         "# the ground-truth boxes in detections.txt stand in for the detector: a COCO\n"
         "# network does not know the textured stand-ins for people (use --config to change)\n"
         "detector:\n"
         "  backend: file\n";
}

bool WrittenBySynth(const fs::path& folder) {
  const fs::path yaml = folder / "sgslam.yaml";
  if (!WhyNotRegularFile(yaml).empty()) return false;
  const RegularFile file(yaml, "sgslam.yaml");
  const std::size_t n = sizeof kCameraYamlHeader - 1;
  return file.size() >= n && file.Read(0, n) == kCameraYamlHeader;
}

SynthSummary GenerateSequence(const SynthOptions& options, const fs::path& out) {
  const auto start = std::chrono::steady_clock::now();
  const PresetDefaults d = DefaultsOf(options.preset);  // checks the preset first
  const SynthSequence seq(options.preset, options.seed, options.frames.value_or(d.frames),
                          options.readout.value_or(d.readout), options.depth_noise.value_or(d.depth_noise));
  CheckOutputFolder(out, options.force);
  // First, so that a folder left by a synth killed part-way is known as synth's.
  WriteFileAtomically(out / "sgslam.yaml", CameraYaml(seq.readout()));
  for (const char* sub : {"rgb", "depth", "mask"}) {
    std::error_code ec;
    fs::create_directories(out / sub, ec);
    if (ec) throw InputError("cannot create folder " + (out / sub).string() + ": " + ec.message());
  }
  std::vector<FrameResult> results;
  const int frames = RenderAll(seq, out, options.threads, options.stop, results);
  WriteLists(seq, results, frames, out);

  SynthSummary summary;
  summary.frames = frames;
  summary.stopped = frames < seq.size();
  summary.preset = options.preset;
  summary.seed = options.seed;
  summary.readout = seq.readout();
  summary.depth_noise = seq.depth_noise();
  summary.out = out;
  for (int i = 0; i < frames; ++i) summary.mean_dynamic_fraction += results[i].dynamic_fraction / frames;
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace sgslam::synth
