// Test helper: the reference libraries' scripts of this folder run with Node.js from the build tree's
// node_modules (installed by the foxglove_node_modules test), and a skip that says why when they are not
// there (no Node.js, no npm registry).
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "tools/map/run_program.hpp"

namespace ogf::testing {

// Why the reference libraries cannot be used, nullopt when they can.
std::optional<std::string> referenceLibrariesMissing();

// `node SCRIPT ARGS...` with SCRIPT from tests/foxglove, run where node_modules is.
ProgramRun runReferenceScript(const std::string& script, const std::vector<std::string>& args,
                              const std::filesystem::path& scratch);

struct ChunkPlace {
  std::uint64_t offset = 0;  // of the Chunk record
  std::uint64_t length = 0;  // of the whole record
  std::string compression;
};

// The chunks of an indexed MCAP file, as the reference reader (@mcap/core McapIndexedReader) lists them.
std::vector<ChunkPlace> referenceChunks(const std::filesystem::path& mcap,
                                        const std::filesystem::path& scratch);

}  // namespace ogf::testing

#define OGF_REQUIRE_REFERENCE_LIBRARIES()                           \
  if (const auto why = ::ogf::testing::referenceLibrariesMissing()) \
  GTEST_SKIP() << "reference "                                      \
                  "libraries: "                                     \
               << *why
