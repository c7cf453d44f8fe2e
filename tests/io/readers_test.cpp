// The io readers on files of the wrong kind and headers that lie (issue #47): a
// FIFO, a folder or a device is refused without blocking, a size or count that
// the file cannot hold is refused before anything is allocated, and every error
// names the file.
#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "sgslam/common/error.h"
#include "sgslam/io/image_file.h"
#include "sgslam/io/ply.h"
#include "sgslam/io/text_file.h"
#include "sgslam/io/trajectory.h"
#include "sgslam/io/tum_dataset.h"
#include "support/reader_faults.h"
#include "support/test_support.h"
#include "support/tiny_dataset.h"

namespace sgslam {
namespace {

namespace fs = std::filesystem;
using test::ExpectAll;
using test::RefusalOf;
using test::TempDir;

TEST(TextFileReader, RefusesAFifoAFolderAndADevice) {
  const TempDir tmp;
  test::MakeFifo(tmp / "rgb.txt");
  const auto noop = [](int, const std::vector<std::string_view>&) {};
  ExpectAll(RefusalOf<InputError>([&] { ForEachDataLine(tmp / "rgb.txt", noop); }, 10, tmp / "rgb.txt"),
            {"rgb.txt", "FIFO"});
  fs::create_directory(tmp / "depth.txt");
  ExpectAll(RefusalOf<InputError>([&] { ForEachDataLine(tmp / "depth.txt", noop); }), {"depth.txt", "folder"});
  ExpectAll(RefusalOf<InputError>([&] { ReadTumTrajectory("/dev/zero"); }), {"/dev/zero", "device"});
}

TEST(TextFileReader, BoundsTheFileAndTheLine) {
  const TempDir tmp;
  test::MakeSparse(tmp / "groundtruth.txt", 3ull << 29);  // 1.5 GiB
  ExpectAll(RefusalOf<InputError>([&] { ReadTumTrajectory(tmp / "groundtruth.txt"); }),
            {"groundtruth.txt", "1610612736 bytes", "more than"});
  // A line of 100 KB: no list's, refused when it passes the bound, naming its line.
  test::WriteText(tmp / "long.txt", "1 2 3 4 5 6 7 1\n" + std::string(100000, '7') + "\n");
  ExpectAll(RefusalOf<ParseError>([&] { ReadTumTrajectory(tmp / "long.txt"); }), {"long.txt:2", "longer than"});
}

TEST(PlyReader, AHeaderClaimingMorePointsThanTheFileHoldsIsRefusedBeforeAllocating) {
  const TempDir tmp;
  const std::string header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 150000000\nproperty float x\nproperty float y\n"
      "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
  test::WriteText(tmp / "cloud.ply", header + std::string(60, '\0'));
  ExpectAll(RefusalOf<InputError>([&] { ReadPlyPoints(tmp / "cloud.ply"); }),
            {"PLY file", "cloud.ply", "claims 150000000 points", "holds 60 bytes"});
  // A count beyond 64 bits, and one that fits but leaves bytes over.
  std::string huge = header;
  huge.replace(huge.find("150000000"), 9, "99999999999999999999999");
  test::WriteText(tmp / "huge.ply", huge);
  ExpectAll(RefusalOf<InputError>([&] { ReadPlyPoints(tmp / "huge.ply"); }), {"huge.ply", "bad vertex count"});
  std::string padded = header;
  padded.replace(padded.find("150000000"), 9, "2");
  test::WriteText(tmp / "padded.ply", padded + std::string(31, '\0'));
  ExpectAll(RefusalOf<InputError>([&] { ReadPlyPoints(tmp / "padded.ply"); }), {"padded.ply", "2 points (30 bytes)", "holds 31 bytes"});
}

TEST(PlyReader, RefusesOtherLayoutsAndFilesOfTheWrongKind) {
  const TempDir tmp;
  test::WriteText(tmp / "faces.ply",
             "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
             "property float z\nelement face 5\nproperty list uchar int vertex_indices\nend_header\n");
  ExpectAll(RefusalOf<InputError>([&] { ReadPlyPoints(tmp / "faces.ply"); }), {"faces.ply", "unsupported PLY layout"});
  test::MakeFifo(tmp / "pipe.ply");
  ExpectAll(RefusalOf<InputError>([&] { ReadPlyPoints(tmp / "pipe.ply"); }, 10, tmp / "pipe.ply"),
            {"pipe.ply", "FIFO"});
  WritePly(tmp / "ok.ply", {{1, 2, 3}, {4, 5, 6}});
  EXPECT_EQ(ReadPlyPoints(tmp / "ok.ply").size(), 2u);
}

TEST(ImageReader, RefusesAFifoAndAHeaderClaimingTooManyPixels) {
  const TempDir tmp;
  test::MakeFifo(tmp / "m.png");
  ExpectAll(RefusalOf<InputError>([&] { ReadFileBytes(tmp / "m.png", 1 << 20); }, 10, tmp / "m.png"),
            {"image", "m.png", "FIFO"});
  cv::imwrite((tmp / "small.png").string(), cv::Mat(4, 4, CV_8UC1, cv::Scalar(7)));
  std::ifstream in(tmp / "small.png", std::ios::binary);
  std::string png((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const char size[8] = {0, 0, '\xEA', '\x60', 0, 0, '\xEA', '\x60'};  // IHDR: 60000 x 60000
  png.replace(16, 8, size, 8);
  test::WriteText(tmp / "big.png", png);
  ExpectAll(RefusalOf<InputError>([&] { ReadImageFile(tmp / "big.png", "mask", cv::IMREAD_GRAYSCALE, 1 << 20, 1 << 26); }),
            {"mask", "big.png", "60000x60000"});
  EXPECT_EQ(ReadImageFile(tmp / "small.png", "mask", cv::IMREAD_GRAYSCALE, 1 << 20, 1 << 26).rows, 4);
}

TEST(TumDatasetReader, AnEntryThatIsNotARegularFileIsAnErrorNotAbsent) {
  const TempDir tmp;
  for (const char* name : {"associations.txt", "groundtruth.txt", "rgb.txt"}) {
    const fs::path seq = tmp / name;
    test::WriteTinyDataset(seq, 2);
    fs::remove(seq / name);
    test::MakeFifo(seq / name);
    ExpectAll(RefusalOf<InputError>([&] { TumDataset(seq, DatasetConfig{}); }, 10, seq / name),
              {(seq / name).string(), "FIFO"});
  }
  const fs::path seq = tmp / "folder";
  test::WriteTinyDataset(seq, 2);
  fs::create_directory(seq / "groundtruth.txt");
  ExpectAll(RefusalOf<InputError>([&] { TumDataset(seq, DatasetConfig{}); }), {"groundtruth.txt", "folder"});
}

TEST(TumDatasetReader, AnImageThatIsAFifoIsNamedWithItsList) {
  const TempDir tmp;
  test::WriteTinyDataset(tmp.path(), 2);
  const TumDataset ds(tmp.path(), DatasetConfig{});
  const fs::path rgb = ds.frames()[1].rgb;
  fs::remove(rgb);
  test::MakeFifo(rgb);
  ExpectAll(RefusalOf<InputError>([&] { ds.Load(1, test::TinyCamera()); }, 10, rgb),
            {rgb.string(), "FIFO", "rgb.txt:3"});
}

}  // namespace
}  // namespace sgslam
