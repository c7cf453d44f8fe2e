// Detections files (detection/detections_file.h), which the file detector replays.
#include <cmath>

#include "fuzz_support.h"
#include "sgslam/detection/detections_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace sgslam;
  const auto path = fuzz::WriteScratch("detections.txt", fuzz::Bytes(data, size));
  fuzz::Parse([&] {
    for (const auto& [t, detections] : ReadDetectionsFile(path)) {
      FUZZ_CHECK(!detections.empty());
      for (const Detection& d : detections) {
        FUZZ_CHECK(d.class_id >= 0 && !d.class_name.empty());
        FUZZ_CHECK(std::isfinite(d.score));
        FUZZ_CHECK(std::isfinite(d.box.x) && std::isfinite(d.box.y) && std::isfinite(d.box.width) &&
                   std::isfinite(d.box.height) && d.box.width >= 0 && d.box.height >= 0);
      }
    }
  });
  return 0;
}
