// The viewer's binary WebSocket messages: a JSON header, then raw arrays.
//   u32 (little-endian) header length | header (UTF-8 JSON) | zero padding to 4 |
//   the buffers one after another, each padded to 4 bytes.
// The header's "buffers" lists them: name, type (f32, u32, u8), count, offset from
// the start of the buffer area and bytes, so the page reads each as a typed array
// without copying (viewer/web/protocol.js).
#pragma once

#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sgslam/common/se3.h"

namespace sgslam::viewer {

class MessageBuilder {
 public:
  explicit MessageBuilder(std::string type) { header_["type"] = std::move(type); }

  nlohmann::json& header() { return header_; }

  void Add(const std::string& name, const std::vector<float>& v) { AddRaw(name, "f32", v.data(), v.size(), 4); }
  void Add(const std::string& name, const std::vector<std::uint32_t>& v) {
    AddRaw(name, "u32", v.data(), v.size(), 4);
  }
  void Add(const std::string& name, const std::vector<std::uint8_t>& v) { AddRaw(name, "u8", v.data(), v.size(), 1); }

  // The whole message, ready to send as one binary frame.
  std::shared_ptr<const std::string> Finish() const;

 private:
  void AddRaw(const std::string& name, const char* type, const void* data, std::size_t count, std::size_t size);

  nlohmann::json header_;
  std::string body_;
};

// A pose as 16 floats, column-major, as three.js's Matrix4.fromArray reads it.
std::vector<float> ColumnMajor(const SE3& T);

}  // namespace sgslam::viewer
