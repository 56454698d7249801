#include "ogf/driver_sources/pcap_replay.hpp"

#include <boost/asio/post.hpp>

namespace ogf::driver_sources {

PcapReplay::PcapReplay(boost::asio::io_context& io, std::unique_ptr<PcapFileReader> reader, double speed,
                       Handler on_record, EndHandler on_end)
    : io_(io),
      timer_(io),
      reader_(std::move(reader)),
      speed_(speed),
      on_record_(std::move(on_record)),
      on_end_(std::move(on_end)) {}

void PcapReplay::start() {
  start_ = std::chrono::steady_clock::now();
  boost::asio::post(io_, [this] { step(); });
}

void PcapReplay::stop() {
  stopped_ = true;
  timer_.cancel();
}

void PcapReplay::step() {
  // Delivers what is due, a bounded number per turn of the loop so signals and timers still run.
  for (int delivered = 0; !stopped_ && delivered < 256; ++delivered) {
    if (!has_pending_) {
      const ReadStatus status = reader_->next(pending_);
      if (status == ReadStatus::End || status == ReadStatus::Error) {
        stopped_ = true;
        if (on_end_) on_end_(status == ReadStatus::Error ? reader_->error() : std::string());
        return;
      }
      has_pending_ = true;
    }
    if (speed_ > 0.0) {
      if (!first_capture_utime_) first_capture_utime_ = pending_.datagram.utime;
      const double offset_us = static_cast<double>(pending_.datagram.utime - *first_capture_utime_) / speed_;
      const auto due = start_ + std::chrono::microseconds(static_cast<std::int64_t>(offset_us));
      if (due > std::chrono::steady_clock::now()) {
        timer_.expires_at(due);
        timer_.async_wait([this](const boost::system::error_code& ec) {
          if (!ec) step();
        });
        return;
      }
    }
    has_pending_ = false;
    on_record_(pending_);
  }
  if (!stopped_) boost::asio::post(io_, [this] { step(); });
}

}  // namespace ogf::driver_sources
