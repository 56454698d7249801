#include "ogf/transport/lcm_url.hpp"

#include <cstdlib>

namespace ogf::transport {

std::string resolveLcmUrl(std::string_view flag_value) {
  if (!flag_value.empty()) return std::string(flag_value);
  if (const char* env = std::getenv("LCM_DEFAULT_URL"); env != nullptr && *env != '\0') return env;
  return std::string(kLcmDefaultUrl);
}

std::string withReceiveBuffer(std::string_view url, int bytes) {
  if (!url.starts_with("udpm://")) return std::string(url);
  const auto query = url.find('?');
  if (query != std::string_view::npos &&
      (url.find("?recv_buf_size=", query) != std::string_view::npos ||
       url.find("&recv_buf_size=", query) != std::string_view::npos)) {
    return std::string(url);
  }
  std::string out(url);
  out += (query == std::string_view::npos) ? '?' : '&';
  out += "recv_buf_size=" + std::to_string(bytes);
  return out;
}

}  // namespace ogf::transport
