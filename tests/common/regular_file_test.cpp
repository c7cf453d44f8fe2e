#include "sgslam/common/regular_file.h"

#include <gtest/gtest.h>

#include <vector>

#include "sgslam/common/error.h"
#include "support/reader_faults.h"
#include "support/test_support.h"

namespace sgslam {
namespace {

namespace fs = std::filesystem;
using test::ExpectAll;
using test::RefusalOf;
using test::TempDir;

TEST(RegularFile, ReadsARegularFile) {
  const TempDir tmp;
  test::WriteText(tmp / "a.txt", "hello\n");
  const RegularFile f(tmp / "a.txt", "list");
  EXPECT_EQ(f.size(), 6u);
  EXPECT_EQ(f.ReadAll(6), "hello\n");
  EXPECT_EQ(f.Read(1, 3), "ell");
  EXPECT_EQ(ReadRegularFile(tmp / "a.txt", "list", 100), "hello\n");
}

TEST(RegularFile, RefusesAFifoWithoutBlocking) {
  const TempDir tmp;
  test::MakeFifo(tmp / "pipe");
  ExpectAll(RefusalOf<InputError>([&] { RegularFile(tmp / "pipe", "vocabulary"); }, 10, tmp / "pipe"),
            {"vocabulary", (tmp / "pipe").string(), "FIFO"});
  ExpectAll(RefusalOf<InputError>([&] { ReadRegularFile(tmp / "pipe", "config file", 100); }, 10, tmp / "pipe"),
            {"config file", "pipe", "FIFO"});
}

TEST(RegularFile, RefusesADevice) {
  ExpectAll(RefusalOf<InputError>([] { ReadRegularFile("/dev/zero", "map file", 1 << 20); }),
            {"map file /dev/zero", "device"});
}

TEST(RegularFile, RefusesAFolder) {
  const TempDir tmp;
  fs::create_directory(tmp / "d.yaml");
  ExpectAll(RefusalOf<InputError>([&] { RegularFile(tmp / "d.yaml", "config file"); }),
            {"config file", "d.yaml", "is a folder"});
}

TEST(RegularFile, NamesAMissingFileAndABrokenLink) {
  const TempDir tmp;
  ExpectAll(RefusalOf<InputError>([&] { RegularFile(tmp / "nope.txt", "detections file"); }),
            {"detections file not found: ", (tmp / "nope.txt").string()});
  fs::create_symlink(tmp / "gone", tmp / "link");
  ExpectAll(RefusalOf<InputError>([&] { RegularFile(tmp / "link", "list"); }), {"link", "broken symbolic link"});
}

TEST(RegularFile, RefusesBeyondTheBoundBeforeReading) {
  const TempDir tmp;
  test::MakeSparse(tmp / "big", 3ull << 30);  // 3 GiB of hole: reading it would take seconds and the memory
  ExpectAll(RefusalOf<InputError>([&] { ReadRegularFile(tmp / "big", "map file", 1 << 20); }),
            {"map file", "big", "3221225472 bytes", "more than the 1048576"});
  ExpectAll(RefusalOf<InputError>([&] {
              RegularFile(tmp / "big", "list").ForEachLine(1 << 20, 100, [](int, std::string_view) {});
            }),
            {"3221225472 bytes"});
}

TEST(RegularFile, AShortReadNamesTheFileAndTheSizes) {
  const TempDir tmp;
  test::WriteText(tmp / "short.bin", "0123456789");
  const RegularFile f(tmp / "short.bin", "vocabulary");
  ExpectAll(RefusalOf<InputError>([&] { f.Read(4, 20); }), {"vocabulary", "short.bin", "ends after 10 bytes", "24"});
}

TEST(RegularFile, ForEachLineNumbersLinesAndKeepsTheLastWithoutNewline) {
  const TempDir tmp;
  test::WriteText(tmp / "l.txt", "a\n\nbb\r\nlast");
  std::vector<std::pair<int, std::string>> lines;
  RegularFile(tmp / "l.txt", "list").ForEachLine(100, 10, [&](int n, std::string_view s) {
    lines.emplace_back(n, std::string(s));
  });
  const std::vector<std::pair<int, std::string>> expected = {{1, "a"}, {2, ""}, {3, "bb\r"}, {4, "last"}};
  EXPECT_EQ(lines, expected);
}

TEST(RegularFile, ForEachLineRefusesALongLineEarly) {
  const TempDir tmp;
  // A line that runs over several read pieces, then a newline.
  test::WriteText(tmp / "l.txt", "ok\n" + std::string(200000, 'x') + "\nnever\n");
  int calls = 0;
  const auto refusal = RefusalOf<ParseError>([&] {
    RegularFile(tmp / "l.txt", "list").ForEachLine(1 << 20, 1000, [&](int, std::string_view) { ++calls; });
  });
  ExpectAll(refusal, {"l.txt:2", "longer than 1000 bytes"});
  EXPECT_EQ(calls, 1);
  // A sparse file without a newline is refused at its first line, not read whole.
  test::MakeSparse(tmp / "zeros", 1ull << 30);
  ExpectAll(RefusalOf<ParseError>([&] {
              RegularFile(tmp / "zeros", "list").ForEachLine(2ull << 30, 4096, [](int, std::string_view) {});
            }),
            {"zeros:1", "longer than 4096"});
}

TEST(OptionalRegularFile, AbsentIsNothingButAnythingElseIsAnError) {
  const TempDir tmp;
  EXPECT_FALSE(OptionalRegularFile(tmp / "groundtruth.txt", "ground truth"));
  test::WriteText(tmp / "groundtruth.txt", "");
  EXPECT_EQ(OptionalRegularFile(tmp / "groundtruth.txt", "ground truth"), tmp / "groundtruth.txt");
  test::MakeFifo(tmp / "sgslam.yaml");
  ExpectAll(RefusalOf<InputError>([&] { OptionalRegularFile(tmp / "sgslam.yaml", "dataset config"); }),
            {"dataset config", "sgslam.yaml", "FIFO"});
  fs::create_directory(tmp / "associations.txt");
  ExpectAll(RefusalOf<InputError>([&] { OptionalRegularFile(tmp / "associations.txt", "list"); }),
            {"associations.txt", "folder"});
  EXPECT_EQ(WhyNotRegularFile(tmp / "groundtruth.txt"), "");
  EXPECT_EQ(WhyNotRegularFile(tmp / "nope"), "not found");
  // Below a file: nothing there, not an error (a dataset "folder" that is a file).
  EXPECT_FALSE(OptionalRegularFile(tmp / "groundtruth.txt" / "sgslam.yaml", "dataset config"));
}

}  // namespace
}  // namespace sgslam
