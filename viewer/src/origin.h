// Who may use the viewer's server: the hosts it answers to, and the pages that may
// open its WebSocket.
//
// A browser lets any page it shows open a WebSocket to any address, and sends the
// page's origin with it; the page's scripts can set neither Origin nor Host. So a
// page from elsewhere (another site, another server on this machine) is told by
// its Origin. A DNS-rebinding page (evil.example resolving to 127.0.0.1) sends an
// Origin that matches its Host, and is told by a Host the server does not answer
// to: a name. IP literals cannot be rebound, and `localhost` is resolved by the
// browser itself.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace sgslam::viewer {

// A web origin. host: lower case; an IPv6 address in brackets.
struct Origin {
  std::string scheme;  // "http" or "https"
  std::string host;
  std::uint16_t port = 0;  // the scheme's default (80, 443) when the text had none
  std::string ToString() const;  // as a browser sends it: the default port left out
  bool operator==(const Origin&) const = default;
};

// "http://host[:port]" or "https://host[:port]", one trailing "/" allowed;
// nothing for anything else (a path, user info, another scheme, "null").
std::optional<Origin> ParseOrigin(std::string_view text);

// An HTTP Host header, "host[:port]". port: none when the header has none.
struct HostHeader {
  std::string host;
  std::optional<std::uint16_t> port;
};
std::optional<HostHeader> ParseHostHeader(std::string_view text);

class AccessRules {
 public:
  enum class Verdict { kAllowed, kUnknownHost, kNoOrigin, kForeignOrigin };

  // loopback: the server listens on a loopback address; port: the one it listens
  // on. allowed: origins (ParseOrigin's form) whose pages may connect too, and
  // whose hosts the server answers to. Throws sgslam::InputError naming one that
  // is not an origin.
  AccessRules(bool loopback, std::uint16_t port, const std::vector<std::string>& allowed);

  // Any request: a loopback host with the server's port; serving on another
  // address, an IP literal too; or an allowed origin's host.
  Verdict CheckHost(std::string_view host) const;
  // The WebSocket: an answered host, and an Origin that is an allowed one or, at
  // a host of the server's own, the page's ("http://" + host).
  Verdict CheckUpgrade(std::string_view host, std::optional<std::string_view> origin) const;

 private:
  bool OwnHost(const HostHeader& h) const;      // loopback, or an IP literal off loopback; the port
  bool AllowedHost(const HostHeader& h) const;  // an allowed origin's
  bool loopback_;
  std::uint16_t port_;
  std::vector<Origin> allowed_;
};

}  // namespace sgslam::viewer
