// The product Occupancy Grid Filter: eq. (5) with the covariance kept only between cells within the stencil
// radius R (docs/filter.md §6), on hashed blocks allocated on demand, so one measurement costs a constant
// amount of work whatever the size of the map. Prior Σ0 = kernel × Wendland taper. Banded storage keeps mean,
// variance and the forward half of the covariances as floats; compact storage a float mean and a 16-bit
// variance, the covariances rebuilt from the prior (FilterConfig::covariance).
//
// Determinism: a batch is applied in a fixed order (colour of its block in a 2×2×2 checkerboard, block key,
// position in the block). Blocks of one colour are more than 2R apart, touch disjoint state and run in
// parallel; the map is bit-identical for any thread count. The stages that prepare a scan-sized batch
// (grouping it by block, dropping the clamped free measurements, placing it in order) share their work among
// the threads too, each thread on its own part, the parts joined in order.
#pragma once

#include <array>
#include <bit>
#include <cstdint>
#include <functional>
#include <memory>
#include <ogf/core/cell_key.hpp>
#include <span>
#include <vector>

#include "ogf/filter/band_kernel.hpp"
#include "ogf/filter/block_key_table.hpp"
#include "ogf/filter/block_storage.hpp"
#include "ogf/filter/change_sink.hpp"
#include "ogf/filter/filter_config.hpp"
#include "ogf/filter/inverse_mills_table.hpp"
#include "ogf/filter/kernel.hpp"
#include "ogf/filter/layer_changes.hpp"
#include "ogf/filter/measurement.hpp"
#include "ogf/filter/published_state.hpp"
#include "ogf/common/result.hpp"
#include "ogf/filter/stencil.hpp"
#include "ogf/filter/variance_code.hpp"
#include "ogf/filter/worker_pool.hpp"

namespace ogf::filter {

struct UpdateStats {
  std::size_t applied = 0;          // measurements that changed the map
  std::size_t skipped = 0;          // updates skipped: clamped (clampZ, freeClampZ) or below skipTolerance
  std::size_t skippedEarly = 0;     // of those, free ones known clamped before the batch was ordered
  std::size_t rejected = 0;         // y not ±1, or z ≠ 0 in a 2-D map
  std::size_t heldBack = 0;         // free measurements of cells measured occupied (OccupiedPriority::kMap)
  std::size_t blocksAllocated = 0;  // new blocks this batch
};

// The wrapping sum of block hashes (BandedOgf::blockHash) over some blocks, and how many.
struct BlockHashSum {
  std::uint64_t sum = 0;
  std::size_t blocks = 0;
};

// Latent mean and variance of one cell; the prior (0, Σ0_ii) for cells never allocated.
struct CellEstimate {
  double mean = 0.0;
  double variance = 0.0;
  bool allocated = false;
};

class BandedOgf {
 public:
  // Error when the configuration does not validate (the message names the field).
  static Result<BandedOgf> create(const FilterConfig& config);
  BandedOgf(BandedOgf&&) noexcept;
  BandedOgf& operator=(BandedOgf&&) noexcept;
  ~BandedOgf();

  // Applies a batch of measurements (one per cell, as a scan's measurement set is) in the deterministic
  // order above, then reports to `sink` (if any) every cell whose class or quantised probability changed.
  UpdateStats update(std::span<const Measurement> batch, ChangeSink* sink = nullptr);
  // One measurement, applied at once (a batch of one).
  UpdateStats update(const Measurement& m) { return update(std::span<const Measurement>(&m, 1)); }

  CellEstimate estimate(const CellKey& cell) const;
  // Σ between two cells: 0 beyond the stencil, the prior where nothing is allocated.
  double covariance(const CellKey& a, const CellKey& b) const;

  // Every allocated cell in a deterministic order: blocks by key, then x, y, z inside a block.
  void forEachCell(const std::function<void(const CellKey&, float mean, float variance)>& visit) const;
  std::size_t allocatedCells() const { return storage_.size() * storage_.cellsPerBlock(); }
  std::size_t memoryBytes() const;
  // 64-bit checksum of the configuration and every stored value: the structure's fields, then the number of
  // blocks and the wrapping sum of their hashes. A sum does not depend on the order of the blocks, so
  // blocks held outside the map (paged out) count with their hashes in `heldElsewhere`, and a block's hash
  // is kept until an update writes the block: a checksum after a scan rehashes only what the scan reached.
  std::uint64_t checksum(const BlockHashSum& heldElsewhere = {}) const;
  // Hash of one block's key, stored values and marks (0 when it is not allocated), and their sum over the
  // map.
  std::uint64_t blockHash(const CellKey& blockKey) const;
  BlockHashSum blockHashSum() const;

