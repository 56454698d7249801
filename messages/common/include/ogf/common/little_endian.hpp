// Little-endian integers to and from byte buffers, independent of the host's byte order: the on-disk
// formats (journal, snapshots) are little-endian by definition.
#pragma once

#include <cstddef>
#include <type_traits>
#include <vector>

namespace ogf {

template <class T>
void putLittleEndian(std::vector<std::byte>& out, T v) {
  using U = std::make_unsigned_t<T>;
  const auto u = static_cast<U>(v);
  for (std::size_t i = 0; i < sizeof(T); ++i) out.push_back(static_cast<std::byte>((u >> (8 * i)) & 0xFFU));
}

template <class T>
T getLittleEndian(const std::byte* p) {
  using U = std::make_unsigned_t<T>;
  U u = 0;
  for (std::size_t i = 0; i < sizeof(T); ++i) u = static_cast<U>(u | (static_cast<U>(p[i]) << (8 * i)));
  return static_cast<T>(u);
}

}  // namespace ogf
