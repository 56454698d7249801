// Everything that shapes the map: how scans become measurements (fusion) and how measurements update the
// filter. Both must agree on the cell size; validate() says which field is wrong.
#pragma once

#include <ogf/filter/filter_config.hpp>
#include <ogf/fusion/fusion_config.hpp>

#include "ogf/common/result.hpp"

namespace ogf::pipeline {

struct MapperConfig {
  fusion::FusionConfig fusion;
  // The filter library defaults to the exact banded covariance; the mapping programs store it compactly
  // (filter_config.hpp, CovarianceStorage; costs in docs/mapping.md).
  filter::FilterConfig filter = [] {
    filter::FilterConfig f;
    f.covariance = filter::CovarianceStorage::kCompact;
    return f;
  }();

  // Sets the one cell size both layers use.
  void setResolution(double metres) {
    fusion.measurement.resolution_m = metres;
    filter.resolution = metres;
  }
  // The first wrong field, with its path ("fusion.measurement.max_range_m: ...", "filter.resolution: ...").
  Status validate() const;
};

}  // namespace ogf::pipeline
