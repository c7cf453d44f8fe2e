#include "sgslam/movers/tracks_file.h"

#include <cstdio>

#include "sgslam/common/error.h"
#include "sgslam/io/atomic_write.h"
#include "sgslam/io/text_file.h"

namespace sgslam::movers {

namespace {

constexpr char kHeader[] =
    "# mover tracks (sgslam): one line per track per tracked frame, in the frame of trajectory.txt\n"
    "# timestamp id class x y z vx vy vz sx sy sz state   (m, m/s, extent in m along the map axes)\n";

}  // namespace

void WriteTracksFile(const std::filesystem::path& path, const std::vector<TrackLine>& lines) {
  std::string text = kHeader;
  text.reserve(text.size() + lines.size() * 110);
  char buf[256];
  for (const TrackLine& l : lines) {
    std::snprintf(buf, sizeof buf, " %d %s %.4f %.4f %.4f %.3f %.3f %.3f %.3f %.3f %.3f %s\n", l.id,
                  l.class_name.c_str(), l.position.x(), l.position.y(), l.position.z(), l.velocity.x(),
                  l.velocity.y(), l.velocity.z(), l.extent.x(), l.extent.y(), l.extent.z(), StateName(l.state));
    text += FormatTimestamp(l.t);
    text += buf;
  }
  WriteFileAtomically(path, text);
}

std::vector<TrackLine> ReadTracksFile(const std::filesystem::path& path) {
  std::vector<TrackLine> lines;
  ForEachDataLine(path, [&](int line, const std::vector<std::string_view>& tok) {
    if (tok.size() != 13) {
      throw ParseError(path.string(), line, "expected 13 fields (timestamp id class x y z vx vy vz sx sy sz state), got " +
                                                std::to_string(tok.size()));
    }
    TrackLine l;
    const auto t = ParseTimestamp(tok[0]);
    if (!t) throw ParseError(path.string(), line, "bad timestamp '" + std::string(tok[0]) + "'");
    l.t = *t;
    const double id = ParseNumber(tok[1], path, line, "id");
    if (id < 0 || id != static_cast<int>(id)) throw ParseError(path.string(), line, "bad id '" + std::string(tok[1]) + "'");
    l.id = static_cast<int>(id);
    l.class_name = std::string(tok[2]);
    for (int a = 0; a < 3; ++a) {
      l.position[a] = ParseNumber(tok[3 + a], path, line, "position");
      l.velocity[a] = ParseNumber(tok[6 + a], path, line, "velocity");
      l.extent[a] = ParseNumber(tok[9 + a], path, line, "extent");
    }
    const std::string_view s = tok[12];
    if (s == "tentative") {
      l.state = TrackState::kTentative;
    } else if (s == "confirmed") {
      l.state = TrackState::kConfirmed;
    } else if (s == "lost") {
      l.state = TrackState::kLost;
    } else {
      throw ParseError(path.string(), line, "bad state '" + std::string(s) + "' (tentative, confirmed or lost)");
    }
    lines.push_back(std::move(l));
  });
  return lines;
}

}  // namespace sgslam::movers
