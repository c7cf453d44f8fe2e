// The vocabulary's reader on files of the wrong kind and headers that lie (issue
// #47): the header is read first, and its node count checked against the file's
// size, so a FIFO, a device, a huge file of another kind or a header claiming
// millions of nodes is refused at once, naming the file.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

#include "sgslam/common/error.h"
#include "sgslam/vocab/vocabulary.h"
#include "support/child_read.h"
#include "support/reader_faults.h"
#include "support/test_support.h"

namespace sgslam::vocab {
namespace {

namespace fs = std::filesystem;
using test::ExpectAll;
using test::RefusalOf;
using test::TempDir;

std::string ValidVocabulary() {
  std::ifstream in(test::SourceDir() / "fuzz" / "corpus" / "vocabulary" / "valid-k2-l3.vocab", std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(VocabularyReader, RefusesAFifoAFolderAndADevice) {
  const TempDir tmp;
  test::MakeFifo(tmp / "v.vocab");
  ExpectAll(RefusalOf<InputError>([&] { Vocabulary::Load(tmp / "v.vocab"); }, 10, tmp / "v.vocab"),
            {"vocabulary", "v.vocab", "FIFO"});
  fs::create_directory(tmp / "d.vocab");
  ExpectAll(RefusalOf<InputError>([&] { Vocabulary::Load(tmp / "d.vocab"); }), {"d.vocab", "folder"});
  ExpectAll(RefusalOf<InputError>([&] { Vocabulary::Load("/dev/zero"); }), {"/dev/zero", "device"});
}

TEST(VocabularyReader, AHugeFileOfAnotherKindIsRefusedFromItsHeader) {
  const TempDir tmp;
  test::MakeSparse(tmp / "zeros.vocab", 3ull << 29);
  ExpectAll(RefusalOf<InputError>([&] { Vocabulary::Load(tmp / "zeros.vocab"); }),
            {"zeros.vocab", "no SGVOCAB header"});
}

TEST(VocabularyReader, AHeaderClaimingMoreNodesThanTheFileHoldsIsRefused) {
  const TempDir tmp;
  std::string bytes = ValidVocabulary();
  ASSERT_GT(bytes.size(), 100u);
  const std::uint32_t count = 50'000'000;  // within the bound, 1.9 GB of nodes
  std::memcpy(bytes.data() + 20, &count, sizeof count);
  test::WriteText(tmp / "lies.vocab", bytes);
  ExpectAll(RefusalOf<InputError>([&] { Vocabulary::Load(tmp / "lies.vocab"); }),
            {"lies.vocab", std::to_string(bytes.size()) + " bytes, expected 1900000096", "50000000 nodes"});
  const std::uint32_t beyond = 0xFFFFFFFFu;
  std::memcpy(bytes.data() + 20, &beyond, sizeof beyond);
  test::WriteText(tmp / "beyond.vocab", bytes);
  ExpectAll(RefusalOf<InputError>([&] { Vocabulary::Load(tmp / "beyond.vocab"); }),
            {"beyond.vocab", "node count 4294967295 out of range"});
  test::WriteText(tmp / "ok.vocab", ValidVocabulary());
  EXPECT_GT(Vocabulary::Load(tmp / "ok.vocab").size(), 0u);
}

TEST(VocabularyReader, AHeaderThatFitsGigabytesOfZerosIsRefusedWithoutHoldingThem) {
  const TempDir tmp;
  std::string header = ValidVocabulary().substr(0, 32);
  const std::uint32_t count = 14'000'000;  // 532 MB of nodes
  std::memcpy(header.data() + 20, &count, sizeof count);
  test::WriteText(tmp / "zeros.vocab", header);
  fs::resize_file(tmp / "zeros.vocab", 32 + std::uint64_t{count} * 38 + 64);
  const auto read = test::RefusalInChild<InputError>([&] { Vocabulary::Load(tmp / "zeros.vocab"); });
  ExpectAll(read.message, {"zeros.vocab", "checksum mismatch"});
  EXPECT_LT(read.peak_rise_mib, 64) << "the body was held before its checksum was checked";
}

}  // namespace
}  // namespace sgslam::vocab
