#include "sgslam/io/mcap_writer.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>

#include <spdlog/spdlog.h>
#include <zstd.h>

#include "sgslam/common/error.h"

namespace sgslam::mcap {

namespace {

// The spec's opcodes.
enum Op : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kStatistics = 0x0B,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

// One record: the opcode, its content's length (set by Finish), the content, all
// integers little-endian.
class Record {
 public:
  explicit Record(Op op) { Int<std::uint8_t>(op).Int<std::uint64_t>(0); }
  template <typename T>
  Record& Int(T v) {
    for (std::size_t i = 0; i < sizeof(T); ++i) bytes_.push_back(static_cast<char>((static_cast<std::uint64_t>(v) >> (8 * i)) & 0xFF));
    return *this;
  }
  Record& Str(std::string_view s) {  // uint32 length, then the bytes
    Int(static_cast<std::uint32_t>(s.size()));
    bytes_.append(s);
    return *this;
  }
  Record& Raw(std::string_view s) {
    bytes_.append(s);
    return *this;
  }
  Record& StrMap(const std::map<std::string, std::string>& m) {  // uint32 byte length, then the pairs
    std::uint32_t length = 0;
    for (const auto& [k, v] : m) length += static_cast<std::uint32_t>(8 + k.size() + v.size());
    Int(length);
    for (const auto& [k, v] : m) Str(k).Str(v);
    return *this;
  }
  const std::string& Finish() {
    const std::uint64_t length = bytes_.size() - 9;
    for (std::size_t i = 0; i < 8; ++i) bytes_[1 + i] = static_cast<char>((length >> (8 * i)) & 0xFF);
    return bytes_;
  }

