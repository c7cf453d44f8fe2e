#include "sgslam/common/time.h"

#include <cstdio>
#include <cstdlib>

namespace sgslam {

std::optional<Timestamp> ParseTimestamp(std::string_view text) {
  if (text.empty()) return std::nullopt;
  bool negative = false;
  std::size_t i = 0;
  if (text[0] == '-' || text[0] == '+') {
    negative = text[0] == '-';
    i = 1;
  }
  std::int64_t seconds = 0;
  std::int64_t nanos = 0;
  int integer_digits = 0;
  for (; i < text.size() && text[i] != '.'; ++i) {
    const char c = text[i];
    if (c < '0' || c > '9' || integer_digits >= 11) return std::nullopt;
    seconds = seconds * 10 + (c - '0');
    ++integer_digits;
  }
  int fraction_digits = 0;
  if (i < text.size()) {  // text[i] == '.'
    for (++i; i < text.size(); ++i) {
      const char c = text[i];
      if (c < '0' || c > '9') return std::nullopt;
      if (fraction_digits < 9) nanos = nanos * 10 + (c - '0');
      ++fraction_digits;
    }
  }
  if (integer_digits == 0 && fraction_digits == 0) return std::nullopt;
  if (seconds > kMaxTimestampSeconds || (seconds == kMaxTimestampSeconds && nanos > 0)) return std::nullopt;
  for (int d = fraction_digits; d < 9; ++d) nanos *= 10;
  const Timestamp t = seconds * kNsPerSecond + nanos;
  return negative ? -t : t;
}

std::string FormatTimestamp(Timestamp t) {
  // Round to microseconds, then print seconds.micros.
  const bool negative = t < 0;
  const std::int64_t a = negative ? -t : t;
  const std::int64_t micros = (a + 500) / 1000;
  char buf[48];
  std::snprintf(buf, sizeof buf, "%s%lld.%06lld", negative ? "-" : "",
                static_cast<long long>(micros / 1'000'000), static_cast<long long>(micros % 1'000'000));
  return buf;
}

}  // namespace sgslam
