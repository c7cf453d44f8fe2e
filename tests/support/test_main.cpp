// The main of every test program. Before any test starts a thread it gives OpenCV
// the process-wide thread budget `sgslam run` and the ROS node give it
// (detector.threads; detection/dnn_detector.h), so that a test's run of the system
// is the programs' run.
#include <gtest/gtest.h>

#include <opencv2/core/utility.hpp>

#include "sgslam/detection/detector_config.h"

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  if (const int threads = sgslam::DetectorConfig{}.threads; threads > 0) cv::setNumThreads(threads);
  return RUN_ALL_TESTS();
}
