#include "ogf/view/view_server.hpp"

#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cerrno>
#include <deque>

#include "ogf/view/access_token.hpp"

namespace ogf::view {
namespace {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = boost::asio::ip::tcp;
using Clock = std::chrono::steady_clock;

std::string_view sv(beast::string_view v) { return {v.data(), v.size()}; }

std::string peerOf(const tcp::socket& socket) {
  beast::error_code ec;
  const auto ep = socket.remote_endpoint(ec);
  return ec ? std::string("?") : ep.address().to_string() + ":" + std::to_string(ep.port());
}

// A page of another site may open a WebSocket to this one (browsers send its Origin and no CORS rule
// applies to WebSockets): only the page served from here may.
bool sameOrigin(std::string_view origin, std::string_view host) {
  if (origin.empty()) return true;  // not a browser
  return origin == fmt::format("http://{}", host) || origin == fmt::format("https://{}", host);
}

class WebSocketSessionImpl final : public WebSocketSession {
 public:
  WebSocketSessionImpl(tcp::socket&& socket, ViewServer& server)
      : ws_(std::move(socket)), server_(server), open_(server.open()) {
    ++open_->feeds;
  }
  ~WebSocketSessionImpl() override { --open_->feeds; }

  void run(http::request<http::string_body> req) {
    // Beast's own timer: the handshake within the timeout, then a ping after half of it without a byte
    // from the peer, and the connection closed when the other half passes in silence too.
    websocket::stream_base::timeout timeout;
    timeout.handshake_timeout = server_.limits().client_timeout;
    timeout.idle_timeout = server_.limits().client_timeout;
    timeout.keep_alive_pings = true;
    ws_.set_option(timeout);
    ws_.read_message_max(kMaxIncomingMessage);
    ws_.set_option(websocket::stream_base::decorator(
        [](websocket::response_type& res) { res.set(http::field::server, "ogf-view"); }));
    ws_.async_accept(req, [self = shared()](beast::error_code ec) {
      if (ec) {
        if (ec == beast::error::timeout) ++self->server_.count().timed_out;
        return;
      }
      self->server_.joined(self);
      self->read();
    });
  }

  void sendUpdate(const std::vector<Frame>& update) override {
    if (closed_) return;
    if (behind_) {
      server_.count().frames_dropped += update.size();
      return;
    }
    std::size_t bytes = 0;
    for (const auto& f : update) bytes += f.bytes->size();
    const std::size_t waiting = queue_.size() - (writing_ ? 1u : 0u);
    if (waiting > 0 && waiting_bytes_ + bytes > kMaxWaitingBytes) {
      // Behind: what waits and this update are replaced by the whole state once the frame in flight
      // is written (maintain()).
      server_.count().frames_dropped += waiting + update.size();
      ++server_.count().resyncs;
      dropWaiting();
      behind_ = true;
      return;
    }
    for (const auto& f : update) queue_.push_back({f, false});
    waiting_bytes_ += bytes;
    if (!writing_) write();
  }
  void sendWhole(const std::vector<Frame>& whole) override {
    if (closed_) return;
    behind_ = false;
    for (const auto& f : whole) queue_.push_back({f, true});
    if (!writing_) write();
  }
  bool behind() const override { return behind_; }
  bool idle() const override { return !writing_ && queue_.empty(); }
  std::optional<Clock::time_point> writingSince() const override {
    return writing_ ? std::optional(writing_since_) : std::nullopt;
  }
  void forEachFrame(const std::function<void(const std::string&)>& f) const override {
    for (const auto& e : queue_) f(*e.frame.bytes);
  }
  bool closed() const override { return closed_; }
  void close() override {
    if (closed_) return;
    closed_ = true;
    dropWaiting();
    beast::error_code ec;
    beast::get_lowest_layer(ws_).socket().shutdown(tcp::socket::shutdown_both, ec);
    beast::get_lowest_layer(ws_).socket().close(ec);
  }

 private:
  struct Queued {
    Frame frame;
    bool whole;  // part of a whole state: not counted in waiting_bytes_
  };

  std::shared_ptr<WebSocketSessionImpl> shared() {
    return std::static_pointer_cast<WebSocketSessionImpl>(shared_from_this());
  }

  // Drops every frame but the one in flight (Beast writes from its bytes until the handler runs).
  void dropWaiting() {
    while (queue_.size() > (writing_ ? 1u : 0u)) queue_.pop_back();
    waiting_bytes_ = 0;
  }

  void write() {
    writing_ = true;
    writing_since_ = Clock::now();
    const Queued& front = queue_.front();
    if (!front.whole) waiting_bytes_ -= front.frame.bytes->size();
    ws_.binary(front.frame.binary);
    ws_.async_write(boost::asio::buffer(*front.frame.bytes), [self = shared()](beast::error_code ec, std::size_t) {
      self->writing_ = false;
      self->queue_.pop_front();
      if (ec) {
        self->end();
        return;
      }
      if (!self->queue_.empty() && !self->closed_) self->write();
    });
  }

