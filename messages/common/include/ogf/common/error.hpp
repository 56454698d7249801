// What went wrong, and of what kind. The kind is what callers decide on: the exit code a program returns
// (command_line.hpp: exitCodeFor) and what the mapper's recovery does with a state file it cannot read
// (only damaged content is set aside; an I/O or resource failure leaves the files where they are). The
// message names the file, offset, line or field that was wrong, for a person to read; nothing matches on it.
#pragma once

#include <cerrno>
#include <cstring>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>

namespace ogf {

enum class ErrorKind {
  usage,          // the command line: an unknown or malformed flag, a bad value
  configuration,  // a configuration file or value, or a file it names, that is wrong or missing
  input_damaged,  // content that does not parse or check: bad magic, checksum, length, field, format
  io,             // the system failed to open, read, write, rename or sync a file, a device, a socket
  resource,       // the system ran out of something: disk space, quota, memory, file descriptors, threads
  internal,       // anything else: a broken invariant, or a failure the code does not classify
};

// The kind's name as documentation and logs spell it: "usage", "configuration", "input damaged", "I/O",
// "resource", "internal".
constexpr std::string_view kindName(ErrorKind kind) {
  switch (kind) {
    case ErrorKind::usage: return "usage";
    case ErrorKind::configuration: return "configuration";
    case ErrorKind::input_damaged: return "input damaged";
    case ErrorKind::io: return "I/O";
    case ErrorKind::resource: return "resource";
    case ErrorKind::internal: return "internal";
  }
  return "internal";
}

// The kind of a failed system call's errno: running out of space, quota, memory or descriptors is a
// resource error (it may pass once something is freed); every other errno is an I/O error.
constexpr ErrorKind kindOfErrno(int errnum) {
  switch (errnum) {
    case ENOSPC:
    case EDQUOT:
    case ENOMEM:
    case EMFILE:
    case ENFILE:
      return ErrorKind::resource;
    default:
      return ErrorKind::io;
  }
}

struct Error {
  Error() = default;
  // An error of kind internal: the code says no more about it. Prefer a factory below.
  explicit Error(std::string text) : message(std::move(text)) {}
  Error(ErrorKind of, std::string text) : message(std::move(text)), kind(of) {}

  static Error usage(std::string message) { return {ErrorKind::usage, std::move(message)}; }
  static Error configuration(std::string message) { return {ErrorKind::configuration, std::move(message)}; }
  static Error inputDamaged(std::string message) { return {ErrorKind::input_damaged, std::move(message)}; }
  static Error io(std::string message) { return {ErrorKind::io, std::move(message)}; }
  static Error resource(std::string message) { return {ErrorKind::resource, std::move(message)}; }
  static Error internal(std::string message) { return {ErrorKind::internal, std::move(message)}; }

  // A failed system call: "<what>: <the system's reason>", of the errno's kind (kindOfErrno). Call it
  // before anything else can change errno.
  static Error system(const std::string& what, int errnum = errno) {
    return {kindOfErrno(errnum), what + ": " + std::strerror(errnum)};
  }
  // The same for a std::filesystem failure.
  static Error system(const std::string& what, const std::error_code& ec) {
    const bool posix = ec.category() == std::generic_category() || ec.category() == std::system_category();
    return {posix ? kindOfErrno(ec.value()) : ErrorKind::io, what + ": " + ec.message()};
  }

  // The same error with more in front of the message ("<context>: <message>"), of the same kind.
  Error within(const std::string& context) const { return {kind, context + ": " + message}; }

  bool is(ErrorKind k) const { return kind == k; }

  std::string message;
  ErrorKind kind = ErrorKind::internal;
};

}  // namespace ogf
