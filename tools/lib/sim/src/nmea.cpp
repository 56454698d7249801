// GPRMC sentence and NMEA checksum.
#include "ogf/sim/nmea.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>

namespace ogf::sim {
namespace {

// ddmm.mmmm (or dddmm.mmmm) and a hemisphere letter.
std::string nmeaAngle(double deg, int degree_digits, char positive, char negative) {
  const char hemi = deg >= 0.0 ? positive : negative;
  const double a = std::abs(deg);
  const int whole = static_cast<int>(std::floor(a));
  const double minutes = (a - whole) * 60.0;
  return fmt::format("{:0{}d}{:07.4f},{}", whole, degree_digits, minutes, hemi);
}

}  // namespace

std::uint8_t nmeaChecksum(std::string_view body) {
  std::uint8_t sum = 0;
  for (const char c : body) sum = static_cast<std::uint8_t>(sum ^ static_cast<std::uint8_t>(c));
  return sum;
}

std::string gprmcSentence(std::int64_t utime, const GeoPosition& where) {
  using namespace std::chrono;
  const sys_seconds second{seconds{utime >= 0 ? utime / 1000000 : (utime - 999999) / 1000000}};
  const auto day = floor<days>(second);
  const year_month_day ymd{day};
  const hh_mm_ss hms{second - day};
  const std::string body = fmt::format(
      "GPRMC,{:02d}{:02d}{:02d},A,{},{},0.0,0.0,{:02d}{:02d}{:02d},,,A", hms.hours().count(),
      hms.minutes().count(), hms.seconds().count(), nmeaAngle(where.latitude_deg, 2, 'N', 'S'),
      nmeaAngle(where.longitude_deg, 3, 'E', 'W'), static_cast<unsigned>(ymd.day()),
      static_cast<unsigned>(ymd.month()), static_cast<int>(ymd.year()) % 100);
  return fmt::format("${}*{:02X}\r\n", body, nmeaChecksum(body));
}

}  // namespace ogf::sim
