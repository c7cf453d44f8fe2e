// Locating and loading a Darknet YOLO model (<model>.cfg, <model>.weights and
// coco.names in one folder) with OpenCV dnn, with errors that name the file at
// fault. OpenCV 4.6 silently accepts a truncated weights file or the weights of
// another cfg (both load and run), so the weights size is checked against the
// parameter count of the parsed network.
#pragma once

#include <filesystem>
#include <opencv2/dnn/dnn.hpp>
#include <string>
#include <vector>

namespace sgslam {

// The folder of the models that ship with sgslam, under DataDir() (common/data_dir.h).
inline constexpr const char* kDefaultModelFolder = "yolo-fastest-1.1-coco";
// <DataDir()>/models/yolo-fastest-1.1-coco; empty when DataDir() is not found.
std::filesystem::path DefaultModelDir();

// The model folder: model_dir, else $SGSLAM_MODEL_DIR, else DefaultModelDir().
// Throws InputError when none is found (saying how to give one) or the folder
// does not exist.
std::filesystem::path ResolveModelDir(const std::string& model_dir);

// <dir>/<model>.cfg and <dir>/<model>.weights, the files LoadDarknetModel reads.
std::filesystem::path DarknetCfgPath(const std::filesystem::path& dir, const std::string& model);
std::filesystem::path DarknetWeightsPath(const std::filesystem::path& dir, const std::string& model);
// Both files of the model are in dir (whether they load is LoadDarknetModel's test).
bool DarknetModelPresent(const std::filesystem::path& dir, const std::string& model);

struct DarknetModel {
  cv::dnn::Net net;
  std::vector<std::string> class_names;  // coco.names, line i = class id i
  std::filesystem::path cfg, weights;
};

// score_floor: OpenCV's [yolo] layer zeroes every class score <= its "thresh"
// parameter, 0.2 unless the cfg sets one, which would hide persons scored below
// 0.2; the cfg text is given thresh = score_floor before parsing. Throws
// InputError naming a missing file, a file whose checksum does not match the
// folder's SHA256SUMS (when it has one), a file OpenCV cannot parse, or weights
// that do not fit the cfg.
DarknetModel LoadDarknetModel(const std::filesystem::path& dir, const std::string& model, float score_floor);

}  // namespace sgslam
