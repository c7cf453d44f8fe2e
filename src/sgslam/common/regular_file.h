// Reading a file a user named: only a regular file is opened (a FIFO, a device or
// a folder is refused at once, without blocking on it or reading it forever), and
// nothing is read beyond a bound checked against the file's size first. Every
// error is an InputError that names what the file is for and its path.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace sgslam {

class RegularFile {
 public:
  // Opens path for reading. `what` says what the file is for ("vocabulary",
  // "map file", ...) and begins every error: "<what> <path>: <reason>", or
  // "<what> not found: <path>".
  RegularFile(std::filesystem::path path, std::string what);
  ~RegularFile();
  RegularFile(RegularFile&& other) noexcept;
  RegularFile& operator=(RegularFile&&) = delete;
  RegularFile(const RegularFile&) = delete;
  RegularFile& operator=(const RegularFile&) = delete;

  const std::filesystem::path& path() const { return path_; }
  const std::string& what() const { return what_; }
  std::uint64_t size() const { return size_; }

  // n bytes from offset; an error naming the file when it ends before them.
  std::string Read(std::uint64_t offset, std::size_t n) const;
  // out.size() bytes from offset into out; the same errors.
  void ReadInto(std::uint64_t offset, std::span<char> out) const;
  // The whole file; refused before reading when it is larger than max_bytes.
  std::string ReadAll(std::uint64_t max_bytes) const;
  // Refused (before reading) when the file is larger than max_bytes.
  void CheckSize(std::uint64_t max_bytes) const;

  // fn(line_number, line) for every line (split at '\n', which is not passed; the
  // last line may lack it), numbered from 1, read in pieces: the file is refused
  // before reading when larger than max_bytes, and a line longer than max_line
  // bytes is refused as soon as it is (a binary file without a newline does not
  // become one huge line).
  void ForEachLine(std::uint64_t max_bytes, std::size_t max_line,
                   const std::function<void(int line, std::string_view text)>& fn) const;

  // Throws InputError("<what> <path>: <why>").
  [[noreturn]] void Fail(const std::string& why) const;

 private:
  std::filesystem::path path_;
  std::string what_;
  int fd_ = -1;
  std::uint64_t size_ = 0;
};

// RegularFile(path, what).ReadAll(max_bytes).
std::string ReadRegularFile(const std::filesystem::path& path, const std::string& what, std::uint64_t max_bytes);

// What WhyNotRegularFile says when nothing is under the name.
inline constexpr std::string_view kNotFound = "not found";

// "" when path names a regular file (links followed), else why not, in words
// (kNotFound, "is a folder, not a file", "is a FIFO (named pipe), not a regular
// file", "is a broken symbolic link", ...).
std::string WhyNotRegularFile(const std::filesystem::path& path);

// An input that may be absent (a dataset's groundtruth.txt, its sgslam.yaml): the
// path when a regular file is there, nullopt when nothing is. Anything else under
// the name (a folder, a FIFO, a device, a broken link) is an InputError naming it:
// skipped without a word, it would be a run without the input its user put there.
std::optional<std::filesystem::path> OptionalRegularFile(const std::filesystem::path& path, const std::string& what);

}  // namespace sgslam
