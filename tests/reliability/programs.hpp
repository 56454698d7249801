// Test helper: runs the project's programs to completion (ogf-sim to make a capture, ogf-replay to send
// it) and reads the figures they print, for the reliability tests.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace ogf::testing {

// Where the programs under test were built (OGF_BIN_DIR).
std::string binDir();

// Runs argv to its end (killed after `limit`): its exit status, -1000 when it did not start or had to be
// killed.
int runToEnd(const std::vector<std::string>& argv, const std::filesystem::path& log, std::chrono::seconds limit);

std::string readText(const std::filesystem::path& path);

// The number after `key` in a "key value key value" line; nullopt when absent.
std::optional<std::int64_t> numberAfter(const std::string& line, const std::string& key);

// ogf-sim's short lab world (a VLP-16 at 600 rpm, `seconds` long, GPS time = now) into `out`; the error
// (with the log) when the simulator failed.
std::optional<std::string> simulateCapture(const std::filesystem::path& out, double seconds);

}  // namespace ogf::testing
