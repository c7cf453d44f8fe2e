// Two guards of the static map (semantic_config.h):
//  - semantic.filters.seen_moving: a cloud point that other keyframes masked as a
//    mover at its place, often enough (kSeenMovingRatio) against the times they saw
//    it unmasked, is dropped on export. Five keyframes of a wall at 4 m; a person at
//    2 m stands in keyframes 0-3 and the detector finds it in 0-2 only; a static
//    patch at 2 m is in every keyframe and a person box (a false detection) covers
//    it in keyframe 4 only.
//  - semantic.filters.image_border: the image border strip (kImageBorder) stays out
//    of the cloud.
// And the semantic thread's own keyframe detector (semantic.keyframe_model) on the
// same scene: the people it finds join the mask, its other classes do not; it runs
// again only once the view has changed (kModelViewDeg, kModelViewMetres).
// The other filters are off, so that each test sees its own alone.
#include <gtest/gtest.h>

#include <stdexcept>

#include "sgslam/camera/camera.h"
#include "semantic/semantic_scenes.h"
#include "semantic/stepped_keyframes.h"

namespace sgslam {
namespace {

const cv::Rect kPerson(100, 100, 60, 120);  // x ~ -0.9 m at 2 m
const cv::Rect kStill(450, 300, 60, 60);    // x ~ +0.6 m at 2 m

Detection PersonBox(const cv::Rect& r) {
  Detection d;
  d.class_name = "person";
  d.score = 0.9f;
  d.box = cv::Rect2f(r);
  return d;
}

Config BaseConfig() {
  Config config;
  config.camera = test::PinholeCamera();
  SemanticFilters& f = config.semantic.filters;
  f.see_through = false;
  f.free_space = false;
  f.box_window = false;
  f.view_support = false;
  f.image_border = false;
  f.seen_moving = false;
  return config;
}

struct Cloud {
  std::size_t wall = 0, person = 0, still = 0, dropped = 0;
  std::vector<Eigen::Vector3d> points;
};

// keyframe_detector: the semantic thread's own (semantic.keyframe_model), if any;
// options: the export filters' parameters.
Cloud BuildCloud(const Config& config, std::unique_ptr<Detector> keyframe_detector = nullptr,
                 const SemanticMapOptions& options = {}, int model_level = 0) {
  std::vector<cv::Mat> depths;
  std::vector<std::vector<Detection>> boxes(5);
  for (int k = 0; k < 5; ++k) {
    cv::Mat depth(480, 640, CV_16UC1, cv::Scalar(4 * 5000));
    depth(kStill).setTo(2 * 5000);
    if (k <= 3) depth(kPerson).setTo(2 * 5000);
    if (k <= 2) boxes[k].push_back(PersonBox(kPerson));  // keyframe 3: the detector misses it
    if (k == 4) boxes[k].push_back(PersonBox(kStill));   // a false detection on the static patch
    depths.push_back(depth);
  }
  const test::SteppedCloud cloud =
      test::ExportSteppedKeyframes(config, depths, boxes, std::move(keyframe_detector), options, model_level);
  Cloud c;
  c.points = cloud.points;
  for (const Eigen::Vector3d& p : c.points) {
    if (p.z() > 3.5) ++c.wall;
    else if (p.x() < 0) ++c.person;
    else ++c.still;
  }
  c.dropped = cloud.seen_moving;
  return c;
}

TEST(SeenMoving, AMoverTheDetectorMissedInOneKeyframeLeavesTheCloud) {
  const Cloud off = BuildCloud(BaseConfig());
  EXPECT_GT(off.person, 50u);  // keyframe 3's view of the person
  EXPECT_GT(off.still, 50u);
  EXPECT_EQ(off.dropped, 0u);

  Config config = BaseConfig();
  config.semantic.filters.seen_moving = true;
  ASSERT_EQ(SemanticMapOptions().seen_moving_ratio, 3.0);  // the pipeline's kSeenMovingRatio
  const Cloud on = BuildCloud(config);
  // Keyframes 0-2 masked a mover at the place keyframe 3 put the person: 3 >= 3 x 1.
  EXPECT_EQ(on.person, 0u);
  EXPECT_GT(on.dropped, 0u);
  // The static patch: masked once (keyframe 4), seen unmasked by all five: it stays.
  EXPECT_EQ(on.still, off.still);
  // The wall behind the person's box is background, not the mover's depth layer.
  EXPECT_EQ(on.wall, off.wall);

  // A ratio the evidence does not reach keeps the person.
  SemanticMapOptions four;
  four.seen_moving_ratio = 4;
  EXPECT_EQ(BuildCloud(config, nullptr, four).person, off.person);
}

// The semantic thread's own detector on keyframes (semantic.keyframe_model): a
// stand-in that finds the person wherever tracking's detector did or did not, and
// calls the static patch a chair, or that throws.
class KeyframeDetector final : public Detector {
 public:
  explicit KeyframeDetector(bool fail, int* calls = nullptr) : fail_(fail), calls_(calls) {}
  std::vector<Detection> Detect(const cv::Mat& bgr, Timestamp) override {
    if (calls_) ++*calls_;
    if (fail_) throw std::runtime_error("broken network");
    EXPECT_EQ(bgr.type(), CV_8UC3);
    Detection chair = PersonBox(kStill);
    chair.class_name = "chair";  // w = 2: not a moving object, so not masked
    return {PersonBox(kPerson), chair};
  }
  std::string Describe() const override { return "stand-in"; }

