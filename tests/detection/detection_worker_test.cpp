#include "sgslam/detection/detection_worker.h"

#include <gtest/gtest.h>

#include <future>
#include <stdexcept>
#include <thread>

#include "sgslam/common/stats.h"

namespace sgslam {
namespace {

using std::chrono::milliseconds;

// Lets a test hold the fake detector inside Detect() and know when it got there.
struct Control {
  std::mutex mutex;
  std::condition_variable changed;
  bool open = true;
  int entered = 0;
  int throw_on_class = -1;
  milliseconds sleep{0};
  std::thread::id last_thread;

  void Close() {
    std::lock_guard l(mutex);
    open = false;
  }
  void Open() {
    std::lock_guard l(mutex);
    open = true;
    changed.notify_all();
  }
  void AwaitEntered(int n) {
    std::unique_lock l(mutex);
    changed.wait(l, [&] { return entered >= n; });
  }
};

// Answers one detection whose class id is the image's first pixel and whose box
// encodes the timestamp, so each frame's answer is recognisable.
class FakeDetector final : public Detector {
 public:
  explicit FakeDetector(std::shared_ptr<Control> c) : c_(std::move(c)) {}
  std::vector<Detection> Detect(const cv::Mat& bgr, Timestamp t) override {
    const int id = bgr.at<cv::Vec3b>(0, 0)[0];
    {
      std::unique_lock l(c_->mutex);
      ++c_->entered;
      c_->last_thread = std::this_thread::get_id();
      c_->changed.notify_all();
      c_->changed.wait(l, [&] { return c_->open; });
      if (id == c_->throw_on_class) throw std::runtime_error("detector failed on frame " + std::to_string(id));
    }
    if (c_->sleep.count() > 0) std::this_thread::sleep_for(c_->sleep);
    Detection d;
    d.class_id = id;
    d.class_name = "person";
    d.score = 0.5f;
    d.box = cv::Rect2f(static_cast<float>(t), 0, 10, 20);
    return {d};
  }
  std::string Describe() const override { return "fake"; }

