#include "foxglove_server.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <thread>
#include <utility>

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "listen.h"
#include "sgslam/common/error.h"
#include "sgslam/common/thread_name.h"

namespace sgslam::viewer {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;
using nlohmann::json;

namespace {

constexpr const char* kSubprotocol = "foxglove.websocket.v1";
constexpr std::size_t kMaxRequestBytes = 8 * 1024;
constexpr auto kHandshakeTimeout = std::chrono::seconds(30);

// A message data frame: opcode 1, the subscription, the time, the payload.
std::shared_ptr<const std::string> MessageFrame(std::uint32_t subscription, std::uint64_t t, const std::string& payload) {
  auto frame = std::make_shared<std::string>(13 + payload.size(), '\0');
  (*frame)[0] = 0x01;
  for (int i = 0; i < 4; ++i) (*frame)[1 + i] = static_cast<char>((subscription >> (8 * i)) & 0xFF);
  for (int i = 0; i < 8; ++i) (*frame)[5 + i] = static_cast<char>((t >> (8 * i)) & 0xFF);
  frame->replace(13, payload.size(), payload);
  return frame;
}

bool OffersFoxglove(std::string_view protocols) {
  for (std::size_t at = 0; at <= protocols.size();) {
    std::size_t end = protocols.find(',', at);
    if (end == std::string_view::npos) end = protocols.size();
    std::string_view p = protocols.substr(at, end - at);
    while (!p.empty() && p.front() == ' ') p.remove_prefix(1);
    while (!p.empty() && p.back() == ' ') p.remove_suffix(1);
    if (p == kSubprotocol) return true;
    at = end + 1;
  }
  return false;
}

class Session;

}  // namespace

struct FoxgloveServer::Impl {
  Impl(std::string n, std::vector<FoxgloveChannel> c) : name(std::move(n)), channels(std::move(c)), subscribers(channels.size()) {
    last.resize(channels.size());
  }
  void Accept();
  std::optional<std::size_t> IndexOf(std::uint32_t id) const {
    const auto it = index.find(id);
    return it == index.end() ? std::nullopt : std::optional<std::size_t>(it->second);
  }

  const std::string name;
  const std::vector<FoxgloveChannel> channels;
  std::map<std::uint32_t, std::size_t> index;  // channel id -> position; fixed after construction
  std::vector<std::atomic<int>> subscribers;   // per channel: subscriptions of every client
  std::string server_info, advertise;
  std::string address;
  std::uint16_t port = 0;
  std::atomic<std::size_t> clients{0};
  std::mutex done_mutex;  // with done: the destructor waits for the clients to go
  std::condition_variable done;
  std::atomic<std::uint64_t> dropped{0};

  net::io_context ioc{1};
  tcp::acceptor acceptor{ioc};
  // The server's thread only:
  std::set<std::shared_ptr<Session>> sessions;
  struct Last {
    std::uint64_t t = 0;
    std::shared_ptr<const std::string> payload;
  };
  std::vector<Last> last;  // per channel, of the latched ones
  std::thread thread;
};

namespace {

class Session : public std::enable_shared_from_this<Session> {
 public:
  Session(tcp::socket socket, FoxgloveServer::Impl& server) : http_(std::move(socket)), server_(server) {}

  // Reads the HTTP request: a WebSocket upgrade asking for the Foxglove protocol
  // becomes the session; anything else gets a short answer saying what this is.
  void Start() {
    parser_.emplace();
    parser_->header_limit(kMaxRequestBytes);
    parser_->body_limit(kMaxRequestBytes);
    http_.expires_after(kHandshakeTimeout);
    http::async_read(http_, buffer_, *parser_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) return;
      self->Upgrade(self->parser_->release());
    });
  }

  // The server's thread: the channel's message to each of this client's
  // subscriptions of it.
  void Deliver(std::size_t channel, std::uint64_t t, const std::string& payload) {
    for (const auto& [id, c] : subscriptions_) {
      if (c != channel) continue;
      if (closing_ || queued_bytes_ + 13 + payload.size() > FoxgloveServer::kMaxQueuedBytes) {
        ++server_.dropped;  // not even copied
        continue;
      }
      Queue(MessageFrame(id, t, payload), true);
    }
  }

  // The server is going: what is queued is sent, then the close frame.
  void CloseWhenSent() {
    closing_ = true;
    if (!writing_ && ws_) StartClose();
  }

  void Close() {
    if (closed_) return;
    closed_ = true;
    for (const auto& [id, c] : subscriptions_) --server_.subscribers[c];
    subscriptions_.clear();
    if (server_.sessions.erase(shared_from_this()) > 0) {
      {
        const std::lock_guard lock(server_.done_mutex);
        --server_.clients;
      }
      server_.done.notify_all();
    }
    beast::error_code ignored;
    if (ws_) {
      beast::get_lowest_layer(*ws_).socket().shutdown(tcp::socket::shutdown_both, ignored);
      beast::get_lowest_layer(*ws_).socket().close(ignored);
    }
  }

