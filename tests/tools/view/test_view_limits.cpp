// ogf-view holds its ground against the clients that reach its port (tools/lib/view/include/ogf/view/
// view_server.hpp): real ogf-view processes showing a saved map, real TCP, HTTP and WebSocket clients on
// loopback. Each test is one way a client could take the view down: too many clients, silent ones,
// clients that never read, an oversized message, a descriptor flood, no token on a network address; and
// against what reaches it on the bus: malformed navigation grid messages.
// Memory figures are printed as "[ figures ]" lines.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <thread>

#include <lcm/lcm-cpp.hpp>

#include <ogf/map_delta_t.hpp>
#include <ogf/map_request_t.hpp>
#include <ogf/nav_grid_t.hpp>

#include "nav_room.hpp"
#include "ogf/delta/delta_stream.hpp"
#include "ogf/view/nav_frame.hpp"
#include "ogf/view/view_server.hpp"
#include "support/multicast.hpp"
#include "support/process_memory.hpp"
#include "view_process.hpp"

namespace {

namespace fs = std::filesystem;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = boost::asio::ip::tcp;
using ogf::testing::ViewProcess;

constexpr char kHost[] = "127.0.0.1";

struct TempMap {
  explicit TempMap(int nx, int ny, int nz)
      : path(fs::temp_directory_path() / ("ogf-view-limits-" + std::to_string(::getpid()) + "-" +
                                          std::to_string(nx * ny * nz) + ".ogfm")) {
    occupied = ogf::testing::writeBlockMap(path, nx, ny, nz);
  }
  ~TempMap() { fs::remove(path); }
  fs::path path;
  std::size_t occupied = 0;
};

struct HttpReply {
  int status = 0;  // 0: no reply (connection failed or closed)
  std::string body;
  std::string set_cookie;
};

HttpReply httpGet(std::uint16_t port, const std::string& target, const std::string& cookie = "") {
  HttpReply out;
  try {
    boost::asio::io_context io;
    beast::tcp_stream stream(io);
    stream.expires_after(std::chrono::seconds(30));
    stream.connect(tcp::endpoint(boost::asio::ip::make_address(kHost), port));
    http::request<http::empty_body> req(http::verb::get, target, 11);
    req.set(http::field::host, std::string(kHost) + ":" + std::to_string(port));
    if (!cookie.empty()) req.set(http::field::cookie, cookie);
    http::write(stream, req);
    beast::flat_buffer buffer;
    http::response<http::string_body> res;
    http::read(stream, buffer, res);
    out.status = static_cast<int>(res.result_int());
    out.body = res.body();
    out.set_cookie = std::string(res[http::field::set_cookie]);
  } catch (const std::exception&) {
  }
  return out;
}

// A WebSocket client; `status` is 101 when the view took it, else what it answered (503, 401, ...).
struct Feed {
  Feed(std::uint16_t port, const std::string& target = "/ws", const std::string& origin = "") : ws(io) {
    try {
      beast::get_lowest_layer(ws).expires_after(std::chrono::seconds(30));
      beast::get_lowest_layer(ws).connect(tcp::endpoint(boost::asio::ip::make_address(kHost), port));
      beast::get_lowest_layer(ws).expires_never();
      if (!origin.empty())
        ws.set_option(websocket::stream_base::decorator(
            [origin](websocket::request_type& req) { req.set(http::field::origin, origin); }));
      // The asynchronous handshake hands back the response of a refusal too (the blocking one does not).
      websocket::response_type res;
      beast::error_code ec = boost::asio::error::would_block;
      ws.async_handshake(res, std::string(kHost) + ":" + std::to_string(port), target,
                         [&ec](beast::error_code e) { ec = e; });
      io.run();
      if (!ec || !res[http::field::server].empty()) status = static_cast<int>(res.result_int());  // ogf-view names itself
      body = res.body();
    } catch (const std::exception&) {
    }
  }
  // Reads one message; nullopt once the view closed the feed (or nothing came within 30 s).
  std::optional<std::string> read() {
    beast::flat_buffer buffer;
    beast::error_code ec;
    beast::get_lowest_layer(ws).expires_after(std::chrono::seconds(30));
    ws.read(buffer, ec);
    if (ec) return std::nullopt;
    return beast::buffers_to_string(buffer.data());
  }
  bool readOne() { return read().has_value(); }
  boost::asio::io_context io;
  websocket::stream<beast::tcp_stream> ws;
  int status = 0;
  std::string body;
};

// A plain TCP connection that sends nothing unless asked.
class RawConnection {
 public:
  explicit RawConnection(std::uint16_t port) {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(port);
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::connect(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
      ::close(fd_);
      fd_ = -1;
    }
  }
  ~RawConnection() {
    if (fd_ >= 0) ::close(fd_);
  }
  RawConnection(const RawConnection&) = delete;
  RawConnection& operator=(const RawConnection&) = delete;
  bool connected() const { return fd_ >= 0; }
  bool send(const std::string& bytes) { return ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(bytes.size()); }
  // Reads until the peer closes (true) or `limit` passes without it (false).
  bool readsToClose(std::chrono::seconds limit, std::string* text = nullptr) {
    timeval tv{static_cast<time_t>(limit.count()), 0};
    ::setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    const auto end = std::chrono::steady_clock::now() + limit;
    char buf[65536];
    while (std::chrono::steady_clock::now() < end) {
      const ssize_t n = ::recv(fd_, buf, sizeof buf, 0);
      if (n == 0) return true;
      if (n < 0) return errno == ECONNRESET;
      if (text) text->append(buf, static_cast<std::size_t>(n));
    }
    return false;
  }

