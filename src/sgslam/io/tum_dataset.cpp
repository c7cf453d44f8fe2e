#include "sgslam/io/tum_dataset.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "sgslam/common/error.h"
#include "sgslam/common/regular_file.h"
#include "sgslam/common/stats.h"
#include "sgslam/io/association.h"
#include "sgslam/io/image_file.h"
#include "sgslam/io/text_file.h"

namespace sgslam {

namespace fs = std::filesystem;

namespace {

struct ListEntry {
  Timestamp t;
  fs::path path;
  int line;
};

std::vector<ListEntry> ReadList(const fs::path& file, const fs::path& dir) {
  std::vector<ListEntry> entries;
  ForEachDataLine(file, [&](int line, const std::vector<std::string_view>& tok) {
    if (tok.size() != 2) {
      throw ParseError(file.string(), line, "expected 'timestamp path', got " + std::to_string(tok.size()) + " fields");
    }
    const auto t = ParseTimestamp(tok[0]);
    if (!t) {
      throw ParseError(file.string(), line, "bad timestamp '" + std::string(tok[0]) + "' (seconds, at most " +
                                                std::to_string(kMaxTimestampSeconds) + ")");
    }
    entries.push_back({*t, dir / fs::path(std::string(tok[1])), line});
  });
  std::stable_sort(entries.begin(), entries.end(), [](const ListEntry& a, const ListEntry& b) { return a.t < b.t; });
  // Equal times (placeholders, say) would make every pair of them a candidate of the
  // association: thousands of frames would take gigabytes instead of an error.
  for (std::size_t i = 1; i < entries.size(); ++i) {
    if (entries[i].t == entries[i - 1].t) {
      throw ParseError(file.string(), entries[i].line, "timestamp " + FormatTimestamp(entries[i].t) +
                                                           " repeats that of line " + std::to_string(entries[i - 1].line));
    }
  }
  return entries;
}

std::string Describe(const cv::Mat& m) {
  const char* depth[] = {"8-bit", "8-bit signed", "16-bit", "16-bit signed", "32-bit int", "32-bit float",
                         "64-bit float", "16-bit float"};
  return std::string(depth[m.depth()]) + " " + std::to_string(m.channels()) + "-channel";
}

struct PixelSize {
  std::uint64_t width = 0, height = 0;
  bool operator==(const PixelSize&) const = default;
  std::string str() const { return std::to_string(width) + "x" + std::to_string(height); }
};

PixelSize Size(const cv::Mat& m) { return {static_cast<std::uint64_t>(m.cols), static_cast<std::uint64_t>(m.rows)}; }

// The RGB and depth images of a frame have the camera's size.
void CheckSizes(const FrameRecord& r, PixelSize rgb, PixelSize depth, const CameraConfig& camera) {
  if (rgb != depth) {
    throw InputError("RGB and depth sizes differ: " + r.rgb.string() + " is " + rgb.str() + ", " + r.depth.string() +
                     " is " + depth.str());
  }
  const PixelSize expected{static_cast<std::uint64_t>(camera.width), static_cast<std::uint64_t>(camera.height)};
  if (rgb != expected) {
    throw InputError("image " + r.rgb.string() + " is " + rgb.str() +
                     " but the camera config says camera.width x camera.height = " + expected.str());
  }
}

}  // namespace

TumDataset::TumDataset(const fs::path& dir, const DatasetConfig& config) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw InputError("dataset folder not found: " + dir.string());
  dir_ = fs::canonical(dir, ec);
  const fs::path associations = dir_ / "associations.txt";
  if (OptionalRegularFile(associations, "associations file")) {
    associations_from_file_ = true;
    ForEachDataLine(associations, [&](int line, const std::vector<std::string_view>& tok) {
      if (tok.size() < 4) {
        throw ParseError(associations.string(), line, "expected 't_rgb rgb_path t_depth depth_path'");
      }
      const auto t_rgb = ParseTimestamp(tok[0]);
      const auto t_depth = ParseTimestamp(tok[2]);
      if (!t_rgb || !t_depth) throw ParseError(associations.string(), line, "bad timestamp");
      frames_.push_back({*t_rgb, *t_depth, dir_ / std::string(tok[1]), dir_ / std::string(tok[3]),
                         "associations.txt:" + std::to_string(line)});
    });
    std::stable_sort(frames_.begin(), frames_.end(),
                     [](const FrameRecord& a, const FrameRecord& b) { return a.t_rgb < b.t_rgb; });
  } else {
    for (const char* list : {"rgb.txt", "depth.txt"}) {
      if (!OptionalRegularFile(dir_ / list, "image list")) {
        throw InputError("missing " + (dir_ / list).string() +
                         " (a TUM RGB-D folder needs rgb.txt and depth.txt, or associations.txt)");
      }
    }
    const auto rgb = ReadList(dir_ / "rgb.txt", dir_);
    const auto depth = ReadList(dir_ / "depth.txt", dir_);
    std::vector<Timestamp> t_rgb, t_depth;
    for (const auto& e : rgb) t_rgb.push_back(e.t);
    for (const auto& e : depth) t_depth.push_back(e.t);
    const auto matches = AssociateByTime(t_rgb, t_depth, FromSeconds(config.max_time_difference));
    for (const auto& [i, j] : matches) {
      frames_.push_back({rgb[i].t, depth[j].t, rgb[i].path, depth[j].path, "rgb.txt:" + std::to_string(rgb[i].line)});
    }
    if (frames_.empty()) {
      throw InputError("empty sequence in " + dir_.string() + ": rgb.txt has " + std::to_string(rgb.size()) +
                       " images, depth.txt " + std::to_string(depth.size()) + ", and no pair is within " +
                       std::to_string(config.max_time_difference) + " s");
    }
    spdlog::debug("associated {} of {} RGB and {} depth images", frames_.size(), rgb.size(), depth.size());
  }
  if (frames_.empty()) throw InputError("empty sequence: " + associations.string() + " lists no frame");
  groundtruth_ = OptionalRegularFile(dir_ / "groundtruth.txt", "ground truth");
}

