// The ground-truth masks as files (issue #47): mask.txt and the masks it lists are
// regular files of bounded size, a PNG header claiming more pixels than any frame
// is refused before decoding, and every error names the file.
#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "sgslam/common/error.h"
#include "sgslam/eval/mask_score.h"
#include "support/reader_faults.h"
#include "support/test_support.h"

namespace sgslam::eval {
namespace {

namespace fs = std::filesystem;
using test::ExpectAll;
using test::RefusalOf;
using test::TempDir;

TEST(MaskFiles, AMaskListThatIsAFifoIsAnErrorNotAbsent) {
  const TempDir tmp;
  EXPECT_TRUE(MaskIndex(tmp.path()).empty());
  test::MakeFifo(tmp / "mask.txt");
  ExpectAll(RefusalOf<InputError>([&] { MaskIndex index(tmp.path()); }, 10, tmp / "mask.txt"), {"mask.txt", "FIFO"});
}

TEST(MaskFiles, AMaskThatIsAFifoOrClaimsTooManyPixelsIsNamed) {
  const TempDir tmp;
  fs::create_directory(tmp / "mask");
  test::WriteText(tmp / "mask.txt", "1.0 mask/a.png\n2.0 mask/b.png\n3.0 mask/c.png\n");
  test::MakeFifo(tmp / "mask" / "a.png");
  cv::imwrite((tmp / "mask" / "c.png").string(), cv::Mat(4, 4, CV_8UC1, cv::Scalar(255)));
  std::ifstream in(tmp / "mask" / "c.png", std::ios::binary);
  std::string png((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const char size[8] = {0, 0, '\xEA', '\x60', 0, 0, '\xEA', '\x60'};  // IHDR: 60000 x 60000
  png.replace(16, 8, size, 8);
  std::ofstream(tmp / "mask" / "b.png", std::ios::binary) << png;
  const MaskIndex index(tmp.path());
  ExpectAll(RefusalOf<InputError>([&] { index.Load(kNsPerSecond); }, 10, tmp / "mask" / "a.png"),
            {"cannot read dynamic mask", "a.png", "FIFO"});
  ExpectAll(RefusalOf<InputError>([&] { index.Load(2 * kNsPerSecond); }),
            {"cannot read dynamic mask", "b.png", "60000x60000"});
  EXPECT_EQ(index.Load(3 * kNsPerSecond)->rows, 4);
}

}  // namespace
}  // namespace sgslam::eval