 private:
  int fd_ = -1;
};

// The view's counters (GET /status), one number.
std::int64_t statusFigure(std::uint16_t port, const std::string& name, const std::string& query = "") {
  const auto reply = httpGet(port, "/status" + query);
  const std::regex re("\"" + name + "\":([0-9]+)");
  std::smatch m;
  if (reply.status != 200 || !std::regex_search(reply.body, m, re)) return -1;
  return std::stoll(m[1]);
}

// Waits (up to `limit`, polling) until the view's counter `name` reaches `want`; returns its last value.
std::int64_t waitForFigure(std::uint16_t port, const std::string& name, std::int64_t want,
                           std::chrono::seconds limit = std::chrono::seconds(60), bool at_most = false) {
  std::int64_t v = -1;
  const auto end = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < end) {
    v = statusFigure(port, name);
    if (v >= 0 && (at_most ? v <= want : v >= want)) return v;
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  return v;
}

double mb(std::int64_t bytes) { return static_cast<double>(bytes) / 1e6; }

double cpuSeconds(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto close = text.rfind(')');
  if (close == std::string::npos) return -1.0;
  std::istringstream rest(text.substr(close + 2));
  std::string field;
  // Fields after the command: state (3), ..., utime (14), stime (15).
  std::vector<std::string> f;
  while (rest >> field) f.push_back(field);
  if (f.size() < 13) return -1.0;
  return static_cast<double>(std::stoll(f[11]) + std::stoll(f[12])) / static_cast<double>(::sysconf(_SC_CLK_TCK));
}

// Malformed messages on OGF_NAV_GRID (bytes that are no nav_grid_t, a truncated one, well-formed ones whose
// fields disagree) are counted in the grid's figures, and the view keeps serving: the page, and on the feed
// the grid of the good keyframe published after them, equal to the mapper's.
TEST(ViewLimits, MalformedNavMessagesAreCountedAndTheViewKeepsServingTheGrid) {
  if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << *why;
  const std::string bus = ogf::testing::loopbackUdpmUrl(27);
  lcm::LCM lcm(bus);
  ASSERT_TRUE(lcm.good());
  ViewProcess view({"--lcm-url", bus, "--port", "0", "--rate", "10"}, "nav-malformed");
  const std::uint16_t port = view.port();
  ASSERT_NE(port, 0);

  ogf::testing::NavRoom room;
  const auto good = room.keyframe(1);
  ASSERT_EQ(good.size(), 1u);
  std::vector<std::uint8_t> encoded(static_cast<std::size_t>(good[0].getEncodedSize()));
  good[0].encode(encoded.data(), 0, static_cast<int>(encoded.size()));
  const std::string garbage = "not a nav_grid_t at all";
  std::vector<ogf::nav_grid_t> disagreeing(4, good[0]);
  disagreeing[0].tile_size = 16;
  disagreeing[1].num_columns -= 1;
  disagreeing[2].cost[0] = 120;
  disagreeing[3].part_count = -3;
  // Each malformed message is sent once, small datagrams on loopback, before the good keyframe.
  const int sent = 2 + static_cast<int>(disagreeing.size());
  lcm.publish("OGF_NAV_GRID", garbage.data(), static_cast<unsigned>(garbage.size()));
  lcm.publish("OGF_NAV_GRID", encoded.data(), static_cast<unsigned>(encoded.size() / 2));
  ogf::testing::publishAll(lcm, "OGF_NAV_GRID", disagreeing);

  Feed feed(port);
  ASSERT_EQ(feed.status, 101);
  const std::regex malformed(R"("nav":\{[^}]*"malformed":([0-9]+))");
  const std::regex consistent(R"("nav":\{"seq":0,"known_columns":225,[^}]*"consistent":true)");
  std::int64_t counted = -1;
  std::size_t tiles = 0;
  bool grid = false;
  for (int i = 0; i < 600 && !(grid && tiles > 0); ++i) {
    if (i % 5 == 0) ogf::testing::publishAll(lcm, "OGF_NAV_GRID", good);
    const auto msg = feed.read();
    ASSERT_TRUE(msg.has_value()) << "the feed closed\n" << view.log();
    if (const auto nav = ogf::view::decodeNavFrame({reinterpret_cast<const std::uint8_t*>(msg->data()), msg->size()})) {
      tiles += nav->tiles.size();
      continue;
    }
    std::smatch m;
    if (std::regex_search(*msg, m, malformed)) counted = std::stoll(m[1]);
    grid = std::regex_search(*msg, consistent);
  }
  EXPECT_TRUE(grid) << "the good keyframe after the malformed messages did not make the grid\n" << view.log();
  EXPECT_EQ(tiles, 1u) << "the room's one tile did not reach the feed";
  EXPECT_EQ(counted, sent) << view.log();
  EXPECT_EQ(httpGet(port, "/").status, 200);
  EXPECT_NE(view.log().find("OGF_NAV_GRID"), std::string::npos) << "no log line names the channel\n" << view.log();
}

// The keyframe requests on OGF_NAV_REQUEST, by the update each names as the last applied.
struct NavRequests {
  explicit NavRequests(lcm::LCM& lcm) { lcm.subscribe("OGF_NAV_REQUEST", &NavRequests::on, this); }
  void on(const lcm::ReceiveBuffer*, const std::string&, const ogf::map_request_t* m) { last_seq.push_back(m->last_seq); }
  std::vector<std::int64_t> last_seq;
};

// A lost update of the navigation grid is a gap: the view asks for a keyframe on OGF_NAV_REQUEST, naming
// the last update it applied, and the keyframe makes its grid equal to the mapper's again.
TEST(ViewLimits, AGapInTheNavGridMakesTheViewAskForAKeyframeAndTheKeyframeRepairsIt) {
  if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << *why;
  const std::string bus = ogf::testing::loopbackUdpmUrl(35);
  lcm::LCM lcm(bus);
  ASSERT_TRUE(lcm.good());
  NavRequests requests(lcm);
  ViewProcess view({"--lcm-url", bus, "--port", "0", "--rate", "10"}, "nav-gap");
  const std::uint16_t port = view.port();
  ASSERT_NE(port, 0);
  Feed feed(port);
  ASSERT_EQ(feed.status, 101);
  // Reads the feed until a status says the grid is at `seq` and equal to the mapper's, publishing `msgs`
  // now and then (a datagram may be lost on loopback) and taking the requests that came meanwhile.
  const auto gridAt = [&](int seq, const std::vector<ogf::nav_grid_t>& msgs) {
    const std::regex at("\"nav\":\\{\"seq\":" + std::to_string(seq) + ",[^}]*\"consistent\":true");
    for (int i = 0; i < 600; ++i) {
      if (i % 5 == 0) ogf::testing::publishAll(lcm, "OGF_NAV_GRID", msgs);
      lcm.handleTimeout(0);
      const auto msg = feed.read();
      if (!msg) return false;
      if (std::regex_search(*msg, at)) return true;
    }
    return false;
  };

  ogf::testing::NavRoom room;
  ASSERT_TRUE(gridAt(0, room.keyframe(1))) << view.log();
  room.addObstacle(6, 9, 6, 9, 2);  // update 1, lost
  const auto update2 = room.addObstacle(2, 4, 2, 4, 3);
  ogf::testing::publishAll(lcm, "OGF_NAV_GRID", update2);
  bool asked = false;
  for (int i = 0; i < 50 && !asked; ++i) {
    lcm.handleTimeout(100);
    asked = std::find(requests.last_seq.begin(), requests.last_seq.end(), 0) != requests.last_seq.end();
  }
  EXPECT_TRUE(asked) << "no keyframe request naming update 0 after the gap\n" << view.log();
  EXPECT_TRUE(gridAt(2, room.keyframe(4))) << view.log();
  EXPECT_NE(view.log().find("gap in the navigation grid"), std::string::npos) << view.log();
}

// A mapper with nav off publishes no navigation grid: the view's keyframe requests on OGF_NAV_REQUEST
// thin out (every 2, 4, 8 s with --keyframe-retry 2, not every 2 s), and the first grid message heard makes
// it ask at once.
TEST(ViewLimits, ASilentNavGridIsAskedForLessOftenAndTheFirstMessageHeardIsAnsweredAtOnce) {
  if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << *why;
  const std::string bus = ogf::testing::loopbackUdpmUrl(36);
  lcm::LCM lcm(bus);
  ASSERT_TRUE(lcm.good());
  NavRequests requests(lcm);
  ViewProcess view({"--lcm-url", bus, "--port", "0", "--rate", "10", "--keyframe-retry", "2"}, "nav-silent");
  ASSERT_NE(view.port(), 0);
  // At 0, 2 and 6 s while nothing is heard (every 2 s would make four by 7 s).
  const auto start = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() - start < std::chrono::seconds(7)) lcm.handleTimeout(100);
  EXPECT_GE(requests.last_seq.size(), 1u) << view.log();
  EXPECT_LE(requests.last_seq.size(), 3u) << view.log();
  // An update of a grid the view has no keyframe of: the next request by the doubling would come at 14 s;
  // this one comes as soon as the update is heard (published again now and then: a datagram may be lost).
  ogf::testing::NavRoom room;
  (void)room.keyframe(1);
  const auto update = room.addObstacle(2, 4, 2, 4, 2);
  const std::size_t before = requests.last_seq.size();
  for (int i = 0; i < 40 && requests.last_seq.size() == before; ++i) {
    if (i % 5 == 0) ogf::testing::publishAll(lcm, "OGF_NAV_GRID", update);
    lcm.handleTimeout(100);
  }
  EXPECT_GT(requests.last_seq.size(), before) << "no keyframe request within 4 s of the first grid message heard\n"
                                    << view.log();
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(14)) << view.log();
}

