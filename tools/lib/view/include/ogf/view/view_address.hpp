// The line ogf-view prints at start: the address a browser opens. A wildcard bind (0.0.0.0) is shown as
// 127.0.0.1, an IPv6 address in brackets; with a token made at start the address carries it, with one read
// from --token FILE the line says where it is (the token itself stays out of logs and terminals).
#pragma once

#include <cstdint>
#include <string>

namespace ogf::view {

// "ogf-view: http://HOST:PORT/...\n"; `token` empty: no token is asked; `token_file` empty: the token was
// made at start.
std::string addressLine(const std::string& bind, std::uint16_t port, const std::string& token,
                        const std::string& token_file);

}  // namespace ogf::view
