// Where the viewer's page server and the Foxglove server listen: an IP address
// ("localhost" taken as 127.0.0.1) and a port, refused with the reason when it
// cannot be had, and a warning when the address is not loopback.
#pragma once

#include <cstdint>
#include <string>

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/socket_base.hpp>
#include <spdlog/spdlog.h>

#include "sgslam/common/error.h"

namespace sgslam::viewer {

// Opens, binds and listens on address (normalised in place) and port (0: any
// free one). who: the error's and the warning's prefix ("viewer", "--foxglove");
// exposed: what anyone who can reach another address can do. Returns the address.
// Throws InputError naming address and port.
inline boost::asio::ip::address Listen(boost::asio::ip::tcp::acceptor& acceptor, std::string& address,
                                       std::uint16_t port, const std::string& who, const std::string& exposed) {
  if (address == "localhost") address = "127.0.0.1";
  boost::system::error_code ec;
  const auto ip = boost::asio::ip::make_address(address, ec);
  if (ec) throw InputError(who + ": '" + address + "' is not an IP address");
  if (!ip.is_loopback()) spdlog::warn("{}: serving on {}: anyone who can reach it can {}", who, address, exposed);
  const boost::asio::ip::tcp::endpoint endpoint(ip, port);
  acceptor.open(endpoint.protocol(), ec);
  if (!ec) acceptor.set_option(boost::asio::socket_base::reuse_address(true), ec);
  if (!ec) acceptor.bind(endpoint, ec);
  if (!ec) acceptor.listen(boost::asio::socket_base::max_listen_connections, ec);
  if (ec) throw InputError(who + ": cannot listen on " + address + ":" + std::to_string(port) + ": " + ec.message());
  return ip;
}

}  // namespace sgslam::viewer
