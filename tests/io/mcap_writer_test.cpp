#include "sgslam/io/mcap_writer.h"

#include <gtest/gtest.h>

#include <csignal>
#include <fstream>
#include <iterator>
#include <map>

#include <sys/resource.h>
#include <zstd.h>

#include "sgslam/common/error.h"
#include "support/test_support.h"

namespace sgslam::mcap {
namespace {

// A reader of just enough of the format to check what the writer promises (the
// viewer's tests read the files with the official @mcap/core too).
struct Cursor {
  const std::string& b;
  std::size_t at;
  template <typename T>
  T Int() {
    std::uint64_t v = 0;
    for (std::size_t i = 0; i < sizeof(T); ++i) v |= static_cast<std::uint64_t>(static_cast<std::uint8_t>(b.at(at + i))) << (8 * i);
    at += sizeof(T);
    return static_cast<T>(v);
  }
  std::string Str() {
    const auto n = Int<std::uint32_t>();
    std::string s = b.substr(at, n);
    at += n;
    return s;
  }
};

struct Rec {
  std::uint8_t op;
  std::size_t start, content;  // offsets of the opcode and of the content
  std::uint64_t length;
};

std::vector<Rec> Records(const std::string& b, std::size_t from, std::size_t to) {
  std::vector<Rec> out;
  Cursor c{b, from};
  while (c.at < to) {
    Rec r{};
    r.start = c.at;
    r.op = c.Int<std::uint8_t>();
    r.length = c.Int<std::uint64_t>();
    r.content = c.at;
    c.at += r.length;
    out.push_back(r);
  }
  EXPECT_EQ(c.at, to) << "records run past their section";
  return out;
}

std::string ReadAll(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

const std::string kMagic{"\x89MCAP0\r\n", 8};

TEST(Mcap, Crc32IsZlibs) {
  EXPECT_EQ(Crc32("123456789"), 0xCBF43926u);
  EXPECT_EQ(Crc32("56789", Crc32("1234")), 0xCBF43926u);  // continued
  EXPECT_EQ(Crc32(""), 0u);
}

TEST(Mcap, ChunksIndexesAndSummaryPointWhereTheySay) {
  test::TempDir tmp;
  const auto path = tmp / "run.mcap";
  {
    WriterOptions small;
    small.chunk_size = 256;  // several chunks
    small.zstd = false;      // stored, for the records to be read in place (compressed below)
    Writer w(path, small);
    const auto pose = w.AddSchema("foxglove.PoseInFrame", "jsonschema", R"({"type":"object"})");
    const auto stats = w.AddSchema("", "", "");
    const auto a = w.AddChannel(pose, "/camera/pose", "json", {{"k", "v"}});
    const auto s = w.AddChannel(stats, "/stats", "json");
    for (std::uint64_t i = 0; i < 40; ++i) {
      w.Write(a, 1000 + i, 1000 + i, R"({"i":)" + std::to_string(i) + "}");
      if (i % 3 == 0) w.Write(s, 1000 + i, 1000 + i, "{}");
    }
    EXPECT_EQ(w.messages(), 54u);
  }  // closed by the destructor
  const std::string b = ReadAll(path);
  ASSERT_GT(b.size(), 16u);
  EXPECT_EQ(b.substr(0, 8), kMagic);
  EXPECT_EQ(b.substr(b.size() - 8), kMagic);

  // The footer: where the summary and its offsets are, and their CRC.
  Cursor f{b, b.size() - 8 - 29};
  ASSERT_EQ(f.Int<std::uint8_t>(), 0x02);
  ASSERT_EQ(f.Int<std::uint64_t>(), 20u);
  const auto summary_start = f.Int<std::uint64_t>();
  const auto summary_offset_start = f.Int<std::uint64_t>();
  const auto summary_crc = f.Int<std::uint32_t>();
  EXPECT_EQ(summary_crc, Crc32(std::string_view(b).substr(summary_start, b.size() - 8 - 4 - summary_start)));

  // The data section: header, schemas, channels, chunks each followed by their
  // message indexes, the data end with the CRC of everything before it.
  const auto data = Records(b, 8, summary_start);
  ASSERT_GE(data.size(), 6u);
  EXPECT_EQ(data.front().op, 0x01);
  ASSERT_EQ(data.back().op, 0x0F);
  Cursor data_end{b, data.back().content};
  EXPECT_EQ(data_end.Int<std::uint32_t>(), Crc32(std::string_view(b).substr(0, data.back().start)));
  std::map<std::size_t, Rec> by_offset;
  for (const Rec& r : data) by_offset[r.start] = r;

  // The summary: schemas, channels, statistics and a chunk index per chunk.
  std::map<std::uint8_t, int> count;
  std::uint64_t indexed_messages = 0;
  for (const Rec& r : Records(b, summary_start, summary_offset_start)) {
    ++count[r.op];
    Cursor c{b, r.content};
    if (r.op == 0x0B) {
      EXPECT_EQ(c.Int<std::uint64_t>(), 54u);  // messages
      EXPECT_EQ(c.Int<std::uint16_t>(), 2u);   // schemas
      EXPECT_EQ(c.Int<std::uint32_t>(), 2u);   // channels
      c.at += 8;                                // attachments, metadata
      EXPECT_GE(c.Int<std::uint32_t>(), 3u);   // chunks
      EXPECT_EQ(c.Int<std::uint64_t>(), 1000u);
      EXPECT_EQ(c.Int<std::uint64_t>(), 1039u);
    }
    if (r.op != 0x08) continue;
    c.at += 16;  // start and end time
    const auto chunk_at = c.Int<std::uint64_t>();
    const auto chunk_length = c.Int<std::uint64_t>();
    ASSERT_TRUE(by_offset.count(chunk_at));
    const Rec chunk = by_offset[chunk_at];
    EXPECT_EQ(chunk.op, 0x06);
    EXPECT_EQ(chunk_length, 9 + chunk.length);
    // Its records, and the CRC of them.
    Cursor k{b, chunk.content + 16};
    const auto uncompressed = k.Int<std::uint64_t>();
    const auto crc = k.Int<std::uint32_t>();
    EXPECT_EQ(k.Str(), "");
    ASSERT_EQ(k.Int<std::uint64_t>(), uncompressed);
    const std::size_t records = k.at;
    EXPECT_EQ(crc, Crc32(std::string_view(b).substr(records, uncompressed)));
    // Each message index names messages of its channel at their offsets.
    const auto n = c.Int<std::uint32_t>() / 10;
    for (std::uint32_t i = 0; i < n; ++i) {
      const auto channel = c.Int<std::uint16_t>();
      const auto index_at = c.Int<std::uint64_t>();
      ASSERT_TRUE(by_offset.count(index_at));
      ASSERT_EQ(by_offset[index_at].op, 0x07);
      Cursor m{b, by_offset[index_at].content};
      EXPECT_EQ(m.Int<std::uint16_t>(), channel);
      const auto entries = m.Int<std::uint32_t>() / 16;
      for (std::uint32_t e = 0; e < entries; ++e) {
        const auto t = m.Int<std::uint64_t>();
        Cursor msg{b, records + m.Int<std::uint64_t>()};
        EXPECT_EQ(msg.Int<std::uint8_t>(), 0x05);
        msg.at += 8;
        EXPECT_EQ(msg.Int<std::uint16_t>(), channel);
        msg.at += 4;
        EXPECT_EQ(msg.Int<std::uint64_t>(), t);
        ++indexed_messages;
      }
    }
  }
  EXPECT_EQ(indexed_messages, 54u);
  EXPECT_EQ(count[0x03], 2);
  EXPECT_EQ(count[0x04], 2);
  EXPECT_EQ(count[0x0B], 1);
  EXPECT_GE(count[0x08], 3);
  // The summary offsets: one per group, each spanning records of its opcode.
  int groups = 0;
  for (const Rec& r : Records(b, summary_offset_start, b.size() - 8 - 29)) {
    ASSERT_EQ(r.op, 0x0E);
    Cursor c{b, r.content};
    const auto op = c.Int<std::uint8_t>();
    const auto start = c.Int<std::uint64_t>();
    const auto length = c.Int<std::uint64_t>();
    for (const Rec& g : Records(b, start, start + length)) EXPECT_EQ(g.op, op);
    ++groups;
  }
  EXPECT_EQ(groups, 4);
}

TEST(Mcap, CompressedChunksHoldTheirRecordsAndCrc) {
  test::TempDir tmp;
  {
    Writer w(tmp / "z.mcap");  // zstd by default
    const auto c = w.AddChannel(0, "/text", "json");
    for (std::uint64_t i = 0; i < 500; ++i) w.Write(c, i, i, R"({"text":"the same words again and again"})");
  }
  const std::string b = ReadAll(tmp / "z.mcap");
  std::size_t chunks = 0;
  Cursor footer{b, b.size() - 8 - 29 + 9};
  const auto summary_start = footer.Int<std::uint64_t>();
  for (const Rec& r : Records(b, 8, summary_start)) {
    if (r.op != 0x06) continue;
    ++chunks;
    Cursor k{b, r.content + 16};
    const auto uncompressed = k.Int<std::uint64_t>();
    const auto crc = k.Int<std::uint32_t>();
    EXPECT_EQ(k.Str(), "zstd");
    const auto compressed = k.Int<std::uint64_t>();
    EXPECT_LT(compressed * 10, uncompressed);  // the same text compresses well
    std::string records(uncompressed, '\0');
    ASSERT_EQ(ZSTD_decompress(records.data(), records.size(), b.data() + k.at, compressed), uncompressed);
    EXPECT_EQ(Crc32(records), crc);
    std::size_t messages = 0;
    for (const Rec& m : Records(records, 0, records.size())) messages += m.op == 0x05;
    EXPECT_EQ(messages, 500u);
  }
  EXPECT_EQ(chunks, 1u);
}

TEST(Mcap, AnEmptyRecordingIsAValidFile) {
  test::TempDir tmp;
  Writer w(tmp / "empty.mcap");
  w.Close();
  EXPECT_TRUE(w.closed());
  const std::string b = ReadAll(tmp / "empty.mcap");
  EXPECT_EQ(b.substr(0, 8), kMagic);
  EXPECT_EQ(b.substr(b.size() - 8), kMagic);
  EXPECT_THROW(w.Write(1, 0, 0, ""), Error);
}

TEST(Mcap, AnEarlierFileStaysUntilTheNewOneIsWhole) {
  test::TempDir tmp;
  const auto path = tmp / "run.mcap";
  { std::ofstream(path) << "the earlier recording"; }
  {
    Writer w(path);
    w.Write(w.AddChannel(0, "/x", "json"), 1, 1, "{}");
    EXPECT_EQ(ReadAll(path), "the earlier recording");  // written beside it, as run.mcap.part
    EXPECT_TRUE(std::filesystem::exists(w.part_path()));
    w.Abandon();  // a run that failed before its first frame
  }
  EXPECT_EQ(ReadAll(path), "the earlier recording");
  EXPECT_FALSE(std::filesystem::exists(tmp / "run.mcap.part"));
  {
    Writer w(path);
    w.Write(w.AddChannel(0, "/x", "json"), 1, 1, "{}");
  }  // closed: renamed over it
  EXPECT_EQ(ReadAll(path).substr(0, 8), kMagic);
  EXPECT_FALSE(std::filesystem::exists(tmp / "run.mcap.part"));
}

// Writes past a file size limit fail (EFBIG) as on a full disk; the signal such a
// write raises is ignored meanwhile.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    getrlimit(RLIMIT_FSIZE, &before_);
    old_handler_ = std::signal(SIGXFSZ, SIG_IGN);
    rlimit limit = before_;
    limit.rlim_cur = bytes;
    setrlimit(RLIMIT_FSIZE, &limit);
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &before_);
    std::signal(SIGXFSZ, old_handler_);
  }

 private:
  rlimit before_{};
  void (*old_handler_)(int) = nullptr;
};

TEST(Mcap, RefusesWhatItCannotWrite) {
  test::TempDir tmp;
  EXPECT_THROW(Writer(tmp / "no" / "such" / "folder.mcap"), InputError);
  const auto path = tmp / "full.mcap";
  try {
    const FileSizeLimit limit(4096);
    WriterOptions small;
    small.chunk_size = 64;
    Writer w(path, small);
    const auto c = w.AddChannel(0, "/x", "json");
    for (int i = 0; i < 100; ++i) w.Write(c, static_cast<std::uint64_t>(i), 0, std::string(100, 'x'));
    w.Close();
    FAIL() << "a full disk went unnoticed";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("full.mcap.part"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(path));  // never renamed: what was written stays as .part
  EXPECT_TRUE(std::filesystem::exists(tmp / "full.mcap.part"));
}

}  // namespace
}  // namespace sgslam::mcap
