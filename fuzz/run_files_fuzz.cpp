// The files of a finished run that sgslam view reads besides trajectories and
// clouds (viewer/src/run_folder_files.h): stats.json, objects.json and octomap.bt.
// The input holds them one after the other, separated by a line "@@"; a file the
// input does not reach is absent (and not read, as the viewer skips it).
#include <array>
#include <cmath>

#include "fuzz_support.h"
#include "run_folder_files.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace sgslam;
  static constexpr std::string_view kSeparator = "\n@@\n";
  std::array<bool, 3> present{};
  std::string_view rest = fuzz::Bytes(data, size);
  const std::array<const char*, 3> names = {"stats.json", "objects.json", "octomap.bt"};
  for (std::size_t i = 0; i < names.size(); ++i) {
    present[i] = i == 0 || !rest.empty();
    if (!present[i]) continue;
    const std::size_t end = rest.find(kSeparator);
    fuzz::WriteScratch(names[i], rest.substr(0, end));
    rest = end == std::string_view::npos ? std::string_view() : rest.substr(end + kSeparator.size());
  }
  fuzz::Parse([&] {
    const auto dir = fuzz::ScratchDir();
    if (present[0]) viewer::ReadRunStats(dir / names[0]);
    if (present[1]) FUZZ_CHECK(viewer::ReadRunObjects(dir / names[1]).is_array());
    if (!present[2]) return;
    const std::vector<float> cells = viewer::ReadOccupiedCells(dir / names[2]);
    FUZZ_CHECK(cells.size() % 4 == 0);
    for (const float v : cells) FUZZ_CHECK(std::isfinite(v));
  });
  return 0;
}
