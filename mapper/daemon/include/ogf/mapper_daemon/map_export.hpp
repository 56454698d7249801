// Where and how ogf-mapper writes map exports (the "export" map command): only into its export
// directory, under a plain file name with the format's extension, never replacing a file and never
// following a link. The file is written under a name nobody can guess or pre-create (O_TMPFILE, or a
// random name opened with O_EXCL where the file system lacks it) and appears under its name only once
// complete, by a link that fails when the name exists.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include "ogf/common/result.hpp"

namespace ogf::mapper_daemon {

inline constexpr std::size_t kMaxExportNameLength = 128;

// The formats an export writes: ogfm, ply, pcd, csv, bt.
bool knownExportFormat(const std::string& format);

// Whether `name` is a plain file name for `format`: letters, digits, '.', '_' and '-' only, not starting
// with '.', at most kMaxExportNameLength characters, ending in "." + format. The error says which rule.
Status checkExportName(const std::string& name, const std::string& format);

// An upper bound of the bytes an export of a map of `cells` allocated cells writes (free-space check
// before anything is copied): csv 96 bytes a cell (six numbers as text), ply and pcd 20 (five floats per
// occupied cell), bt 8 (OctoMap's 2 bits per child and its leaf values), plus 64 KiB of headers; ogfm
// `ogfm_bytes`, the map file's own size (filter::encodedMapBytes), plus the same 64 KiB.
std::uint64_t exportBytesBound(const std::string& format, std::uint64_t cells, std::uint64_t ogfm_bytes);

// The export directory, opened without following a link (created, mode 0750, when missing; its parent
// must exist). Movable, closes on destruction.
class ExportDirectory {
 public:
  static Result<ExportDirectory> open(const std::filesystem::path& dir);
  ExportDirectory(ExportDirectory&& o) noexcept;
  ExportDirectory& operator=(ExportDirectory&& o) noexcept;
  ~ExportDirectory();

  const std::filesystem::path& path() const { return path_; }
  // Whether `name` exists in the directory (a symbolic link included, never followed).
  bool holds(const std::string& name) const;
  // Bytes free to this user on the directory's file system.
  Result<std::uint64_t> freeBytes() const;
  // Creates `name` (checked by checkExportName first) holding what `write` writes to the path it is given
  // (a path to the unnamed file being written); fails, leaving nothing behind, when `write` fails or `name`
  // exists.
  Status writeNew(const std::string& name, const std::function<Status(const std::filesystem::path&)>& write) const;

 private:
  ExportDirectory(int fd, std::filesystem::path path) : fd_(fd), path_(std::move(path)) {}
  int fd_ = -1;
  std::filesystem::path path_;
};

}  // namespace ogf::mapper_daemon
