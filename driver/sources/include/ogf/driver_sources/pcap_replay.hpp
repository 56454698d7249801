// Replays a capture file on a Boost.Asio io_context: each UDP datagram is delivered at its capture time
// divided by a speed factor (relative to the first record), or as fast as possible with speed 0. The
// capture timestamp is the datagram's receive time, so a replay decodes to the same scans every time.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <functional>
#include <memory>
#include <optional>

#include "ogf/driver_sources/pcap_file_reader.hpp"

namespace ogf::driver_sources {

class PcapReplay {
 public:
  using Handler = std::function<void(const PcapRecord& record)>;
  // Called once at the end: an empty string for a clean end, else the reader's error (records before it
  // have been delivered).
  using EndHandler = std::function<void(const std::string& error)>;

  PcapReplay(boost::asio::io_context& io, std::unique_ptr<PcapFileReader> reader, double speed,
             Handler on_record, EndHandler on_end);
  void start();
  void stop();

 private:
  void step();

  boost::asio::io_context& io_;
  boost::asio::steady_timer timer_;
  std::unique_ptr<PcapFileReader> reader_;
  double speed_;
  Handler on_record_;
  EndHandler on_end_;
  std::optional<std::int64_t> first_capture_utime_;
  std::chrono::steady_clock::time_point start_;
  PcapRecord pending_;
  bool has_pending_ = false;
  bool stopped_ = false;
};

}  // namespace ogf::driver_sources
