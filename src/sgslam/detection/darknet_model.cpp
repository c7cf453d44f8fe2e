#include "sgslam/detection/darknet_model.h"

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <map>
#include <sstream>

#include <spdlog/spdlog.h>

#include "sgslam/common/data_dir.h"
#include "sgslam/common/error.h"
#include "sgslam/common/regular_file.h"
#include "sgslam/common/sha256.h"

namespace sgslam {

namespace fs = std::filesystem;

namespace {

// What a model folder's files may weigh. Darknet cfgs are a few KB and a class
// list of COCO's 80 names 1 KB; the largest YOLO weights (v4, v7-e6e) are 250-600
// MB. The bounds stop the wrong file before it is read.
constexpr std::uint64_t kMaxCfgBytes = 1 << 20;
constexpr std::uint64_t kMaxNamesBytes = 1 << 20;
constexpr std::uint64_t kMaxWeightsBytes = std::uint64_t{2} << 30;

std::string Trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(" \t\r") - first + 1);
}

// Gives every [yolo] section thresh = floor (replacing a thresh it may have) and
// returns the class count of the last [yolo] section (0 when there is none).
std::string SetYoloThreshold(const std::string& cfg, float floor, int& classes) {
  std::istringstream in(cfg);
  std::string line, out, section;
  classes = 0;
  while (std::getline(in, line)) {
    const std::string t = Trim(line);
    if (!t.empty() && t.front() == '[') {
      section = t;
      out += line + "\n";
      if (section == "[yolo]") out += "thresh=" + std::to_string(floor) + "\n";
      continue;
    }
    const auto eq = t.find('=');
    const std::string key = eq == std::string::npos ? "" : Trim(t.substr(0, eq));
    if (section == "[yolo]" && key == "thresh") continue;
    if (section == "[yolo]" && key == "classes") classes = std::atoi(t.c_str() + eq + 1);
    out += line + "\n";
  }
  return out;
}

std::vector<std::string> ParseNames(const std::string& text) {
  std::vector<std::string> names;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (const std::string name = Trim(line); !name.empty()) names.push_back(name);
  }
  return names;
}

// Darknet weights: int32 major, minor, revision, then "seen" (int64 from version
// 0.2 on), then float32 parameters. The parameters equal the blobs OpenCV builds
// from them (conv weights and biases, batch-norm scale/mean/variance); the Region
// layers' anchors come from the cfg. Checked on both Yolo-Fastest 1.1 models.
void CheckWeightsSize(const cv::dnn::Net& net, const std::string& weights, const DarknetModel& m) {
  std::int32_t version[3] = {0, 0, 0};
  if (weights.size() < sizeof version) throw InputError("weights file too short: " + m.weights.string());
  std::memcpy(version, weights.data(), sizeof version);
  const bool long_seen = version[0] * 10 + version[1] >= 2 && version[0] < 1000 && version[1] < 1000;
  std::size_t expected = sizeof version + (long_seen ? 8 : 4);
  for (const auto& name : net.getLayerNames()) {
    const cv::Ptr<cv::dnn::Layer> layer = net.getLayer(name);
    if (layer->type == "Region") continue;
    for (const cv::Mat& blob : layer->blobs) expected += blob.total() * sizeof(float);
  }
  if (weights.size() != expected) {
    throw InputError("weights file does not fit its cfg (" + std::to_string(weights.size()) + " bytes, " +
                     m.cfg.filename().string() + " needs " + std::to_string(expected) +
                     "): truncated or from another model: " + m.weights.string());
  }
}

// A folder with a SHA256SUMS list (the shipped models have one) vouches for the
// files it lists: a file that does not match is refused, naming it.
void CheckListedSum(const fs::path& file, const std::string& bytes, const std::map<std::string, std::string>& sums) {
  const auto it = sums.find(file.filename().string());
  if (it == sums.end()) return;
  if (const std::string actual = Sha256Hex(bytes); actual != it->second) {
    throw InputError("checksum mismatch: " + file.string() + " has SHA-256 " + actual + ", " +
                     (file.parent_path() / "SHA256SUMS").string() + " lists " + it->second +
                     " (a damaged or replaced file)");
  }
}

}  // namespace

fs::path DefaultModelDir() {
  const auto data = DataDir();
  return data ? *data / "models" / kDefaultModelFolder : fs::path();
}

