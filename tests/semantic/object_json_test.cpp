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
  chair.exported = true;
  ObjectEstimate hidden = chair;
  hidden.exported = false;  // not written
  const std::vector<ObjectEstimate> back = ObjectsFromJson(ObjectsJson({chair, hidden}));
  ASSERT_EQ(back.size(), 1u);
  const ObjectEstimate& o = back[0];
  EXPECT_EQ(o.id, 7);
  EXPECT_EQ(o.class_id, 56);
  EXPECT_EQ(o.class_name, "chair");
  EXPECT_DOUBLE_EQ(o.confidence, 0.83);
  EXPECT_EQ(o.observations, 5);
  EXPECT_FALSE(o.complete);
  EXPECT_EQ(o.centroid, chair.centroid);
  EXPECT_EQ(o.size, chair.size);
  EXPECT_TRUE(o.exported);
}

}  // namespace
}  // namespace sgslam
