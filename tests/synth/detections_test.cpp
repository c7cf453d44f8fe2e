#include <gtest/gtest.h>

#include <map>
#include <set>

#include "sgslam/detection/detections_file.h"
#include "sgslam/synth/shapes.h"
#include "sgslam/synth/sequence.h"
#include "support/test_support.h"

namespace sgslam::synth {
namespace {

// Every detection is the tight box of its object's visible pixels; objects with at
// least kMinDetectionPixels visible pixels have exactly one.
void ExpectDetectionsMatchIds(const SynthSequence& seq, const RenderedFrame& f, const std::vector<Detection>& dets) {
  std::map<int, int> pixels;
  std::map<int, cv::Rect> boxes;
  for (int v = 0; v < f.object_id.rows; ++v) {
    for (int u = 0; u < f.object_id.cols; ++u) {
      const int id = f.object_id.at<int>(v, u);
      if (id == 0) continue;
      boxes[id] = pixels[id]++ == 0 ? cv::Rect(u, v, 1, 1) : (boxes[id] | cv::Rect(u, v, 1, 1));
    }
  }
  std::size_t expected = 0;
  for (const auto& [id, count] : pixels) expected += count >= kMinDetectionPixels;
  ASSERT_EQ(dets.size(), expected) << "frame " << f.index;
  for (const Detection& d : dets) {
    // Find the object this detection is for: its box must hold all of its pixels.
    bool matched = false;
    for (const auto& [id, box] : boxes) {
      const ObjectInfo& info = seq.objects().at(id - 1).info;
      if (pixels[id] < kMinDetectionPixels || d.class_id != info.class_id) continue;
      const cv::Rect2f b(box);
      if (d.box != b) continue;
      matched = true;
      EXPECT_EQ(d.class_name, info.class_name);
      EXPECT_EQ(d.score, 1.f);
      // Every pixel of the object lies inside the box (and the box is tight by construction).
      EXPECT_EQ(cv::countNonZero(f.object_id(box) == id), pixels[id]) << "pixels outside the box";
    }
    EXPECT_TRUE(matched) << d.class_name << " " << d.box;
  }
}

TEST(SynthDetections, BoxesHoldTheVisiblePixelsAndClassesAreCoco) {
  EXPECT_EQ(CocoId("person"), 0);
  EXPECT_EQ(CocoId("bottle"), 39);
  EXPECT_EQ(CocoId("chair"), 56);
  EXPECT_EQ(CocoId("sofa"), 57);
  EXPECT_EQ(CocoId("pottedplant"), 58);
  EXPECT_EQ(CocoId("diningtable"), 60);
  EXPECT_EQ(CocoId("tvmonitor"), 62);
  for (const char* preset : {"walkers", "objects"}) {
    const SynthSequence seq(preset, 1, 120);
    int detections = 0;
    for (int i = 0; i < seq.size(); i += 17) {
      const RenderedFrame f = seq.Render(i);
      const auto dets = GroundTruthDetections(f, seq.scene());
      ExpectDetectionsMatchIds(seq, f, dets);
      detections += static_cast<int>(dets.size());
    }
    EXPECT_GE(detections, 5) << preset;
  }
}

TEST(SynthDetections, ObjectsPresetHasKnownBoxesSeenFromSeveralViews) {
  const SynthSequence seq("objects", 1, 300);
  std::set<std::string> classes;
  std::map<int, int> seen;
  for (const SceneObject& o : seq.objects()) {
    classes.insert(o.info.class_name);
    EXPECT_EQ(CocoId(o.info.class_name), o.info.class_id);
    Eigen::Vector3d min, max;
    Bounds(o.quads, min, max);
    EXPECT_LT((0.5 * (min + max) - o.info.centroid).norm(), 1e-9);
    EXPECT_LT((max - min - o.info.size).norm(), 1e-9);
    EXPECT_TRUE((min.array() >= -1e-9).all() && (max.array() <= seq.scene().room_size.array()).all());
  }
  EXPECT_GE(seq.objects().size(), 6u);
  EXPECT_TRUE(classes.count("chair") && classes.count("tvmonitor") && classes.count("pottedplant"));
  for (int i = 0; i < seq.size(); i += 10) {
    for (const Detection& d : GroundTruthDetections(seq.Render(i), seq.scene())) ++seen[d.class_id];
  }
  for (const auto& [class_id, views] : seen) {
    EXPECT_GE(views, class_id == CocoId("bottle") ? 1 : 3) << "class " << class_id;  // the small bottle may hide
  }
  EXPECT_EQ(seen.size(), classes.size());
}

TEST(SynthDetections, RoundTripThroughTheDetectionsFile) {
  const SynthSequence seq("walkers", 1, 30);
  std::vector<FrameDetections> frames;
  for (int i = 0; i < seq.size(); i += 5) frames.emplace_back(seq.timestamp(i), GroundTruthDetections(seq.Render(i), seq.scene()));
  test::TempDir dir;
  WriteDetectionsFile(dir / "detections.txt", frames);
  const auto read = ReadDetectionsFile(dir / "detections.txt");
  for (const auto& [t, dets] : frames) {
    if (dets.empty()) continue;
    ASSERT_EQ(read.count(t), 1u);
    ASSERT_EQ(read.at(t).size(), dets.size());
    for (std::size_t k = 0; k < dets.size(); ++k) {
      EXPECT_EQ(read.at(t)[k].class_name, dets[k].class_name);
      EXPECT_EQ(read.at(t)[k].class_id, dets[k].class_id);
      EXPECT_EQ(read.at(t)[k].box, dets[k].box);  // whole pixels survive exactly
    }
  }
}

}  // namespace
}  // namespace sgslam::synth
