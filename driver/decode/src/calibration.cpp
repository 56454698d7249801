#include "ogf/velodyne/calibration.hpp"

#include <yaml-cpp/yaml.h>

#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <numbers>
#include <optional>
#include <sstream>

namespace ogf::velodyne {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

Calibration fromDegrees(const double* vertical_deg, const double* rotation_deg, const double* vert_offset_m,
                        int lasers, double resolution, Model model) {
  Calibration c;
  c.distance_resolution_m = resolution;
  c.source = "nominal " + std::string(modelName(model));
  c.lasers.resize(static_cast<std::size_t>(lasers));
  for (int i = 0; i < lasers; ++i) {
    auto& l = c.lasers[static_cast<std::size_t>(i)];
    l.vert_correction_rad = vertical_deg[i] * kDegToRad;
    l.rot_correction_rad = rotation_deg != nullptr ? rotation_deg[i] * kDegToRad : 0.0;
    l.vert_offset_m = vert_offset_m != nullptr ? vert_offset_m[i] : 0.0;
  }
  return c;
}

// The nominal VLP-16 elevations and beam-origin heights (docs/wire-format.md §6.1 and §8.3).
constexpr std::array<double, 16> kVlp16Vertical{-15, 1, -13, 3, -11, 5, -9, 7, -7, 9, -5, 11, -3, 13, -1, 15};
constexpr std::array<double, 16> kVlp16VertOffset{0.0112, -0.0007, 0.0097, -0.0022, 0.0081, -0.0037,
                                                  0.0066, -0.0051, 0.0051, -0.0066, 0.0037, -0.0081,
                                                  0.0022, -0.0097, 0.0007, -0.0112};
constexpr std::array<double, 16> kHiResVertical{-10,    0.667, -8.667, 2,     -7.333, 3.333, -6,     4.667,
                                                -4.667, 6,     -3.333, 7.333, -2,     8.667, -0.667, 10};
constexpr std::array<double, 32> kHdl32Vertical{-30.67, -9.33, -29.33, -8,    -28,    -6.67, -26.67, -5.33,
                                                -25.33, -4,    -24,    -2.67, -22.67, -1.33, -21.33, 0,
                                                -20,    1.33,  -18.67, 2.67,  -17.33, 4,     -16,    5.33,
                                                -14.67, 6.67,  -13.33, 8,     -12,    9.33,  -10.67, 10.67};
constexpr std::array<double, 32> kVlp32Vertical{
    -25,    -1,     -1.667, -15.639, -11.31, 0,      -0.667, -8.843, -7.254, 0.333,  -0.333,
    -6.148, -5.333, 1.333,  0.667,   -4,     -4.667, 1.667,  1,      -3.667, -3.333, 3.333,
    2.333,  -2.667, -3,     7,       4.667,  -2.333, -2,     15,     10.333, -1.333};
constexpr std::array<double, 32> kVlp32Rotation{
    -1.4, 4.2, -1.4, 1.4, -1.4, 1.4, -4.2, 1.4, -1.4, 4.2, -1.4, 1.4, -4.2, 1.4, -4.2, 1.4,
    -1.4, 4.2, -1.4, 4.2, -4.2, 1.4, -1.4, 1.4, -1.4, 1.4, -1.4, 4.2, -4.2, 1.4, -1.4, 1.4};

std::optional<double> parseNumber(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  double v = 0.0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || s.empty() || !std::isfinite(v)) return std::nullopt;
  return v;
}

Error fieldError(std::string_view source, int line, std::string_view field, std::string_view what) {
  std::ostringstream os;
  os << source << ':' << line << ": field '" << field << "': " << what;
  return Error::configuration(os.str());
}

// ---- ROS YAML -----------------------------------------------------------------------------------

Result<double> yamlNumber(const YAML::Node& map, const char* key, std::string_view source, bool required,
                          double fallback) {
  const YAML::Node n = map[key];
  if (!n) {
    if (required) return fieldError(source, map.Mark().line + 1, key, "missing");
    return fallback;
  }
  if (!n.IsScalar()) return fieldError(source, n.Mark().line + 1, key, "not a scalar");
  const auto v = parseNumber(n.Scalar());
  if (!v) return fieldError(source, n.Mark().line + 1, key, "not a number '" + n.Scalar() + "'");
  return *v;
}

}  // namespace

