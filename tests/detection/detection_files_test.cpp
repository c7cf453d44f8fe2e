// The detection module's readers on files of the wrong kind (issue #47): a
// detections file, a model's cfg, weights, class names and SHA256SUMS that are
// FIFOs or folders are refused at once, naming the file.
#include <gtest/gtest.h>

#include <filesystem>

#include "sgslam/common/error.h"
#include "sgslam/common/sha256.h"
#include "sgslam/detection/darknet_model.h"
#include "sgslam/detection/detections_file.h"
#include "support/reader_faults.h"
#include "support/test_support.h"

namespace sgslam {
namespace {

namespace fs = std::filesystem;
using test::ExpectAll;
using test::RefusalOf;
using test::TempDir;

TEST(DetectionFiles, ADetectionsFileThatIsAFifoOrHasALongLineIsRefused) {
  const TempDir tmp;
  test::MakeFifo(tmp / "detections.txt");
  ExpectAll(RefusalOf<InputError>([&] { ReadDetectionsFile(tmp / "detections.txt"); }, 10, tmp / "detections.txt"),
            {"detections file", "detections.txt", "FIFO"});
  test::WriteText(tmp / "long.txt", "1.0 0 0.5 1 1 2 2 " + std::string(70000, 'x') + "\n");
  ExpectAll(RefusalOf<InputError>([&] { ReadDetectionsFile(tmp / "long.txt"); }), {"long.txt:1", "longer than"});
  ExpectAll(RefusalOf<InputError>([&] { ReadDetectionsFile(tmp / "none.txt"); }),
            {"detections file not found", "none.txt"});
}

// A model folder whose files are all there, one of them replaced by a FIFO.
void ExpectModelFileRefused(const fs::path& dir, const std::string& name) {
  fs::create_directories(dir);
  test::WriteText(dir / "m.cfg", "[net]\n[yolo]\nclasses=1\n");
  test::WriteText(dir / "m.weights", std::string(16, '\0'));
  test::WriteText(dir / "coco.names", "person\n");
  fs::remove(dir / name);
  test::MakeFifo(dir / name);
  ExpectAll(RefusalOf<InputError>([&] { LoadDarknetModel(dir, "m", 0.1f); }, 10, dir / name),
            {(dir / name).string(), "FIFO"});
}

TEST(DetectionFiles, AModelFileThatIsAFifoIsRefused) {
  const TempDir tmp;
  for (const char* name : {"m.cfg", "m.weights", "coco.names", "SHA256SUMS"}) ExpectModelFileRefused(tmp / name, name);
  // Present, though not a file: refused by the loader, not taken for a model not installed.
  EXPECT_TRUE(DarknetModelPresent(tmp / "m.cfg", "m"));
  EXPECT_FALSE(DarknetModelPresent(tmp / "m.cfg", "other"));
}

TEST(DetectionFiles, AChecksumListIsBounded) {
  const TempDir tmp;
  test::MakeSparse(tmp / "SHA256SUMS", 1ull << 30);
  ExpectAll(RefusalOf<InputError>([&] { ReadSha256Sums(tmp / "SHA256SUMS"); }),
            {"checksum list", "SHA256SUMS", "1073741824 bytes"});
  test::WriteText(tmp / "ok", std::string(64, 'a') + "  m.cfg\r\n# comment\n");
  EXPECT_EQ(ReadSha256Sums(tmp / "ok").at("m.cfg"), std::string(64, 'a'));
}

}  // namespace
}  // namespace sgslam
