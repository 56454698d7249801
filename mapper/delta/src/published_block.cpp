#include "ogf/delta/published_block.hpp"

#include <cstring>

namespace ogf::delta {
namespace {

void encode(std::byte* at, const PublishedValue& v) {
  std::memcpy(at, &v.probability, 2);
  std::memcpy(at + 2, &v.cell_class, 1);
  std::memcpy(at + 3, &v.variance, 4);
}

PublishedValue decode(const std::byte* at) {
  PublishedValue v;
  std::memcpy(&v.probability, at, 2);
  std::memcpy(&v.cell_class, at + 2, 1);
  std::memcpy(&v.variance, at + 3, 4);
  return v;
}

}  // namespace

static_assert(sizeof(PublishedBlock) == 16, "a slab is its mask and one pointer");
static_assert(PublishedBlock::kCellBytes == sizeof(PublishedValue::probability) +
                                                sizeof(PublishedValue::cell_class) + sizeof(PublishedValue::variance));

PublishedValue PublishedBlock::at(unsigned local) const { return valueAt(rank(local)); }

PublishedValue PublishedBlock::valueAt(std::size_t rank) const { return decode(cells_.get() + rank * kCellBytes); }

void PublishedBlock::replaceAt(std::size_t rank, const PublishedValue& value) {
  encode(cells_.get() + rank * kCellBytes, value);
}

std::optional<PublishedValue> PublishedBlock::put(unsigned local, const PublishedValue& value) {
  const std::size_t r = rank(local);
  if (has(local)) {
    const PublishedValue old = valueAt(r);
    replaceAt(r, value);
    return old;
  }
  insertAt(local, r, value);
  return std::nullopt;
}

std::size_t PublishedBlock::insertAt(unsigned local, std::size_t rank, const PublishedValue& value) {
  const std::size_t n = size();
  const std::size_t tail = (n - rank) * kCellBytes;
  std::size_t grown_by = 0;
  if (n == capacity()) {
    // Full: move into storage kGrowth cells larger, leaving the new cell's place open on the way.
    auto grown = std::make_unique_for_overwrite<std::byte[]>((n + kGrowth) * kCellBytes);
    if (n > 0) {
      std::memcpy(grown.get(), cells_.get(), rank * kCellBytes);
      std::memcpy(grown.get() + (rank + 1) * kCellBytes, cells_.get() + rank * kCellBytes, tail);
    }
    cells_ = std::move(grown);
    grown_by = kGrowth;
  } else {
    std::memmove(cells_.get() + (rank + 1) * kCellBytes, cells_.get() + rank * kCellBytes, tail);
  }
  encode(cells_.get() + rank * kCellBytes, value);
  present_ |= std::uint64_t{1} << local;
  return grown_by;
}

}  // namespace ogf::delta
