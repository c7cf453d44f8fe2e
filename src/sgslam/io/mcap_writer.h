// An MCAP file writer (https://mcap.dev/spec): the container Foxglove opens.
// Messages go into chunks (zstd-compressed or stored) written as the run goes, each followed by
// its message indexes, so memory stays bounded by one chunk; Close() adds the data
// end, the summary (schemas, channels, statistics, chunk indexes) and its offsets,
// which let a reader seek by time. Every record the spec gives a CRC has one.
// The file is written as <path>.part and renamed to <path> when closed, so an
// earlier file of that name stays until the new one is whole. A file not closed
// (the process killed, a full disk) stays as <path>.part with its chunks: stream
// readers read it, indexed readers refuse it.
#pragma once

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace sgslam::mcap {

// The bytes an MCAP file begins and ends with.
inline constexpr std::string_view kFileMagic{"\x89MCAP0\r\n", 8};

struct WriterOptions {
  std::size_t chunk_size = 1 << 20;  // bytes of records a chunk holds before it is written
  bool zstd = true;                  // chunks compressed with zstd (level 3), else stored
  std::string profile;               // the header's profile ("" for none; "ros1", "ros2")
  std::string library = "sgslam";
};

class Writer {
 public:
  // Creates (or truncates) <path>.part and writes the magic and header. Throws
  // InputError naming the path when it cannot.
  explicit Writer(const std::filesystem::path& path, WriterOptions options = {});
  ~Writer();  // closes, when Close() was not called; an error there is logged
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  // Ids start at 1. Schema encodings: "jsonschema", "protobuf", ...; message
  // encodings: "json", "protobuf", ... (the spec's well-known names).
  std::uint16_t AddSchema(const std::string& name, const std::string& encoding, std::string_view data);
  std::uint16_t AddChannel(std::uint16_t schema_id, const std::string& topic, const std::string& message_encoding,
                           const std::map<std::string, std::string>& metadata = {});
  // log_time: ns, when it was recorded (Foxglove plays by it); publish_time: ns.
  void Write(std::uint16_t channel, std::uint64_t log_time, std::uint64_t publish_time, std::string_view data);
  // The last chunk, the summary and the footer, then the rename. Throws InputError
  // on a failed write (now or before); afterwards nothing more can be written.
  void Close();

  // Closes and removes <path>.part: nothing of it is wanted (a run that failed before
  // its first frame); an earlier file at path stays as it was.
  void Abandon();

  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path part_path() const { return path_.string() + ".part"; }
  bool closed() const { return file_ == nullptr; }
  bool failed() const { return !failure_.empty(); }  // a write failed: closed, left as part_path()
  std::uint64_t bytes() const { return offset_ + chunk_.size(); }  // written, and buffered in the open chunk
  std::uint64_t messages() const { return message_count_; }

 private:
  struct Schema {
    std::uint16_t id;
    std::string name, encoding, data;
  };
  struct Channel {
    std::uint16_t id, schema_id;
    std::string topic, encoding;
    std::map<std::string, std::string> metadata;
  };
  struct ChunkIndex {
    std::uint64_t start_time, end_time, offset, length;
    std::map<std::uint16_t, std::uint64_t> message_index_offsets;
    std::uint64_t message_index_length, compressed_size, size;
  };

  void FlushChunk();
  void Put(std::string_view bytes);  // to the file, counted in the data section's CRC
  [[noreturn]] void Fail(const std::string& what);

  std::filesystem::path path_;
  WriterOptions options_;
  std::FILE* file_ = nullptr;
  std::string failure_;  // why a write failed
  std::uint64_t offset_ = 0;  // bytes in the file
  std::uint32_t data_crc_ = 0;

  std::vector<Schema> schemas_;
  std::vector<Channel> channels_;
  std::vector<ChunkIndex> chunk_indexes_;
  std::map<std::uint16_t, std::uint64_t> channel_counts_;
  std::uint64_t message_count_ = 0, start_time_ = 0, end_time_ = 0;

  // The open chunk: its records, and per channel (log time, offset in the records).
  std::string chunk_;
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> chunk_index_;
  std::uint64_t chunk_start_ = 0, chunk_end_ = 0;
};

// The CRC-32 MCAP uses (that of zlib and PNG), continued from `crc`.
std::uint32_t Crc32(std::string_view bytes, std::uint32_t crc = 0);

}  // namespace sgslam::mcap