 private:
  void Upgrade(http::request<http::string_body> req) {
    if (!websocket::is_upgrade(req) || !OffersFoxglove(req[http::field::sec_websocket_protocol])) {
      auto res = std::make_shared<http::response<http::string_body>>(http::status::bad_request, req.version());
      res->set(http::field::server, "sgslam");
      res->set(http::field::content_type, "text/plain; charset=utf-8");
      res->keep_alive(false);
      res->body() = "sgslam serves Foxglove's WebSocket protocol (" + std::string(kSubprotocol) +
                    ") here: in Foxglove, open a connection to ws://" + server_.address + ":" +
                    std::to_string(server_.port) + "\n";
      res->prepare_payload();
      http::async_write(http_, *res, [self = shared_from_this(), res](beast::error_code, std::size_t) {
        beast::error_code ignored;
        self->http_.socket().shutdown(tcp::socket::shutdown_both, ignored);
      });
      return;
    }
    http_.expires_never();
    ws_.emplace(http_.release_socket());
    ws_->set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_->set_option(websocket::stream_base::decorator([](websocket::response_type& res) {
      res.set(http::field::sec_websocket_protocol, kSubprotocol);
      res.set(http::field::server, "sgslam");
    }));
    ws_->read_message_max(FoxgloveServer::kMaxClientMessage);
    ws_->async_accept(req, [self = shared_from_this()](beast::error_code ec) {
      if (ec) return;
      self->server_.sessions.insert(self);
      ++self->server_.clients;
      self->Queue(std::make_shared<const std::string>(self->server_.server_info), false);
      self->Queue(std::make_shared<const std::string>(self->server_.advertise), false);
      self->Read();
    });
  }

  void Read() {
    ws_->async_read(in_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec || self->closed_) return self->Close();
      const bool text = self->ws_->got_text();
      std::string message = beast::buffers_to_string(self->in_.data());
      self->in_.consume(self->in_.size());
      if (!text || !self->Handle(message)) return self->Close();  // clients publish nothing here
      self->Read();
    });
  }

  // One client message; false when it is not the protocol's JSON.
  bool Handle(const std::string& text) {
    json m;
    try {
      m = json::parse(text);
      const std::string op = m.at("op").get<std::string>();
      if (op == "subscribe") {
        for (const json& s : m.at("subscriptions")) {
          const auto id = s.at("id").get<std::uint32_t>();
          const auto channel = server_.IndexOf(s.at("channelId").get<std::uint32_t>());
          if (!channel) {
            Status(2, "no channel " + s.at("channelId").dump());
            continue;
          }
          if (subscriptions_.count(id) > 0) {
            Status(2, "subscription " + std::to_string(id) + " is in use");
            continue;
          }
          if (std::any_of(subscriptions_.begin(), subscriptions_.end(), [&](const auto& sub) { return sub.second == *channel; })) {
            Status(1, "already subscribed to channel " + s.at("channelId").dump());
            continue;
          }
          subscriptions_.emplace(id, *channel);
          ++server_.subscribers[*channel];
          const auto& last = server_.last[*channel];
          if (last.payload) Deliver(*channel, last.t, *last.payload);
        }
      } else if (op == "unsubscribe") {
        for (const json& id : m.at("subscriptionIds")) {
          const auto it = subscriptions_.find(id.get<std::uint32_t>());
          if (it == subscriptions_.end()) {
            Status(1, "no subscription " + id.dump());
            continue;
          }
          --server_.subscribers[it->second];
          subscriptions_.erase(it);
        }
      } else {
        Status(1, "sgslam does not offer '" + op + "'");
      }
      return true;
    } catch (const json::exception&) {
      return false;
    }
  }

  void Status(int level, const std::string& message) {
    Queue(std::make_shared<const std::string>(json{{"op", "status"}, {"level", level}, {"message", message}}.dump()),
          false);
  }

  // Messages that do not fit kMaxQueuedBytes are dropped; the protocol's own (text)
  // are never dropped: a client they no longer fit for is closed.
  void Queue(std::shared_ptr<const std::string> message, bool binary) {
    if (closed_) return;
    if (queued_bytes_ + message->size() > FoxgloveServer::kMaxQueuedBytes) {
      if (!binary) return Close();
      ++server_.dropped;
      return;
    }
    queued_bytes_ += message->size();
    queue_.push_back({std::move(message), binary});
    if (!writing_) Write();
  }

  void Write() {
    writing_ = true;
    ws_->binary(queue_.front().binary);
    ws_->async_write(net::buffer(*queue_.front().data), [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (self->closed_) return;
      if (ec) return self->Close();
      self->queued_bytes_ -= self->queue_.front().data->size();
      self->queue_.pop_front();
      if (!self->queue_.empty()) return self->Write();
      self->writing_ = false;
      if (self->closing_) self->StartClose();
    });
  }

  void StartClose() {
    if (closed_ || close_started_) return;
    close_started_ = true;
    ws_->async_close(websocket::close_code::going_away,
                     [self = shared_from_this()](beast::error_code) { self->Close(); });
  }

  struct Out {
    std::shared_ptr<const std::string> data;
    bool binary;
  };
  beast::tcp_stream http_;
  std::optional<websocket::stream<beast::tcp_stream>> ws_;
  FoxgloveServer::Impl& server_;
  beast::flat_buffer buffer_, in_;
  std::optional<http::request_parser<http::string_body>> parser_;
  std::map<std::uint32_t, std::size_t> subscriptions_;  // subscription id -> channel position
  std::deque<Out> queue_;
  std::size_t queued_bytes_ = 0;
  bool writing_ = false, closed_ = false, closing_ = false, close_started_ = false;
};

}  // namespace

