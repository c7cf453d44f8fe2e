#include "message.h"

namespace sgslam::viewer {

namespace {

void PadTo4(std::string& s) { s.append((4 - s.size() % 4) % 4, '\0'); }

}  // namespace

void MessageBuilder::AddRaw(const std::string& name, const char* type, const void* data, std::size_t count,
                            std::size_t size) {
  header_["buffers"].push_back(
      {{"name", name}, {"type", type}, {"count", count}, {"offset", body_.size()}, {"bytes", count * size}});
  body_.append(static_cast<const char*>(data), count * size);
  PadTo4(body_);
}

std::vector<float> ColumnMajor(const SE3& T) {
  const Eigen::Matrix4d m = T.matrix();
  std::vector<float> out(16);
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) out[4 * c + r] = static_cast<float>(m(r, c));
  }
  return out;
}

std::shared_ptr<const std::string> MessageBuilder::Finish() const {
  nlohmann::json header = header_;
  if (!header.contains("buffers")) header["buffers"] = nlohmann::json::array();
  std::string text = header.dump();
  auto out = std::make_shared<std::string>();
  const auto n = static_cast<std::uint32_t>(text.size());
  const unsigned char len[4] = {static_cast<unsigned char>(n), static_cast<unsigned char>(n >> 8),
                                static_cast<unsigned char>(n >> 16), static_cast<unsigned char>(n >> 24)};
  out->reserve(4 + text.size() + 3 + body_.size());
  out->append(reinterpret_cast<const char*>(len), 4);
  out->append(text);
  PadTo4(*out);
  out->append(body_);
  return out;
}

}  // namespace sgslam::viewer
