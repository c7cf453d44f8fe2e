// Inference time of the detection thread per 640x480 frame (blob, forward pass,
// decoding) for both Yolo-Fastest models, with one OpenCV thread (the default
// budget, dnn_detector.h) and with OpenCV's default thread count. The model folder
// is found as `sgslam run` finds it ($SGSLAM_MODEL_DIR, else the shipped models).
#include <benchmark/benchmark.h>

#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "sgslam/detection/dnn_detector.h"

namespace {

using namespace sgslam;

// A real photo when the darknet package is installed (the decoding then has
// objects to decode), else textured noise; both 640x480 like TUM frames.
cv::Mat TestImage() {
  cv::Mat image = cv::imread("/usr/share/darknet/data/person.jpg");
  if (image.empty()) {
    image.create(480, 640, CV_8UC3);
    cv::theRNG().state = 42;
    cv::randu(image, cv::Scalar::all(0), cv::Scalar::all(255));
    cv::GaussianBlur(image, image, cv::Size(9, 9), 3);
  }
  cv::resize(image, image, cv::Size(640, 480));
  return image;
}

// range(0): 0 = yolo-fastest-1.1, 1 = yolo-fastest-1.1-xl; range(1): OpenCV threads (0: OpenCV's default).
void BM_Detect(benchmark::State& state) {
  const int default_threads = cv::getNumThreads();
  DetectorConfig config;
  config.model = state.range(0) == 0 ? "yolo-fastest-1.1" : "yolo-fastest-1.1-xl";
  config.threads = static_cast<int>(state.range(1));
  DnnDetector detector(config);
  state.SetLabel(config.model + (config.threads == 0 ? ", default threads" : ", 1 thread"));
  const cv::Mat image = TestImage();
  detector.Detect(image, 0);  // the first pass allocates and fuses layers
  std::size_t found = 0;
  for (auto _ : state) {
    const auto detections = detector.Detect(image, 0);
    found = detections.size();
    benchmark::DoNotOptimize(detections.data());
  }
  state.counters["detections"] = static_cast<double>(found);
  state.counters["cv_threads"] = cv::getNumThreads();
  cv::setNumThreads(default_threads);  // process-wide: leave it as found
}
BENCHMARK(BM_Detect)
    ->ArgsProduct({{0, 1}, {1, 0}})
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

}  // namespace
