// The address ogf-view prints: see view_address.hpp.
#include "ogf/view/view_address.hpp"

#include <fmt/format.h>

namespace ogf::view {

std::string addressLine(const std::string& bind, std::uint16_t port, const std::string& token,
                        const std::string& token_file) {
  const std::string host =
      bind == "0.0.0.0" ? "127.0.0.1" : bind.find(':') != std::string::npos ? "[" + bind + "]" : bind;
  const unsigned p = port;
  if (token.empty()) return fmt::format("ogf-view: http://{}:{}/\n", host, p);
  if (token_file.empty()) return fmt::format("ogf-view: http://{}:{}/?token={}\n", host, p, token);
  return fmt::format("ogf-view: http://{}:{}/ (add ?token= and the token in {})\n", host, p, token_file);
}

}  // namespace ogf::view
