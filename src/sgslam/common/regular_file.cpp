#include "sgslam/common/regular_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstring>
#include <utility>

#include "sgslam/common/error.h"

namespace sgslam {

namespace {

// Lines are read in pieces of this size: a line costs its own length, not the file's.
constexpr std::size_t kLinePiece = 64 * 1024;

std::string KindOf(mode_t mode) {
  if (S_ISDIR(mode)) return "is a folder, not a file";
  if (S_ISFIFO(mode)) return "is a FIFO (named pipe), not a regular file";
  if (S_ISCHR(mode) || S_ISBLK(mode)) return "is a device, not a regular file";
  if (S_ISSOCK(mode)) return "is a socket, not a regular file";
  return "is not a regular file";
}

std::string Bytes(std::uint64_t n) { return std::to_string(n) + " bytes"; }

}  // namespace

std::string WhyNotRegularFile(const std::filesystem::path& path) {
  struct stat st {};
  if (stat(path.c_str(), &st) != 0) {
    const int error = errno;
    struct stat link {};
    if (error == ENOENT && lstat(path.c_str(), &link) == 0) return "is a broken symbolic link";
    // ENOTDIR: a folder on the way is a file ("run.txt/sgslam.yaml"), so nothing is there.
    return error == ENOENT || error == ENOTDIR ? std::string(kNotFound) : std::strerror(error);
  }
  return S_ISREG(st.st_mode) ? "" : KindOf(st.st_mode);
}

std::optional<std::filesystem::path> OptionalRegularFile(const std::filesystem::path& path, const std::string& what) {
  const std::string why = WhyNotRegularFile(path);
  if (why.empty()) return path;
  if (why == kNotFound) return std::nullopt;
  throw InputError(what + " " + path.string() + ": " + why);
}

RegularFile::RegularFile(std::filesystem::path path, std::string what) : path_(std::move(path)), what_(std::move(what)) {
  // Looked at before it is opened: opening a FIFO waits for a writer, and opening
  // some devices acts on them. The open itself does not block (O_NONBLOCK), and
  // what was opened is checked again, in case the name changed in between.
  if (const std::string why = WhyNotRegularFile(path_); !why.empty()) Fail(why);
  fd_ = open(path_.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK);
  if (fd_ < 0) Fail(std::string("cannot open: ") + std::strerror(errno));
  struct stat st {};
  if (fstat(fd_, &st) != 0) Fail(std::string("cannot read: ") + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) Fail(KindOf(st.st_mode));
  size_ = static_cast<std::uint64_t>(st.st_size);
}

RegularFile::~RegularFile() {
  if (fd_ >= 0) close(fd_);
}

RegularFile::RegularFile(RegularFile&& other) noexcept
    : path_(std::move(other.path_)), what_(std::move(other.what_)), fd_(std::exchange(other.fd_, -1)),
      size_(other.size_) {}

void RegularFile::Fail(const std::string& why) const {
  if (why == kNotFound) throw InputError(what_ + " not found: " + path_.string());
  throw InputError(what_ + " " + path_.string() + ": " + why);
}

void RegularFile::ReadInto(std::uint64_t offset, std::span<char> out) const {
  std::size_t done = 0;
  while (done < out.size()) {
    const ssize_t got = pread(fd_, out.data() + done, out.size() - done, static_cast<off_t>(offset + done));
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) Fail(std::string("read error: ") + std::strerror(errno));
    if (got == 0) {
      Fail("ends after " + Bytes(offset + done) + ", " + Bytes(offset + out.size()) + " expected (cut short?)");
    }
    done += static_cast<std::size_t>(got);
  }
}

std::string RegularFile::Read(std::uint64_t offset, std::size_t n) const {
  std::string bytes(n, '\0');
  ReadInto(offset, bytes);
  return bytes;
}

void RegularFile::CheckSize(std::uint64_t max_bytes) const {
  if (size_ > max_bytes) {
    Fail(Bytes(size_) + ", more than the " + Bytes(max_bytes) + " such a file can have (the wrong file?)");
  }
}

std::string RegularFile::ReadAll(std::uint64_t max_bytes) const {
  CheckSize(max_bytes);
  return Read(0, static_cast<std::size_t>(size_));
}

void RegularFile::ForEachLine(std::uint64_t max_bytes, std::size_t max_line,
                              const std::function<void(int, std::string_view)>& fn) const {
  CheckSize(max_bytes);
  std::string piece(static_cast<std::size_t>(std::min<std::uint64_t>(kLinePiece, size_)), '\0');
  std::string line;
  int number = 1;
  const auto too_long = [&] {
    throw ParseError(path_.string(), number,
                     "a line longer than " + Bytes(max_line) + " (a binary file, or the wrong file?)");
  };
  for (std::uint64_t at = 0; at < size_;) {
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(piece.size(), size_ - at));
    ReadInto(at, std::span<char>(piece.data(), n));
    at += n;
    for (std::size_t from = 0; from < n;) {
      const void* found = std::memchr(piece.data() + from, '\n', n - from);
      const std::size_t end = found ? static_cast<std::size_t>(static_cast<const char*>(found) - piece.data()) : n;
      if (line.size() + (end - from) > max_line) too_long();
      line.append(piece, from, end - from);
      if (!found) break;
      fn(number, line);
      line.clear();
      if (number == INT_MAX) Fail("more lines than can be counted");
      ++number;
      from = end + 1;
    }
  }
  if (!line.empty()) fn(number, line);
}

std::string ReadRegularFile(const std::filesystem::path& path, const std::string& what, std::uint64_t max_bytes) {
  return RegularFile(path, what).ReadAll(max_bytes);
}

}  // namespace sgslam
