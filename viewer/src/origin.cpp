#include "origin.h"

#include <arpa/inet.h>
#include <netinet/in.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstring>

#include "sgslam/common/error.h"

namespace sgslam::viewer {

namespace {

constexpr std::uint16_t kHttpPort = 80;

std::string Lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return std::tolower(c); });
  return out;
}

std::uint16_t DefaultPort(const std::string& scheme) { return scheme == "https" ? 443 : kHttpPort; }

bool IsIpv4(const std::string& host) {
  in_addr a{};
  return inet_pton(AF_INET, host.c_str(), &a) == 1;
}

// "[...]" holding an IPv6 address; the address, when it is one.
std::optional<in6_addr> Ipv6(const std::string& host) {
  if (host.size() < 3 || host.front() != '[' || host.back() != ']') return std::nullopt;
  in6_addr a{};
  if (inet_pton(AF_INET6, host.substr(1, host.size() - 2).c_str(), &a) != 1) return std::nullopt;
  return a;
}

// A DNS name's letters (checked only for what they are made of: the comparisons
// are exact, so a name no resolver would take simply never matches).
bool IsName(const std::string& host) {
  return !host.empty() && host.size() <= 253 && std::all_of(host.begin(), host.end(), [](unsigned char c) {
           return std::isalnum(c) || c == '.' || c == '-';
         });
}

bool IsLoopback(const std::string& host) {
  if (host == "localhost") return true;
  if (IsIpv4(host)) return host.rfind("127.", 0) == 0;
  const auto v6 = Ipv6(host);
  return v6 && std::memcmp(&*v6, &in6addr_loopback, sizeof in6addr_loopback) == 0;
}

bool IsIpLiteral(const std::string& host) { return IsIpv4(host) || Ipv6(host).has_value(); }

std::optional<std::uint16_t> ParsePort(std::string_view digits) {
  unsigned value = 0;
  if (digits.empty() || digits.size() > 5) return std::nullopt;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (ec != std::errc() || end != digits.data() + digits.size() || value == 0 || value > 65535) return std::nullopt;
  return static_cast<std::uint16_t>(value);
}

}  // namespace

std::string Origin::ToString() const {
  return scheme + "://" + host + (port == DefaultPort(scheme) ? "" : ":" + std::to_string(port));
}

std::optional<HostHeader> ParseHostHeader(std::string_view text) {
  // The port's colon: after the brackets of an IPv6 address, else the only one.
  const std::size_t after_host = !text.empty() && text[0] == '[' ? text.find(']') : 0;
  if (after_host == std::string_view::npos) return std::nullopt;
  const std::size_t colon = text.find(':', after_host);
  HostHeader h;
  h.host = Lower(text.substr(0, colon));
  if (!IsName(h.host) && !Ipv6(h.host)) return std::nullopt;
  if (colon != std::string_view::npos && !(h.port = ParsePort(text.substr(colon + 1)))) return std::nullopt;
  return h;
}

std::optional<Origin> ParseOrigin(std::string_view text) {
  const std::size_t sep = text.find("://");
  if (sep == std::string_view::npos) return std::nullopt;
  Origin o;
  o.scheme = Lower(text.substr(0, sep));
  if (o.scheme != "http" && o.scheme != "https") return std::nullopt;
  std::string_view authority = text.substr(sep + 3);
  if (!authority.empty() && authority.back() == '/') authority.remove_suffix(1);
  const auto h = ParseHostHeader(authority);  // refuses "/", "@", "?", "#" and the like
  if (!h) return std::nullopt;
  o.host = h->host;
  o.port = h->port.value_or(DefaultPort(o.scheme));
  return o;
}

AccessRules::AccessRules(bool loopback, std::uint16_t port, const std::vector<std::string>& allowed)
    : loopback_(loopback), port_(port) {
  for (const std::string& text : allowed) {
    const auto o = ParseOrigin(text);
    if (!o) throw InputError("viewer: '" + text + "' is not an origin (http://HOST[:PORT] or https://HOST[:PORT])");
    allowed_.push_back(*o);
  }
}

bool AccessRules::OwnHost(const HostHeader& h) const {
  return h.port.value_or(kHttpPort) == port_ && (IsLoopback(h.host) || (!loopback_ && IsIpLiteral(h.host)));
}

bool AccessRules::AllowedHost(const HostHeader& h) const {
  return std::any_of(allowed_.begin(), allowed_.end(), [&](const Origin& o) {
    return o.host == h.host && h.port.value_or(DefaultPort(o.scheme)) == o.port;
  });
}

AccessRules::Verdict AccessRules::CheckHost(std::string_view text) const {
  const auto h = ParseHostHeader(text);
  return h && (OwnHost(*h) || AllowedHost(*h)) ? Verdict::kAllowed : Verdict::kUnknownHost;
}

AccessRules::Verdict AccessRules::CheckUpgrade(std::string_view text, std::optional<std::string_view> origin) const {
  const auto h = ParseHostHeader(text);
  if (!h || !(OwnHost(*h) || AllowedHost(*h))) return Verdict::kUnknownHost;
  if (!origin) return Verdict::kNoOrigin;
  const auto o = ParseOrigin(*origin);
  if (!o) return Verdict::kForeignOrigin;
  // The page's own origin only at a host of the server's own: at an allowed
  // origin's host, the page is that origin (not, say, its plain-http twin).
  const bool own_page =
      OwnHost(*h) && o->scheme == "http" && o->host == h->host && o->port == h->port.value_or(kHttpPort);
  const bool allowed_page = std::find(allowed_.begin(), allowed_.end(), *o) != allowed_.end();
  return own_page || allowed_page ? Verdict::kAllowed : Verdict::kForeignOrigin;
}

}  // namespace sgslam::viewer
