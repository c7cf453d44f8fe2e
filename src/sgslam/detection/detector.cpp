#include "sgslam/detection/detector.h"

#include "sgslam/common/error.h"
#include "sgslam/detection/dnn_detector.h"
#include "sgslam/detection/file_detector.h"

namespace sgslam {

std::unique_ptr<Detector> MakeDetector(const DetectorConfig& config, const std::filesystem::path& dataset_dir) {
  if (config.backend == "none") return nullptr;
  if (config.backend == "dnn") return std::make_unique<DnnDetector>(config);
  if (config.backend == "file") {
    const std::filesystem::path file =
        config.detections_file.empty() ? dataset_dir / "detections.txt" : std::filesystem::path(config.detections_file);
    return std::make_unique<FileDetector>(file);
  }
  throw ConfigError("detector.backend = " + config.backend + ": must be dnn, file or none");
}

}  // namespace sgslam
