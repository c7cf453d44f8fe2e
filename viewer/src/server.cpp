#include "server.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <optional>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <spdlog/spdlog.h>

#include "listen.h"
#include "origin.h"
#include "sgslam/common/data_dir.h"
#include "sgslam/common/error.h"
#include "sgslam/common/thread_name.h"
#include "ws_session.h"

namespace sgslam::viewer {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;

namespace {

constexpr std::size_t kMaxRequestBytes = 8 * 1024;  // an HTTP request's header and body
constexpr auto kHttpTimeout = std::chrono::seconds(30);

const char* ContentType(const std::filesystem::path& p) {
  const std::string e = p.extension().string();
  if (e == ".html") return "text/html; charset=utf-8";
  if (e == ".js") return "text/javascript; charset=utf-8";
  if (e == ".css") return "text/css; charset=utf-8";
  if (e == ".png") return "image/png";
  if (e == ".svg") return "image/svg+xml";
  return "application/octet-stream";
}

// The file under root that target names, or nothing: only plain names of letters,
// digits and ._- in folders, no "..", no hidden files, no folders themselves.
std::optional<std::filesystem::path> AssetPath(const std::filesystem::path& root, std::string_view target) {
  if (const auto q = target.find_first_of("?#"); q != std::string_view::npos) target = target.substr(0, q);
  if (target.empty() || target[0] != '/') return std::nullopt;
  std::string rel(target.substr(1));
  if (rel.empty()) rel = "index.html";
  if (rel.size() > 200) return std::nullopt;
  for (char c : rel) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '_' && c != '-' && c != '/') return std::nullopt;
  }
  std::stringstream parts(rel);
  for (std::string part; std::getline(parts, part, '/');) {
    if (part.empty() || part[0] == '.') return std::nullopt;
  }
  std::error_code ec;
  const std::filesystem::path p = root / rel;
  if (!std::filesystem::is_regular_file(p, ec)) return std::nullopt;
  const auto canonical = std::filesystem::canonical(p, ec);
  if (ec) return std::nullopt;
  const auto root_c = std::filesystem::canonical(root, ec);
  if (ec) return std::nullopt;
  const auto [r, c] = std::mismatch(root_c.begin(), root_c.end(), canonical.begin(), canonical.end());
  if (r != root_c.end()) return std::nullopt;  // a link out of the assets
  return canonical;
}

// A header's value for the log: printable, and short (a hostile page chooses it).
std::string Printable(std::string_view s) {
  constexpr std::size_t kMax = 100;
  std::string out;
  for (char c : s.substr(0, kMax)) out += std::isprint(static_cast<unsigned char>(c)) ? c : '?';
  return s.size() > kMax ? out + "..." : out;
}

std::optional<std::string> ReadWhole(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream s;
  s << in.rdbuf();
  if (!in && !in.eof()) return std::nullopt;
  return s.str();
}

}  // namespace

struct Server::Impl {
  Impl(ServerOptions o, Source& s) : options(std::move(o)), source(s) {}

  void Accept();
  void StartHttp(tcp::socket socket);
  void Deliver();  // on the server's thread: the new frame to the pages waiting
  // Logs a refusal the first time one of its kind comes: a hostile page may try
  // again and again, and the log is the user's.
  void LogRefusal(AccessRules::Verdict verdict, std::string_view host, std::string_view origin);

  ServerOptions options;
  Source& source;
  net::io_context ioc{1};
  tcp::acceptor acceptor{ioc};
  std::optional<AccessRules> rules;  // set once the port is known
  std::string hosts_text;            // the hosts they answer to, for the log
  // The server's thread only:
  std::set<std::shared_ptr<WsSession>> sessions;
  std::uint64_t pages_opened = 0;  // the next connection's number (Source::Control's page)
  std::array<bool, 4> refusal_logged{};  // by AccessRules::Verdict
  std::atomic<std::size_t> clients{0};
  std::uint16_t port = 0;
  std::thread thread;
};

