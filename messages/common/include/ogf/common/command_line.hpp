// The command line every ogf program shares: one exit-code convention, unknown options named as such
// (before any "--x is required"), and value checks whose messages say the rule in words.
#pragma once

#include <CLI/CLI.hpp>

#include <optional>
#include <string>

#include "ogf/common/error.hpp"

namespace ogf::cli {

// Exit codes of every ogf program (docs/reliability.md): 0 success; 1 a failure at run time (a file that
// cannot be read or written, the bus, a state directory in use); 2 a usage or configuration error (an
// unknown or malformed flag, a bad value, an invalid configuration file).
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;

// The exit code for a program that stops on `kind` of error: kExitUsage for usage and configuration
// errors (the person starting it must change something), kExitFailure for the rest.
constexpr int exitCodeFor(ErrorKind kind) {
  return kind == ErrorKind::usage || kind == ErrorKind::configuration ? kExitUsage : kExitFailure;
}
inline int exitCodeFor(const Error& error) { return exitCodeFor(error.kind); }

// Parses the command line. Returns nullopt to go on, or the code to exit with: kExitOk after --help,
// kExitUsage after an error, which is printed on stderr as "<program>: <message>". An option the program
// does not have is reported as "unknown option --x" (with the closest known one), whatever else is wrong.
std::optional<int> parseCommandLine(CLI::App& app, int argc, const char* const* argv);

// Value checks: > 0, >= 0, and within [lo, hi] ("must be between 0 and 360, got 400").
CLI::Validator positive();
CLI::Validator nonNegative();
CLI::Validator between(double lo, double hi);

}  // namespace ogf::cli

// Parses or returns from main with the convention's exit code.
#define OGF_PARSE_COMMAND_LINE(app, argc, argv) \
  if (const auto ogf_rc_ = ::ogf::cli::parseCommandLine((app), (argc), (argv))) return *ogf_rc_
