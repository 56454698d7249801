#include "programs.hpp"

#include <fstream>
#include <regex>
#include <sstream>

#include "support/child_process.hpp"

namespace ogf::testing {

std::string binDir() { return OGF_BIN_DIR; }

int runToEnd(const std::vector<std::string>& argv, const std::filesystem::path& log, std::chrono::seconds limit) {
  return runAndCapture(argv, log.string(), limit).rc;
}

std::string readText(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::optional<std::int64_t> numberAfter(const std::string& line, const std::string& key) {
  std::smatch m;
  if (!std::regex_search(line, m, std::regex("(^|\\s)" + key + " +(-?[0-9]+)"))) return std::nullopt;
  return std::stoll(m[2]);
}

std::optional<std::string> simulateCapture(const std::filesystem::path& out, double seconds) {
  const auto now_us =
      std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
  const auto log = out.string() + ".log";
  const int rc = runToEnd({binDir() + "/ogf-sim", "--world", "lab", "--duration", std::to_string(seconds), "--out",
                           out.string(), "--start-utime", std::to_string(now_us), "--log-level", "warn"},
                          log, std::chrono::seconds(120));
  if (rc != 0) return "ogf-sim exited " + std::to_string(rc) + ": " + readText(log);
  return std::nullopt;
}

}  // namespace ogf::testing
