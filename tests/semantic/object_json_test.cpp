#include "sgslam/semantic/object_json.h"

#include <gtest/gtest.h>

namespace sgslam {
namespace {

TEST(ObjectJson, ReadsBackWhatItWrites) {
  ObjectEstimate chair;
  chair.id = 7;
  chair.class_id = 56;
  chair.class_name = "chair";
  chair.confidence = 0.83;
  chair.observations = 5;
  chair.complete = false;
  chair.centroid = {0.5, -0.25, 1.75};
  chair.size = {0.4, 0.9, 0.45};
  chair.dimensions = {0.9, 0.45, 0.4};
  chair.class_share = 0.75;
  chair.views_expected = 9;
  chair.views_seen = 5;
  chair.spread_deg = 21.5;
  chair.points = 1200;
  chair.confirmed = chair.plausible = chair.exported = true;
  ObjectEstimate hidden = chair;
  hidden.confirmed = hidden.exported = false;  // a candidate: not in the objects' list
  const std::vector<ObjectEstimate> back = ObjectsFromJson(ObjectsJson({chair, hidden}));
  ASSERT_EQ(back.size(), 1u);
  const std::vector<ObjectEstimate> candidates = ObjectsFromJson(ObjectsJson({chair, hidden}, true));
  ASSERT_EQ(candidates.size(), 1u);
  EXPECT_FALSE(candidates[0].confirmed);
  EXPECT_FALSE(candidates[0].exported);
  const ObjectEstimate& o = back[0];
  EXPECT_EQ(o.id, 7);
  EXPECT_EQ(o.class_id, 56);
  EXPECT_EQ(o.class_name, "chair");
  EXPECT_DOUBLE_EQ(o.confidence, 0.83);
  EXPECT_EQ(o.observations, 5);
  EXPECT_FALSE(o.complete);
  EXPECT_EQ(o.centroid, chair.centroid);
  EXPECT_EQ(o.size, chair.size);
  EXPECT_EQ(o.dimensions, chair.dimensions);
  EXPECT_DOUBLE_EQ(o.class_share, 0.75);
  EXPECT_EQ(o.views_expected, 9);
  EXPECT_EQ(o.views_seen, 5);
  EXPECT_DOUBLE_EQ(o.spread_deg, 21.5);
  EXPECT_EQ(o.points, 1200);
  EXPECT_TRUE(o.exported);
}

}  // namespace
}  // namespace sgslam
