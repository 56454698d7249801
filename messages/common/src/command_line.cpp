#include "ogf/common/command_line.hpp"

#include <algorithm>
#include <cctype>
#include <iostream>
#include <sstream>
#include <vector>

namespace ogf::cli {
namespace {

std::size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

// The closest long option name, when close enough to be a typo.
std::optional<std::string> closest(const CLI::App& app, const std::string& name) {
  std::optional<std::string> best;
  std::size_t best_d = 3;
  for (const CLI::Option* opt : app.get_options()) {
    for (const auto& l : opt->get_lnames()) {
      const std::string candidate = "--" + l;
      const auto d = editDistance(name, candidate);
      if (d < best_d) {
        best_d = d;
        best = candidate;
      }
    }
  }
  return best;
}

bool isOptionToken(const std::string& t) {
  if (t.size() >= 3 && t[0] == '-' && t[1] == '-') return true;
  // "-x" is an option, "-1" or "-.5" a negative number given as a value.
  return t.size() >= 2 && t[0] == '-' && std::isalpha(static_cast<unsigned char>(t[1])) != 0;
}

int usageError(const char* argv0, const std::string& message) {
  std::string program = argv0 != nullptr ? argv0 : "";
  program = program.substr(program.find_last_of('/') + 1);
  std::cerr << program << ": " << message << "\nRun with --help for the options.\n";
  return kExitUsage;
}

}  // namespace

std::optional<int> parseCommandLine(CLI::App& app, int argc, const char* const* argv) {
  // Unknown options first: CLI11 checks required options before it reports extras, which turns a typo
  // of a required flag into "--flag is required".
  for (int i = 1; i < argc; ++i) {
    const std::string token = argv[i];
    if (token == "--") break;
    if (!isOptionToken(token)) continue;
    std::string name = token.substr(0, token.find('='));
    if (name.size() > 2 && name[1] != '-') name = name.substr(0, 2);  // -xVALUE
    if (app.get_option_no_throw(name) != nullptr) continue;
    std::string message = "unknown option " + name;
    if (auto near = closest(app, name)) message += " (did you mean " + *near + "?)";
    return usageError(argv[0], message);
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    app.exit(e);
    return kExitOk;
  } catch (const CLI::CallForAllHelp& e) {
    app.exit(e);
    return kExitOk;
  } catch (const CLI::CallForVersion& e) {
    app.exit(e);
    return kExitOk;
  } catch (const CLI::RequiredError& e) {
    // CLI11 checks required options before it converts and checks values: parse again without them, so a
    // bad value (the nearer mistake) is reported before an option left out.
    std::string message = e.what();
    std::vector<CLI::Option*> required;
    for (CLI::Option* opt : app.get_options()) {
      if (opt->get_required()) {
        required.push_back(opt);
        opt->required(false);
      }
    }
    app.clear();
    try {
      app.parse(argc, argv);
    } catch (const CLI::ParseError& other) {
      message = other.what();
    }
    for (CLI::Option* opt : required) opt->required(true);
    return usageError(argv[0], message);
  } catch (const CLI::ParseError& e) {
    return usageError(argv[0], e.what());
  }
  return std::nullopt;
}

namespace {

std::string number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

CLI::Validator numberCheck(const std::string& description, std::function<std::string(double)> rule) {
  return CLI::Validator(
      [rule = std::move(rule)](std::string& text) -> std::string {
        double v = 0;
        std::size_t used = 0;
        try {
          v = std::stod(text, &used);
        } catch (const std::exception&) {
          return "'" + text + "' is not a number";
        }
        if (used != text.size()) return "'" + text + "' is not a number";
        return rule(v);
      },
      description);
}

}  // namespace

CLI::Validator positive() {
  return numberCheck("POSITIVE", [](double v) {
    return v > 0 ? std::string() : "must be greater than 0, got " + number(v);
  });
}

CLI::Validator nonNegative() {
  return numberCheck("NONNEGATIVE", [](double v) {
    return v >= 0 ? std::string() : "must be 0 or more, got " + number(v);
  });
}

CLI::Validator between(double lo, double hi) {
  return numberCheck("[" + number(lo) + ", " + number(hi) + "]", [lo, hi](double v) {
    return v >= lo && v <= hi ? std::string()
                              : "must be between " + number(lo) + " and " + number(hi) + ", got " + number(v);
  });
}

}  // namespace ogf::cli
