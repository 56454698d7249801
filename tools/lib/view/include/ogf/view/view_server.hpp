// The HTTP and WebSocket server of ogf-view (Boost.Beast on the program's io_context, one thread):
// GET / is the page, GET /lib/<name> a JavaScript library from the files it was given, GET /status the
// server's counters as JSON, and /ws the feed: binary cell frames (cell_frame.hpp) and JSON status
// frames, both pushed by the program. A browser that joins gets the whole state first (the `whole_state`
// callback makes it; the program shares one copy between browsers).
//
// What one client can cost is bounded, so that nobody who reaches the port can exhaust the view:
// - at most `max_clients` feeds at once and 4 x max_clients + 8 HTTP connections besides; the rest get
//   503 with a short text body;
// - a connection whose peer is silent for `client_timeout` is closed: an HTTP request not complete, an
//   idle keep-alive connection, a feed whose peer answers no ping (Beast's keep-alive pings, sent at
//   half the timeout), and a feed whose frame in flight has not been written for that long;
// - a feed keeps at most kMaxWaitingBytes of updates waiting behind the frame in flight; beyond, it drops
//   them and gets the whole state again once that frame is written (it never shows a map with holes);
// - frames kept only for clients that are behind (not the latest update nor the latest whole state) may
//   take `memory_budget` bytes in all; beyond, the client whose write has waited longest is closed;
// - incoming WebSocket messages are capped at kMaxIncomingMessage bytes (the page sends none: only the
//   control frames of the protocol) and request bodies at kMaxRequestBody;
// - when descriptors run out (EMFILE, ENFILE) accepting pauses 100 ms, doubling to 1 s, instead of
//   retrying at once; the pending connections wait in the listen queue.
// With a token set every request must carry it (access_token.hpp), else 401.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <unordered_set>
#include <vector>

#include "ogf/common/result.hpp"
#include "ogf/transport/logging.hpp"

namespace ogf::view {

// Updates a feed may keep waiting behind the frame being written: about one full cell frame (262 144
// cells of 22 bytes, cell_frame.hpp), or 15 s of a map changing 5000 cells a second at 22 bytes a cell.
inline constexpr std::size_t kMaxWaitingBytes = std::size_t{4} << 20;
// The page sends no message of its own; pings, pongs and close frames carry at most 125 bytes (RFC 6455
// 5.5). 4 KiB leaves room and bounds what a client can make the view buffer.
inline constexpr std::size_t kMaxIncomingMessage = 4096;
// GET requests carry no body.
inline constexpr std::size_t kMaxRequestBody = 4096;

struct ServerLimits {
  std::size_t max_clients = 32;
  std::chrono::milliseconds client_timeout{30000};
  std::size_t memory_budget = std::size_t{256} << 20;
  // Empty: no token asked.
  std::string token;
};

// What the server refused, closed and dropped since start (GET /status, and the program's log).
struct ServerCounters {
  std::uint64_t connections = 0;      // accepted
  std::uint64_t refused_busy = 0;     // 503: max_clients feeds or the HTTP connections' limit reached
  std::uint64_t refused_token = 0;    // 401: no token or a wrong one
  std::uint64_t refused_origin = 0;   // 403: a WebSocket upgrade from a page of another site
  std::uint64_t timed_out = 0;        // closed after client_timeout of silence or of a stalled write
  std::uint64_t oversized = 0;        // closed for an incoming message over kMaxIncomingMessage
  std::uint64_t resyncs = 0;          // feeds that fell behind and were sent the whole state again
  std::uint64_t frames_dropped = 0;   // frames not sent to feeds that were behind
  std::uint64_t over_budget = 0;      // feeds closed to keep within memory_budget
  std::uint64_t accept_pauses = 0;    // times accepting paused because descriptors ran out
};

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
  // The frames a browser needs to show the current state from nothing.
  using WholeState = std::function<std::vector<Frame>()>;

