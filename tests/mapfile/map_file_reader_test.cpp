// The map file's reader on files of the wrong kind and headers that lie (issue
// #47): the 52-byte header is read and checked against the file's size before the
// payload, so a FIFO, a device, a huge file of another kind or a header claiming a
// huge payload is refused at once, naming the file.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

#include "sgslam/common/error.h"
#include "sgslam/mapfile/map_file.h"
#include "support/child_read.h"
#include "support/reader_faults.h"
#include "support/test_support.h"

namespace sgslam::mapfile {
namespace {

namespace fs = std::filesystem;
using test::ExpectAll;
using test::RefusalOf;
using test::TempDir;

std::string ValidMap() {
  std::ifstream in(test::SourceDir() / "fuzz" / "corpus" / "map" / "valid-minimal.map", std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(MapFileReader, ReadsAValidMap) {
  const TempDir tmp;
  test::WriteText(tmp / "m.map", ValidMap());
  EXPECT_FALSE(ReadMapFile(tmp / "m.map").keyframes.empty());
}

TEST(MapFileReader, RefusesAFifoAFolderAndADevice) {
  const TempDir tmp;
  test::MakeFifo(tmp / "pipe.map");
  ExpectAll(RefusalOf<InputError>([&] { ReadMapFile(tmp / "pipe.map"); }, 10, tmp / "pipe.map"),
            {"map file", "pipe.map", "FIFO"});
  fs::create_directory(tmp / "d.map");
  ExpectAll(RefusalOf<InputError>([&] { ReadMapFile(tmp / "d.map"); }), {"d.map", "folder"});
  ExpectAll(RefusalOf<InputError>([&] { ReadMapFile("/dev/zero"); }), {"/dev/zero", "device"});
  ExpectAll(RefusalOf<InputError>([&] { ReadMapFile(tmp / "none.map"); }), {"map file not found", "none.map"});
}

TEST(MapFileReader, AHugeFileOfAnotherKindIsRefusedFromItsHeader) {
  const TempDir tmp;
  test::MakeSparse(tmp / "zeros.map", 3ull << 29);  // 1.5 GiB: read whole, it took 2 GB and seconds
  ExpectAll(RefusalOf<InputError>([&] { ReadMapFile(tmp / "zeros.map"); }), {"zeros.map", "wrong magic"});
}

TEST(MapFileReader, AHeaderClaimingAHugePayloadIsRefusedBeforeReadingIt) {
  const TempDir tmp;
  std::string bytes = ValidMap();
  const std::uint64_t claimed = std::uint64_t{1} << 40;
  std::memcpy(bytes.data() + 12, &claimed, sizeof claimed);
  test::WriteText(tmp / "lies.map", bytes);
  ExpectAll(RefusalOf<InputError>([&] { ReadMapFile(tmp / "lies.map"); }),
            {"lies.map", "the header says 1099511627776 payload bytes", std::to_string(bytes.size() - 52)});
  // A payload of the right size behind a header of another version: the version
  // is refused before the payload is read.
  bytes = ValidMap();
  bytes[8] = 9;
  test::WriteText(tmp / "v9.map", bytes);
  ExpectAll(RefusalOf<InputError>([&] { ReadMapFile(tmp / "v9.map"); }), {"v9.map", "format version 9"});
}

TEST(MapFileReader, AHeaderThatFitsGigabytesOfZerosIsRefusedWithoutHoldingThem) {
  const TempDir tmp;
  std::string header = ValidMap().substr(0, 52);
  const std::uint64_t size = 512ull << 20;
  const std::uint64_t payload = size - 52;
  std::memcpy(header.data() + 12, &payload, sizeof payload);
  test::WriteText(tmp / "zeros.map", header);
  fs::resize_file(tmp / "zeros.map", size);
  const auto read = test::RefusalInChild<InputError>([&] { ReadMapFile(tmp / "zeros.map"); });
  ExpectAll(read.message, {"zeros.map", "checksum mismatch"});
  EXPECT_LT(read.peak_rise_mib, 64) << "the payload was held before its checksum was checked";
}

}  // namespace
}  // namespace sgslam::mapfile