TEST(ViewLimits, ClientsBeyondTheMaximumAreRefusedWhileTheOthersKeepTheirFeed) {
  const TempMap map(20, 20, 5);
  ViewProcess view({"--map", map.path.string(), "--port", "0", "--rate", "10", "--max-clients", "2"}, "max");
  const auto port = view.port();
  ASSERT_NE(port, 0);

  Feed a(port), b(port);
  ASSERT_EQ(a.status, 101) << view.log();
  ASSERT_EQ(b.status, 101);
  ASSERT_TRUE(a.readOne());
  Feed c(port);
  EXPECT_EQ(c.status, 503) << "a third feed with --max-clients 2";
  EXPECT_NE(c.body.find("serves 2 browsers at once"), std::string::npos) << c.body;
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(a.readOne()) << "the first feed stopped after the refusal";
  ASSERT_TRUE(b.readOne());

  // HTTP connections beyond 4 x 2 + 8 = 16 get 503 too; the page comes back once they are gone.
  std::vector<std::unique_ptr<RawConnection>> held;
  for (int i = 0; i < 15; ++i) held.push_back(std::make_unique<RawConnection>(port));
  ASSERT_EQ(waitForFigure(port, "http_connections", 16), 16);  // the 15 and the /status request itself
  held.push_back(std::make_unique<RawConnection>(port));
  const auto busy = httpGet(port, "/");
  EXPECT_EQ(busy.status, 503);
  EXPECT_NE(busy.body.find("too many connections"), std::string::npos) << busy.body;
  held.clear();
  EXPECT_EQ(waitForFigure(port, "http_connections", 1, std::chrono::seconds(30), true), 1);
  EXPECT_EQ(httpGet(port, "/").status, 200);
  EXPECT_TRUE(a.readOne());
  EXPECT_GE(statusFigure(port, "refused_busy"), 2);
}

