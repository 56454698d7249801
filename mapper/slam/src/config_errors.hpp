// How the slam layer's configuration checks word an error: the field, the rule, the value seen.
#pragma once

#include <sstream>
#include <string>

#include "ogf/common/result.hpp"

namespace ogf::slam {

inline Error fieldError(const std::string& field, const std::string& rule, double value) {
  std::ostringstream s;
  s << field << " " << rule << " (got " << value << ")";
  return Error::configuration(s.str());
}

// The error of a nested part, its field path prefixed ("proposal.samples_per_axis ...").
inline Status prefixed(const std::string& prefix, Status status) {
  if (status) return status;
  return Error::configuration(prefix + status.error().message);
}

}  // namespace ogf::slam