  const FilterConfig& config() const { return config_; }
  const Stencil& stencil() const { return stencil_; }
  const PriorCovariance& prior() const { return prior_; }
  // Number of worker threads for update(); does not change results.
  void setThreads(int threads) { config_.threads = threads < 1 ? 1 : threads; }
  // Whether update() drops the free measurements it is certain to skip before it orders the batch
  // (dropClampedFree; on by default, in compact storage); does not change results.
  void setSkipsClampedEarly(bool on) { skipsClampedEarly_ = on; }
  // The same map in the other covariance storage: compact keeps each cell's mean and variance and drops its
  // covariances; banded rebuilds them from the prior as compact storage computes them
  // (FilterConfig::covariance), so converting back and forth changes nothing but that rounding.
  BandedOgf withCovarianceStorage(CovarianceStorage storage) const;
  // Takes the policy of `config` (thresholds r_o/r_f, skip tolerance, clamps, threads) and keeps the map's
  // structure (dimensions, resolution, kernel, stencil, taper): a map restored from a file then filters as
  // configured now, not as it was when saved. Error (nothing changed) when `config` is invalid.
  Status adoptPolicy(const FilterConfig& config);

  // Raw block access for the map file: sorted keys, a block's floats (layout of Block) and cell marks
  // (CellMark), and restoring a block from them (error on a wrong size, a key outside the 2-D slice or a
  // duplicate; no marks: all 0).
  // Compact storage exchanges its blocks as banded storage without covariances: [mean, variance] per cell.
  std::vector<CellKey> blockKeys() const { return storage_.sortedKeys(); }
  std::vector<float> blockValues(const CellKey& blockKey) const;
  std::span<const std::uint8_t> blockMarks(const CellKey& blockKey) const;
  std::size_t floatsPerBlock() const { return storage_.cellsPerBlock() * floatsPerCell(); }
  std::size_t cellsPerBlock() const { return storage_.cellsPerBlock(); }
  Status restoreBlock(const CellKey& blockKey, std::span<const float> values,
                      std::span<const std::uint8_t> marks = {});

  // A block as it is stored (Block's layout for this storage, storedFloatsPerBlock() floats; empty when not
  // allocated), put back bit for bit by restoreStoredBlock (same errors as restoreBlock), and dropped from
  // the map by eraseBlock (false when not allocated): for holding blocks outside the map (paging).
  std::span<const float> storedValues(const CellKey& blockKey) const;
  std::size_t storedFloatsPerBlock() const { return storage_.floatsPerBlock(); }
  Status restoreStoredBlock(const CellKey& blockKey, std::span<const float> stored,
                            std::span<const std::uint8_t> marks);
  bool eraseBlock(const CellKey& blockKey) { return storage_.erase(blockKey); }
  // Every allocated block's key, in no particular order.
  template <class Visit>
  void forEachBlockKey(Visit visit) const {
    storage_.forEachBlock([&](const CellKey& key, const Block&) { visit(key); });
  }

