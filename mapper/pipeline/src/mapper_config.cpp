#include "ogf/pipeline/mapper_config.hpp"

#include <string>

namespace ogf::pipeline {

Status MapperConfig::validate() const {
  if (auto st = fusion.validate(); !st) return Error::configuration("fusion." + st.error().message);
  if (auto r = filter.resolved(); !r) return Error::configuration("filter." + r.error().message);
  if (filter.dimensions != 3) return Error::configuration("filter.dimensions: the mapper builds 3-D maps, got " + std::to_string(filter.dimensions));
  if (fusion.measurement.resolution_m != filter.resolution)
    return Error::configuration("filter.resolution: " + std::to_string(filter.resolution) + " m differs from fusion's " +
                 std::to_string(fusion.measurement.resolution_m) + " m; one cell size serves both");
  return okStatus();
}

}  // namespace ogf::pipeline
