#include "ogf/delta/keyframe_writer.hpp"

namespace ogf::delta {

KeyframeWriter::KeyframeWriter(const DeltaStream& stream, std::int64_t utime)
    : header_(stream.header(utime, ogf::map_delta_t::KIND_KEYFRAME, -1, stream.map().size())),
      per_(static_cast<std::size_t>(stream.config().max_cells_per_message)),
      cells_(stream.map().size()) {
  pending_.reserve(per_);
}

void KeyframeWriter::add(std::span<const PublishedCell> cells, std::vector<ogf::map_delta_t>& out) {
  for (const PublishedCell& c : cells) {
    if (written_ + pending_.size() == cells_) {
      ++surplus_;
      continue;
    }
    pending_.push_back(c);
    if (pending_.size() == per_) {
      out.push_back(makePart(header_, next_++, pending_));
      written_ += pending_.size();
      pending_.clear();
    }
  }
}

void KeyframeWriter::finish(std::vector<ogf::map_delta_t>& out) {
  while (next_ < header_.part_count) {
    out.push_back(makePart(header_, next_++, pending_));
    written_ += pending_.size();
    pending_.clear();
  }
}

}  // namespace ogf::delta
