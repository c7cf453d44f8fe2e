// Timestamps are int64 nanoseconds everywhere (docs/architecture.md, "Conventions"). TUM files write
// seconds with up to 9 decimals; parsing the decimal text directly keeps them exact,
// so association and file round trips never suffer from double rounding.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace sgslam {

using Timestamp = std::int64_t;  // ns

constexpr Timestamp kNsPerSecond = 1'000'000'000;

// The largest |time| in seconds: the year 2096 since 1970, so that the difference
// of two times fits in the nanosecond type too.
constexpr std::int64_t kMaxTimestampSeconds = 4'000'000'000;

// Parses "1305031229.528748" (seconds, optional fraction, optional sign, at most
// kMaxTimestampSeconds). Returns nullopt for anything else (the caller names file and line).
std::optional<Timestamp> ParseTimestamp(std::string_view text);

// Seconds with 6 decimals, the precision of the TUM files ("1305031229.528748").
std::string FormatTimestamp(Timestamp t);

inline double ToSeconds(Timestamp t) { return static_cast<double>(t) * 1e-9; }
inline Timestamp FromSeconds(double s) { return static_cast<Timestamp>(s * 1e9 + (s >= 0 ? 0.5 : -0.5)); }

}  // namespace sgslam
