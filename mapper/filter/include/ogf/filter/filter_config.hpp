// Typed configuration of the banded Occupancy Grid Filter, with validation that names the bad field and the
// paper's values as defaults (Sec. VI: σ = half the cell size, amplitude 1/(σ√(2π)), r_o = 0.65,
// r_f = 0.35). Unset optional fields are derived by resolved(): σ from the resolution, R from σ/cell, the
// taper support from R.
#pragma once

#include <optional>
#include <string_view>

#include "ogf/filter/kernel.hpp"
#include "ogf/common/result.hpp"

namespace ogf::filter {

// Side of a storage block in cells (docs/filter.md §6.3: B = 8). Blocks are B×B×B in 3-D and B×B×1 in 2-D.
inline constexpr int kBlockSide = 8;

// Which measurements of a cell that rays have ended in reach the filter (Sun et al. Sec. VI-B: "a cell
// previously measured as free could be re-measured as occupied, but the opposite was not allowed"). A
// surface cell is crossed by the rays of neighbouring beams, by grazing rays and, with range noise, by rays
// that end in the next cell; with a symmetric likelihood those free measurements outvote the hits of a
// cell that is hit in fewer than about half of the scans, and real surfaces vanish from the map.
enum class OccupiedPriority : int {
  // Occupied wins over free within one batch only (the measurement set of a scan keeps one measurement
  // per cell); every measurement reaches eq. (5): the exact filter.
  kScan = 0,
  // Occupied wins across batches: a cell once measured occupied ignores free measurements until
  // `freeReleaseCount` batches in a row have measured it free and none occupied (a moving solid that left);
  // then it takes them again until its next occupied measurement.
  kMap = 1,
};

// How the covariance between neighbouring cells is kept (docs/filter.md §6.3 and §6.4).
enum class CovarianceStorage : int {
  // Every cell stores its covariances to the forward half of its stencil (56 bytes a cell at the default
  // stencil): eq. (5) applied exactly inside the band.
  kBanded = 0,
  // Every cell stores its mean and variance only (8 bytes, with its mark 9): the covariance of two cells
  // within the stencil is rebuilt from the prior, Σ_jk = Σ0_jk·(Σ_jj/Σ0_jj)·(Σ_kk/Σ0_kk), so a correlation
  // fades as its cells become certain, the way eq. (5) shrinks Σ_ij by Σ_ii'/Σ_ii when cell i is measured.
  // Positive semi-definite: it is S·Σ0·S (S = diag(Σ_jj/Σ0_jj)) plus the non-negative diagonal
  // Σ_jj − Σ_jj²/Σ0_jj. Costs against the banded filter: docs/mapping.md, "Covariance storage".
  kCompact = 1,
};

struct FilterConfig {
  // 3: cells are 3-D and the stencil is a ball. 2: the map is the z = 0 slice and the stencil a disc.
  int dimensions = 3;
  double resolution = 0.2;                 // metres per cell
  std::optional<double> kernelSigma;       // metres; default resolution / 2
  std::optional<double> kernelAmplitude;   // default 1/(σ√(2π)), the paper's normal pdf
  std::optional<double> stencilRadius;     // R, cells; default defaultStencilRadius(σ/cell)
  int stencilManhattanRadius = 2;          // L, cells: |o|₁ ≤ L is kept too (stencil_shape.hpp); 0 = none
  // cells; default: the longest of s·{64, 16, 8, 6, 4, 3, 2.5, 2, 1.5, 1.25} whose banded prior is
  // certified positive definite, else s, the shortest offset outside the stencil (nothing dropped, so
  // definite by the Schur product theorem).
  std::optional<double> taperSupport;
  double occupiedThreshold = 0.65;         // r_o of eq. (3)
  double freeThreshold = 0.35;             // r_f of eq. (3)
  // An update whose change to the measured cell's mean and variance is below this is skipped
  // (docs/filter.md §7.2). 0 applies every update.
  double skipTolerance = 1e-4;
  // A measurement that agrees with a confidently classified cell, y·m/√(1+s) > clampZ, is skipped without
  // evaluating λ: the OGF's OctoMap-style clamping. The probit update converges only logarithmically, so
  // without it a static scene never falls below skipTolerance. 0 disables all clamping (the exact filter).
  double clampZ = 3.0;
  // The threshold for free measurements (y = −1), which are most of a scan's: −m/√(1+s) > freeClampZ skips
  // one, i.e. once the predictive probability of "free" exceeds Φ(1.5) = 0.933 (OctoMap clamps free space
  // at 0.88, its 0.12 occupancy bound). Occupied measurements keep clampZ, so occupied evidence keeps
  // accumulating. Costs and gains: docs/mapping.md, "Clamps". 0: free measurements use clampZ too. Ignored
  // when clampZ is 0.
  double freeClampZ = 1.5;
  OccupiedPriority occupiedPriority = OccupiedPriority::kMap;
  // Under kMap, the free measurement (one a batch, so a scan) that releases a cell once measured occupied
  // when it is the freeReleaseCount-th in a row: the ones before it are held back, it and later ones apply.
  // 0: never released (the paper's rule as stated). At most kMaxFreeRelease. 20 scans (2 s at 10 Hz) keep
  // real surfaces that most rays miss and clear a walking person's trail as fast as OctoMap (docs/mapping.md).
  int freeReleaseCount = 20;
  // A structural choice, like the stencil: a map file keeps the storage it was made with
  // (BandedOgf::withCovarianceStorage converts).
  CovarianceStorage covariance = CovarianceStorage::kBanded;
  int threads = 1;  // worker threads of BandedOgf::update; the map is bit-identical for any count

  // Every optional field filled in, and every field checked. The error names the field.
  Result<FilterConfig> resolved() const;
  // The checks of the policy fields alone (thresholds, skip tolerance, clamps, threads), which resolved()
  // also makes; cheap, unlike the prior's certificate.
  Status validatePolicy() const;

  // Valid only on a resolved configuration.
  GaussianKernel kernel() const { return {*kernelSigma, *kernelAmplitude}; }
  WendlandTaper taper() const { return {*taperSupport}; }
  StencilShape stencilShape() const { return {*stencilRadius, stencilManhattanRadius}; }
  PriorCovariance prior() const { return {kernel(), taper(), resolution, stencilShape()}; }
};

// The default stencil radius, in cells, for a kernel of `sigmaCells` cells: √2 up to σ = cell/2 (with the
// default Manhattan radius 2: d(banded, dense) ≈ 0.3 % on random 2-D and 3-D scenes, 56 bytes per cell in
// 3-D), else √⌊(4σ/cell)²⌋: at σ = cell, R = 4 keeps d ≈ 0.1 % on the paper's 2-D experiment where R = 3
// needs a taper that damps the prior enough to cost ≈ 10 % (ogf-paper2d --banded-radius).
double defaultStencilRadius(double sigmaCells);

inline constexpr int kMaxFreeRelease = 127;  // the count is kept in 7 bits of a cell's mark

// "scan" / "map", as configuration files spell the policy; nullopt for anything else.
const char* toString(OccupiedPriority p);
std::optional<OccupiedPriority> parseOccupiedPriority(std::string_view text);
// "banded" / "compact", as configuration files spell the storage; nullopt for anything else.
const char* toString(CovarianceStorage c);
std::optional<CovarianceStorage> parseCovarianceStorage(std::string_view text);

}  // namespace ogf::filter
