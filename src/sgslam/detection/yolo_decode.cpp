#include "sgslam/detection/yolo_decode.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <opencv2/dnn/dnn.hpp>

namespace sgslam {

namespace {

struct Candidates {
  std::vector<cv::Rect2d> boxes;
  std::vector<float> scores;
};

}  // namespace

std::vector<Detection> DecodeYoloOutputs(const std::vector<cv::Mat>& outputs, cv::Size image,
                                         const std::vector<std::string>& class_names, const YoloDecodeParams& params) {
  const int classes = static_cast<int>(class_names.size());
  const float min_score = std::min(params.score_threshold, params.person_score_threshold);
  std::map<int, Candidates> by_class;  // ordered: deterministic output
  for (const cv::Mat& out : outputs) {
    if (out.empty() || out.dims != 2 || out.type() != CV_32F || out.cols < 5 + classes) continue;
    for (int r = 0; r < out.rows; ++r) {
      const float* row = out.ptr<float>(r);
      // A broken model or weights file may give NaN or infinite outputs: such a row is no box.
      if (!std::all_of(row, row + 4, [](float v) { return std::isfinite(v); }) || !(row[2] > 0) || !(row[3] > 0)) continue;
      for (int c = 0; c < classes; ++c) {
        const float score = row[5 + c];
        if (!(score >= min_score) || !(score <= 1.f)) continue;  // NaN fails both
        const float threshold = class_names[static_cast<std::size_t>(c)] == "person" ? params.person_score_threshold
                                                                                     : params.score_threshold;
        if (score < threshold) continue;
        const double w = row[2] * image.width, h = row[3] * image.height;
        Candidates& k = by_class[c];
        k.boxes.emplace_back(row[0] * image.width - w / 2, row[1] * image.height - h / 2, w, h);
        k.scores.push_back(score);
      }
    }
  }
  const cv::Rect2d frame(0, 0, image.width, image.height);
  std::vector<Detection> detections;
  for (const auto& [c, k] : by_class) {
    std::vector<int> keep;
    cv::dnn::NMSBoxes(k.boxes, k.scores, 0.f, params.nms_threshold, keep);
    std::stable_sort(keep.begin(), keep.end(), [&scores = k.scores](int a, int b) { return scores[a] > scores[b]; });
    for (int i : keep) {
      const cv::Rect2d box = k.boxes[static_cast<std::size_t>(i)] & frame;
      if (box.width <= 0 || box.height <= 0) continue;
      Detection d;
      d.class_id = c;
      d.class_name = class_names[static_cast<std::size_t>(c)];
      d.score = k.scores[static_cast<std::size_t>(i)];
      d.box = cv::Rect2f(static_cast<float>(box.x), static_cast<float>(box.y), static_cast<float>(box.width),
                         static_cast<float>(box.height));
      detections.push_back(std::move(d));
    }
  }
  return detections;
}

}  // namespace sgslam
