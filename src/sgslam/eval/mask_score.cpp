#include "sgslam/eval/mask_score.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "sgslam/common/error.h"
#include "sgslam/common/regular_file.h"
#include "sgslam/io/image_file.h"
#include "sgslam/io/text_file.h"

namespace sgslam::eval {

void MaskScore::Add(const MaskScore& o) {
  frames += o.frames;
  moving += o.moving;
  moving_rejected += o.moving_rejected;
  static_points += o.static_points;
  static_rejected += o.static_rejected;
  static_near += o.static_near;
  static_near_rejected += o.static_near_rejected;
}

MaskScore ScoreKeypoints(const cv::Mat& mask, const std::vector<cv::Point2f>& points,
                         const std::vector<std::uint8_t>& rejected) {
  MaskScore s;
  s.frames = 1;
  // Distance of every pixel to the nearest moving one (none moving: all far).
  cv::Mat distance;
  if (cv::countNonZero(mask) > 0) cv::distanceTransform(mask == 0, distance, cv::DIST_L2, cv::DIST_MASK_5);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const int u = cvRound(points[i].x), v = cvRound(points[i].y);
    if (u < 0 || v < 0 || u >= mask.cols || v >= mask.rows) continue;
    const bool out = i < rejected.size() && rejected[i] != 0;
    if (mask.at<std::uint8_t>(v, u) != 0) {
      ++s.moving;
      s.moving_rejected += out ? 1 : 0;
    } else {
      ++s.static_points;
      s.static_rejected += out ? 1 : 0;
      if (!distance.empty() && distance.at<float>(v, u) < MaskScore::kOutlinePx) {
        ++s.static_near;
        s.static_near_rejected += out ? 1 : 0;
      }
    }
  }
  return s;
}

MaskIndex::MaskIndex(const std::filesystem::path& dir) : dir_(dir) {
  const auto list = dir / "mask.txt";
  if (!OptionalRegularFile(list, "mask list")) return;
  ForEachDataLine(list, [&](int line, const std::vector<std::string_view>& tokens) {
    if (tokens.size() < 2) throw ParseError(list.string(), line, "expected 'timestamp file'");
    const auto t = ParseTimestamp(tokens[0]);
    if (!t) throw ParseError(list.string(), line, "bad timestamp '" + std::string(tokens[0]) + "'");
    files_[*t] = std::string(tokens[1]);
  });
}

std::optional<cv::Mat> MaskIndex::Load(Timestamp t) const {
  if (files_.empty()) return std::nullopt;
  auto it = files_.lower_bound(t - FromSeconds(0.001));
  if (it == files_.end() || it->first > t + FromSeconds(0.001)) return std::nullopt;
  const auto path = dir_ / it->second;
  try {
    return ReadImageFile(path, "image", cv::IMREAD_GRAYSCALE, kMaxNamedImageBytes, kMaxNamedImagePixels);
  } catch (const InputError& e) {
    throw InputError(std::string("cannot read dynamic mask: ") + e.what());
  }
}

}  // namespace sgslam::eval
