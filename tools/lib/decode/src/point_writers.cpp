#include "ogf/decode/point_writers.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>

namespace ogf::tools {

CsvPointWriter::CsvPointWriter(const std::string& path) : path_(path) {
  file_ = std::fopen(path.c_str(), "w");
  if (file_ == nullptr) {
    error_ = path + ": " + std::strerror(errno);
    return;
  }
  static constexpr char kHeader[] =
      "scan,x,y,z,intensity,ring,laser_id,azimuth_deg,distance_m,time_s,return_type\n";
  failed_ = std::fputs(kHeader, file_) < 0;
}

CsvPointWriter::~CsvPointWriter() { close(); }

void CsvPointWriter::write(const velodyne::Scan& scan) {
  if (!ok()) return;
  for (const velodyne::ScanPoint& p : scan.points) {
    line_.clear();
    fmt::format_to(std::back_inserter(line_), "{},{:.4f},{:.4f},{:.4f},{},{},{},{:.2f},{:.3f},{:.9f},{}\n",
                   scan.seq, p.x, p.y, p.z, p.intensity, p.ring, p.laser_id, p.azimuth_deg, p.distance_m,
                   static_cast<double>(p.time_offset_ns) * 1e-9, velodyne::returnTypeName(p.return_type));
    if (std::fwrite(line_.data(), 1, line_.size(), file_) != line_.size()) {
      failed_ = true;
      error_ = path_ + ": " + std::strerror(errno);
      return;
    }
  }
}

bool CsvPointWriter::close() {
  if (file_ == nullptr) return ok();
  if (std::fclose(file_) != 0 && !failed_) {
    failed_ = true;
    error_ = path_ + ": " + std::strerror(errno);
  }
  file_ = nullptr;
  return !failed_ && error_.empty();
}

void PlyPointWriter::write(const velodyne::Scan& scan) {
  for (const velodyne::ScanPoint& p : scan.points)
    vertices_.push_back(Vertex{p.x, p.y, p.z, static_cast<float>(p.intensity),
                               static_cast<float>(static_cast<double>(p.time_offset_ns) * 1e-9), p.ring,
                               p.laser_id, static_cast<std::uint32_t>(scan.seq),
                               static_cast<std::uint8_t>(p.return_type)});
}

bool PlyPointWriter::close() {
  std::FILE* f = std::fopen(path_.c_str(), "wb");
  if (f == nullptr) {
    error_ = path_ + ": " + std::strerror(errno);
    return false;
  }
  const std::string header = fmt::format(
      "ply\nformat binary_little_endian 1.0\ncomment ogf-decode: Velodyne points, REP-103 sensor frame, "
      "metres\n"
      "element vertex {}\nproperty float x\nproperty float y\nproperty float z\nproperty float intensity\n"
      "property float time\nproperty ushort ring\nproperty ushort laser_id\nproperty uint scan\n"
      "property uchar return_type\nend_header\n",
      vertices_.size());
  bool good = std::fwrite(header.data(), 1, header.size(), f) == header.size();
  // Field by field: the vertex layout on disk has no padding, little-endian (x86 and ARM hosts).
  std::vector<unsigned char> record;
  for (const Vertex& v : vertices_) {
    record.clear();
    auto put = [&record](const auto& value) {
      const auto* bytes = reinterpret_cast<const unsigned char*>(&value);
      record.insert(record.end(), bytes, bytes + sizeof(value));
    };
    put(v.x), put(v.y), put(v.z), put(v.intensity), put(v.time_s), put(v.ring), put(v.laser_id), put(v.scan),
        put(v.return_type);
    good = good && std::fwrite(record.data(), 1, record.size(), f) == record.size();
  }
  if (std::fclose(f) != 0) good = false;
  if (!good) error_ = path_ + ": write failed";
  return good;
}

}  // namespace ogf::tools
