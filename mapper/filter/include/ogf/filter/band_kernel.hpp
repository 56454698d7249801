// The inner loop of the banded OGF: eq. (5) applied to the stored entries of one measurement's stencil
// (docs/filter.md §3.1 and §6.2). Given the cell's scalar update (probit_update.hpp) and the records of the
// stencil cells in the 3×3×3 neighbourhood of blocks (found by a BandLocate), it reads the column Σ[:, i]
// and applies
//   m_s  += gain·Σ_si,   Σ_ss −= shrink·Σ_si²,   Σ_st −= shrink·Σ_si·Σ_ti  for every stored pair (s, t).
//
// Two implementations with the same arithmetic in the same order, so they give the same floats bit for bit:
// a generic one driven by run-time tables (any stencil, 2-D or 3-D), and ones compiled for the common 3-D
// stencils (R = 1, √2, √3, 2, and the default √2 ball + Manhattan 2), whose pair lists are generated at
// compile time from the same rule as Stencil's and unrolled into straight-line code: no index loads, no
// loop control, constant offsets. bandKernelFor() picks a compiled kernel only when its tables equal the
// run-time stencil's.
//
// Two arithmetics: the x86-64 baseline (the build assumes only SSE2) multiplies, then subtracts; on a CPU
// with AVX2 and FMA every entry is one fused multiply-add (one rounding). The choice is made once per
// process from the CPU, so a map is bit-identical for any thread count and batch order on one machine,
// while an FMA and a non-FMA machine differ in the last bits of the floats.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "ogf/filter/filter_config.hpp"
#include "ogf/filter/stencil.hpp"

namespace ogf::filter {

// The per-stencil tables of the update, derived from a Stencil and the block layout (8×8×8 cells, x fastest).
struct BandTables {
  BandTables(const Stencil& stencil, int dimensions, CovarianceStorage storage = CovarianceStorage::kBanded);

  std::size_t cells = 0;     // stencil cells S
  std::size_t stride = 0;    // floats per cell record: 2 + forward slots (banded); 1, the mean (compact)
  std::size_t pointers = 0;  // record pointers per measurement: S (banded); 2S, means then variances (compact)
  std::size_t blockCells = 0;  // cells in a block (where a compact block's variance codes begin)
  std::size_t self = 0;    // index of offset 0
  // Per local position l and stencil cell s, [l·S + s]: the neighbouring block (13 = own) and the first float
  // of the record in it.
  std::vector<std::uint8_t> recordBlock;
  std::vector<std::uint32_t> recordFloat;
  // recordFloat in 16 bits, when every offset fits (small stencils, all the compiled ones): the compiled
  // locators read this half-size copy, which leaves more of the L1 cache to the records. Empty otherwise.
  std::vector<std::uint16_t> recordFloat16;
  // Per stencil cell s: where Σ_si is stored: (record of cell `columnCell[s]`, float `columnFloat[s]`).
  std::vector<std::uint16_t> columnCell;
  std::vector<std::uint16_t> columnFloat;
  // The pairs kept by stencil cell s: [pairStart[s], pairStart[s + 1]); per pair the other cell and the float
  // of s's record that holds Σ_st.
  std::vector<std::uint32_t> pairStart;
  std::vector<std::uint16_t> pairOther;
  std::vector<std::uint16_t> pairFloat;

  // Per stencil cell s: 1 when no stencil cell follows it along x (the last record of its x row).
  std::vector<std::uint8_t> rowEnd;
  // Compact storage: per stencil cell s, the prior covariance Σ0_si between s and the measured cell, and
  // the prior variance. Filled by the filter, which owns the prior; empty for banded storage.
  std::vector<float> correlation;
  float priorVariance = 0.0F;

  // The record of stencil cell s of the measurement at `local`, `blocks` as for BandKernel.
  float* record(float* const* blocks, std::size_t local, std::size_t s) const {
    return blocks[recordBlock[local * cells + s]] + recordFloat[local * cells + s];
  }
};

// The scalars of one update (probit_update.hpp), in float as the records are.
struct BandUpdate {
  float gain = 0.0F;           // meanGain
  float shrink = 0.0F;         // covShrink
  float varianceFloor = 0.0F;  // variances never drop below this
};

// Applies one update given the records of its stencil cells: `records[s]` is the record of stencil cell s
// (BandTables::record: the blocks of the 3×3×3 neighbourhood, d = (dx+1) + 3(dy+1) + 9(dz+1), every one the
// stencil reaches present). The caller finds them once for its prefetch and the update.
using BandKernel = void (*)(float* const* records, BandUpdate update, const BandTables& tables);

// Finds the records of the stencil cells of the measurement at `local` (`blocks` as above) into `records`
// and asks the CPU for their cache lines: the first float of every record, and the last float of the last
// record of each x row (records of one row are consecutive in a block), so every line of the row is asked
// for once (a row cut by a block face may leave the tail of one record to the hardware). Called a few
// measurements ahead of the kernel, which then takes `records`.
using BandLocate = void (*)(float* const* blocks, std::size_t local, const BandTables& tables,
                            float** records);

// The generic one, for any stencil.
void genericBandLocate(float* const* blocks, std::size_t local, const BandTables& tables, float** records);

// One unrolled for the stencil when a compiled kernel exists for it (same choice as bandKernelFor), else
// the generic one.
BandLocate bandLocateFor(const BandTables& tables);

// The generic kernel in the baseline arithmetic.
void genericBandKernel(float* const* records, BandUpdate update, const BandTables& tables);

// Compact storage (CovarianceStorage::kCompact): `records[s]` is the mean of stencil cell s and
// `records[S + s]` its variance code (variance_code.hpp), as a float pointer.
void compactBandLocate(float* const* blocks, std::size_t local, const BandTables& tables, float** records);
// Its update: with r = Σ_ss/Σ0 the stored variance ratios, the column is Σ_si = Σ0_si·r_s·r_i (Σ0·r_i for the
// cell itself), then m_s += gain·Σ_si and r_s −= shrink·Σ_si²/Σ0 for every stencil cell, rounded to its
// code. One arithmetic on every CPU.
void compactBandKernel(float* const* records, BandUpdate update, const BandTables& tables);
// Whether this CPU (and OS) can run AVX2 + FMA code.
bool cpuHasFma();

// The same arithmetic with the cell count fixed at compile time for the stencils of 25 cells (the default:
// the √2 ball and the axial cells at distance 2) and 19 (the √2 ball alone, the lean stencil of
// docs/mapping.md), in 8-wide vectors when `avx2` (the same floats: no fused operations), else
// compactBandKernel (which takes stencils of any size).
BandKernel compactBandKernelFor(const BandTables& tables, bool avx2 = cpuHasFma());

// The generic kernel: in the fused arithmetic when `fma` (and the build has it), else genericBandKernel.
BandKernel genericBandKernelFor(bool fma);

// A compiled kernel whose tables equal `tables`, or the generic one when there is none; in the fused
// arithmetic when `fma`. Kernels of one arithmetic give the same floats, bit for bit.
BandKernel bandKernelFor(const BandTables& tables, bool fma = cpuHasFma());

}  // namespace ogf::filter
