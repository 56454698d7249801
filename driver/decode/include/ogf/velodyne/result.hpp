// The error type the decoding library returns instead of throwing or printing: the project's Result/Error
// (common/), whose message names the file, offset or field that was wrong.
#pragma once

#include "ogf/common/result.hpp"

namespace ogf::velodyne {

using ogf::Error;
using ogf::Ok;
using ogf::okStatus;
using ogf::Result;
using ogf::Status;

}  // namespace ogf::velodyne
