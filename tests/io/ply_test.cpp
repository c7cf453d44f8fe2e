#include "sgslam/io/ply.h"

#include <gtest/gtest.h>

#include <fstream>

#include "sgslam/common/error.h"
#include "support/test_support.h"

namespace sgslam {
namespace {

TEST(Ply, RoundTripsPointsAndColours) {
  test::TempDir tmp;
  const std::vector<Eigen::Vector3d> pts = {{1.5, -2.25, 3.0}, {0, 0, 0}, {1e3, 2e-3, -7}};
  const std::vector<Rgb> rgb = {Rgb{1, 2, 3}, Rgb{255, 0, 128}, Rgb{9, 9, 9}};
  WritePly(tmp / "c.ply", pts, rgb);
  std::vector<Rgb> back_rgb;
  const auto back = ReadPlyPoints(tmp / "c.ply", &back_rgb);
  ASSERT_EQ(back.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_LT((back[i] - pts[i]).norm(), 1e-4 * std::max(1.0, pts[i].norm()));
    EXPECT_EQ(back_rgb[i], rgb[i]);
  }
  WritePly(tmp / "p.ply", pts);
  EXPECT_EQ(ReadPlyPoints(tmp / "p.ply").size(), 3u);
  std::ifstream head(tmp / "p.ply");
  std::string first;
  std::getline(head, first);
  EXPECT_EQ(first, "ply");
}

TEST(Ply, MismatchedColoursAndBadFilesAreErrors) {
  test::TempDir tmp;
  EXPECT_THROW(WritePly(tmp / "x.ply", {{0, 0, 0}}, {Rgb{}, Rgb{}}), Error);
  test::WriteText(tmp / "bad.ply", "ply\nformat ascii 1.0\nend_header\n");
  EXPECT_THROW(ReadPlyPoints(tmp / "bad.ply"), InputError);
  EXPECT_THROW(ReadPlyPoints(tmp / "none.ply"), InputError);
}

}  // namespace
}  // namespace sgslam
