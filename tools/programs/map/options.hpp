// ogf-map's command line (options.cpp): the flags bound to a map_io::MapRequest, and the log level.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "ogf/map_io/map_request.hpp"

namespace ogf::map_program {

struct MapOptions {
  map_io::MapRequest request;
  std::string log_level = "info";
};

// Defines every flag of ogf-map on `app`, bound to `o`, with the program's description.
void defineCommandLine(CLI::App& app, MapOptions& o);

// After parsing: which of the flags that override the --config file the command line gave.
void noteGivenFlags(const CLI::App& app, map_io::MapRequest& r);

}  // namespace ogf::map_program
