#include "sgslam/detection/detections_file.h"

#include <cmath>
#include <cstdio>
#include <string>
#include <string_view>

#include "sgslam/common/error.h"
#include "sgslam/io/atomic_write.h"
#include "sgslam/io/text_file.h"

namespace sgslam {

namespace fs = std::filesystem;

namespace {

bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\r'; }

// Splits off the first `count` whitespace-separated tokens; `rest` is what follows,
// trimmed (the class name, which may hold spaces).
bool SplitFields(std::string_view line, int count, std::vector<std::string_view>& tokens, std::string_view& rest) {
  tokens.clear();
  std::size_t i = 0;
  while (static_cast<int>(tokens.size()) < count) {
    while (i < line.size() && IsSpace(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !IsSpace(line[i])) ++i;
    if (i == start) return false;
    tokens.emplace_back(line.substr(start, i - start));
  }
  while (i < line.size() && IsSpace(line[i])) ++i;
  std::size_t end = line.size();
  while (end > i && IsSpace(line[end - 1])) --end;
  rest = line.substr(i, end - i);
  return !rest.empty();
}

double ParseCorner(std::string_view token, const fs::path& path, int line, const char* what) {
  const double v = ParseNumber(token, path, line, what);
  if (std::abs(v) > kMaxBoxCoordinate) {  // boxes become integer pixel rectangles downstream
    throw ParseError(path.string(), line, std::string(what) + " = " + std::string(token) + " is beyond +-1e6 px");
  }
  return v;
}

Detection ParseDetection(const std::vector<std::string_view>& f, std::string_view name, const fs::path& path,
                         int line) {
  Detection d;
  const double class_id = ParseNumber(f[1], path, line, "class_id");
  if (class_id < 0 || class_id != std::floor(class_id) || class_id > 1e6) {
    throw ParseError(path.string(), line, "class_id must be a non-negative integer, got '" + std::string(f[1]) + "'");
  }
  d.class_id = static_cast<int>(class_id);
  const double score = ParseNumber(f[2], path, line, "score");
  if (score < 0 || score > 1) throw ParseError(path.string(), line, "score must be in [0, 1], got '" + std::string(f[2]) + "'");
  d.score = static_cast<float>(score);
  const double x0 = ParseCorner(f[3], path, line, "x0");
  const double y0 = ParseCorner(f[4], path, line, "y0");
  const double x1 = ParseCorner(f[5], path, line, "x1");
  const double y1 = ParseCorner(f[6], path, line, "y1");
  if (x1 < x0 || y1 < y0) throw ParseError(path.string(), line, "box corners out of order (need x0 <= x1, y0 <= y1)");
  d.box = cv::Rect2f(static_cast<float>(x0), static_cast<float>(y0), static_cast<float>(x1 - x0),
                     static_cast<float>(y1 - y0));
  d.class_name = std::string(name);
  return d;
}

}  // namespace

void WriteDetectionsFile(const fs::path& path, const std::vector<FrameDetections>& frames) {
  std::string text = "# detections: timestamp class_id score x0 y0 x1 y1 class_name (box in px)\n";
  char buf[160];
  for (const auto& [t, detections] : frames) {
    const std::string stamp = FormatTimestamp(t);
    for (const Detection& d : detections) {
      const cv::Rect2f& b = d.box;
      std::snprintf(buf, sizeof buf, " %d %.3f %.3f %.3f %.3f %.3f ", d.class_id, static_cast<double>(d.score),
                    static_cast<double>(b.x), static_cast<double>(b.y), static_cast<double>(b.x + b.width),
                    static_cast<double>(b.y + b.height));
      text += stamp;
      text += buf;
      text += d.class_name;
      text += '\n';
    }
  }
  WriteFileAtomically(path, text);
}

std::map<Timestamp, std::vector<Detection>> ReadDetectionsFile(const fs::path& path) {
  std::map<Timestamp, std::vector<Detection>> result;
  std::vector<std::string_view> fields;
  ForEachTextLine(path, "detections file", [&](int number, std::string_view line) {
    std::size_t first = 0;
    while (first < line.size() && IsSpace(line[first])) ++first;
    if (first == line.size() || line[first] == '#') return;
    std::string_view name;
    if (!SplitFields(line, 7, fields, name)) {
      throw ParseError(path.string(), number,
                       "expected 'timestamp class_id score x0 y0 x1 y1 class_name', got '" + std::string(line) + "'");
    }
    const auto t = ParseTimestamp(fields[0]);
    if (!t) throw ParseError(path.string(), number, "bad timestamp '" + std::string(fields[0]) + "'");
    result[*t].push_back(ParseDetection(fields, name, path, number));
  });
  return result;
}

}  // namespace sgslam
