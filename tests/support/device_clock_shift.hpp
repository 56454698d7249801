// A copy of a Velodyne capture whose device clock reads a chosen time, or with a pause in its stream.
// Without a GPS lock the driver places each packet's microseconds-past-the-hour counter in the host's hour,
// so a replayed capture's device time sits wherever its counter falls against the host's minute and second:
// tests that need a device clock a known distance from the host clock rewrite the counters instead of
// depending on the time of day.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>

namespace ogf::testing {

// Copies the classic pcap `from` (Ethernet/IPv4/UDP frames) to `to`, adding `shift_us` (mod one hour) to the
// counter of every VLP-16 data packet (1206-byte payload, bytes 1200..1203) and position packet (512- or
// 554-byte payload, bytes 198..201). Returns what is wrong with the input, or nullopt.
std::optional<std::string> copyWithDeviceClockShift(const std::filesystem::path& from,
                                                    const std::filesystem::path& to, std::int64_t shift_us);

// The first data packet's counter of the capture, or nullopt when it holds none.
std::optional<std::uint32_t> firstDataPacketToh(const std::filesystem::path& capture);

// Copies `from` to `to` with a pause of `pause_us` before data packet `after_data_packets` (0-based): that
// record and every later one is captured `pause_us` later, its sensor counter too (mod one hour), as when
// the sensor's stream stops and resumes (cable, switch, sensor restart).
std::optional<std::string> copyWithPause(const std::filesystem::path& from, const std::filesystem::path& to,
                                         std::int64_t after_data_packets, std::int64_t pause_us);

// The capture times (µs since the epoch) of the capture's first and last UDP records, or nullopt.
std::optional<std::pair<std::int64_t, std::int64_t>> captureTimeSpan(const std::filesystem::path& capture);

}  // namespace ogf::testing