// One HTTP connection: files until it asks to become the WebSocket.
class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(tcp::socket socket, Server::Impl& server) : stream_(std::move(socket)), server_(server) {}

  void Read() {
    parser_.emplace();
    parser_->header_limit(kMaxRequestBytes);
    parser_->body_limit(kMaxRequestBytes);
    stream_.expires_after(kHttpTimeout);
    http::async_read(stream_, buffer_, *parser_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) return self->Close();
      self->Handle(self->parser_->release());
    });
  }

 private:
  void Handle(http::request<http::string_body> req) {
    // The files are checked for their Host too, though they are no secret: a page
    // at a name the server does not answer to could not open the WebSocket anyway,
    // and the user who typed that name is better told at once, with the reason.
    const std::string_view host = req[http::field::host];
    if (const auto v = server_.rules->CheckHost(host); v != AccessRules::Verdict::kAllowed) {
      return Refuse(req, v, "");
    }
    if (websocket::is_upgrade(req)) {
      if (req.target() != "/ws") return Close();
      const auto origin = req.find(http::field::origin);
      const auto v = server_.rules->CheckUpgrade(
          host, origin == req.end() ? std::nullopt : std::optional<std::string_view>(origin->value()));
      if (v != AccessRules::Verdict::kAllowed) return Refuse(req, v, origin == req.end() ? "" : origin->value());
      stream_.expires_never();
      // The session forgets itself when it closes (and its page's pause ends).
      auto ws = std::make_shared<WsSession>(stream_.release_socket(), server_.source, ++server_.pages_opened,
                                            [&server = server_](const std::shared_ptr<WsSession>& closed) {
                                              if (server.sessions.erase(closed) > 0) --server.clients;
                                            });
      server_.sessions.insert(ws);
      ++server_.clients;
      ws->Start(std::move(req));
      return;
    }
    auto res = std::make_shared<http::response<http::string_body>>();
    res->version(req.version());
    res->keep_alive(req.keep_alive());
    res->set(http::field::server, "sgslam viewer");
    res->set(http::field::cache_control, "no-cache");
    res->set("X-Content-Type-Options", "nosniff");
    std::optional<std::string> body;
    std::optional<std::filesystem::path> path;
    if (req.method() != http::verb::get && req.method() != http::verb::head) {
      res->result(http::status::method_not_allowed);
    } else if (!(path = AssetPath(server_.options.assets, req.target())) || !(body = ReadWhole(*path))) {
      res->result(http::status::not_found);
      res->set(http::field::content_type, "text/plain; charset=utf-8");
      res->body() = "not found\n";
    } else {
      res->result(http::status::ok);
      res->set(http::field::content_type, ContentType(*path));
      res->set("Content-Security-Policy",
               "default-src 'self'; img-src 'self' blob: data:; connect-src 'self'; style-src 'self'");
      if (req.method() == http::verb::get) res->body() = std::move(*body);
    }
    res->prepare_payload();
    http::async_write(stream_, *res, [self = shared_from_this(), res](beast::error_code ec, std::size_t) {
      if (ec || !res->keep_alive()) return self->Close();
      self->Read();
    });
  }

  // 403 with a short reason, then the connection closes.
  void Refuse(const http::request<http::string_body>& req, AccessRules::Verdict verdict, std::string_view origin) {
    server_.LogRefusal(verdict, req[http::field::host], origin);
    auto res = std::make_shared<http::response<http::string_body>>(http::status::forbidden, req.version());
    res->set(http::field::server, "sgslam viewer");
    res->set(http::field::content_type, "text/plain; charset=utf-8");
    res->keep_alive(false);
    res->body() = verdict == AccessRules::Verdict::kUnknownHost ? "forbidden: not a host this viewer answers to\n"
                  : verdict == AccessRules::Verdict::kNoOrigin  ? "forbidden: a WebSocket without an Origin\n"
                                                                : "forbidden: not this viewer's page\n";
    res->prepare_payload();
    http::async_write(stream_, *res,
                      [self = shared_from_this(), res](beast::error_code, std::size_t) { self->Close(); });
  }

  void Close() {
    beast::error_code ignored;
    stream_.socket().shutdown(tcp::socket::shutdown_both, ignored);
    stream_.socket().close(ignored);
  }

  beast::tcp_stream stream_;
  Server::Impl& server_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
};

