// How the package reports failures to Python: the exception classes a user catches, each carrying the file
// and the reason that the C++ libraries put in their Error messages.
//   a file that does not exist            FileNotFoundError (errno ENOENT, filename = the path)
//   a file the system cannot read         OSError (filename = the path)
//   a file that is not an ogf map         ogf.MapFileError, a ValueError, with loadOgfMap's message
//   a bad argument (band, box, LCM URL)   ValueError
#pragma once

#include <pybind11/pybind11.h>

#include <ogf/common/error.hpp>

#include <filesystem>
#include <string>

namespace ogf::python {

// Registers ogf.MapFileError in `m`.
void registerErrors(pybind11::module_& m);

// Raises the Python exception for a failure to load `path` (see the table above).
[[noreturn]] void raiseLoadError(const std::filesystem::path& path, const Error& error);

// Raises ValueError(message).
[[noreturn]] void raiseValueError(const std::string& message);

}  // namespace ogf::python
