// The exceptions of errors.hpp.
#include "errors.hpp"

#include <Python.h>

#include <cerrno>
#include <system_error>

namespace py = pybind11;

namespace ogf::python {
namespace {

// ogf.MapFileError, created once by registerErrors(); owned by the module for the interpreter's life.
PyObject* g_map_file_error = nullptr;

// Raises `type`(errnum, message, filename): OSError's constructor sets .errno, .strerror and .filename.
[[noreturn]] void raiseOsError(PyObject* type, int errnum, const std::string& message,
                               const std::filesystem::path& path) {
  py::tuple args = py::make_tuple(errnum, message, path.string());
  PyErr_SetObject(type, args.ptr());
  throw py::error_already_set();
}

}  // namespace

void registerErrors(py::module_& m) {
  g_map_file_error = PyErr_NewExceptionWithDoc(
      "ogf.MapFileError",
      "A file that is not a readable ogf map: neither a map file (ogf-map --out) nor a snapshot "
      "(ogf-mapper's snapshot.ogfs), or one whose content is damaged. A ValueError; str() names the file "
      "and the reason.",
      PyExc_ValueError, nullptr);
  if (g_map_file_error == nullptr) throw py::error_already_set();
  m.add_object("MapFileError", py::reinterpret_borrow<py::object>(g_map_file_error));
}

void raiseLoadError(const std::filesystem::path& path, const Error& error) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) raiseOsError(PyExc_FileNotFoundError, ENOENT, path.string() + ": no such file", path);
  if (error.is(ErrorKind::io) || error.is(ErrorKind::resource)) raiseOsError(PyExc_OSError, EIO, error.message, path);
  PyErr_SetString(g_map_file_error, error.message.c_str());
  throw py::error_already_set();
}

void raiseValueError(const std::string& message) { throw py::value_error(message); }

}  // namespace ogf::python
