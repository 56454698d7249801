// Which LCM bus a process joins, and the receive-side settings that keep udpm from dropping messages.
#pragma once

#include <string>
#include <string_view>

namespace ogf::transport {

// LCM's own default when neither a flag nor LCM_DEFAULT_URL names a bus (lcm.h, v1.3.1).
inline constexpr std::string_view kLcmDefaultUrl = "udpm://239.255.76.67:7667?ttl=0";

// Per-subscription queue length. LCM's default of 30 (31 in practice, lcm#167) silently drops the
// *newest* messages once full (lcm#345): a 200-message burst on udpm arrives as 31.
inline constexpr int kSubscriptionQueueCapacity = 10000;

// Kernel receive buffer asked for on udpm subscribers: a decoded scan is ~0.5 MB in 8 fragments, and the
// Linux default of 208 KiB loses whole messages (measured: 0/5 1 MB messages received).
inline constexpr int kUdpmReceiveBufferBytes = 8 * 1024 * 1024;

// The URL to use: `flag_value` when non-empty, else $LCM_DEFAULT_URL when set and non-empty, else
// kLcmDefaultUrl.
std::string resolveLcmUrl(std::string_view flag_value);

// For a udpm:// URL without a recv_buf_size option, the same URL with recv_buf_size=`bytes` added;
// any other URL unchanged. An explicit recv_buf_size always wins.
std::string withReceiveBuffer(std::string_view url, int bytes = kUdpmReceiveBufferBytes);

}  // namespace ogf::transport