  // The page sends nothing but control frames; reading keeps them flowing (pongs, close).
  void read() {
    ws_.async_read(in_, [self = shared()](beast::error_code ec, std::size_t) {
      if (ec) {
        if (ec == beast::error::timeout) {
          ++self->server_.count().timed_out;
          self->server_.logRefusal("closed a feed whose peer stopped answering");
        } else if (ec == websocket::error::message_too_big) {
          ++self->server_.count().oversized;
          self->server_.logRefusal(fmt::format("closed a feed that sent a message over {} bytes", kMaxIncomingMessage));
        }
        self->end();
        return;
      }
      self->in_.consume(self->in_.size());
      self->read();
    });
  }

  void end() {
    close();
    server_.left(this);
  }

  websocket::stream<beast::tcp_stream> ws_;
  ViewServer& server_;
  std::shared_ptr<ViewServer::OpenConnections> open_;
  beast::flat_buffer in_;
  std::deque<Queued> queue_;  // the front is in flight while writing_
  std::size_t waiting_bytes_ = 0;
  Clock::time_point writing_since_;
  bool writing_ = false;
  bool behind_ = false;
  bool closed_ = false;
};

class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(tcp::socket&& socket, ViewServer& server)
      : stream_(std::move(socket)), server_(server), open_(server.open()) {
    ++open_->http;
  }
  ~HttpSession() { --open_->http; }

  void read() {
    parser_.emplace();
    parser_->body_limit(kMaxRequestBody);
    stream_.expires_after(server_.limits().client_timeout);
    http::async_read(stream_, buffer_, *parser_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) {  // closed, timed out or not HTTP
        if (ec == beast::error::timeout) ++self->server_.count().timed_out;
        return;
      }
      self->req_ = self->parser_->release();
      self->handle();
    });
  }

 private:
  void handle() {
    const auto& limits = server_.limits();
    const bool upgrade = websocket::is_upgrade(req_);
    if (static_cast<std::size_t>(open_->http) > server_.httpLimit()) {
      ++server_.count().refused_busy;
      server_.logRefusal(fmt::format("refused {}: {} HTTP connections open", peer(), open_->http));
      respondText(http::status::service_unavailable, "ogf-view is busy: too many connections; try again later\n");
      return;
    }
    std::string path(sv(req_.target()));
    if (const auto q = path.find('?'); q != std::string::npos) path.resize(q);
    bool token_in_query = false;
    if (!limits.token.empty()) {
      const auto in_query = tokenInTarget(sv(req_.target()));
      const auto in_cookie = tokenInCookie(sv(req_[http::field::cookie]));
      token_in_query = in_query && tokensEqual(*in_query, limits.token);
      if (!token_in_query && !(in_cookie && tokensEqual(*in_cookie, limits.token))) {
        ++server_.count().refused_token;
        server_.logRefusal(fmt::format("refused {} {}: no valid token", peer(), path));
        respondText(http::status::unauthorized,
                    "ogf-view needs its token: open the address it printed at start (http://HOST:PORT/?token=...)\n");
        return;
      }
    }
    if (upgrade) {
      if (path != "/ws") {
        respondText(http::status::not_found, "no such feed\n");
        return;
      }
      if (!sameOrigin(sv(req_[http::field::origin]), sv(req_[http::field::host]))) {
        ++server_.count().refused_origin;
        server_.logRefusal(fmt::format("refused {}: a feed for a page of another site ({})", peer(),
                                       std::string(sv(req_[http::field::origin]).substr(0, 100))));
        respondText(http::status::forbidden, "the feed is for ogf-view's own page\n");
        return;
      }
      if (static_cast<std::size_t>(open_->feeds) >= limits.max_clients) {
        ++server_.count().refused_busy;
        server_.logRefusal(fmt::format("refused {}: {} browsers connected, the most --max-clients allows", peer(),
                                       open_->feeds));
        respondText(http::status::service_unavailable,
                    fmt::format("ogf-view serves {} browsers at once and has that many; try again later\n",
                                limits.max_clients));
        return;
      }
      stream_.expires_never();
      std::make_shared<WebSocketSessionImpl>(stream_.release_socket(), server_)->run(std::move(req_));
      return;
    }
    if (req_.method() != http::verb::get && req_.method() != http::verb::head) {
      respondText(http::status::method_not_allowed, "GET only\n");
      return;
    }
    std::string cookie;
    if (token_in_query)
      cookie = fmt::format("{}={}; Path=/; HttpOnly; SameSite=Strict", kTokenCookie, limits.token);
    if (path == "/status") {
      respond(http::status::ok, "application/json", std::make_shared<const std::string>(server_.statusJson()),
              cookie);
    } else if (const ViewServer::Page* p = server_.page(path)) {
      respond(http::status::ok, p->content_type, p->body, cookie);
    } else {
      respondText(http::status::not_found, "not found\n");
    }
  }

  std::string peer() { return peerOf(stream_.socket()); }

  // Errors and refusals: a short text body, and the connection closed after it.
  void respondText(http::status status, std::string text) {
    respond(status, "text/plain; charset=utf-8", std::make_shared<const std::string>(std::move(text)), "", true);
  }

  void respond(http::status status, const std::string& type, std::shared_ptr<const std::string> body,
               const std::string& cookie, bool close = false) {
    auto res = std::make_shared<http::response<http::string_body>>(status, req_.version());
    res->set(http::field::server, "ogf-view");
    res->set(http::field::content_type, type);
    res->set(http::field::cache_control, "no-cache");
    if (!cookie.empty()) res->set(http::field::set_cookie, cookie);
    res->keep_alive(req_.keep_alive() && !close);
    if (req_.method() != http::verb::head) res->body() = *body;
    res->content_length(body->size());
    http::async_write(stream_, *res, [self = shared_from_this(), res](beast::error_code ec, std::size_t) {
      if (ec || !res->keep_alive()) {
        beast::error_code ignored;
        self->stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
        return;
      }
      self->read();
    });
  }

  beast::tcp_stream stream_;
  ViewServer& server_;
  std::shared_ptr<ViewServer::OpenConnections> open_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  http::request<http::string_body> req_;
};

