// The lists of a TUM RGB-D folder (io/tum_dataset.h): rgb.txt and depth.txt, paired
// by AssociateByTime (io/association.h), or associations.txt; all read with
// ForEachDataLine (io/text_file.h). The input holds the files one after the other,
// separated by a line "@@": rgb.txt, depth.txt, associations.txt; a file the input
// does not reach is absent from the folder.
#include <algorithm>
#include <array>
#include <cstdlib>

#include "fuzz_support.h"
#include "sgslam/io/tum_dataset.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace sgslam;
  static constexpr std::string_view kSeparator = "\n@@\n";
  static const std::array<std::string, 3> kFiles = {"rgb.txt", "depth.txt", "associations.txt"};
  std::string_view rest = fuzz::Bytes(data, size);
  bool more = true;
  for (const std::string& file : kFiles) {
    if (!more) {
      fuzz::RemoveScratch(file);
      continue;
    }
    const std::size_t end = rest.find(kSeparator);
    more = end != std::string_view::npos;
    fuzz::WriteScratch(file, rest.substr(0, end));
    rest = more ? rest.substr(end + kSeparator.size()) : std::string_view();
  }
  fuzz::Parse([&] {
    const TumDataset dataset(fuzz::ScratchDir(), DatasetConfig{});
    FUZZ_CHECK(dataset.size() > 0);
    FUZZ_CHECK(std::is_sorted(dataset.frames().begin(), dataset.frames().end(),
                              [](const FrameRecord& a, const FrameRecord& b) { return a.t_rgb < b.t_rgb; }));
    const Timestamp window = FromSeconds(DatasetConfig{}.max_time_difference);
    for (const FrameRecord& f : dataset.frames()) {
      FUZZ_CHECK(!f.listed_at.empty());
      FUZZ_CHECK(dataset.associations_from_file() || std::llabs(f.t_rgb - f.t_depth) < window);
    }
  });
  return 0;
}
