#include "sgslam/io/text_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <charconv>
#include <cmath>
#include <fstream>
#include <system_error>

#include "sgslam/common/error.h"

namespace sgslam {

namespace fs = std::filesystem;

void ForEachDataLine(const fs::path& path,
                     const std::function<void(int, const std::vector<std::string_view>&)>& fn) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw InputError("file not found: " + path.string());
  std::ifstream in(path);
  if (!in) throw InputError("cannot open file: " + path.string());
  std::string line;
  std::vector<std::string_view> tokens;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();  // files written on Windows
    tokens.clear();
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == ',')) ++i;
      const std::size_t start = i;
      while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != ',') ++i;
      if (i > start) tokens.emplace_back(line.data() + start, i - start);
    }
    if (tokens.empty() || tokens[0].front() == '#') continue;
    fn(number, tokens);
  }
  if (in.bad()) throw InputError("error while reading file: " + path.string());
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

}  // namespace

void WriteFileAtomically(const fs::path& path, const std::string& content) {
  std::error_code ec;
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  fs::create_directories(dir, ec);
  // A fresh name created exclusively: a file or link planted under a fixed
  // temporary name is never written through.
  std::string tmp = path.string() + ".tmp.XXXXXX";
  const int fd = mkostemp(tmp.data(), O_CLOEXEC);
  if (fd < 0) throw InputError("cannot write file: " + path.string() + ": " + std::strerror(errno));
  // Complete on disk before it replaces the old file (a power cut leaves one of the two).
  bool ok = WriteAll(fd, content) && fsync(fd) == 0;
  const std::string why = ok ? "" : std::strerror(errno);
  ok = fchmod(fd, 0666 & ~CurrentUmask()) == 0 && ok;  // as an ordinary new file (mkstemp makes it 0600)
  if (close(fd) != 0) ok = false;
  if (!ok) {
    fs::remove(tmp, ec);
    throw InputError("error while writing file (disk full?): " + path.string() + (why.empty() ? "" : ": " + why));
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw InputError("cannot rename " + tmp + " to " + path.string() + ": " + ec.message());
  }
  if (const int d = open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); d >= 0) {
    fsync(d);  // the rename itself
    close(d);
  }
}

}  // namespace sgslam
