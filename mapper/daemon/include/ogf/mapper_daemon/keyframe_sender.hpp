// Sends keyframes from a thread of its own, so mapping goes on while a large map goes out. The worker cuts
// a keyframe (delta/keyframe_writer.hpp: the published cells in memory copied, the pages holding the rest
// named) and hands it over; this thread reads the pages one at a time, publishes each part as it fills, in
// bursts with a pause between them (a receiver's socket buffer takes a burst), and reports when done.
// Memory stays at one page and one part beyond the copy, whatever the map's size.
#pragma once

#include <ogf/map_delta_t.hpp>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "ogf/delta/keyframe_writer.hpp"
#include "ogf/delta/published_cell.hpp"
#include "ogf/persistence/map_pager.hpp"

namespace ogf::mapper_daemon {

class KeyframeSender {
 public:
  struct Job {
    delta::KeyframeWriter writer;
    std::vector<delta::PublishedCell> resident;  // the published cells in memory when it was cut
    std::vector<std::filesystem::path> pages;    // the pages holding the rest (MapPager::heldPublishedPages)
    double cut_ms = 0.0;                         // what cutting it cost the worker
  };
  struct Report {
    std::int64_t seq = 0;
    std::size_t cells = 0;       // cells sent
    std::int32_t parts = 0;
    std::size_t page_cells = 0;  // of them, read from pages
    std::size_t missing = 0;     // cells the parts lack (damaged pages), surplus: cells beyond the count
    std::size_t surplus = 0;
    double cut_ms = 0.0;
    double send_ms = 0.0;
    std::vector<persistence::PageDamage> damage;
  };
  using Publish = std::function<void(const ogf::map_delta_t&)>;
  using Done = std::function<void(const Report&)>;
  // How long to wait before the next part (0: send it now): the delta channel's byte budget.
  using Pace = std::function<std::chrono::microseconds()>;

  // `publish`, `done` and `pace` run on the sender's thread; `done` only for a keyframe sent whole, before
  // the sender turns idle (busy() is still true while it runs). Parts go out `burst` at a time (16 parts of
  // 3300 cells are about 1 MB) with `pause` between bursts, and each waits first for what `pace` asks.
  KeyframeSender(Publish publish, Done done, int burst = 16,
                 std::chrono::microseconds pause = std::chrono::milliseconds(2), Pace pace = {});
  // Stops the thread; a keyframe in flight is cut short.
  ~KeyframeSender();
  KeyframeSender(const KeyframeSender&) = delete;
  KeyframeSender& operator=(const KeyframeSender&) = delete;

  // Whether a keyframe is being sent; send() takes one only when not.
  bool busy() const;
  void send(Job job);
  // Stops the keyframe in flight, if any, and returns when the sender is idle (no report for it): before
  // the pages it reads go away.
  void cancel();
  // The file names of the pages the keyframe in flight reads: MapPager::collect must keep them.
  std::vector<std::string> pinnedPages() const;

 private:
  void run();
  Report sendJob(Job& job);
  // Publishes one part, pausing after each burst; false when stopping or cancelled.
  bool publishPaced(const ogf::map_delta_t& part);
  bool halted() const;  // stop or cancel (mu_ not held)

  Publish publish_;
  Done done_;
  Pace pace_;
  int burst_;
  std::chrono::microseconds pause_;
  int in_burst_ = 0;

  mutable std::mutex mu_;
  std::condition_variable cv_;
  std::optional<Job> job_;
  bool busy_ = false;
  bool stop_ = false;
  bool cancel_ = false;
  std::vector<std::string> pinned_;
  std::thread thread_;
};

}  // namespace ogf::mapper_daemon
