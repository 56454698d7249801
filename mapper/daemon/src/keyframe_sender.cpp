#include "ogf/mapper_daemon/keyframe_sender.hpp"

#include <algorithm>
#include <span>

namespace ogf::mapper_daemon {

KeyframeSender::KeyframeSender(Publish publish, Done done, int burst, std::chrono::microseconds pause, Pace pace)
    : publish_(std::move(publish)),
      done_(std::move(done)),
      pace_(std::move(pace)),
      burst_(std::max(1, burst)),
      pause_(pause) {
  thread_ = std::thread([this] { run(); });
}

KeyframeSender::~KeyframeSender() {
  {
    std::lock_guard lk(mu_);
    stop_ = true;
  }
  cv_.notify_all();
  if (thread_.joinable()) thread_.join();
}

bool KeyframeSender::busy() const {
  std::lock_guard lk(mu_);
  return busy_;
}

void KeyframeSender::send(Job job) {
  {
    std::lock_guard lk(mu_);
    if (busy_ || stop_) return;
    pinned_.clear();
    for (const auto& page : job.pages) pinned_.push_back(page.filename().string());
    job_.emplace(std::move(job));
    busy_ = true;
  }
  cv_.notify_all();
}

void KeyframeSender::cancel() {
  std::unique_lock lk(mu_);
  if (!busy_) return;
  cancel_ = true;
  cv_.notify_all();
  cv_.wait(lk, [this] { return !busy_; });
  cancel_ = false;
}

bool KeyframeSender::halted() const {
  std::lock_guard lk(mu_);
  return stop_ || cancel_;
}

std::vector<std::string> KeyframeSender::pinnedPages() const {
  std::lock_guard lk(mu_);
  return pinned_;
}

void KeyframeSender::run() {
  std::unique_lock lk(mu_);
  while (true) {
    cv_.wait(lk, [this] { return stop_ || job_.has_value(); });
    if (stop_) return;
    Job job = std::move(*job_);
    job_.reset();
    lk.unlock();
    const Report report = sendJob(job);
    lk.lock();
    const bool whole = !stop_ && !cancel_;
    lk.unlock();
    if (whole) done_(report);
    lk.lock();
    pinned_.clear();
    busy_ = false;
    cv_.notify_all();  // cancel() waits for this
  }
}

bool KeyframeSender::publishPaced(const ogf::map_delta_t& part) {
  if (pace_) {
    for (auto wait = pace_(); wait.count() > 0; wait = pace_()) {
      std::unique_lock lk(mu_);
      if (cv_.wait_for(lk, wait, [this] { return stop_ || cancel_; })) return false;
    }
  }
  publish_(part);
  if (++in_burst_ < burst_) return true;
  in_burst_ = 0;
  std::unique_lock lk(mu_);
  return !cv_.wait_for(lk, pause_, [this] { return stop_ || cancel_; });
}

KeyframeSender::Report KeyframeSender::sendJob(Job& job) {
  const auto began = std::chrono::steady_clock::now();
  Report report;
  report.seq = job.writer.seq();
  report.cut_ms = job.cut_ms;
  in_burst_ = 0;
  std::vector<ogf::map_delta_t> parts;
  bool going = true;
  const auto flush = [&] {
    for (const auto& part : parts) {
      if (!going) break;
      report.cells += static_cast<std::size_t>(part.num_cells);
      ++report.parts;
      going = publishPaced(part);
    }
    parts.clear();
  };
  // The copy in memory a part at a time, then each page.
  const std::size_t step = 4096;
  const std::span<const delta::PublishedCell> resident(job.resident);
  for (std::size_t i = 0; i < resident.size() && going; i += step) {
    job.writer.add(resident.subspan(i, std::min(step, resident.size() - i)), parts);
    flush();
  }
  job.resident = {};
  for (const auto& page : job.pages) {
    if (!going || halted()) break;
    auto cells = persistence::MapPager::publishedCellsOf(page);
    if (!cells) {
      report.damage.push_back({page, cells.error().message});
      continue;
    }
    report.page_cells += cells->size();
    job.writer.add(*cells, parts);
    flush();
  }
  if (going && !halted()) {
    job.writer.finish(parts);
    flush();
  }
  report.missing = job.writer.missing();
  report.surplus = job.writer.surplus();
  report.send_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - began).count();
  return report;
}

}  // namespace ogf::mapper_daemon
