// Integration tests run real LCM udpm:// on the loopback interface (memq:// hides the queue and
// kernel-buffer drops). This arranges the multicast route they need when the test may, and otherwise
// says why it cannot, so the test skips with that reason.
#pragma once

#include <optional>
#include <string>

namespace ogf::testing {

// nullopt when 239.255.76.67 routes over lo (after adding `224.0.0.0/4 dev lo` when running as root);
// else the reason udpm on loopback is unavailable.
std::optional<std::string> ensureLoopbackMulticast();

// A udpm URL on loopback with ttl=0, a port no other test uses at the same time (from the PID and
// `slot`), and a large receive buffer.
std::string loopbackUdpmUrl(int slot);

}  // namespace ogf::testing
