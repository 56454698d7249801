// Who may use ogf-view: on a loopback address only the robot itself can connect, so no token is asked;
// on any other address (0.0.0.0 included: every interface) every request carries a token, in the query
// (`?token=...`, the address ogf-view prints at start) or in the cookie the page gets with it. Pure
// functions: the server and the program own the sockets and the files.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace ogf::view {

inline constexpr std::string_view kTokenCookie = "ogf_view_token";
// A token of fewer characters is refused: 16 random hex digits are 64 bits, more than a network
// attacker can try at the rate one view answers.
inline constexpr std::size_t kMinTokenLength = 16;

// True for 127.0.0.0/8, ::1 and ::ffff:127.x.y.z; false for every other address, the wildcards 0.0.0.0
// and :: among them, and for text that is not an address.
bool isLoopbackAddress(std::string_view address);

// Compares in a time that depends on the lengths only, not on where the first difference lies.
bool tokensEqual(std::string_view a, std::string_view b);

// The value of `token` in a request target's query ("/ws?token=abc" -> "abc"), if there is one.
std::optional<std::string_view> tokenInTarget(std::string_view target);
// The value of the kTokenCookie cookie in a Cookie header ("a=1; ogf_view_token=abc" -> "abc").
std::optional<std::string_view> tokenInCookie(std::string_view cookie_header);

// Why a token read from a file cannot be used (too short, or characters a URL would have to escape),
// nullopt when it is fine. Letters, digits and "-._~" are allowed.
std::optional<std::string> tokenProblem(std::string_view token);

// The token a --token file holds: its first line without the blanks (spaces, tabs, CR) around it.
std::string tokenOfFileText(std::string_view text);

}  // namespace ogf::view
