#include "sgslam/system/run_config.h"

#include <spdlog/spdlog.h>

#include "sgslam/camera/presets.h"
#include "sgslam/config/yaml_io.h"

namespace sgslam {

namespace fs = std::filesystem;

RunConfig ResolveRunConfig(const std::optional<fs::path>& config_file, const fs::path& dataset_dir) {
  RunConfig out;
  std::error_code ec;
  const fs::path local = dataset_dir / "sgslam.yaml";
  if (config_file) {
    LoadConfigFile(*config_file, out.config);
    out.source = config_file->string();
  } else if (fs::is_regular_file(local, ec)) {
    LoadConfigFile(local, out.config);
    out.source = local.string();
  } else if (const auto preset = CameraPresetForFolder(dataset_dir)) {
    out.config.camera = *CameraPreset(*preset);
    out.source = "camera preset " + *preset + " (from the folder name)";
  } else {
    out.source = "defaults (TUM fr1 camera)";
    spdlog::warn("no --config given and the folder name '{}' names no known camera: using the TUM fr1 "
                 "calibration; pass --config configs/<camera>.yaml if this is another camera",
                 dataset_dir.filename().string());
  }
  out.config.Validate(out.source);
  return out;
}

}  // namespace sgslam
