#include "sgslam/io/tum_dataset.h"

#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "sgslam/common/error.h"
#include "sgslam/io/frame_stream.h"
#include "sgslam/io/image_file.h"
#include "sgslam/io/text_file.h"
#include "support/test_support.h"
#include "support/tiny_dataset.h"

namespace sgslam {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

// Runs fn, expects an InputError whose message contains every one of `parts`.
template <class Fn>
void ExpectInputError(Fn fn, std::initializer_list<std::string> parts) {
  try {
    fn();
    ADD_FAILURE() << "no error thrown";
  } catch (const InputError& e) {
    for (const auto& p : parts) EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what() << " lacks " << p;
  }
}

std::vector<fs::path> Sorted(const fs::path& dir) {
  std::vector<fs::path> v(fs::directory_iterator(dir), fs::directory_iterator{});
  std::sort(v.begin(), v.end());
  return v;
}

TEST(TumDataset, AssociatesRgbAndDepthByTimestamp) {
  TempDir tmp;
  test::WriteTinyDataset(tmp.path(), 5);
  const TumDataset ds(tmp.path(), DatasetConfig{});
  ASSERT_EQ(ds.size(), 5u);
  EXPECT_FALSE(ds.associations_from_file());
  for (const auto& f : ds.frames()) EXPECT_EQ(f.t_depth - f.t_rgb, 5'000'000);
  const RgbdImages img = ds.Load(2, test::TinyCamera());
  EXPECT_EQ(img.bgr.type(), CV_8UC3);
  EXPECT_EQ(img.depth.type(), CV_16UC1);
  EXPECT_EQ(img.t, ds.frames()[2].t_rgb);
}

TEST(TumDataset, ErrorsNameTheCulprit) {
  TempDir tmp;
  ExpectInputError([&] { TumDataset(tmp / "nope", DatasetConfig{}); }, {"dataset folder not found", "nope"});
  ExpectInputError([&] { TumDataset(tmp.path(), DatasetConfig{}); }, {"rgb.txt"});

  test::WriteTinyDataset(tmp.path(), 3);
  test::WriteText(tmp / "depth.txt", "# depth\n1000.0 depth/a.png\nnot-a-time depth/b.png\n");
  ExpectInputError([&] { TumDataset(tmp.path(), DatasetConfig{}); }, {"depth.txt:3", "bad timestamp"});
  test::WriteText(tmp / "depth.txt", "1000.0 depth/a.png extra\n");
  ExpectInputError([&] { TumDataset(tmp.path(), DatasetConfig{}); }, {"depth.txt:1"});
  test::WriteText(tmp / "depth.txt", "# far from every RGB stamp\n5.0 depth/a.png\n");
  ExpectInputError([&] { TumDataset(tmp.path(), DatasetConfig{}); }, {"empty sequence", "no pair is within"});
  test::WriteText(tmp / "depth.txt", "");
  ExpectInputError([&] { TumDataset(tmp.path(), DatasetConfig{}); }, {"empty sequence"});
}

// Lists whose images all had one placeholder time paired every image with every
// other: 5000 frames took 13 s and 840 MB, 20000 would take gigabytes more.
TEST(TumDataset, ATimeListedTwiceNamesBothLines) {
  TempDir tmp;
  test::WriteTinyDataset(tmp.path(), 3);
  test::WriteText(tmp / "depth.txt", "# depth\n1000.0 depth/a.png\n2000.0 depth/b.png\n1000.000 depth/c.png\n");
  ExpectInputError([&] { TumDataset(tmp.path(), DatasetConfig{}); },
                   {"depth.txt:4", "timestamp 1000.000000 repeats that of line 2"});
}

TEST(TumDataset, BadImagesAreReportedByPath) {
  TempDir tmp;
  const CameraConfig cam = test::TinyCamera();
  test::WriteTinyDataset(tmp.path(), 4);
  const TumDataset ds(tmp.path(), DatasetConfig{});
  const auto rgb = Sorted(tmp / "rgb");
  const auto depth = Sorted(tmp / "depth");

  fs::remove(rgb[0]);
  ExpectInputError([&] { ds.Load(0, cam); }, {"image missing", rgb[0].filename().string(), "rgb.txt:2"});
  test::WriteText(rgb[1], "this is not a PNG");
  ExpectInputError([&] { ds.Load(1, cam); }, {"cannot read image", rgb[1].filename().string()});
  cv::imwrite(depth[2].string(), cv::Mat(48, 64, CV_8UC3, cv::Scalar(1, 2, 3)));
  ExpectInputError([&] { ds.Load(2, cam); }, {depth[2].filename().string(), "8-bit 3-channel", "16-bit single-channel"});
  cv::imwrite(depth[3].string(), cv::Mat(24, 32, CV_16UC1, cv::Scalar(10000)));
  ExpectInputError([&] { ds.Load(3, cam); }, {"sizes differ", depth[3].filename().string()});
}

TEST(TumDataset, ImageSizeMustMatchCamera) {
  TempDir tmp;
  test::WriteTinyDataset(tmp.path(), 1);
  CameraConfig cam = test::TinyCamera();
  cam.width = 640;
  cam.height = 480;
  const TumDataset ds(tmp.path(), DatasetConfig{});
  ExpectInputError([&] { ds.Load(0, cam); }, {"64x48", "camera.width", "640x480"});
}

TEST(TumDataset, WrongDepthScaleIsCaught) {
  TempDir tmp;
  test::WriteTinyDataset(tmp.path(), 1);  // raw depth 10000
  const TumDataset ds(tmp.path(), DatasetConfig{});
  CameraConfig cam = test::TinyCamera();
  const RgbdImages img = ds.Load(0, cam);
  EXPECT_EQ(CheckDepthScale(img, ds.frames()[0], cam, DatasetConfig{}), std::nullopt);  // 2 m
  cam.depth_factor = 50;  // 10000 / 50 = 200 m
  ExpectInputError([&] { CheckDepthScale(img, ds.frames()[0], cam, DatasetConfig{}); },
                   {"median depth of 200 m", "depth_factor", "max_median_depth"});
  cam.depth_factor = 50000;  // 0.2 m: the depth 5x too near, as millimetres read with 5000 are
  ExpectInputError([&] { CheckDepthScale(img, ds.frames()[0], cam, DatasetConfig{}); },
                   {"median depth of 0.2 m", "with camera.depth_factor = 5000 it would be 2 m", "min_median_depth"});
  cam.depth_factor = 25000;  // 0.4 m: possible, but unusual
  const auto warning = CheckDepthScale(img, ds.frames()[0], cam, DatasetConfig{});
  ASSERT_TRUE(warning);
  EXPECT_NE(warning->find("unusually near"), std::string::npos) << *warning;
  EXPECT_NE(warning->find("it would be 2 m"), std::string::npos) << *warning;
  DatasetConfig near;
  near.min_median_depth = 0.1;  // a user whose scene really is that near
  cam.depth_factor = 50000;
  EXPECT_TRUE(CheckDepthScale(img, ds.frames()[0], cam, near));
}

// Overwrites bytes [at, at + 4) with a big-endian number.
void PutBigEndian(std::vector<std::uint8_t>& b, std::size_t at, std::uint32_t v) {
  for (int i = 3; i >= 0; --i, v >>= 8) b[at + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(v & 0xFF);
}

void WriteBytes(const fs::path& p, const std::vector<std::uint8_t>& b) {
  std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

TEST(ImageFile, HeadersGiveTheSizeAndTellACutFile) {
  std::vector<std::uint8_t> png, jpg;
  cv::imencode(".png", cv::Mat(48, 64, CV_16UC1, cv::Scalar(7)), png);
  cv::imencode(".jpg", cv::Mat(48, 64, CV_8UC3, cv::Scalar(1, 2, 3)), jpg);
  for (const auto* bytes : {&png, &jpg}) {
    const auto h = ReadImageHeader(*bytes);
    ASSERT_TRUE(h);
    EXPECT_EQ(h->width, 64u);
    EXPECT_EQ(h->height, 48u);
    EXPECT_TRUE(h->complete) << h->format;
    const std::span<const std::uint8_t> cut(bytes->data(), bytes->size() * 2 / 3);
    ASSERT_TRUE(ReadImageHeader(cut));
    EXPECT_FALSE(ReadImageHeader(cut)->complete) << h->format;
  }
  for (auto* bytes : {&png, &jpg}) {  // a trailer after the end is no cut
    bytes->insert(bytes->end(), 100, 0xAB);
    EXPECT_TRUE(ReadImageHeader(*bytes)->complete);
  }
  png.resize(png.size() - 100 - 12);  // IEND gone
  EXPECT_FALSE(ReadImageHeader(png)->complete);
  const std::vector<std::uint8_t> text = {'P', '3', '\n'};
  EXPECT_FALSE(ReadImageHeader(text));
  EXPECT_FALSE(ReadImageHeader(std::span<const std::uint8_t>(png.data(), 12)));
}

TEST(TumDataset, BadHeadersAndCutFilesAreRefusedBeforeDecoding) {
  TempDir tmp;
  const CameraConfig cam = test::TinyCamera();
  test::WriteTinyDataset(tmp.path(), 3);
  const TumDataset ds(tmp.path(), DatasetConfig{});
  const auto rgb = Sorted(tmp / "rgb");
  const auto depth = Sorted(tmp / "depth");
  std::vector<std::uint8_t> png;
  cv::imencode(".png", cv::Mat(48, 64, CV_8UC3, cv::Scalar(1, 2, 3)), png);
  PutBigEndian(png, 16, 60000);  // IHDR width and height
  PutBigEndian(png, 20, 60000);
  WriteBytes(rgb[0], png);
  WriteBytes(depth[0], png);
  ExpectInputError([&] { ds.Load(0, cam); }, {rgb[0].filename().string(), "60000x60000", "camera.width"});

  std::vector<std::uint8_t> jpg;
  cv::imencode(".jpg", cv::Mat(48, 64, CV_8UC3, cv::Scalar(1, 2, 3)), jpg);
  jpg.resize(jpg.size() / 2);
  WriteBytes(rgb[1], jpg);  // a JPEG under a .png name: the bytes decide
  ExpectInputError([&] { ds.Load(1, cam); }, {rgb[1].filename().string(), "cut short", "JPEG"});

  std::vector<std::uint8_t> depth_png;
  cv::imencode(".png", cv::Mat(48, 64, CV_16UC1, cv::Scalar(10000)), depth_png);
  depth_png.resize(depth_png.size() - 20);
  WriteBytes(depth[2], depth_png);
  ExpectInputError([&] { ds.Load(2, cam); }, {depth[2].filename().string(), "cut short", "PNG"});

  WriteBytes(rgb[2], std::vector<std::uint8_t>(64 * 48 * 8 + (1u << 20) + 1, 0));
  ExpectInputError([&] { ds.Load(2, cam); }, {rgb[2].filename().string(), "bytes, more than"});
}

TEST(FrameStream, StreamsInOrderAndRethrowsAtTheBadFrame) {
  TempDir tmp;
  test::WriteTinyDataset(tmp.path(), 6);
  const TumDataset ds(tmp.path(), DatasetConfig{});
  {
    FrameStream stream(ds, test::TinyCamera(), 2);
    std::size_t n = 0;
    while (auto f = stream.Next()) EXPECT_EQ(f->index, n++);
    EXPECT_EQ(n, 6u);
    EXPECT_FALSE(stream.Next());
  }
  {
    FrameStream stream(ds, test::TinyCamera(), 2, 3);  // max_frames
    std::size_t n = 0;
    while (stream.Next()) ++n;
    EXPECT_EQ(n, 3u);
  }
  fs::remove(ds.frames()[4].rgb);
  FrameStream stream(ds, test::TinyCamera(), 2);
  for (int i = 0; i < 4; ++i) ASSERT_TRUE(stream.Next());
  EXPECT_THROW(stream.Next(), InputError);
  EXPECT_FALSE(stream.Next());
}

TEST(FrameStream, DestroyedEarlyWithoutDeadlock) {
  TempDir tmp;
  test::WriteTinyDataset(tmp.path(), 10);
  const TumDataset ds(tmp.path(), DatasetConfig{});
  FrameStream stream(ds, test::TinyCamera(), 1);
  ASSERT_TRUE(stream.Next());  // the reader is blocked on a full queue when we leave
}

TEST(TumDataset, RealSequenceAssociationMatchesTheShippedAssociations) {
  SGSLAM_REQUIRE_SHARED(dir, "data/tum_fr1_rpy");
  const TumDataset with_file(dir, DatasetConfig{});
  EXPECT_TRUE(with_file.associations_from_file());
  EXPECT_EQ(with_file.size(), 694u);
  // Same folder without associations.txt: our association of rgb.txt/depth.txt must
  // give the pairs of the shipped file, which TUM's associate.py produced.
  TempDir tmp;
  fs::create_directory_symlink(dir / "rgb", tmp / "rgb");
  fs::create_directory_symlink(dir / "depth", tmp / "depth");
  fs::copy_file(dir / "rgb.txt", tmp / "rgb.txt");
  fs::copy_file(dir / "depth.txt", tmp / "depth.txt");
  const TumDataset ours(tmp.path(), DatasetConfig{});
  ASSERT_EQ(ours.size(), with_file.size());
  for (std::size_t i = 0; i < ours.size(); ++i) {
    EXPECT_EQ(ours.frames()[i].t_rgb, with_file.frames()[i].t_rgb) << i;
    EXPECT_EQ(ours.frames()[i].t_depth, with_file.frames()[i].t_depth) << i;
  }
  const RgbdImages img = with_file.Load(0, CameraConfig{});
  EXPECT_EQ(img.bgr.cols, 640);
  EXPECT_NO_THROW(CheckDepthScale(img, with_file.frames()[0], CameraConfig{}, DatasetConfig{}));
}

}  // namespace
}  // namespace sgslam
