// The viewer's server tests' fixture (server_test.cpp, server_access_test.cpp): a
// folder of the page's files, and a Source whose answers tell what the page asked.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "message.h"
#include "server.h"
#include "support/test_support.h"

namespace sgslam::viewer {

class FakeSource : public Source {
 public:
  std::uint64_t FrameVersion() const override { return version; }
  std::shared_ptr<const std::string> EncodeFrame() override {
    MessageBuilder m("frame");
    m.header()["version"] = version.load();
    return m.Finish();
  }
  std::shared_ptr<const std::string> EncodeMap(const MapRequest& request) override {
    ++maps;
    MessageBuilder m("map");
    m.header()["pieces_after"] = request.pieces_after;
    m.header()["cells_have"] = request.cells_have;
    m.Add("points", std::vector<float>(map_floats, 1.f));
    return m.Finish();
  }
  nlohmann::json Info() const override { return {{"live", true}, {"dataset", "fake"}}; }
  bool Control(const std::string& what, std::uint64_t /*page*/) override {
    std::lock_guard lock(mutex);
    controls.push_back(what);
    return true;
  }
  std::vector<std::string> Controls() {
    std::lock_guard lock(mutex);
    return controls;
  }
  std::atomic<std::uint64_t> version{0};
  std::atomic<int> maps{0};
  std::size_t map_floats = 3;
  std::mutex mutex;
  std::vector<std::string> controls;
};

struct Fixture {
  Fixture() {
    std::ofstream(dir / "index.html") << "<!doctype html><title>t</title>";
    std::ofstream(dir / "app.js") << "export {};";
    std::filesystem::create_directories(dir / "three");
    std::ofstream(dir / "three" / "lib.js") << "export {};";
    std::ofstream(dir / ".hidden") << "secret";
    std::ofstream(dir.path().parent_path() / (dir.path().filename().string() + "-outside.txt")) << "secret";
    options.assets = dir.path();
  }
  test::TempDir dir;
  ServerOptions options;
  FakeSource source;
};

}  // namespace sgslam::viewer
