#include "sgslam/detection/people_scale.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

namespace sgslam {
namespace {

// A wall 4 m away (TUM's 5000 units per metre) with a person 2 m away in front of
// it, 300 px tall: 300 * 2 / fy metres.
struct Scene {
  CameraConfig camera;
  cv::Mat depth{480, 640, CV_16UC1, cv::Scalar(20000)};
  Detection person;
  Scene() {
    cv::rectangle(depth, cv::Rect(300, 100, 40, 300), cv::Scalar(10000), cv::FILLED);
    person.class_id = 0;
    person.class_name = "person";
    person.score = 0.9f;
    person.box = cv::Rect2f(290, 100, 60, 300);  // wider than the person: the wall shows at its sides
  }
};

TEST(PersonHeight, IsTheBoxHeightAtThePersonsDepth) {
  const Scene s;
  const auto h = PersonHeight(s.depth, s.person, s.camera);
  ASSERT_TRUE(h);
  EXPECT_NEAR(*h, 300 * 2.0 / s.camera.fy, 1e-9);
}

TEST(PersonHeight, NothingForBoxesThatDoNotMeasureAWholePerson) {
  Scene s;
  Detection cut = s.person;
  cut.box.y = 0;  // the head may be above the image
  EXPECT_FALSE(PersonHeight(s.depth, cut, s.camera));
  Detection carried = s.person;
  carried.carried = 2;
  EXPECT_FALSE(PersonHeight(s.depth, carried, s.camera));
  Detection chair = s.person;
  chair.class_name = "chair";
  EXPECT_FALSE(PersonHeight(s.depth, chair, s.camera));
  s.depth.setTo(0);  // no depth
  EXPECT_FALSE(PersonHeight(s.depth, s.person, s.camera));
}

TEST(PeopleScaleCheck, QuietForPeopleOfAPlausibleSize) {
  const Scene s;
  PeopleScaleCheck check;
  for (int i = 0; i < PeopleScaleCheck::kPeopleNeeded + 5; ++i) EXPECT_FALSE(check.Add(s.depth, {s.person}, s.camera));
  EXPECT_EQ(check.measured(), PeopleScaleCheck::kPeopleNeeded);  // stops measuring once judged
  EXPECT_NEAR(*check.median_height(), 1.16, 0.01);
}

TEST(PeopleScaleCheck, WarnsWhenTheDepthFactorMakesPeopleGiants) {
  Scene s;
  s.camera.depth_factor = 1000;  // 5000-scaled depth read 5x too far: 5.8 m tall
  PeopleScaleCheck check;
  std::optional<std::string> warning;
  for (int i = 0; i < PeopleScaleCheck::kPeopleNeeded && !warning; ++i) warning = check.Add(s.depth, {s.person}, s.camera);
  ASSERT_TRUE(warning);
  EXPECT_NE(warning->find("the shortest of the 15 people"), std::string::npos) << *warning;
  EXPECT_NE(warning->find("with camera.depth_factor = 5000 it would be 1.16 m"), std::string::npos) << *warning;
}

TEST(PeopleScaleCheck, WarnsOnceWhenTheDepthFactorMakesPeopleTiny) {
  Scene s;
  s.camera.depth_factor = 25000;  // depth read 5x too near
  PeopleScaleCheck check;
  std::vector<std::string> warnings;
  for (int i = 0; i < 2 * PeopleScaleCheck::kPeopleNeeded; ++i) {
    if (auto w = check.Add(s.depth, {s.person}, s.camera)) warnings.push_back(*w);
  }
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("the tallest of the 15 people measured in the first frames is 0.23 m"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("with camera.depth_factor = 5000 it would be 1.16 m"), std::string::npos)
      << warnings[0];
}

}  // namespace
}  // namespace sgslam
