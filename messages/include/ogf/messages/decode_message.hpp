// Decoding one received LCM buffer safely, for every reader of untrusted bytes (subscriptions, LCM logs):
// the array counts are checked before decode() can allocate for them (EncodedSizeCheck), anything decode()
// throws is a malformed message, and the message must use the whole buffer.
#pragma once

#include <cstddef>
#include <exception>
#include <optional>
#include <string>

#include "ogf/messages/encoded_size_check.hpp"

namespace ogf::messages {

// Decodes `data` into `out`; nullopt on success, else why the buffer is not a valid Message.
template <class Message>
std::optional<std::string> decodeMessage(const void* data, std::size_t size, Message& out) {
  if (auto bad = EncodedSizeCheck<Message>::check(data, size)) return "is malformed: " + *bad;
  int used = -1;
  try {
    used = out.decode(data, 0, static_cast<int>(size));
  } catch (const std::exception&) {
    used = -1;  // a count the check does not cover made a vector throw
  }
  if (used < 0) return std::string("does not decode (wrong type or truncated)");
  if (static_cast<std::size_t>(used) != size) return std::string("has trailing bytes after the message");
  return std::nullopt;
}

}  // namespace ogf::messages
