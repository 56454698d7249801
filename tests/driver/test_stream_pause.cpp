// A pause in the sensor stream, on the real VLP-16 capture: its packets fed to the decoding stream with the
// host receive times of a sensor that stops for 12 s in the middle of a scan. The scan open at the pause is
// never emitted as part of handling the first packet after it (it would go out 12 s late, dated before the
// time subscribers followed meanwhile); flushed when the stream goes idle, as ogf-driver does, it goes out
// with its own times and nothing is dropped.
#include <gtest/gtest.h>

#include <vector>

#include "ogf/driver_sources/pcap_file_reader.hpp"
#include "ogf/velodyne/packet_stream.hpp"
#include "support/shared_data.hpp"

namespace ov = ogf::velodyne;
namespace ds = ogf::driver_sources;

namespace {

constexpr std::int64_t kPauseUs = 12'000'000;

struct Emitted {
  ov::Scan scan;
  std::int64_t emitted_at_host_utime;  // receive time of the packet being handled, or of the idle flush
};

struct PausedRun {
  std::vector<Emitted> scans;
  std::int64_t dropped = 0;
  std::int64_t pause_starts_at = 0;  // host time of the last data packet before the pause
};

// Feeds the capture; data packet `pause_before` and every record after it arrive kPauseUs later. With
// `flush_at_idle`, flushScan() is called during the pause (its host time: the last data packet's + 0.3 s).
PausedRun feedWithPause(const std::filesystem::path& pcap, std::int64_t pause_before, bool flush_at_idle) {
  PausedRun run;
  auto stream = ov::PacketStream::create({});
  EXPECT_TRUE(stream);
  std::int64_t now = 0;
  stream->setScanSink([&](const ov::Scan& s) { run.scans.push_back({s, now}); });
  auto reader = ds::PcapFileReader::open(pcap);
  EXPECT_TRUE(reader);
  ds::PcapRecord record;
  ds::ReadStatus status;
  std::int64_t data_index = 0, shift = 0, last_host = 0;
  while ((status = (*reader)->next(record)) == ds::ReadStatus::Datagram || status == ds::ReadStatus::Skipped) {
    if (status != ds::ReadStatus::Datagram) continue;
    const auto& d = record.datagram;
    if (d.destination_port == 2368 && data_index++ == pause_before) {
      run.pause_starts_at = last_host;
      if (flush_at_idle) {
        now = last_host + 300'000;
        stream->flushScan();
      }
      shift = kPauseUs;
    }
    now = d.utime + shift;
    if (d.destination_port == 2368) last_host = now;
    if (d.destination_port == 2368) stream->addDataPacket(d.payload, now);
    if (d.destination_port == 8308) stream->addPositionPacket(d.payload, now);
  }
  stream->finish();
  run.dropped = stream->scansDroppedAtPause();
  return run;
}

}  // namespace

TEST(StreamPause, TheScanOpenAtAPauseIsDroppedNotEmittedLateWithThePacketAfterIt) {
  OGF_REQUIRE_SHARED_FILE(pcap, "data/real/vlp-16-test-90deg-1-50-frames.pcap");
  // Packet 1000 of 1902: mid-capture, inside a scan (about 37 packets a turn at 1200 rpm).
  const PausedRun run = feedWithPause(pcap, 1000, false);
  ASSERT_GE(run.scans.size(), 40u);
  for (const auto& e : run.scans) {
    // Emitted within a scan's time of its last packet, never across the pause.
    EXPECT_LT(e.emitted_at_host_utime - e.scan.host_utime_end, 1'000'000) << "scan " << e.scan.seq;
    EXPECT_LT(e.scan.host_utime_end - e.scan.host_utime_start, kPauseUs) << "scan " << e.scan.seq;
  }
  EXPECT_EQ(run.dropped, 1);
  // The dropped scan takes no sequence number: subscribers see no scan missing.
  for (std::size_t i = 1; i < run.scans.size(); ++i)
    EXPECT_EQ(run.scans[i].scan.seq, run.scans[i - 1].scan.seq + 1) << "scan " << i;
  // The first scan after the pause starts with the first packet after it, not at the cut, without loss.
  std::size_t after = 0;
  while (after < run.scans.size() && run.scans[after].scan.host_utime_start <= run.pause_starts_at) ++after;
  ASSERT_LT(after, run.scans.size());
  EXPECT_FALSE(run.scans[after].scan.starts_at_cut);
  EXPECT_EQ(run.scans[after].scan.packets_lost, 0);
}

TEST(StreamPause, FlushedWhenTheStreamGoesIdleTheOpenScanGoesOutWithItsOwnTimesAndNoneIsDropped) {
  OGF_REQUIRE_SHARED_FILE(pcap, "data/real/vlp-16-test-90deg-1-50-frames.pcap");
  const PausedRun dropped = feedWithPause(pcap, 1000, false);
  const PausedRun flushed = feedWithPause(pcap, 1000, true);
  EXPECT_EQ(flushed.dropped, 0);
  ASSERT_EQ(flushed.scans.size(), dropped.scans.size() + 1);
  // Exactly one scan went out at the idle flush: the one open at the pause, ending with its last packet.
  std::vector<const Emitted*> at_idle;
  for (const auto& e : flushed.scans)
    if (e.emitted_at_host_utime == flushed.pause_starts_at + 300'000) at_idle.push_back(&e);
  ASSERT_EQ(at_idle.size(), 1u);
  const Emitted& partial = *at_idle.front();
  EXPECT_EQ(partial.scan.host_utime_end, flushed.pause_starts_at);
  EXPECT_FALSE(partial.scan.ends_at_cut);
  EXPECT_GT(partial.scan.points.size(), 0u);
  for (std::size_t i = 1; i < flushed.scans.size(); ++i) {
    EXPECT_EQ(flushed.scans[i].scan.seq, flushed.scans[i - 1].scan.seq + 1) << "scan " << i;
    EXPECT_GT(flushed.scans[i].scan.device_utime_start, flushed.scans[i - 1].scan.device_utime_end) << "scan " << i;
  }
}
