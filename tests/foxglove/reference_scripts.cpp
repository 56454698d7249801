#include "reference_scripts.hpp"

#include <fstream>
#include <sstream>

namespace ogf::testing {

std::optional<std::string> referenceLibrariesMissing() {
  const std::filesystem::path dir = OGF_NODE_DIR;
  if (std::filesystem::exists(dir / "node_modules" / "@mcap" / "core")) return std::nullopt;
  std::ifstream why(dir / "unavailable.txt");
  std::string line;
  if (std::getline(why, line)) return line;
  return "not installed in " + dir.string() + " (run the foxglove_node_modules test first)";
}

ProgramRun runReferenceScript(const std::string& script, const std::vector<std::string>& args,
                              const std::filesystem::path& scratch) {
  // Node finds packages from the script's folder upwards: the script is copied next to node_modules.
  const std::filesystem::path dir = OGF_NODE_DIR;
  const std::filesystem::path source = std::filesystem::path(OGF_FOXGLOVE_TESTS_DIR) / script;
  std::filesystem::copy_file(source, dir / script, std::filesystem::copy_options::overwrite_existing);
  std::vector<std::string> argv = {"node", (dir / script).string()};
  argv.insert(argv.end(), args.begin(), args.end());
  return runProgram(argv, scratch);
}

std::vector<ChunkPlace> referenceChunks(const std::filesystem::path& mcap,
                                        const std::filesystem::path& scratch) {
  const auto run = runReferenceScript("list_mcap_chunks.mjs", {mcap.string()}, scratch);
  EXPECT_EQ(run.exit_code, 0) << run.output;
  std::vector<ChunkPlace> out;
  std::istringstream lines(run.stdout_text);
  std::string word;
  ChunkPlace c;
  while (lines >> word >> c.offset >> c.length >> c.compression)
    if (word == "chunk") out.push_back(c);
  return out;
}

}  // namespace ogf::testing
