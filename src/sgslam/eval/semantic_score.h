// How much of the semantic map comes from things that moved, against ground-truth
// dynamic masks (sgslam synth and dyn_dev carry them: mask.txt + mask/*.png, 255 =
// moving). Read after the run from the finished map, outside the runtime path.
#pragma once

#include <cstddef>
#include <functional>

#include <opencv2/core.hpp>

#include "sgslam/common/time.h"
#include "sgslam/semantic/semantic_mapper.h"

namespace sgslam::eval {

// The mask of a timestamp; empty when there is none.
using ImageOf = std::function<cv::Mat(Timestamp)>;

struct CloudTruth {
  std::size_t keyframes = 0, points = 0, moving = 0;
};
// The exported cloud's points that come from moving pixels, each re-projected into
// the keyframe it came from. After SemanticMapper::ExportCloud.
CloudTruth ScoreCloud(const SemanticMapper& map, const ImageOf& mask_of);

struct OctoMapTruth {
  std::size_t keyframes = 0, path_cells = 0, occupied = 0;
};
// The movers' swept volume in the OctoMap: the cells (at its resolution) that the
// keyframes' ground-truth moving pixels fall in with the final poses, less those
// within one cell of any static pixel's (the floor under a foot, the desk behind a
// hand: noise, not the path), and how many of them ended occupied. depth_of: the
// raw depth image of a timestamp. After SemanticMapper::ExportCloud.
OctoMapTruth ScoreOctoMap(const SemanticMapper& map, const ImageOf& mask_of, const ImageOf& depth_of, int stride = 2);

}  // namespace sgslam::eval
