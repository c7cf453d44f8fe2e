#include "sgslam/io/text_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <atomic>
#include <charconv>
#include <cmath>
#include <fstream>
#include <system_error>

#include "sgslam/common/error.h"
#include "sgslam/common/regular_file.h"

namespace sgslam {

namespace fs = std::filesystem;

namespace {

// No TUM list, trajectory or detections file comes near these: an hour at 100 Hz
// is 30 MB, and a line holds a few numbers and a path of at most PATH_MAX (4096)
// bytes. A file beyond them is the wrong file, refused before it costs memory.
constexpr std::uint64_t kMaxTextFileBytes = std::uint64_t{1} << 30;
constexpr std::size_t kMaxTextLineBytes = 64 * 1024;

}  // namespace

void ForEachTextLine(const fs::path& path, const std::string& what,
                     const std::function<void(int line, std::string_view text)>& fn) {
  RegularFile(path, what).ForEachLine(kMaxTextFileBytes, kMaxTextLineBytes, [&](int number, std::string_view line) {
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);  // files written on Windows
    if (line.find('\0') != std::string_view::npos) {  // a path would end at it and name another file
      throw ParseError(path.string(), number, "a NUL byte in the line (a binary file, or a corrupted one?)");
    }
    fn(number, line);
  });
}

void ForEachDataLine(const fs::path& path,
                     const std::function<void(int, const std::vector<std::string_view>&)>& fn) {
  std::vector<std::string_view> tokens;
  ForEachTextLine(path, "file", [&](int number, std::string_view line) {
    tokens.clear();
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == ',')) ++i;
      const std::size_t start = i;
      while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != ',') ++i;
      if (i > start) tokens.emplace_back(line.data() + start, i - start);
    }
    if (tokens.empty() || tokens[0].front() == '#') return;
    fn(number, tokens);
  });
}

double ParseNumber(std::string_view token, const fs::path& path, int line, const char* what) {
  double value = 0;
  const char* end = token.data() + token.size();
  auto [ptr, ec] = std::from_chars(token.data(), end, value);
  if (ec != std::errc() || ptr != end || !std::isfinite(value)) {
    throw ParseError(path.string(), line, std::string("expected a number for ") + what + ", got '" +
                                              std::string(token) + "'");
  }
  return value;
}

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
  tmp.name = path.string() + ".tmp.XXXXXX";
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

}  // namespace

void WriteFileAtomically(const fs::path& path, const std::string& content) {
  std::error_code ec;
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  fs::create_directories(dir, ec);
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
