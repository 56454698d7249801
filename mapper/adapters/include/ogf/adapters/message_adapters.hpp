// From LCM messages to what the fusion layer takes: a Pose from ogf.odometry_t or libbot2's
// bot_core.pose_t (the POSE channel may carry either; the fingerprint says which), and a scan's points
// after checking the message is well-formed (array lengths, counts, time offsets).
#pragma once

#include <lcm/lcm-cpp.hpp>
#include <ogf/fusion/clock_agreement.hpp>
#include <ogf/fusion/deskew.hpp>
#include <ogf/fusion/pose.hpp>
#include <ogf/lidar_scan_t.hpp>

#include <string>

#include "ogf/common/result.hpp"

namespace ogf::adapters {

// Which scan clock the odometry's utime shares: the sensor's device time, the driver host's receive time,
// or auto: the device time of scans whose device time is UTC (PPS locked, NMEA hour), the host time of
// the others.
enum class ScanTimeBase { kDevice, kHost, kAuto };

// Decodes a POSE message of either type; its utime must be a time in [0, 2^62) µs. Errors say why
// ("fingerprint matches neither ...", "truncated", "utime: ... is not a time").
Result<fusion::Pose> decodePose(const void* data, std::size_t size);

// Checks a decoded scan: point count within limits and equal to every array's length, non-negative time
// offsets, finite coordinates, times in [0, 2^62) µs, end not before start. The error names the field.
Status validateScan(const ogf::lidar_scan_t& scan);

// The clock `base` times a scan on: kAuto is the device clock for a scan whose time_source (a
// lidar_scan_t::TIME_SOURCE_* value) is PPS_NMEA, its device time then being UTC, else the host clock.
fusion::ScanClock scanClockOf(std::int8_t time_source, ScanTimeBase base);
fusion::ScanClock scanClockOf(const ogf::lidar_scan_t& scan, ScanTimeBase base);

// The scan's start time on `clock`.
std::int64_t scanStartOn(const ogf::lidar_scan_t& scan, fusion::ScanClock clock);

// The scan's points as the fusion layer reads them, timed on `base`. The spans point into `scan`.
fusion::ScanPoints scanPointsOf(const ogf::lidar_scan_t& scan, ScanTimeBase base);

}  // namespace ogf::adapters
