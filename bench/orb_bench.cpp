// ORB extraction as tracking calls it once per frame: 640x480, 1000 features,
// 8 levels (ORB-SLAM2's settings). Uses the first image of TUM fr1/rpy when the
// shared data folder is found ($SGSLAM_SHARED_DIR, else ../shared or
// ../../shared from the working directory, else beside the source tree),
// otherwise a synthetic texture, and
// says which in the label. Also the Hamming distance every matcher calls.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <random>
#include <string>

#include "sgslam/features/hamming.h"
#include "sgslam/features/orb_extractor.h"

namespace {

namespace fs = std::filesystem;
using namespace sgslam;

struct BenchImage {
  cv::Mat gray;
  std::string label;
};

std::optional<fs::path> FirstTumImage() {
  std::vector<fs::path> roots;
  if (const char* env = std::getenv("SGSLAM_SHARED_DIR")) roots.emplace_back(env);
  roots.emplace_back("../shared");
  roots.emplace_back("../../shared");
  roots.emplace_back(fs::path(__FILE__).parent_path().parent_path().parent_path() /
                     "shared");  // beside the source tree
  for (const fs::path& root : roots) {
    const fs::path rgb = root / "data" / "tum_fr1_rpy" / "rgb";
    std::error_code ec;
    if (!fs::is_directory(rgb, ec)) continue;
    std::vector<fs::path> images;
    for (const auto& e : fs::directory_iterator(rgb, ec)) {
      if (e.path().extension() == ".png" || e.path().extension() == ".jpg") images.push_back(e.path());
    }
    if (!images.empty()) return *std::min_element(images.begin(), images.end());
  }
  return std::nullopt;
}

BenchImage LoadImage() {
  if (const auto path = FirstTumImage()) {
    cv::Mat gray = cv::imread(path->string(), cv::IMREAD_GRAYSCALE);
    if (!gray.empty()) return {gray, "tum_fr1_rpy/" + path->filename().string()};
  }
  // Fallback: seeded random blocks, which give FAST more corners than a real room.
  cv::Mat gray(480, 640, CV_8UC1, cv::Scalar(128));
  std::mt19937 rng(1);
  std::uniform_int_distribution<int> x(0, 639), y(0, 479), side(4, 24), grey(0, 255);
  for (int i = 0; i < 5000; ++i)
    gray(cv::Rect(x(rng), y(rng), side(rng), side(rng)) & cv::Rect(0, 0, 640, 480)).setTo(grey(rng));
  cv::GaussianBlur(gray, gray, cv::Size(3, 3), 0.8);
  return {gray, "synthetic texture (TUM fr1/rpy not found; set SGSLAM_SHARED_DIR)"};
}

// Arg: extraction threads (2: levels split with a helper thread, as in parallel
// runs without a detector).
void BM_OrbExtract(benchmark::State& state) {
  const BenchImage image = LoadImage();
  features::OrbExtractor orb(OrbConfig{});
  orb.set_threads(static_cast<int>(state.range(0)));
  std::vector<cv::KeyPoint> kps;
  cv::Mat desc;
  for (auto _ : state) {
    orb.Extract(image.gray, kps, desc);
    benchmark::DoNotOptimize(desc.data);
  }
  state.counters["keypoints"] = static_cast<double>(kps.size());
  state.SetLabel(image.label);
}
BENCHMARK(BM_OrbExtract)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// One descriptor against 1000 others: the inner loop of a brute-force search.
void BM_Hamming1000(benchmark::State& state) {
  std::mt19937 rng(2);
  std::uniform_int_distribution<int> byte(0, 255);
  cv::Mat desc(1001, 32, CV_8U);
  for (int r = 0; r < desc.rows; ++r) {
    for (int c = 0; c < 32; ++c) desc.at<uint8_t>(r, c) = static_cast<uint8_t>(byte(rng));
  }
  const uint8_t* query = desc.ptr<uint8_t>(1000);
  for (auto _ : state) {
    int best = 257;
    for (int r = 0; r < 1000; ++r) best = std::min(best, features::HammingDistance(query, desc.ptr<uint8_t>(r)));
    benchmark::DoNotOptimize(best);
  }
  state.SetItemsProcessed(state.iterations() * 1000);
}
BENCHMARK(BM_Hamming1000);

}  // namespace
