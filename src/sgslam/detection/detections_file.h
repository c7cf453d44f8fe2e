// Detections files: one detection a line,
//   timestamp class_id score x0 y0 x1 y1 class_name
// with the box corners in pixels (x1 = x0 + width) and the class name last, so it
// may contain spaces ("potted plant"). Lines starting with '#' are comments.
// `sgslam synth` writes ground-truth detections in this format; the detection
// module reads them to replay detections instead of running a network.
#pragma once

#include <filesystem>
#include <map>
#include <utility>
#include <vector>

#include "sgslam/common/time.h"
#include "sgslam/detection/detection.h"

namespace sgslam {

using FrameDetections = std::pair<Timestamp, std::vector<Detection>>;

// The farthest a box corner may lie from the image origin, px: far beyond any
// image, and far from int's range, where the pixel rectangles made of boxes live.
inline constexpr double kMaxBoxCoordinate = 1e6;

// Writes atomically; frames without detections leave no line. Timestamps with 6
// decimals (FormatTimestamp), score and corners with 3.
void WriteDetectionsFile(const std::filesystem::path& path, const std::vector<FrameDetections>& frames);

// Reads every detection, grouped by timestamp in file order. Throws InputError for a
// missing file, one that is not a regular file or one too large (io/text_file.h's
// ForEachTextLine), and ParseError (file:line) for a malformed line: a score outside
// [0, 1], a corner beyond kMaxBoxCoordinate, or corners out of order, say.
std::map<Timestamp, std::vector<Detection>> ReadDetectionsFile(const std::filesystem::path& path);

}  // namespace sgslam