 private:
  bool fail_;
  int* calls_;
};

// The keyframe model on every keyframe, whatever the view.
SemanticMapOptions EveryKeyFrame() {
  SemanticMapOptions o;
  o.model_view_deg = o.model_view_metres = 0;
  return o;
}

TEST(KeyframeDetector, ThePeopleItFindsLeaveTheCloudItsOtherClassesStay) {
  const Cloud off = BuildCloud(BaseConfig(), nullptr);
  EXPECT_GT(off.person, 50u);  // keyframe 3's view of the person
  const Cloud on = BuildCloud(BaseConfig(), std::make_unique<KeyframeDetector>(false), EveryKeyFrame());
  EXPECT_EQ(on.person, 0u);
  EXPECT_EQ(on.still, off.still);  // its chair is no mover
  EXPECT_GT(on.still, 50u);
  // Its box masks the wall behind it too (boxes are masked whole), and only there.
  EXPECT_LE(on.wall, off.wall);
  EXPECT_GT(on.wall, off.wall * 95 / 100);
}

TEST(KeyframeDetector, RunsAgainOnlyOnANewView) {
  // The five keyframes step 5 mm sideways: one view for the 0.10 m gate.
  int calls = 0;
  const Cloud gated = BuildCloud(BaseConfig(), std::make_unique<KeyframeDetector>(false, &calls));
  EXPECT_EQ(calls, 1);
  EXPECT_GT(gated.person, 50u);  // keyframe 3's person: only tracking's boxes there, which missed it
  calls = 0;
  BuildCloud(BaseConfig(), std::make_unique<KeyframeDetector>(false, &calls), EveryKeyFrame());
  EXPECT_EQ(calls, 5);
  // A gate of 1 cm: keyframes 0, 2 and 4 (10 mm from the last the model ran on).
  SemanticMapOptions centimetre;
  centimetre.model_view_metres = 0.0099;
  calls = 0;
  BuildCloud(BaseConfig(), std::make_unique<KeyframeDetector>(false, &calls), centimetre);
  EXPECT_EQ(calls, 3);
  // The CPU budget's level 1 doubles the gate: keyframes 0 and 4.
  calls = 0;
  BuildCloud(BaseConfig(), std::make_unique<KeyframeDetector>(false, &calls), centimetre, 1);
  EXPECT_EQ(calls, 2);
}

TEST(KeyframeDetector, AFailingOneLeavesTrackingsBoxesAtWork) {
  const Cloud off = BuildCloud(BaseConfig(), nullptr);
  const Cloud failing = BuildCloud(BaseConfig(), std::make_unique<KeyframeDetector>(true));
  EXPECT_EQ(failing.person, off.person);
  EXPECT_EQ(failing.still, off.still);
  EXPECT_EQ(failing.wall, off.wall);
}

TEST(CloudBorder, TheBorderStripStaysOutOfTheCloud) {
  Config config = BaseConfig();
  const Cloud off = BuildCloud(config);
  config.semantic.filters.image_border = true;
  const Cloud on = BuildCloud(config);
  EXPECT_LT(on.wall, off.wall);
  EXPECT_GT(on.wall, off.wall / 2);
  const Camera camera(config.camera);
  // The first keyframe is at the origin; the others are at most 2 cm off, 2 px at 4 m.
  const int strip = kImageBorder - 2;
  int outside = 0;
  for (const Eigen::Vector3d& p : on.points) {
    const Eigen::Vector2d uv = camera.Project(p);
    outside += uv.x() < strip || uv.y() < strip || uv.x() > 640 - strip || uv.y() > 480 - strip;
  }
  EXPECT_EQ(outside, 0);
}

}  // namespace
}  // namespace sgslam
