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

PublishedValue PublishedBlock::at(unsigned local) const { return decode(cells_.get() + rank(local) * kCellBytes); }

std::optional<PublishedValue> PublishedBlock::put(unsigned local, const PublishedValue& value) {
  const std::size_t r = rank(local);
  if (has(local)) {
    std::byte* at = cells_.get() + r * kCellBytes;
    const PublishedValue old = decode(at);
    encode(at, value);
    return old;
  }
  const std::size_t n = size();
  const std::size_t tail = (n - r) * kCellBytes;
  if (n == capacity()) {
    // Full: move into storage kGrowth cells larger, leaving the new cell's place open on the way.
    auto grown = std::make_unique_for_overwrite<std::byte[]>((n + kGrowth) * kCellBytes);
    if (n > 0) {
      std::memcpy(grown.get(), cells_.get(), r * kCellBytes);
      std::memcpy(grown.get() + (r + 1) * kCellBytes, cells_.get() + r * kCellBytes, tail);
    }
    cells_ = std::move(grown);
  } else {
    std::memmove(cells_.get() + (r + 1) * kCellBytes, cells_.get() + r * kCellBytes, tail);
  }
  encode(cells_.get() + r * kCellBytes, value);
  present_ |= std::uint64_t{1} << local;
  return std::nullopt;
}

}  // namespace ogf::delta