 private:
  struct Group;
  explicit BandedOgf(const FilterConfig& resolved);
  static std::size_t floatsPerBlockOf(int dimensions, CovarianceStorage storage, const Stencil& stencil);
  // Floats per cell in the banded layout and in the exchange format (2 when compact).
  bool compact() const { return config_.covariance == CovarianceStorage::kCompact; }
  std::size_t floatsPerCell() const { return 2 + (compact() ? 0 : stencil_.forwardOffsets().size()); }
  struct Moments {
    float mean = 0.0F;
    float variance = 0.0F;
  };
  // The mean and variance of the cell at `local` in a block's values (either layout); inline, as the change
  // detection calls it for every touched cell.
  Moments momentsAt(const float* blockData, std::size_t local) const {
    if (compact()) {
      const auto* codes = reinterpret_cast<const std::uint16_t*>(blockData + storage_.cellsPerBlock());
      return {blockData[local], priorVariance_ * decodeVarianceRatio(codes[local])};
    }
    const float* d = blockData + local * floatsPerCell();
    return {d[0], d[1]};
  }
  // A cell's variance as stored: the 16-bit code in compact storage, the float's bits in banded storage.
  // Equal words are equal variances, so the change detection compares these and decodes only the cells
  // that changed.
  std::uint32_t storedVarianceAt(const float* blockData, std::size_t local) const {
    if (compact()) {
      return reinterpret_cast<const std::uint16_t*>(blockData + storage_.cellsPerBlock())[local];
    }
    return std::bit_cast<std::uint32_t>(blockData[local * floatsPerCell() + 1]);
  }
  float meanAt(const float* blockData, std::size_t local) const {
    return blockData[compact() ? local : local * floatsPerCell()];
  }
  float varianceOfStored(std::uint32_t stored) const {
    return compact() ? priorVariance_ * decodeVarianceRatio(static_cast<std::uint16_t>(stored))
                     : std::bit_cast<float>(stored);
  }
  // restoreBlock's checks of a block about to be restored with `values` floats (of `expected`) and marks.
  Status checkRestorable(const CellKey& blockKey, std::size_t values, std::size_t expected,
                         std::size_t marks) const;
  std::uint64_t blockHash(const CellKey& key, const Block& block) const;
  // A new block's values (the prior) and marks (cleared).
  void initialiseBlock(Block& block);
  // New blocks, on all filter threads when there are many (kParallelBlocksMin): the first write to a fresh
  // page is a fault, most of what allocating a first scan's blocks costs.
  void initialiseBlocks(std::span<Block* const> blocks);
  bool prioritisesOccupied() const { return config_.occupiedPriority == OccupiedPriority::kMap; }
  // Whether grouping the batch reads the blocks it has (their marks, or the means dropClampedFree tests).
  bool readsBlocks() const { return prioritisesOccupied() || dropsClampedFree_; }
  // Measurements in a batch for groupByBlock, dropClampedFree and orderGroups to share out among the threads.
  static constexpr std::size_t kParallelBatchMin = 16384;
  static constexpr std::size_t kParallelLayersMin = 1024;  // touched layers, for the change detection
  static constexpr std::size_t kParallelBlocksMin = 256;   // new blocks, for their initialisation

  // update()'s stages, in order, a source file each (src/banded_batch.hpp lists them; each function says
  // what it does where it is defined). The state a batch carries from stage to stage and each stage's
  // scratch are defined there too.
  struct TouchedBlock;
  struct Batch;
  struct Scratch;
  // The number of `blockKey` in Batch::touched, looked up in the map the first time in a batch.
  std::uint32_t lookUp(const CellKey& blockKey);
  // 1. batch_grouping.cpp
  std::vector<Group> groupByBlock(std::span<const Measurement> batch, UpdateStats& stats);
  void findRuns(std::span<const Measurement> batch);
  void prefetchRunsAhead(std::span<const Measurement> batch, std::size_t r,
                         std::span<const Block*> foundAhead) const;
  bool acceptable(const Measurement& m) const;
  // OccupiedPriority::kMap: whether a free measurement of the cell with this mark is held back (and the
  // mark counted on, or released).
  bool holdBackFree(std::uint8_t& mark) const;
  void acceptRun(std::span<const Measurement> batch, std::size_t i, std::size_t end, std::uint32_t g,
                 Group& group, std::size_t& next, UpdateStats& stats);
  Group makeGroup(const CellKey& block, Block* existing) const;
  bool groupInParallel(std::span<const Measurement> batch, std::vector<Group>& groups, UpdateStats& stats,
                       WorkerPool& threads);
  void closeUp(std::size_t from, std::size_t count, std::size_t to);
  void groupRun(std::span<const Measurement> batch, std::size_t r, std::vector<Group>& groups,
                std::size_t& accepted, UpdateStats& stats);
  // free_clamp_drop.cpp: removes from the batch (counted as skipped) the free measurements that
  // applyMeasurement would skip whatever the order: z above the free clamp before the batch, and no
  // occupied measurement of the batch within the cell's stencil. In compact storage with a non-negative
  // prior, free updates only lower a cell's mean and variance, so its z only grows: the map is the same,
  // bit for bit, without the locate, prefetch and z of each (most of a scan's free measurements once the
  // map has seen a place).
  void dropClampedFree(std::span<Group> groups, UpdateStats& stats);
  // 2. batch_order.cpp
  std::vector<Group> orderGroups(std::vector<Group>& groups);
  // 3. block_neighbourhoods.cpp
  void obtainNeighbourhoods(std::span<const Group> sorted, UpdateStats& stats);
  void findNeighbourhoods(std::span<const Group> sorted);
  // A group's codes in the order of application (Batch::sorted).
  std::span<const std::uint16_t> codesOf(const Group& g) const;
  // The marks of a group's occupied measurements (OccupiedPriority::kMap).
  static void markOccupied(Block& block, std::span<const std::uint16_t> codes);
  // 4. and 6. change_detection.cpp
  void recordChangeableCells(std::span<const Group> sorted);
  void markStencilReach(const Group& g, const std::uint32_t* touchedOfGroup,
                        std::array<std::array<std::uint64_t, 8>, 27>& reached);
  // Banded storage: copies the means and stored variances of the touched cells (the change detection's
  // state before the batch).
  void copyTouchedCells();
  // Compact storage: lists the touched layers of Batch::touched in Batch::touchedOrder and copies their
  // means and codes (the change detection's state before the batch).
  void copyTouchedLayers();
  // Starts loading the touched layers of the block whose first touched layer is ChangeScratch's [e].
  void prefetchTouchedLayers(std::size_t e, std::size_t end) const;
  struct ChangeChunk;
  void reportChanges(ChangeSink& sink);
  void collectLayerChanges(ChangeChunk& chunk, ChangeSink& sink, std::size_t e0, std::size_t e1) const;
  void collectCellChanges(ChangeChunk& chunk, ChangeSink& sink);
  void flushChanges(ChangeChunk& chunk, ChangeSink& sink) const;
  // 5. measurement_apply.cpp
  void applyColours(std::span<const Group> sorted, UpdateStats& stats);
  void applyColourInParallel(std::span<const Group> sorted, std::size_t g0, std::size_t g1,
                             UpdateStats& stats);
  // The measurements of consecutive groups (`groups`, their neighbourhoods from `neighbourhoods`, 27 per
  // group), in order, on one thread. The stencil records of a measurement a few places ahead are found
  // then (locate_, into `ring`: slots of band_.cells pointers) and asked of the CPU: a colour pass over a
  // scan-sized map (several MB) finds many of them out of cache, above all the cells one z layer ahead,
  // which no earlier measurement of the block has touched. The kernel takes the same pointers, so the
  // records are found once: the update alone takes about half the time it takes when the kernel searches
  // the records itself without prefetch (docs/performance.md).
  void applyRun(std::span<const Group> groups, std::span<const std::uint16_t> codes,
                float* const* neighbourhoods, std::span<float*> ring, UpdateStats& stats);
  bool applyMeasurement(float* const* records, int y);

