// Test helper: runs a program to completion through the shell with stdout and stderr captured in a file,
// and gives back the exit code and the output, so the tests can check what a user would see.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace ogf::testing {

struct ProgramRun {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
  std::string stdout_text;
};

inline std::string shellQuote(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'') out += "'\\''";
    else out += c;
  }
  return out + "'";
}

inline ProgramRun runProgram(const std::vector<std::string>& argv, const std::filesystem::path& scratch) {
  const auto out_path = scratch / "run.stdout";
  const auto err_path = scratch / "run.stderr";
  std::string command;
  for (const auto& a : argv) command += shellQuote(a) + " ";
  command += "> " + shellQuote(out_path.string()) + " 2> " + shellQuote(err_path.string());
  const int status = std::system(command.c_str());
  ProgramRun run;
  run.exit_code = (status != -1 && WIFEXITED(status)) ? WEXITSTATUS(status) : -1;
  const auto slurp = [](const std::filesystem::path& p) {
    std::ifstream in(p);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  };
  run.stdout_text = slurp(out_path);
  run.output = run.stdout_text + slurp(err_path);
  return run;
}

}  // namespace ogf::testing