Calibration nominalCalibration(Model model) {
  switch (model) {
    case Model::Vlp16HiRes: {
      // Hi-Res beam origins: the same 41.91 mm geometry as the VLP-16 (vd calib_db.cpp:27-40).
      std::array<double, 16> offsets{};
      for (std::size_t i = 0; i < 16; ++i) offsets[i] = 0.04191 * std::tan(-kHiResVertical[i] * kDegToRad);
      return fromDegrees(kHiResVertical.data(), nullptr, offsets.data(), 16, 0.002, model);
    }
    case Model::Vlp32C:
      return fromDegrees(kVlp32Vertical.data(), kVlp32Rotation.data(), nullptr, 32, 0.004, model);
    case Model::Hdl32E:
      return fromDegrees(kHdl32Vertical.data(), nullptr, nullptr, 32, 0.002, model);
    case Model::Vlp16:
    case Model::Unknown:
      break;
  }
  return fromDegrees(kVlp16Vertical.data(), nullptr, kVlp16VertOffset.data(), 16, 0.002, Model::Vlp16);
}

Result<Calibration> parseRosYamlCalibration(std::string_view text, std::string_view source) {
  YAML::Node root;
  try {
    root = YAML::Load(std::string(text));
  } catch (const YAML::Exception& e) {
    return fieldError(source, e.mark.line + 1, "(document)", e.msg);
  }
  if (!root.IsMap()) return fieldError(source, 1, "(document)", "not a YAML mapping");
  Calibration c;
  c.source = std::string(source);
  const auto resolution = yamlNumber(root, "distance_resolution", source, false, 0.002);
  if (!resolution) return resolution.error();
  if (*resolution <= 0.0 || *resolution > 0.1)
    return fieldError(source, root["distance_resolution"].Mark().line + 1, "distance_resolution",
                      "out of range (0, 0.1] m");
  c.distance_resolution_m = *resolution;
  const YAML::Node lasers = root["lasers"];
  if (!lasers || !lasers.IsSequence() || lasers.size() == 0)
    return fieldError(source, root.Mark().line + 1, "lasers", "missing or not a non-empty list");
  if (lasers.size() > 128)
    return fieldError(source, lasers.Mark().line + 1, "lasers", "more than 128 lasers");
  c.lasers.resize(lasers.size());
  std::vector<bool> seen(lasers.size(), false);
  for (const YAML::Node& entry : lasers) {
    const int line = entry.Mark().line + 1;
    if (!entry.IsMap()) return fieldError(source, line, "lasers[]", "not a mapping");
    const auto id = yamlNumber(entry, "laser_id", source, true, 0);
    if (!id) return id.error();
    if (*id < 0 || *id >= static_cast<double>(lasers.size()) || std::floor(*id) != *id)
      return fieldError(source, line, "laser_id", "not an index below the number of lasers");
    const auto index = static_cast<std::size_t>(*id);
    if (seen[index]) return fieldError(source, line, "laser_id", "duplicate id");
    seen[index] = true;
    LaserCorrection& l = c.lasers[index];
    const auto vert = yamlNumber(entry, "vert_correction", source, true, 0);
    if (!vert) return vert.error();
    if (std::abs(*vert) > std::numbers::pi / 2)
      return fieldError(source, line, "vert_correction", "beyond +-pi/2 rad (degrees given?)");
    l.vert_correction_rad = *vert;
    const auto rot = yamlNumber(entry, "rot_correction", source, false, 0);
    if (!rot) return rot.error();
    l.rot_correction_rad = *rot;
    const auto dist = yamlNumber(entry, "dist_correction", source, false, 0);
    if (!dist) return dist.error();
    l.dist_correction_m = *dist;
    const auto voff = yamlNumber(entry, "vert_offset_correction", source, false, 0);
    if (!voff) return voff.error();
    l.vert_offset_m = *voff;
    const auto hoff = yamlNumber(entry, "horiz_offset_correction", source, false, 0);
    if (!hoff) return hoff.error();
    l.horiz_offset_m = *hoff;
  }
  if (const YAML::Node n = root["num_lasers"]) {
    const auto count = yamlNumber(root, "num_lasers", source, true, 0);
    if (!count) return count.error();
    if (*count != static_cast<double>(lasers.size()))
      return fieldError(source, n.Mark().line + 1, "num_lasers",
                        "does not match the number of entries in 'lasers'");
  }
  return c;
}

namespace {

// ---- VeloView XML: a small scanner for the boost-serialization layout --------------------------------

struct XmlScanner {
  std::string_view text;
  std::string_view source;

  int lineAt(std::size_t offset) const {
    int line = 1;
    for (std::size_t i = 0; i < offset && i < text.size(); ++i) line += text[i] == '\n' ? 1 : 0;
    return line;
  }
  // Position of "<tag>" or "<tag " at or after `from` and before `until`; npos when absent.
  std::size_t findOpen(std::string_view tag, std::size_t from, std::size_t until) const {
    std::string open = "<" + std::string(tag);
    for (std::size_t p = text.find(open, from); p != std::string_view::npos && p < until;
         p = text.find(open, p + 1)) {
      const std::size_t after = p + open.size();
      if (after < text.size() && (text[after] == '>' || text[after] == ' ')) return p;
    }
    return std::string_view::npos;
  }
  // The text between <tag ...> and </tag> of the element opening at `open`, and the end of the element.
  std::optional<std::pair<std::string_view, std::size_t>> element(std::string_view tag,
                                                                  std::size_t open) const {
    const std::size_t start = text.find('>', open);
    if (start == std::string_view::npos) return std::nullopt;
    const std::string close = "</" + std::string(tag) + ">";
    const std::size_t end = text.find(close, start);
    if (end == std::string_view::npos) return std::nullopt;
    return std::make_pair(text.substr(start + 1, end - start - 1), end + close.size());
  }
};

}  // namespace