bool descriptorsRanOut(const beast::error_code& ec) {
  return ec == boost::asio::error::no_descriptors || ec == beast::error_code(ENFILE, boost::system::system_category()) || ec == boost::asio::error::no_buffer_space ||
         ec == boost::asio::error::no_memory;
}

}  // namespace

ViewServer::ViewServer(boost::asio::io_context& io, std::map<std::string, Page> pages, WholeState whole_state,
                       ServerLimits limits)
    : io_(io),
      acceptor_(io),
      accept_pause_timer_(io),
      pages_(std::move(pages)),
      whole_state_(std::move(whole_state)),
      limits_(std::move(limits)) {}

ViewServer::~ViewServer() {
  beast::error_code ec;
  acceptor_.close(ec);
  accept_pause_timer_.cancel();
  for (auto& [raw, weak] : sessions_)
    if (auto s = weak.lock()) s->close();
}

Result<std::unique_ptr<ViewServer>> ViewServer::start(boost::asio::io_context& io, const std::string& address,
                                                      std::uint16_t port, std::map<std::string, Page> pages,
                                                      WholeState whole_state, ServerLimits limits) {
  std::unique_ptr<ViewServer> server(new ViewServer(io, std::move(pages), std::move(whole_state), std::move(limits)));
  beast::error_code ec;
  const auto addr = boost::asio::ip::make_address(address, ec);
  if (ec) return Error{"--bind " + address + ": not an IP address"};
  const tcp::endpoint endpoint(addr, port);
  auto& a = server->acceptor_;
  if (a.open(endpoint.protocol(), ec); ec) return Error{"cannot open a socket: " + ec.message()};
  a.set_option(boost::asio::socket_base::reuse_address(true), ec);
  if (a.bind(endpoint, ec); ec) return Error{"cannot bind " + address + ":" + std::to_string(port) + ": " + ec.message()};
  if (a.listen(boost::asio::socket_base::max_listen_connections, ec); ec) return Error{"cannot listen: " + ec.message()};
  server->accept();
  return server;
}

std::uint16_t ViewServer::port() const {
  beast::error_code ec;
  return acceptor_.local_endpoint(ec).port();
}

void ViewServer::accept() {
  acceptor_.async_accept(io_, [this](beast::error_code ec, tcp::socket socket) {
    if (ec == boost::asio::error::operation_aborted) return;
    if (ec) {
      pauseAccepting(ec);
      return;
    }
    if (accept_pause_.count() > 0) {
      spdlog::info("accepting connections again ({} accepts failed while paused)", accepts_missed_);
      accept_pause_ = std::chrono::milliseconds(0);
      accepts_missed_ = 0;
    }
    ++counters_.connections;
    if (static_cast<std::size_t>(open_->http) >= 2 * httpLimit()) {
      // Even a 503 would hold the descriptor while the request is read.
      ++counters_.refused_busy;
      logRefusal(fmt::format("closed {} at once: {} HTTP connections open", peerOf(socket), open_->http));
      beast::error_code ignored;
      socket.close(ignored);
    } else {
      std::make_shared<HttpSession>(std::move(socket), *this)->read();
    }
    accept();
  });
}

