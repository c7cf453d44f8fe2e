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
        FUZZ_CHECK(d.score >= 0 && d.score <= 1);
        // Corners within 1e6 px of 0: finite, and safe to cast to int.
        FUZZ_CHECK(std::abs(d.box.x) <= 1e6f && std::abs(d.box.y) <= 1e6f);
        FUZZ_CHECK(d.box.width >= 0 && d.box.height >= 0 && d.box.width <= 2e6f && d.box.height <= 2e6f);
      }
    }
  });
  return 0;
}