std::string TumDataset::name() const { return dir_.filename().string(); }

RgbdImages TumDataset::Load(std::size_t i, const CameraConfig& camera) const {
  const FrameRecord& r = frames_.at(i);
  // Even an uncompressed 16-bit RGBA file of the camera's size fits in this.
  const std::uintmax_t max_bytes = 8ull * static_cast<std::uintmax_t>(camera.width) * camera.height + (1u << 20);
  const auto read = [&](const fs::path& p) {
    if (!OptionalRegularFile(p, "image (listed in " + r.listed_at + ")")) {
      throw InputError("image missing: " + p.string() + " (listed in " + r.listed_at + ")");
    }
    return ReadFileBytes(p, max_bytes);
  };
  const std::vector<std::uint8_t> rgb_bytes = read(r.rgb), depth_bytes = read(r.depth);
  const auto rgb_header = ReadImageHeader(rgb_bytes), depth_header = ReadImageHeader(depth_bytes);
  if (rgb_header && depth_header) {  // before decoding: a header claiming 60000x60000 pixels costs nothing
    CheckSizes(r, {rgb_header->width, rgb_header->height}, {depth_header->width, depth_header->height}, camera);
  }
  RgbdImages out;
  out.index = i;
  out.t = r.t_rgb;
  out.bgr = DecodeImageFile(r.rgb, rgb_bytes, rgb_header, cv::IMREAD_UNCHANGED);
  out.depth = DecodeImageFile(r.depth, depth_bytes, depth_header, cv::IMREAD_UNCHANGED);
  if (out.depth.type() != CV_16UC1) {
    throw InputError("depth image " + r.depth.string() + " is " + Describe(out.depth) +
                     "; expected a 16-bit single-channel PNG");
  }
  if (out.bgr.depth() != CV_8U || (out.bgr.channels() != 1 && out.bgr.channels() != 3 && out.bgr.channels() != 4)) {
    throw InputError("RGB image " + r.rgb.string() + " is " + Describe(out.bgr) + "; expected 8-bit colour");
  }
  if (out.bgr.channels() == 1) cv::cvtColor(out.bgr, out.bgr, cv::COLOR_GRAY2BGR);
  if (out.bgr.channels() == 4) cv::cvtColor(out.bgr, out.bgr, cv::COLOR_BGRA2BGR);
  CheckSizes(r, Size(out.bgr), Size(out.depth), camera);
  return out;
}

namespace {

// Where RGB-D cameras see a room: Kinect-class sensors measure from 0.4-0.5 m, the
// nearest RealSense models from 0.1-0.3 m, and few scenes have half their pixels
// beyond 6 m. A median outside is the mark of a wrong depth factor (millimetres
// read with TUM's 5000 make depth 5x too near), so the message names the common
// factors that would put it inside.
constexpr double kUsualMedianMin = 0.5, kUsualMedianMax = 6.0;

std::string Metres(double m) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g m", m);
  return buf;
}

}  // namespace

std::string DepthFactorHint(double metres, double factor, double lo, double hi) {
  std::string hint;
  for (const double f : {1000.0, 5000.0}) {
    const double m = metres * factor / f;
    if (f != factor && m >= lo && m <= hi) {
      hint = "; with camera.depth_factor = " + std::to_string(static_cast<int>(f)) + (f == 1000 ? " (millimetres)" : "") +
             " it would be " + Metres(m);
    }
  }
  return hint;
}

std::optional<std::string> CheckDepthScale(const RgbdImages& frame, const FrameRecord& record,
                                           const CameraConfig& camera, const DatasetConfig& dataset) {
  std::vector<double> depths;
  for (int v = 0; v < frame.depth.rows; v += 4) {
    const auto* row = frame.depth.ptr<std::uint16_t>(v);
    for (int u = 0; u < frame.depth.cols; u += 4) {
      if (row[u] != 0) depths.push_back(row[u] / camera.depth_factor);
    }
  }
  if (depths.size() < 100) return std::nullopt;  // nothing to judge by; tracking will report the lack of depth
  const double median = Median(std::move(depths));
  char factor[32];
  std::snprintf(factor, sizeof factor, "%g", camera.depth_factor);
  const std::string what = "depth image " + record.depth.string() + " has a median depth of " + Metres(median) +
                           " with camera.depth_factor = " + factor;
  const std::string hint = DepthFactorHint(median, camera.depth_factor, kUsualMedianMin, kUsualMedianMax);
  if (median < dataset.min_median_depth || median > dataset.max_median_depth) {
    const bool near = median < dataset.min_median_depth;
    throw InputError(what + hint + ". The depth scale is wrong for this data: set camera.depth_factor (TUM and Bonn " +
                     "use 5000, millimetre depth 1000), or dataset." + (near ? "min_median_depth" : "max_median_depth") +
                     " if the scene really is " + (near ? "this near" : "this far"));
  }
  if (median < kUsualMedianMin || median > kUsualMedianMax) {
    return what + ", unusually " + (median < kUsualMedianMin ? "near" : "far") + " for an RGB-D camera" + hint +
           ". Check camera.depth_factor (TUM and Bonn use 5000, millimetre depth 1000)";
  }
  return std::nullopt;
}

}  // namespace sgslam
