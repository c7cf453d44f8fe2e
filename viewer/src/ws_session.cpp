#include "ws_session.h"

#include <chrono>
#include <utility>

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

namespace sgslam::viewer {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;

namespace {

constexpr std::size_t kMaxPageMessage = 1024;  // what the page sends is a line of JSON
// A page that neither sends nor answers a ping for this long is gone (a laptop shut,
// a network lost: no FIN comes) and its connection closed, ending its pause. A
// browser answers pings even for a page in the background, but not while a
// message to it is still being written, when the page sends nothing either: the
// time is long enough for a whole live map (up to 8 MB) over a 1 Mbit/s link.
constexpr auto kPageIdleTimeout = std::chrono::seconds(60);

}  // namespace

WsSession::WsSession(tcp::socket socket, Source& source, std::uint64_t page, ClosedFn closed)
    : ws_(std::move(socket)), source_(source), page_(page), closed_fn_(std::move(closed)) {}

void WsSession::Start(http::request<http::string_body> request) {
  auto timeout = websocket::stream_base::timeout::suggested(beast::role_type::server);
  timeout.idle_timeout = kPageIdleTimeout;
  timeout.keep_alive_pings = true;
  ws_.set_option(timeout);
  ws_.read_message_max(kMaxPageMessage);
  ws_.binary(true);
  ws_.async_accept(request, [self = shared_from_this()](beast::error_code ec) {
    if (ec) return self->Close();
    self->Read();
  });
}

void WsSession::DeliverFrame(const std::shared_ptr<const std::string>& frame) {
  if (!wants_frame_ || !frame) return;
  wants_frame_ = false;
  Send(frame);
}

void WsSession::Close() {
  if (closed_) return;
  closed_ = true;
  beast::error_code ignored;
  beast::get_lowest_layer(ws_).socket().shutdown(tcp::socket::shutdown_both, ignored);
  beast::get_lowest_layer(ws_).socket().close(ignored);
  source_.PageClosed(page_);  // before the server forgets it: clients() then tells it is done
  closed_fn_(shared_from_this());
}

void WsSession::Read() {
  ws_.async_read(in_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
    if (ec) return self->Close();
    const bool ok = self->ws_.got_text() && self->Handle(beast::buffers_to_string(self->in_.data()));
    self->in_.consume(self->in_.size());
    if (!ok) {
      spdlog::warn("viewer: a page sent a message that is not a request; its connection is closed");
      return self->Close();
    }
    self->Read();
  });
}

// {"get": "frame", "have": N} | {"get": "map", "pieces_after": ID[, "cells_have": V]} | {"get": "info"}
// | {"control": "pause"}
bool WsSession::Handle(const std::string& text) {
  const nlohmann::json m = nlohmann::json::parse(text, nullptr, false);
  if (!m.is_object()) return false;
  if (m.contains("control")) {
    if (!m["control"].is_string()) return false;
    source_.Control(m["control"].get<std::string>(), page_);
    return true;
  }
  if (!m.contains("get") || !m["get"].is_string()) return false;
  const std::string what = m["get"].get<std::string>();
  if (what == "info") {
    nlohmann::json info = source_.Info();
    info["type"] = "info";
    const std::string text_out = info.dump();
    std::string msg(4, '\0');
    for (int i = 0; i < 4; ++i) msg[i] = static_cast<char>((text_out.size() >> (8 * i)) & 0xff);
    msg += text_out;
    msg.append((4 - msg.size() % 4) % 4, '\0');
    Send(std::make_shared<const std::string>(std::move(msg)));
  } else if (what == "frame") {
    if (!m.contains("have") || !m["have"].is_number_unsigned()) return false;
    wants_frame_ = true;
    if (source_.FrameVersion() > m["have"].get<std::uint64_t>()) DeliverFrame(source_.EncodeFrame());
  } else if (what == "map") {
    if (!m.contains("pieces_after") || !m["pieces_after"].is_number_integer()) return false;
    Source::MapRequest request;
    request.pieces_after = m["pieces_after"].get<std::int64_t>();
    if (m.contains("cells_have")) {
      if (!m["cells_have"].is_number_unsigned()) return false;
      request.cells_have = m["cells_have"].get<std::uint64_t>();
    }
    if (auto map = source_.EncodeMap(request)) Send(map);
  } else {
    return false;
  }
  return true;
}

void WsSession::Send(std::shared_ptr<const std::string> message) {
  if (closed_) return;
  // Full: drop the oldest waiting message (never the one being written).
  if (queue_.size() >= Server::kMaxQueued) queue_.erase(queue_.begin() + (writing_ ? 1 : 0));
  queue_.push_back(std::move(message));
  if (!writing_) Write();
}

void WsSession::Write() {
  writing_ = true;
  ws_.async_write(net::buffer(*queue_.front()), [self = shared_from_this()](beast::error_code ec, std::size_t) {
    self->queue_.pop_front();
    self->writing_ = false;
    if (ec) return self->Close();
    if (!self->queue_.empty()) self->Write();
  });
}

}  // namespace sgslam::viewer
