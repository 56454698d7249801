// Writers for ogf-decode's point outputs: CSV with one row per point and a header, and binary
// little-endian PLY that CloudCompare and Open3D open.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include "ogf/velodyne/scan.hpp"

namespace ogf::tools {

class CsvPointWriter {
 public:
  // Opens and writes the header; ok() is false (with error()) when the file cannot be written.
  explicit CsvPointWriter(const std::string& path);
  ~CsvPointWriter();
  CsvPointWriter(const CsvPointWriter&) = delete;
  CsvPointWriter& operator=(const CsvPointWriter&) = delete;
  bool ok() const { return file_ != nullptr && !failed_; }
  const std::string& error() const { return error_; }
  void write(const velodyne::Scan& scan);
  bool close();

 private:
  std::FILE* file_ = nullptr;
  bool failed_ = false;
  std::string path_, error_;
  std::string line_;
};

// Collects points and writes the PLY at close() (the header needs the vertex count).
class PlyPointWriter {
 public:
  explicit PlyPointWriter(std::string path) : path_(std::move(path)) {}
  void write(const velodyne::Scan& scan);
  // False with error() when the file cannot be written.
  bool close();
  const std::string& error() const { return error_; }

 private:
  struct Vertex {
    float x, y, z, intensity, time_s;
    std::uint16_t ring, laser_id;
    std::uint32_t scan;
    std::uint8_t return_type;
  };
  std::string path_, error_;
  std::vector<Vertex> vertices_;
};

}  // namespace ogf::tools