TEST(ViewLimits, IdleAndHalfOpenConnectionsAreClosedAfterTheClientTimeout) {
  const TempMap map(20, 20, 5);
  ViewProcess view({"--map", map.path.string(), "--port", "0", "--rate", "10", "--client-timeout", "2"}, "idle");
  const auto port = view.port();
  ASSERT_NE(port, 0);

  // A feed whose peer stops reading and answering (as a host that vanished): closed, counted.
  Feed silent(port);
  ASSERT_EQ(silent.status, 101) << view.log();
  // A feed that reads (Beast answers pings while reading) stays through several timeouts.
  Feed live(port);
  ASSERT_EQ(live.status, 101);
  // A keep-alive HTTP connection left idle after one request, and one that never completes a request.
  RawConnection keep_alive(port), partial(port);
  ASSERT_TRUE(keep_alive.send("GET /status HTTP/1.1\r\nHost: x\r\n\r\n"));
  ASSERT_TRUE(partial.send("GET / HTTP/1.1\r\nHost: x\r\n"));

  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(8);
  while (std::chrono::steady_clock::now() < until) ASSERT_TRUE(live.readOne()) << "a reading feed was closed\n" << view.log();
  EXPECT_EQ(statusFigure(port, "clients"), 1) << "the silent feed is still open";
  EXPECT_GE(statusFigure(port, "timed_out"), 3);
  EXPECT_TRUE(keep_alive.readsToClose(std::chrono::seconds(30))) << "the idle keep-alive connection stayed open";
  EXPECT_TRUE(partial.readsToClose(std::chrono::seconds(30))) << "the incomplete request stayed open";
  bool silent_closed = false;
  for (int i = 0; i < 1000 && !silent_closed; ++i) silent_closed = !silent.readOne();
  EXPECT_TRUE(silent_closed) << "the silent feed's socket was not closed";
}