 private:
  std::shared_ptr<Control> c_;
};

cv::Mat Image(int id) { return cv::Mat(4, 4, CV_8UC3, cv::Scalar(id, 0, 0)); }

struct Fixture {
  explicit Fixture(bool sequential = false, std::size_t max_pending = 1)
      : control(std::make_shared<Control>()),
        worker(std::make_unique<FakeDetector>(control), DetectionWorker::Options{sequential, max_pending}) {}
  std::shared_ptr<Control> control;
  DetectionWorker worker;
};

TEST(DetectionWorker, WaitReturnsTheDetectionsOfThatFrame) {
  Fixture f;
  f.control->sleep = milliseconds(5);  // a slow detector
  for (int id = 1; id <= 5; ++id) {
    f.worker.Submit(static_cast<std::uint64_t>(id), 1000 + id, Image(id));
    const auto result = f.worker.WaitResult(static_cast<std::uint64_t>(id), milliseconds(10'000));
    ASSERT_TRUE(result);
    EXPECT_EQ(result->frame_id, static_cast<std::uint64_t>(id));
    EXPECT_EQ(result->t, 1000 + id);
    ASSERT_EQ(result->detections.size(), 1u);
    EXPECT_EQ(result->detections[0].class_id, id);
    EXPECT_EQ(result->detections[0].box.x, 1000.f + static_cast<float>(id));
    EXPECT_GE(result->inference_ms, 4.0);
  }
  EXPECT_NE(f.control->last_thread, std::this_thread::get_id());
  const auto s = f.worker.stats();
  EXPECT_EQ(s.submitted, 5u);
  EXPECT_EQ(s.processed, 5u);
  EXPECT_EQ(s.dropped + s.timeouts + s.errors, 0u);
  EXPECT_GE(s.max_inference_ms, 4.0);
  EXPECT_EQ(f.worker.Describe(), "fake");
}

TEST(DetectionWorker, TimeoutGivesNulloptAndIsCounted) {
  Fixture f;
  f.control->Close();
  f.worker.Submit(1, 1, Image(1));
  EXPECT_FALSE(f.worker.Wait(1, milliseconds(20)));
  EXPECT_EQ(f.worker.stats().timeouts, 1u);
  f.control->Open();
  // The late result of frame 1 is discarded; frame 2 arrives normally.
  f.worker.Submit(2, 2, Image(2));
  const auto second = f.worker.Wait(2, milliseconds(10'000));
  ASSERT_TRUE(second);
  EXPECT_EQ((*second)[0].class_id, 2);
  EXPECT_FALSE(f.worker.Wait(1, milliseconds(0)));  // older than the last waited frame
  EXPECT_EQ(f.worker.stats().timeouts, 1u);
}

TEST(DetectionWorker, DropsTheOldestPendingFrameWhenBusy) {
  Fixture f;
  f.control->Close();
  f.worker.Submit(1, 1, Image(1));
  f.control->AwaitEntered(1);  // the worker is busy with frame 1
  f.worker.Submit(2, 2, Image(2));
  f.worker.Submit(3, 3, Image(3));  // pushes frame 2 out
  const Stopwatch watch;
  EXPECT_FALSE(f.worker.Wait(2, milliseconds(10'000)));  // known dropped: no waiting
  EXPECT_LT(watch.ElapsedMs(), 5'000);
  f.control->Open();
  const auto third = f.worker.Wait(3, milliseconds(10'000));
  ASSERT_TRUE(third);
  EXPECT_EQ((*third)[0].class_id, 3);
  const auto s = f.worker.stats();
  EXPECT_EQ(s.dropped, 1u);
  EXPECT_EQ(s.timeouts, 0u);
  EXPECT_EQ(s.processed, 2u);  // frames 1 and 3
}

TEST(DetectionWorker, ShutdownWakesAWaiter) {
  Fixture f;
  f.control->Close();
  f.worker.Submit(1, 1, Image(1));
  auto waiter = std::async(std::launch::async, [&] { return f.worker.Wait(1, milliseconds(60'000)); });
  f.control->AwaitEntered(1);
  f.worker.Shutdown();
  ASSERT_EQ(waiter.wait_for(std::chrono::seconds(10)), std::future_status::ready);
  EXPECT_FALSE(waiter.get());
  f.control->Open();                // let the worker leave Detect so the destructor can join it
  f.worker.Submit(2, 2, Image(2));  // after Shutdown: dropped, never processed
  EXPECT_FALSE(f.worker.Wait(2, milliseconds(0)));
  EXPECT_EQ(f.worker.stats().dropped, 1u);
}

TEST(DetectionWorker, DetectorExceptionIsRethrownByTheNextWait) {
  Fixture f;
  f.control->throw_on_class = 2;
  f.worker.Submit(1, 1, Image(1));
  ASSERT_TRUE(f.worker.Wait(1, milliseconds(10'000)));
  f.worker.Submit(2, 2, Image(2));
  try {
    f.worker.Wait(2, milliseconds(10'000));
    FAIL() << "the detector's exception was lost";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "detector failed on frame 2");
  }
  // Rethrown once; the worker carries on.
  f.worker.Submit(3, 3, Image(3));
  ASSERT_TRUE(f.worker.Wait(3, milliseconds(10'000)));
  EXPECT_EQ(f.worker.stats().errors, 1u);
}

TEST(DetectionWorker, ExceptionOfAnUnwaitedFrameReachesTheNextWait) {
  Fixture f(/*sequential=*/true);
  f.control->throw_on_class = 1;
  f.worker.Submit(1, 1, Image(1));
  f.worker.Submit(2, 2, Image(2));
  EXPECT_THROW(f.worker.Wait(2, milliseconds(0)), std::runtime_error);
}

TEST(DetectionWorker, SequentialModeGivesTheSameResultsOnTheCallersThread) {
  Fixture threaded, sequential(/*sequential=*/true);
  for (int id = 1; id <= 6; ++id) {
    const auto u = static_cast<std::uint64_t>(id);
    threaded.worker.Submit(u, 100 * id, Image(id));
    sequential.worker.Submit(u, 100 * id, Image(id));
    const auto a = threaded.worker.Wait(u, milliseconds(10'000));
    const auto b = sequential.worker.Wait(u, milliseconds(0));
    ASSERT_TRUE(a && b);
    ASSERT_EQ(a->size(), b->size());
    for (std::size_t i = 0; i < a->size(); ++i) {
      EXPECT_EQ((*a)[i].class_id, (*b)[i].class_id);
      EXPECT_EQ((*a)[i].box, (*b)[i].box);
    }
  }
  EXPECT_EQ(sequential.control->last_thread, std::this_thread::get_id());
  EXPECT_EQ(sequential.worker.stats().processed, 6u);
}

TEST(DetectionWorker, UnknownFramesAndBadIds) {
  Fixture f;
  const Stopwatch watch;
  EXPECT_FALSE(f.worker.Wait(7, milliseconds(10'000)));  // never submitted: nothing to wait for
  EXPECT_LT(watch.ElapsedMs(), 5'000);
  f.worker.Submit(5, 5, Image(5));
  EXPECT_THROW(f.worker.Submit(5, 6, Image(5)), std::invalid_argument);
  EXPECT_THROW(DetectionWorker(nullptr, {}), std::invalid_argument);
}

}  // namespace
}  // namespace sgslam
