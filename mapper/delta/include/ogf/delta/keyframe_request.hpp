// What a client of OGF_MAP_DELTA publishes on OGF_MAP_REQUEST when its MapReceiver needs a keyframe.
#pragma once

#include <ogf/map_request_t.hpp>

#include <string>

#include "ogf/delta/map_receiver.hpp"

namespace ogf::delta {

// "host:pid", naming this process in its requests.
std::string requesterName();

// A request stamped now (host clock), from `requester`, carrying the last update `receiver` applied.
ogf::map_request_t keyframeRequest(const MapReceiver& receiver, const std::string& requester);

}  // namespace ogf::delta