  FilterConfig config_;
  PriorCovariance prior_;
  Stencil stencil_;
  BlockStorage storage_;
  std::vector<float> priorSlots_;  // Σ0 for each forward slot
  float priorVariance_ = 0.0F;
  float varianceFloor_ = 0.0F;
  // Compact storage: 1/√(1 + s) of each variance code's s, as applyMeasurement computes it.
  std::vector<double> inverseScales_;
  void derivePolicyState();                   // clampZ_, freeClampZ_ and published_ from config_
  PublishedStateRule published_;              // class and quantised probability for the ChangeSink
  double clampZ_ = 0.0;                       // for occupied measurements; +inf: never
  double freeClampZ_ = 0.0;                   // for free ones
  std::vector<std::uint32_t> neighbourMask_;  // per position in a block: neighbouring blocks reached
  // The stencil as rows along x, for the change detection's dilation: each (dy, dz) of its offsets with
  // the index of its set of dx in stencilRowSets_ (bit dx + 8 per dx).
  struct StencilRow {
    int dy = 0;
    int dz = 0;
    std::uint32_t set = 0;
  };
  std::vector<StencilRow> stencilRows_;
  std::vector<std::uint32_t> stencilRowSets_;
  BandTables band_;                      // where the stencil cells and their pairs are
  BandLocate locate_ = nullptr;          // the records of a measurement's stencil cells, prefetched
  BandKernel kernel_ = nullptr;          // eq. (5) in the band (compiled for common stencils)
  LayerChanges layerChanges_ = nullptr;  // the change detection's comparison of a layer
  const InverseMillsTable* lambda_ = &inverseMillsTable();  // λ(z) of eq. (5), tabulated
  bool parallelSafe_ = false;
  bool dropsClampedFree_ = false;  // compact storage, Σ0 ≥ 0 in the stencil: dropClampedFree applies
  bool skipsClampedEarly_ = true;
  std::unique_ptr<Scratch> scratch_;
  // config_.threads threads (null while that is 1), started at the first update that shares its work.
  WorkerPool* pool();
  // body(begin, end) over [0, n): on the calling thread alone unless `worthSharing` (and threads above 1),
  // else in even shares on all filter threads, share 0 on the calling one.
  template <class Body>
  void shareOut(std::size_t n, bool worthSharing, Body&& body);
  std::unique_ptr<WorkerPool> pool_;
};

}  // namespace ogf::filter
