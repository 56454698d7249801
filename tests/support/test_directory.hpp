// Test helper: an empty scratch directory of the running test, for a daemon's configuration, state and logs.
#pragma once

#include <filesystem>
#include <string>

namespace ogf::testing {

// <tmp>/<prefix>-<pid>-<test name> (<tmp>/<prefix>-<pid> outside a test), emptied when it exists: a rerun
// starts clean, and two test processes side by side never share one.
std::filesystem::path emptyTestDirectory(const std::string& prefix);

}  // namespace ogf::testing
