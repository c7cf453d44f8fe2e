// A page of the viewer's server over loopback, for its tests (server_test.cpp,
// server_access_test.cpp): an HTTP request, and the WebSocket the page opens.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <nlohmann/json.hpp>

namespace sgslam::viewer {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;

inline std::string Loopback(std::uint16_t port) { return "127.0.0.1:" + std::to_string(port); }

inline http::response<http::string_body> Get(std::uint16_t port, const std::string& target,
                                             http::verb verb = http::verb::get, const std::string& host = "") {
  net::io_context ioc;
  beast::tcp_stream stream(ioc);
  stream.connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), port));
  http::request<http::empty_body> req(verb, target, 11);
  req.set(http::field::host, host.empty() ? Loopback(port) : host);
  http::write(stream, req);
  beast::flat_buffer buffer;
  http::response<http::string_body> res;
  http::read(stream, buffer, res);
  return res;
}

// The viewer's own page, as a browser opens its WebSocket.
struct Client {
  explicit Client(std::uint16_t port) : ws(ioc) {
    beast::get_lowest_layer(ws).connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), port));
    ws.set_option(websocket::stream_base::decorator(
        [port](websocket::request_type& req) { req.set(http::field::origin, "http://" + Loopback(port)); }));
    ws.handshake(Loopback(port), "/ws");
  }
  void Send(const std::string& text) {
    ws.text(true);
    ws.write(net::buffer(text));
  }
  // The next message's JSON header; throws when the connection is closed.
  nlohmann::json Receive() {
    beast::flat_buffer b;
    ws.read(b);
    const std::string s = beast::buffers_to_string(b.data());
    const std::uint32_t n = static_cast<unsigned char>(s[0]) | static_cast<unsigned char>(s[1]) << 8 |
                            static_cast<unsigned char>(s[2]) << 16 | static_cast<unsigned char>(s[3]) << 24;
    return nlohmann::json::parse(s.substr(4, n));
  }
  bool Closed() {
    try {
      beast::get_lowest_layer(ws).expires_after(std::chrono::seconds(5));
      beast::flat_buffer b;
      ws.read(b);
      return false;
    } catch (const std::exception&) {
      return true;
    }
  }
  net::io_context ioc;
  websocket::stream<beast::tcp_stream> ws;
};

}  // namespace sgslam::viewer
