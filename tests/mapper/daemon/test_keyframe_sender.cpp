// KeyframeSender: a keyframe cut from a published map part in memory and part in pages goes out over real
// udpm on loopback and a client rebuilds the whole map from it; a damaged page costs only its cells and is
// reported; while it sends, the pages it reads are pinned, and cancel() stops it without a report.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <fstream>
#include <future>
#include <mutex>
#include <random>
#include <thread>

#include "ogf/delta/delta_stream.hpp"
#include "ogf/delta/map_receiver.hpp"
#include "ogf/mapper_daemon/keyframe_sender.hpp"
#include "ogf/persistence/page_file.hpp"
#include "ogf/transport/lcm_url.hpp"
#include "support/lcm_thread.hpp"
#include "support/multicast.hpp"

namespace ogf::mapper_daemon {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

class KeyframeSenderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("ogf-keyframe-sender-" + std::to_string(::getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    // A published map around the origin; two regions of it (32 cells a side) go to pages, as paging does.
    std::mt19937 rng(5);
    std::uniform_int_distribution<int> coord(-40, 40);
    std::uniform_int_distribution<int> prob(0, 10000);
    for (int scan = 0; scan < 8; ++scan) {
      std::vector<delta::PublishedCell> cells;
      for (int i = 0; i < 400; ++i) {
        const auto p = static_cast<std::int16_t>(prob(rng));
        cells.push_back({{coord(rng), coord(rng), coord(rng) / 8}, p, static_cast<std::int8_t>(p > 6500 ? 1 : -1), 0.25f});
      }
      stream_.update(scan, cells);
    }
    for (const CellKey region : {CellKey{0, 0, 0}, CellKey{-1, -1, 0}}) {
      const CellKey lo{region.x * 32, region.y * 32, region.z * 32};
      const CellKey hi = lo + CellKey{32, 32, 32};
      persistence::Page page;
      page.region = region;
      page.published = stream_.map().cellsIn(lo, hi);
      ASSERT_FALSE(page.published.empty());
      page_cells_ += page.published.size();
      stream_.map().evict(lo, hi);
      const auto bytes = persistence::encodePage(page);
      const fs::path path = dir_ / ("r" + std::to_string(region.x) + "_" + std::to_string(region.y) + "_0-1.ogfp");
      std::ofstream(path, std::ios::binary)
          .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
      pages_.push_back(path);
    }
  }
  void TearDown() override { fs::remove_all(dir_); }

  KeyframeSender::Job job() {
    return {delta::KeyframeWriter(stream_, 1), stream_.map().sortedCells(), pages_, 0.0};
  }

  fs::path dir_;
  delta::DeltaStream stream_{{0.2, 7, 100}};
  std::vector<fs::path> pages_;
  std::size_t page_cells_ = 0;
};

// A client of the keyframe channel.
class KeyframeClient {
 public:
  explicit KeyframeClient(const std::string& url) : bus_(url) {
    // A keyframe is more parts than LCM's default queue of 30 holds while this thread waits for a core.
    bus_.lcm().subscribe("TEST_KEYFRAME", &KeyframeClient::onDelta, this)->setQueueCapacity(
        transport::kSubscriptionQueueCapacity);
    bus_.lcm().subscribe("TEST_PING", &KeyframeClient::onPing, this);
    bus_.start(20ms);
  }
  // Pings through `lcm` until this client hears one: its socket is in the group before a keyframe starts.
  bool waitListening(lcm::LCM& lcm) {
    for (int i = 0; i < 100; ++i) {
      const ogf::map_delta_t ping{};
      lcm.publish("TEST_PING", &ping);
      std::unique_lock lk(mu_);
      if (cv_.wait_for(lk, 50ms, [this] { return pinged_; })) return true;
    }
    return false;
  }
  bool waitApplied(std::chrono::milliseconds limit) {
    std::unique_lock lk(mu_);
    return cv_.wait_for(lk, limit, [this] { return receiver_.keyframesApplied() > 0; });
  }
  std::uint64_t checksum() {
    std::lock_guard lk(mu_);
    return receiver_.map().checksum();
  }
  bool consistent() {
    std::lock_guard lk(mu_);
    return receiver_.consistent();
  }

