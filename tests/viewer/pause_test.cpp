// The pages' pause (viewer/src/pause.h): held by the pages that paused or stepped,
// ended by "resume" from any page or by the last holder's going; every change that
// lets the run go wakes its thread. Through the server: server_test.cpp.
#include <gtest/gtest.h>
#include <poll.h>

#include "pause.h"

namespace sgslam::viewer {
namespace {

bool Awake(const PauseControl& pause) {
  pollfd p{pause.wake_fd(), POLLIN, 0};
  return poll(&p, 1, 0) == 1;  // no wait: the wake-up is written before the call returns
}

TEST(ViewerPause, ThePagesThatPausedHoldTheRunUntilTheLastGoes) {
  PauseControl pause;
  EXPECT_TRUE(pause.MayGo());
  pause.Pause(1);
  pause.Pause(2);
  pause.Pause(2);
  EXPECT_TRUE(pause.paused());
  EXPECT_FALSE(pause.MayGo());
  EXPECT_FALSE(pause.Release(3));  // held nothing
  EXPECT_FALSE(pause.Release(1));  // 2 holds
  EXPECT_FALSE(Awake(pause));
  EXPECT_FALSE(pause.MayGo());
  EXPECT_TRUE(pause.Release(2));
  EXPECT_TRUE(Awake(pause));
  EXPECT_FALSE(pause.paused());
  EXPECT_TRUE(pause.MayGo());
  EXPECT_FALSE(Awake(pause));  // MayGo took the wake-up
}

TEST(ViewerPause, ResumeFromAnyPageEndsEveryHold) {
  PauseControl pause;
  pause.Pause(1);
  pause.Pause(2);
  pause.Resume();
  EXPECT_TRUE(Awake(pause));
  EXPECT_TRUE(pause.MayGo());
  EXPECT_FALSE(pause.Release(1));  // nothing left to end
}

TEST(ViewerPause, AStepLetsOneFrameThroughAndHolds) {
  PauseControl pause;
  pause.Step(1);
  EXPECT_TRUE(Awake(pause));
  EXPECT_TRUE(pause.MayGo());
  EXPECT_FALSE(pause.MayGo());
  EXPECT_TRUE(pause.paused());
  pause.Step(1);
  pause.Step(1);
  EXPECT_TRUE(pause.MayGo());
  EXPECT_TRUE(pause.MayGo());
  EXPECT_FALSE(pause.MayGo());
  // Steps not taken end with the pause: a later pause is not let through by them.
  pause.Step(2);
  EXPECT_FALSE(pause.Release(2));  // 1 holds
  EXPECT_TRUE(pause.Release(1));
  pause.Pause(3);
  EXPECT_FALSE(pause.MayGo());
}

}  // namespace
}  // namespace sgslam::viewer