void ViewServer::pauseAccepting(const boost::system::error_code& ec) {
  ++accepts_missed_;
  if (accept_pause_.count() == 0) {
    ++counters_.accept_pauses;
    accept_pause_ = std::chrono::milliseconds(100);
    spdlog::warn("cannot accept a connection: {}{}; pausing accepts (100 ms, doubling to 1 s) until one succeeds",
                 ec.message(), descriptorsRanOut(ec) ? " (the process is out of descriptors or memory)" : "");
  } else {
    accept_pause_ = std::min(2 * accept_pause_, std::chrono::milliseconds(1000));
  }
  accept_pause_timer_.expires_after(accept_pause_);
  accept_pause_timer_.async_wait([this](const beast::error_code& wait_ec) {
    if (!wait_ec) accept();
  });
}

const ViewServer::Page* ViewServer::page(const std::string& target) const {
  const auto it = pages_.find(target);
  return it == pages_.end() ? nullptr : &it->second;
}

std::vector<Frame> ViewServer::wholeState() {
  if (whole_state_) latest_whole_ = whole_state_();
  current_.clear();
  for (const auto* frames : {&latest_update_, &latest_whole_})
    for (const auto& f : *frames) current_.insert(f.bytes.get());
  return latest_whole_;
}

void ViewServer::joined(const std::shared_ptr<WebSocketSession>& s) {
  sessions_[s.get()] = s;
  s->sendWhole(wholeState());
  enforceBudget();
}

void ViewServer::left(WebSocketSession* s) { sessions_.erase(s); }

void ViewServer::broadcast(const std::vector<Frame>& update) {
  latest_update_ = update;
  current_.clear();
  for (const auto* frames : {&latest_update_, &latest_whole_})
    for (const auto& f : *frames) current_.insert(f.bytes.get());
  for (auto& [raw, weak] : sessions_)
    if (auto s = weak.lock()) s->sendUpdate(update);
  enforceBudget();
}

void ViewServer::maintain() {
  const auto now = Clock::now();
  for (auto& [raw, weak] : sessions_) {
    auto s = weak.lock();
    if (!s || s->closed()) continue;
    if (const auto since = s->writingSince(); since && now - *since > limits_.client_timeout) {
      ++counters_.timed_out;
      logRefusal("closed a feed whose peer took no data for --client-timeout");
      s->close();
    }
  }
  for (auto& [raw, weak] : sessions_) {
    auto s = weak.lock();
    if (s && !s->closed() && s->behind() && s->idle()) s->sendWhole(wholeState());
  }
  enforceBudget();
}

std::size_t ViewServer::behindBytes() const {
  std::unordered_set<const std::string*> seen;
  std::size_t bytes = 0;
  for (const auto& [raw, weak] : sessions_) {
    auto s = weak.lock();
    if (!s || s->closed()) continue;
    s->forEachFrame([&](const std::string& f) {
      if (!current_.contains(&f) && seen.insert(&f).second) bytes += f.size();
    });
  }
  return bytes;
}

void ViewServer::enforceBudget() {
  while (behindBytes() > limits_.memory_budget) {
    std::shared_ptr<WebSocketSession> slowest;
    Clock::time_point oldest = Clock::time_point::max();
    for (auto& [raw, weak] : sessions_) {
      auto s = weak.lock();
      if (!s || s->closed()) continue;
      if (const auto since = s->writingSince(); since && *since < oldest) {
        oldest = *since;
        slowest = s;
      }
    }
    if (!slowest) return;
    ++counters_.over_budget;
    logRefusal("closed the slowest feed: frames kept for feeds behind exceed --memory-budget");
    slowest->close();
  }
}

std::size_t ViewServer::clients() const { return sessions_.size(); }

std::string ViewServer::statusJson() const {
  const auto& c = counters_;
  return fmt::format(
      R"({{"clients":{},"http_connections":{},"max_clients":{},"behind_bytes":{},"memory_budget":{},)"
      R"("connections":{},"refused_busy":{},"refused_token":{},"refused_origin":{},"timed_out":{},"oversized":{},)"
      R"("resyncs":{},"frames_dropped":{},"over_budget":{},"accept_pauses":{}}})",
      clients(), open_->http, limits_.max_clients, behindBytes(), limits_.memory_budget, c.connections,
      c.refused_busy, c.refused_token, c.refused_origin, c.timed_out, c.oversized, c.resyncs, c.frames_dropped,
      c.over_budget, c.accept_pauses) + "\n";
}

void ViewServer::logRefusal(const std::string& what) {
  if (auto n = refusal_log_.allow()) spdlog::warn("{} ({} more such since the last report)", what, *n);
}

}  // namespace ogf::view
