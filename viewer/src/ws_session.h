// One page's WebSocket for the viewer's server (server.h): reads the page's
// requests and controls, writes at most one message at a time and keeps at most
// Server::kMaxQueued waiting, and closes a page that has gone silent, so that what
// the page held (a pause) ends with it. It knows the server only through the
// Source and the callback that forgets it, so it can be read on its own.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <string>

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include "server.h"

namespace sgslam::viewer {

class WsSession : public std::enable_shared_from_this<WsSession> {
 public:
  // Called once, on close, after source.PageClosed: the server drops the session.
  using ClosedFn = std::function<void(const std::shared_ptr<WsSession>&)>;

  // page: the connection's number (Source::Control's page), never reused.
  WsSession(boost::asio::ip::tcp::socket socket, Source& source, std::uint64_t page, ClosedFn closed);

  // Completes the upgrade that request asked for, then reads the page's messages.
  void Start(boost::beast::http::request<boost::beast::http::string_body> request);

  bool wants_frame() const { return wants_frame_; }
  // The frame the page waits for, if it waits.
  void DeliverFrame(const std::shared_ptr<const std::string>& frame);
  void Close();

 private:
  void Read();
  // One message of the page; false when it is not one of its requests.
  bool Handle(const std::string& text);
  void Send(std::shared_ptr<const std::string> message);
  void Write();

  boost::beast::websocket::stream<boost::beast::tcp_stream> ws_;
  Source& source_;
  const std::uint64_t page_;
  ClosedFn closed_fn_;
  boost::beast::flat_buffer in_;
  std::deque<std::shared_ptr<const std::string>> queue_;
  bool writing_ = false, wants_frame_ = false, closed_ = false;
};

}  // namespace sgslam::viewer
