// WriteFileAtomically (text_file.h): a fresh temporary file renamed over the
// output, and the temporary files of killed runs cleared away.
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
#include "sgslam/io/text_file.h"

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
  tmp.name = path.string() + ".tmp." + std::to_string(getpid()) + ".XXXXXX";  // the pattern RemoveStaleTempFiles knows
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

// Gives the written, unnamed file a fresh name beside path (linkat does not replace
// a file, so the rename that follows is what replaces the old one atomically).
bool LinkUnderTempName(TempFile& tmp, const fs::path& path) {
  static std::atomic<unsigned> counter{0};
  const std::string proc = "/proc/self/fd/" + std::to_string(tmp.fd);
  for (int attempt = 0; attempt < 100; ++attempt) {
    const std::string name = path.string() + ".tmp." + std::to_string(getpid()) + "." + std::to_string(counter++);
    if (linkat(AT_FDCWD, proc.c_str(), AT_FDCWD, name.c_str(), AT_SYMLINK_FOLLOW) == 0) {
      tmp.name = name;
      return true;
    }
    if (errno != EEXIST) return false;
  }
  return false;
}

// When process pid started (seconds since the epoch), from /proc; nothing when
// it is not running or this cannot be told.
std::optional<double> ProcessStart(long pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string text;
  if (!std::getline(stat, text)) return std::nullopt;
  const std::size_t paren = text.rfind(')');  // the command's name may hold spaces and parentheses
  if (paren == std::string::npos) return std::nullopt;
  std::istringstream fields(text.substr(paren + 2));
  std::string field;
  unsigned long long ticks = 0;
  for (int i = 3; i <= 22 && fields >> field; ++i) {
    if (i == 22) ticks = std::strtoull(field.c_str(), nullptr, 10);  // starttime: ticks after boot
  }
  std::ifstream proc_stat("/proc/stat");
  for (std::string line; std::getline(proc_stat, line);) {
    if (line.rfind("btime ", 0) == 0) {
      return std::strtod(line.c_str() + 6, nullptr) + static_cast<double>(ticks) / static_cast<double>(sysconf(_SC_CLK_TCK));
    }
  }
  return std::nullopt;
}

// The writer's process id in "<name>.tmp.<pid>.<suffix>", the names this file's
// writers give their temporary files; nothing for any other name.
std::optional<long> TempFileOwner(const std::string& entry, const std::string& name) {
  const std::string prefix = name + ".tmp.";
  if (entry.size() <= prefix.size() || entry.compare(0, prefix.size(), prefix) != 0) return std::nullopt;
  const char* begin = entry.data() + prefix.size();
  const char* end = entry.data() + entry.size();
  long pid = 0;
  const auto [dot, ec] = std::from_chars(begin, end, pid);
  if (ec != std::errc() || dot == end || *dot != '.' || dot + 1 == end || pid <= 0) return std::nullopt;
  if (!std::all_of(dot + 1, end, [](char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_'; })) {
    return std::nullopt;
  }
  return pid;
}

// A temporary file is a killed writer's when its process is gone, or when the
// process of that id started after the file was last written (the id was reused).
bool LeftByDeadWriter(long pid, const fs::path& file) {
  if (pid == getpid()) return false;  // another thread of this run may be writing it
  if (kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH) return true;
  struct stat st {};
  if (lstat(file.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return false;
  const std::optional<double> started = ProcessStart(pid);
  return started && *started > static_cast<double>(st.st_mtim.tv_sec) + 1.0;
}

}  // namespace

void RemoveStaleTempFiles(const fs::path& path) {
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  const std::string name = path.filename().string();
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string entry = it->path().filename().string();
    const std::optional<long> pid = TempFileOwner(entry, name);
    if (!pid || !it->is_regular_file(ec) || it->is_symlink(ec) || !LeftByDeadWriter(*pid, it->path())) continue;
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
