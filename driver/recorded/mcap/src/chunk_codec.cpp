#include "ogf/mcap/chunk_codec.hpp"

#include <fmt/format.h>
#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

#include <memory>

namespace ogf::mcap {
namespace {

Result<std::vector<std::uint8_t>> unzstd(std::span<const std::uint8_t> in, std::uint64_t size) {
  std::vector<std::uint8_t> out(size);
  const std::size_t n = ZSTD_decompress(out.data(), out.size(), in.data(), in.size());
  if (ZSTD_isError(n))
    return Error::inputDamaged(
        fmt::format("zstd: {} (the chunk declares {} bytes uncompressed)", ZSTD_getErrorName(n), size));
  if (n != size)
    return Error::inputDamaged(fmt::format("zstd: {} bytes uncompressed, the chunk declares {}", n, size));
  return out;
}

struct FreeLz4Context {
  void operator()(LZ4F_dctx* c) const { LZ4F_freeDecompressionContext(c); }
};

Result<std::vector<std::uint8_t>> unlz4(std::span<const std::uint8_t> in, std::uint64_t size) {
  LZ4F_dctx* raw = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&raw, LZ4F_VERSION)))
    return Error::resource("lz4: cannot make a decompression context");
  std::unique_ptr<LZ4F_dctx, FreeLz4Context> ctx(raw);
  std::vector<std::uint8_t> out(size);
  std::size_t in_pos = 0, out_pos = 0;
  for (;;) {
    std::size_t in_n = in.size() - in_pos, out_n = out.size() - out_pos;
    const std::size_t hint =
        LZ4F_decompress(ctx.get(), out.data() + out_pos, &out_n, in.data() + in_pos, &in_n, nullptr);
    if (LZ4F_isError(hint))
      return Error::inputDamaged(
          fmt::format("lz4: {} (the chunk declares {} bytes uncompressed)", LZ4F_getErrorName(hint), size));
    in_pos += in_n;
    out_pos += out_n;
    if (hint == 0) break;  // the frame is complete
    if (in_n == 0 && out_n == 0) {
      if (out_pos == out.size())
        return Error::inputDamaged(fmt::format("lz4: more than the {} bytes the chunk declares", size));
      return Error::inputDamaged(fmt::format(
          "lz4: the frame ends early, after {} of the {} bytes the chunk declares", out_pos, size));
    }
  }
  if (out_pos != size)
    return Error::inputDamaged(
        fmt::format("lz4: {} bytes uncompressed, the chunk declares {}", out_pos, size));
  return out;
}

}  // namespace

bool isKnownCompression(std::string_view compression) {
  return compression.empty() || compression == "zstd" || compression == "lz4";
}

Result<std::vector<std::uint8_t>> decompressRecords(std::string_view compression,
                                                    std::span<const std::uint8_t> records,
                                                    std::uint64_t uncompressed_size) {
  if (compression.empty()) {
    if (records.size() != uncompressed_size)
      return Error::inputDamaged(fmt::format("{} bytes of uncompressed records, the chunk declares {}",
                                             records.size(), uncompressed_size));
    return std::vector<std::uint8_t>(records.begin(), records.end());
  }
  if (compression == "zstd") return unzstd(records, uncompressed_size);
  if (compression == "lz4") return unlz4(records, uncompressed_size);
  return Error::inputDamaged(fmt::format("compression '{}' is none of zstd, lz4 and none", compression));
}

Result<std::vector<std::uint8_t>> compressRecords(std::string_view compression,
                                                  std::span<const std::uint8_t> records, int level) {
  if (compression.empty()) return std::vector<std::uint8_t>(records.begin(), records.end());
  if (compression == "zstd") {
    std::vector<std::uint8_t> out(ZSTD_compressBound(records.size()));
    const std::size_t n = ZSTD_compress(out.data(), out.size(), records.data(), records.size(), level);
    if (ZSTD_isError(n)) return Error::internal(fmt::format("zstd: {}", ZSTD_getErrorName(n)));
    out.resize(n);
    return out;
  }
  if (compression == "lz4") {
    LZ4F_preferences_t prefs{};
    prefs.frameInfo.contentSize = records.size();
    std::vector<std::uint8_t> out(LZ4F_compressFrameBound(records.size(), &prefs));
    const std::size_t n = LZ4F_compressFrame(out.data(), out.size(), records.data(), records.size(), &prefs);
    if (LZ4F_isError(n)) return Error::internal(fmt::format("lz4: {}", LZ4F_getErrorName(n)));
    out.resize(n);
    return out;
  }
  return Error::usage(fmt::format("compression '{}' is none of zstd, lz4 and none", compression));
}

std::uint32_t crc32(std::span<const std::uint8_t> bytes, std::uint32_t crc) {
  // zlib's crc32 takes at most a uInt of length at a time.
  while (!bytes.empty()) {
    const auto n = static_cast<uInt>(std::min<std::size_t>(bytes.size(), 1u << 30));
    crc = static_cast<std::uint32_t>(::crc32(crc, bytes.data(), n));
    bytes = bytes.subspan(n);
  }
  return crc;
}

}  // namespace ogf::mcap
