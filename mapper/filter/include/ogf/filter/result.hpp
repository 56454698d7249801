// Error reporting for the filter library: the project's Result/Error (common/), whose message names the
// file, offset or field that was wrong. The library never prints or exits; programs report.
#pragma once

#include "ogf/common/result.hpp"

namespace ogf::filter {

using ogf::Error;
using ogf::Ok;
using ogf::okStatus;
using ogf::Result;
using ogf::Status;

}  // namespace ogf::filter