 private:
  void onPing(const lcm::ReceiveBuffer*, const std::string&, const ogf::map_delta_t*) {
    std::lock_guard lk(mu_);
    pinged_ = true;
    cv_.notify_all();
  }
  void onDelta(const lcm::ReceiveBuffer*, const std::string&, const ogf::map_delta_t* m) {
    std::lock_guard lk(mu_);
    receiver_.accept(*m);
    cv_.notify_all();
  }
  std::mutex mu_;
  std::condition_variable cv_;
  delta::MapReceiver receiver_;
  bool pinged_ = false;
  ogf::testing::LcmThread bus_;  // last: its thread stops before the receiver is gone
};

TEST_F(KeyframeSenderTest, ClientRebuildsAMapHeldPartlyInPagesOverUdpm) {
  if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << *why;
  const std::string url = ogf::testing::loopbackUdpmUrl(76);
  KeyframeClient client(url);
  lcm::LCM lcm(url);
  ASSERT_TRUE(client.waitListening(lcm)) << "no message came back over " << url;
  std::promise<KeyframeSender::Report> done;
  KeyframeSender sender([&](const ogf::map_delta_t& m) { lcm.publish("TEST_KEYFRAME", &m); },
                        [&](const KeyframeSender::Report& r) { done.set_value(r); });
  sender.send(job());
  auto report = done.get_future();
  ASSERT_EQ(report.wait_for(10s), std::future_status::ready);
  const KeyframeSender::Report r = report.get();
  EXPECT_EQ(r.cells, stream_.map().size());
  EXPECT_EQ(r.page_cells, page_cells_);
  EXPECT_EQ(r.parts, static_cast<std::int32_t>((stream_.map().size() + 99) / 100));
  EXPECT_EQ(r.missing + r.surplus, 0u);
  EXPECT_TRUE(r.damage.empty());
  ASSERT_TRUE(client.waitApplied(5s)) << "the keyframe did not arrive whole";
  EXPECT_TRUE(client.consistent());
  EXPECT_EQ(client.checksum(), stream_.map().checksum());
  // The report comes from the sender's thread just before it turns idle.
  const auto deadline = std::chrono::steady_clock::now() + 5s;
  while (sender.busy() && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(1ms);
  EXPECT_FALSE(sender.busy());
  EXPECT_TRUE(sender.pinnedPages().empty());
}

TEST_F(KeyframeSenderTest, DamagedPageCostsItsCellsAndIsReported) {
  std::ofstream(pages_[1], std::ios::binary | std::ios::trunc) << "torn";
  delta::MapReceiver receiver;
  std::promise<KeyframeSender::Report> done;
  KeyframeSender sender([&](const ogf::map_delta_t& m) { receiver.accept(m); },
                        [&](const KeyframeSender::Report& r) { done.set_value(r); });
  sender.send(job());
  auto report = done.get_future();
  ASSERT_EQ(report.wait_for(10s), std::future_status::ready);
  const KeyframeSender::Report r = report.get();
  ASSERT_EQ(r.damage.size(), 1u);
  EXPECT_EQ(r.damage[0].file, pages_[1]);
  EXPECT_NE(r.damage[0].reason.find(pages_[1].filename().string()), std::string::npos) << r.damage[0].reason;
  EXPECT_GT(r.missing, 0u);
  EXPECT_EQ(r.cells + r.missing, stream_.map().size());
  EXPECT_EQ(receiver.keyframesApplied(), 1u) << "every part goes out, so the client is not left waiting";
  EXPECT_FALSE(receiver.consistent());
}

TEST_F(KeyframeSenderTest, PagesArePinnedWhileSendingAndCancelStopsWithoutAReport) {
  std::mutex mu;
  std::condition_variable cv;
  std::atomic<int> published{0};
  std::atomic<int> reports{0};
  // One part a burst and an hour's pause: after its first part the sender waits, and only cancel() ends it.
  KeyframeSender sender(
      [&](const ogf::map_delta_t&) {
        std::lock_guard lk(mu);
        ++published;
        cv.notify_all();
      },
      [&](const KeyframeSender::Report&) { ++reports; }, 1, std::chrono::hours(1));
  sender.send(job());
  {
    std::unique_lock lk(mu);
    ASSERT_TRUE(cv.wait_for(lk, 5s, [&] { return published.load() > 0; }));
  }
  EXPECT_TRUE(sender.busy());
  const auto pinned = sender.pinnedPages();
  ASSERT_EQ(pinned.size(), 2u);
  EXPECT_EQ(pinned[0], pages_[0].filename().string());
  EXPECT_EQ(pinned[1], pages_[1].filename().string());
  sender.send(job());  // refused while busy
  sender.cancel();
  EXPECT_FALSE(sender.busy());
  EXPECT_TRUE(sender.pinnedPages().empty());
  EXPECT_EQ(reports.load(), 0);
  EXPECT_EQ(published.load(), 1) << "it went on after cancel()";
  ASSERT_GT(stream_.map().size(), 100u) << "the map must need more than one part";
}

}  // namespace
}  // namespace ogf::mapper_daemon