// `clients` feeds that never read a byte, on a map of 200 000 occupied cells (a whole state of 4.4 MB),
// with `args` added to ogf-view's. The view may take its start plus two whole states (the one shared by
// the feeds and one being made), 64 KiB a connection (Beast's buffers, the socket, the allocator) and
// 32 MiB of slack; a copy of the whole state per feed (100 x 4.4 MB) does not fit.
void expectMemoryBoundedWithNeverReadingFeeds(int clients, std::vector<std::string> args) {
  const TempMap map(100, 100, 20);
  ASSERT_GT(map.occupied, 150000u);
  const std::int64_t whole_state = static_cast<std::int64_t>(map.occupied) * 22;
  args.insert(args.end(), {"--map", map.path.string(), "--port", "0"});
  ViewProcess view(args, "memory");
  const auto port = view.port();
  ASSERT_NE(port, 0);
  ASSERT_EQ(httpGet(port, "/").status, 200);
  const auto start = ogf::testing::residentBytes(view.pid());
  ASSERT_TRUE(start.has_value());

  std::int64_t peak = 0;
  int taken = 0, refused = 0;
  {
    ogf::testing::RssSampler sampler(view.pid(), std::chrono::milliseconds(20));
    std::vector<std::unique_ptr<Feed>> feeds;
    for (int i = 0; i < clients; ++i) {
      feeds.push_back(std::make_unique<Feed>(port));
      (feeds.back()->status == 101 ? taken : refused) += 1;
    }
    std::this_thread::sleep_for(std::chrono::seconds(3));  // let the view queue what it would
    peak = sampler.peakBytes();
  }
  const std::int64_t bound = *start + 2 * whole_state + std::int64_t{clients} * (64 << 10) + (std::int64_t{32} << 20);
  std::printf("[ figures ] %d feeds that never read (%d taken, %d refused), whole state %.1f MB: view RSS %.1f MB "
              "at start, %.1f MB peak, bound %.1f MB\n",
              clients, taken, refused, mb(whole_state), mb(*start), mb(peak), mb(bound));
  EXPECT_LE(peak, bound);
  EXPECT_GT(taken, 0);
}

