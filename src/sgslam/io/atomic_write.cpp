#include "sgslam/io/atomic_write.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <charconv>
#include <csignal>
#include <fstream>
#include <optional>
#include <sstream>
#include <system_error>

#include <spdlog/spdlog.h>

#include "sgslam/common/error.h"

namespace sgslam {

namespace fs = std::filesystem;

namespace {

// The process's umask, without changing it (umask() would, for every thread).
mode_t CurrentUmask() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("Umask:", 0) == 0) return static_cast<mode_t>(std::stoul(line.substr(6), nullptr, 8));
  }
  return 022;
}

bool WriteAll(int fd, const std::string& content) {
  const char* data = content.data();
  std::size_t left = content.size();
  while (left > 0) {
    const ssize_t n = write(fd, data, left);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    data += n;
    left -= static_cast<std::size_t>(n);
  }
  return true;
}

struct TempFile {
  int fd = -1;
  std::string name;  // empty while the file is unnamed (O_TMPFILE)
};

// The file being written, unnamed where the file system allows (O_TMPFILE): a run
// killed while writing (SIGKILL, a power cut) then leaves nothing behind. Else a
// fresh name created exclusively, so that a file or link planted under a fixed
// temporary name is never written through.
TempFile OpenTempFile(const fs::path& path, const fs::path& dir) {
  TempFile tmp;
  if (access("/proc/self/fd", X_OK) == 0) {  // the way to name it afterwards
    tmp.fd = open(dir.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666);  // the umask applies
    if (tmp.fd >= 0) return tmp;
  }
  tmp.name = TempFilePrefix(path) + "XXXXXX";
  tmp.fd = mkostemp(tmp.name.data(), O_CLOEXEC);
  if (tmp.fd < 0) throw InputError("cannot write file: " + path.string() + ": " + std::strerror(errno));
  if (fchmod(tmp.fd, 0666 & ~CurrentUmask()) != 0) {  // as an ordinary new file (mkstemp makes it 0600)
    const std::string why = std::strerror(errno);
    close(tmp.fd);
    std::error_code ec;
    fs::remove(tmp.name, ec);
    throw InputError("cannot write file: " + path.string() + ": " + why);
  }
  return tmp;
}

// Who may judge a temporary file: processes of this boot of this machine, in this
// PID namespace (a process id means nothing elsewhere: another host sharing the
// folder, another container, a boot before).
std::string MakeOwnerToken() {
  std::string boot = "0";
  if (std::ifstream in("/proc/sys/kernel/random/boot_id"); std::getline(in, boot)) boot = boot.substr(0, 8);
  struct stat ns {};
  const unsigned long long pid_namespace = stat("/proc/self/ns/pid", &ns) == 0 ? ns.st_ino : 0;
  char hex[24];
  const auto r = std::to_chars(hex, hex + sizeof hex, pid_namespace, 16);
  return boot + "-" + std::string(hex, r.ptr);
}

const std::string& TempOwnerToken() {
  static const std::string token = MakeOwnerToken();
  return token;
}

// The writer's process id in "<name>.tmp-sgslam.<owner>.<pid>.<suffix>" with this
// process's owner token; nothing for any other name (a user's "room.map.tmp.old",
// another machine's or container's temporary file).
std::optional<long> TempFileOwner(const std::string& entry, const std::string& name) {
  const std::string prefix = name + ".tmp-sgslam." + TempOwnerToken() + ".";
  if (entry.size() <= prefix.size() || entry.compare(0, prefix.size(), prefix) != 0) return std::nullopt;
  const char* begin = entry.data() + prefix.size();
  const char* end = entry.data() + entry.size();
  long pid = 0;
  const auto [dot, ec] = std::from_chars(begin, end, pid);
  if (ec != std::errc() || dot == end || *dot != '.' || pid <= 0) return std::nullopt;
  const std::size_t suffix = static_cast<std::size_t>(end - dot - 1);  // mkostemp's 6, Python's 8, a counter
  if (suffix == 0 || suffix > 16 ||
      !std::all_of(dot + 1, end, [](char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_'; })) {
    return std::nullopt;
  }
  return pid;
}

// Gives the written, unnamed file a fresh name beside path (linkat does not replace
// a file, so the rename that follows is what replaces the old one atomically).
bool LinkUnderTempName(TempFile& tmp, const fs::path& path) {
  static std::atomic<unsigned> counter{0};
  const std::string proc = "/proc/self/fd/" + std::to_string(tmp.fd);
  for (int attempt = 0; attempt < 100; ++attempt) {
    const std::string name = TempFilePrefix(path) + std::to_string(counter++);
    if (linkat(AT_FDCWD, proc.c_str(), AT_FDCWD, name.c_str(), AT_SYMLINK_FOLLOW) == 0) {
      tmp.name = name;
      return true;
    }
    if (errno != EEXIST) return false;
  }
  return false;
}

}  // namespace

std::string TempFilePrefix(const fs::path& path) {
  return path.string() + ".tmp-sgslam." + TempOwnerToken() + "." + std::to_string(getpid()) + ".";
}

void RemoveStaleTempFiles(const fs::path& path) {
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  const std::string name = path.filename().string();
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::optional<long> pid = TempFileOwner(it->path().filename().string(), name);
    // Only a file whose writer is gone: its id names no process here (a reused id
    // keeps the file until that process ends, which is harmless).
    if (!pid || *pid == getpid() || kill(static_cast<pid_t>(*pid), 0) == 0 || errno != ESRCH) continue;
    if (!it->is_regular_file(ec) || it->is_symlink(ec)) continue;
    if (fs::remove(it->path(), ec)) spdlog::info("removed {}, left by a writer that was killed", it->path().string());
  }
}

void WriteFileAtomically(const fs::path& path, const std::string& content) {
  std::error_code ec;
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  fs::create_directories(dir, ec);
  RemoveStaleTempFiles(path);
  TempFile tmp = OpenTempFile(path, dir);
  // Complete on disk before it replaces the old file (a power cut leaves one of the two).
  bool ok = WriteAll(tmp.fd, content) && fsync(tmp.fd) == 0;
  std::string why = ok ? "" : std::strerror(errno);
  if (ok && tmp.name.empty() && !LinkUnderTempName(tmp, path)) {
    ok = false;
    why = std::strerror(errno);
  }
  if (close(tmp.fd) != 0) ok = false;
  if (!ok) {
    if (!tmp.name.empty()) fs::remove(tmp.name, ec);
    throw InputError("error while writing file (disk full?): " + path.string() + (why.empty() ? "" : ": " + why));
  }
  fs::rename(tmp.name, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp.name, ignored);
    throw InputError("cannot rename " + tmp.name + " to " + path.string() + ": " + ec.message());
  }
  if (const int d = open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); d >= 0) {
    fsync(d);  // the rename itself
    close(d);
  }
}

}  // namespace sgslam
