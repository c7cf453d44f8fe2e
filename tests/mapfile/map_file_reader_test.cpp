// The map file's reader on files of the wrong kind and headers that lie (issue
// #47): the 52-byte header is read and checked against the file's size before the
// payload, so a FIFO, a device, a huge file of another kind or a header claiming a
// huge payload is refused at once, naming the file.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <chrono>
#include <cstring>
#include <fstream>

#include "sgslam/common/error.h"
#include "sgslam/mapfile/map_file.h"
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
  const auto started = std::chrono::steady_clock::now();
  ExpectAll(RefusalOf<InputError>([&] { ReadMapFile(tmp / "zeros.map"); }), {"zeros.map", "wrong magic"});
  EXPECT_LT(std::chrono::steady_clock::now() - started, std::chrono::seconds(1));
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

// The peak resident memory of this process so far, in MiB.
double PeakMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

TEST(MapFileReader, AHeaderThatFitsGigabytesOfZerosIsRefusedWithoutHoldingThem) {
  const TempDir tmp;
  std::string header = ValidMap().substr(0, 52);
  const std::uint64_t size = 512ull << 20;
  const std::uint64_t payload = size - 52;
  std::memcpy(header.data() + 12, &payload, sizeof payload);
  test::WriteText(tmp / "zeros.map", header);
  fs::resize_file(tmp / "zeros.map", size);
  const double before = PeakMiB();
  ExpectAll(RefusalOf<InputError>([&] { ReadMapFile(tmp / "zeros.map"); }, 60), {"zeros.map", "checksum mismatch"});
  EXPECT_LT(PeakMiB() - before, 64) << "the payload was held before its checksum was checked";
}

}  // namespace
}  // namespace sgslam::mapfile