int idleClients() {
  const char* n = std::getenv("OGF_VIEW_IDLE_CLIENTS");  // 300 for the figures in docs/reliability.md
  return n ? std::atoi(n) : 100;
}

// With the default flags: --max-clients 32 takes 32, refuses the rest.
TEST(ViewLimits, ClientsThatNeverReadKeepTheViewMemoryBounded) { expectMemoryBoundedWithNeverReadingFeeds(idleClients(), {}); }

// With room for all of them: they share one whole state, and what waits behind it is bounded.
TEST(ViewLimits, ClientsThatNeverReadShareOneWholeStateWhenAllAreTaken) {
  const int n = idleClients();
  expectMemoryBoundedWithNeverReadingFeeds(n, {"--max-clients", std::to_string(n)});
}

// On a live bus, 16 feeds that never read each hold the whole state of the moment they joined (6.6 MB:
// 300 000 occupied cells, --max-boxes above it) while the map changes between joins: every generation
// they pin (106 MB in all) is kept only for them. With --memory-budget 16 the view closes the feeds whose
// writes waited longest once those frames pass 16 MiB, and its memory stays under start + the budget +
// three whole states (the current one, one being made, one in flight) + 64 KiB a connection + 32 MiB.
TEST(ViewLimits, FramesKeptForFeedsThatAreBehindStayWithinTheMemoryBudget) {
  if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << *why;
  const std::string bus = ogf::testing::loopbackUdpmUrl(25);
  lcm::LCM lcm(bus);
  ASSERT_TRUE(lcm.good());
  ViewProcess view({"--lcm-url", bus, "--port", "0", "--rate", "10", "--memory-budget", "16", "--max-boxes", "2000000"},
                   "budget");
  const auto port = view.port();
  ASSERT_NE(port, 0);

  ogf::delta::DeltaStream stream({0.2, 25, ogf::messages::kMaxDeltaCellsPerMessage});
  std::vector<ogf::delta::PublishedCell> block;
  for (int x = 0; x < 150; ++x)
    for (int y = 0; y < 100; ++y)
      for (int z = 0; z < 20; ++z) block.push_back({{x, y, z}, 9000, ogf::map_delta_t::CLASS_OCCUPIED, 0.3f});
  stream.update(1, block);
  const std::int64_t whole_state = static_cast<std::int64_t>(block.size()) * 22;
  Feed watcher(port);
  ASSERT_EQ(watcher.status, 101) << view.log();
  // Until the watcher's figures say `seq`; the keyframe is sent again when a datagram was lost.
  const auto waitForSeq = [&](std::int64_t seq, const std::vector<ogf::map_delta_t>& resend) {
    const std::string want = "\"seq\":" + std::to_string(seq) + ",";
    for (int i = 0; i < 600; ++i) {
      const auto m = watcher.read();
      if (!m) return false;
      if (m->find(want) != std::string::npos) return true;
      if (i % 20 == 0)
        for (const auto& d : resend) lcm.publish("OGF_MAP_DELTA", &d);
    }
    return false;
  };
  ASSERT_TRUE(waitForSeq(1, stream.keyframe(2))) << view.log();
  const auto start = ogf::testing::residentBytes(view.pid());
  ASSERT_TRUE(start.has_value());

  std::int64_t peak = 0, over_budget = -1, behind_bytes = -1;
  int clients = 0;
  {
    ogf::testing::RssSampler sampler(view.pid(), std::chrono::milliseconds(20));
    std::vector<std::unique_ptr<Feed>> stuck;
    for (int g = 0; g < 16; ++g, ++clients) {
      stuck.push_back(std::make_unique<Feed>(port));
      std::vector<ogf::delta::PublishedCell> one{{{200 + g, 0, 0}, 9000, ogf::map_delta_t::CLASS_OCCUPIED, 0.3f}};
      const auto update = stream.update(3 + g, one);
      for (const auto& d : update) lcm.publish("OGF_MAP_DELTA", &d);
      ASSERT_TRUE(waitForSeq(stream.seq(), stream.keyframe(3 + g))) << view.log();
    }
    std::this_thread::sleep_for(std::chrono::seconds(1));
    peak = sampler.peakBytes();
    over_budget = statusFigure(port, "over_budget");
    behind_bytes = statusFigure(port, "behind_bytes");
  }
  const std::int64_t budget = std::int64_t{16} << 20;
  const std::int64_t bound = *start + budget + 3 * whole_state + clients * (64 << 10) + (std::int64_t{32} << 20);
  std::printf("[ figures ] %d feeds stuck on as many generations of a %.1f MB whole state, --memory-budget 16: view RSS "
              "%.1f MB at start, %.1f MB peak, bound %.1f MB\n",
              clients, mb(whole_state), mb(*start), mb(peak), mb(bound));
  EXPECT_GE(over_budget, 1);
  EXPECT_GE(behind_bytes, 0);
  EXPECT_LE(behind_bytes, budget);
  EXPECT_LE(peak, bound);
}

