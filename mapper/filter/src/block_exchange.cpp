// The banded OGF's blocks as the map file and paging see them: hashes and the checksum, blocks read out
// and restored with their checks.

#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include "ogf/filter/banded_ogf.hpp"
#include "ogf/filter/map_checksum.hpp"
#include "ogf/filter/variance_code.hpp"

namespace ogf::filter {

std::uint64_t BandedOgf::blockHash(const CellKey& key, const Block& block) const {
  if (!block.hashKnown()) {
    block.setHash(blockChecksum(key, block.values(), block.marks()));
  }
  return block.hash();
}

std::uint64_t BandedOgf::blockHash(const CellKey& blockKey) const {
  const Block* b = storage_.find(blockKey);
  return b == nullptr ? 0 : blockHash(blockKey, *b);
}

BlockHashSum BandedOgf::blockHashSum() const {
  // Known hashes are summed as they come; the blocks changed since their last hash (those a scan touched)
  // are hashed four at a time (blockChecksums), the rest one by one.
  BlockHashSum total;
  std::array<BlockBytes, 4> pending;
  std::array<const Block*, 4> pendingBlocks{};
  std::size_t waiting = 0;
  storage_.forEachBlock([&](const CellKey& key, const Block& block) {
    ++total.blocks;
    if (block.hashKnown()) {
      total.sum += block.hash();
      return;
    }
    pending[waiting] = {key, block.values(), block.marks()};
    pendingBlocks[waiting] = &block;
    if (++waiting == pending.size()) {
      const std::array<std::uint64_t, 4> hashes = blockChecksums(pending);
      for (std::size_t j = 0; j < hashes.size(); ++j) {
        pendingBlocks[j]->setHash(hashes[j]);
        total.sum += hashes[j];
      }
      waiting = 0;
    }
  });
  for (std::size_t j = 0; j < waiting; ++j) {
    total.sum += blockHash(pending[j].key, *pendingBlocks[j]);
  }
  return total;
}

std::uint64_t BandedOgf::checksum(const BlockHashSum& heldElsewhere) const {
  MapChecksum sum;
  sum.addValue(config_.dimensions);
  sum.addValue(config_.resolution);
  sum.addValue(*config_.kernelSigma);
  sum.addValue(*config_.kernelAmplitude);
  sum.addValue(*config_.stencilRadius);
  sum.addValue(*config_.taperSupport);
  if (config_.covariance != CovarianceStorage::kBanded) {
    sum.addValue(static_cast<int>(config_.covariance));
  }
  BlockHashSum blocks = blockHashSum();
  blocks.sum += heldElsewhere.sum;
  blocks.blocks += heldElsewhere.blocks;
  sum.addValue(blocks.blocks);
  sum.addValue(blocks.sum);
  return sum.value();
}

std::vector<float> BandedOgf::blockValues(const CellKey& blockKey) const {
  const Block* b = storage_.find(blockKey);
  if (b == nullptr) {
    return {};
  }
  if (!compact()) {
    return {b->values().begin(), b->values().end()};
  }
  std::vector<float> values;
  values.reserve(floatsPerBlock());
  for (std::size_t l = 0; l < b->cells(); ++l) {
    const Moments c = momentsAt(b->data(), l);
    values.push_back(c.mean);
    values.push_back(c.variance);
  }
  return values;
}

std::span<const std::uint8_t> BandedOgf::blockMarks(const CellKey& blockKey) const {
  const Block* b = storage_.find(blockKey);
  return b == nullptr ? std::span<const std::uint8_t>{} : b->marks();
}

Status BandedOgf::checkRestorable(const CellKey& blockKey, std::size_t values, std::size_t expected,
                                  std::size_t marks) const {
  const std::string block = "block " + std::to_string(blockKey.x) + "," + std::to_string(blockKey.y) + "," +
                            std::to_string(blockKey.z);
  if (marks != 0 && marks != storage_.cellsPerBlock()) {
    return Error::inputDamaged(block + ": " + std::to_string(marks) + " cell marks, expected " +
                               std::to_string(storage_.cellsPerBlock()));
  }
  if (values != expected) {
    return Error::inputDamaged(block + ": " + std::to_string(values) + " values, expected " +
                               std::to_string(expected));
  }
  if (config_.dimensions == 2 && blockKey.z != 0) {
    return Error::inputDamaged("block z = " + std::to_string(blockKey.z) + " in a 2-D map");
  }
  if (storage_.find(blockKey) != nullptr) {
    return Error::inputDamaged(block + " appears twice");
  }
  return okStatus();
}

std::span<const float> BandedOgf::storedValues(const CellKey& blockKey) const {
  const Block* b = storage_.find(blockKey);
  return b == nullptr ? std::span<const float>{} : b->values();
}

Status BandedOgf::restoreStoredBlock(const CellKey& blockKey, std::span<const float> stored,
                                     std::span<const std::uint8_t> marks) {
  if (auto st = checkRestorable(blockKey, stored.size(), storage_.floatsPerBlock(), marks.size()); !st) {
    return st;
  }
  bool fresh = false;
  Block& b = storage_.obtain(blockKey, fresh);
  std::copy(stored.begin(), stored.end(), b.data());
  std::copy(marks.begin(), marks.end(), b.marks().begin());
  return okStatus();
}

Status BandedOgf::restoreBlock(const CellKey& blockKey, std::span<const float> values,
                               std::span<const std::uint8_t> marks) {
  if (!compact()) {
    return restoreStoredBlock(blockKey, values, marks);  // banded storage exchanges its blocks as stored
  }
  if (auto st = checkRestorable(blockKey, values.size(), floatsPerBlock(), marks.size()); !st) {
    return st;
  }
  bool fresh = false;
  Block& b = storage_.obtain(blockKey, fresh);
  auto* codes = reinterpret_cast<std::uint16_t*>(b.data() + b.cells());
  for (std::size_t l = 0; l < b.cells(); ++l) {
    b.data()[l] = values[2 * l];
    codes[l] = encodeVarianceRatio(values[2 * l + 1] / priorVariance_);
  }
  std::copy(marks.begin(), marks.end(), b.marks().begin());
  return okStatus();
}

}  // namespace ogf::filter
