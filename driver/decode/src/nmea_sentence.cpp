#include "ogf/velodyne/nmea_sentence.hpp"

#include <array>
#include <charconv>
#include <chrono>
#include <cmath>
#include <string>

namespace ogf::velodyne {
namespace {

constexpr int kMaxFields = 24;

struct Fields {
  std::array<std::string_view, kMaxFields> f{};
  int count = 0;
  std::string_view operator[](int i) const {
    return i < count ? f[static_cast<std::size_t>(i)] : std::string_view{};
  }
};

std::optional<double> number(std::string_view s) {
  if (s.empty()) return std::nullopt;
  double v = 0.0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::optional<int> digits(std::string_view s) {
  int v = 0;
  for (char c : s) {
    if (c < '0' || c > '9') return std::nullopt;
    v = v * 10 + (c - '0');
  }
  return s.empty() ? std::nullopt : std::optional<int>(v);
}

int hexDigit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

Error fieldError(std::string_view field, std::string_view what) {
  return Error::inputDamaged("NMEA field '" + std::string(field) + "': " + std::string(what));
}

// ddmm.mmmm (latitude) or dddmm.mmmm (longitude) with a hemisphere letter.
Result<std::optional<double>> coordinate(std::string_view value, std::string_view hemisphere, char positive,
                                         char negative, const char* name) {
  if (value.empty()) return std::optional<double>{};
  const auto v = number(value);
  if (!v || *v < 0) return fieldError(name, "not a coordinate '" + std::string(value) + "'");
  const double degrees = std::floor(*v / 100.0);
  double result = degrees + (*v - degrees * 100.0) / 60.0;
  if (hemisphere.size() != 1 || (hemisphere[0] != positive && hemisphere[0] != negative))
    return fieldError(name, "bad hemisphere '" + std::string(hemisphere) + "'");
  if (hemisphere[0] == negative) result = -result;
  return std::optional<double>(result);
}

}  // namespace

std::int64_t NmeaFix::microsecondsOfDay() const {
  return (static_cast<std::int64_t>(hour) * 3600 + minute * 60) * 1'000'000 + std::llround(second * 1e6);
}

std::optional<std::int64_t> NmeaFix::utcMicroseconds() const {
  if (!year || !month || !day) return std::nullopt;
  using namespace std::chrono;
  const year_month_day ymd{std::chrono::year(*year), std::chrono::month(static_cast<unsigned>(*month)),
                           std::chrono::day(static_cast<unsigned>(*day))};
  if (!ymd.ok()) return std::nullopt;
  const auto days = sys_days(ymd).time_since_epoch().count();
  return static_cast<std::int64_t>(days) * 86'400'000'000LL + microsecondsOfDay();
}

Result<NmeaFix> parseNmeaSentence(std::string_view s) {
  while (!s.empty() && (s.back() == '\r' || s.back() == '\n' || s.back() == '\0')) s.remove_suffix(1);
  if (s.size() < 7 || s.front() != '$') return fieldError("$", "sentence does not start with '$'");
  const std::size_t star = s.rfind('*');
  if (star == std::string_view::npos || star + 3 != s.size()) return fieldError("*hh", "checksum missing");
  const int hi = hexDigit(s[star + 1]), lo = hexDigit(s[star + 2]);
  if (hi < 0 || lo < 0) return fieldError("*hh", "checksum is not hexadecimal");
  unsigned sum = 0;
  for (std::size_t i = 1; i < star; ++i) sum ^= static_cast<unsigned char>(s[i]);
  if (sum != static_cast<unsigned>(hi * 16 + lo)) return fieldError("*hh", "checksum mismatch");
  const std::string_view body = s.substr(1, star - 1);
  Fields fields;
  std::size_t start = 0;
  while (fields.count < kMaxFields) {
    const std::size_t comma = body.find(',', start);
    fields.f[static_cast<std::size_t>(fields.count++)] =
        body.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start);
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  const std::string_view id = fields[0];
  if (id.size() != 5) return fieldError("address", "not a talker and sentence id '" + std::string(id) + "'");
  const std::string_view type = id.substr(2);
  NmeaFix fix;
  int time_field = 1;
  if (type == "RMC") {
    fix.kind = NmeaFix::Kind::Rmc;
  } else if (type == "GGA") {
    fix.kind = NmeaFix::Kind::Gga;
  } else {
    return fieldError("address", "unsupported sentence '" + std::string(id) + "'");
  }
  const std::string_view time = fields[time_field];
  if (time.size() < 6) return fieldError("time", "not hhmmss '" + std::string(time) + "'");
  const auto hh = digits(time.substr(0, 2)), mm = digits(time.substr(2, 2));
  const auto ss = number(time.substr(4));
  if (!hh || !mm || !ss || *hh > 23 || *mm > 59 || *ss < 0 || *ss >= 61)
    return fieldError("time", "not hhmmss '" + std::string(time) + "'");
  fix.hour = *hh;
  fix.minute = *mm;
  fix.second = *ss;
  if (fix.kind == NmeaFix::Kind::Rmc) {
    if (fields.count < 10) return fieldError("RMC", "fewer than 10 fields");
    const std::string_view status = fields[2];
    if (status != "A" && status != "V") return fieldError("status", "not A or V");
    fix.fix_valid = status == "A";
    const auto lat = coordinate(fields[3], fields[4], 'N', 'S', "latitude");
    if (!lat) return lat.error();
    const auto lon = coordinate(fields[5], fields[6], 'E', 'W', "longitude");
    if (!lon) return lon.error();
    fix.latitude_deg = *lat;
    fix.longitude_deg = *lon;
    if (!fields[7].empty()) {
      fix.speed_knots = number(fields[7]);
      if (!fix.speed_knots) return fieldError("speed", "not a number");
    }
    if (!fields[8].empty()) {
      fix.course_deg = number(fields[8]);
      if (!fix.course_deg) return fieldError("course", "not a number");
    }
    const std::string_view date = fields[9];
    const auto dd = digits(date.substr(0, 2)), mo = digits(date.size() >= 4 ? date.substr(2, 2) : "");
    const auto yy = digits(date.size() == 6 ? date.substr(4, 2) : "");
    if (date.size() != 6 || !dd || !mo || !yy || *mo < 1 || *mo > 12 || *dd < 1 || *dd > 31)
      return fieldError("date", "not ddmmyy '" + std::string(date) + "'");
    fix.day = *dd;
    fix.month = *mo;
    fix.year = 2000 + *yy;  // two-digit NMEA years; receivers in service report 20yy
  } else {
    if (fields.count < 7) return fieldError("GGA", "fewer than 7 fields");
    const auto lat = coordinate(fields[2], fields[3], 'N', 'S', "latitude");
    if (!lat) return lat.error();
    const auto lon = coordinate(fields[4], fields[5], 'E', 'W', "longitude");
    if (!lon) return lon.error();
    fix.latitude_deg = *lat;
    fix.longitude_deg = *lon;
    const auto quality = digits(fields[6]);
    if (!quality) return fieldError("quality", "not a digit");
    fix.fix_valid = *quality > 0;
  }
  return fix;
}

}  // namespace ogf::velodyne