TEST(ViewLimits, AnOversizedIncomingMessageClosesThatClientOnly) {
  const TempMap map(20, 20, 5);
  ViewProcess view({"--map", map.path.string(), "--port", "0", "--rate", "10"}, "oversized");
  const auto port = view.port();
  ASSERT_NE(port, 0);
  Feed big(port), other(port);
  ASSERT_EQ(big.status, 101) << view.log();
  ASSERT_EQ(other.status, 101);
  ASSERT_TRUE(big.readOne());

  big.ws.text(true);
  beast::error_code ec;
  big.ws.write(boost::asio::buffer(std::string(64 * 1024, 'x')), ec);
  bool closed = false;
  for (int i = 0; i < 200 && !closed; ++i) closed = !big.readOne();  // 20 s of frames at --rate 10
  EXPECT_TRUE(closed) << "a 64 KiB message did not close its feed";
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(other.readOne()) << "the other feed was closed too";
  EXPECT_EQ(statusFigure(port, "oversized"), 1);
  EXPECT_EQ(statusFigure(port, "clients"), 1);
}

// prlimit gives the view 48 descriptors; 80 connections that send nothing take them all, the rest wait in
// the listen queue. While they are held the view must not spin on accept (at most a tenth of the time
// held spent on the CPU: spinning takes all of it), and once they close a real client gets in.
TEST(ViewLimits, AtTheDescriptorLimitTheViewWaitsAndLetsARealClientInLater) {
  if (::access("/usr/bin/prlimit", X_OK) != 0) GTEST_SKIP() << "prlimit (util-linux) is not installed";
  const TempMap map(20, 20, 5);
  ViewProcess view({"--map", map.path.string(), "--port", "0"}, "descriptors", {"/usr/bin/prlimit", "--nofile=48:48", "--"});
  const auto port = view.port();
  ASSERT_NE(port, 0) << view.log();

  std::vector<std::unique_ptr<RawConnection>> held;
  for (int i = 0; i < 80; ++i) held.push_back(std::make_unique<RawConnection>(port));
  std::this_thread::sleep_for(std::chrono::seconds(1));
  const double cpu0 = cpuSeconds(view.pid());
  const auto t0 = std::chrono::steady_clock::now();
  std::this_thread::sleep_for(std::chrono::seconds(5));
  const double cpu1 = cpuSeconds(view.pid());
  const double held_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("[ figures ] 80 connections held on 48 descriptors: %.2f s of CPU in %.1f s\n", cpu1 - cpu0, held_s);
  ASSERT_GE(cpu0, 0.0);
  EXPECT_LT(cpu1 - cpu0, 0.1 * held_s) << "the view spins at the descriptor limit";

  held.clear();
  HttpReply page;
  for (int i = 0; i < 100 && page.status != 200; ++i) {
    page = httpGet(port, "/");
    if (page.status != 200) std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  EXPECT_EQ(page.status, 200) << view.log();
  Feed feed(port);
  EXPECT_EQ(feed.status, 101);
  EXPECT_TRUE(feed.readOne());
  // Each shortage is logged once, however many accepts failed during it.
  const auto episodes = statusFigure(port, "accept_pauses");
  const std::string log = view.log();
  std::int64_t lines = 0;
  for (auto at = log.find("pausing accepts"); at != std::string::npos; at = log.find("pausing accepts", at + 1)) ++lines;
  EXPECT_GE(episodes, 1);
  EXPECT_EQ(lines, episodes) << log;
}

TEST(ViewLimits, ANetworkBindAsksForTheTokenAndLoopbackDoesNot) {
  const TempMap map(10, 10, 5);
  {
    // 0.0.0.0 is every interface: a token is made and printed; the test talks to it over 127.0.0.1.
    ViewProcess view({"--map", map.path.string(), "--port", "0", "--bind", "0.0.0.0"}, "token");
    const std::string url = view.url();
    const auto at = url.find("?token=");
    ASSERT_NE(at, std::string::npos) << "no token in the address printed: " << url;
    const std::string token = url.substr(at + 7);
    ASSERT_GE(token.size(), 32u);
    const auto port = view.port();

    EXPECT_EQ(httpGet(port, "/").status, 401);
    EXPECT_EQ(httpGet(port, "/?token=" + std::string(token.size(), '0')).status, 401);
    EXPECT_EQ(httpGet(port, "/lib/three.min.js").status, 401);
    EXPECT_EQ(httpGet(port, "/status").status, 401);
    const auto page = httpGet(port, "/?token=" + token);
    EXPECT_EQ(page.status, 200);
    EXPECT_NE(page.set_cookie.find("ogf_view_token=" + token), std::string::npos) << page.set_cookie;
    EXPECT_EQ(httpGet(port, "/lib/three.min.js", "ogf_view_token=" + token).status, 200);
    EXPECT_EQ(Feed(port).status, 401);
    EXPECT_EQ(Feed(port, "/ws?token=x" + token).status, 401);
    Feed feed(port, "/ws?token=" + token);
    EXPECT_EQ(feed.status, 101);
    EXPECT_TRUE(feed.readOne());
    // A page of another site may not open the feed, even with the token.
    EXPECT_EQ(Feed(port, "/ws?token=" + token, "http://elsewhere.example").status, 403);
  }
  {
    // 127.0.0.2 is loopback: no token.
    ViewProcess view({"--map", map.path.string(), "--port", "0", "--bind", "127.0.0.2"}, "loopback2");
    const std::string url = view.url();
    EXPECT_EQ(url.find("token"), std::string::npos) << url;
    boost::asio::io_context io;
    beast::tcp_stream stream(io);
    beast::error_code ec;
    stream.connect(tcp::endpoint(boost::asio::ip::make_address("127.0.0.2"), view.port()), ec);
    ASSERT_FALSE(ec) << ec.message();
    http::request<http::empty_body> req(http::verb::get, "/", 11);
    req.set(http::field::host, "127.0.0.2");
    http::write(stream, req);
    beast::flat_buffer buffer;
    http::response<http::string_body> res;
    http::read(stream, buffer, res);
    EXPECT_EQ(res.result_int(), 200);
  }
}

}  // namespace
