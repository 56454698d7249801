#include "ogf/view/view_server.hpp"

#include <boost/asio/strand.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include <deque>

namespace ogf::view {
namespace {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = boost::asio::ip::tcp;

class WebSocketSessionImpl final : public WebSocketSession {
 public:
  WebSocketSessionImpl(tcp::socket&& socket, ViewServer& server) : ws_(std::move(socket)), server_(server) {}

  void run(http::request<http::string_body> req) {
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_.set_option(websocket::stream_base::decorator(
        [](websocket::response_type& res) { res.set(http::field::server, "ogf-view"); }));
    ws_.async_accept(req, [self = shared()](beast::error_code ec) {
      if (ec) return;
      self->server_.joined(self);
      self->read();
    });
  }

  void send(const Frame& frame) override {
    if (lagging_ || closed_) {
      server_.countDrop();
      return;
    }
    if (queued_bytes_ + frame.bytes->size() > kMaxQueuedBytes) {
      // Keep only the frame being written; the rest is replaced by the whole state later.
      lagging_ = true;
      server_.countDrop();
      while (queue_.size() > (writing_ ? 1u : 0u)) {
        queued_bytes_ -= queue_.back().bytes->size();
        queue_.pop_back();
      }
      return;
    }
    queue_.push_back(frame);
    queued_bytes_ += frame.bytes->size();
    if (!writing_) write();
  }
  bool lagging() const override { return lagging_; }
  bool idle() const override { return !writing_ && queue_.empty(); }
  void clearLagging() override { lagging_ = false; }
  void close() override {
    if (closed_) return;
    closed_ = true;
    beast::error_code ec;
    beast::get_lowest_layer(ws_).socket().shutdown(tcp::socket::shutdown_both, ec);
    beast::get_lowest_layer(ws_).socket().close(ec);
  }

 private:
  std::shared_ptr<WebSocketSessionImpl> shared() {
    return std::static_pointer_cast<WebSocketSessionImpl>(shared_from_this());
  }

  void write() {
    writing_ = true;
    ws_.binary(queue_.front().binary);
    ws_.async_write(boost::asio::buffer(*queue_.front().bytes), [self = shared()](beast::error_code ec, std::size_t) {
      self->writing_ = false;
      if (ec) {
        self->end();
        return;
      }
      self->queued_bytes_ -= self->queue_.front().bytes->size();
      self->queue_.pop_front();
      if (!self->queue_.empty()) self->write();
    });
  }

  // The page sends nothing but close frames; reading keeps the control frames flowing.
  void read() {
    ws_.async_read(in_, [self = shared()](beast::error_code ec, std::size_t) {
      if (ec) {
        self->end();
        return;
      }
      self->in_.consume(self->in_.size());
      self->read();
    });
  }

  void end() {
    queue_.clear();
    queued_bytes_ = 0;
    closed_ = true;
    server_.left(this);
  }

  websocket::stream<beast::tcp_stream> ws_;
  ViewServer& server_;
  beast::flat_buffer in_;
  std::deque<Frame> queue_;
  std::size_t queued_bytes_ = 0;
  bool writing_ = false;
  bool lagging_ = false;
  bool closed_ = false;
};

class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(tcp::socket&& socket, ViewServer& server) : stream_(std::move(socket)), server_(server) {}

  void read() {
    req_ = {};
    stream_.expires_after(std::chrono::seconds(30));
    http::async_read(stream_, buffer_, req_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) return;  // closed, timed out or not HTTP
      self->handle();
    });
  }

 private:
  void handle() {
    if (websocket::is_upgrade(req_)) {
      if (req_.target() == "/ws") {
        stream_.expires_never();
        std::make_shared<WebSocketSessionImpl>(stream_.release_socket(), server_)->run(std::move(req_));
        return;
      }
      respond(http::status::not_found, "text/plain", std::make_shared<const std::string>("no such feed\n"));
      return;
    }
    if (req_.method() != http::verb::get && req_.method() != http::verb::head) {
      respond(http::status::method_not_allowed, "text/plain", std::make_shared<const std::string>("GET only\n"));
      return;
    }
    std::string target(req_.target());
    if (const auto q = target.find('?'); q != std::string::npos) target.resize(q);
    if (const ViewServer::Page* p = server_.page(target)) {
      respond(http::status::ok, p->content_type, p->body);
    } else {
      respond(http::status::not_found, "text/plain", std::make_shared<const std::string>("not found\n"));
    }
  }

  void respond(http::status status, const std::string& type, std::shared_ptr<const std::string> body) {
    auto res = std::make_shared<http::response<http::string_body>>(status, req_.version());
    res->set(http::field::server, "ogf-view");
    res->set(http::field::content_type, type);
    res->set(http::field::cache_control, "no-cache");
    res->keep_alive(req_.keep_alive());
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
  beast::flat_buffer buffer_;
  http::request<http::string_body> req_;
};

}  // namespace

ViewServer::ViewServer(boost::asio::io_context& io, std::map<std::string, Page> pages, JoinHandler on_join)
    : io_(io), acceptor_(io), pages_(std::move(pages)), on_join_(std::move(on_join)) {}

ViewServer::~ViewServer() {
  beast::error_code ec;
  acceptor_.close(ec);
  for (auto& [raw, weak] : sessions_)
    if (auto s = weak.lock()) s->close();
}

Result<std::unique_ptr<ViewServer>> ViewServer::start(boost::asio::io_context& io, const std::string& address,
                                                      std::uint16_t port, std::map<std::string, Page> pages,
                                                      JoinHandler on_join) {
  std::unique_ptr<ViewServer> server(new ViewServer(io, std::move(pages), std::move(on_join)));
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
    if (!ec) std::make_shared<HttpSession>(std::move(socket), *this)->read();
    accept();
  });
}

const ViewServer::Page* ViewServer::page(const std::string& target) const {
  const auto it = pages_.find(target);
  return it == pages_.end() ? nullptr : &it->second;
}

void ViewServer::joined(const std::shared_ptr<WebSocketSession>& s) {
  sessions_[s.get()] = s;
  if (on_join_) on_join_(*s);
}

void ViewServer::left(WebSocketSession* s) { sessions_.erase(s); }

void ViewServer::broadcast(const Frame& frame) {
  for (auto& [raw, weak] : sessions_)
    if (auto s = weak.lock()) s->send(frame);
}

void ViewServer::resyncLagging() {
  for (auto& [raw, weak] : sessions_) {
    auto s = weak.lock();
    if (!s || !s->lagging() || !s->idle()) continue;
    s->clearLagging();
    if (on_join_) on_join_(*s);
  }
}

std::size_t ViewServer::clients() const { return sessions_.size(); }

}  // namespace ogf::view
