// The HTTP and WebSocket server of ogf-view (Boost.Beast on the program's io_context, one thread):
// GET / is the page, GET /lib/<name> a JavaScript library from the files it was given, and /ws the feed:
// binary cell frames (cell_frame.hpp) and JSON status frames, both pushed by the program. A browser
// that joins gets the whole state first (the `on_join` callback sends it). A browser that cannot keep up
// (more than kMaxQueuedBytes waiting) loses what was queued and gets the whole state again once its
// queue has drained, so it never shows a map with holes.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "ogf/common/result.hpp"

namespace ogf::view {

inline constexpr std::size_t kMaxQueuedBytes = std::size_t{96} << 20;

class WebSocketSession;

// One outgoing WebSocket message, shared by every browser it goes to.
struct Frame {
  std::shared_ptr<const std::string> bytes;
  bool binary = false;
};

class ViewServer {
 public:
  struct Page {
    std::string content_type;
    std::shared_ptr<const std::string> body;
  };
  using JoinHandler = std::function<void(WebSocketSession&)>;

  // Binds at once (port 0: any free port, see port()).
  static Result<std::unique_ptr<ViewServer>> start(boost::asio::io_context& io, const std::string& address,
                                                   std::uint16_t port, std::map<std::string, Page> pages,
                                                   JoinHandler on_join);
  ~ViewServer();
  ViewServer(const ViewServer&) = delete;
  ViewServer& operator=(const ViewServer&) = delete;

  std::uint16_t port() const;
  // Queues the frame for every connected browser that has its whole state.
  void broadcast(const Frame& frame);
  // Browsers that lost frames and whose queue has drained get the whole state again (call periodically).
  void resyncLagging();
  std::size_t clients() const;
  // Frames dropped for slow browsers since start.
  std::uint64_t dropped() const { return dropped_; }

  // Used by the sessions.
  const Page* page(const std::string& target) const;
  void joined(const std::shared_ptr<WebSocketSession>& s);
  void left(WebSocketSession* s);
  void countDrop() { ++dropped_; }

 private:
  ViewServer(boost::asio::io_context& io, std::map<std::string, Page> pages, JoinHandler on_join);
  void accept();

  boost::asio::io_context& io_;
  boost::asio::ip::tcp::acceptor acceptor_;
  std::map<std::string, Page> pages_;
  JoinHandler on_join_;
  std::map<WebSocketSession*, std::weak_ptr<WebSocketSession>> sessions_;
  std::uint64_t dropped_ = 0;
};

class WebSocketSession : public std::enable_shared_from_this<WebSocketSession> {
 public:
  virtual ~WebSocketSession() = default;
  // Queues a frame; when the queue is over kMaxQueuedBytes the queue is dropped and the session waits
  // for a resync.
  virtual void send(const Frame& frame) = 0;
  virtual bool lagging() const = 0;
  virtual bool idle() const = 0;
  virtual void clearLagging() = 0;
  virtual void close() = 0;
};

}  // namespace ogf::view