void Server::Impl::Accept() {
  acceptor.async_accept([this](beast::error_code ec, tcp::socket socket) {
    if (ec == net::error::operation_aborted) return;
    if (!ec) std::make_shared<HttpSession>(std::move(socket), *this)->Read();
    Accept();
  });
}

void Server::Impl::LogRefusal(AccessRules::Verdict verdict, std::string_view host, std::string_view origin) {
  bool& logged = refusal_logged[static_cast<std::size_t>(verdict)];
  if (logged) return;
  logged = true;
  constexpr const char* kOpen = "run --viewer-origin and view --origin allow another";
  constexpr const char* kOnce = "further refusals of this kind are not logged";
  switch (verdict) {
    case AccessRules::Verdict::kUnknownHost:
      spdlog::warn("viewer: refused a request for host '{}': the viewer answers to {} ({}); {}", Printable(host),
                   hosts_text, kOpen, kOnce);
      break;
    case AccessRules::Verdict::kNoOrigin:
      spdlog::warn("viewer: refused a WebSocket without an Origin header (not a web page's); {}", kOnce);
      break;
    case AccessRules::Verdict::kForeignOrigin:
      spdlog::warn("viewer: refused a WebSocket from a page at '{}', not this viewer's own page ({}); {}",
                   Printable(origin), kOpen, kOnce);
      break;
    case AccessRules::Verdict::kAllowed:
      break;
  }
}

void Server::Impl::Deliver() {
  if (std::none_of(sessions.begin(), sessions.end(), [](const auto& s) { return s->wants_frame(); })) return;
  const auto frame = source.EncodeFrame();  // once for every page
  const auto copy = sessions;               // a failed write may close (erase) a session
  for (const auto& s : copy) s->DeliverFrame(frame);
}

Server::Server(ServerOptions options, Source& source) : impl_(std::make_unique<Impl>(std::move(options), source)) {
  Impl& m = *impl_;
  if (m.options.assets.empty()) {
    const auto data = DataDir();
    if (!data) throw Error("viewer: the page's files were not found (no share/sgslam beside the executable)");
    m.options.assets = *data / "viewer";
  }
  if (!std::filesystem::is_regular_file(m.options.assets / "index.html")) {
    throw Error("viewer: no index.html in " + m.options.assets.string() +
                " (the page's files, copied there by a build with SGSLAM_VIEWER on)");
  }
  const auto address =
      Listen(m.acceptor, m.options.address, m.options.port, "viewer", "see the run (and pause a live one)");
  m.port = m.acceptor.local_endpoint().port();
  m.rules.emplace(address.is_loopback(), m.port, m.options.allowed_origins);
  m.hosts_text = std::string(address.is_loopback() ? "loopback hosts (127.0.0.1, localhost, [::1])"
                                                   : "IP addresses and loopback hosts") +
                 " with port " + std::to_string(m.port);
  for (std::size_t i = 0; i < m.options.allowed_origins.size(); ++i) {
    m.hosts_text += (i == 0 ? ", and the hosts of " : ", ") + m.options.allowed_origins[i];
  }
  m.Accept();
  m.thread = std::thread([&m] {
    NameThisThread("sg-viewer");
    for (;;) {
      try {
        m.ioc.run();
        return;
      } catch (const std::exception& e) {  // a source that threw: log and serve on
        spdlog::error("viewer: {}", e.what());
      }
    }
  });
}

Server::~Server() {
  // The connections close with the io_context (after the sessions, declared later).
  impl_->ioc.stop();
  impl_->thread.join();
}

std::uint16_t Server::port() const { return impl_->port; }

std::string Server::url() const {
  const std::string& a = impl_->options.address;
  const std::string host = a.find(':') != std::string::npos ? "[" + a + "]" : a;
  return "http://" + host + ":" + std::to_string(impl_->port) + "/";
}

void Server::NotifyFrame() {
  Impl& m = *impl_;
  net::post(m.ioc, [&m] { m.Deliver(); });
}

std::size_t Server::clients() const { return impl_->clients.load(); }

}  // namespace sgslam::viewer