Result<Calibration> parseVeloViewXmlCalibration(std::string_view text, std::string_view source) {
  const XmlScanner xml{text, source};
  Calibration c;
  c.source = std::string(source);
  const std::size_t npos = std::string_view::npos;
  if (const std::size_t p = xml.findOpen("distLSB_", 0, text.size()); p != npos) {
    const auto e = xml.element("distLSB_", p);
    if (!e) return fieldError(source, xml.lineAt(p), "distLSB_", "element not closed");
    const auto v = parseNumber(e->first);
    if (!v || *v <= 0.0 || *v > 10.0)
      return fieldError(source, xml.lineAt(p), "distLSB_", "not a length in (0, 10] cm");
    c.distance_resolution_m = *v / 100.0;  // centimetres in VeloView files
  }
  const std::size_t points = xml.findOpen("points_", 0, text.size());
  if (points == npos) return fieldError(source, xml.lineAt(text.size()), "points_", "missing");
  const auto points_element = xml.element("points_", points);
  if (!points_element) return fieldError(source, xml.lineAt(points), "points_", "element not closed");
  const std::size_t points_end = points_element->second;
  std::vector<bool> seen;
  for (std::size_t p = xml.findOpen("px", points, points_end); p != npos;
       p = xml.findOpen("px", p + 1, points_end)) {
    const auto px = xml.element("px", p);
    if (!px) return fieldError(source, xml.lineAt(p), "px", "element not closed");
    const std::size_t px_end = px->second;
    auto field = [&](const char* name, bool required, double fallback) -> Result<double> {
      const std::size_t f = xml.findOpen(name, p, px_end);
      if (f == npos) {
        if (required) return fieldError(source, xml.lineAt(p), name, "missing");
        return fallback;
      }
      const auto e = xml.element(name, f);
      if (!e) return fieldError(source, xml.lineAt(f), name, "element not closed");
      const auto v = parseNumber(e->first);
      if (!v) return fieldError(source, xml.lineAt(f), name, "not a number '" + std::string(e->first) + "'");
      return *v;
    };
    const auto id = field("id_", true, 0);
    if (!id) return id.error();
    if (*id < 0 || *id >= 128 || std::floor(*id) != *id)
      return fieldError(source, xml.lineAt(p), "id_", "not a laser index 0..127");
    const auto index = static_cast<std::size_t>(*id);
    if (index >= c.lasers.size()) {
      c.lasers.resize(index + 1);
      seen.resize(index + 1, false);
    }
    if (seen[index]) return fieldError(source, xml.lineAt(p), "id_", "duplicate id");
    seen[index] = true;
    LaserCorrection& l = c.lasers[index];
    const auto vert = field("vertCorrection_", true, 0);
    if (!vert) return vert.error();
    if (std::abs(*vert) > 90.0)
      return fieldError(source, xml.lineAt(p), "vertCorrection_", "beyond +-90 degrees");
    l.vert_correction_rad = *vert * kDegToRad;
    const auto rot = field("rotCorrection_", false, 0);
    if (!rot) return rot.error();
    l.rot_correction_rad = *rot * kDegToRad;
    const auto dist = field("distCorrection_", false, 0);
    if (!dist) return dist.error();
    l.dist_correction_m = *dist / 100.0;
    const auto voff = field("vertOffsetCorrection_", false, 0);
    if (!voff) return voff.error();
    l.vert_offset_m = *voff / 100.0;
    const auto hoff = field("horizOffsetCorrection_", false, 0);
    if (!hoff) return hoff.error();
    l.horiz_offset_m = *hoff / 100.0;
  }
  if (c.lasers.empty()) return fieldError(source, xml.lineAt(points), "points_", "holds no <px> entries");
  for (std::size_t i = 0; i < seen.size(); ++i)
    if (!seen[i])
      return fieldError(source, xml.lineAt(points), "px", "laser id " + std::to_string(i) + " missing");
  return c;
}

Result<Calibration> loadCalibrationFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error::configuration(path.string() + ": cannot open calibration file");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  const std::size_t first = text.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && text[first] == '<')
    return parseVeloViewXmlCalibration(text, path.string());
  return parseRosYamlCalibration(text, path.string());
}

}  // namespace ogf::velodyne
