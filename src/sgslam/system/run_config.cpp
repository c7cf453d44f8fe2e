#include "sgslam/system/run_config.h"

#include <spdlog/spdlog.h>

#include "sgslam/camera/presets.h"
#include "sgslam/common/data_dir.h"
#include "sgslam/common/error.h"
#include "sgslam/common/regular_file.h"
#include "sgslam/config/yaml_io.h"

namespace sgslam {

namespace fs = std::filesystem;

fs::path ResolveConfigPath(const fs::path& config) {
  std::error_code ec;
  if (fs::is_regular_file(config, ec)) return config;
  if (config.has_parent_path()) {
    // A folder (or a device) would reach the YAML reader, whose stream error names no file.
    if (fs::exists(config, ec)) {
      throw ConfigError("config file " + config.string() + " " + WhyNotRegularFile(config));
    }
    return config;
  }
  const auto data = DataDir();
  if (!data) {
    throw InputError("config file not found: " + config.string() +
                     " (and the configs shipped with sgslam were not found beside the executable)");
  }
  fs::path shipped = *data / "configs" / config;
  if (!shipped.has_extension()) shipped += ".yaml";
  if (fs::is_regular_file(shipped, ec)) return shipped;
  std::string names;
  for (const auto& entry : fs::directory_iterator(*data / "configs", ec)) {
    if (entry.path().extension() == ".yaml") names += (names.empty() ? "" : ", ") + entry.path().stem().string();
  }
  throw InputError("config file not found: " + config.string() + " (neither a file nor one of the configs shipped in " +
                   (*data / "configs").string() + ": " + names + ")");
}

RunConfig ResolveRunConfig(const std::optional<fs::path>& config_file, const fs::path& dataset_dir) {
  RunConfig out;
  const fs::path local = dataset_dir / "sgslam.yaml";
  // A FIFO or a folder under the name is an error, not a folder without a config.
  const bool has_local = OptionalRegularFile(local, "the dataset's config file").has_value();
  std::optional<fs::path> file;
  if (config_file) file = ResolveConfigPath(*config_file);
  if (!file && has_local) file = local;
  const std::optional<std::string> preset = CameraPresetForFolder(dataset_dir);
  // A file with a camera section describes the camera (keys it omits keep their
  // generic defaults: a readout it does not give is a global shutter); a file
  // without one, such as a panel's orb budget, keeps the camera of the folder.
  if (file && ConfigFileHasSection(*file, "camera")) {
    LoadConfigFile(*file, out.config);
    out.source = file->string();
  } else if (file && has_local && ConfigFileHasSection(local, "camera")) {
    // The folder describes its own camera (sgslam synth writes one): the given
    // file goes on top of the folder's file, camera and all. Before, the TUM fr1
    // camera replaced a synthetic sequence's.
    LoadConfigFile(local, out.config);
    LoadConfigFile(*file, out.config);
    out.source = file->string() + " over " + local.string();
  } else {
    out.config.camera = *CameraPreset(preset.value_or("tum_fr1"));
    out.source = preset ? "camera preset " + *preset + " (from the folder name)" : "defaults (TUM fr1 camera)";
    if (file) {
      LoadConfigFile(*file, out.config);
      out.source = file->string() + " + " + out.source;
    } else if (!preset) {
      spdlog::warn("no --config given and the folder name '{}' names no known camera: using the TUM fr1 "
                   "calibration; pass --config configs/<camera>.yaml if this is another camera",
                   dataset_dir.filename().string());
    }
  }
  out.config.Validate(out.source);
  return out;
}

}  // namespace sgslam
