// PublishedMap's slabs by key: a CellKeyTable with the slab stored in its slot (32 bytes) and kept at most
// 3/4 full. A look-up reads one slot, and DeltaStream::update prefetches the slots of the slabs to come
// (prefetch()). Slots move when the table grows or a slab is erased: a pointer from find() or obtain()
// holds until the next obtain() or erase().
#pragma once

#include <ogf/core/cell_key_table.hpp>

#include "ogf/delta/published_block.hpp"

namespace ogf::delta {

using SlabTable = CellKeyTable<PublishedBlock, 3, 4>;

}  // namespace ogf::delta
