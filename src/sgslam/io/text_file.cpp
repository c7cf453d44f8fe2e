#include "sgslam/io/text_file.h"

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

void WriteFileAtomically(const fs::path& path, const std::string& content) {
  std::error_code ec;
  if (path.has_parent_path()) fs::create_directories(path.parent_path(), ec);
  const fs::path tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError("cannot write file: " + tmp.string());
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.flush();
    if (!out) throw InputError("error while writing file (disk full?): " + tmp.string());
  }
  fs::rename(tmp, path, ec);
  if (ec) throw InputError("cannot rename " + tmp.string() + " to " + path.string() + ": " + ec.message());
}

}  // namespace sgslam
