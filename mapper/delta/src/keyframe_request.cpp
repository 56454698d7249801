#include "ogf/delta/keyframe_request.hpp"

#include <unistd.h>

#include <chrono>

namespace ogf::delta {

std::string requesterName() {
  char host[256] = {};
  ::gethostname(host, sizeof(host) - 1);
  return std::string(host) + ":" + std::to_string(::getpid());
}

ogf::map_request_t keyframeRequest(const MapReceiver& receiver, const std::string& requester) {
  ogf::map_request_t req{};
  req.utime = std::chrono::duration_cast<std::chrono::microseconds>(
                  std::chrono::system_clock::now().time_since_epoch()).count();
  req.requester = requester;
  req.last_seq = receiver.appliedSeq();
  return req;
}

}  // namespace ogf::delta
