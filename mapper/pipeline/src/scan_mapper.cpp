#include "ogf/pipeline/scan_mapper.hpp"

#include "ogf/pipeline/published_cells.hpp"

#include <ogf/filter/map_file.hpp>

#include <algorithm>
#include <cmath>

namespace ogf::pipeline {
namespace {

// Collects the filter's changed cells as delta candidates.
class ChangeCollector final : public filter::ChangeSink {
 public:
  explicit ChangeCollector(ChangedCells& out) : out_(out) {}
  void cellChanged(const filter::CellChange& c) override { out_.push_back(publishedOf(c)); }
  // Each cell written once: a resize would first write every new element's defaults, and a 0.1 m street
  // scan reports a million changed cells.
  void cellsChanged(std::span<const filter::CellChange> changes) override {
    const std::size_t need = out_.size() + changes.size();
    if (need > out_.capacity()) out_.reserve(std::max(need, 2 * out_.capacity()));
    for (const filter::CellChange& c : changes) out_.push_back(publishedOf(c));
  }

 private:
  static delta::PublishedCell publishedOf(const filter::CellChange& c) {
    return {c.key, static_cast<std::int16_t>(c.quantisedProbability), c.occupancyClass, c.variance};
  }
  ChangedCells& out_;
};

}  // namespace

Result<ScanMapper> ScanMapper::create(const MapperConfig& config) {
  if (auto st = config.validate(); !st) return st.error();
  auto filter = filter::BandedOgf::create(config.filter);
  if (!filter) return Error::configuration("filter." + filter.error().message);
  return ScanMapper(config, std::move(*filter));
}

ScanMapper::ScanMapper(const MapperConfig& config, filter::BandedOgf filter)
    : config_(config),
      deskew_(config.fusion.extrinsic.bodyFromSensor()),
      set_(config.fusion.measurement),
      filter_(std::move(filter)) {}

fusion::PoseCoverage ScanMapper::measure(const fusion::ScanPoints& scan, const fusion::PoseBuffer& poses) {
  measurements_ = {};
  const fusion::PoseCoverage c = deskew_.place(scan, poses, origins_, endpoints_);
  if (c != fusion::PoseCoverage::kCovered) return c;
  measurements_ = set_.build(origins_, endpoints_);
  return c;
}

fusion::PoseCoverage ScanMapper::measure(const fusion::ScanPoints& scan, const fusion::PoseBuffer& poses,
                                         correction::ScanPoseCorrection& correction,
                                         correction::ScanCorrection* applied) {
  const fusion::PoseCoverage c = place(scan, poses);
  if (c == fusion::PoseCoverage::kCovered) measurePlaced(correction, applied);
  return c;
}

fusion::PoseCoverage ScanMapper::place(const fusion::ScanPoints& scan, const fusion::PoseBuffer& poses) {
  measurements_ = {};
  const fusion::PoseCoverage c = deskew_.place(scan, poses, origins_, endpoints_);
  if (c != fusion::PoseCoverage::kCovered) return c;
  const fusion::ScanTimeSpan span = fusion::timeSpanOf(scan);
  const fusion::PoseLookup reference = poses.interpolate(span.begin_utime + (span.end_utime - span.begin_utime) / 2);
  if (!reference.ok()) return reference.coverage;  // cannot happen after place() covered the span
  reference_ = reference.pose;
  return c;
}

void ScanMapper::measurePlaced(correction::ScanPoseCorrection& correction, correction::ScanCorrection* applied) {
  const correction::ScanCorrection result = correction.correct(reference_.odomFromBody(), endpoints_);
  if (correction.mode() != slam::CorrectionMode::kNone) {
    for (Eigen::Vector3d& o : origins_) o = result.map_from_odom * o;
    for (Eigen::Vector3d& e : endpoints_) e = result.map_from_odom * e;
  }
  if (applied != nullptr) *applied = result;
  measurements_ = set_.build(origins_, endpoints_);
}

void ScanMapper::measureStatic(const fusion::ScanPoints& scan, const Eigen::Isometry3d& odom_from_sensor) {
  const std::size_t n = scan.size();
  origins_.assign(n, odom_from_sensor.translation());
  endpoints_.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    endpoints_[i] = odom_from_sensor * Eigen::Vector3d(scan.x[i], scan.y[i], scan.z[i]);
  measurements_ = set_.build(origins_, endpoints_);
}

filter::UpdateStats ScanMapper::apply(std::span<const Measurement> measurements,
                                      ChangedCells* changes) {
  if (changes == nullptr) return filter_.update(measurements);
  ChangeCollector collector(*changes);
  return filter_.update(measurements, &collector);
}

Status ScanMapper::restoreFilter(std::span<const std::uint8_t> map_bytes, const std::string& source) {
  auto loaded = filter::decodeMap(map_bytes, source, filter_.config().threads);
  if (!loaded) return loaded.error();
  const auto& want = filter_.config();
  const auto& got = loaded->config();
  const auto differs = [](double a, double b) { return std::abs(a - b) > 1e-12 * std::max(1.0, std::abs(a)); };
  const auto mismatch = [&](const char* field, double saved, double configured) -> Status {
    return Error::configuration(source + ": " + field + " " + std::to_string(saved) +
                                " of the saved map differs from the configured " + std::to_string(configured));
  };
  if (got.dimensions != want.dimensions) return mismatch("dimensions", got.dimensions, want.dimensions);
  if (differs(got.resolution, want.resolution)) return mismatch("resolution", got.resolution, want.resolution);
  if (differs(*got.kernelSigma, *want.kernelSigma)) return mismatch("kernel sigma", *got.kernelSigma, *want.kernelSigma);
  if (differs(*got.kernelAmplitude, *want.kernelAmplitude))
    return mismatch("kernel amplitude", *got.kernelAmplitude, *want.kernelAmplitude);
  if (differs(*got.stencilRadius, *want.stencilRadius)) return mismatch("stencil radius", *got.stencilRadius, *want.stencilRadius);
  if (got.stencilManhattanRadius != want.stencilManhattanRadius)
    return mismatch("stencil Manhattan radius", got.stencilManhattanRadius, want.stencilManhattanRadius);
  // The thresholds, clamps and skip tolerance are the configuration's, not those saved with the map (an
  // older file, or a changed configuration).
  if (auto st = loaded->adoptPolicy(want); !st) return st.error().within(source);
  // A map saved in the other covariance storage is converted to the configured one.
  filter_ = got.covariance == want.covariance ? std::move(*loaded) : loaded->withCovarianceStorage(want.covariance);
  return okStatus();
}

std::vector<delta::PublishedCell> ScanMapper::publishedCells() const { return publishedCellsOf(filter_); }

}  // namespace ogf::pipeline
