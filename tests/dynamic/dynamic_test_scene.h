// Synthetic two-view data for the dynamic module's tests: consecutive frames of the
// synth presets (exact poses, dynamic masks, ground-truth boxes), ORB keypoints of
// the current frame, their truth labels, and precision/recall of a rejection.
#pragma once

#include <cstdio>
#include <map>
#include <memory>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "sgslam/dynamic/algorithm1.h"
#include "sgslam/dynamic/refinements.h"
#include "sgslam/synth/sequence.h"

namespace sgslam::dynamic::test {

struct FramePair {
  cv::Mat prev_gray, cur_gray;        // CV_8U
  cv::Mat prev_depth, cur_depth;      // CV_32F, m
  cv::Mat cur_dynamic;                // CV_8U, 255 on moving objects
  std::vector<Detection> detections;  // ground-truth boxes of the current frame
  SE3 T_cur_prev;
  Pinhole K;
};

inline const synth::SynthSequence& Sequence(const std::string& preset) {
  static std::map<std::string, std::unique_ptr<synth::SynthSequence>> sequences;
  auto& seq = sequences[preset];
  if (!seq) seq = std::make_unique<synth::SynthSequence>(preset, 1u, 300);
  return *seq;
}

// Frames are rendered once per (preset, index) and shared by the tests of a binary.
inline const synth::RenderedFrame& Frame(const std::string& preset, int i) {
  static std::map<std::pair<std::string, int>, synth::RenderedFrame> frames;
  auto it = frames.find({preset, i});
  if (it == frames.end()) it = frames.emplace(std::pair{preset, i}, Sequence(preset).Render(i)).first;
  return it->second;
}

// Frames i (previous) and i + 1 (current) of the preset, seed 1.
inline FramePair MakePair(const std::string& preset, int i) {
  const synth::RenderedFrame& a = Frame(preset, i);
  const synth::RenderedFrame& b = Frame(preset, i + 1);
  const synth::SynthSequence* seq = &Sequence(preset);
  FramePair p;
  cv::cvtColor(a.bgr, p.prev_gray, cv::COLOR_BGR2GRAY);
  cv::cvtColor(b.bgr, p.cur_gray, cv::COLOR_BGR2GRAY);
  p.prev_depth = a.depth;
  p.cur_depth = b.depth;
  p.cur_dynamic = b.dynamic_mask;
  p.detections = synth::GroundTruthDetections(b, seq->scene());
  p.T_cur_prev = b.T_w_c.Inverse() * a.T_w_c;
  const synth::Intrinsics& K = seq->intrinsics();
  p.K = {K.fx, K.fy, K.cx, K.cy};
  return p;
}

inline std::vector<cv::KeyPoint> DetectKeypoints(const cv::Mat& gray, int n = 1000) {
  std::vector<cv::KeyPoint> keys;
  cv::ORB::create(n)->detect(gray, keys);
  return keys;
}

inline double PersonWeight(const std::string& name) { return name == "person" ? 5.0 : 1.0; }

enum class Truth { kStatic, kDynamic, kAmbiguous };

// Dynamic when the mask is set at the keypoint's pixel, static when no mask pixel is
// within `radius` px; corners on a silhouette within the radius are ambiguous (their
// patch mixes both motions) and left out of the scores.
inline std::vector<Truth> Label(const std::vector<cv::KeyPoint>& keys, const cv::Mat& mask, int radius = 3) {
  std::vector<Truth> out;
  for (const cv::KeyPoint& k : keys) {
    const int x = cvRound(k.pt.x), y = cvRound(k.pt.y);
    const cv::Rect r =
        cv::Rect(x - radius, y - radius, 2 * radius + 1, 2 * radius + 1) & cv::Rect(0, 0, mask.cols, mask.rows);
    if (mask.at<uchar>(y, x))
      out.push_back(Truth::kDynamic);
    else
      out.push_back(cv::countNonZero(mask(r)) ? Truth::kAmbiguous : Truth::kStatic);
  }
  return out;
}

struct Score {
  int dynamic = 0, dynamic_rejected = 0, stat = 0, static_rejected = 0;
  double Recall() const { return dynamic ? double(dynamic_rejected) / dynamic : 1.0; }
  double StaticLoss() const { return stat ? double(static_rejected) / stat : 0.0; }
  double Precision() const {
    const int rejected = dynamic_rejected + static_rejected;
    return rejected ? double(dynamic_rejected) / rejected : 1.0;
  }
  void Add(const RejectionResult& r, const std::vector<Truth>& truth) {
    for (size_t i = 0; i < truth.size(); ++i) {
      const bool rejected = !r.keypoints[i].kept;
      if (truth[i] == Truth::kDynamic) ++dynamic, dynamic_rejected += rejected;
      if (truth[i] == Truth::kStatic) ++stat, static_rejected += rejected;
    }
  }
  void Print(const char* label) const {
    std::printf("%-34s dynamic %5d  recall %6.3f  precision %6.3f  static %5d  static lost %6.3f\n", label, dynamic,
                Recall(), Precision(), stat, StaticLoss());
  }
};

}  // namespace sgslam::dynamic::test