 private:
  std::string bytes_;
};

const std::array<std::uint32_t, 256>& CrcTable() {
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  return table;
}

}  // namespace

std::uint32_t Crc32(std::string_view bytes, std::uint32_t crc) {
  const auto& table = CrcTable();
  crc = ~crc;
  for (const char b : bytes) crc = table[(crc ^ static_cast<std::uint8_t>(b)) & 0xFF] ^ (crc >> 8);
  return ~crc;
}

Writer::Writer(const std::filesystem::path& path, WriterOptions options) : path_(path), options_(std::move(options)) {
  file_ = std::fopen(part_path().c_str(), "wb");
  if (!file_) throw InputError("cannot write " + part_path().string() + ": " + std::strerror(errno));
  Put(kFileMagic);
  Put(Record(kHeader).Str(options_.profile).Str(options_.library).Finish());
}

Writer::~Writer() {
  if (!file_) return;
  try {
    Close();
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
  }
}

void Writer::Abandon() {
  if (file_) {
    std::fclose(file_);
    file_ = nullptr;
    std::error_code ignored;
    std::filesystem::remove(part_path(), ignored);
  }
  if (failure_.empty()) failure_ = "mcap: " + path_.string() + " abandoned";
}

void Writer::Fail(const std::string& what) {
  const std::string reason = errno ? std::strerror(errno) : "write failed";
  std::fclose(file_);
  file_ = nullptr;
  failure_ = what + " " + part_path().string() + ": " + reason + " (what was written before is there; " +
             path_.filename().string() + " was not replaced)";
  throw InputError(failure_);
}

void Writer::Put(std::string_view bytes) {
  errno = 0;
  if (std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size()) Fail("cannot write");
  data_crc_ = Crc32(bytes, data_crc_);
  offset_ += bytes.size();
}

std::uint16_t Writer::AddSchema(const std::string& name, const std::string& encoding, std::string_view data) {
  if (!file_) throw Error("mcap: AddSchema after Close");
  const auto id = static_cast<std::uint16_t>(schemas_.size() + 1);
  schemas_.push_back({id, name, encoding, std::string(data)});
  Put(Record(kSchema).Int(id).Str(name).Str(encoding).Str(data).Finish());
  return id;
}

std::uint16_t Writer::AddChannel(std::uint16_t schema_id, const std::string& topic, const std::string& message_encoding,
                                 const std::map<std::string, std::string>& metadata) {
  if (!file_) throw Error("mcap: AddChannel after Close");
  if (schema_id > schemas_.size()) throw Error("mcap: channel " + topic + " names an unknown schema");
  const auto id = static_cast<std::uint16_t>(channels_.size() + 1);
  channels_.push_back({id, schema_id, topic, message_encoding, metadata});
  Put(Record(kChannel).Int(id).Int(schema_id).Str(topic).Str(message_encoding).StrMap(metadata).Finish());
  return id;
}

void Writer::Write(std::uint16_t channel, std::uint64_t log_time, std::uint64_t publish_time, std::string_view data) {
  if (!file_) throw Error("mcap: Write after Close");
  if (channel == 0 || channel > channels_.size()) throw Error("mcap: message on an unknown channel");
  if (chunk_.empty()) chunk_start_ = chunk_end_ = log_time;
  chunk_start_ = std::min(chunk_start_, log_time);
  chunk_end_ = std::max(chunk_end_, log_time);
  chunk_index_[channel].emplace_back(log_time, chunk_.size());
  Record r(kMessage);
  r.Int(channel).Int(static_cast<std::uint32_t>(channel_counts_[channel])).Int(log_time).Int(publish_time).Raw(data);
  chunk_ += r.Finish();
  if (message_count_ == 0) start_time_ = end_time_ = log_time;
  start_time_ = std::min(start_time_, log_time);
  end_time_ = std::max(end_time_, log_time);
  ++message_count_;
  ++channel_counts_[channel];
  if (chunk_.size() >= options_.chunk_size) FlushChunk();
}

void Writer::FlushChunk() {
  if (chunk_.empty()) return;
  std::string_view records = chunk_;
  std::string compressed;
  if (options_.zstd) {
    compressed.resize(ZSTD_compressBound(chunk_.size()));
    const std::size_t n = ZSTD_compress(compressed.data(), compressed.size(), chunk_.data(), chunk_.size(), 3);
    if (ZSTD_isError(n)) {
      errno = 0;
      Fail(std::string("zstd: ") + ZSTD_getErrorName(n) + ", in");
    }
    compressed.resize(n);
    records = compressed;
  }
  const char* compression = options_.zstd ? "zstd" : "";
  ChunkIndex index{chunk_start_, chunk_end_, offset_, 0, {}, 0, records.size(), chunk_.size()};
  Record chunk(kChunk);
  chunk.Int(chunk_start_).Int(chunk_end_).Int(static_cast<std::uint64_t>(chunk_.size())).Int(Crc32(chunk_));
  chunk.Str(compression).Int(static_cast<std::uint64_t>(records.size())).Raw(records);
  Put(chunk.Finish());
  index.length = offset_ - index.offset;
  const std::uint64_t indexes_start = offset_;
  for (const auto& [channel, entries] : chunk_index_) {
    index.message_index_offsets[channel] = offset_;
    Record r(kMessageIndex);
    r.Int(channel).Int(static_cast<std::uint32_t>(entries.size() * 16));
    for (const auto& [t, at] : entries) r.Int(t).Int(at);
    Put(r.Finish());
  }
  index.message_index_length = offset_ - indexes_start;
  chunk_indexes_.push_back(std::move(index));
  chunk_.clear();
  chunk_index_.clear();
  // On disk as it goes: a run killed keeps what it recorded up to here.
  errno = 0;
  if (std::fflush(file_) != 0) Fail("cannot write");
}

void Writer::Close() {
  if (!failure_.empty()) throw InputError(failure_);
  if (!file_) return;
  FlushChunk();
  Put(Record(kDataEnd).Int(data_crc_).Finish());

  // The summary: each group's records, then where each group is.
  const std::uint64_t summary_start = offset_;
  std::string summary;
  struct Group {
    Op op;
    std::uint64_t start, length;
  };
  std::vector<Group> groups;
  const auto group = [&](Op op, const auto& write_records) {
    const std::uint64_t start = summary_start + summary.size();
    write_records();
    if (summary_start + summary.size() > start) groups.push_back({op, start, summary_start + summary.size() - start});
  };
  group(kSchema, [&] {
    for (const auto& s : schemas_) summary += Record(kSchema).Int(s.id).Str(s.name).Str(s.encoding).Str(s.data).Finish();
  });
  group(kChannel, [&] {
    for (const auto& c : channels_) {
      summary += Record(kChannel).Int(c.id).Int(c.schema_id).Str(c.topic).Str(c.encoding).StrMap(c.metadata).Finish();
    }
  });
  group(kStatistics, [&] {
    Record r(kStatistics);
    r.Int(message_count_).Int(static_cast<std::uint16_t>(schemas_.size())).Int(static_cast<std::uint32_t>(channels_.size()));
    r.Int(std::uint32_t{0}).Int(std::uint32_t{0}).Int(static_cast<std::uint32_t>(chunk_indexes_.size()));
    r.Int(start_time_).Int(end_time_);
    r.Int(static_cast<std::uint32_t>(channel_counts_.size() * 10));
    for (const auto& [channel, count] : channel_counts_) r.Int(channel).Int(count);
    summary += r.Finish();
  });
  group(kChunkIndex, [&] {
    for (const auto& c : chunk_indexes_) {
      Record r(kChunkIndex);
      r.Int(c.start_time).Int(c.end_time).Int(c.offset).Int(c.length);
      r.Int(static_cast<std::uint32_t>(c.message_index_offsets.size() * 10));
      for (const auto& [channel, at] : c.message_index_offsets) r.Int(channel).Int(at);
      r.Int(c.message_index_length).Str(options_.zstd ? "zstd" : "").Int(c.compressed_size).Int(c.size);
      summary += r.Finish();
    }
  });
  const std::uint64_t summary_offset_start = summary_start + summary.size();
  for (const Group& g : groups) summary += Record(kSummaryOffset).Int(g.op).Int(g.start).Int(g.length).Finish();
  // The footer; its CRC covers the summary and the footer up to the CRC.
  Record footer_record(kFooter);
  std::string footer = footer_record.Int(summary_start).Int(summary_offset_start).Int(std::uint32_t{0}).Finish();
  const std::uint32_t summary_crc = Crc32(std::string_view(footer).substr(0, footer.size() - 4), Crc32(summary));
  for (std::size_t i = 0; i < 4; ++i) footer[footer.size() - 4 + i] = static_cast<char>((summary_crc >> (8 * i)) & 0xFF);
  Put(summary);
  Put(footer);
  Put(kFileMagic);
  std::FILE* f = file_;
  file_ = nullptr;
  errno = 0;
  if (std::fclose(f) != 0) {
    failure_ = "cannot write " + part_path().string() + ": " + std::strerror(errno);
    throw InputError(failure_);
  }
  std::error_code ec;
  std::filesystem::rename(part_path(), path_, ec);
  if (ec) {
    failure_ = "cannot rename " + part_path().string() + " to " + path_.string() + ": " + ec.message();
    throw InputError(failure_);
  }
}

}  // namespace sgslam::mcap
