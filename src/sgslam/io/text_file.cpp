#include "sgslam/io/text_file.h"

#include <charconv>
#include <cmath>
#include <cstdint>
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

}  // namespace sgslam
