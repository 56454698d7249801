#include "ogf/map_io/pcd_file.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

namespace ogf::map_io {
namespace {

struct Field {
  std::string name;
  std::size_t size = 4;
  char type = 'F';
  std::size_t count = 1;
  std::size_t offset = 0;  // bytes from the start of a binary record
};

std::vector<std::string_view> words(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

template <class T>
bool number(std::string_view s, T& v) {
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return ec == std::errc() && ptr == s.data() + s.size();
}

// Reads one x/y/z value of a binary record.
double readBinary(const char* p, const Field& f) {
  if (f.size == 8) {
    double d;
    std::memcpy(&d, p, sizeof d);
    return d;
  }
  float v;
  std::memcpy(&v, p, sizeof v);
  return static_cast<double>(v);
}

}  // namespace

Result<PcdCloud> parsePcd(std::string_view bytes, std::string_view source) {
  std::vector<Field> fields;
  std::size_t width = 0, height = 1, points = 0;
  bool have_points = false;
  PcdCloud cloud;
  std::string data_kind;
  std::size_t pos = 0;
  int line_no = 0;
  const auto fail = [&](const std::string& what) { return Error{fmt::format("{}: line {}: {}", source, line_no, what)}; };
  // Header: keyword lines up to and including DATA.
  while (data_kind.empty()) {
    if (pos >= bytes.size()) return Error{fmt::format("{}: header ends before its DATA line", source)};
    const std::size_t nl = bytes.find('\n', pos);
    const std::string_view line = bytes.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos);
    pos = nl == std::string_view::npos ? bytes.size() : nl + 1;
    ++line_no;
    const auto w = words(line);
    if (w.empty() || w[0].front() == '#') continue;
    const std::string_view key = w[0];
    const std::size_t n = w.size() - 1;
    if (key == "VERSION") continue;
    if (key == "FIELDS") {
      fields.clear();
      for (std::size_t i = 1; i < w.size(); ++i) fields.push_back({std::string(w[i])});
    } else if (key == "SIZE" || key == "TYPE" || key == "COUNT") {
      if (n != fields.size()) return fail(fmt::format("{} has {} entries for {} FIELDS", key, n, fields.size()));
      for (std::size_t i = 0; i < n; ++i) {
        const std::string_view v = w[i + 1];
        if (key == "TYPE") {
          if (v.size() != 1 || (v[0] != 'F' && v[0] != 'I' && v[0] != 'U')) return fail(fmt::format("TYPE '{}' is not F, I or U", v));
          fields[i].type = v[0];
        } else {
          std::size_t x = 0;
          if (!number(v, x) || x == 0) return fail(fmt::format("{} '{}' is not a positive integer", key, v));
          (key == "SIZE" ? fields[i].size : fields[i].count) = x;
        }
      }
    } else if (key == "WIDTH" || key == "HEIGHT" || key == "POINTS") {
      std::size_t x = 0;
      if (n != 1 || !number(w[1], x)) return fail(fmt::format("{} needs one integer", key));
      if (key == "WIDTH") width = x;
      else if (key == "HEIGHT") height = x;
      else {
        points = x;
        have_points = true;
      }
    } else if (key == "VIEWPOINT") {
      double v[7];
      if (n != 7) return fail("VIEWPOINT needs 7 numbers: tx ty tz qw qx qy qz");
      for (std::size_t i = 0; i < 7; ++i)
        if (!number(w[i + 1], v[i])) return fail(fmt::format("VIEWPOINT entry '{}' is not a number", w[i + 1]));
      cloud.viewpoint_translation = {v[0], v[1], v[2]};
      cloud.viewpoint_rotation = Eigen::Quaterniond(v[3], v[4], v[5], v[6]);
    } else if (key == "DATA") {
      if (n != 1) return fail("DATA needs one of ascii, binary");
      data_kind = std::string(w[1]);
    } else {
      return fail(fmt::format("unknown header keyword '{}'", key));
    }
  }
  if (!have_points) points = width * height;
  std::size_t record = 0;
  int ix = -1, iy = -1, iz = -1;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    fields[i].offset = record;
    record += fields[i].size * fields[i].count;
    const int idx = static_cast<int>(i);
    if (fields[i].name == "x") ix = idx;
    if (fields[i].name == "y") iy = idx;
    if (fields[i].name == "z") iz = idx;
  }
  if (ix < 0 || iy < 0 || iz < 0) return Error{fmt::format("{}: FIELDS lacks x, y or z", source)};
  for (int i : {ix, iy, iz}) {
    const Field& f = fields[static_cast<std::size_t>(i)];
    if (f.type != 'F' || (f.size != 4 && f.size != 8) || f.count != 1)
      return Error{fmt::format("{}: field {} must be F 4 or F 8 with COUNT 1", source, f.name)};
  }
  const auto keep = [&](double x, double y, double z) {
    if (std::isfinite(x) && std::isfinite(y) && std::isfinite(z)) cloud.points.emplace_back(x, y, z);
    else ++cloud.non_finite;
  };
  cloud.points.reserve(points);
  if (data_kind == "binary") {
    if (bytes.size() - pos < points * record)
      return Error{fmt::format("{}: binary data holds {} bytes, {} points of {} bytes need {}", source,
                               bytes.size() - pos, points, record, points * record)};
    const auto& fx = fields[static_cast<std::size_t>(ix)];
    const auto& fy = fields[static_cast<std::size_t>(iy)];
    const auto& fz = fields[static_cast<std::size_t>(iz)];
    for (std::size_t k = 0; k < points; ++k) {
      const char* r = bytes.data() + pos + k * record;
      keep(readBinary(r + fx.offset, fx), readBinary(r + fy.offset, fy), readBinary(r + fz.offset, fz));
    }
  } else if (data_kind == "ascii") {
    // Values per point: one per field element.
    std::vector<std::size_t> first(fields.size());
    std::size_t values = 0;
    for (std::size_t i = 0; i < fields.size(); ++i) {
      first[i] = values;
      values += fields[i].count;
    }
    std::size_t read = 0;
    while (read < points && pos < bytes.size()) {
      const std::size_t nl = bytes.find('\n', pos);
      const std::string_view line = bytes.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos);
      pos = nl == std::string_view::npos ? bytes.size() : nl + 1;
      ++line_no;
      const auto w = words(line);
      if (w.empty()) continue;
      if (w.size() != values) return fail(fmt::format("{} values, the fields need {}", w.size(), values));
      double xyz[3];
      const int which[3] = {ix, iy, iz};
      for (int a = 0; a < 3; ++a) {
        const std::string_view s = w[first[static_cast<std::size_t>(which[a])]];
        if (s == "nan" || s == "NaN" || s == "-nan") xyz[a] = std::nan("");
        else if (!number(s, xyz[a])) return fail(fmt::format("'{}' is not a number", s));
      }
      keep(xyz[0], xyz[1], xyz[2]);
      ++read;
    }
    if (read < points) return Error{fmt::format("{}: {} points announced, {} found", source, points, read)};
  } else if (data_kind == "binary_compressed") {
    return Error{fmt::format("{}: DATA binary_compressed is not supported; save the cloud as binary or ascii "
                             "(pcl_convert_pcd_ascii_binary <in> <out> 1)", source)};
  } else {
    return Error{fmt::format("{}: DATA '{}' is not ascii or binary", source, data_kind)};
  }
  return cloud;
}

Result<PcdCloud> readPcdFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error{fmt::format("{}: cannot open PCD file", path.string())};
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return parsePcd(bytes.str(), path.string());
}

}  // namespace ogf::map_io