fs::path ResolveModelDir(const std::string& model_dir) {
  fs::path dir = model_dir;
  const char* how = "detector.model_dir / --model";
  if (dir.empty()) {
    if (const char* env = std::getenv("SGSLAM_MODEL_DIR"); env != nullptr && *env != '\0') {
      dir = env;
      how = "$SGSLAM_MODEL_DIR";
    }
  }
  if (dir.empty()) {
    dir = DefaultModelDir();
    how = "the models installed with sgslam";
    if (dir.empty()) {
      throw InputError(
          "no detector model folder: sgslam's own models/ were not found beside the executable (share/sgslam); "
          "pass --model DIR, set detector.model_dir in the config or the environment variable SGSLAM_MODEL_DIR, "
          "or run geometry-only with --no-detector or --mode geometric");
    }
  }
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    throw InputError(std::string("detector model folder not found (from ") + how + "): " + dir.string());
  }
  return dir;
}

fs::path DarknetCfgPath(const fs::path& dir, const std::string& model) { return dir / (model + ".cfg"); }
fs::path DarknetWeightsPath(const fs::path& dir, const std::string& model) { return dir / (model + ".weights"); }

bool DarknetModelPresent(const fs::path& dir, const std::string& model) {
  // Something under both names counts: a FIFO or a folder there is then refused by
  // LoadDarknetModel, naming it, rather than taken for a model not installed.
  return WhyNotRegularFile(DarknetCfgPath(dir, model)) != kNotFound &&
         WhyNotRegularFile(DarknetWeightsPath(dir, model)) != kNotFound;
}

DarknetModel LoadDarknetModel(const fs::path& dir, const std::string& model, float score_floor) {
  DarknetModel m;
  m.cfg = DarknetCfgPath(dir, model);
  m.weights = DarknetWeightsPath(dir, model);
  const fs::path names_file = dir / "coco.names";
  const std::string cfg_text = ReadRegularFile(m.cfg, "model cfg file", kMaxCfgBytes);
  const std::string weights = ReadRegularFile(m.weights, "model weights file", kMaxWeightsBytes);
  const std::string names = ReadRegularFile(names_file, "class names file", kMaxNamesBytes);
  if (const auto sums_file = OptionalRegularFile(dir / "SHA256SUMS", "checksum list")) {
    const auto sums = ReadSha256Sums(*sums_file);
    for (const fs::path& f : {m.cfg, m.weights}) {
      if (!sums.count(f.filename().string())) {
        spdlog::warn("{} does not list {}: the file is loaded unchecked", sums_file->string(), f.filename().string());
      }
    }
    CheckListedSum(m.cfg, cfg_text, sums);
    CheckListedSum(m.weights, weights, sums);
    CheckListedSum(names_file, names, sums);
  }
  m.class_names = ParseNames(names);
  int classes = 0;
  const std::string cfg = SetYoloThreshold(cfg_text, score_floor, classes);
  if (cfg_text.find("[net]") == std::string::npos || classes <= 0) {
    throw InputError("not a Darknet YOLO cfg (needs [net] and [yolo] sections with classes=): " + m.cfg.string());
  }
  if (static_cast<int>(m.class_names.size()) != classes) {
    throw InputError("class names file has " + std::to_string(m.class_names.size()) + " names, " +
                     m.cfg.filename().string() + " has " + std::to_string(classes) +
                     " classes: " + names_file.string());
  }
  // Parse the cfg alone first, so an error names the file that caused it. OpenCV
  // sizes layers from the cfg, so a wild value may end in std::bad_alloc (or
  // another library exception) instead of a cv::Exception: each names the file too.
  try {
    cv::dnn::readNetFromDarknet(cfg.data(), cfg.size());
  } catch (const cv::Exception& e) {
    throw InputError("OpenCV cannot parse the model cfg " + m.cfg.string() + ": " + e.err);
  } catch (const std::exception& e) {
    throw InputError("OpenCV cannot parse the model cfg " + m.cfg.string() + ": " + e.what());
  }
  try {
    m.net = cv::dnn::readNetFromDarknet(cfg.data(), cfg.size(), weights.data(), weights.size());
  } catch (const cv::Exception& e) {
    throw InputError("OpenCV cannot read the model weights " + m.weights.string() + ": " + e.err);
  } catch (const std::exception& e) {
    throw InputError("OpenCV cannot read the model weights " + m.weights.string() + ": " + e.what());
  }
  CheckWeightsSize(m.net, weights, m);
  m.net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  m.net.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  return m;
}

}  // namespace sgslam
