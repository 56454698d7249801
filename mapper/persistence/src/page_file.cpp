#include "ogf/persistence/page_file.hpp"

#include <ogf/filter/map_checksum.hpp>

#include <bit>
#include <cstring>

#include "ogf/common/little_endian.hpp"

namespace ogf::persistence {
namespace {

static_assert(std::endian::native == std::endian::little, "pages store floats as the host holds them");

constexpr char kPageMagic[8] = {'O', 'G', 'F', 'P', 'A', 'G', 'E', '1'};
constexpr std::uint32_t kPageVersion = 2;
constexpr std::size_t kPublishedCellBytes = 12 + 2 + 1 + 4;
constexpr std::size_t kHeader = 8 + 4 + 3 * 4 + 3 * 4;
constexpr std::size_t kTrailer = 8;

// The map file's checksum (several GB/s; a page is read back every time its region is reached again).
std::uint64_t pageChecksum(std::span<const std::byte> bytes) {
  filter::MapChecksum sum;
  sum.add(bytes);
  return sum.value();
}

}  // namespace

std::vector<std::byte> encodePage(const Page& page) {
  std::vector<std::byte> out;
  out.reserve(kHeader + page.blocks.size() * (12 + page.floats_per_block * sizeof(float) + page.cells_per_block) + kTrailer);
  for (char c : kPageMagic) out.push_back(static_cast<std::byte>(c));
  putLittleEndian<std::uint32_t>(out, kPageVersion);
  putLittleEndian<std::int32_t>(out, page.region.x);
  putLittleEndian<std::int32_t>(out, page.region.y);
  putLittleEndian<std::int32_t>(out, page.region.z);
  putLittleEndian<std::uint32_t>(out, static_cast<std::uint32_t>(page.blocks.size()));
  putLittleEndian<std::uint32_t>(out, page.floats_per_block);
  putLittleEndian<std::uint32_t>(out, page.cells_per_block);
  for (const PageBlock& b : page.blocks) {
    putLittleEndian<std::int32_t>(out, b.key.x);
    putLittleEndian<std::int32_t>(out, b.key.y);
    putLittleEndian<std::int32_t>(out, b.key.z);
    const auto* v = reinterpret_cast<const std::byte*>(b.stored.data());
    out.insert(out.end(), v, v + b.stored.size() * sizeof(float));
    const auto* m = reinterpret_cast<const std::byte*>(b.marks.data());
    out.insert(out.end(), m, m + b.marks.size());
  }
  putLittleEndian<std::uint32_t>(out, static_cast<std::uint32_t>(page.published.size()));
  for (const delta::PublishedCell& c : page.published) {
    putLittleEndian<std::int32_t>(out, c.key.x);
    putLittleEndian<std::int32_t>(out, c.key.y);
    putLittleEndian<std::int32_t>(out, c.key.z);
    putLittleEndian<std::int16_t>(out, c.probability);
    putLittleEndian<std::int8_t>(out, c.cell_class);
    putLittleEndian<std::uint32_t>(out, std::bit_cast<std::uint32_t>(c.variance));
  }
  putLittleEndian<std::uint64_t>(out, pageChecksum(out));
  return out;
}

Result<Page> decodePage(std::span<const std::byte> bytes, const std::string& source) {
  const auto fail = [&](std::size_t offset, const std::string& what) {
    return Error::inputDamaged(source + ": offset " + std::to_string(offset) + ": " + what);
  };
  if (bytes.size() < kHeader + kTrailer)
    return fail(0, "page truncated (" + std::to_string(bytes.size()) + " bytes)");
  if (std::memcmp(bytes.data(), kPageMagic, sizeof kPageMagic) != 0) return fail(0, "not an ogf page (bad magic)");
  const auto version = getLittleEndian<std::uint32_t>(bytes.data() + 8);
  if (version != 1 && version != kPageVersion) return fail(8, "unsupported page version " + std::to_string(version));
  const std::size_t checksumAt = bytes.size() - kTrailer;
  if (getLittleEndian<std::uint64_t>(bytes.data() + checksumAt) != pageChecksum(bytes.first(checksumAt)))
    return fail(checksumAt, "page checksum mismatch (truncated or corrupt)");
  Page page;
  page.region = {getLittleEndian<std::int32_t>(bytes.data() + 12), getLittleEndian<std::int32_t>(bytes.data() + 16),
                 getLittleEndian<std::int32_t>(bytes.data() + 20)};
  const auto count = getLittleEndian<std::uint32_t>(bytes.data() + 24);
  page.floats_per_block = getLittleEndian<std::uint32_t>(bytes.data() + 28);
  page.cells_per_block = getLittleEndian<std::uint32_t>(bytes.data() + 32);
  const std::size_t perBlock = 12 + std::size_t{page.floats_per_block} * sizeof(float) + page.cells_per_block;
  // Version 2: the blocks, then the published cells' count and the cells.
  const std::size_t blocksEnd = kHeader + std::size_t{count} * perBlock;
  std::size_t published = 0;
  if (version >= 2) {
    if (count > (checksumAt - kHeader) / perBlock || blocksEnd + 4 > checksumAt)
      return fail(24, std::to_string(count) + " blocks of " + std::to_string(perBlock) +
                          " bytes leave no room for the published cells' count");
    published = getLittleEndian<std::uint32_t>(bytes.data() + blocksEnd);
    if (published > (checksumAt - blocksEnd - 4) / kPublishedCellBytes ||
        blocksEnd + 4 + published * kPublishedCellBytes != checksumAt)
      return fail(blocksEnd, std::to_string(published) + " published cells of " + std::to_string(kPublishedCellBytes) +
                                 " bytes do not fill the " + std::to_string(checksumAt - blocksEnd - 4) +
                                 " bytes after the blocks");
  } else if (std::size_t{count} * perBlock != checksumAt - kHeader) {
    return fail(24, std::to_string(count) + " blocks of " + std::to_string(perBlock) + " bytes do not fill the " +
                        std::to_string(checksumAt - kHeader) + " bytes of blocks");
  }
  page.blocks.resize(count);
  const std::byte* p = bytes.data() + kHeader;
  for (PageBlock& b : page.blocks) {
    b.key = {getLittleEndian<std::int32_t>(p), getLittleEndian<std::int32_t>(p + 4),
             getLittleEndian<std::int32_t>(p + 8)};
    p += 12;
    b.stored.resize(page.floats_per_block);
    std::memcpy(b.stored.data(), p, b.stored.size() * sizeof(float));
    p += b.stored.size() * sizeof(float);
    b.marks.resize(page.cells_per_block);
    std::memcpy(b.marks.data(), p, b.marks.size());
    p += b.marks.size();
  }
  if (version >= 2) p += 4;
  page.has_published = version >= 2;
  page.published.resize(published);
  for (delta::PublishedCell& c : page.published) {
    c.key = {getLittleEndian<std::int32_t>(p), getLittleEndian<std::int32_t>(p + 4), getLittleEndian<std::int32_t>(p + 8)};
    c.probability = getLittleEndian<std::int16_t>(p + 12);
    c.cell_class = getLittleEndian<std::int8_t>(p + 14);
    c.variance = std::bit_cast<float>(getLittleEndian<std::uint32_t>(p + 15));
    p += kPublishedCellBytes;
  }
  return page;
}

}  // namespace ogf::persistence
