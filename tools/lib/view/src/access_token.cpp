#include "ogf/view/access_token.hpp"

#include <boost/asio/ip/address.hpp>

namespace ogf::view {

bool isLoopbackAddress(std::string_view address) {
  boost::system::error_code ec;
  const auto a = boost::asio::ip::make_address(std::string(address), ec);
  if (ec) return false;
  if (a.is_v4()) return a.to_v4().is_loopback();
  const auto v6 = a.to_v6();
  if (v6.is_v4_mapped()) return boost::asio::ip::make_address_v4(boost::asio::ip::v4_mapped, v6).is_loopback();
  return v6.is_loopback();
}

bool tokensEqual(std::string_view a, std::string_view b) {
  // Every byte of the longer one is looked at; the difference accumulates without an early exit.
  const std::size_t n = std::max(a.size(), b.size());
  unsigned diff = a.size() == b.size() ? 0u : 1u;
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned char x = i < a.size() ? static_cast<unsigned char>(a[i]) : 0;
    const unsigned char y = i < b.size() ? static_cast<unsigned char>(b[i]) : 0;
    diff |= static_cast<unsigned>(x ^ y);
  }
  return diff == 0;
}

namespace {

// The value of `name` in a list of name=value pairs separated by `separator` (spaces around pairs skipped).
std::optional<std::string_view> valueIn(std::string_view list, char separator, std::string_view name) {
  while (!list.empty()) {
    const auto end = list.find(separator);
    std::string_view pair = list.substr(0, end);
    list = end == std::string_view::npos ? std::string_view{} : list.substr(end + 1);
    while (!pair.empty() && pair.front() == ' ') pair.remove_prefix(1);
    const auto eq = pair.find('=');
    if (eq != std::string_view::npos && pair.substr(0, eq) == name) return pair.substr(eq + 1);
  }
  return std::nullopt;
}

}  // namespace

std::optional<std::string_view> tokenInTarget(std::string_view target) {
  const auto q = target.find('?');
  if (q == std::string_view::npos) return std::nullopt;
  auto query = target.substr(q + 1);
  if (const auto hash = query.find('#'); hash != std::string_view::npos) query = query.substr(0, hash);
  return valueIn(query, '&', "token");
}

std::optional<std::string_view> tokenInCookie(std::string_view cookie_header) {
  return valueIn(cookie_header, ';', kTokenCookie);
}

std::optional<std::string> tokenProblem(std::string_view token) {
  if (token.size() < kMinTokenLength)
    return "the token has " + std::to_string(token.size()) + " characters, fewer than " +
           std::to_string(kMinTokenLength);
  for (const char c : token) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' ||
                    c == '.' || c == '_' || c == '~';
    if (!ok) return "the token holds a character other than letters, digits and -._~";
  }
  return std::nullopt;
}

std::string tokenOfFileText(std::string_view text) {
  std::string token(text.substr(0, text.find('\n')));
  const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  while (!token.empty() && blank(token.back())) token.pop_back();
  while (!token.empty() && blank(token.front())) token.erase(token.begin());
  return token;
}

}  // namespace ogf::view