void FoxgloveServer::Impl::Accept() {
  acceptor.async_accept([this](beast::error_code ec, tcp::socket socket) {
    if (ec == net::error::operation_aborted) return;
    if (!ec) std::make_shared<Session>(std::move(socket), *this)->Start();
    Accept();
  });
}

FoxgloveServer::FoxgloveServer(const std::string& address, std::uint16_t port, std::string name,
                               std::vector<FoxgloveChannel> channels)
    : impl_(std::make_unique<Impl>(std::move(name), std::move(channels))) {
  Impl& m = *impl_;
  json advertised = json::array();
  for (std::size_t i = 0; i < m.channels.size(); ++i) {
    const FoxgloveChannel& c = m.channels[i];
    if (c.id == 0 || !m.index.emplace(c.id, i).second) throw Error("foxglove: channel ids must be unique and not 0");
    advertised.push_back({{"id", c.id}, {"topic", c.topic}, {"encoding", c.encoding}, {"schemaName", c.schema_name},
                          {"schema", c.schema}, {"schemaEncoding", c.schema_encoding}});
  }
  m.advertise = json{{"op", "advertise"}, {"channels", std::move(advertised)}}.dump();
  m.server_info = json{{"op", "serverInfo"},
                       {"name", m.name},
                       {"capabilities", json::array()},
                       {"supportedEncodings", json::array()},
                       {"metadata", json::object()},
                       {"sessionId", std::to_string(std::chrono::system_clock::now().time_since_epoch().count())}}
                      .dump();
  m.address = address;
  Listen(m.acceptor, m.address, port, "--foxglove", "see the run");
  m.port = m.acceptor.local_endpoint().port();
  m.Accept();
  m.thread = std::thread([&m] {
    NameThisThread("sg-foxglove");
    m.ioc.run();
  });
}

FoxgloveServer::~FoxgloveServer() {
  Impl& m = *impl_;
  net::post(m.ioc, [&m] {
    beast::error_code ignored;
    m.acceptor.close(ignored);
    const auto sessions = m.sessions;
    for (const auto& s : sessions) s->CloseWhenSent();
  });
  {
    std::unique_lock lock(m.done_mutex);
    m.done.wait_for(lock, kCloseWait, [&m] { return m.clients.load() == 0; });
  }
  m.ioc.stop();
  m.thread.join();
}

std::uint16_t FoxgloveServer::port() const { return impl_->port; }

std::string FoxgloveServer::url() const {
  const std::string& a = impl_->address;
  return "ws://" + (a.find(':') != std::string::npos ? "[" + a + "]" : a) + ":" + std::to_string(impl_->port);
}

bool FoxgloveServer::Subscribed(std::uint32_t channel) const {
  const auto i = impl_->IndexOf(channel);
  return i && impl_->subscribers[*i].load() > 0;
}

void FoxgloveServer::Publish(std::uint32_t channel, std::uint64_t t, std::string payload) {
  Impl& m = *impl_;
  const auto i = m.IndexOf(channel);
  if (!i) throw Error("foxglove: no channel " + std::to_string(channel));
  auto shared = std::make_shared<const std::string>(std::move(payload));
  net::post(m.ioc, [&m, i = *i, t, shared] {
    if (m.channels[i].latched) m.last[i] = {t, shared};
    const auto sessions = m.sessions;  // a failed write may close (erase) a session
    for (const auto& s : sessions) s->Deliver(i, t, *shared);
  });
}

std::uint64_t FoxgloveServer::dropped() const { return impl_->dropped.load(); }

}  // namespace sgslam::viewer