  // Binds at once (port 0: any free port, see port()).
  static Result<std::unique_ptr<ViewServer>> start(boost::asio::io_context& io, const std::string& address,
                                                   std::uint16_t port, std::map<std::string, Page> pages,
                                                   WholeState whole_state, ServerLimits limits = {});
  ~ViewServer();
  ViewServer(const ViewServer&) = delete;
  ViewServer& operator=(const ViewServer&) = delete;

  std::uint16_t port() const;
  // Queues one update (its frames in order) for every connected browser that has the whole state.
  void broadcast(const std::vector<Frame>& update);
  // Call periodically: browsers that fell behind and whose queue has drained get the whole state again,
  // stalled writes are closed, the memory budget is enforced.
  void maintain();
  std::size_t clients() const;
  const ServerCounters& counters() const { return counters_; }
  // Bytes of frames kept only for browsers that are behind (what memory_budget bounds).
  std::size_t behindBytes() const;
  std::string statusJson() const;

  // Used by the sessions.
  const Page* page(const std::string& target) const;
  const ServerLimits& limits() const { return limits_; }
  ServerCounters& count() { return counters_; }
  void joined(const std::shared_ptr<WebSocketSession>& s);
  void left(WebSocketSession* s);
  // Connections open: HTTP (counted until upgraded or closed) and feeds (from the upgrade on). Shared
  // with the sessions, which may outlive the server until the io_context drops their handlers.
  struct OpenConnections {
    int http = 0;
    int feeds = 0;
  };
  const std::shared_ptr<OpenConnections>& open() const { return open_; }
  // HTTP connections served at once; beyond, 503; beyond twice as many, closed at once.
  std::size_t httpLimit() const { return 4 * limits_.max_clients + 8; }
  // Logs a refusal at most once a second, with how many were held back.
  void logRefusal(const std::string& what);

 private:
  ViewServer(boost::asio::io_context& io, std::map<std::string, Page> pages, WholeState whole_state,
             ServerLimits limits);
  void accept();
  void pauseAccepting(const boost::system::error_code& ec);
  void enforceBudget();
  std::vector<Frame> wholeState();

  boost::asio::io_context& io_;
  boost::asio::ip::tcp::acceptor acceptor_;
  boost::asio::steady_timer accept_pause_timer_;
  std::chrono::milliseconds accept_pause_{0};  // 0: accepting; else the current pause
  std::uint64_t accepts_missed_ = 0;           // failed accepts in the current pause episode
  std::map<std::string, Page> pages_;
  WholeState whole_state_;
  ServerLimits limits_;
  std::map<WebSocketSession*, std::weak_ptr<WebSocketSession>> sessions_;
  // The frames of the latest update and of the latest whole state: they exist whoever is behind.
  std::unordered_set<const std::string*> current_;
  std::vector<Frame> latest_update_, latest_whole_;
  ServerCounters counters_;
  std::shared_ptr<OpenConnections> open_ = std::make_shared<OpenConnections>();
  ogf::transport::LogRateLimiter refusal_log_;
};

class WebSocketSession : public std::enable_shared_from_this<WebSocketSession> {
 public:
  virtual ~WebSocketSession() = default;
  // Queues an update; a feed that is behind (over kMaxWaitingBytes waiting) drops what waits and this.
  virtual void sendUpdate(const std::vector<Frame>& update) = 0;
  // Queues the whole state and clears "behind".
  virtual void sendWhole(const std::vector<Frame>& whole) = 0;
  virtual bool behind() const = 0;
  virtual bool idle() const = 0;
  // Since when the frame in flight is being written (nullopt when none is).
  virtual std::optional<std::chrono::steady_clock::time_point> writingSince() const = 0;
  // Calls `f` with every frame this session holds (in flight and waiting).
  virtual void forEachFrame(const std::function<void(const std::string&)>& f) const = 0;
  virtual bool closed() const = 0;
  virtual void close() = 0;
};

}  // namespace ogf::view
