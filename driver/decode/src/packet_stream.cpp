#include "ogf/velodyne/packet_stream.hpp"

#include <algorithm>
#include <string>
#include <utility>

namespace ogf::velodyne {

PacketStream::PacketStream(const StreamConfig& config)
    : config_(config), detector_(config.model), assembler_(config.assembler),
      clock_settled_(config.clock_settle_packets <= 0) {
  pending_.reserve(static_cast<std::size_t>(std::max(ModelDetector::kMaxPackets, config.clock_settle_packets)));
}

Result<PacketStream> PacketStream::create(const StreamConfig& config) {
  // Validate now what the decoder would refuse later: with a configured model, for that model; otherwise
  // the range limits and that the calibration suits at least a 16-laser model.
  DecoderConfig probe;
  probe.model = config.model.value_or(Model::Vlp16);
  probe.calibration = config.calibration;
  probe.return_mode = config.return_mode;
  probe.min_range_m = config.min_range_m;
  probe.max_range_m = config.max_range_m;
  auto decoder = PacketDecoder::create(probe);
  if (!decoder) return decoder.error();
  if (config.clock_settle_packets > 4096)
    return Error::configuration("clock_settle_packets " + std::to_string(config.clock_settle_packets) +
                 " is above 4096 (5 s of packets): the first scan would wait too long");
  PacketStream stream(config);
  if (config.model) stream.decoder_.emplace(std::move(*decoder));
  return stream;
}

bool PacketStream::ensureDecoder() {
  if (decoder_) return true;
  if (!detector_.model()) return false;
  DecoderConfig c;
  c.model = *detector_.model();
  c.calibration = config_.calibration;
  c.return_mode = config_.return_mode;
  c.min_range_m = config_.min_range_m;
  c.max_range_m = config_.max_range_m;
  auto decoder = PacketDecoder::create(c);
  if (!decoder) return false;  // e.g. a 16-laser calibration for a detected 32-laser model
  decoder_.emplace(std::move(*decoder));
  return true;
}

PacketStatus PacketStream::decodeAndAssemble(std::span<const std::uint8_t> payload, std::int64_t host_utime) {
  const PacketStatus status = decoder_->decode(payload, decoded_);
  switch (status) {
    case PacketStatus::Ok:
      break;
    case PacketStatus::WrongSize:
      ++counters_.bad_size;
      return status;
    case PacketStatus::BadBlockFlag:
      ++counters_.bad_block_flag;
      return status;
    case PacketStatus::BadAzimuth:
      ++counters_.bad_other;
      return status;
    case PacketStatus::BadTimeOfHour:
    case PacketStatus::UnknownReturnMode:
    case PacketStatus::UnknownProduct:
      count(status);
      return status;
  }
  ++counters_.data_packets;
  counters_.points += decoded_.point_count;
  last_mode_ = decoded_.return_mode;
  const PacketTime time{clock_.toAbsolute(decoded_.toh_us, host_utime), host_utime};
  assembler_.add(decoded_, time, decoder_->model(), [this](const Scan& scan) {
    ++counters_.scans;
    if (sink_) sink_(scan);
  });
  return status;
}

void PacketStream::count(PacketStatus status) {
  switch (status) {
    case PacketStatus::BadTimeOfHour:
      ++counters_.bad_time_of_hour;
      break;
    case PacketStatus::UnknownReturnMode:
      ++counters_.unknown_return_mode;
      break;
    case PacketStatus::UnknownProduct:
      ++counters_.unknown_model;
      break;
    default:
      break;
  }
}

PacketStatus PacketStream::addDataPacket(std::span<const std::uint8_t> payload, std::int64_t host_utime) {
  if (payload.size() != wire::kDataPacketSize) {
    ++counters_.bad_size;
    return PacketStatus::WrongSize;
  }
  if (!decoder_) {
    // Check the block flags before letting the packet vote on the model.
    for (int b = 0; b < wire::kBlocksPerPacket; ++b) {
      if (wire::readLe16(payload.data() + b * 100) != wire::kUpperBankFlag) {
        ++counters_.bad_block_flag;
        return PacketStatus::BadBlockFlag;
      }
    }
    if (const PacketStatus trailer = checkPacketTrailer(payload); trailer != PacketStatus::Ok) {
      count(trailer);
      return trailer;
    }
    detector_.observe(payload[1205], payload[1204], wire::readLe32(payload.data() + 1200));
    if (!ensureDecoder() && pending_.size() >= ModelDetector::kMaxPackets) {
      ++counters_.bad_other;  // unknown product: never decodable without a configured model
      return PacketStatus::Ok;
    }
  }
  if (!clock_settled_ && std::cmp_greater_equal(pending_.size(), config_.clock_settle_packets))
    clock_settled_ = true;  // no position packet in time: the host's hour is the time base
  if (!decoder_ || !clock_settled_) {
    holdPacket(payload, host_utime);
    return PacketStatus::Ok;
  }
  decodeHeldPackets();
  return decodeAndAssemble(payload, host_utime);
}

void PacketStream::holdPacket(std::span<const std::uint8_t> payload, std::int64_t host_utime) {
  Pending p;
  std::copy(payload.begin(), payload.end(), p.bytes.begin());
  p.host_utime = host_utime;
  pending_.push_back(p);
}

void PacketStream::decodeHeldPackets() {
  for (const Pending& p : pending_) decodeAndAssemble(p.bytes, p.host_utime);
  pending_.clear();
}

bool PacketStream::addPositionPacket(std::span<const std::uint8_t> payload, std::int64_t host_utime) {
  if (payload.size() != wire::kPositionPacketSize) {
    ++counters_.bad_size;
    return false;
  }
  if (wire::readLe32(payload.data() + offsetof(wire::RawPositionPacket, timestamp)) >= wire::kMicrosecondsPerHour) {
    ++counters_.bad_time_of_hour;
    return false;
  }
  auto packet = parsePositionPacket(payload);
  if (!packet) {
    ++counters_.bad_position;
    return false;
  }
  ++counters_.position_packets;
  if (!clock_.onPositionPacket(*packet, host_utime)) ++counters_.nmea_time_refused;
  last_position_ = *packet;
  if (!clock_settled_) {
    clock_settled_ = true;
    if (decoder_) decodeHeldPackets();
  }
  return true;
}

void PacketStream::finish() {
  if (!pending_.empty()) {
    if (!detector_.model()) {
      // Too few packets to measure the period: the product byte decides.
      ModelDetector fallback(modelFromProductId(pending_.front().bytes[1205]));
      detector_ = fallback;
    }
    if (ensureDecoder()) {
      decodeHeldPackets();
    } else {
      counters_.bad_other += static_cast<std::int64_t>(pending_.size());
      pending_.clear();
    }
  }
  flushScan();
}

void PacketStream::flushScan() {
  assembler_.flush([this](const Scan& scan) {
    ++counters_.scans;
    if (sink_) sink_(scan);
  });
}

}  // namespace ogf::velodyne
