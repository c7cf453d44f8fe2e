// Binary PLY clouds (io/ply.h), as sgslam view reads cloud.ply and map_points.ply:
// the header's count is checked against the file's size before anything is
// allocated, so no input may return a point the file does not hold.
#include "fuzz_support.h"
#include "sgslam/io/ply.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace sgslam;
  const auto path = fuzz::WriteScratch("cloud.ply", fuzz::Bytes(data, size));
  fuzz::Parse([&] {
    std::vector<Rgb> colours;
    const std::vector<Eigen::Vector3d> points = ReadPlyPoints(path, &colours);
    FUZZ_CHECK(points.size() * 12 <= size);
    FUZZ_CHECK(colours.empty() || colours.size() == points.size());
  });
  return 0;
}
