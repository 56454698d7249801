// How every ogf_sim function reports failure: the project's Result/Error (common/), whose message names the
// file, the line or the field that was wrong.
#pragma once

#include "ogf/common/result.hpp"

namespace ogf::sim {

using ogf::Error;
using ogf::Ok;
using ogf::Result;
using ogf::Status;

}  // namespace ogf::sim
